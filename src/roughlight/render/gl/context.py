"""OpenGL for the renderers: the headless platform, the parts of pyrender they use, shader programs, contexts.

This is the one module that loads OpenGL. It takes PyOpenGL's platform from
``PYOPENGL_PLATFORM`` (:data:`PLATFORMS`: ``osmesa``, the default, or ``egl``,
:mod:`roughlight.render.gl.egl`; a workflow job sets it from ``render.platform``
before anything loads OpenGL), turns PyOpenGL's bare import errors into one
message that says what to install, makes every context (the GL methods' and
pyrender's for the naive method, :func:`offscreen_renderer`) on that platform,
refuses one older than OpenGL 4.3 (:func:`check_version`), and loads only the
parts of pyrender the fast method needs (see :func:`import_pyrender_core`).
The GL methods import it (the fast renderer, :mod:`roughlight.render.fast`; the
naive procedure, :mod:`roughlight.render.naive.procedure`; the implicit shader,
:mod:`roughlight.render.implicit.shader`), and only when they render (the registry,
:mod:`roughlight.render.methods`, imports a method on first use), so measuring with the
exact reference or analysing a study table never loads OpenGL.

pyrender's program cache keys programs on the GL context object, which OSMesa
hands back anew on every call (every render would recompile):
:class:`ShaderCache` keys them on the shader files and defines only.
"""

from __future__ import annotations

import os

#: The headless platforms (``render.platform``).
PLATFORMS = ("osmesa", "egl")
PLATFORM = os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")
if PLATFORM not in PLATFORMS:
    raise ValueError(f"PYOPENGL_PLATFORM (render.platform) must be one of {PLATFORMS}, got {PLATFORM!r}")

import importlib  # noqa: E402
import importlib.util  # noqa: E402
import re  # noqa: E402
import sys  # noqa: E402
import types  # noqa: E402

from . import egl  # noqa: E402
from .osmesa import HELP as _OSMESA_HELP  # noqa: E402
from .osmesa import OSMesaUnavailable, check_osmesa  # noqa: E402

#: The error a platform that cannot start raises: the message says what to install.
Unavailable = egl.EGLUnavailable if PLATFORM == "egl" else OSMesaUnavailable
_HELP = egl.HELP if PLATFORM == "egl" else _OSMESA_HELP

try:
    from OpenGL import GL as gl  # noqa: E402
except (ImportError, AttributeError, OSError) as _exc:  # PyOpenGL's own errors do not say what to do
    if PLATFORM == "osmesa":
        check_osmesa()  # raises OSMesaUnavailable naming the missing or broken library
    else:
        egl.check_egl()
    raise Unavailable(f"PyOpenGL could not load ({type(_exc).__name__}: {_exc}): {_HELP}") from _exc


def import_pyrender_core():
    """Load the parts of pyrender the fast method uses, without pyrender's package ``__init__``.

    ``import pyrender`` imports its viewer (pyglet), its trimesh-based Mesh and
    Scene, and through trimesh scipy and networkx: about 1.7 s, paid again by
    every sweep job (each is a fresh process). The fast method needs only the
    OSMesa platform, Primitive (vertex buffers with instancing) and the shader
    programs, whose modules import nothing heavy. When pyrender is not yet
    imported, an empty package module stands in for its ``__init__`` so that
    those submodules load alone; :func:`import_pyrender` swaps in the real
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


def import_pyrender():
    """The whole pyrender package (Scene, OffscreenRenderer, ...), for the naive method."""
    module = sys.modules.get("pyrender")
    if module is not None and getattr(module, "_roughlight_core_only", False):
        del sys.modules["pyrender"]  # the real __init__ reuses the submodules already loaded
    return importlib.import_module("pyrender")


import_pyrender_core()
from pyrender.constants import GLTF, SHADOW_TEX_SZ  # noqa: E402
from pyrender.platforms.osmesa import OSMesaPlatform  # noqa: E402
from pyrender.primitive import Primitive  # noqa: E402
from pyrender.shader_program import ShaderProgram  # noqa: E402
from pyrender.shader_program import ShaderProgramCache as PyrenderShaderCache  # noqa: E402

__all__ = [
    "gl",
    "GLTF",
    "SHADOW_TEX_SZ",
    "Primitive",
    "PyrenderShaderCache",
    "SHADER_DIR",
    "OSMESA_HELP",
    "ShaderCache",
    "set_uniforms",
    "set_material_uniforms",
    "Context",
    "context",
    "release_contexts",
    "PLATFORMS",
    "PLATFORM",
    "Unavailable",
    "REQUIRED_VERSION",
    "check_version",
    "new_platform",
    "start_platform",
    "renderer",
    "describe",
    "offscreen_renderer",
    "import_pyrender",
]

SHADER_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "shaders")  # render/shaders

#: What to do when OpenGL cannot start: the one message a sweep job ends with.
OSMESA_HELP = "could not create an OpenGL core context with OSMesa (software rendering): " + _OSMESA_HELP
_START_HELP = OSMESA_HELP if PLATFORM == "osmesa" else egl.HELP
#: The oldest OpenGL the renderers are run on. The random tiles' counting pass needed it (shader storage buffers
#: with ``atomicAdd``) until it moved to the CPU (:mod:`roughlight.render.fast.raster`); the shaders left ask for
#: 3.3 with ``GL_ARB_shading_language_420pack``, but no older context has been tried.
REQUIRED_VERSION = (4, 3)

#: The renderer and OpenGL version of this process's contexts (:func:`renderer`), once one is made.
_DESCRIBED: dict = {}


def check_version(version: str, renderer: str = "") -> tuple[int, int]:
    """The (major, minor) of a ``GL_VERSION`` string (``"4.5 (Core Profile) Mesa 22.3.6"``), refused below
    :data:`REQUIRED_VERSION` with a message naming what is missing."""
    found = re.match(r"\s*(\d+)\.(\d+)", version or "")
    if not found:
        raise Unavailable(f"OpenGL reported no version ({version!r}) on {renderer or 'this platform'}: {_HELP}")
    major_minor = (int(found.group(1)), int(found.group(2)))
    if major_minor < REQUIRED_VERSION:
        raise Unavailable(
            f"OpenGL {version} on {renderer or PLATFORM} is older than 4.3 core, the oldest the renderers are run "
            f"on: use a newer driver or Mesa, or render.platform {'osmesa' if PLATFORM == 'egl' else 'egl'}"
        )
    return major_minor


def new_platform(width: int, height: int):
    """A platform (pyrender's interface) of ``width`` x ``height`` pixels on :data:`PLATFORM`, not yet started."""
    if PLATFORM == "egl":
        return egl.EGLPlatform(width, height)
    return OSMesaPlatform(width, height)


def start_platform(platform) -> None:
    """Make ``platform``'s context, make it current and check its OpenGL version (:func:`check_version`)."""
    try:
        platform.init_context()
        if PLATFORM == "osmesa" and not platform._context:
            raise RuntimeError("OSMesaCreateContextAttribs returned no context")
        platform.make_current()
    except Unavailable:
        raise
    except Exception as exc:
        raise Unavailable(f"{_START_HELP} ({type(exc).__name__}: {exc})") from exc
    if not _DESCRIBED:
        name, version = (gl.glGetString(key).decode() for key in (gl.GL_RENDERER, gl.GL_VERSION))
        check_version(version, name)
        _DESCRIBED.update(renderer=name, version=version, platform=PLATFORM)


def renderer() -> str:
    """What this process renders on, for the study's provenance: ``"llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5
    (Core Profile) Mesa 22.3.6, osmesa"``; empty before any context is made."""
    if not _DESCRIBED:
        return ""
    return f"{_DESCRIBED['renderer']}, OpenGL {_DESCRIBED['version']}, {_DESCRIBED['platform']}"


def describe() -> str:
    """:func:`renderer`, after making (and deleting) a context of one pixel when this process has made none yet:
    what a sweep would be drawn on, known before drawing it (the sweep store's key)."""
    if not _DESCRIBED:
        platform = new_platform(1, 1)
        start_platform(platform)
        platform.delete_context()
    return renderer()


def offscreen_renderer(width: int, height: int):
    """pyrender's OffscreenRenderer (the naive method's) on this process's platform (:func:`new_platform`):
    drawing into framebuffer 0 as OSMesa's, never pyrender's multisampled buffer, and on EGL never terminating
    the display other contexts share."""
    pyrender = import_pyrender()

    class OffscreenRenderer(pyrender.OffscreenRenderer):
        def _create(self):
            self._platform = new_platform(self.viewport_width, self.viewport_height)
            start_platform(self._platform)
            self._renderer = pyrender.Renderer(self.viewport_width, self.viewport_height)

    return OffscreenRenderer(int(width), int(height))


_INCLUDE = re.compile(r'^#include\s+"([A-Za-z0-9_.]+)"\s*$', re.MULTILINE)


class Program(ShaderProgram):
    """pyrender's shader program with one more directive: ``#include "file"`` (a file of the same
    directory, its defines applied as to the includer), so that two stages can share GLSL functions."""

    def _load(self, shader_filename):
        folder = os.path.dirname(shader_filename)
        text = ShaderProgram._load(self, shader_filename)
        return _INCLUDE.sub(lambda match: self._load(os.path.join(folder, match.group(1))), text)


class ShaderCache:
    """pyrender shader programs keyed by shader files and defines, not by GL context.

    Shader files may ``#include "file"`` another file of the shader directory.
    """

    def __init__(self, shader_dir: str = SHADER_DIR):
        self.shader_dir = shader_dir
        self._programs = {}

    def get_program(self, vertex_shader, fragment_shader, defines=None):
        defines = dict(defines or {})
        key = (vertex_shader, fragment_shader, tuple(sorted(defines.items())))
        program = self._programs.get(key)
        if program is None:
            program = Program(
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


def set_uniforms(program, uniforms: dict) -> None:
    """Set each ``name: value`` of ``uniforms`` on the bound ``program`` (ints as int, floats as float,
    float32 arrays as vectors or matrices)."""
    for name, value in uniforms.items():
        program.set_uniform(name, value)


def set_material_uniforms(program, lighting, light_dir) -> None:
    """The lighting equation's uniforms (:func:`roughlight.render.shading.material_uniforms`) on the bound ``program``."""
    from ..shading import material_uniforms

    set_uniforms(program, material_uniforms(lighting, light_dir))


class Context:
    """One context (OSMesa's or EGL's, :data:`PLATFORM`) of a fixed framebuffer size, with its programs and, once
    the fast renderer asks for it,
    its periodic shadow map (:meth:`shadow_map`).

    Attributes
    ----------
    width, height : int
        The framebuffer, pixels.
    programs : ShaderCache
    shadow_size : int
        Texels a side of the shadow map, built only by :meth:`shadow_map`: the fast renderer's drawing pass
        (:mod:`roughlight.render.fast.passes`). The implicit shader's and the random tiles' counting contexts
        never build one.
    """

    def __init__(self, width: int, height: int, shadow_map_size: int):
        self.width, self.height = int(width), int(height)
        self.platform = new_platform(self.width, self.height)
        start_platform(self.platform)
        self.programs = ShaderCache()
        self.shadow_size = int(shadow_map_size)
        self._shadow = None  # (framebuffer, depth texture), built by shadow_map()

    def shadow_map(self) -> tuple:
        """The periodic shadow map, built on the first call: ``(framebuffer, texture)`` GL names of a depth
        texture of ``shadow_size`` texels a side (nearest filtering, wrapped: one period of light-oblique
        coordinates) and the framebuffer that draws into it. Call with the context current."""
        if self._shadow is None:
            tex = gl.glGenTextures(1)
            gl.glBindTexture(gl.GL_TEXTURE_2D, tex)
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
            fbo = gl.glGenFramebuffers(1)
            gl.glBindFramebuffer(gl.GL_FRAMEBUFFER, fbo)
            gl.glFramebufferTexture2D(gl.GL_FRAMEBUFFER, gl.GL_DEPTH_ATTACHMENT, gl.GL_TEXTURE_2D, tex, 0)
            gl.glDrawBuffer(gl.GL_NONE)
            gl.glReadBuffer(gl.GL_NONE)
            status = gl.glCheckFramebufferStatus(gl.GL_FRAMEBUFFER)
            gl.glBindFramebuffer(gl.GL_FRAMEBUFFER, 0)
            self._shadow = (fbo, tex)
            if status != gl.GL_FRAMEBUFFER_COMPLETE:
                raise RuntimeError(f"shadow framebuffer incomplete (status {status})")
        return self._shadow

    def delete(self):
        self.platform.make_current()
        self.programs.clear()
        if self._shadow is not None:
            gl.glDeleteFramebuffers(1, [self._shadow[0]])
            gl.glDeleteTextures([self._shadow[1]])
            self._shadow = None
        self.platform.delete_context()


#: The GL methods' live contexts, by (width, height, shadow map size): one at a time.
CONTEXTS: dict = {}


def context(width: int, height: int, shadow_map_size: int) -> Context:
    """An OSMesa context whose framebuffer holds at least ``width`` x ``height`` pixels, whose shadow map (built
    when the fast renderer first draws in it, :meth:`Context.shadow_map`) is ``shadow_map_size`` texels a side:
    the live one when it is large enough (callers draw into their own
    viewport of it), else a new one as large as both (framebuffer 0 is fixed at creation; one at a time).
    A framebuffer's size is not neutral: llvmpipe clips a draw to the framebuffer, so the fast method starts
    every sweep with none (:func:`release_contexts`), as a fresh process does."""
    for (w, h, size), ctx in CONTEXTS.items():
        if size == shadow_map_size and w >= width and h >= height:
            ctx.platform.make_current()
            return ctx
    for (w, h, _), other in list(CONTEXTS.items()):
        width, height = max(width, w), max(height, h)
        other.delete()
    CONTEXTS.clear()
    ctx = CONTEXTS[(width, height, shadow_map_size)] = Context(width, height, shadow_map_size)
    ctx.platform.make_current()
    return ctx


def release_contexts() -> None:
    """Delete the GL methods' contexts (before the naive method makes its own: one at a time)."""
    for ctx in list(CONTEXTS.values()):
        ctx.delete()
    CONTEXTS.clear()
