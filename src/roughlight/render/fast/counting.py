"""Adaptive sampling of random tiles: each region's visible share from pixel counts made on the GL side.

A random tile (:mod:`roughlight.surfaces.roughness`) has hundreds of facets. Its views are measured as the regular
surface's adaptive sampling measures them (:mod:`roughlight.render.fast.shares`), each region (the lit or the shadowed
part of a facet) weighted by its facet's 8-bit values (:func:`roughlight.render.shading.facet_sum`):

* **Nothing hidden.** Where every facet faces the view, each region's share is its exact projected area: its plan
  area times its facet's area ratio ``det = 1 - alpha d_x - beta d_y`` (the projection along the view is affine on
  a facet). No rendering.
* **Something hidden.** The other views are drawn (those within :data:`GRAZING_BAND` of the horizon apart, at
  ``TileSettings.grazing_scale`` times the pixels), a framebuffer of tiles at a time, in one pass of the
  copies (:mod:`roughlight.render.fast.passes`) with ``shaders/periodic_count.frag``. The tile is drawn as its regions'
  triangles (:func:`region_triangles`), each vertex carrying its region, so the lit and the shadowed part of a facet
  are told apart by the exact polygons, not by a shadow map. Each fragment adds one to its view's count of its
  region (an atomic counter on the GL side). The shader runs before the depth test (it has side effects and asks
  for no early tests), so every fragment counts, hidden or not: the total is exactly the number of pixel centres in
  the region's projection, the count :func:`roughlight.render.fast.shares.counts_and_areas` computes from polygons. The
  depth test keeps the nearest fragment's region in the image, which is read back: each view's pixels of each
  region are its visible count. ``visible / total`` is the region's visible fraction with the pixel errors along
  its own edges cancelled (:func:`roughlight.render.fast.shares.ratio_shares`). Times the exact area it is the region's
  share; what remains is the error along the edges of whatever hides it.
* **Near the horizon.** Views within :data:`ORIENTED_BAND` of the horizon are each drawn on a lattice turned to
  their azimuth, and those within :data:`GRAZING_BAND` count their visible pixels only, with early depth tests
  (:func:`counting_passes`).
"""

from __future__ import annotations

import numpy as np

from ..gl.context import GLTF, Primitive, context, gl
from . import shares
from .passes import ATTRIBUTES, batch_poses, begin_pass, cached_layout, draw
from .sampling import oriented_lattices

__all__ = ["region_plan_areas", "projected_areas", "counted_shares"]

#: Largest framebuffer side (pixels) of the counting pass. A 4096-pixel framebuffer holds four times the views a
#: pass, but with its depth buffer and the counts it took a heightfield tile sweep to 1.2 GB; at 2048 it stays
#: under 0.75 GB and is no slower (random heightfield t 0.5, a 1, seed 2: 1.22 GB in 6.2 s against 0.73 GB in
#: 5.9 s, one llvmpipe thread).
FRAMEBUFFER = 2048

#: Views within this many degrees of the horizon are counted at ``TileSettings.grazing_scale`` times the
#: pixels (:func:`counted_shares`).
GRAZING_BAND = 10.0

#: Views within this many degrees of the horizon are each drawn on their own rotated lattice
#: (:func:`counting_passes`).
ORIENTED_BAND = 30.0

#: Facets with an area ratio below this face away from the view (as in :func:`roughlight.render.fast.shares.all_facing`).
FACING = 1e-9


def region_plan_areas(regions: shares.Regions) -> np.ndarray:
    """(R,) each region's plan area (periods^2): its rings' shoelace sums, holes (clockwise) subtracted."""
    out = np.zeros(len(regions.rings))
    for r, rings in enumerate(regions.rings):
        for ring in rings:
            x, y = ring[:, 0], ring[:, 1]
            out[r] += 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    return out


def projected_areas(regions: shares.Regions, plan_areas, shears) -> np.ndarray:
    """(V, R) each region's projected area along each view: its plan area times its facet's area ratio
    ``1 - alpha d_x - beta d_y``, 0 where the facet faces away (periods^2; a view's areas sum to 1 where nothing
    is hidden).

    Parameters
    ----------
    regions : Regions
    plan_areas : (R,) array
        :func:`region_plan_areas`.
    shears : (V, 2) array
        Each view's plan shift ``d = (V_x / V_z, V_y / V_z)``.
    """
    det = 1.0 - regions.alpha[None, :] * shears[:, 0:1] - regions.beta[None, :] * shears[:, 1:2]
    return plan_areas[None, :] * np.where(det > FACING, det, 0.0)[:, regions.facet]


def counted_shares(surface, incidence: float, views, lighting, settings, regions=None):
    """Each region's share of each view's image, for a random tile (see the module's description).

    Parameters
    ----------
    surface : RandomSurface
        Drawn as one period.
    incidence : float
        Light elevation, degrees in [0, 90] (light at azimuth 0).
    views : (V, 3) array
        Unit vectors toward the detector, none grazing (``V_z > 0``).
    lighting : Lighting
        Only whether it casts shadows matters here (the values come from :func:`roughlight.render.shading.facet_sum`).
    settings : FastSettings
        The tile's own (:meth:`FastSettings.tile_settings` then :meth:`FastSettings.for_tile`): its
        ``pixels_per_period`` is per tile.
    regions : Regions, optional
        :func:`roughlight.render.fast.shares.facet_regions` of the tile under this light (computed when not given).

    Returns
    -------
    lit, shadow : (V, F) arrays
        Each facet's lit and shadowed share (summing to 1 a view).
    regions : Regions
    """
    regions = regions if regions is not None else shares.facet_regions(surface, incidence, lighting.shadows)
    views = np.atleast_2d(np.asarray(views, float))
    shears = views[:, :2] / views[:, 2:3]
    plan = region_plan_areas(regions)
    n_views, n_facets = len(views), len(regions.normals)
    lit, shadow = np.zeros((n_views, n_facets)), np.zeros((n_views, n_facets))
    # (views, regions) arrays a batch at a time: whole, they take gigabytes on large tiles
    batches = range(0, n_views, 1024)
    whole = np.flatnonzero(np.concatenate([shares.all_facing(regions, shears[i:i + 1024]) for i in batches]))
    for first in range(0, whole.size, 1024):
        idx = whole[first:first + 1024]
        _store(lit, shadow, idx, projected_areas(regions, plan, shears[idx]))
    hidden = np.setdiff1d(np.arange(n_views), whole)
    triangles = region_triangles(regions) if hidden.size else None
    for part, part_settings, matrix, totals in counting_passes(views, hidden, settings):
        for idx, visible, total, per_tile in counted_batches(surface.height, triangles, len(regions.rings), views,
                                                              shears, part, part_settings, matrix, totals):
            if total is None:  # near the horizon: the visible pixels alone
                ratio = visible / per_tile
            else:
                areas = projected_areas(regions, plan, shears[idx])
                ratio = np.where(total > 0.5, areas * visible / np.maximum(total, 1.0), visible / per_tile)
            sums = ratio.sum(axis=1, keepdims=True)
            _store(lit, shadow, idx, np.where(sums > 0, ratio / np.where(sums > 0, sums, 1.0), 0.0))
    return lit, shadow, regions


def counting_passes(views, hidden, settings):
    """How the views ``hidden`` (indices into the (V, 3) unit ``views``) are counted: a list of (their indices,
    settings, sampling matrix, whether every fragment is counted), one a lattice and density.

    Views more than :data:`ORIENTED_BAND` degrees above the horizon are drawn on the tile's lattice
    (``settings.sampling_matrix()``). Nearer the horizon each view is drawn on the rotated lattice across whose
    rows its azimuth runs at the golden slope (:func:`roughlight.render.fast.sampling.oriented_lattices`): there the
    image is stretched along the azimuth, and on a fixed lattice the views whose azimuth ran near a row (as
    azimuth 30 on the tile's lattice, turned 31.7 degrees) were off by more than a level. Within
    :data:`GRAZING_BAND` of the horizon they are also drawn at ``tile_grazing_scale`` times the pixels, and only
    their visible pixels are counted: there a region's visible part is the top of a projection stretched over
    many periods, whose own edges the total no longer cancels, and its fragments were most of a sweep's (more than
    ten for each visible one).
    """
    sin_e = np.abs(views[hidden, 2])
    oriented = sin_e < np.sin(np.radians(ORIENTED_BAND))
    grazing = sin_e < np.sin(np.radians(GRAZING_BAND))
    passes = [(hidden[~oriented], settings, settings.sampling_matrix(), True)]
    for part, part_settings, totals in ((hidden[oriented & ~grazing], settings, True),
                                        (hidden[grazing], grazing_settings(settings), False)):
        azimuth = np.degrees(np.arctan2(views[part, 1], views[part, 0]))
        matrices, choice = oriented_lattices(int(part_settings.pixels_per_period), azimuth)
        passes += [(part[choice == k], part_settings, matrix, totals) for k, matrix in enumerate(matrices)]
    return [p for p in passes if p[0].size]


def grazing_settings(settings):
    """The settings of the views within :data:`GRAZING_BAND` of the horizon: ``tile_grazing_scale`` times the
    pixels."""
    from dataclasses import replace

    scale = float(settings.tile.grazing_scale)
    return settings if scale == 1.0 else replace(
        settings, pixels_per_period=int(round(int(settings.pixels_per_period) * scale)))


def _store(lit, shadow, idx, share) -> None:
    """Put the (n, R) region shares ``share`` of the views ``idx`` into the (V, F) ``lit`` and ``shadow``."""
    lit[idx] = share[:, 0::2]
    shadow[idx] = share[:, 1::2]


def counted_pixels(surface, regions, views, shears, hidden, settings):
    """Visible and total pixel counts (H, R) of each region in each of the views ``hidden`` (indices into
    ``views``, in order), and a tile's pixel count: :func:`counted_batches` gathered."""
    batches = list(counted_batches(surface.height, region_triangles(regions), len(regions.rings), views, shears,
                                    hidden, settings))
    per_tile = batches[0][3]
    return (np.concatenate([b[1] for b in batches]), np.concatenate([b[2] for b in batches]), per_tile)


def counted_batches(height, triangles, n_regions, views, shears, hidden, settings, matrix=None, totals=True):
    """For each framebuffer of the views ``hidden`` (indices into ``views``): those views' indices, their visible
    and total pixel counts (n, R) of each region (the total None unless ``totals``), and a tile's pixel count.

    Parameters
    ----------
    height : float
        The tile's height (periods).
    triangles : tuple
        :func:`region_triangles` of its ``n_regions`` regions.
    views, shears : (V, 3), (V, 2) arrays
    hidden : (H,) int array
    settings : FastSettings
        The tile's own.
    matrix : (2, 2) int array, optional
        The sampling matrix (default ``settings.sampling_matrix()``).
    """
    matrix = settings.sampling_matrix() if matrix is None else np.asarray(matrix)
    side = min(int(settings.max_framebuffer), FRAMEBUFFER)
    width, height_px, slots, pixel_order = cached_layout(matrix, hidden.size, side)
    ctx = context(width, height_px, int(settings.shadow_map_size))
    per_tile = len(pixel_order) // len(slots)
    buffer = gl.glGenBuffers(1)
    try:
        for first in range(0, hidden.size, len(slots)):
            idx = hidden[first:first + len(slots)]
            poses = batch_poses(height, views, shears, idx, slots, np.zeros(2))
            slot_pixels = pixel_order[: idx.size * per_tile].reshape(idx.size, per_tile)
            seen, total = _count_batch(ctx, triangles, height, poses, matrix, width, height_px, buffer, slot_pixels,
                                       n_regions, totals)
            yield idx, seen, total, per_tile
    finally:
        gl.glDeleteBuffers(1, [buffer])


def region_triangles(regions: shares.Regions):
    """Each region triangulated: (T, 3, 3) corners (plan x, y and the facet's height, periods; counter-clockwise
    seen from above) and (T,) the region each triangle belongs to. The triangles of a region cover exactly its
    polygons (constrained Delaunay triangulation, holes left out)."""
    import shapely

    from ..exact.clipping import area_parts

    tris, owner = [], []
    for r, rings in enumerate(regions.rings):
        f = regions.facet[r]
        polygons = []
        for ring in rings:
            x, y = ring[:, 0], ring[:, 1]
            twice_area = np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))
            if twice_area > 1e-15:  # an exterior starts a polygon
                polygons.append([ring[:, :2], []])
            elif twice_area < -1e-15 and polygons:  # a hole of the last exterior
                polygons[-1][1].append(ring[:, :2])
        if not polygons:  # zero-area slivers only
            continue
        area = area_parts(shapely.MultiPolygon([shapely.Polygon(ext, holes) for ext, holes in polygons]))
        parts = shapely.get_parts(shapely.constrained_delaunay_triangles(area))
        xy = shapely.get_coordinates(parts).reshape(len(parts), 4, 2)[:, :3]
        flip = (xy[:, 1, 0] - xy[:, 0, 0]) * (xy[:, 2, 1] - xy[:, 0, 1]) \
            - (xy[:, 1, 1] - xy[:, 0, 1]) * (xy[:, 2, 0] - xy[:, 0, 0]) < 0
        xy[flip] = xy[flip][:, ::-1]
        z0 = rings[0][0, 2] - regions.alpha[f] * rings[0][0, 0] - regions.beta[f] * rings[0][0, 1]
        z = regions.alpha[f] * xy[..., 0] + regions.beta[f] * xy[..., 1] + z0
        tris.append(np.concatenate([xy, z[..., None]], axis=2))
        owner.append(np.full(len(parts), r))
    return np.concatenate(tris), np.concatenate(owner)


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
    depth_scale = 1.0 / max(height * 1.001, 1e-6)
    uniforms = {"sampling": matrix.astype(np.float32), "ndc_scale": np.array([2.0 / width, 2.0 / height_px],
                np.float32), "surface_shift": np.zeros(2, np.float32), "depth_scale": float(depth_scale)}
    begin_pass(0, width, height_px, gl.GL_COLOR_BUFFER_BIT | gl.GL_DEPTH_BUFFER_BIT)
    program = ctx.programs.get_program("periodic.vert", "periodic_count.frag",
                                       defines=ATTRIBUTES if totals else {**ATTRIBUTES, "VISIBLE_ONLY": 1})
    size = len(slot_pixels) * n_regions
    if totals:
        gl.glBindBuffer(gl.GL_SHADER_STORAGE_BUFFER, buffer)
        gl.glBufferData(gl.GL_SHADER_STORAGE_BUFFER, size * 4, np.zeros(size, np.uint32), gl.GL_DYNAMIC_READ)
        gl.glBindBufferBase(gl.GL_SHADER_STORAGE_BUFFER, 0, buffer)
    program._bind()
    for name, value in uniforms.items():
        program.set_uniform(name, value)
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
