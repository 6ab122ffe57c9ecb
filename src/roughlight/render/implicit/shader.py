"""The implicit rough surface on OpenGL: one quad, ``shaders/implicit.frag``, pyrender over OSMesa.

Two uses:

* :func:`implicit_sweep`: a sweep (one surface from many views) with the
  exact form or the first-order correction (``render.method``
  ``implicit_exact`` / ``implicit_correction``). The quad covers the
  framebuffer; each view owns ``M`` consecutive pixels (``M`` a Fibonacci
  number), pixel ``k`` of a view being point ``k`` of the Fibonacci lattice
  over one period (:func:`roughlight.render.implicit.model.fibonacci_lattice`). The view's
  value is the mean of its pixels' 8-bit values.
* :func:`render_field`: a picture of an ``N x N`` field of periods as a
  real-time scene would draw it: one quad through an orthographic camera
  (used by the speed benchmark, :mod:`roughlight.measurements.implicit_surface`).

The numpy forms of both models are in :mod:`roughlight.render.implicit.model`.
"""

from __future__ import annotations

import contextlib
import time
from functools import partial

import numpy as np

from ...surfaces.surface import Surface
from .. import shading, sweep
from ..gl.context import GLTF, Primitive, context, gl, set_uniforms
from .clipped import clipped_scene, clipped_shares
from .model import shader_uniforms
from .settings import CLIPPED_PICTURE, ImplicitSettings

__all__ = ["implicit_sweep", "render_field", "scene_defines", "table_defines", "table_uniforms", "shader_sources",
           "FRAMEBUFFER_WIDTH"]

#: Width of the sweep's framebuffer, pixels.
FRAMEBUFFER_WIDTH = 2048
#: Texels a row of the samples' texture of a scene with the exact form's shares once a frame.
FRAME_SAMPLES_WIDTH = 512

#: Most framebuffer rows of one pass.
MAX_ROWS = 2048


def _quad(z: float = 0.0, size: float = 1.0, ndc: bool = False):
    lo, hi = (-1.0, 1.0) if ndc else (0.0, size)
    corners = np.array([[lo, lo, z], [hi, lo, z], [hi, hi, z], [lo, lo, z], [hi, hi, z], [lo, hi, z]], np.float32)
    return Primitive(positions=corners, mode=GLTF.TRIANGLES)


def _draw_quad(quad) -> None:
    """Draw an uploaded quad (:func:`_field_quad`): its two triangles."""
    quad._bind()
    gl.glDrawArrays(gl.GL_TRIANGLES, 0, 6)
    quad._unbind()


def _begin(width: int, height: int, framebuffer: int = 0, clear: bool = True) -> None:
    """Draw into ``framebuffer`` (0: the context's own) over ``width`` x ``height`` pixels, no depth test, culling,
    blending or clip planes; cleared to 0 unless ``clear`` is False (a pass that writes every pixel)."""
    gl.glBindFramebuffer(gl.GL_FRAMEBUFFER, framebuffer)
    gl.glViewport(0, 0, width, height)
    gl.glDisable(gl.GL_DEPTH_TEST)
    gl.glDisable(gl.GL_CULL_FACE)
    gl.glDisable(gl.GL_BLEND)
    for plane in range(4):
        gl.glDisable(gl.GL_CLIP_DISTANCE0 + plane)
    if clear:
        gl.glClearColor(0.0, 0.0, 0.0, 0.0)
        gl.glClear(gl.GL_COLOR_BUFFER_BIT | gl.GL_DEPTH_BUFFER_BIT)


def _views_texture(views: np.ndarray, width: int) -> int:
    rows = -(-len(views) // width)
    data = np.zeros((rows * width, 4), np.float32)
    data[: len(views), :3] = views
    return _unit0_texture(width, rows, gl.GL_RGBA32F, gl.GL_FLOAT, data)


def _unit0_texture(width: int, rows: int, internal_format, pixel_type, data) -> int:
    """A new RGBA 2-D texture of ``width`` x ``rows`` texels from ``data``, on unit 0, read texel by texel
    (nearest); returns its name."""
    tex = gl.glGenTextures(1)
    gl.glActiveTexture(gl.GL_TEXTURE0)
    gl.glBindTexture(gl.GL_TEXTURE_2D, tex)
    gl.glTexImage2D(gl.GL_TEXTURE_2D, 0, internal_format, width, rows, 0, gl.GL_RGBA, pixel_type, data)
    gl.glTexParameteri(gl.GL_TEXTURE_2D, gl.GL_TEXTURE_MIN_FILTER, gl.GL_NEAREST)
    gl.glTexParameteri(gl.GL_TEXTURE_2D, gl.GL_TEXTURE_MAG_FILTER, gl.GL_NEAREST)
    return tex


def implicit_sweep(surface: Surface, incidence, azimuth, elevation, lighting=None, settings=None,
                   light_azimuth: float = 0.0) -> dict:
    """Render one sweep through the implicit shader on one quad.

    Parameters
    ----------
    surface : Surface
    incidence : float
        Light elevation, degrees in [0, 90].
    azimuth, elevation : (n_views,) arrays, degrees
    lighting : Lighting, optional
    settings : ImplicitSettings, optional
        The ``model`` (``"exact"``, the default, ``"correction"`` or ``"table"`` with its ``table``) and the
        pixels a view ``samples``, a Fibonacci number (default
        :func:`roughlight.render.implicit.model.model_samples`).
    light_azimuth : float, optional
        The light's azimuth, degrees, any: the exact form and the correction take the light's direction as it is;
        the table model turns it into its table's wedge [0, 45] (:func:`table_uniforms`).

    Returns
    -------
    dict as :func:`roughlight.render.fast.periodic.fast_sweep`: ``diffuse``, ``specular``,
    ``total``, ``coverage`` (n_views,) and ``seconds``; the means before rounding and without inner shadows are NaN
    (an 8-bit framebuffer: a float target beside it cost 10-14% of the sweep; docs/conventions.md).
    """
    settings = settings or ImplicitSettings()
    uniforms = shader_uniforms(settings.model, surface, incidence, lighting, settings.samples,  # checks every input
                               light_azimuth)
    samples = uniforms["samples"]
    table = _table_for(settings, surface, (lighting or shading.Lighting()).shadows)

    def step(out, views, incidence, lighting):
        todo, directions = views.measured, views.directions()
        width = FRAMEBUFFER_WIDTH
        per_pass = (width * MAX_ROWS) // samples
        rows = -(-min(per_pass, todo.size) * samples // width)
        ctx = context(width, rows, 1)
        program = ctx.programs.get_program("implicit.vert", "implicit.frag", table_defines(table))
        drawn = _with_table(uniforms, table, incidence, light_azimuth, lighting)
        textures = _table_textures(table)
        try:
            for first in range(0, todo.size, per_pass):
                idx = np.arange(first, min(first + per_pass, todo.size))
                raw = _draw_views(program, drawn, directions[idx], width, rows, table)
                _store_view_means(out, todo[idx], raw, samples)
        finally:
            if textures:
                gl.glDeleteTextures(textures)

    return sweep.measure(step, incidence, azimuth, elevation, lighting)


def _draw_views(program, uniforms: dict, views: np.ndarray, width: int, rows: int, table=None) -> bytes:
    """One pass of a sweep: the quad over a ``width`` x ``rows`` framebuffer, the (n, 3) unit ``views`` each
    owning ``uniforms["samples"]`` consecutive pixels; returns the framebuffer's RGBA bytes."""
    _begin(width, rows)
    with _field_quad(None) as quad:
        tex = _sweep_pass(program, uniforms, views, width, quad, table)
    gl.glFinish()
    gl.glDeleteTextures([tex])
    return gl.glReadPixels(0, 0, width, rows, gl.GL_RGBA, gl.GL_UNSIGNED_BYTE)


def _sweep_pass(program, uniforms: dict, views: np.ndarray, width: int, quad, table=None) -> int:
    """The sweep's draw into the bound framebuffer (``width`` pixels a row, :func:`_begin`): ``views`` uploaded
    to a texture on unit 0, whose name is returned for the caller to delete, and the full-viewport ``quad``
    (``_field_quad(None)``) drawn."""
    program._bind()
    set_uniforms(program, uniforms)
    _set_table_uniforms(program, table)
    program.set_uniform("camera", np.eye(4, dtype=np.float32))
    program.set_uniform("field_size", 0.0)
    program.set_uniform("fb_width", width)
    program.set_uniform("n_views", int(len(views)))
    views_width = min(len(views), 4096)
    program.set_uniform("views_width", views_width)
    tex = _views_texture(views, views_width)
    program.set_uniform("views", 0)
    _draw_quad(quad)
    program._unbind()
    return tex


def _store_view_means(out: dict, target: np.ndarray, raw: bytes, samples: int) -> None:
    """Store at ``target`` (n,) each view's mean 8-bit diffuse, specular and total (0-255) and coverage (0-1)
    over its ``samples`` consecutive pixels of the framebuffer's bytes ``raw``."""
    image = np.frombuffer(raw, np.uint8).reshape(-1, 4)[: target.size * samples]
    means = image.reshape(target.size, samples, 4).mean(axis=1, dtype=np.float64)
    for channel, name in enumerate(("diffuse", "specular", "total")):
        out[name][target] = means[:, channel]
    out["coverage"][target] = means[:, 3] / 255.0


def field_camera(view, field_size: float, span: float) -> np.ndarray:
    """World -> clip matrix of an orthographic camera looking along ``-view`` at the field's centre.

    ``span`` periods of the field's centre fill the picture across; the
    picture's up is the direction of increasing elevation.
    """
    v = np.asarray(view, float)
    up = np.array([0.0, 0.0, 1.0]) - v[2] * v
    if np.linalg.norm(up) < 1e-9:
        up = np.array([-1.0, 0.0, 0.0])
    up /= np.linalg.norm(up)
    right = np.cross(up, v)
    centre = np.array([field_size / 2.0, field_size / 2.0, 0.0])
    half = span / 2.0
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = right / half, up / half, -v / (4.0 * field_size + 4.0)
    m[:3, 3] = -m[:3, :3] @ centre
    return m


def scene_defines(model: str) -> dict:
    """Defines of the implicit shader drawing a scene with ``model``: the correction and the table see the whole
    field along one view under one light, so their shares and values are computed once a vertex and a pixel only
    picks one (``SCENE_CORRECTION``, implicit.vert; the table adds ``TABLE_SHARES``); the exact form casts its
    rays a pixel, as in a sweep."""
    if model == "exact":
        return {}
    extra = {"table": {"TABLE_SHARES": 1}, "clipped": {"GIVEN_SHARES": 1}}.get(model, {})
    return {"SCENE_CORRECTION": 1, **extra}


def table_defines(table) -> dict:
    """Defines of a sweep's shader: ``TABLE_SHARES`` with a table (the shares read from it), else none."""
    return {} if table is None else {"TABLE_SHARES": 1}


#: View elevation nodes the shader holds (``MAX_TABLE_ELEVATIONS`` in implicit_model.glsl: an array uniform).
MAX_TABLE_ELEVATIONS = 64


def _table_for(settings, surface: Surface, shadows: bool = True):
    """The table model's table, checked against the surface (with no table in the settings, the surface's own:
    :meth:`ImplicitSettings.share_table`) and against what the shader holds; None for the other models."""
    if settings.model != "table":
        return None
    table = settings.share_table(surface, shadows)
    if abs(table.truncation - surface.truncation) > 1e-9 or abs(table.aspect - surface.aspect) > 1e-9:
        raise ValueError(f"the share table is of the surface t {table.truncation:g}, a {table.aspect:g}, not of "
                         f"t {surface.truncation:g}, a {surface.aspect:g}: export the surface's own table")
    if table.elevation.size > MAX_TABLE_ELEVATIONS:
        raise ValueError(f"the share table has {table.elevation.size} view elevation nodes (its elevations with, "
                         f"under export.table.hot_spot_views, its incidences); the shader holds at most "
                         f"{MAX_TABLE_ELEVATIONS}: fewer nodes, or hot_spot_views false")
    return table


def table_uniforms(table, incidence: float, light_azimuth: float, lighting=None) -> dict:
    """The table model's uniforms for one light: the light turned to the table's light azimuths (``light_dir``
    and the material's terms), the turn of the views (``view_turn``), the light's four nodes (``table_slices``,
    ``table_weights``; :func:`roughlight.render.implicit.table.light_corners`), each node's azimuth and incidence
    less the light's (``table_turns``, ``table_rises``) with ``hot_spot_blend`` (the hot spot's reading,
    :func:`roughlight.render.implicit.table.table_shares`), and the texture's extent. The node elevations are an
    array uniform, set by :func:`_set_table_uniforms`."""
    from .table import HOT_SPOT_BLEND, light_corners

    slices, weights, light_c, turn = light_corners(table, incidence, light_azimuth)
    psi = np.degrees(np.arctan2(light_c[1], light_c[0])) % 360.0
    return {
        **shading.material_uniforms(lighting or shading.Lighting(), light_c),
        "view_turn": turn.astype(np.float32),
        "table_turns": (table.slice_azimuth[slices] - psi).astype(np.float32),
        "table_rises": (table.slice_incidence[slices] - float(incidence)).astype(np.float32),
        "hot_spot_blend": float(HOT_SPOT_BLEND),
        "table_slices": slices.astype(np.int32),
        "table_weights": weights.astype(np.float32),
        "table_depth": table.lights,
        "table_azimuths": int(table.azimuth_nodes),
        "table_elevations": int(table.elevation.size),
    }


def _with_table(uniforms: dict, table, incidence, light_azimuth, lighting) -> dict:
    """``uniforms`` with the table's (:func:`table_uniforms`) when there is a table."""
    if table is None:
        return uniforms
    return {**uniforms, **table_uniforms(table, incidence, light_azimuth, lighting)}


#: Texture units of the table's three textures (unit 0 holds a sweep's views).
TABLE_UNITS = {"table_lit": 1, "table_mixed": 2, "table_shadow": 3}


def _table_textures(table) -> list:
    """Upload the table's shares as three RGBA16 3-D textures on :data:`TABLE_UNITS` (x view azimuth, repeating;
    y view elevation node; z light node), filtered linearly; returns their names ([] without a table)."""
    if table is None:
        return []
    from .table import CHANNELS

    n_l, n_e, n_a, _ = table.shares.shape
    names = list(np.atleast_1d(gl.glGenTextures(3)))
    for unit, tex, first in zip(TABLE_UNITS.values(), names, (0, 4, 8)):
        gl.glActiveTexture(gl.GL_TEXTURE0 + unit)
        gl.glBindTexture(gl.GL_TEXTURE_3D, tex)
        data = np.zeros((n_l, n_e, n_a, 4), np.uint16)  # one texture's four channels at a time (the last two: 0)
        data[..., :min(4, CHANNELS - first)] = table.shares[..., first:first + 4]
        gl.glTexImage3D(gl.GL_TEXTURE_3D, 0, gl.GL_RGBA16, n_a, n_e, n_l, 0, gl.GL_RGBA, gl.GL_UNSIGNED_SHORT, data)
        del data
        for parameter, value in ((gl.GL_TEXTURE_MIN_FILTER, gl.GL_LINEAR), (gl.GL_TEXTURE_MAG_FILTER, gl.GL_LINEAR),
                                 (gl.GL_TEXTURE_WRAP_S, gl.GL_REPEAT), (gl.GL_TEXTURE_WRAP_T, gl.GL_CLAMP_TO_EDGE),
                                 (gl.GL_TEXTURE_WRAP_R, gl.GL_CLAMP_TO_EDGE)):
            gl.glTexParameteri(gl.GL_TEXTURE_3D, parameter, value)
    gl.glActiveTexture(gl.GL_TEXTURE0)
    return names


#: Tables whose textures a context keeps resident (the latest drawn; an older one's are deleted): each is tens of
#: MB of texture, and a validation draws a table a surface.
KEPT_TABLES = 2


def _resident_textures(ctx, table) -> None:
    """Bind ``table``'s textures (:func:`_table_textures`) on :data:`TABLE_UNITS`, uploaded once a context and
    table and kept there (the last :data:`KEPT_TABLES` tables): Mesa copies a texture into its own layout at the
    first draw that reads it, which a frame that uploaded its table would pay for every time (1 ms of a 2 ms frame
    at the default nodes)."""
    if table is None:
        return
    kept = ctx.__dict__.setdefault("_share_tables", {})
    if id(table) not in kept:
        while len(kept) >= KEPT_TABLES:
            _, textures = kept.pop(next(iter(kept)))
            gl.glDeleteTextures(np.asarray(textures, np.uint32))
        kept[id(table)] = (table, _table_textures(table))  # the table kept too: its id is never reused meanwhile
    else:
        kept[id(table)] = kept.pop(id(table))  # the latest drawn last
    for unit, tex in zip(TABLE_UNITS.values(), kept[id(table)][1]):
        gl.glActiveTexture(gl.GL_TEXTURE0 + unit)
        gl.glBindTexture(gl.GL_TEXTURE_3D, tex)
    gl.glActiveTexture(gl.GL_TEXTURE0)


def _set_table_uniforms(program, table) -> None:
    """The bound ``program``'s table samplers and node elevations (array uniforms pyrender does not set)."""
    if table is None:
        return
    for name, unit in TABLE_UNITS.items():
        program.set_uniform(name, unit)
    _set_float_array(program, "table_elevation", table.elevation)


def _set_float_array(program, name: str, values) -> None:
    """The bound ``program``'s float array uniform ``name`` (pyrender sets no array uniform) to ``values``."""
    values = np.asarray(values, np.float32)
    gl.glUniform1fv(gl.glGetUniformLocation(program._program_id, name), values.size, values)


def shader_sources(model: str) -> tuple[str, str]:
    """The implicit shader's vertex and fragment sources for a scene drawn with ``model``, self-contained:
    ``#include`` expanded and the model's defines applied, ready for any OpenGL 3.3 program to compile.
    Set the uniforms :func:`roughlight.render.implicit.model.shader_uniforms` gives, plus ``camera`` (world -> clip),
    ``field_size`` (N), ``scene_view`` (unit vector toward the detector) and ``fb_width`` (pixels), and draw
    one quad over ``[0, N]^2`` of the plane ``z = 0`` (:func:`render_field`)."""
    from ..gl.context import SHADER_DIR, Program

    program = Program.__new__(Program)  # only its source loader: no GL context is needed
    program.defines = scene_defines(model)
    return tuple(program._load(f"{SHADER_DIR}/implicit.{stage}") for stage in ("vert", "frag"))


def render_field(model: str, surface: Surface, incidence, elevation, azimuth, field_size: int,
                 size: int = 512, span: float | None = None, lighting=None, samples: int = 46368, table=None,
                 frame_samples: int | None = None, phases: dict | None = None):
    """One picture of an ``N x N`` field drawn as one implicit quad.

    ``table``: the table model's :class:`~roughlight.render.implicit.table.ShareTable` (or its file); its
    textures are uploaded before the frame's timer, once a context and table (:func:`_resident_textures`), as a
    real-time scene keeps them.

    ``model`` ``"clipped"``: the clipped scene, whose frame clips its view's facet shares exactly on the CPU
    (:func:`roughlight.render.implicit.clipped.clipped_shares`, phase ``shares`` of the frame's time) and draws them
    as the correction draws its own.

    ``frame_samples`` (the exact form only; a Fibonacci number): the exact form's shares once a frame. The whole
    picture sees the field along one view under one light, so a first pass casts the rays of ``frame_samples``
    points of one period once, as a sweep's view (:func:`_sweep_pass`), into a texture that stays on the GPU, and
    the picture's pixels each show the sample their dither picks (``SCENE_SAMPLES``, implicit.frag): the exact
    form's sweep at that many samples a view, in one pass of ``frame_samples`` ray casts and one of texture reads,
    both inside the frame's time.

    ``phases``, when a dict is given, receives the frame's time by phase, seconds, each ended by ``glFinish``:
    ``clear``, ``draw`` (the uniforms set and the quad drawn), ``read`` (the picture read back) and, once a frame,
    ``first_pass`` (the samples' rays cast into their texture).

    Returns
    -------
    image : (size, size, 4) uint8 array (r diffuse, g specular, b total, a coverage)
    seconds : float, the frame's time (clear, draw and read back)
    """
    if model == "clipped":
        return _field_by_clipped_shares(surface, incidence, elevation, azimuth, field_size, size, span, lighting,
                                        samples, phases)
    if frame_samples is not None:
        if model != "exact":
            raise ValueError(f"frame_samples: the exact form's shares once a frame, not the {model} model's")
        return _field_by_frame_samples(surface, incidence, elevation, azimuth, field_size, size, span, lighting,
                                       int(frame_samples), phases)
    uniforms, table = _scene_uniforms(model, surface, incidence, lighting, samples, table)
    view = shading.view_direction(float(elevation), float(azimuth))
    ctx = context(size, size, 1)
    program = ctx.programs.get_program("implicit.vert", "implicit.frag", scene_defines(model))
    _resident_textures(ctx, table)  # a real-time scene keeps its textures resident, as its buffers
    uniforms = {**uniforms, "scene_view": np.asarray(view, np.float32), "fb_width": size}
    with _field_quad(field_size) as quad:
        return _picture(program, uniforms, quad, view, field_size, size, span, _Phases(phases), table)


def _scene_uniforms(model: str, surface: Surface, incidence, lighting, samples: int, table):
    """A scene's uniforms (:func:`shader_uniforms`, with the table's for the table model) and its table (None for
    the other models)."""
    uniforms = shader_uniforms(model, surface, incidence, lighting, samples)
    if model != "table":
        return uniforms, None
    table = _table_for(ImplicitSettings("table", table=table), surface, (lighting or shading.Lighting()).shadows)
    return _with_table(uniforms, table, incidence, 0.0, lighting), table


class _Phases:
    """A frame's clock: :meth:`end` finishes the GL work so far (``glFinish``) and records the phase's seconds in
    ``phases`` (a dict, or None to keep none); it returns the seconds since the clock started."""

    def __init__(self, phases: dict | None):
        self.phases = phases
        self.start = self.last = time.perf_counter()

    def end(self, phase: str) -> float:
        gl.glFinish()
        now = time.perf_counter()
        if self.phases is not None:
            self.phases[phase] = now - self.last
        self.last = now
        return now - self.start


class _Untimed(_Phases):
    """A clock that times nothing and finishes no GL work: a sweep's pictures, whose read-back waits for the
    drawing anyway (three ``glFinish`` a picture were a fifth of the clipped sweep's time)."""

    def end(self, phase: str) -> float:
        return 0.0


@contextlib.contextmanager
def _field_quad(field_size: int | None):
    """The field's quad, ``[0, N]^2`` of the base plane (``field_size`` None: the full-viewport quad of a sweep's
    pass), uploaded (before a frame's clock starts, as a real-time scene keeps its buffers) and deleted after."""
    quad = _quad(ndc=True) if field_size is None else _quad(size=float(field_size))
    quad._add_to_context()
    try:
        yield quad
    finally:
        quad.delete()


def _field_by_clipped_shares(surface: Surface, incidence, elevation, azimuth, field_size: int, size: int, span,
                             lighting, samples: int, phases: dict | None = None, light_azimuth: float = 0.0):
    """:func:`render_field` of the clipped scene: each frame clips its view's facet shares on the CPU
    (:func:`clipped_shares`, inside the frame's time: phase ``shares``) and the quad draws them as the correction
    draws its own (``SCENE_CORRECTION`` with ``GIVEN_SHARES``). The light's scene (its facets and the light, as the
    C clipper takes them) is made before the frame's clock and kept while the light stays, as a scene keeps its
    buffers; every frame clips its view whole, the light's occluders too."""
    lighting = lighting or shading.Lighting()
    uniforms = shader_uniforms("correction", surface, incidence, lighting, samples, light_azimuth)  # checks inputs
    view = shading.view_direction(float(elevation), float(azimuth))
    scene = clipped_scene(surface, float(incidence), bool(lighting.shadows), float(light_azimuth))  # kept
    shares = partial(scene.shares, float(elevation), float(azimuth))
    ctx = context(size, size, 1)
    program = ctx.programs.get_program("implicit.vert", "implicit.frag", scene_defines("clipped"))
    uniforms = {**uniforms, "scene_view": np.asarray(view, np.float32), "fb_width": size}
    with _field_quad(field_size) as quad:
        clock = _Phases(phases)
        given = shares()
        clock.end("shares")
        return _picture(program, uniforms, quad, view, field_size, size, span, clock, given=given)


def clipped_sweep(surface: Surface, incidence, azimuth, elevation, lighting=None, settings=None,
                  light_azimuth: float = 0.0) -> dict:
    """A sweep of the clipped scene: each view drawn as :func:`render_field`'s ``"clipped"`` frame draws it (the
    view's facet shares clipped exactly on the CPU, then one quad whose pixels each show one facet's 8-bit value,
    picked by a dither threshold; one quad and program for the whole sweep, every view's shares clipped in one call),
    and its picture's mean (:data:`~roughlight.render.implicit.settings.CLIPPED_PICTURE`, wholly covered by the field).

    Parameters
    ----------
    surface : Surface (regular)
    incidence : float, light elevation, degrees in [0, 90]
    azimuth, elevation : (n_views,) arrays, degrees
    lighting : Lighting, optional
    settings : ImplicitSettings with ``model`` ``"clipped"``, optional (method ``implicit_clipped``; it has no knobs)
    light_azimuth : float, the light's azimuth, degrees

    Returns
    -------
    dict as :func:`implicit_sweep`'s: ``diffuse``, ``specular``, ``total``, ``coverage`` (n_views,) and ``seconds``;
    the means before rounding and without inner shadows are NaN (an 8-bit framebuffer).
    """
    picture = CLIPPED_PICTURE
    size, field_size = picture["size"], picture["field_size"]
    lighting = lighting or shading.Lighting()
    uniforms = {**shader_uniforms("correction", surface, incidence, lighting, None, light_azimuth),  # checks inputs
                "fb_width": size}

    def step(out, views, incidence, lighting):
        program = context(size, size, 1).programs.get_program("implicit.vert", "implicit.frag", scene_defines("clipped"))
        measured = np.asarray(views.measured)
        lit, shadowed = clipped_shares(surface, incidence, views.elevation[measured], views.azimuth[measured],
                                       lighting.shadows, light_azimuth)  # every view's shares, in one call
        with _field_quad(field_size) as quad:
            for j, k in enumerate(measured):
                e, phi = views.elevation[k], views.azimuth[k]
                view = shading.view_direction(float(e), float(phi))
                given = lit[j], shadowed[j]
                image, _ = _picture(program, {**uniforms, "scene_view": np.asarray(view, np.float32)}, quad, view,
                                    field_size, size, picture["span"], _Untimed(None), given=given)
                means = image.reshape(-1, 4).mean(axis=0, dtype=np.float64)
                for channel, name in enumerate(("diffuse", "specular", "total")):
                    out[name][k] = means[channel]
                out["coverage"][k] = means[3] / 255.0

    return sweep.measure(step, incidence, azimuth, elevation, lighting)


def _set_given_shares(program, given) -> None:
    """The bound ``program``'s ``given_lit`` and ``given_shadow`` (array uniforms pyrender does not set) from
    ``given`` ((lit, shadowed), :func:`clipped_shares`); nothing when None."""
    if given is None:
        return
    for name, shares in zip(("given_lit", "given_shadow"), given):
        _set_float_array(program, name, shares)


def _picture(program, uniforms: dict, quad, view, field_size: int, size: int, span, clock, table=None, given=None):
    """A scene's picture pass: the ``size`` x ``size`` picture cleared, then the field's ``quad``
    (:func:`_field_quad`; ``span`` periods across the picture, default half the field's ``field_size``) drawn by
    ``program`` with ``uniforms`` and the camera along ``view``, and read back; ``clock`` (:class:`_Phases`) times
    its ``clear``, ``draw`` and ``read``. Returns :func:`render_field`'s picture and seconds."""
    span = float(field_size) / 2.0 if span is None else float(span)
    _begin(size, size)
    clock.end("clear")
    program._bind()
    set_uniforms(program, uniforms)
    _set_table_uniforms(program, table)
    _set_given_shares(program, given)
    program.set_uniform("camera", field_camera(view, field_size, span).astype(np.float32))
    program.set_uniform("field_size", float(field_size))
    _draw_quad(quad)
    program._unbind()
    clock.end("draw")
    raw = gl.glReadPixels(0, 0, size, size, gl.GL_RGBA, gl.GL_UNSIGNED_BYTE)
    seconds = clock.end("read")
    return np.frombuffer(raw, np.uint8).reshape(size, size, 4)[::-1].copy(), seconds


def _field_by_frame_samples(surface: Surface, incidence, elevation, azimuth, field_size: int, size: int, span,
                            lighting, samples: int, phases: dict | None = None):
    """:func:`render_field` of the exact form with its shares once a frame (``frame_samples``): the first pass draws
    the samples into a texture (:func:`_samples_target`), which the picture reads; no read-back between them."""
    uniforms = shader_uniforms("exact", surface, incidence, lighting, samples)
    view = shading.view_direction(float(elevation), float(azimuth))
    width = FRAME_SAMPLES_WIDTH  # the samples' texture, row by row, whatever the picture's size
    rows = -(-samples // width)
    ctx = context(size, size, 1)
    sweep_program = ctx.programs.get_program("implicit.vert", "implicit.frag", {})
    program = ctx.programs.get_program("implicit.vert", "implicit.frag", {"SCENE_SAMPLES": 1})
    with _field_quad(field_size) as quad, _field_quad(None) as pass_quad, _samples_target(width, rows) as target:
        framebuffer, texture = target
        clock = _Phases(phases)
        _begin(width, rows, framebuffer, clear=False)  # the pass writes every texel
        views = _sweep_pass(sweep_program, uniforms, np.asarray(view, float)[None, :], width, pass_quad)
        try:
            clock.end("first_pass")
            gl.glActiveTexture(gl.GL_TEXTURE0)
            gl.glBindTexture(gl.GL_TEXTURE_2D, texture)
            return _picture(program, {"samples": samples, "samples_width": width, "frame_samples": 0}, quad, view,
                            field_size, size, span, clock)
        finally:
            gl.glDeleteTextures([views])


@contextlib.contextmanager
def _samples_target(width: int, rows: int):
    """A ``width`` x ``rows`` RGBA8 texture (nearest) as the colour of a framebuffer object of its own, made
    before a frame's clock starts (as a real-time scene keeps its render targets) and deleted after: yields
    (framebuffer, texture)."""
    texture = _unit0_texture(width, rows, gl.GL_RGBA8, gl.GL_UNSIGNED_BYTE, None)
    framebuffer = gl.glGenFramebuffers(1)
    try:
        gl.glBindFramebuffer(gl.GL_FRAMEBUFFER, framebuffer)
        gl.glFramebufferTexture2D(gl.GL_FRAMEBUFFER, gl.GL_COLOR_ATTACHMENT0, gl.GL_TEXTURE_2D, texture, 0)
        status = gl.glCheckFramebufferStatus(gl.GL_FRAMEBUFFER)
        gl.glBindFramebuffer(gl.GL_FRAMEBUFFER, 0)
        if status != gl.GL_FRAMEBUFFER_COMPLETE:
            raise RuntimeError(f"the exact form's samples texture ({width} x {rows}) is no complete framebuffer: "
                               f"status {status:#x}")
        yield framebuffer, texture
    finally:
        gl.glBindFramebuffer(gl.GL_FRAMEBUFFER, 0)
        gl.glDeleteFramebuffers(1, [framebuffer])
        gl.glDeleteTextures([texture])
