"""The fast method: every view of a sweep in one framebuffer, one period per view (pyrender over OSMesa).

A sweep is one surface under one directional light seen from many views. The
renderer draws *every view of a sweep in one framebuffer*, one small tile per
view, with one instanced draw call:

* Each view's tile shows exactly one period of the projected image of the
  infinite periodic surface. The projection is the oblique parallel projection
  along the view direction onto the base plane (``shaders/periodic.vert``): it
  is an orthographic camera whose image plane is sheared onto the surface's
  lattice, so the pixels of a tile sample one period uniformly and the tile
  mean is the mean over the infinite surface: no background, no patch edge,
  no moire between the surface period and the pixel grid. ``coverage`` is
  the fraction of the tile's pixels that show the surface (1 for every view
  but the grazing ones, ``e`` = 0 or 180, which see no area and are 0).
  How the tile samples the period is :mod:`roughlight.render.fast.sampling`.
* The scene holds only what the measurement needs: one period (at most 10
  triangles), instanced at the lattice copies whose projection reaches the
  tile (more copies only near grazing views of tall surfaces).
* The light does not move during a sweep, so the shadow map is drawn once per
  sweep. It is periodic too: one period of light-oblique coordinates,
  sampled with wrap-around, storing the height of the first surface along
  each light ray; a fragment compares its own facet's height at the texel
  centre (receiver-plane depth), so a facet never shadows itself.
* The lighting equation (:mod:`roughlight.render.shading`) is evaluated per fragment
  in ``shaders/periodic.frag``; diffuse, specular and total go to the r, g and
  b channels of one pass and are each stored as 8-bit values.

pyrender provides the OSMesa context, the vertex buffers with instancing and
the shader programs (:mod:`roughlight.render.gl.context`); its stock shader
(metallic-roughness PBR with gamma) is not the study's equation and is not used.

This module runs a sweep: it takes its plan from numpy (which views are exact and on which lattices the others
are drawn: :func:`roughlight.render.fast.shares.adaptive_plan`,
:func:`roughlight.render.fast.sampling.one_lattice`, :func:`roughlight.render.fast.sampling.counting_passes`),
draws it (:mod:`roughlight.render.fast.passes`, :mod:`roughlight.render.fast.counting`) and weights each
region's share by its 8-bit values.
"""

from __future__ import annotations

import numpy as np

from ...surfaces.surface import Surface
from .. import shading, sweep
from ..gl.context import context, gl, release_contexts
from . import raster, sampling, shares
from .passes import Scene, batch_poses, begin_pass, draw, make_scene, primitive, set_lighting_uniforms, set_viewport_uniforms
from .regions import adaptive_regions, facet_regions
from .settings import FastSettings


def fast_sweep(
    surface: Surface,
    incidence: float,
    azimuth,
    elevation,
    lighting: shading.Lighting | None = None,
    settings: FastSettings | None = None,
    light_azimuth: float = 0.0,
) -> dict:
    """Render one sweep with the ``fast`` method (pyrender over OSMesa).

    Parameters
    ----------
    surface : Surface or RandomSurface
        The surface (see :mod:`roughlight.surfaces.surface`), or a random tile
        (:mod:`roughlight.surfaces.roughness`) drawn as one period.
    incidence : float
        Light elevation above the surface plane, degrees in [0, 90].
    azimuth, elevation : (n_views,) arrays
        Views, degrees: azimuth in [0, 180), elevation in [0, 180].
    light_azimuth : float
        The light's azimuth, degrees (0, the study's: the light in the x-z plane).
    lighting : Lighting
    settings : FastSettings
        A random tile is drawn with its tile settings
        (:meth:`FastSettings.tile_settings`), densities per cell: a tile of
        ``cells`` a side is sampled at ``cells`` times them
        (:meth:`FastSettings.for_tile`).

    Returns
    -------
    dict
        ``diffuse``, ``specular``, ``total``: (n_views,) means of the 8-bit
        pixel values of the view's tile (0-255); ``coverage``: (n_views,)
        fraction of the tile's pixels showing the surface; :data:`roughlight.render.sweep.EXTRA_KEYS` (NaN
        but with adaptive sampling); ``seconds``: wall
        time of the sweep; ``renderer`` for a random tile with adaptive sampling, which draws nothing with
        OpenGL (:func:`roughlight.render.fast.raster.identity`).
    """
    settings = (settings or FastSettings()).for_surface(surface)
    light_azimuth = shading.check_light_azimuth(light_azimuth)

    counted = hasattr(surface, "cells") and settings.sampling == "adaptive"  # a random tile: counted on the CPU

    def step(out, views, incidence, lighting):
        fill = _counted_views if counted else _render_views
        fill(out, surface, (incidence, light_azimuth), views.measured, views.directions(), lighting, settings)

    # Every sweep draws in contexts of its own, as in a fresh process: a context left by an earlier sweep has a
    # framebuffer as large as that sweep's largest, and llvmpipe clips a draw to the framebuffer, not to the
    # viewport, which moved 3 views of a regular sweep (t 0.6, a 0.9) by up to 0.13 of a level when a process
    # rendered its truncation's row in order. A new context costs nothing measurable here: Mesa keeps the
    # compiled shaders on disk.
    release_contexts()
    gives = shading.EXTRAS if settings.sampling == "adaptive" else ()  # lattice, grid: 8-bit pixels averaged
    out = sweep.measure(step, incidence, azimuth, elevation, lighting, gives)
    if counted:
        out["renderer"] = raster.identity()
    return out


def _counted_views(out, surface, light, todo, views, lighting, settings) -> None:
    """Fill ``out`` at the non-grazing views ``todo`` of a random tile with adaptive sampling: each region's share
    counted on the CPU (:func:`counted_shares`), weighted by its 8-bit values. ``light``: (incidence, light
    azimuth), degrees."""
    incidence, light_azimuth = light
    regions = adaptive_regions(surface, incidence, lighting.shadows, light_azimuth)
    lit, shadow, _ = counted_shares(surface, incidence, views, lighting, settings, regions)
    _add_from_shares(out, todo, 1.0, regions, views, lit, shadow, shading.light_direction(*light), lighting, 1.0)


def counted_shares(surface, incidence: float, views, lighting, settings, regions=None):
    """Each facet's lit and shadowed share of each view's image, for a random tile (:mod:`roughlight.render.fast.counting`).

    Where nothing is hidden (:func:`roughlight.render.fast.shares.exact_views`) they are the exact projected
    areas (:func:`roughlight.render.fast.shares.projected_areas`); the other views are counted on the CPU on
    the lattices of :func:`roughlight.render.fast.sampling.counting_passes`
    (:func:`roughlight.render.fast.counting.counted_views`), each region's count corrected by its exact area
    (:func:`roughlight.render.fast.shares.normalised_shares`).

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
        The tile's own (:meth:`FastSettings.for_surface`): its ``pixels_per_period`` is per tile.
    regions : Regions, optional
        :func:`roughlight.render.fast.regions.facet_regions` of the tile under this light (computed when not given).

    Returns
    -------
    lit, shadow : (V, F) arrays
        Each facet's lit and shadowed share (summing to 1 a view).
    regions : Regions
    """
    from .counting import counted_views, region_triangles

    regions = regions if regions is not None else facet_regions(surface, incidence, lighting.shadows)
    views = np.atleast_2d(np.asarray(views, float))
    shears = views[:, :2] / views[:, 2:3]
    plan = shares.region_plan_areas(regions)
    lit, shadow = np.zeros((len(views), len(regions.normals))), np.zeros((len(views), len(regions.normals)))
    whole = np.flatnonzero(shares.exact_views(regions, shears))
    for first in range(0, whole.size, 1024):  # (views, regions) arrays a batch at a time
        idx = whole[first:first + 1024]
        _store(lit, shadow, idx, shares.projected_areas(regions, plan, shears[idx]))
    hidden = np.setdiff1d(np.arange(len(views)), whole)
    triangles = region_triangles(regions) if hidden.size else None
    for drawn in sampling.counting_passes(views, hidden, settings):
        for idx, visible, total, per_tile in counted_views(triangles, len(regions.rings), shears, drawn):
            areas = None if total is None else shares.projected_areas(regions, plan, shears[idx])
            _store(lit, shadow, idx, shares.normalised_shares(visible, per_tile, total, areas))
    return lit, shadow, regions


def _store(lit, shadow, idx, share) -> None:
    """Put the (n, R) region shares ``share`` of the views ``idx`` into the (V, F) ``lit`` and ``shadow`` (a random
    tile's regions alternate lit and shadowed, facet by facet)."""
    lit[idx] = share[:, 0::2]
    shadow[idx] = share[:, 1::2]


def _render_views(out, surface, light, todo, views, lighting, settings) -> None:
    """Fill ``out`` at the non-grazing views ``todo`` (their (V, 3) unit ``views``) under ``light``, (incidence,
    light azimuth) in degrees.

    Adaptive sampling first takes the views where nothing is hidden from their exact areas and draws the rest
    on the lattices of its plan (:func:`roughlight.render.fast.shares.adaptive_plan`); lattice and grid sampling
    draw every view on the one sampling matrix (:func:`roughlight.render.fast.sampling.one_lattice`). Each
    lattice is then drawn in as many framebuffer passes as its layout needs.
    """
    incidence, light_azimuth = light
    light_dir = shading.light_direction(incidence, light_azimuth)
    regions = None
    if settings.sampling == "adaptive":
        regions = adaptive_regions(surface, incidence, lighting.shadows, light_azimuth)
        plan = shares.adaptive_plan(regions, views, light_dir, lighting, settings)
        _add_from_shares(out, todo[plan.exact], 1.0, regions, views[plan.exact], plan.lit, plan.shadow, light_dir,
                         lighting, 1.0)
        todo, views, drawn = todo[~plan.exact], views[~plan.exact], plan.passes
    else:
        drawn = sampling.one_lattice(todo.size, settings)
    if not drawn:
        return
    shears = views[:, :2] / views[:, 2:3]
    ctx = context(max(p.layout[0] for p in drawn), max(p.layout[1] for p in drawn), int(settings.shadow_map_size))
    scene = make_scene(ctx, surface, light_dir, lighting, settings, regions)
    for lattice in drawn:
        _draw_group(out, scene, todo, views, shears, lattice)


def _draw_group(out, scene: Scene, todo, views, shears, lattice) -> None:
    """Draw one lattice's views (``lattice``, a :class:`roughlight.render.fast.sampling.LatticePass`) a
    framebuffer at a time and add their values, times their weights, to ``out`` at ``todo`` of them. ``views``
    (V, 3) and ``shears`` (V, 2) are all the drawn views'."""
    matrix, shift, members, weights, (width, height_px, slots, pixel_order), _ = lattice
    per_tile = len(pixel_order) // len(slots)
    for first in range(0, members.size, len(slots)):
        idx, weight = members[first:first + len(slots)], weights[first:first + len(slots)]
        poses = batch_poses(scene.height, views, shears, idx, slots, shift)
        raw = _render_batch(scene, poses, matrix, shift, width, height_px)
        tiles_px = _tile_pixels(raw, pixel_order[: idx.size * per_tile], idx.size)
        target = todo[idx]
        if scene.regions is not None:
            ids = tiles_px[..., 0].astype(np.int64) + 256 * tiles_px[..., 1].astype(np.int64)
            _adaptive_values(out, target, weight, ids, scene.regions, shears[idx], views[idx], matrix, shift,
                             scene.light_dir, scene.lighting)
        else:
            _tile_means(out, target, tiles_px, per_tile)


def _render_batch(scene: Scene, poses, matrix, shift, width: int, height_px: int) -> bytes:
    """Draw the copies ``poses`` into the ``width`` x ``height_px`` viewport with the sampling ``matrix`` and
    the surface ``shift``; return the viewport's RGBA bytes."""
    program = scene.program
    begin_pass(0, width, height_px, gl.GL_COLOR_BUFFER_BIT | gl.GL_DEPTH_BUFFER_BIT)
    program._bind()
    set_lighting_uniforms(program, scene)
    set_viewport_uniforms(program, matrix, width, height_px, shift, scene.depth_scale)
    draw(scene.ctx, primitive(scene.surface, poses), program)
    program._unbind()
    gl.glFinish()
    return gl.glReadPixels(0, 0, width, height_px, gl.GL_RGBA, gl.GL_UNSIGNED_BYTE)


def _tile_means(out, target, tiles_px, per_tile: int) -> None:
    """Store at ``target`` each tile's mean diffuse, specular and total (0-255) and coverage (0-1) from its
    (n_tiles, per_tile, 4) uint8 pixels: integer sums (exact) over the tile's pixel count, the same float64
    means as numpy's mean, faster."""
    means = tiles_px.sum(axis=1, dtype=np.uint32) / float(per_tile)
    out["diffuse"][target] = means[:, 0]
    out["specular"][target] = means[:, 1]
    out["total"][target] = means[:, 2]
    out["coverage"][target] = means[:, 3] / 255.0


def _tile_pixels(raw: bytes, pixel_order: np.ndarray, n_tiles: int) -> np.ndarray:
    """(n_tiles, pixels a tile, 4) uint8: each tile's RGBA pixels out of the framebuffer's bytes, gathered as
    one 32-bit word a pixel (a third faster than gathering rows of four bytes)."""
    words = np.frombuffer(raw, np.uint32).take(pixel_order)
    return words.view(np.uint8).reshape(n_tiles, -1, 4)


def _adaptive_values(out, target, weight, ids, regions, shear, views, matrix, shift, light_dir, lighting) -> None:
    """Add to ``out`` at ``target``, times ``weight``, the values from the tiles' (facet, lit) identities (``ids``
    = 2 facet + lit + 1): each facet's shares by :func:`roughlight.render.fast.shares.ratio_shares`, weighted by its 8-bit
    values as the framebuffer stores them (:func:`roughlight.render.shading.facet_sum`)."""
    n, width = len(ids), 2 * len(regions.normals) + 2
    histogram = np.bincount((np.arange(n)[:, None] * width + ids).ravel(), minlength=n * width).reshape(n, width)
    pixel_counts = histogram[:, 2 * regions.facet + regions.lit.astype(int) + 1]
    lit, shadow = shares.ratio_shares(pixel_counts, regions, shear, matrix, shift)
    _add_from_shares(out, target, weight, regions, views, lit, shadow, light_dir, lighting,
                     1.0 - histogram[:, 0] / ids.shape[1])


def _add_from_shares(out, target, weight, regions, views, lit, shadow, light_dir, lighting, coverage) -> None:
    """Add at ``target`` (no repeats), times ``weight``, each component's facet sum of the (V, F) ``lit`` and
    ``shadow`` shares, its sums before rounding and without inner shadows (:func:`roughlight.render.shading.facet_sums`),
    and ``coverage``."""
    values = shading.facet_sums(regions.normals, light_dir, views, lit, shadow, lighting)
    for key, value in values.items():
        out[key][target] += weight * value
    out["coverage"][target] += weight * coverage
