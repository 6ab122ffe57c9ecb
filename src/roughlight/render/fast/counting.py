"""Random tiles on the GL side: each region's visible and total pixels counted as it is drawn.

A random tile (:mod:`roughlight.surfaces.roughness`) has hundreds of facets. Its views are measured as the regular
surface's adaptive sampling measures them (:mod:`roughlight.render.fast.shares`), each region (the lit or the
shadowed part of a facet) weighted by its facet's 8-bit values; the sweep puts it together
(:func:`roughlight.render.fast.periodic.counted_shares`). Where nothing is hidden a region's share is its exact
projected area (:func:`roughlight.render.fast.shares.projected_areas`), unrendered. The other views are drawn
here, a framebuffer of tiles at a time, in one pass of the copies (:mod:`roughlight.render.fast.passes`) with
``shaders/periodic_count.frag``, on the lattices and at the densities
:func:`roughlight.render.fast.sampling.counting_passes` chose:

* The tile is drawn as its regions' triangles (:func:`region_triangles`), each vertex carrying its region, so the
  lit and the shadowed part of a facet are told apart by the exact polygons, not by a shadow map (the context
  builds none).
* Each fragment adds one to its view's count of its region (an atomic counter on the GL side). The shader runs
  before the depth test (it has side effects and asks for no early tests), so every fragment counts, hidden or
  not: the total is exactly the number of pixel centres in the region's projection, the count
  :func:`roughlight.render.fast.shares.counts_and_areas` computes from polygons.
* The depth test keeps the nearest fragment's region in the image, which is read back: each view's pixels of each
  region are its visible count. ``visible / total`` is the region's visible fraction with the pixel errors along
  its own edges cancelled (:func:`roughlight.render.fast.shares.normalised_shares`); times the exact area it is
  the region's share, and what remains is the error along the edges of whatever hides it.
* A pass whose ``totals`` is False (views near the horizon) counts the visible pixels only, with early depth
  tests.
"""

from __future__ import annotations

import numpy as np

from ..gl.context import GLTF, Primitive, context, gl
from .passes import ATTRIBUTES, batch_poses, begin_pass, depth_scale, draw, set_viewport_uniforms

__all__ = ["region_triangles", "counted_batches", "counted_pixels"]


def counted_pixels(height: float, regions, views, shears, drawn, shadow_map_size: int):
    """Visible and total pixel counts (n, R) of each region in each of the views ``drawn.members`` (in order),
    and a tile's pixel count: :func:`counted_batches` of the tile's :func:`region_triangles`, gathered."""
    batches = list(counted_batches(height, region_triangles(regions), len(regions.rings), views, shears, drawn,
                                   shadow_map_size))
    per_tile = batches[0][3]
    return (np.concatenate([b[1] for b in batches]), np.concatenate([b[2] for b in batches]), per_tile)


def counted_batches(height, triangles, n_regions, views, shears, drawn, shadow_map_size: int):
    """For each framebuffer of the views of one lattice pass: those views' indices, their visible and total pixel
    counts (n, R) of each region (the total None unless ``drawn.totals``), and a tile's pixel count.

    Parameters
    ----------
    height : float
        The tile's height (periods).
    triangles : tuple
        :func:`region_triangles` of its ``n_regions`` regions.
    views, shears : (V, 3), (V, 2) arrays
        Unit vectors toward the detector and their plan shifts ``d = (V_x / V_z, V_y / V_z)``.
    drawn : LatticePass
        :class:`roughlight.render.fast.sampling.LatticePass`: the views (indices into ``views``), the lattice, its
        layout and whether every fragment is counted (unshifted: its ``shift`` and ``weights`` are not read).
    shadow_map_size : int
        The tile settings' (the context's key; no shadow map is built).
    """
    matrix = np.asarray(drawn.matrix)
    width, height_px, slots, pixel_order = drawn.layout
    hidden = drawn.members
    ctx = context(width, height_px, int(shadow_map_size))
    per_tile = len(pixel_order) // len(slots)
    buffer = gl.glGenBuffers(1)
    try:
        for first in range(0, hidden.size, len(slots)):
            idx = hidden[first:first + len(slots)]
            poses = batch_poses(height, views, shears, idx, slots, np.zeros(2))
            slot_pixels = pixel_order[: idx.size * per_tile].reshape(idx.size, per_tile)
            seen, total = _count_batch(ctx, triangles, height, poses, matrix, width, height_px, buffer, slot_pixels,
                                       n_regions, drawn.totals)
            yield idx, seen, total, per_tile
    finally:
        gl.glDeleteBuffers(1, [buffer])


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
            x, y = ring[:, 0], ring[:, 1]
            twice_area = np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))
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
    parts, index = shapely.get_parts(shapely.constrained_delaunay_triangles(valid), return_index=True)
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


def _count_batch(ctx, triangles, height, poses, matrix, width, height_px, buffer, slot_pixels, n_regions,
                 totals=True):
    """One framebuffer of views in one pass: every fragment counted on the GL side as the image is drawn (unless
    not ``totals``), then each slot's visible regions read from the image.

    Parameters
    ----------
    slot_pixels : (n, N) int array
        Each drawn view's pixels (indices into the framebuffer's row-major pixels), N a tile.
    totals : bool
        Count every fragment; False: draw with early depth tests and count none.

    Returns
    -------
    visible : (n, R) float array
    total : (n, R) float array, or None unless ``totals``
    """
    if n_regions >= 0xFFFF:
        raise ValueError(f"a tile of {n_regions // 2} facets is too many to count (the image holds 16-bit regions)")
    begin_pass(0, width, height_px, gl.GL_COLOR_BUFFER_BIT | gl.GL_DEPTH_BUFFER_BIT)
    program = ctx.programs.get_program("periodic.vert", "periodic_count.frag",
                                       defines=ATTRIBUTES if totals else {**ATTRIBUTES, "VISIBLE_ONLY": 1})
    size = len(slot_pixels) * n_regions
    if totals:
        gl.glBindBuffer(gl.GL_SHADER_STORAGE_BUFFER, buffer)
        gl.glBufferData(gl.GL_SHADER_STORAGE_BUFFER, size * 4, np.zeros(size, np.uint32), gl.GL_DYNAMIC_READ)
        gl.glBindBufferBase(gl.GL_SHADER_STORAGE_BUFFER, 0, buffer)
    program._bind()
    set_viewport_uniforms(program, matrix, width, height_px, np.zeros(2), depth_scale(height))
    program.set_uniform("n_regions", int(n_regions))
    draw(ctx, _region_primitive(*triangles, poses), program)
    program._unbind()
    total = None
    if totals:
        gl.glMemoryBarrier(gl.GL_BUFFER_UPDATE_BARRIER_BIT)
        total = np.frombuffer(gl.glGetBufferSubData(gl.GL_SHADER_STORAGE_BUFFER, 0, size * 4), np.uint32)
        total = total.reshape(len(slot_pixels), n_regions).astype(float)
    raw = gl.glReadPixels(0, 0, width, height_px, gl.GL_RGBA, gl.GL_UNSIGNED_BYTE)
    return _visible_counts(raw, slot_pixels, n_regions), total


def _region_primitive(tris, region, poses):
    """The region triangles as one instanced primitive at the copies ``poses``; each vertex carries its region."""
    positions = tris.reshape(-1, 3).astype(np.float32)
    # normals unused, but present: pyrender numbers the attributes in order (passes.ATTRIBUTES)
    return Primitive(positions=positions, normals=np.broadcast_to(np.float32([0, 0, 1]), positions.shape),
                     texcoord_0=np.repeat(np.stack([region.astype(np.float32), np.zeros(len(region), np.float32)],
                                                   axis=1), 3, axis=0),
                     mode=GLTF.TRIANGLES, poses=poses)


def _visible_counts(raw: bytes, slot_pixels, n_regions: int) -> np.ndarray:
    """(n, R) each view's pixels of each region, from the framebuffer's RGBA bytes (the region + 1 in red and
    green, 0 where no surface) at the views' pixels ``slot_pixels`` ((n, N))."""
    n_views = len(slot_pixels)
    key = np.frombuffer(raw, np.uint16)[0::2].take(slot_pixels).astype(np.int32)  # red + 256 green, little-endian
    key += (np.arange(n_views, dtype=np.int32) * (n_regions + 1))[:, None]  # bin 0 of each view: no surface
    counts = np.bincount(key.ravel(), minlength=n_views * (n_regions + 1))
    return counts.reshape(n_views, n_regions + 1)[:, 1:].astype(float)
