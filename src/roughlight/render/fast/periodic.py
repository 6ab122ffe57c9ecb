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
"""

from __future__ import annotations

import numpy as np

from ...surfaces.surface import Surface
from .. import shading, sweep
from ..gl.context import context, gl
from . import shares
from .passes import (
    Scene,
    batch_poses,
    begin_pass,
    cached_layout,
    draw,
    make_scene,
    primitive,
    set_lighting_uniforms,
    surface_shift,
)
from .settings import FastSettings


def fast_sweep(
    surface: Surface,
    incidence: float,
    azimuth,
    elevation,
    lighting: shading.Lighting | None = None,
    settings: FastSettings | None = None,
) -> dict:
    """Render one sweep with the ``fast`` method (pyrender over OSMesa).

    Parameters
    ----------
    surface : Surface or RandomSurface
        The surface (see :mod:`roughlight.surfaces.surface`), or a random tile
        (:mod:`roughlight.surfaces.roughness`) drawn as one period.
    incidence : float
        Light elevation above the surface plane, degrees in [0, 90]; the light
        comes from azimuth 0.
    azimuth, elevation : (n_views,) arrays
        Views, degrees: azimuth in [0, 180), elevation in [0, 180].
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
        fraction of the tile's pixels showing the surface; ``seconds``: wall
        time of the sweep.
    """
    settings = (settings or FastSettings()).for_surface(surface)

    def step(out, views, incidence, lighting):
        if hasattr(surface, "cells") and settings.sampling == "adaptive":  # a random tile: counted on the GL side
            _counted_views(out, surface, incidence, views.measured, views.directions(), lighting, settings)
        else:
            _render_views(out, surface, incidence, views.measured, views.directions(), lighting, settings)

    return sweep.measure(step, incidence, azimuth, elevation, lighting)


def _counted_views(out, surface, incidence, todo, views, lighting, settings) -> None:
    """Fill ``out`` at the non-grazing views ``todo`` of a random tile with adaptive sampling: each region's share
    counted on the GL side (:func:`roughlight.render.fast.counting.counted_shares`), weighted by its 8-bit values."""
    from .counting import counted_shares

    regions = _adaptive_regions(surface, incidence, lighting)
    lit, shadow, _ = counted_shares(surface, incidence, views, lighting, settings, regions)
    _add_from_shares(out, todo, 1.0, regions, views, lit, shadow, shading.light_direction(incidence), lighting, 1.0)


def _render_views(out, surface, incidence, todo, views, lighting, settings) -> None:
    """Fill ``out`` at the non-grazing views ``todo`` (their (V, 3) unit ``views``).

    Adaptive sampling first takes the views where nothing is hidden from their exact areas and groups the
    rest by lattice (:func:`_adaptive_groups`); lattice and grid sampling draw every view on the one
    sampling matrix. Each group is then drawn in as many framebuffer passes as its layout needs.
    """
    shears = views[:, :2] / views[:, 2:3]
    light_dir = shading.light_direction(incidence)
    regions = None
    if settings.sampling == "adaptive":
        regions = _adaptive_regions(surface, incidence, lighting)
        todo, views, shears, groups = _adaptive_groups(out, regions, todo, views, shears, light_dir, lighting,
                                                       settings)
        if todo.size == 0:
            return
    else:
        groups = [_lattice_group(0, settings.sampling_matrix(), np.zeros((1, todo.size), int),
                                 np.zeros(todo.size, bool))]
    groups = [g for g in groups if g[1].size]
    layouts = [cached_layout(m, idx.size, int(settings.max_framebuffer)) for m, idx, _ in groups]
    ctx = context(max(lay[0] for lay in layouts), max(lay[1] for lay in layouts), int(settings.shadow_map_size))
    scene = make_scene(ctx, surface, light_dir, lighting, settings, regions)
    for group, layout in zip(groups, layouts):
        _draw_group(out, scene, todo, views, shears, group, layout)


def _adaptive_regions(surface, incidence: float, lighting):
    """The surface's facet regions (:func:`roughlight.render.fast.shares.facet_regions`) for adaptive sampling,
    which takes at most :data:`roughlight.render.fast.shares.MAX_FACETS` facets a period."""
    regions = shares.facet_regions(surface, incidence, lighting.shadows)
    if len(regions.normals) > shares.MAX_FACETS:
        raise ValueError(f"render.sampling: adaptive takes at most {shares.MAX_FACETS} facets a period, "
                         f"this surface has {len(regions.normals)}; use lattice")
    return regions


def _adaptive_groups(out, regions, todo, views, shears, light_dir, lighting, settings):
    """Adaptive sampling's plan: the views left to draw and, for each candidate lattice, its pass.

    Where every facet faces the view nothing is hidden: each region's share is its exact area, added to
    ``out`` unrendered. Each of the others is drawn on its best lattice
    (:func:`roughlight.render.fast.shares.choose_lattices`), and on the next best too, averaged, where even the best
    may be off by ``settings.average_lattices_above`` levels.

    Returns
    -------
    todo, views, shears : the views left to draw, (V,), (V, 3) and (V, 2)
    groups : list of :func:`_lattice_group` passes, one a candidate lattice; empty when no view is left
    """
    whole = shares.all_facing(regions, shears)
    _exact_values(out, todo[whole], regions, shears[whole], views[whole], light_dir, lighting)
    todo, views, shears = todo[~whole], views[~whole], shears[~whole]
    if todo.size == 0:
        return todo, views, shears, []
    matrices = shares.candidate_lattices(int(settings.pixels_per_period))
    shifts = [surface_shift(m, settings.jitter) for m in matrices]
    values = shares.region_values(regions, light_dir, views, lighting)
    order, score = shares.choose_lattices(regions, shears, matrices, shifts, values)
    many = score >= float(settings.average_lattices_above)
    return todo, views, shears, [_lattice_group(k, m, order, many) for k, m in enumerate(matrices)]


def _draw_group(out, scene: Scene, todo, views, shears, group, layout) -> None:
    """Draw one lattice's views (``group``, a :func:`_lattice_group`) a framebuffer at a time and store their
    values in ``out`` at ``todo`` of them. ``views`` (V, 3) and ``shears`` (V, 2) are all the drawn views';
    ``layout`` is the lattice's :func:`roughlight.render.fast.sampling.tile_layout`."""
    matrix, members, weights = group
    width, height_px, slots, pixel_order = layout
    per_tile = len(pixel_order) // len(slots)
    shift = surface_shift(matrix, scene.settings.jitter)
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
    set_lighting_uniforms(program, scene.lighting, scene.light_dir, scene.shadow_mode, scene.ctx, scene.settings,
                          scene.depth_scale, scene.height)
    program.set_uniform("sampling", matrix.astype(np.float32))
    program.set_uniform("ndc_scale", np.array([2.0 / width, 2.0 / height_px], np.float32))
    program.set_uniform("surface_shift", shift.astype(np.float32))
    gl.glActiveTexture(gl.GL_TEXTURE0)
    gl.glBindTexture(gl.GL_TEXTURE_2D, scene.ctx.shadow_tex)
    program.set_uniform("shadow_map", 0)
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


def _lattice_group(k, matrix, order, many):
    """Lattice ``k``'s pass: (matrix, the views it draws, each one's weight in its value).

    ``order`` (K, V): each view's best lattices, best first; ``many`` (V,) bool: the views drawn on all K, each
    with weight 1 / K; the others are drawn on their best alone, with weight 1.
    """
    drawn = (order[0] == k) | (many & np.any(order[1:] == k, axis=0))
    members = np.flatnonzero(drawn)
    return matrix, members, np.where(many[members], 1.0 / len(order), 1.0)


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


def _exact_values(out, target, regions, shear, views, light_dir, lighting) -> None:
    """Add to ``out`` at ``target``, views where nothing is hidden: each facet's exact lit and shadowed areas
    (:func:`roughlight.render.fast.shares.area_shares`) weighted by its 8-bit values
    (:func:`roughlight.render.shading.facet_sum`)."""
    lit, shadow = shares.area_shares(regions, shear)
    _add_from_shares(out, target, 1.0, regions, views, lit, shadow, light_dir, lighting, 1.0)


def _add_from_shares(out, target, weight, regions, views, lit, shadow, light_dir, lighting, coverage) -> None:
    """Add at ``target`` (no repeats), times ``weight``, each component's facet sum of the (V, F) ``lit`` and
    ``shadow`` shares, and ``coverage``."""
    values = shading.facet_sum(regions.normals, light_dir, views, lit, shadow, lighting)
    for component in shading.COMPONENTS:
        out[component][target] += weight * values[component]
    out["coverage"][target] += weight * coverage
