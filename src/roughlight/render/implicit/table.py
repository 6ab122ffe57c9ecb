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
- the light's azimuth ``psi``, nodes in [0, 45], a list of its own for each incidence node (closer where the light
  is low: ``ShareTable.rows``): square pyramids repeat every 90 degrees and mirror about the diagonals, so every
  light is one of these, the views turned with it (:func:`roughlight.surfaces.symmetry.canonical_directions`); the
  plate needs only 0;
- the view's elevation ``e`` above the plane, nodes ``elevation`` in (0, 90] (closer below the horizon's first
  node: a view lower than it reads the first node's shares; the study's grazing views, ``e`` 0, have no image);
- the view's azimuth ``phi`` on the whole circle, ``azimuth_nodes`` nodes ``0, 360 / n, ...`` (wrapping).

The shares are stored as 16-bit fractions (``SCALE``) in an (L, E, A, 10) array, one slice a light node (the
incidence rows in turn, each row's azimuth nodes ascending): channels 0-4 each facet's lit share, 5-9 its shadowed
share, facets in :data:`roughlight.surfaces.geometry.FACET_NAMES` order. A light is read between the two incidence
rows around it, each between its own two azimuth nodes around the light: four slices (:func:`light_slices`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...atomic import atomic_path
from ...surfaces.surface import Surface
from ...surfaces.symmetry import canonical_directions
from .. import shading

__all__ = ["SCALE", "CHANNELS", "HOT_SPOT_BLEND", "ShareTable", "light_rows", "save_table", "load_table",
           "node_weights", "light_slices", "hot_spot_weight", "table_shares", "table_values", "table_angles", "light_corners"]

#: A share of 1 as stored (16-bit unsigned: a share's rounding is at most 7.6e-6, 0.001 of a level at J = 127).
SCALE = 65535
#: Shares a (light, view) node: five facets lit, then five in shadow.
CHANNELS = 10


def _nodes(name: str, values, low: float, high: float, first: bool) -> np.ndarray:
    """``values`` as an ascending float array within ``[low, high]`` (``(low, high]`` unless ``first``), else
    ValueError naming the table's ``name`` nodes."""
    nodes = np.asarray(values, float)
    if nodes.ndim != 1 or nodes.size == 0 or np.any(np.diff(nodes) <= 0):
        raise ValueError(f"table {name} nodes must be a non-empty ascending list, got {nodes!r}")
    if nodes[0] < low or nodes[-1] > high or (not first and nodes[0] <= low):
        raise ValueError(f"table {name} nodes must lie in {'[' if first else '('}{low:g}, {high:g}], got {nodes!r}")
    return nodes


def _one_list(values) -> bool:
    """Whether ``values`` is one list of numbers (not a list of lists, ragged or not)."""
    try:
        return np.asarray(values, float).ndim == 1
    except (TypeError, ValueError):
        return False


def light_rows(rows: int, light_azimuth) -> tuple[np.ndarray, ...]:
    """Each of ``rows`` incidence rows' light azimuth nodes (ascending in [0, 45], degrees, else ValueError):
    ``light_azimuth`` is one list for every row, or a list of each row's own."""
    listed = [light_azimuth] * rows if _one_list(light_azimuth) else list(light_azimuth)
    if len(listed) != rows:
        raise ValueError(f"table light_azimuth must be one list of nodes or one for each of the {rows} incidence "
                         f"nodes, got {len(listed)}")
    return tuple(_nodes("light_azimuth", row, 0.0, 45.0, True) for row in listed)


@dataclass(frozen=True, eq=False)
class ShareTable:
    """A regular surface's facet shares over light and view directions (module docstring for the axes).

    Attributes
    ----------
    truncation, aspect : float
        The surface.
    shadows : bool
        Whether the surface casts shadows (``Lighting.shadows``) in the measured shares.
    incidence : (I,) float array
        Light incidence nodes in [0, 90], degrees, ascending.
    light_azimuth : (P,) float array, or a sequence of I of them
        Light azimuth nodes in [0, 45], degrees, ascending: one list for every incidence row, or each row's own.
        Once built, the union of the rows' nodes (each row's are :attr:`rows`).
    elevation : (E,) float array
        View elevation nodes in (0, 90], degrees, ascending.
    azimuth_nodes : int
        View azimuth nodes on the circle, ``360 / azimuth_nodes`` degrees apart from 0.
    shares : uint16 array
        Each node's shares times :data:`SCALE`: (I, P, E, A, 10) for one list of azimuth nodes, (L, E, A, 10) for
        the rows' own (L light nodes, row by row). Once built, (L, E, A, 10) either way (a view of the array given).
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
        incidence = _nodes("incidence", self.incidence, 0.0, 90.0, True)
        elevation = _nodes("elevation", self.elevation, 0.0, 90.0, False)
        if int(self.azimuth_nodes) < 4:
            raise ValueError(f"table azimuth_nodes must be at least 4, got {self.azimuth_nodes!r}")
        shared = _one_list(self.light_azimuth)
        rows = light_rows(incidence.size, self.light_azimuth)
        start = np.concatenate([[0], np.cumsum([row.size for row in rows])])
        view = (elevation.size, int(self.azimuth_nodes), CHANNELS)
        shares = np.asarray(self.shares)
        if shared and shares.shape == (incidence.size, rows[0].size) + view:
            shares = shares.reshape((int(start[-1]),) + view)
        if shares.shape != (int(start[-1]),) + view:
            expected = ((incidence.size, rows[0].size) if shared else (int(start[-1]),)) + view
            raise ValueError(f"table shares must have the shape {expected}, got {np.shape(self.shares)}")
        for name, value in (("incidence", incidence), ("elevation", elevation), ("shares", shares),
                            ("light_azimuth", np.unique(np.concatenate(rows))), ("rows", rows),
                            ("row_start", start)):
            object.__setattr__(self, name, value)

    @property
    def surface(self) -> Surface:
        """The tabulated surface."""
        return Surface(self.truncation, self.aspect)

    @property
    def azimuth_step(self) -> float:
        """Degrees between view azimuth nodes."""
        return 360.0 / int(self.azimuth_nodes)

    @property
    def lights(self) -> int:
        """Light nodes (the shares' slices)."""
        return int(self.row_start[-1])

    @property
    def slice_incidence(self) -> np.ndarray:
        """(L,) each slice's light incidence, degrees."""
        return np.repeat(self.incidence, np.diff(self.row_start))

    @property
    def slice_azimuth(self) -> np.ndarray:
        """(L,) each slice's light azimuth, degrees."""
        return np.concatenate(self.rows)

    @property
    def nbytes(self) -> int:
        """Bytes of the shares (what a renderer holds in texture memory)."""
        return int(self.shares.nbytes)


def save_table(path, table: ShareTable) -> None:
    """Write ``table`` to ``path`` (NumPy ``.npz``), atomically: a temporary name in the same folder, then renamed."""
    with atomic_path(path) as temporary, open(temporary, "wb") as handle:
        np.savez_compressed(handle, truncation=table.truncation, aspect=table.aspect, shadows=table.shadows,
                            incidence=table.incidence, slice_azimuth=table.slice_azimuth, row_start=table.row_start,
                            elevation=table.elevation, azimuth_nodes=table.azimuth_nodes, shares=table.shares)


def load_table(path) -> ShareTable:
    """The :class:`ShareTable` :func:`save_table` wrote at ``path`` (or, from a file of before 30 November 2026,
    one list of light azimuth nodes for every incidence row)."""
    with np.load(path) as data:
        if "row_start" in data:
            start, azimuth = data["row_start"], data["slice_azimuth"]
            light_azimuth = [azimuth[start[k]:start[k + 1]] for k in range(len(start) - 1)]
        else:
            light_azimuth = data["light_azimuth"]
        return ShareTable(float(data["truncation"]), float(data["aspect"]), bool(data["shadows"]),
                          data["incidence"], light_azimuth, data["elevation"], int(data["azimuth_nodes"]),
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


def light_slices(table: ShareTable, incidence, psi):
    """The four light nodes around each light and their weights: the incidence rows below and above it, and in each
    row the two of its own azimuth nodes around it (each axis linear, clamped to the end nodes).

    Parameters
    ----------
    table : ShareTable
    incidence, psi : (n,) arrays, the lights' incidence and azimuth in the table's range ([0, 45]), degrees

    Returns
    -------
    slices : (n, 4) int array, the shares' slices (row below: azimuth below, above; then the row above)
    weights : (n, 4) float array, summing to 1 along the last axis
    """
    incidence, psi = np.atleast_1d(np.asarray(incidence, float)), np.atleast_1d(np.asarray(psi, float))
    i0, wi = node_weights(table.incidence, incidence)
    slices, weights = np.zeros((incidence.size, 4), int), np.zeros((incidence.size, 4))
    for di, fi in ((0, 1.0 - wi), (1, wi)):
        row = np.minimum(i0 + di, table.incidence.size - 1)
        for r in np.unique(row):
            at = row == r
            p0, wp = node_weights(table.rows[r], psi[at])
            last = table.rows[r].size - 1
            for dp, fp in ((0, 1.0 - wp), (1, wp)):
                slices[at, 2 * di + dp] = table.row_start[r] + np.minimum(p0 + dp, last)
                weights[at, 2 * di + dp] = fi[at] * fp
    return slices, weights


def _read_nodes(table: ShareTable, corners, elevation, phi, turned_from=None) -> np.ndarray:
    """The shares at views (``elevation``, ``phi``: (n,) degrees) read multilinearly between the four light nodes
    ``corners`` (:func:`light_slices`' slices and weights) and the view nodes: (n, CHANNELS) fractions. With
    ``turned_from`` (the lights' incidence and azimuth, (n,) each) each light node reads the view turned with the
    light: its azimuth and elevation moved by the node's less the light's, so that ``V = L`` reads every node's own
    hot spot."""
    slices, weights = corners
    step = table.azimuth_step
    node_incidence, node_azimuth = table.slice_incidence, table.slice_azimuth
    shares = np.zeros((len(elevation), CHANNELS))
    for k in range(4):
        at_slice = slices[:, k]
        at_e = (elevation if turned_from is None
                else np.clip(elevation + node_incidence[at_slice] - turned_from[0], 0.0, 90.0))
        e0, we = node_weights(table.elevation, at_e)
        at = phi if turned_from is None else np.mod(phi + node_azimuth[at_slice] - turned_from[1], 360.0)
        a0 = np.floor(at / step).astype(int) % table.azimuth_nodes
        wa = at / step - np.floor(at / step)
        for de, fe in ((0, 1.0 - we), (1, we)):
            for da, fa in ((0, 1.0 - wa), (1, wa)):
                node = table.shares[at_slice, np.minimum(e0 + de, table.elevation.size - 1),
                                    (a0 + da) % table.azimuth_nodes]
                shares += (weights[:, k] * fe * fa)[:, None] * node
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
    corners = light_slices(table, incidence, psi)
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
    """The four light nodes around one light (:func:`light_slices`) and their weights, with the light turned to the
    table's azimuths: what the shader reads a light's shares from.

    Returns
    -------
    slices : (4,) int array
        The corners' slices of the table's texture (:func:`roughlight.render.implicit.shader`).
    weights : (4,) float array (summing to 1)
    light_c : (3,) array, the light turned (unit vector toward it)
    turn : (3, 3) array, the turn that takes a view along (``view_c = turn @ view``)
    """
    light = shading.light_direction(incidence, light_azimuth)
    eye = np.eye(3)
    light_c, turned = canonical_directions(table.surface, np.vstack([light, light, light]), eye)
    turn = np.column_stack(turned)  # images of the basis vectors: the map's matrix
    _, psi, _, _ = table_angles(light_c[:1], eye[:1])
    slices, weights = light_slices(table, [incidence], psi)
    return slices[0], weights[0], light_c[0], turn
