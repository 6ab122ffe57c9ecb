"""The clipping engine of the exact reference (:mod:`roughlight.render.exact.reference`): one period's facets, the
lattice copies that can hide them, and each facet's visible region along a direction (toward the viewer or the
light) in that direction's oblique base-plane coordinates, by GEOS overlays (shapely).

The method is :mod:`roughlight.render.exact.reference`'s ("Oblique coordinates"): the visible region of a facet is its
projection minus the union of the projections, on their overlap, of the facet copies in front of it. Overlays run
in double precision, or snap-rounded to a grid (``grid_size``) where the reference falls back to that.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import shapely

from ...surfaces.geometry import facet_polygons, period_triangles
from ...surfaces.surface import Surface
from ...surfaces.symmetry import symmetry

__all__ = ["Facets", "period_facets", "lattice_offsets", "area_parts", "affine_each", "overlay",
           "visible_regions", "projection_ratios", "to_oblique", "from_oblique", "MIN_OVERLAP", "EDGE_ON", "MAX_COPIES"]

#: Overlaps of smaller area (period^2) are floating-point slivers: ignored.
MIN_OVERLAP = 1e-13
#: Facets whose projection has a smaller area ratio are edge-on: not seen / not lit.
EDGE_ON = 1e-12
#: Refuse views that would need more lattice copies than this (near grazing).
MAX_COPIES = 200_000


@dataclass
class Facets:
    """The facets of one period (:func:`roughlight.surfaces.geometry.facet_polygons`), with their planes."""

    names: list
    verts: list  # (n, 3) arrays, one per facet
    normals: np.ndarray  # (F, 3) unit normals (period_triangles', as the renderer uses)
    alpha: np.ndarray  # facet plane z = alpha x + beta y + gamma
    beta: np.ndarray
    gamma: np.ndarray
    height: float
    plate: bool
    footprints: list = field(default_factory=list)  # shapely polygons in (x, y)
    corners: np.ndarray = None  # (F, n, 3) each facet's vertices, its last repeated up to the most a facet has
    sides: np.ndarray = None  # (F,) int, each facet's vertex count
    #: what the surface repeats (:func:`roughlight.surfaces.symmetry.symmetry`): ``square`` for regular pyramids
    symmetry: str = "none"
    #: views clipped, and facets' images under the square's symmetries (:mod:`roughlight.render.exact.square_views`)
    views: dict = field(default_factory=dict, repr=False)
    facet_maps: dict = field(default_factory=dict, repr=False)


def period_facets(surface: Surface) -> Facets:
    """One period's facets of ``surface`` (a regular surface or a random tile): polygons, the renderer's unit
    normals, planes ``z = alpha x + beta y + gamma`` and plan footprints."""
    polys = facet_polygons(surface)
    _, tri_normals, tri_names = period_triangles(surface)
    names = [name for name, _ in polys]
    verts = [np.asarray(v, float) for _, v in polys]
    first = {}  # each name's first triangle
    for k, name in enumerate(tri_names):
        first.setdefault(name, k)
    normals = np.array([tri_normals[first[name]] for name in names], float)
    alpha = -normals[:, 0] / normals[:, 2]
    beta = -normals[:, 1] / normals[:, 2]
    gamma = np.array([v[0, 2] - al * v[0, 0] - be * v[0, 1] for v, al, be in zip(verts, alpha, beta)])
    plate = surface.is_plate
    height = surface.height
    footprints = [shapely.Polygon(v[:, :2]) for v in verts]
    sides = np.array([len(v) for v in verts])
    corners = np.stack([v[np.minimum(np.arange(sides.max()), len(v) - 1)] for v in verts])
    return Facets(names, verts, normals, alpha, beta, gamma, height, plate, footprints, corners, sides,
                  symmetry(surface))


def lattice_offsets(height: float, d: np.ndarray) -> np.ndarray:
    """Offsets ``(m, n)`` of the period copies whose projection can overlap period 0's.

    A point of a period at height ``z`` in ``[0, H]`` projects to
    ``(x, y) - z d``, so the projection of the copy at ``(m, n)`` lies in the
    unit square at ``(m, n)`` swept along ``[0, -H d]``; two such regions
    overlap only if ``(m, n) - lam H d`` is in ``[-1, 1]^2`` for some
    ``lam`` in ``[-1, 1]``. Returns an ``(K, 2)`` float array, ``(0, 0)`` first.
    """
    hd = height * np.asarray(d, float)
    mx = int(math.ceil(1.0 + abs(hd[0]))) + 1
    my = int(math.ceil(1.0 + abs(hd[1]))) + 1
    if (2 * mx + 1) * (2 * my + 1) > 50 * MAX_COPIES:
        raise ValueError(
            "view too close to grazing for the exact reference "
            f"(surface top shifted by {hd} periods)"
        )
    m, n = np.meshgrid(np.arange(-mx, mx + 1), np.arange(-my, my + 1), indexing="ij")
    m, n = m.ravel().astype(float), n.ravel().astype(float)
    lo = np.full(m.shape, -1.0)
    hi = np.full(m.shape, 1.0)
    slack = 1.0 + 1e-9
    for c, h in ((m, hd[0]), (n, hd[1])):
        if abs(h) > 1e-15:
            a_, b_ = (c - slack) / h, (c + slack) / h
            lo = np.maximum(lo, np.minimum(a_, b_))
            hi = np.minimum(hi, np.maximum(a_, b_))
        else:
            hi = np.where(np.abs(c) <= slack, hi, -2.0)
    keep = lo <= hi
    off = np.stack([m[keep], n[keep]], axis=1)
    if len(off) > MAX_COPIES:
        raise ValueError(
            f"view too close to grazing for the exact reference ({len(off)} lattice copies needed)"
        )
    centre = np.flatnonzero((off[:, 0] == 0) & (off[:, 1] == 0))
    order = np.concatenate([centre, np.setdiff1d(np.arange(len(off)), centre)])
    return off[order]


def _polygonal(geometry, grid_size):
    """The polygonal part of a geometry (or of each in an array, any shape; None stays None), snapped to
    ``grid_size``: a snap-rounded overlay can leave collapsed slivers as lines or points, which carry no area."""
    if geometry is None:
        return None
    if isinstance(geometry, np.ndarray):
        return np.array([_polygonal(g, grid_size) for g in geometry], dtype=object)
    # lines and points first: set_precision on a mixed collection can drop its polygons too
    geometry = shapely.set_precision(area_parts(geometry), grid_size)
    return geometry if geometry.geom_type in ("Polygon", "MultiPolygon") else area_parts(geometry)


def area_parts(geometry):
    """The polygons of a geometry, valid, without the lines and points an overlay can leave (they carry no area);
    of an array of geometries, each one's, made valid in one GEOS call."""
    if isinstance(geometry, np.ndarray):  # made valid once: make_valid keeps a valid geometry as it is
        valid = np.array(shapely.make_valid(geometry), dtype=object, ndmin=1)
        for i in np.flatnonzero(~_is_polygonal(valid)):
            valid[i] = _polygons_of(valid[i])
        return valid
    geometry = shapely.make_valid(geometry)
    if geometry.geom_type in ("Polygon", "MultiPolygon"):
        return geometry
    return _polygons_of(geometry)


def _is_polygonal(geometries) -> np.ndarray:
    """(n,) bool: which geometries are a Polygon or a MultiPolygon."""
    return np.isin(shapely.get_type_id(geometries), (shapely.GeometryType.POLYGON, shapely.GeometryType.MULTIPOLYGON))


def _polygons_of(geometry):
    """The union of a valid geometry's polygonal parts (an empty polygon if it has none)."""
    parts = [p for p in shapely.get_parts(geometry) if p.geom_type in ("Polygon", "MultiPolygon")]
    return shapely.union_all(parts) if parts else shapely.Polygon()


def overlay(operation, *geometries, grid_size=None, **options):
    """A GEOS overlay: in double precision, or snap-rounded to ``grid_size`` (robust; see
    :data:`roughlight.render.exact.reference.SNAP_GRID`). ``options`` go to ``operation`` (``axis`` of
    ``shapely.union_all``)."""
    if grid_size is None:
        return operation(*geometries, **options)
    snapped = [_polygonal(g, grid_size) for g in geometries]
    return _polygonal(operation(*snapped, grid_size=grid_size, **options), grid_size)


def projection_ratios(surf: Facets, d) -> np.ndarray:
    """(F,) each facet's area ratio of its projection along the direction with plan shift ``d`` (oblique area over
    plan area, ``1 - alpha dx - beta dy``): at most :data:`EDGE_ON` where the facet faces away or is edge-on."""
    return 1.0 - surf.alpha * d[0] - surf.beta * d[1]


def visible_regions(surf: Facets, d, grid_size=None) -> tuple[list, np.ndarray]:
    """Visible region of each facet of period 0 along the direction with plan shift ``d``.

    ``d = (Dx/Dz, Dy/Dz)`` for a direction ``D`` (toward the viewer or the
    light) with ``Dz > 0``. Coordinates are the oblique ones
    ``(x - z dx, y - z dy)``; a point is in front when its ``z`` is larger.
    A facet's visible region is its projection minus the overlaps with the
    projections of the facet copies in front of it (:func:`_visible_parts`).

    Returns
    -------
    list of shapely geometries (empty polygon for facets not facing ``D``),
    one per facet, and the per-facet area ratio ``det`` of the projection.
    """
    d = np.asarray(d, float)
    det = projection_ratios(surf, d)
    front = np.flatnonzero(det > EDGE_ON)
    empty = shapely.Polygon()
    out = [empty] * len(surf.names)
    if len(front) == 0:
        return out, det
    offsets = lattice_offsets(surf.height, d)
    copies = projected_copies(surf, front, d, offsets)
    homes = np.arange(len(front)) * len(offsets)
    for f, region in zip(front, _visible_parts(surf, front, det, copies, homes, may_overlap(copies, homes),
                                                grid_size)):
        out[f] = region
    return out, det


class _Copies(NamedTuple):
    """The projections of every front-facing facet of every lattice copy along one direction, facet-major:
    facet ``front[j]``'s copies are rows ``j K .. (j + 1) K - 1``, offset ``(0, 0)`` first (``K`` offsets)."""

    #: (F' K,) shapely polygons in oblique coordinates
    geoms: np.ndarray
    #: (F' K,) int, the facet each copy is of
    owner: np.ndarray
    #: (F' K, 2) float, each copy's lattice offset (periods)
    offs: np.ndarray
    #: (F' K, 4) float, each copy's bounding box (xmin, ymin, xmax, ymax)
    bbox: np.ndarray
    #: (F' K, n, 2) float, each copy's vertices (the last one repeated up to the most a front facet has, n)
    points: np.ndarray
    #: (F' K, n, 2) float, the normals of each copy's edges (the first one repeated up to n): the axes that
    #: separate two convex polygons that do not overlap
    axes: np.ndarray


def projected_copies(surf: Facets, front, d, offsets) -> _Copies:
    """Project the facets ``front`` of every lattice copy at ``offsets`` ((K, 2), ``(0, 0)`` first) along the
    direction with plan shift ``d`` into oblique coordinates."""
    n_off = len(offsets)
    sides = surf.sides[front]
    n_max = int(sides.max())
    corners = surf.corners[front, :n_max]  # (F', n, 3)
    p = corners[..., :2] - corners[..., 2:3] * d  # (F', n, 2), period 0
    coords = p[:, None, :, :] + offsets[None, :, None, :]  # (F', K, n, 2)
    geoms = np.empty((len(front), n_off), dtype=object)
    for n in np.unique(sides):
        geoms[sides == n] = shapely.polygons(coords[sides == n][:, :, :n])
    # each edge from corner i to the next (the first after the last); padding repeats the first edge
    i = np.arange(n_max)[None, :]
    start = np.where(i < sides[:, None], i, 0)
    end = np.where(start + 1 < sides[:, None], start + 1, 0)
    rows = np.arange(len(front))[:, None]
    edge = p[rows, end] - p[rows, start]
    normal = np.stack([-edge[..., 1], edge[..., 0]], axis=-1)  # (F', n, 2)
    coords = coords.reshape(-1, n_max, 2)
    return _Copies(geoms.ravel(), np.repeat(front, n_off), np.tile(offsets, (len(front), 1)),
                   np.concatenate([coords.min(axis=1), coords.max(axis=1)], axis=1), coords,
                   np.repeat(normal, n_off, axis=0))


def _visible_parts(surf: Facets, front, det, copies: _Copies, homes, near, grid_size=None) -> np.ndarray:
    """Each facet ``front[j]``'s visible region: its period-0 projection (``copies`` row ``homes[j]``) minus the
    union of its overlaps, of more than :data:`MIN_OVERLAP`, with the copies ``near[j]`` (those it may overlap,
    :func:`may_overlap`) in front of it there (:func:`_in_front`); the projection itself where none is.

    Every facet's overlaps are clipped in one GEOS call, their unions in one (a row of occluders a facet, in the
    order of ``near[j]``) and the differences in one: each facet's overlays are those of a loop over the facets."""
    whole = copies.geoms[homes]
    out = whole.copy()
    count = np.array([len(idx) for idx in near], int)
    if count.sum() == 0:
        return out
    row, other = np.repeat(np.arange(len(front)), count), np.concatenate(near)
    inter = overlay(shapely.intersection, copies.geoms[homes[row]], copies.geoms[other], grid_size=grid_size)
    ok = shapely.area(inter) > MIN_OVERLAP
    row, other, inter = row[ok], other[ok], inter[ok]
    ahead = _in_front(surf, front[row], det, inter, copies.owner[other], copies.offs[other])
    row, occ = row[ahead], inter[ahead]
    if len(row) == 0:
        return out
    hidden, first, n_occ = np.unique(row, return_index=True, return_counts=True)
    table = np.full((len(hidden), n_occ.max()), None, dtype=object)  # each hidden facet's occluders, in order
    table[np.repeat(np.arange(len(hidden)), n_occ), np.arange(len(row)) - np.repeat(first, n_occ)] = occ
    union = overlay(shapely.union_all, table, grid_size=grid_size, axis=1)
    out[hidden] = overlay(shapely.difference, whole[hidden], union, grid_size=grid_size)
    return out


def may_overlap(copies: _Copies, homes) -> list:
    """For each row of ``homes`` ((H,) rows of ``copies``), the rows whose projection may overlap it in some
    area, in ascending order: bounding boxes overlapping by more than 1e-12 (periods) both ways, then no edge
    normal of either separating them (facets are convex, :func:`roughlight.surfaces.geometry.facet_polygons`, so
    a separating axis means they touch at most). GEOS need not intersect the others: their overlap would be
    dropped as under :data:`MIN_OVERLAP`. The home row itself is left out.

    The candidates are those whose bounding boxes meet at all (a GEOS STRtree of the copies), the boxes' margins
    then tested exactly."""
    homes = np.asarray(homes, int)
    which, other = shapely.STRtree(copies.geoms).query(copies.geoms[homes])
    home_box, box = copies.bbox[homes[which]], copies.bbox[other]
    tol = 1e-12
    near = ((box[:, 0] < home_box[:, 2] - tol) & (box[:, 2] > home_box[:, 0] + tol)
            & (box[:, 1] < home_box[:, 3] - tol) & (box[:, 3] > home_box[:, 1] + tol) & (other != homes[which]))
    which, other = which[near], other[near]
    keep = ~_separated(copies, homes[which], other)
    which, other = which[keep], other[keep]
    order = np.lexsort((other, which))
    which, other = which[order], other[order]
    return np.split(other, np.searchsorted(which, np.arange(1, len(homes))))


def _separated(copies: _Copies, a, b) -> np.ndarray:
    """(P,) bool: where an edge normal of copy ``a`` or of copy ``b`` ((P,) rows each) separates their convex
    projections (they touch at most)."""
    p_a, p_b = copies.points[a], copies.points[b]  # (P, n, 2)
    apart = np.zeros(len(a), bool)
    for axes in (copies.axes[a], copies.axes[b]):  # (P, n, 2)
        on_a = p_a[:, :, None, 0] * axes[:, None, :, 0] + p_a[:, :, None, 1] * axes[:, None, :, 1]  # (P, n, n)
        on_b = p_b[:, :, None, 0] * axes[:, None, :, 0] + p_b[:, :, None, 1] * axes[:, None, :, 1]
        apart |= np.any((on_a.max(axis=1) <= on_b.min(axis=1)) | (on_b.max(axis=1) <= on_a.min(axis=1)), axis=1)
    return apart


def _in_front(surf: Facets, f, det, inter, owner, offs) -> np.ndarray:
    """(k,) bool: where the copy of facet ``owner`` at lattice offset ``offs`` ((k,) and (k, 2)) is higher than
    facet ``f`` of period 0 (one, or (k,) of them) at the centroid of their overlap ``inter`` (oblique
    coordinates): there it is in front throughout (facets meet only at edges)."""
    c = shapely.get_coordinates(shapely.centroid(inter))  # (k, 2)
    z_g = (surf.alpha[owner] * (c[:, 0] - offs[:, 0]) + surf.beta[owner] * (c[:, 1] - offs[:, 1])
           + surf.gamma[owner]) / det[owner]
    z_f = (surf.alpha[f] * c[:, 0] + surf.beta[f] * c[:, 1] + surf.gamma[f]) / det[f]
    return z_g > z_f


def to_oblique(surf: Facets, f, d) -> list:
    """Affine map (shapely's 6-list) from plan ``(x, y)`` on facet ``f``'s plane to oblique coords (for an array
    of facets, each entry an array of theirs)."""
    al, be, ga = surf.alpha[f], surf.beta[f], surf.gamma[f]
    dx, dy = d
    # s = x - dx z, u = y - dy z, z = al x + be y + ga
    return [1.0 - dx * al, -dx * be, -dy * al, 1.0 - dy * be, -dx * ga, -dy * ga]


def from_oblique(surf: Facets, f, d) -> list:
    """Inverse of :func:`to_oblique` (the facet must not be edge-on; an array of facets as there)."""
    a, b, c, e, xo, yo = to_oblique(surf, f, d)
    det = a * e - b * c
    ia, ib, ic, ie = e / det, -b / det, -c / det, a / det
    return [ia, ib, ic, ie, -(ia * xo + ib * yo), -(ic * xo + ie * yo)]


def affine_each(geometries, matrix) -> np.ndarray:
    """Each 2D geometry of an array mapped by its own affine map: ``matrix`` is shapely's 6-list
    ``[a, b, d, e, xoff, yoff]`` with an (n,) array of each entry, one a geometry (:func:`from_oblique` of n
    facets). The arithmetic of ``shapely.affinity.affine_transform``, coordinate by coordinate, to the bit, in one
    pass over all the coordinates."""
    per_point = np.repeat(np.arange(len(geometries)), shapely.get_num_coordinates(geometries))
    a, b, d, e, xoff, yoff = (np.asarray(m, float)[per_point] for m in matrix)

    def mapped(coords):
        x, y = coords.T
        return np.stack([a * x + b * y + xoff, d * x + e * y + yoff]).T

    return shapely.transform(geometries, mapped)
