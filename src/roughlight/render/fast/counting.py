"""Random tiles: each region's visible and total pixels counted, view by view.

A random tile (:mod:`roughlight.surfaces.roughness`) has hundreds of facets. Its views are measured as the regular
surface's adaptive sampling measures them (:mod:`roughlight.render.fast.shares`), each region (the lit or the
shadowed part of a facet) weighted by its facet's 8-bit values; the sweep puts it together
(:func:`roughlight.render.fast.periodic.counted_shares`). Where nothing is hidden a region's share is its exact
projected area (:func:`roughlight.render.fast.shares.projected_areas`), uncounted. The other views are counted
here, on the lattices and at the densities :func:`roughlight.render.fast.sampling.counting_passes` chose:

* The tile is its regions' triangles (:func:`region_triangles`), each carrying its region, so the lit and the
  shadowed part of a facet are told apart by the exact polygons, not by a shadow map.
* Each view's pixel centres of one period are counted on the CPU (:func:`roughlight.render.fast.raster.count_views`):
  the *total* of a region is every centre of its projection, hidden or not (exactly the count
  :func:`roughlight.render.fast.shares.counts_and_areas` computes from polygons, but within rounding of an edge);
  its *visible* count the centres where it is the highest surface.
* ``visible / total`` is the region's visible fraction with the pixel errors along its own edges cancelled
  (:func:`roughlight.render.fast.shares.normalised_shares`); times the exact area it is the region's share, and
  what remains is the error along the edges of whatever hides it.
* A pass whose ``totals`` is False (views near the horizon) counts the visible centres only.

Until issue 46 these counts were drawn with OpenGL (llvmpipe), an atomic counter a region; the CPU counts the same
centres three to six times faster (docs/budgets.md).
"""

from __future__ import annotations

import numpy as np

from ...surfaces.geometry import twice_signed_area
from .raster import count_views

__all__ = ["region_triangles", "triangulated_regions", "counted_views", "counted_pixels", "VIEWS_AT_ONCE"]

#: Views counted at once: their (views, regions) counts are held together (a 4-cell heightfield tile's 1,024
#: regions make 16 MB a thousand views).
VIEWS_AT_ONCE = 1024


def counted_pixels(regions, shears, drawn):
    """Visible and total pixel counts (n, R) of each region in each of the views ``drawn.members`` (in order),
    and a tile's pixel count: :func:`counted_views` of the tile's :func:`region_triangles`, gathered."""
    batches = list(counted_views(region_triangles(regions), len(regions.rings), shears, drawn))
    total = None if not drawn.totals else np.concatenate([b[2] for b in batches])
    return np.concatenate([b[1] for b in batches]), total, batches[0][3]


def counted_views(triangles, n_regions: int, shears, drawn):
    """For each block of at most :data:`VIEWS_AT_ONCE` views of one lattice pass: those views' indices, their
    visible and total pixel counts (n, R) of each region (the total None unless ``drawn.totals``), and a tile's
    pixel count.

    Parameters
    ----------
    triangles : tuple
        :func:`region_triangles` of the tile's ``n_regions`` regions.
    shears : (V, 2) array
        Every view's plan shift ``d = (V_x / V_z, V_y / V_z)``; ``drawn.members`` index it.
    drawn : LatticePass
        :class:`roughlight.render.fast.sampling.LatticePass`: the views, the lattice and whether every centre is
        counted (unshifted: its ``shift`` and ``weights`` are not read).
    """
    tris, owner = triangles
    members = np.asarray(drawn.members)
    for first in range(0, members.size, VIEWS_AT_ONCE):
        idx = members[first:first + VIEWS_AT_ONCE]
        visible, total, per_tile = count_views(tris, owner, n_regions, shears[idx], drawn.matrix, drawn.totals)
        yield idx, visible, total, per_tile


#: The grid a region is snapped to where GEOS cannot triangulate it as it is (plan units, periods).
SNAP = 1e-12


def triangulated_regions(regions: np.ndarray) -> np.ndarray:
    """Each region's constrained Delaunay triangles. GEOS refuses a region whose hole touches its exterior to
    within 1e-18 ("Unable to find a convex corner": met once in 1,100 random tiles); such a region alone is
    snapped to :data:`SNAP` first, which moved that region's area by 1e-14. Every other region is
    triangulated as it is."""
    import shapely

    try:
        return shapely.constrained_delaunay_triangles(regions)
    except shapely.errors.GEOSException:
        out = np.empty(len(regions), dtype=object)
        for k, region in enumerate(regions):
            try:
                out[k] = shapely.constrained_delaunay_triangles(region)
            except shapely.errors.GEOSException:
                out[k] = shapely.constrained_delaunay_triangles(shapely.set_precision(region, SNAP))
        return out


def region_triangles(regions):
    """Each region triangulated: (T, 3, 3) corners (plan x, y and the facet's height, periods; counter-clockwise
    seen from above) and (T,) the region each triangle belongs to. The triangles of a region cover exactly its
    polygons (constrained Delaunay triangulation, holes left out), region after region. The regions are made valid
    and triangulated in whole-array GEOS calls (one call a region was most of a coarse random sweep's time)."""
    import shapely

    from ..exact.clipping import area_parts

    areas, kept = [], []
    for r, rings in enumerate(regions.rings):
        polygons = []
        for ring in rings:
            twice_area = twice_signed_area(ring[:, 0], ring[:, 1])
            if twice_area > 1e-15:  # an exterior starts a polygon
                polygons.append([ring[:, :2], []])
            elif twice_area < -1e-15 and polygons:  # a hole of the last exterior
                polygons[-1][1].append(ring[:, :2])
        if polygons:  # else zero-area slivers only
            areas.append(shapely.MultiPolygon([shapely.Polygon(ext, holes) for ext, holes in polygons]))
            kept.append(r)
    if not kept:
        return np.zeros((0, 3, 3)), np.zeros(0, int)
    valid = area_parts(np.array(areas, dtype=object))
    parts, index = shapely.get_parts(triangulated_regions(valid), return_index=True)
    owner = np.asarray(kept, int)[index]
    xy = shapely.get_coordinates(parts).reshape(len(parts), 4, 2)[:, :3]
    flip = (xy[:, 1, 0] - xy[:, 0, 0]) * (xy[:, 2, 1] - xy[:, 0, 1]) \
        - (xy[:, 1, 1] - xy[:, 0, 1]) * (xy[:, 2, 0] - xy[:, 0, 0]) < 0
    xy[flip] = xy[flip][:, ::-1]
    f = regions.facet[owner]
    first = np.array([regions.rings[r][0][0] for r in kept])[index]  # a corner of each region's first ring
    z0 = first[:, 2] - regions.alpha[f] * first[:, 0] - regions.beta[f] * first[:, 1]
    z = regions.alpha[f, None] * xy[..., 0] + regions.beta[f, None] * xy[..., 1] + z0[:, None]
    return np.concatenate([xy, z[..., None]], axis=2), owner
