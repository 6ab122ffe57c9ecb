"""Rendering sweeps with pyrender over OSMesa.

The ``fast`` method
-------------------
A sweep is one surface under one directional light seen from many views. The
renderer draws *every view of a sweep in one framebuffer*, one small tile per
view, with one instanced draw call:

* Each view's tile shows exactly one period of the projected image of the
  infinite periodic surface. The projection is the oblique parallel projection
  along the view direction onto the base plane (``shaders/periodic.vert``): it
  is an orthographic camera whose image plane is sheared onto the surface's
  lattice, so the pixels of a tile sample one period uniformly and the tile
  mean is the mean over the infinite surface: no background, no patch edge,
  no moiré between the surface period and the pixel grid. ``coverage`` is
  the fraction of the tile's pixels that show the surface (1 for every view
  but the grazing ones, ``e`` = 0 or 180, which see no area and are 0).
* The scene holds only what the measurement needs: one period (at most 10
  triangles), instanced at the lattice copies whose projection reaches the
  tile (more copies only near grazing views of tall surfaces).
* The light does not move during a sweep, so the shadow map is drawn once per
  sweep. It is periodic too: one period of light-oblique coordinates,
  sampled with wrap-around, storing the height of the first surface along
  each light ray; a fragment compares its own facet's height at the texel
  centre (receiver-plane depth), so a facet never shadows itself.
* The lighting equation (``roughlight.shading``) is evaluated per fragment in
  ``shaders/periodic.frag``; diffuse, specular and total go to the r, g and b
  channels of one pass and are each stored as 8-bit values.

pyrender provides the OSMesa context, the vertex buffers with instancing and
the shader programs; its stock shader (metallic-roughness PBR with gamma) is
not the study's equation and is not used. Its program cache keys programs on
the GL context object, which OSMesa hands back anew on every call (every
render would recompile); :class:`ShaderCache` keys them on the shader files
and defines only.
"""

from __future__ import annotations

import os

os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")

import math  # noqa: E402
import time  # noqa: E402
from dataclasses import dataclass  # noqa: E402

import importlib  # noqa: E402
import importlib.util  # noqa: E402
import sys  # noqa: E402
import types  # noqa: E402

import numpy as np  # noqa: E402

from .osmesa import HELP as _OSMESA_HELP  # noqa: E402
from .osmesa import OSMesaUnavailable, check_osmesa  # noqa: E402

try:
    from OpenGL import GL as gl  # noqa: E402
except (ImportError, AttributeError, OSError) as _exc:  # PyOpenGL's own errors do not say what to do
    if os.environ.get("PYOPENGL_PLATFORM") == "osmesa":
        check_osmesa()  # raises OSMesaUnavailable naming the missing or broken library
    raise OSMesaUnavailable(f"PyOpenGL could not load ({type(_exc).__name__}: {_exc}): {_OSMESA_HELP}") from _exc


def _import_pyrender_core():
    """Load the parts of pyrender the fast method uses, without pyrender's package ``__init__``.

    ``import pyrender`` imports its viewer (pyglet), its trimesh-based Mesh and
    Scene, and through trimesh scipy and networkx: about 1.7 s, paid again by
    every sweep job (each is a fresh process). The fast method needs only the
    OSMesa platform, Primitive (vertex buffers with instancing) and the shader
    programs, whose modules import nothing heavy. When pyrender is not yet
    imported, an empty package module stands in for its ``__init__`` so that
    those submodules load alone; :func:`_import_pyrender` swaps in the real
    package whenever the whole of pyrender is needed (the naive method).
    """
    if "pyrender" not in sys.modules:
        spec = importlib.util.find_spec("pyrender")
        if spec is None or not spec.submodule_search_locations:
            raise ImportError("pyrender is not installed: run `make setup` (pip package pyrender2)")
        package = types.ModuleType("pyrender")
        package.__path__ = list(spec.submodule_search_locations)
        package.__spec__ = spec
        package.__file__ = spec.origin
        package._roughlight_core_only = True
        sys.modules["pyrender"] = package
    for name in ("constants", "primitive", "shader_program", "platforms.osmesa"):
        importlib.import_module(f"pyrender.{name}")
    return sys.modules["pyrender"]


def _import_pyrender():
    """The whole pyrender package (Scene, OffscreenRenderer, ...), for the naive method."""
    module = sys.modules.get("pyrender")
    if module is not None and getattr(module, "_roughlight_core_only", False):
        del sys.modules["pyrender"]  # the real __init__ reuses the submodules already loaded
    return importlib.import_module("pyrender")


_import_pyrender_core()
from pyrender.constants import GLTF, SHADOW_TEX_SZ  # noqa: E402
from pyrender.platforms.osmesa import OSMesaPlatform  # noqa: E402
from pyrender.primitive import Primitive  # noqa: E402
from pyrender.shader_program import ShaderProgram  # noqa: E402
from pyrender.shader_program import ShaderProgramCache as ShaderProgramCache_  # noqa: E402

from . import geometry, shading, sweeps  # noqa: E402

__all__ = [
    "METHODS",
    "RenderSettings",
    "ShaderCache",
    "lattice_copies",
    "render_sweep",
    "measure_sweep",
]

SHADER_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "shaders")

#: What to do when OpenGL cannot start: the one message a sweep job ends with.
OSMESA_HELP = "could not create an OpenGL 3.3 core context with OSMesa (software rendering): " + _OSMESA_HELP

#: Pixel sampling patterns of the fast renderer (``render.sampling``).
SAMPLINGS = ("lattice", "grid")

#: Renderers selectable with ``render.method``.
METHODS = ("fast", "naive", "reference")


@dataclass(frozen=True)
class RenderSettings:
    """Knobs of the ``fast`` renderer that trade speed for accuracy.

    Attributes
    ----------
    pixels_per_period : int
        Sampling density: about this many pixels per period along each
        direction (each view's tile holds one period of the projected
        surface, about ``pixels_per_period ** 2`` pixels).
    sampling : str
        ``"lattice"``: the tile is a rotated square whose pixel centres sample
        the period on a rotated lattice (no row of samples along the facets'
        axis-aligned or diagonal edges); ``"grid"``: a plain square tile of
        ``pixels_per_period`` x ``pixels_per_period`` pixels.
    shadow_map_size : int
        Texels per period (along each direction) of the periodic shadow map.
    shadow_bias : float
        Height tolerance of the shadow test, as a fraction of the surface
        height (the receiver-plane test needs only rounding slack).
    max_framebuffer : int
        Largest framebuffer side in pixels; views beyond one framebuffer are
        drawn in further passes.
    jitter : (float, float)
        Sub-pixel shift of the camera (equivalently of the surface) in pixels,
        for measuring how a value moves when the pixels fall elsewhere on the
        surface (the thesis's "flashing lines"). The mean over the infinite
        periodic surface does not depend on it; a sampled mean does.
    """

    pixels_per_period: int = 24
    sampling: str = "lattice"
    shadow_map_size: int = 512
    shadow_bias: float = 1e-4
    max_framebuffer: int = 4096
    jitter: tuple = (0.0, 0.0)

    def __post_init__(self):
        if int(self.pixels_per_period) < 1:
            raise ValueError(f"render.pixels_per_period must be >= 1, got {self.pixels_per_period!r}")
        if int(self.shadow_map_size) < 1:
            raise ValueError(f"render.shadow_map_size must be >= 1, got {self.shadow_map_size!r}")
        if not (self.shadow_bias >= 0):
            raise ValueError(f"render.shadow_bias must be >= 0, got {self.shadow_bias!r}")
        if self.pixels_per_period > self.max_framebuffer // 2:
            raise ValueError("render.pixels_per_period exceeds the largest framebuffer")
        if self.sampling not in SAMPLINGS:
            raise ValueError(f"render.sampling must be one of {SAMPLINGS}, got {self.sampling!r}")

    def sampling_matrix(self) -> np.ndarray:
        """Integer 2x2 matrix from cell coordinates to window pixels (see ``periodic.vert``)."""
        return sampling_matrix(int(self.pixels_per_period), self.sampling)


def lattice_copies(shifts, margin: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Lattice offsets of the period copies whose projection reaches the unit cell.

    A copy at offset ``(k, l)`` occupies ``[k, k+1] x [l, l+1]`` in plan; the
    oblique projection moves a point at height ``z`` by ``-z * shear``, so the
    copy's projection is the unit square swept along the segment from
    ``(k, l)`` to ``(k, l) - d`` with ``d = H * shear``. It reaches the open
    unit cell iff that segment meets the open square ``(-1, 1)^2``.

    Parameters
    ----------
    shifts : (n, 2) array
        ``d`` for each of ``n`` views: the plan shift of the surface's top
        (height ``H``) relative to its base, in periods.
    margin : float
        Widen the cell by this much on every side (periods), for a sampling
        grid shifted by less than ``margin``.

    Returns
    -------
    view : (m,) int array
        Which view each copy belongs to (non-decreasing).
    offsets : (m, 2) int array
        ``(k, l)`` of each copy.
    """
    d = np.atleast_2d(np.asarray(shifts, float))
    eps = -float(margin) if margin else 1e-9
    # x: candidate columns k per view; the slab (-1, 1) in x bounds lambda
    pad = 1 + int(math.ceil(max(float(margin), 0.0)))
    k_lo = np.floor(np.minimum(0.0, d[:, 0])).astype(int) - pad
    k_hi = np.ceil(np.maximum(0.0, d[:, 0])).astype(int) + pad
    counts = k_hi - k_lo + 1
    view = np.repeat(np.arange(len(d)), counts)
    k = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts) + np.repeat(k_lo, counts)
    dx, dy = d[view, 0], d[view, 1]
    lam_lo = np.zeros(len(view))
    lam_hi = np.ones(len(view))
    moving = np.abs(dx) > 1e-15
    with np.errstate(divide="ignore", invalid="ignore"):
        a = (k - (1.0 - eps)) / dx
        b = (k + (1.0 - eps)) / dx
    lam_lo = np.where(moving, np.maximum(lam_lo, np.minimum(a, b)), lam_lo)
    lam_hi = np.where(moving, np.minimum(lam_hi, np.maximum(a, b)), lam_hi)
    lam_hi = np.where(~moving & (np.abs(k) >= 1.0 - eps), -1.0, lam_hi)
    keep = lam_lo <= lam_hi
    view, k, dy, lam_lo, lam_hi = view[keep], k[keep], dy[keep], lam_lo[keep], lam_hi[keep]
    # y: l - lam * dy must fall in (-1, 1) for some lam in [lam_lo, lam_hi]
    y_lo = np.minimum(lam_lo * dy, lam_hi * dy) - (1.0 - eps)
    y_hi = np.maximum(lam_lo * dy, lam_hi * dy) + (1.0 - eps)
    l_lo = np.ceil(y_lo).astype(int)
    l_hi = np.floor(y_hi).astype(int)
    counts = np.maximum(l_hi - l_lo + 1, 0)
    view_out = np.repeat(view, counts)
    l = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts) + np.repeat(l_lo, counts)
    k_out = np.repeat(k, counts)
    return view_out, np.stack([k_out, l], axis=1)


def sampling_matrix(pixels_per_period: int, sampling: str = "lattice") -> np.ndarray:
    """Integer matrix ``S`` mapping cell coordinates to window pixels.

    ``grid``: ``P * I``. ``lattice``: ``[[p, q], [-q, p]]`` with ``p^2 + q^2``
    within 10% of ``P^2`` (closest when none is), ``q / p`` closest to the golden ratio's conjugate
    0.618 (a slope far from every ratio of small integers), ``p + q`` odd (so
    that no pixel centre falls on a tile's edge) and ``gcd(p, q) = 1`` (so that
    every line along a lattice axis or diagonal meets one sample per period).
    """
    P = int(pixels_per_period)
    if sampling == "grid":
        return np.array([[P, 0], [0, P]])
    if sampling != "lattice":
        raise ValueError(f"render.sampling must be one of {SAMPLINGS}, got {sampling!r}")
    best = None
    for p in range(1, P + 2):
        for q in range(0, p + 1):
            if (p + q) % 2 == 0 or math.gcd(p, q) != 1:
                continue
            size_error = abs(p * p + q * q - P * P) / max(P * P, 1)
            # within 10% of the asked density, the slope matters most
            score = (max(size_error, 0.1), abs(q / p - 0.6180339887498949), size_error)
            if best is None or score < best[0]:
                best = (score, p, q)
    _, p, q = best
    return np.array([[p, q], [-q, p]])


def tile_layout(matrix: np.ndarray, n_views: int, max_framebuffer: int):
    """Slots for view tiles in one framebuffer, and which slot each pixel samples.

    Parameters
    ----------
    matrix : (2, 2) int array
        Cell coordinates to window pixels (:func:`sampling_matrix`).
    n_views : int
        Views wanted in one pass (fewer slots are returned if the largest
        framebuffer cannot hold them all).
    max_framebuffer : int
        Largest framebuffer side, pixels.

    Returns
    -------
    width, height : int
        Framebuffer size.
    slots : (m, 2) int array
        Integer cell offset ``K`` of each tile; tile ``k`` covers the window
        region ``matrix @ (K_k + [0, 1)^2)``, wholly inside the framebuffer.
    pixel_order : (m * N,) int array
        Flat pixel indices (row-major, bottom row first as OpenGL reads them)
        grouped by slot: ``pixel_order.reshape(m, N)`` lists slot ``k``'s
        ``N = |det matrix|`` pixels.
    """
    matrix = np.asarray(matrix, float)
    per_tile = int(round(abs(np.linalg.det(matrix))))
    reach = int(np.abs(matrix).sum(axis=0).max()) + 1
    side = int(math.ceil(math.sqrt(n_views * per_tile * 1.03))) + 2 * reach
    side = min(max(side, reach + 1), max_framebuffer)
    inverse = np.linalg.inv(matrix)
    while True:
        width = height = side
        corners = np.array([[0, 0], [width, 0], [0, height], [width, height]], float)
        pre = corners @ inverse.T
        lo = np.floor(pre.min(axis=0)).astype(int) - 1
        hi = np.ceil(pre.max(axis=0)).astype(int) + 1
        kx, ky = np.meshgrid(np.arange(lo[0], hi[0] + 1), np.arange(lo[1], hi[1] + 1), indexing="ij")
        cand = np.stack([kx.ravel(), ky.ravel()], axis=1)
        unit = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], float)
        pts = (cand[:, None, :] + unit[None]) @ matrix.T
        inside = np.all((pts[..., 0] >= 0) & (pts[..., 0] <= width) & (pts[..., 1] >= 0) & (pts[..., 1] <= height), axis=1)
        slots = cand[inside]
        if len(slots) >= n_views or side >= max_framebuffer:
            break
        side = min(max_framebuffer, int(side * 1.05) + 1)
    # keep the slots nearest the origin first (row-major in the window)
    centre = (slots + 0.5) @ matrix.T
    slots = slots[np.lexsort((centre[:, 0], np.floor(centre[:, 1] / reach)))][: max(n_views, 1)]
    # the pixel centres of the slot at K = 0; every slot is that set moved by matrix @ K
    box = np.abs(matrix).sum(axis=1).astype(int) + 1
    lo_px = np.minimum(0, matrix.sum(axis=1).clip(max=0)).astype(int) - 1
    ys, xs = np.mgrid[lo_px[1] - box[1]:box[1] + 1, lo_px[0] - box[0]:box[0] + 1]
    centres = np.stack([xs.ravel() + 0.5, ys.ravel() + 0.5], axis=1)
    home = np.all(np.floor(centres @ inverse.T) == 0, axis=1)
    base = np.stack([xs.ravel()[home], ys.ravel()[home]], axis=1)
    if len(base) != per_tile:
        raise RuntimeError("tile layout: a tile does not hold exactly |det S| pixel centres")
    shift = np.rint(slots @ matrix.T).astype(np.int64)
    px = base[None, :, :] + shift[:, None, :]
    pixel_order = (px[..., 1] * width + px[..., 0]).ravel()
    return width, height, slots, pixel_order


class ShaderCache:
    """pyrender shader programs keyed by shader files and defines, not by GL context."""

    def __init__(self, shader_dir: str = SHADER_DIR):
        self.shader_dir = shader_dir
        self._programs = {}

    def get_program(self, vertex_shader, fragment_shader, defines=None):
        defines = dict(defines or {})
        key = (vertex_shader, fragment_shader, tuple(sorted(defines.items())))
        program = self._programs.get(key)
        if program is None:
            program = ShaderProgram(
                vertex_shader=os.path.join(self.shader_dir, vertex_shader),
                fragment_shader=os.path.join(self.shader_dir, fragment_shader),
                defines=defines,
            )
            program._add_to_context()
            self._programs[key] = program
        return program

    def __len__(self):
        return len(self._programs)

    def clear(self):
        for program in self._programs.values():
            program.delete()
        self._programs = {}


class _Context:
    """One OSMesa context of a fixed framebuffer size, with its programs and shadow target."""

    def __init__(self, width: int, height: int, shadow_map_size: int):
        self.width, self.height = int(width), int(height)
        self.platform = OSMesaPlatform(self.width, self.height)
        try:
            self.platform.init_context()
            if not self.platform._context:
                raise RuntimeError("OSMesaCreateContextAttribs returned no context")
            self.platform.make_current()
        except Exception as exc:
            raise OSMesaUnavailable(f"{OSMESA_HELP} ({type(exc).__name__}: {exc})") from exc
        self.programs = ShaderCache()
        self.shadow_size = int(shadow_map_size)
        # periodic shadow map: a depth texture, one period of light-oblique coordinates
        self.shadow_tex = gl.glGenTextures(1)
        gl.glBindTexture(gl.GL_TEXTURE_2D, self.shadow_tex)
        gl.glTexImage2D(
            gl.GL_TEXTURE_2D, 0, gl.GL_DEPTH_COMPONENT24, self.shadow_size, self.shadow_size, 0,
            gl.GL_DEPTH_COMPONENT, gl.GL_FLOAT, None,
        )
        for pname, value in (
            (gl.GL_TEXTURE_MIN_FILTER, gl.GL_NEAREST),
            (gl.GL_TEXTURE_MAG_FILTER, gl.GL_NEAREST),
            (gl.GL_TEXTURE_WRAP_S, gl.GL_REPEAT),
            (gl.GL_TEXTURE_WRAP_T, gl.GL_REPEAT),
            (gl.GL_TEXTURE_COMPARE_MODE, gl.GL_NONE),
        ):
            gl.glTexParameteri(gl.GL_TEXTURE_2D, pname, value)
        self.shadow_fbo = gl.glGenFramebuffers(1)
        gl.glBindFramebuffer(gl.GL_FRAMEBUFFER, self.shadow_fbo)
        gl.glFramebufferTexture2D(
            gl.GL_FRAMEBUFFER, gl.GL_DEPTH_ATTACHMENT, gl.GL_TEXTURE_2D, self.shadow_tex, 0
        )
        gl.glDrawBuffer(gl.GL_NONE)
        gl.glReadBuffer(gl.GL_NONE)
        status = gl.glCheckFramebufferStatus(gl.GL_FRAMEBUFFER)
        gl.glBindFramebuffer(gl.GL_FRAMEBUFFER, 0)
        if status != gl.GL_FRAMEBUFFER_COMPLETE:
            raise RuntimeError(f"shadow framebuffer incomplete (status {status})")

    def delete(self):
        self.platform.make_current()
        self.programs.clear()
        gl.glDeleteFramebuffers(1, [self.shadow_fbo])
        gl.glDeleteTextures([self.shadow_tex])
        self.platform.delete_context()


_CONTEXTS: dict = {}


def _context(width: int, height: int, shadow_map_size: int) -> _Context:
    key = (width, height, shadow_map_size)
    ctx = _CONTEXTS.get(key)
    if ctx is None:
        # one framebuffer size at a time: OSMesa buffers are fixed at creation
        for other in list(_CONTEXTS.values()):
            other.delete()
        _CONTEXTS.clear()
        ctx = _CONTEXTS[key] = _Context(width, height, shadow_map_size)
    ctx.platform.make_current()
    return ctx


def _primitive(truncation: float, aspect: float, poses: np.ndarray):
    tris, normals, _ = geometry.period_triangles(truncation, aspect)
    return Primitive(
        positions=tris.reshape(-1, 3).astype(np.float32),
        normals=np.repeat(normals, 3, axis=0).astype(np.float32),
        mode=GLTF.TRIANGLES,
        poses=poses,
    )


def _draw(ctx: _Context, primitive, program):
    primitive._add_to_context()
    try:
        primitive._bind()
        gl.glDrawArraysInstanced(gl.GL_TRIANGLES, 0, len(primitive.positions), len(primitive.poses))
        primitive._unbind()
    finally:
        primitive.delete()


def _copy_poses(copies: np.ndarray, shear, view, tile) -> np.ndarray:
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


def _begin_pass(framebuffer, width: int, height: int, clear_bits) -> None:
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
    gl.glClear(clear_bits)


def _shadow_pass(ctx: _Context, truncation, aspect, light_dir, depth_scale):
    height = geometry.surface_height(truncation, aspect)
    shear = light_dir[:2] / light_dir[2]
    _, copies = lattice_copies(height * shear[None, :])
    poses = _copy_poses(copies, shear, light_dir, np.zeros(2))
    _begin_pass(ctx.shadow_fbo, ctx.shadow_size, ctx.shadow_size, gl.GL_DEPTH_BUFFER_BIT)
    primitive = _primitive(truncation, aspect, poses)
    program = ctx.programs.get_program(
        "periodic.vert", "periodic_depth.frag", defines={"NORMAL_LOC": 1, "INST_M_LOC": 2}
    )
    program._bind()
    program.set_uniform("depth_scale", float(depth_scale))
    program.set_uniform("sampling", np.eye(2, dtype=np.float32) * ctx.shadow_size)
    program.set_uniform("ndc_scale", np.full(2, 2.0 / ctx.shadow_size, np.float32))
    program.set_uniform("surface_shift", np.zeros(2, np.float32))
    _draw(ctx, primitive, program)
    program._unbind()
    gl.glBindFramebuffer(gl.GL_FRAMEBUFFER, 0)


_LAYOUTS: dict = {}


def _cached_layout(matrix: np.ndarray, n_views: int, max_framebuffer: int):
    key = (tuple(np.asarray(matrix).ravel()), n_views, max_framebuffer)
    if key not in _LAYOUTS:
        _LAYOUTS.clear()
        _LAYOUTS[key] = tile_layout(matrix, n_views, max_framebuffer)
    return _LAYOUTS[key]


def render_sweep(
    truncation: float,
    aspect: float,
    incidence: float,
    azimuth,
    elevation,
    lighting: shading.Lighting | None = None,
    settings: RenderSettings | None = None,
) -> dict:
    """Render one sweep with the ``fast`` method (pyrender over OSMesa).

    Parameters
    ----------
    truncation, aspect : float
        The surface (see :mod:`roughlight.geometry`).
    incidence : float
        Light elevation above the surface plane, degrees in [0, 90]; the light
        comes from azimuth 0.
    azimuth, elevation : (n_views,) arrays
        Views, degrees: azimuth in [0, 180), elevation in [0, 180].
    lighting : Lighting
    settings : RenderSettings

    Returns
    -------
    dict
        ``diffuse``, ``specular``, ``total``: (n_views,) means of the 8-bit
        pixel values of the view's tile (0-255); ``coverage``: (n_views,)
        fraction of the tile's pixels showing the surface; ``seconds``: wall
        time of the sweep.
    """
    start = time.perf_counter()
    lighting = lighting or shading.Lighting()
    settings = settings or RenderSettings()
    truncation, aspect = geometry.validate_surface(truncation, aspect)
    incidence = shading.check_incidence(incidence)
    azimuth = np.atleast_1d(np.asarray(azimuth, float))
    elevation = np.atleast_1d(np.asarray(elevation, float))
    if azimuth.shape != elevation.shape:
        raise ValueError("azimuth and elevation must have the same shape")
    n = azimuth.size
    out = {key: np.zeros(n) for key in ("diffuse", "specular", "total", "coverage")}
    todo = np.flatnonzero(~sweeps.is_grazing(elevation))
    if todo.size == 0:
        out["seconds"] = time.perf_counter() - start
        return out

    matrix = settings.sampling_matrix()
    width, height_px, slots, pixel_order = _cached_layout(matrix, todo.size, int(settings.max_framebuffer))
    per_tile = len(pixel_order) // len(slots)
    # a camera shift by `jitter` pixels is the surface moved the other way, in cell units
    shift = -np.linalg.solve(matrix.astype(float), np.asarray(settings.jitter, float))
    ctx = _context(width, height_px, int(settings.shadow_map_size))
    height = geometry.surface_height(truncation, aspect)
    depth_scale = 1.0 / max(height * 1.001, 1e-6)
    light_dir = shading.light_direction(incidence)

    shadow_mode = 0
    if lighting.shadows and height > 0:
        if light_dir[2] < 1e-9:
            shadow_mode = 2
        else:
            shadow_mode = 1
            _shadow_pass(ctx, truncation, aspect, light_dir, depth_scale)

    program = ctx.programs.get_program(
        "periodic.vert", "periodic.frag", defines={"NORMAL_LOC": 1, "INST_M_LOC": 2}
    )
    views = shading.view_direction(elevation[todo], azimuth[todo])
    shears = views[:, :2] / views[:, 2:3]
    per_pass = len(slots)
    for first in range(0, todo.size, per_pass):
        idx = np.arange(first, min(first + per_pass, todo.size))
        owner, copies = lattice_copies(height * shears[idx], margin=float(np.abs(shift).max()))
        poses = _copy_poses(copies, shears[idx][owner], views[idx][owner], slots[idx - first][owner])

        _begin_pass(0, ctx.width, ctx.height, gl.GL_COLOR_BUFFER_BIT | gl.GL_DEPTH_BUFFER_BIT)
        program._bind()
        _set_lighting_uniforms(program, lighting, light_dir, shadow_mode, ctx, settings, depth_scale, height)
        program.set_uniform("sampling", matrix.astype(np.float32))
        program.set_uniform("ndc_scale", np.array([2.0 / ctx.width, 2.0 / ctx.height], np.float32))
        program.set_uniform("surface_shift", shift.astype(np.float32))
        gl.glActiveTexture(gl.GL_TEXTURE0)
        gl.glBindTexture(gl.GL_TEXTURE_2D, ctx.shadow_tex)
        program.set_uniform("shadow_map", 0)
        _draw(ctx, _primitive(truncation, aspect, poses), program)
        program._unbind()
        gl.glFinish()

        raw = gl.glReadPixels(0, 0, ctx.width, ctx.height, gl.GL_RGBA, gl.GL_UNSIGNED_BYTE)
        image = np.frombuffer(raw, np.uint8).reshape(-1, 4)
        tiles_px = image[pixel_order[: idx.size * per_tile]].reshape(idx.size, per_tile, 4)
        means = tiles_px.mean(axis=1, dtype=np.float64)
        target = todo[idx]
        out["diffuse"][target] = means[:, 0]
        out["specular"][target] = means[:, 1]
        out["total"][target] = means[:, 2]
        out["coverage"][target] = means[:, 3] / 255.0
    out["seconds"] = time.perf_counter() - start
    return out


def _set_lighting_uniforms(program, lighting, light_dir, shadow_mode, ctx, settings, depth_scale, height):
    program.set_uniform("light_dir", np.asarray(light_dir, np.float32))
    program.set_uniform("light", float(lighting.light) / 255.0)
    program.set_uniform("ambient_term", float(lighting.ambient_reflectance * lighting.ambient))
    program.set_uniform("diffuse_reflectance", float(lighting.diffuse_reflectance))
    program.set_uniform("specular_reflectance", float(lighting.specular_reflectance))
    program.set_uniform("shininess", float(lighting.shininess))
    program.set_uniform("specular_model", int(shading.SPECULAR_MODELS.index(lighting.specular_model)))
    program.set_uniform("shadow_mode", int(shadow_mode))
    program.set_uniform("shadow_size", int(ctx.shadow_size))
    lz = max(float(light_dir[2]), 1e-12)
    program.set_uniform("light_shear", np.array([light_dir[0] / lz, light_dir[1] / lz], np.float32))
    program.set_uniform("depth_scale", float(depth_scale))
    program.set_uniform("shadow_bias", float(settings.shadow_bias * max(height, 1e-6)))


#: Shading of the naive method's faceted mesh: ``flat`` (true face normals, the
#: study's), ``phong`` (averaged vertex normals interpolated per fragment),
#: ``gouraud`` (the equation at the vertices with averaged normals, interpolated).
SHADINGS = ("flat", "phong", "gouraud")


class _PyrenderShaders(ShaderProgramCache_):
    """pyrender's program cache, as it comes (keyed on the GL context), with the
    study's equation in place of its PBR shaders (``naive.vert``, ``naive.frag``)."""

    shading = "flat"

    def get_program(self, vertex_shader, fragment_shader, geometry_shader=None, defines=None):
        if fragment_shader == "mesh.frag":
            vertex_shader = os.path.join(SHADER_DIR, "naive.vert")
            fragment_shader = os.path.join(SHADER_DIR, "naive.frag")
            if self.shading == "gouraud":
                defines = {**(defines or {}), "GOURAUD": 1}
        return super().get_program(vertex_shader, fragment_shader, geometry_shader, defines)


def _up_vector(view: np.ndarray) -> np.ndarray:
    """Image 'up': the direction of increasing elevation (keeps the horizon level)."""
    e = math.asin(max(-1.0, min(1.0, view[2])))
    phi = math.atan2(view[1], view[0]) if abs(math.cos(e)) > 1e-12 else 0.0
    if math.cos(e) < 0:  # beyond the zenith the orbit's azimuth is phi + 180
        phi += math.pi
    return np.array([-math.sin(e) * math.cos(phi), -math.sin(e) * math.sin(phi), math.cos(e)])


def _look_pose(direction: np.ndarray, up: np.ndarray, distance: float) -> np.ndarray:
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


def patch_mesh(truncation: float, aspect: float, periods: int, averaged_normals: bool = False):
    """A finite ``periods`` x ``periods`` patch of the surface, centred on the origin (trimesh).

    With ``averaged_normals`` the vertices shared by facets are merged and each
    carries the plain average of the normals of the faces around it (the
    shading notes' Gouraud construction); otherwise every triangle keeps its
    own vertices and its true face normal.
    """
    import trimesh

    tile = geometry.period_mesh(truncation, aspect)
    offsets = np.arange(periods) - periods / 2.0
    copies = []
    for dx in offsets:
        for dy in offsets:
            copy = tile.copy()
            copy.apply_translation([dx, dy, 0.0])
            copies.append(copy)
    mesh = trimesh.util.concatenate(copies)
    if averaged_normals:
        mesh = trimesh.Trimesh(vertices=mesh.vertices, faces=mesh.faces, process=False)
        mesh.merge_vertices(digits_vertex=9)
        sums = np.zeros((len(mesh.vertices), 3))
        for corner in range(3):
            np.add.at(sums, mesh.faces[:, corner], mesh.face_normals)
        mesh.vertex_normals = sums / np.linalg.norm(sums, axis=1, keepdims=True)
    return mesh


class _NaiveScene:
    """The thesis's set-up in pyrender as it comes: a finite patch, an orthographic
    camera orbiting it, one DirectionalLight whose shadow map pyrender redraws on
    every render."""

    def __init__(self, truncation, aspect, incidence, lighting, size, periods, view_periods, shading_model="flat"):
        if shading_model not in SHADINGS:
            raise ValueError(f"shading_model must be one of {SHADINGS}, got {shading_model!r}")
        pyrender = self.pyrender = _import_pyrender()
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
        mesh = patch_mesh(truncation, aspect, periods, averaged_normals=smooth)
        self.scene.add(pyrender.Mesh.from_trimesh(mesh, material=material, smooth=smooth))
        self.shading_model = shading_model
        light_dir = shading.light_direction(incidence)
        light = pyrender.DirectionalLight(color=np.ones(3), intensity=float(lighting.light) / 255.0)
        up = np.array([0.0, 0.0, 1.0]) if abs(light_dir[2]) < 0.99 else np.array([1.0, 0.0, 0.0])
        self.scene.add(light, pose=_look_pose(light_dir, up, 10.0))
        half_width = view_periods / 2.0
        camera = pyrender.OrthographicCamera(
            xmag=half_width, ymag=half_width * self.size[1] / self.size[0], znear=0.05, zfar=4.0 * periods + 20.0
        )
        self.distance = 2.0 * periods + 10.0
        self.camera_node = self.scene.add(camera, pose=np.eye(4))
        self.shadows = bool(lighting.shadows) and not geometry.is_plate(truncation, aspect)

    def render(self, renderer, view, jitter=(0.0, 0.0)):
        pyrender = self.pyrender
        pose = _look_pose(view, _up_vector(view), self.distance)
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


_NAIVE_RENDERERS: dict = {}

#: The naive method as it comes: a 400 x 300 window spanning 40 periods (10 pixels a period).
NAIVE_WINDOW = (400, 300)
NAIVE_VIEW_PERIODS = 40.0
#: pyrender's directional shadow map, texels a side (``pyrender.constants.SHADOW_TEX_SZ``).
NAIVE_SHADOW_MAP = SHADOW_TEX_SZ


def recorded_settings(method: str, settings=None) -> dict:
    """How a method sampled the surface, as the study table and the benchmark record it.

    Returns
    -------
    dict: ``pixels_per_period`` (int), ``sampling`` (``lattice`` | ``grid`` for
    fast, ``window`` for naive, ``exact`` for the reference) and
    ``shadow_map_size`` (texels a side; 0 for the reference, which needs none).
    """
    if method == "fast":
        settings = settings or RenderSettings()
        return {"pixels_per_period": int(settings.pixels_per_period), "sampling": settings.sampling,
                "shadow_map_size": int(settings.shadow_map_size)}
    if method == "naive":
        return {"pixels_per_period": int(round(NAIVE_WINDOW[0] / NAIVE_VIEW_PERIODS)), "sampling": "window",
                "shadow_map_size": NAIVE_SHADOW_MAP}
    if method == "reference":
        return {"pixels_per_period": 0, "sampling": "exact", "shadow_map_size": 0}
    raise ValueError(f"render.method must be one of {METHODS}, got {method!r}")


def _naive_renderer(size):
    renderer = _NAIVE_RENDERERS.get(size)
    if renderer is None:
        for other in list(_NAIVE_RENDERERS.values()):
            other.delete()
        _NAIVE_RENDERERS.clear()
        # free the fast method's context too: one OSMesa context at a time
        for ctx in list(_CONTEXTS.values()):
            ctx.delete()
        _CONTEXTS.clear()
        renderer = _import_pyrender().OffscreenRenderer(*size)
        renderer._renderer._program_cache = _PyrenderShaders()
        _NAIVE_RENDERERS[size] = renderer
    return renderer


def naive_sweep(truncation, aspect, incidence, azimuth, elevation, lighting=None, window=NAIVE_WINDOW,
                capture=40, view_periods=NAIVE_VIEW_PERIODS, lowest_elevation=10.0, jitter=(0.0, 0.0), shading_model="flat") -> dict:
    """The thesis's procedure with pyrender as it comes: one render per view.

    Each view renders a ``window`` (400 x 300 pixels, as the thesis) of a finite
    patch through an orthographic camera, with pyrender redrawing its 2048^2
    directional shadow map and (its program cache being keyed on OSMesa's
    ever-new context) recompiling its shaders on every render; the value is
    the mean of the central ``capture`` x ``capture`` pixels (the thesis's
    40 x 40). The window spans ``view_periods`` periods across (10 pixels a
    period by default), the patch enough periods to fill the capture window
    down to ``lowest_elevation`` degrees (10 by default). ``coverage`` is the
    fraction of capture pixels showing the surface (from the depth buffer).
    ``jitter`` shifts the camera by that many pixels (x, y) in its image plane.
    ``shading_model`` is one of :data:`SHADINGS`: ``flat`` is the study's
    (true face normals); ``phong`` and ``gouraud`` use averaged vertex
    normals, to measure how wrong they make each component.

    Returns the dict of :func:`render_sweep`.
    """
    start = time.perf_counter()
    lighting = lighting or shading.Lighting()
    truncation, aspect = geometry.validate_surface(truncation, aspect)
    incidence = shading.check_incidence(incidence)
    azimuth = np.atleast_1d(np.asarray(azimuth, float))
    elevation = np.atleast_1d(np.asarray(elevation, float))
    periods = _patch_periods(view_periods * capture / window[0], lowest_elevation)
    # the scene first: it checks the shading model before any OpenGL context is made
    scene = _NaiveScene(truncation, aspect, incidence, lighting, window, periods, view_periods, shading_model)
    renderer = _naive_renderer(tuple(window))
    views = shading.view_direction(elevation, azimuth)
    out = {key: np.zeros(azimuth.size) for key in ("diffuse", "specular", "total", "coverage")}
    w, h = window
    x0, y0 = (w - capture) // 2, (h - capture) // 2
    box = np.s_[y0:y0 + capture, x0:x0 + capture]
    for k in np.flatnonzero(~sweeps.is_grazing(elevation)):
        color, depth = scene.render(renderer, views[k], jitter)
        means = color[box].reshape(-1, color.shape[-1]).mean(axis=0, dtype=np.float64)
        out["diffuse"][k], out["specular"][k], out["total"][k] = means[:3]
        out["coverage"][k] = float(np.mean(depth[box] > 0))
    out["seconds"] = time.perf_counter() - start
    return out


def render_picture(truncation, aspect, incidence, elevation, azimuth, lighting=None, size=(400, 300),
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
    scene = _NaiveScene(truncation, aspect, shading.check_incidence(incidence), lighting, size, min(patch, 201), periods,
                        shading_model)
    renderer = _naive_renderer(tuple(size))
    view = shading.view_direction(float(elevation), float(azimuth))
    color, _ = scene.render(renderer, view)
    channel = {"diffuse": 0, "specular": 1, "total": 2}[component]
    return np.repeat(color[..., channel : channel + 1], 3, axis=2).copy()


def measure_sweep(method: str, truncation, aspect, incidence, azimuth, elevation, lighting=None, settings=None) -> dict:
    """Measure a sweep with the named method (``render.method``).

    ``fast`` renders with :func:`render_sweep`; ``naive`` with
    :func:`naive_sweep` (the thesis's procedure, one render per view);
    ``reference`` computes the
    same quantity exactly by polygon clipping (:mod:`roughlight.reference`).
    Returns the dict of :func:`render_sweep`.
    """
    if method == "fast":
        return render_sweep(truncation, aspect, incidence, azimuth, elevation, lighting, settings)
    if method == "naive":
        return naive_sweep(truncation, aspect, incidence, azimuth, elevation, lighting)
    if method == "reference":
        from . import reference

        start = time.perf_counter()
        out = reference.reference_sweep(truncation, aspect, incidence, azimuth, elevation, lighting or shading.Lighting())
        out = {key: np.asarray(value, float) for key, value in out.items()}
        out["seconds"] = time.perf_counter() - start
        return out
    raise ValueError(f"render.method must be one of {METHODS}, got {method!r}")
