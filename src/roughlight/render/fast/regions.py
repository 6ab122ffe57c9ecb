"""Each facet's lit and shadowed parts of one period under a light: the *regions* the fast renderer's shares are
counted and corrected over (:mod:`roughlight.render.fast.shares`), from the exact reference's polygon clipping of the
light's view (:func:`roughlight.render.exact.reference.lit_scene`), once a sweep; and their edges.

Coordinates: plan ``(x, y, z)`` of one period, z on each facet's plane ``z = alpha x + beta y + gamma``.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from ...surfaces.geometry import ring_next

__all__ = ["Regions", "facet_regions", "adaptive_regions", "facet_edges", "unique_edges", "MAX_FACETS",
           "KEPT_REGIONS"]

#: Largest number of facets whose (facet, lit) identity fits two 8-bit channels (2 F + 1 < 65536).
MAX_FACETS = 32767


@dataclass(frozen=True)
class Regions:
    """The lit and shadowed parts of each facet of one period under one light.

    Attributes
    ----------
    facet : (R,) int array
        The facet each region belongs to (index into ``normals``).
    lit : (R,) bool array
        True for the lit part, False for the shadowed part.
    rings : list of R lists of (n, 3) float arrays
        Each region's boundary rings in plan coordinates with their heights, the exterior counter-clockwise and
        holes clockwise (seen from above); an empty list for an empty region.
    normals : (F, 3) float array
        Unit facet normals.
    alpha, beta : (F,) float arrays
        The facets' planes ``z = alpha x + beta y + gamma``.
    """

    facet: np.ndarray
    lit: np.ndarray
    rings: list
    normals: np.ndarray
    alpha: np.ndarray
    beta: np.ndarray


def facet_regions(surface, incidence: float, shadows: bool, light_azimuth: float = 0.0) -> Regions:
    """The lit and shadowed part of every facet (exact polygon clipping of the light's view, once a sweep), the
    light at ``incidence`` and ``light_azimuth`` (degrees).

    Kept for the process's last :data:`KEPT_REGIONS` surfaces and lights (a random tile's take seconds, and the
    measurements and tests draw one tile under one light many times): the arrays come back read-only."""
    return _kept_regions(surface, float(incidence), bool(shadows), float(light_azimuth))


#: How many surfaces' and lights' :func:`facet_regions` a process keeps.
KEPT_REGIONS = 16


@functools.lru_cache(maxsize=KEPT_REGIONS)
def _kept_regions(surface, incidence: float, shadows: bool, light_azimuth: float) -> Regions:
    regions = _facet_regions(surface, incidence, shadows, light_azimuth)
    for values in (regions.facet, regions.lit, regions.normals, regions.alpha, regions.beta,
                   *(ring for rings in regions.rings for ring in rings)):
        values.setflags(write=False)
    return regions


def _facet_regions(surface, incidence: float, shadows: bool, light_azimuth: float) -> Regions:
    import shapely

    from ..exact.clipping import area_parts
    from ..exact.reference import lit_scene

    scene = lit_scene(surface, incidence, shadows, light_azimuth)
    surf = scene.surf
    n_facets = len(surf.names)
    lit = np.array(scene.lit, dtype=object)
    shadowed = np.array(surf.footprints, dtype=object)
    cut = np.flatnonzero(~shapely.is_empty(lit))
    shadowed[cut] = area_parts(shapely.difference(shadowed[cut], lit[cut]))
    facet = np.repeat(np.arange(n_facets), 2)  # each facet's lit part, then its shadowed part
    region = np.empty(2 * n_facets, dtype=object)
    region[0::2], region[1::2] = lit, shadowed
    rings = _region_rings(region, surf.alpha[facet], surf.beta[facet], surf.gamma[facet])
    return Regions(facet, np.tile([True, False], n_facets), rings, np.asarray(surf.normals, float),
                   np.asarray(surf.alpha, float), np.asarray(surf.beta, float))


def _region_rings(regions, alpha, beta, gamma) -> list:
    """Each region's boundary rings with their heights, for :class:`Regions`: (n, 3) arrays, each polygon of
    positive area oriented (its exterior counter-clockwise, then its holes clockwise), its closing corner left out.

    Parameters
    ----------
    regions : (R,) object array
        Shapely polygons or multipolygons in plan coordinates.
    alpha, beta, gamma : (R,) arrays
        The plane ``z = alpha x + beta y + gamma`` of each region's facet.
    """
    import shapely

    parts, owner = shapely.get_parts(regions, return_index=True)
    kept = ~shapely.is_empty(parts) & (shapely.area(parts) > 0.0)
    parts, owner = shapely.orient_polygons(parts[kept], exterior_cw=False), owner[kept]
    rings, ring_polygon = shapely.get_rings(parts, return_index=True)
    xy, ring_of = shapely.get_coordinates(rings, return_index=True)
    corner = np.ones(len(xy), bool)
    corner[np.cumsum(shapely.get_num_coordinates(rings)) - 1] = False  # each ring's closing corner
    xy, ring_of = xy[corner], ring_of[corner]
    r = owner[ring_polygon][ring_of]
    corners = np.column_stack([xy, alpha[r] * xy[:, 0] + beta[r] * xy[:, 1] + gamma[r]])
    out = [[] for _ in range(len(regions))]
    ring_owner = owner[ring_polygon]
    for k, ring in enumerate(np.split(corners, np.cumsum(np.bincount(ring_of, minlength=len(rings)))[:-1])):
        out[ring_owner[k]].append(ring)
    return out


def adaptive_regions(surface, incidence: float, shadows: bool, light_azimuth: float = 0.0) -> Regions:
    """:func:`facet_regions` for adaptive sampling, which takes at most :data:`MAX_FACETS` facets a period (the
    facet identities the framebuffer holds); raises ``ValueError`` naming the surface's count beyond that."""
    regions = facet_regions(surface, incidence, shadows, light_azimuth)
    if len(regions.normals) > MAX_FACETS:
        raise ValueError(f"render.sampling: adaptive takes at most {MAX_FACETS} facets a period, "
                         f"this surface has {len(regions.normals)}; use lattice")
    return regions


def facet_edges(regions: Regions):
    """Every ring edge: start (E, 3), end (E, 3), region (E,)."""
    start, end, owner = [], [], []
    for r, rings in enumerate(regions.rings):
        for ring in rings:
            start.append(ring)
            end.append(ring_next(ring))
            owner.append(np.full(len(ring), r))
    if not start:
        return np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, int)
    return np.concatenate(start), np.concatenate(end), np.concatenate(owner)


def unique_edges(regions: Regions):
    """Every edge once: start (E, 3), end (E, 3) and the regions on its two sides (E, 2).

    The first side owns the edge's direction (its interior on the left, seen from above). An edge on the cell's
    border is paired with the next period's copy of the edge it meets, whose region is then its second side; -1
    where no copy matches vertex for vertex.
    """
    start, end, owner = facet_edges(regions)
    rounded = [(tuple(a), tuple(b)) for a, b in zip(np.round(start, 9), np.round(end, 9))]
    # polygon clipping can leave zero-width spikes, an edge there and back within one region: they bound nothing
    ring = set(zip(rounded, owner.tolist()))
    solid = [k for k, ((a, b), r) in enumerate(zip(rounded, owner.tolist())) if ((b, a), r) not in ring]
    found = {}
    for k in solid:
        a, b = rounded[k]
        found.setdefault((b, a) if (b, a) in found else (a, b), []).append(k)
    keep = np.array([ks[0] for ks in found.values()], int)
    sides = np.array([[owner[ks[0]], owner[ks[1]] if len(ks) > 1 else -1] for ks in found.values()], int)
    start, end, sides = start[keep], end[keep], sides.reshape(-1, 2)
    lone = {rounded[keep[k]]: k for k in range(len(keep)) if sides[k, 1] < 0}
    absorbed = set()
    for k in lone.values():
        if k in absorbed or sides[k, 1] >= 0:
            continue
        for step in ((1.0, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, -1.0, 0.0)):
            other = lone.get((tuple(np.round(end[k] + step, 9)), tuple(np.round(start[k] + step, 9))))
            if other is not None and other != k and other not in absorbed:
                sides[k, 1] = sides[other, 0]
                absorbed.add(other)
                break
    kept = np.array([k for k in range(len(sides)) if k not in absorbed], int)
    return start[kept], end[kept], sides[kept]
