"""The naive method: the thesis's procedure with pyrender as it comes, one render per view.

Each view renders a 400 x 300 window of a finite patch of the surface through
an orthographic camera orbiting it, with one directional light whose shadow
map pyrender redraws on every render; the view's value is the mean of the
central 40 x 40 pixels, as the thesis read its framebuffer. Only the shaders
are the study's (``naive.vert``, ``naive.frag``: the OpenGL lighting
equation in place of pyrender's PBR). It is the baseline the fast method is
measured against; :func:`render_picture` uses the same scene for pictures.
"""

from __future__ import annotations

import math
import os

import numpy as np

from ...surfaces import geometry
from ...surfaces.surface import Surface
from .. import shading, sweep
from ..gl.context import SHADER_DIR, Program, PyrenderShaderCache, import_pyrender, offscreen_renderer, release_contexts
from ..shading import SHADINGS
from .settings import NaiveSettings


class _PyrenderShaders(PyrenderShaderCache):
    """pyrender's program cache, as it comes (keyed on the GL context), with the
    study's equation in place of its PBR shaders (``naive.vert``, ``naive.frag``)."""

    shading = "flat"

    def get_program(self, vertex_shader, fragment_shader, geometry_shader=None, defines=None):
        if fragment_shader != "mesh.frag":
            return super().get_program(vertex_shader, fragment_shader, geometry_shader, defines)
        # ours, compiled with the study's `#include` (lighting.glsl) and keyed as pyrender keys its own programs
        import OpenGL.contextdata

        defines = {**(defines or {}), **({"GOURAUD": 1} if self.shading == "gouraud" else {})}
        key = ("naive", OpenGL.contextdata.getContext(), tuple(sorted(defines.items())))
        if key not in self._program_cache:
            self._program_cache[key] = Program(vertex_shader=os.path.join(SHADER_DIR, "naive.vert"),
                                               fragment_shader=os.path.join(SHADER_DIR, "naive.frag"),
                                               defines=defines)
        return self._program_cache[key]


class CompiledShaders(_PyrenderShaders):
    """:class:`_PyrenderShaders` keyed on the shader files only, so each program compiles once: what a
    real-time program does (the implicit surface's frame-time benchmark draws its explicit field with it)."""

    def get_program(self, vertex_shader, fragment_shader, geometry_shader=None, defines=None):
        key = (vertex_shader, fragment_shader, geometry_shader, tuple(sorted((defines or {}).items())))
        programs = self.__dict__.setdefault("_compiled", {})
        if key not in programs:
            programs[key] = super().get_program(vertex_shader, fragment_shader, geometry_shader, defines)
        return programs[key]

    def clear(self):
        pass


def up_vector(view: np.ndarray) -> np.ndarray:
    """Image 'up': the direction of increasing elevation (keeps the horizon level)."""
    e = math.asin(max(-1.0, min(1.0, view[2])))
    phi = math.atan2(view[1], view[0]) if abs(math.cos(e)) > 1e-12 else 0.0
    if math.cos(e) < 0:  # beyond the zenith the orbit's azimuth is phi + 180
        phi += math.pi
    return np.array([-math.sin(e) * math.cos(phi), -math.sin(e) * math.sin(phi), math.cos(e)])


def look_pose(direction: np.ndarray, up: np.ndarray, distance: float) -> np.ndarray:
    """Camera (or light) pose at ``distance * direction`` looking back at the origin."""
    z = direction / np.linalg.norm(direction)
    x = np.cross(up, z)
    if np.linalg.norm(x) < 1e-9:
        x = np.cross([0.0, 1.0, 0.0], z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2], pose[:3, 3] = x, y, z, z * distance
    return pose


def _patch_periods(span: float, lowest_elevation: float) -> int:
    """Odd patch side (periods) that a view ``span`` periods across still fills at ``lowest_elevation`` degrees.

    Seen from elevation e, a window ``span`` periods tall reaches ``span / sin e``
    periods along the ground (at most ten spans: below about 5.7 degrees the
    patch stops growing); two periods more on each side keep the shadow
    casters, and an odd count centres a period on the origin.
    """
    reach = span / max(math.sin(math.radians(lowest_elevation)), 0.1)
    return int(2 * math.ceil(reach / 2.0 + 2)) + 1


def patch_mesh(surface: Surface, periods: int, averaged_normals: bool = False):
    """A finite ``periods`` x ``periods`` patch of the surface, centred on the origin (trimesh).

    With ``averaged_normals`` the vertices shared by facets are merged and each
    carries the plain average of the normals of the faces around it (the
    shading notes' Gouraud construction); otherwise every triangle keeps its
    own vertices and its true face normal.
    """
    import trimesh

    tris, normals, _ = geometry.period_triangles(surface)
    offsets = np.arange(periods) - periods / 2.0
    shifts = np.zeros((periods * periods, 3))
    shifts[:, 0] = np.repeat(offsets, periods)
    shifts[:, 1] = np.tile(offsets, periods)
    # every copy keeps its own vertices (flat facets), as period_mesh's
    vertices = (tris[None, :, :, :] + shifts[:, None, None, :]).reshape(-1, 3)
    faces = np.arange(len(vertices)).reshape(-1, 3)
    face_normals = np.tile(normals, (periods * periods, 1))
    # no vertex normals: flat shading draws the face normals (pyrender's from_trimesh, smooth off), and averaged
    # normals are made below from the merged mesh; a copy of them was 75 MB of the N 512 field's peak
    mesh = trimesh.Trimesh(vertices=vertices, faces=faces, face_normals=face_normals, process=False)
    if averaged_normals:
        mesh = trimesh.Trimesh(vertices=mesh.vertices, faces=mesh.faces, process=False)
        mesh.merge_vertices(digits_vertex=9)
        sums = np.zeros((len(mesh.vertices), 3))
        for corner in range(3):
            np.add.at(sums, mesh.faces[:, corner], mesh.face_normals)
        mesh.vertex_normals = sums / np.linalg.norm(sums, axis=1, keepdims=True)
    return mesh


class NaiveScene:
    """The thesis's set-up in pyrender as it comes: a finite patch, an orthographic
    camera orbiting it, one DirectionalLight whose shadow map pyrender redraws on
    every render."""

    def __init__(self, surface, incidence, lighting, size, periods, view_periods, shading_model="flat"):
        if shading_model not in SHADINGS:
            raise ValueError(f"shading_model must be one of {SHADINGS}, got {shading_model!r}")
        pyrender = self.pyrender = import_pyrender()
        self.size = tuple(int(v) for v in size)
        self.scene = pyrender.Scene(bg_color=[0.0, 0.0, 0.0, 0.0], ambient_light=[0.0, 0.0, 0.0])
        material = pyrender.MetallicRoughnessMaterial(
            baseColorFactor=[
                lighting.diffuse_reflectance,
                lighting.specular_reflectance,
                lighting.ambient_reflectance * lighting.ambient,
                lighting.shininess / 128.0,
            ],
            metallicFactor=1.0 if lighting.specular_model == "blinn" else 0.0,
            doubleSided=False,
        )
        smooth = shading_model != "flat"
        mesh = patch_mesh(surface, periods, averaged_normals=smooth)
        self.scene.add(pyrender.Mesh.from_trimesh(mesh, material=material, smooth=smooth))
        self.shading_model = shading_model
        light_dir = shading.light_direction(incidence)
        light = pyrender.DirectionalLight(color=np.ones(3), intensity=float(lighting.light) / 255.0)
        up = np.array([0.0, 0.0, 1.0]) if abs(light_dir[2]) < 0.99 else np.array([1.0, 0.0, 0.0])
        self.scene.add(light, pose=look_pose(light_dir, up, 10.0))
        half_width = view_periods / 2.0
        camera = pyrender.OrthographicCamera(
            xmag=half_width, ymag=half_width * self.size[1] / self.size[0], znear=0.05, zfar=4.0 * periods + 20.0
        )
        self.distance = 2.0 * periods + 10.0
        self.camera_node = self.scene.add(camera, pose=np.eye(4))
        self.shadows = bool(lighting.shadows) and not surface.is_plate
        if self.shadows and not lighting.specular_shadows:
            raise ValueError("render.specular_shadows: false is not available with the naive method (pyrender's "
                             "shadow pass darkens every component); use render.method fast or reference")

    def render(self, renderer, view, jitter=(0.0, 0.0)):
        pyrender = self.pyrender
        pose = look_pose(view, up_vector(view), self.distance)
        pixel = 2.0 * self.camera_node.camera.xmag / self.size[0]  # world units per pixel
        pose[:3, 3] += pixel * (jitter[0] * pose[:3, 0] + jitter[1] * pose[:3, 1])
        self.scene.set_pose(self.camera_node, pose)
        cache = renderer._renderer._program_cache
        cache.shading = self.shading_model
        flags = pyrender.RenderFlags.SHADOWS_DIRECTIONAL if self.shadows else pyrender.RenderFlags.NONE
        color, depth = renderer.render(self.scene, flags=flags)
        # pyrender keys its programs on the context object, new on every OSMesa call: it compiles
        # them anew each render (the cost the naive method keeps) and never frees the old ones
        # (about 2 MB a render, 4.5 GB over the benchmark's naive views): free them here
        cache.clear()
        return color, depth


NAIVE_RENDERERS: dict = {}


def _naive_renderer(size):
    renderer = NAIVE_RENDERERS.get(size)
    if renderer is None:
        for other in list(NAIVE_RENDERERS.values()):
            other.delete()
        NAIVE_RENDERERS.clear()
        release_contexts()  # the fast method's too: one OSMesa context at a time
        renderer = offscreen_renderer(*size)
        renderer._renderer._program_cache = _PyrenderShaders()
        NAIVE_RENDERERS[size] = renderer
    return renderer


def naive_sweep(surface: Surface, incidence, azimuth, elevation, lighting=None, settings=None) -> dict:
    """The thesis's procedure with pyrender as it comes: one render per view.

    Each view renders a ``settings.window`` (400 x 300 pixels, as the thesis) of a finite
    patch through an orthographic camera, with pyrender redrawing its 2048^2
    directional shadow map and (its program cache being keyed on OSMesa's
    ever-new context) recompiling its shaders on every render; the value is
    the mean of the central ``capture`` x ``capture`` pixels (the thesis's
    40 x 40). The window spans ``view_periods`` periods across (10 pixels a
    period by default), the patch enough periods to fill the capture window
    down to ``lowest_elevation`` degrees (10 by default). ``coverage`` is the
    fraction of capture pixels showing the surface (from the depth buffer).
    ``settings`` is a :class:`roughlight.render.naive.settings.NaiveSettings` (default: the thesis's), which
    also sets the camera's ``jitter`` and the ``shading_model``.

    Returns the dict of :func:`roughlight.render.fast.periodic.fast_sweep`.
    """
    lighting = lighting or shading.Lighting()
    s = settings or NaiveSettings()
    window, capture = tuple(int(w) for w in s.window), int(s.capture)
    periods = _patch_periods(s.view_periods * capture / window[0], s.lowest_elevation)
    scene = NaiveScene(surface, shading.check_incidence(incidence), lighting, window, periods, s.view_periods,
                       s.shading_model)
    w, h = window
    x0, y0 = (w - capture) // 2, (h - capture) // 2
    box = np.s_[y0:y0 + capture, x0:x0 + capture]

    def step(out, views, incidence, lighting):
        renderer = _naive_renderer(window)
        for k, view in zip(views.measured, views.directions()):
            color, depth = scene.render(renderer, view, s.jitter)
            means = color[box].reshape(-1, color.shape[-1]).mean(axis=0, dtype=np.float64)
            out["diffuse"][k], out["specular"][k], out["total"][k] = means[:3]
            out["coverage"][k] = float(np.mean(depth[box] > 0))

    # an 8-bit framebuffer read back: no mean before rounding, none without the shadows (NaN)
    return sweep.measure(step, incidence, azimuth, elevation, lighting)


def render_picture(surface: Surface, incidence, elevation, azimuth, lighting=None, size=(400, 300),
                   periods=6, component="total", shading_model="flat") -> np.ndarray:
    """A picture of the surface as the detector sees it (the thesis's screenshots).

    A finite patch, ``periods`` periods across the picture, orthographic camera
    at (``elevation``, ``azimuth``) degrees, lit and shadowed as the study;
    ``shading_model`` as :func:`naive_sweep` (``flat``: true face normals).

    Returns
    -------
    (H, W, 3) uint8 array, the chosen component (``diffuse``, ``specular`` or
    ``total``) as grey levels.
    """
    lighting = lighting or shading.Lighting()
    patch = _patch_periods(periods, max(float(elevation), 1.0))
    scene = NaiveScene(surface, shading.check_incidence(incidence), lighting, size, min(patch, 201), periods,
                        shading_model)
    renderer = _naive_renderer(tuple(size))
    view = shading.view_direction(float(elevation), float(azimuth))
    color, _ = scene.render(renderer, view)
    channel = {"diffuse": 0, "specular": 1, "total": 2}[component]
    return np.repeat(color[..., channel : channel + 1], 3, axis=2).copy()
