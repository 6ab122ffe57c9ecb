"""The OpenGL passes a sweep of the fast method draws (pyrender over OSMesa): the period as instanced lattice
copies, the pass state, the periodic shadow map, each batch's instance matrices and the lighting uniforms.

:mod:`roughlight.render.fast.periodic` draws values or facet identities with them, :mod:`roughlight.render.fast.counting`
counts each region's pixels. Coordinates and the instance matrices are ``shaders/periodic.vert``'s.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...surfaces import geometry
from ...surfaces.surface import Surface
from .. import shading
from ..gl.context import GLTF, Context, Primitive, gl, set_material_uniforms
from .sampling import lattice_copies, tile_layout
from .settings import FastSettings

#: Vertex attribute locations of ``periodic.vert`` (pyrender numbers them in order: position, normal,
#: texcoord_0 = the facet's index and lit state, then the instance matrix).
ATTRIBUTES = {"NORMAL_LOC": 1, "FACET_LOC": 2, "INST_M_LOC": 3}


def primitive(surface: Surface, poses: np.ndarray, lit_state=None):
    """The period's triangles as one instanced pyrender primitive, drawn at the copies ``poses`` ((m, 4, 4),
    :func:`copy_poses`). Each vertex carries its facet's index (numbered as
    :func:`roughlight.surfaces.geometry.facet_polygons` lists them) and, from ``lit_state`` ((F,) per facet, default
    0), whether the fragment shader tests the shadow map: 0 test it, 1 wholly lit, 2 wholly in shadow."""
    tris, normals, names = geometry.period_triangles(surface)
    order = list(dict.fromkeys(names))  # facets in facet_polygons' order, as the reference numbers them
    facet = np.array([order.index(name) for name in names], np.int64)
    state = np.zeros(len(order), np.float32) if lit_state is None else np.asarray(lit_state, np.float32)
    return Primitive(
        positions=tris.reshape(-1, 3).astype(np.float32),
        normals=np.repeat(normals, 3, axis=0).astype(np.float32),
        texcoord_0=np.repeat(np.stack([facet.astype(np.float32), state[facet]], axis=1), 3, axis=0),
        mode=GLTF.TRIANGLES,
        poses=poses,
    )


def draw(ctx: Context, primitive, program):
    """Draw ``primitive`` (:func:`primitive`) with ``program``, all its instances in one call, and free it."""
    primitive._add_to_context()
    try:
        primitive._bind()
        gl.glDrawArraysInstanced(gl.GL_TRIANGLES, 0, len(primitive.positions), len(primitive.poses))
        primitive._unbind()
    finally:
        primitive.delete()


def copy_poses(copies: np.ndarray, shear, view, tile) -> np.ndarray:
    """Instance matrices (see ``shaders/periodic.vert``), one per copy.

    ``shear``, ``view`` and ``tile`` (the slot's integer cell offset) are per
    copy ((m, 2), (m, 3), (m, 2)) or broadcast from one view.
    """
    n = len(copies)
    poses = np.zeros((n, 4, 4), np.float32)
    poses[:, 0, 0] = copies[:, 0]
    poses[:, 1, 0] = copies[:, 1]
    poses[:, 0, 1] = shear[..., 0]
    poses[:, 1, 1] = shear[..., 1]
    poses[:, 0:3, 2] = view
    poses[:, 0:2, 3] = tile
    return poses


def begin_pass(framebuffer, width: int, height: int, clear_bits) -> None:
    """Bind a framebuffer and set the state both passes draw with: depth test
    keeping the highest surface, back faces culled, copies clipped to their tile."""
    gl.glBindFramebuffer(gl.GL_FRAMEBUFFER, framebuffer)
    gl.glViewport(0, 0, width, height)
    gl.glClearColor(0.0, 0.0, 0.0, 0.0)
    gl.glClearDepth(1.0)
    gl.glEnable(gl.GL_DEPTH_TEST)
    gl.glDepthMask(gl.GL_TRUE)
    gl.glDepthFunc(gl.GL_LESS)
    gl.glDisable(gl.GL_BLEND)
    gl.glEnable(gl.GL_CULL_FACE)
    gl.glCullFace(gl.GL_BACK)
    gl.glFrontFace(gl.GL_CCW)
    for plane in range(4):
        gl.glEnable(gl.GL_CLIP_DISTANCE0 + plane)
    # clear only the viewport: the context's framebuffer may be larger
    gl.glEnable(gl.GL_SCISSOR_TEST)
    gl.glScissor(0, 0, width, height)
    gl.glClear(clear_bits)
    gl.glDisable(gl.GL_SCISSOR_TEST)


def shadow_pass(ctx: Context, surface: Surface, light_dir, depth_scale):
    height = surface.height
    shear = light_dir[:2] / light_dir[2]
    _, copies = lattice_copies(height * shear[None, :])
    poses = copy_poses(copies, shear, light_dir, np.zeros(2))
    begin_pass(ctx.shadow_fbo, ctx.shadow_size, ctx.shadow_size, gl.GL_DEPTH_BUFFER_BIT)
    period = primitive(surface, poses)
    program = ctx.programs.get_program("periodic.vert", "periodic_depth.frag", defines=ATTRIBUTES)
    program._bind()
    program.set_uniform("depth_scale", float(depth_scale))
    program.set_uniform("sampling", np.eye(2, dtype=np.float32) * ctx.shadow_size)
    program.set_uniform("ndc_scale", np.full(2, 2.0 / ctx.shadow_size, np.float32))
    program.set_uniform("surface_shift", np.zeros(2, np.float32))
    draw(ctx, period, program)
    program._unbind()
    gl.glBindFramebuffer(gl.GL_FRAMEBUFFER, 0)


_LAYOUTS: dict = {}


def cached_layout(matrix: np.ndarray, n_views: int, max_framebuffer: int):
    """:func:`roughlight.render.fast.sampling.tile_layout` for at least ``n_views``: the count is rounded up to a step of
    2^(1/4) (at most 19% spare slots), so that sweeps drawing slightly different numbers of views with one
    lattice (adaptive sampling) share a layout; the caller uses the first slots."""
    n_views = int(math.ceil(2.0 ** (math.ceil(4.0 * math.log2(max(int(n_views), 1))) / 4.0)))
    key = (tuple(np.asarray(matrix).ravel()), n_views, max_framebuffer)
    if key not in _LAYOUTS:
        if len(_LAYOUTS) >= 64:
            _LAYOUTS.clear()
        _LAYOUTS[key] = tile_layout(matrix, n_views, max_framebuffer)
    return _LAYOUTS[key]


class Scene(NamedTuple):
    """What every pass of one sweep draws with: the surface under its light, the context and the program."""

    surface: Surface
    #: the surface's height (periods), read once
    height: float
    #: (3,) unit vector towards the light
    light_dir: np.ndarray
    lighting: shading.Lighting
    settings: FastSettings
    ctx: Context
    program: object
    #: 0 none, 1 periodic shadow map, 2 all in shadow (grazing light), as ``periodic.frag`` reads it
    shadow_mode: int
    #: 1 / the surface's height (slightly more), mapping heights to depths in [0, 1)
    depth_scale: float
    #: adaptive sampling's facet regions (:func:`roughlight.render.fast.shares.facet_regions`), else None
    regions: object


def make_scene(ctx: Context, surface, light_dir, lighting, settings, regions) -> Scene:
    """Set up what every pass of the sweep draws with: the shadow map (drawn once, the light does not move)
    and the program (with facet identities for adaptive sampling)."""
    height = surface.height
    depth_scale = 1.0 / max(height * 1.001, 1e-6)
    shadow_mode = 0
    if lighting.shadows and height > 0:
        if light_dir[2] < 1e-9:
            shadow_mode = 2
        else:
            shadow_mode = 1
            shadow_pass(ctx, surface, light_dir, depth_scale)
    defines = {**ATTRIBUTES, "FACET_IDS": 1} if regions is not None else ATTRIBUTES
    program = ctx.programs.get_program("periodic.vert", "periodic.frag", defines=defines)
    return Scene(surface, height, light_dir, lighting, settings, ctx, program, shadow_mode, depth_scale, regions)


def batch_poses(height: float, views, shears, idx, slots, shift) -> np.ndarray:
    """Instance matrices of the copies drawn for the views ``idx`` (one framebuffer), the views in ``slots``
    order, each view's copies nearest the detector first, so that the depth test rejects the copies behind
    before shading them. ``shift`` (2,) is the surface's sub-pixel shift in periods. Each copy also carries its
    view's slot number in the batch (``shaders/periodic.vert``'s ``frag_slot``)."""
    owner, copies = lattice_copies(height * shears[idx], margin=float(np.abs(shift).max()))
    nearest = np.lexsort((-(copies * shears[idx][owner]).sum(axis=1), owner))
    owner, copies = owner[nearest], copies[nearest]
    copy_idx = idx[owner]
    poses = copy_poses(copies, shears[copy_idx], views[copy_idx], slots[: idx.size][owner])
    poses[:, 2, 3] = owner
    return poses


def surface_shift(matrix: np.ndarray, jitter) -> np.ndarray:
    """(2,) the surface's shift in periods that a camera shift by ``jitter`` pixels is, drawn with ``matrix``."""
    return -np.linalg.solve(np.asarray(matrix, float), np.asarray(jitter, float))


def set_lighting_uniforms(program, lighting, light_dir, shadow_mode, ctx, settings, depth_scale, height):
    set_material_uniforms(program, lighting, light_dir)
    program.set_uniform("shadow_mode", int(shadow_mode))
    program.set_uniform("shadow_size", int(ctx.shadow_size))
    lz = max(float(light_dir[2]), 1e-12)
    program.set_uniform("light_shear", np.array([light_dir[0] / lz, light_dir[1] / lz], np.float32))
    program.set_uniform("depth_scale", float(depth_scale))
    program.set_uniform("shadow_bias", float(settings.shadow_bias * max(height, 1e-6)))
