"""The implicit surface by table: each facet's lit and shadowed share of the image, tabulated over light and view
directions, read back between its nodes (the ``implicit_table`` model).

A regular surface's image is five flat facets (top, east, west, north, south), each lit or in shadow, and a view's
value is the facet sum: every facet's 8-bit value weighted by its share (:func:`roughlight.render.shading.facet_sum`).
The values are the OpenGL lighting equation of one facet, a closed form; what no closed form follows is the shares
(the first-order correction's failure at grazing views, docs/implicit-surface.md). :class:`ShareTable` holds them,
measured by the exact reference at the table's nodes (:mod:`roughlight.measurements.brdf_export`), and a view
between the nodes reads them multilinearly.

Axes (all angles in degrees):

- the light's incidence ``i`` (elevation above the surface plane), nodes ``incidence`` from 0 to 90;
- the light's azimuth ``psi``, nodes ``light_azimuth`` in [0, 45]: square pyramids repeat every 90 degrees and
  mirror about the diagonals, so every light is one of these, the views turned with it
  (:func:`roughlight.surfaces.symmetry.canonical_directions`); the plate needs only 0;
- the view's elevation ``e`` above the plane, nodes ``elevation`` in (0, 90] (closer below the horizon's first
  node: a view lower than it reads the first node's shares; the study's grazing views, ``e`` 0, have no image);
- the view's azimuth ``phi`` on the whole circle, ``azimuth_nodes`` nodes ``0, 360 / n, ...`` (wrapping).

The shares are stored as 16-bit fractions (``SCALE``) in an (I, P, E, A, 10) array: channels 0-4 each facet's lit
share, 5-9 its shadowed share, facets in :data:`roughlight.surfaces.geometry.FACET_NAMES` order.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...atomic import atomic_path
from ...surfaces.surface import Surface
from ...surfaces.symmetry import canonical_directions
from .. import shading

__all__ = ["SCALE", "CHANNELS", "HOT_SPOT_BLEND", "ShareTable", "save_table", "load_table", "node_weights",
           "hot_spot_weight", "table_shares", "table_values", "table_angles", "light_corners"]

#: A share of 1 as stored (16-bit unsigned: a share's rounding is at most 7.6e-6, 0.001 of a level at J = 127).
SCALE = 65535
#: Shares a (light, view) node: five facets lit, then five in shadow.
CHANNELS = 10


@dataclass(frozen=True, eq=False)
class ShareTable:
    """A regular surface's facet shares over light and view directions (module docstring for the axes).

    Attributes
    ----------
    truncation, aspect : float
        The surface.
    shadows : bool
        Whether the surface casts shadows (``Lighting.shadows``) in the measured shares.
    incidence, light_azimuth, elevation : (I,), (P,), (E,) float arrays
        Light incidence in [0, 90], light azimuth in [0, 45] and view elevation in (0, 90] nodes, degrees,
        ascending.
    azimuth_nodes : int
        View azimuth nodes on the circle, ``360 / azimuth_nodes`` degrees apart from 0.
    shares : (I, P, E, A, 10) uint16 array
        Each node's shares times :data:`SCALE`.
    """

    truncation: float
    aspect: float
    shadows: bool
    incidence: np.ndarray
    light_azimuth: np.ndarray
    elevation: np.ndarray
    azimuth_nodes: int
    shares: np.ndarray

    def __post_init__(self):
        Surface(self.truncation, self.aspect)  # refuses a surface that is not one
        for name, low, high, first in (("incidence", 0.0, 90.0, True), ("light_azimuth", 0.0, 45.0, True),
                                       ("elevation", 0.0, 90.0, False)):
            nodes = np.asarray(getattr(self, name), float)
            if nodes.ndim != 1 or nodes.size == 0 or np.any(np.diff(nodes) <= 0):
                raise ValueError(f"table {name} nodes must be a non-empty ascending list, got {nodes!r}")
            if nodes[0] < low or nodes[-1] > high or (not first and nodes[0] <= low):
                raise ValueError(f"table {name} nodes must lie in {'[' if first else '('}{low:g}, {high:g}], "
                                 f"got {nodes!r}")
            object.__setattr__(self, name, nodes)
        if int(self.azimuth_nodes) < 4:
            raise ValueError(f"table azimuth_nodes must be at least 4, got {self.azimuth_nodes!r}")
        shape = (self.incidence.size, self.light_azimuth.size, self.elevation.size, int(self.azimuth_nodes),
                 CHANNELS)
        if self.shares.shape != shape:
            raise ValueError(f"table shares must have the shape {shape}, got {self.shares.shape}")

    @property
    def surface(self) -> Surface:
        """The tabulated surface."""
        return Surface(self.truncation, self.aspect)

    @property
    def azimuth_step(self) -> float:
        """Degrees between view azimuth nodes."""
        return 360.0 / int(self.azimuth_nodes)

    @property
    def nbytes(self) -> int:
        """Bytes of the shares (what a renderer holds in texture memory)."""
        return int(self.shares.nbytes)


def save_table(path, table: ShareTable) -> None:
    """Write ``table`` to ``path`` (NumPy ``.npz``), atomically: a temporary name in the same folder, then renamed."""
    with atomic_path(path) as temporary, open(temporary, "wb") as handle:
        np.savez_compressed(handle, truncation=table.truncation, aspect=table.aspect, shadows=table.shadows,
                            incidence=table.incidence, light_azimuth=table.light_azimuth,
                            elevation=table.elevation, azimuth_nodes=table.azimuth_nodes, shares=table.shares)


def load_table(path) -> ShareTable:
    """The :class:`ShareTable` :func:`save_table` wrote at ``path``."""
    with np.load(path) as data:
        return ShareTable(float(data["truncation"]), float(data["aspect"]), bool(data["shadows"]),
                          data["incidence"], data["light_azimuth"], data["elevation"], int(data["azimuth_nodes"]),
                          data["shares"])


def node_weights(nodes, x):
    """Linear interpolation between ascending ``nodes`` at ``x`` (clamped to the end nodes).

    Returns
    -------
    lower : (n,) int array, the node at or below each ``x``
    weight : (n,) float array in [0, 1], the weight of node ``lower + 1`` (0 where there is none)
    """
    nodes = np.asarray(nodes, float)
    x = np.clip(np.asarray(x, float), nodes[0], nodes[-1])
    if nodes.size == 1:
        return np.zeros(x.shape, int), np.zeros(x.shape)
    lower = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, nodes.size - 2)
    weight = (x - nodes[lower]) / (nodes[lower + 1] - nodes[lower])
    return lower, np.clip(weight, 0.0, 1.0)


def table_angles(light, view):
    """The table's four axes of (light, view) pairs: incidence, light azimuth, view elevation and view azimuth,
    degrees, each (n,), of unit vectors (n, 3) (the light above the plane; azimuths in [0, 360))."""
    incidence = np.degrees(np.arcsin(np.clip(light[:, 2], -1.0, 1.0)))
    psi = np.mod(np.degrees(np.arctan2(light[:, 1], light[:, 0])), 360.0)
    elevation = np.degrees(np.arcsin(np.clip(view[:, 2], -1.0, 1.0)))
    phi = np.mod(np.degrees(np.arctan2(view[:, 1], view[:, 0])), 360.0)
    return incidence, psi, elevation, phi


#: Within this phase angle of the light (degrees) the shadowed part of what each facet shows is read with the view
#: turned with the light (:func:`table_shares`), fully at ``V = L`` and less with the angle, none beyond it.
HOT_SPOT_BLEND = 15.0


def _read_nodes(table: ShareTable, corners, elevation, phi, turned_from=None) -> np.ndarray:
    """The shares at views (``elevation``, ``phi``: (n,) degrees) read multilinearly between the four light nodes
    ``corners`` (``i0``, ``wi``, ``p0``, ``wp``) and the view nodes: (n, CHANNELS) fractions. With ``turned_from``
    (the lights' incidence and azimuth, (n,) each) each light node reads the view turned with the light: its
    azimuth and elevation moved by the node's less the light's, so that ``V = L`` reads every node's own hot spot."""
    i0, wi, p0, wp = corners
    step = table.azimuth_step
    shares = np.zeros((len(elevation), CHANNELS))
    for di, fi in ((0, 1.0 - wi), (1, wi)):
        i = np.minimum(i0 + di, table.incidence.size - 1)
        at_e = elevation if turned_from is None else np.clip(elevation + table.incidence[i] - turned_from[0], 0.0, 90.0)
        e0, we = node_weights(table.elevation, at_e)
        for dp, fp in ((0, 1.0 - wp), (1, wp)):
            p = np.minimum(p0 + dp, table.light_azimuth.size - 1)
            at = phi if turned_from is None else np.mod(phi + table.light_azimuth[p] - turned_from[1], 360.0)
            a0 = np.floor(at / step).astype(int) % table.azimuth_nodes
            wa = at / step - np.floor(at / step)
            for de, fe in ((0, 1.0 - we), (1, we)):
                for da, fa in ((0, 1.0 - wa), (1, wa)):
                    node = table.shares[i, p, np.minimum(e0 + de, table.elevation.size - 1),
                                        (a0 + da) % table.azimuth_nodes]
                    shares += (fi * fp * fe * fa)[:, None] * node
    return shares / SCALE


def hot_spot_weight(light, view, blend: float = HOT_SPOT_BLEND) -> np.ndarray:
    """How much of the shadowed part is read with the view turned with the light: ``1 - g / blend`` clipped to
    [0, 1], ``g`` the phase angle between ``light`` and ``view`` ((n, 3) unit vectors), degrees."""
    phase = np.degrees(np.arccos(np.clip(np.sum(light * view, axis=1), -1.0, 1.0)))
    return np.clip(1.0 - phase / float(blend), 0.0, 1.0)


def table_shares(table: ShareTable, light, view, hot_spot_blend: float = HOT_SPOT_BLEND):
    """Each facet's lit and shadowed share at many (light, view) pairs, read from ``table`` between its nodes.

    Each facet's share of the image (lit and shadowed together) is read at the view's azimuth in the lattice's
    frame, between the four light nodes around the light and the view nodes around the view. Near the hot spot
    (``V = L``, where no shadow is seen and the shares have a cusp that light nodes 15 degrees apart smear) the
    part of it in shadow is read as well with the view turned with the light: at each light node the view's
    azimuth and elevation relative to the light are kept, so that every node reads its own hot spot; the two
    readings of that part are blended by :func:`hot_spot_weight` (docs/export.md, "Resolution").

    Parameters
    ----------
    table : ShareTable
    light, view : (n, 3) arrays
        Unit vectors toward the light (incidence in [0, 90]) and toward the detector (above the plane), a pair a
        row, in the surface's frame (the study's: azimuth 0 along the lattice's x axis).
    hot_spot_blend : float
        The phase angle, degrees, within which the hot spot's reading enters (0: never; the shader's is
        :data:`HOT_SPOT_BLEND`).

    Returns
    -------
    lit, shadow : (n, 5) arrays
        Shares in the canonical frame (the facets as seen with ``light_c``, ``view_c``)
    light_c, view_c : (n, 3) arrays
        The pairs turned to the table's light azimuths (:func:`roughlight.surfaces.symmetry.canonical_directions`).
    """
    light_c, view_c = canonical_directions(table.surface, light, view)
    incidence, psi, elevation, phi = table_angles(light_c, view_c)
    corners = node_weights(table.incidence, incidence) + node_weights(table.light_azimuth, psi)
    lattice = _read_nodes(table, corners, elevation, phi)
    seen = lattice[:, :5] + lattice[:, 5:]
    shadow = lattice[:, 5:]
    near = hot_spot_weight(light_c, view_c, hot_spot_blend) if hot_spot_blend > 0 else np.zeros(len(light_c))
    rows = np.flatnonzero(near > 0)  # the turned reading only where it enters
    if rows.size:
        turned = _read_nodes(table, tuple(part[rows] for part in corners), elevation[rows], phi[rows],
                             turned_from=(incidence[rows], psi[rows]))
        turned_seen = turned[:, :5] + turned[:, 5:]
        fraction = np.where(seen[rows] > 0, shadow[rows] / np.where(seen[rows] > 0, seen[rows], 1.0), 0.0)
        turned_fraction = np.where(turned_seen > 1e-9, turned[:, 5:] / np.where(turned_seen > 1e-9, turned_seen, 1.0),
                                   fraction)
        weight = near[rows, None]
        shadow = shadow.copy()
        shadow[rows] = seen[rows] * (weight * turned_fraction + (1.0 - weight) * fraction)
    return seen - shadow, shadow, light_c, view_c


def table_values(table: ShareTable, light, view, lighting=None, quantized: bool = True) -> dict:
    """The study's value (0-255) of each component at many (light, view) pairs: the facet sum of the table's
    shares (:func:`table_shares`) with each facet's lighting equation (8-bit when ``quantized``, as the
    framebuffer stores a pixel).

    Parameters
    ----------
    table : ShareTable
    light, view : (n, 3) arrays, unit vectors (see :func:`table_shares`)
    lighting : Lighting, optional

    Returns
    -------
    dict: ``diffuse``, ``specular``, ``total`` (n,) arrays, 0-255; 0 where the view lies in the plane or below.
    """
    from .model import facet_normals

    lighting = lighting or shading.Lighting()
    light, view = np.atleast_2d(np.asarray(light, float)), np.atleast_2d(np.asarray(view, float))
    lit, shadow, light_c, view_c = table_shares(table, light, view)
    values = shading.facet_sum(facet_normals(table.surface), light_c[:, None, :], view_c, lit, shadow, lighting,
                               quantized)
    seen = view[:, 2] > 0.0
    return {name: np.where(seen, value, 0.0) for name, value in values.items()}


def light_corners(table: ShareTable, incidence: float, light_azimuth: float):
    """The four (incidence, light azimuth) nodes around one light and their weights, with the light turned to the
    table's azimuths: what the shader reads a light's shares from.

    Returns
    -------
    slices : (4,) int array
        The corners' slices ``i * P + p`` of the table's texture (:func:`roughlight.render.implicit.shader`).
    weights : (4,) float array (summing to 1)
    light_c : (3,) array, the light turned (unit vector toward it)
    turn : (3, 3) array, the turn that takes a view along (``view_c = turn @ view``)
    """
    light = shading.light_direction(incidence, light_azimuth)
    eye = np.eye(3)
    light_c, turned = canonical_directions(table.surface, np.vstack([light, light, light]), eye)
    turn = np.column_stack(turned)  # images of the basis vectors: the map's matrix
    _, psi, _, _ = table_angles(light_c[:1], eye[:1])
    i0, wi = node_weights(table.incidence, [incidence])
    p0, wp = node_weights(table.light_azimuth, psi)
    last_i, last_p = table.incidence.size - 1, table.light_azimuth.size - 1
    slices, weights = [], []
    for di, fi in ((0, 1.0 - wi[0]), (1, wi[0])):
        for dp, fp in ((0, 1.0 - wp[0]), (1, wp[0])):
            slices.append(min(i0[0] + di, last_i) * table.light_azimuth.size + min(p0[0] + dp, last_p))
            weights.append(fi * fp)
    return np.array(slices, int), np.array(weights, float), light_c[0], turn
