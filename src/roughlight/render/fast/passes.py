"""The OpenGL passes a sweep of the fast method draws (pyrender over OSMesa): the period as instanced lattice
copies, the pass state, the periodic shadow map, each batch's instance matrices, the viewport's and the
lighting's uniforms.

:mod:`roughlight.render.fast.periodic` draws values or facet identities with them, :mod:`roughlight.render.fast.counting`
counts each region's pixels. Coordinates and the instance matrices are ``shaders/periodic.vert``'s. What is drawn
on which lattice, and where in the framebuffer, is planned in numpy (:mod:`roughlight.render.fast.sampling`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...surfaces import geometry
from ...surfaces.surface import Surface
from .. import shading
from ..gl.context import GLTF, Context, Primitive, gl, set_material_uniforms
from .sampling import lattice_copies
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


def depth_scale(height: float) -> float:
    """1 / the surface's ``height`` (periods), slightly more: maps heights to depths in [0, 1) (``periodic.vert``)."""
    return 1.0 / max(height * 1.001, 1e-6)


def set_viewport_uniforms(program, matrix, width: int, height: int, shift, depth: float) -> None:
    """The uniforms ``periodic.vert`` maps a copy into its tile with, on the bound ``program``.

    Parameters
    ----------
    matrix : (2, 2) array
        Cell coordinates to window pixels (integers).
    width, height : int
        The viewport, pixels.
    shift : (2,) array
        The surface's shift in periods.
    depth : float
        :func:`depth_scale` of the surface.
    """
    program.set_uniform("sampling", np.asarray(matrix).astype(np.float32))
    program.set_uniform("ndc_scale", np.array([2.0 / width, 2.0 / height], np.float32))
    program.set_uniform("surface_shift", np.asarray(shift).astype(np.float32))
    program.set_uniform("depth_scale", float(depth))


def shadow_pass(ctx: Context, surface: Surface, light_dir, depth: float) -> None:
    """Draw the periodic shadow map of ``surface`` under the light ``light_dir`` ((3,), unit, ``L_z > 0``): one
    period of light-oblique coordinates, ``ctx.shadow_size`` texels a side, holding the depth (:func:`depth_scale`
    ``depth``) of the first surface along each light ray (:meth:`roughlight.render.gl.context.Context.shadow_map`)."""
    shear = light_dir[:2] / light_dir[2]
    _, copies = lattice_copies(surface.height * shear[None, :])
    poses = copy_poses(copies, shear, light_dir, np.zeros(2))
    size = ctx.shadow_size
    begin_pass(ctx.shadow_map()[0], size, size, gl.GL_DEPTH_BUFFER_BIT)
    period = primitive(surface, poses)
    program = ctx.programs.get_program("periodic.vert", "periodic_depth.frag", defines=ATTRIBUTES)
    program._bind()
    set_viewport_uniforms(program, np.eye(2) * size, size, size, np.zeros(2), depth)
    draw(ctx, period, program)
    program._unbind()
    gl.glBindFramebuffer(gl.GL_FRAMEBUFFER, 0)


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
    #: adaptive sampling's facet regions (:func:`roughlight.render.fast.regions.facet_regions`), else None
    regions: object


def make_scene(ctx: Context, surface, light_dir, lighting, settings, regions) -> Scene:
    """Set up what every pass of the sweep draws with: the shadow map (drawn once, the light does not move; the
    context's map is built even without shadows, the program samples it) and the program (with facet identities
    for adaptive sampling)."""
    height = surface.height
    depth = depth_scale(height)
    ctx.shadow_map()
    shadow_mode = 0
    if lighting.shadows and height > 0:
        if light_dir[2] < 1e-9:
            shadow_mode = 2
        else:
            shadow_mode = 1
            shadow_pass(ctx, surface, light_dir, depth)
    defines = {**ATTRIBUTES, "FACET_IDS": 1} if regions is not None else ATTRIBUTES
    program = ctx.programs.get_program("periodic.vert", "periodic.frag", defines=defines)
    return Scene(surface, height, light_dir, lighting, settings, ctx, program, shadow_mode, depth, regions)


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


def set_lighting_uniforms(program, scene: Scene) -> None:
    """The lighting equation's and the shadow test's uniforms of ``scene`` on the bound ``periodic.frag``
    ``program``, and its shadow map on texture unit 0."""
    set_material_uniforms(program, scene.lighting, scene.light_dir)
    program.set_uniform("shadow_mode", int(scene.shadow_mode))
    program.set_uniform("shadow_size", int(scene.ctx.shadow_size))
    light_dir = scene.light_dir
    lz = max(float(light_dir[2]), 1e-12)
    program.set_uniform("light_shear", np.array([light_dir[0] / lz, light_dir[1] / lz], np.float32))
    program.set_uniform("shadow_bias", float(scene.settings.shadow_bias * max(scene.height, 1e-6)))
    gl.glActiveTexture(gl.GL_TEXTURE0)
    gl.glBindTexture(gl.GL_TEXTURE_2D, scene.ctx.shadow_map()[1])
    program.set_uniform("shadow_map", 0)
