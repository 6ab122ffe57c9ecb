"""EGL for the renderers: a headless OpenGL context on a GPU, or on Mesa's software device, beside OSMesa.

``render.platform: egl`` renders through EGL's device route (``EGL_EXT_device_enumeration``), the way GPU nodes
without a display or libOSMesa offer OpenGL: NVIDIA's driver ships it, and Mesa exposes its software renderer
(llvmpipe) as a device too. Everything here talks to ``libEGL.so.1`` through ctypes, so the preflight
(:func:`check_egl`) loads no OpenGL, and PyOpenGL (``PYOPENGL_PLATFORM=egl``) only issues the GL calls.

Three rules the renderers rely on:

- the device: an explicit index (``render.egl_device``), else the first hardware device, else Mesa's software
  device with a line in the log (:func:`choose_device`);
- a display is initialised once a process and never terminated: every context shares it, and
  ``eglTerminate`` would destroy the other contexts (pyrender's EGL platform does, which killed one method's
  context when another's was deleted);
- framebuffer 0 is a pbuffer surface of the context's size, as OSMesa's buffer is: the fast renderer and pyrender
  (whose multisampled offscreen buffer the naive method does not use) draw and read it the same way on both
  platforms, so their values are the same to the bit on llvmpipe.
"""

from __future__ import annotations

import ctypes
import logging
import os
from dataclasses import dataclass, field

__all__ = ["HELP", "EGLUnavailable", "Device", "check_egl", "devices", "device_index", "choose_device", "EGLPlatform"]

#: What to do, the end of every message.
HELP = (
    "install Debian's libegl1, libegl-mesa0 and libgl1-mesa-dri (`make setup` does), or on a GPU node the "
    "driver's EGL (NVIDIA's libEGL_nvidia), or set render.platform: osmesa; rerun snakemake, sweeps already "
    "written are kept"
)

#: The EGL library's names, tried in order.
LIBRARY_NAMES = ("libEGL.so.1", "libEGL.so")
#: Entry points of libEGL itself, and extension functions it must hand out.
REQUIRED_SYMBOLS = ("eglGetProcAddress", "eglInitialize", "eglChooseConfig", "eglCreateContext",
                    "eglCreatePbufferSurface", "eglMakeCurrent", "eglBindAPI")
REQUIRED_EXTENSIONS = (b"eglQueryDevicesEXT", b"eglQueryDeviceStringEXT", b"eglGetPlatformDisplayEXT")

# EGL's enums (EGL 1.5 and its device extensions)
_NONE, _EXTENSIONS, _PLATFORM_DEVICE, _DRM_DEVICE_FILE = 0x3038, 0x3055, 0x313F, 0x3233
_CONFIG = (0x3033, 0x0001,  # surface type: pbuffer
           0x3024, 8, 0x3023, 8, 0x3022, 8, 0x3021, 8, 0x3025, 24,  # red, green, blue, alpha, depth
           0x3040, 0x0008, 0x3042, 0x0008)  # renderable and conformant: OpenGL
_OPENGL_API = 0x30A2
#: The context asked for: OpenGL 4.3 core (the counting pass's shader storage buffers need it).
_CONTEXT = (0x3098, 4, 0x30FB, 3, 0x30FD, 0x1)  # major, minor, core profile
_WIDTH, _HEIGHT = 0x3057, 0x3056


class EGLUnavailable(RuntimeError):
    """EGL is missing, broken or offers no usable device; the message says which and what to do."""


@dataclass(frozen=True)
class Device:
    """One EGL device.

    Attributes
    ----------
    index : int
        Its place in EGL's enumeration (``render.egl_device``).
    extensions : str
        Its extension string; Mesa's software device has ``EGL_MESA_device_software``.
    drm_file : str or None
        Its DRM device file (``/dev/dri/card0``), when it has one.
    handle : int or None
        EGL's ``EGLDeviceEXT`` for it (None for a device not enumerated by :func:`devices`).
    """

    index: int
    extensions: str
    drm_file: str | None = None
    handle: int | None = field(default=None, compare=False, repr=False)

    @property
    def software(self) -> bool:
        """True for Mesa's software renderer (llvmpipe), False for a GPU."""
        return "EGL_MESA_device_software" in self.extensions.split()

    def __str__(self) -> str:
        kind = "software (llvmpipe)" if self.software else "hardware"
        return f"EGL device {self.index}: {kind}" + (f", {self.drm_file}" if self.drm_file else "")


def _library(names=LIBRARY_NAMES):
    errors = []
    for name in names:
        try:
            return ctypes.CDLL(name, mode=ctypes.RTLD_GLOBAL), name
        except OSError as exc:
            errors.append(str(exc))
    raise EGLUnavailable(f"libEGL is missing (tried {', '.join(names)}; last: {errors[-1]}): {HELP}")


def _extension(lib, name: bytes, restype, *argtypes):
    lib.eglGetProcAddress.restype = ctypes.c_void_p
    lib.eglGetProcAddress.argtypes = [ctypes.c_char_p]
    address = lib.eglGetProcAddress(name)
    if not address:
        raise EGLUnavailable(f"libEGL lacks {name.decode()} (EGL_EXT_device_enumeration): {HELP}")
    return ctypes.CFUNCTYPE(restype, *argtypes)(address)


def check_egl(index: int | None = None, names=LIBRARY_NAMES) -> str:
    """The libEGL this process would use, checked for the entry points rendering needs and for the device.

    Loads no OpenGL (the Snakefile's preflight calls it before any job).

    Parameters
    ----------
    index : int or None
        ``render.egl_device`` (:func:`choose_device`).
    names : sequence of str
        Library names tried in order.

    Returns
    -------
    str
        The library's name and the device :func:`choose_device` takes, for the log.

    Raises
    ------
    EGLUnavailable
        No libEGL, one without the device extensions, or no device.
    """
    lib, name = _library(names)
    missing = [s for s in REQUIRED_SYMBOLS if not hasattr(lib, s)]
    if missing:
        raise EGLUnavailable(f"libEGL is broken: {name} lacks {', '.join(missing)}: {HELP}")
    return f"{name}, {choose_device(devices(lib), index, log=lambda message: None)}"


def devices(lib=None) -> list[Device]:
    """The EGL devices, in EGL's order (``eglQueryDevicesEXT``)."""
    lib = lib or _library()[0]
    query = _extension(lib, b"eglQueryDevicesEXT", ctypes.c_uint, ctypes.c_int, ctypes.POINTER(ctypes.c_void_p),
                       ctypes.POINTER(ctypes.c_int))
    string = _extension(lib, b"eglQueryDeviceStringEXT", ctypes.c_char_p, ctypes.c_void_p, ctypes.c_int)
    count = ctypes.c_int()
    if not query(0, None, ctypes.byref(count)) or count.value < 1:
        return []
    handles = (ctypes.c_void_p * count.value)()
    query(count.value, handles, ctypes.byref(count))
    out = []
    for k in range(count.value):
        drm = string(handles[k], _DRM_DEVICE_FILE)
        out.append(Device(k, (string(handles[k], _EXTENSIONS) or b"").decode(), drm.decode() if drm else None,
                          handles[k]))
    return out


def device_index() -> int | None:
    """``render.egl_device`` as the job's environment carries it (``ROUGHLIGHT_EGL_DEVICE``), or None."""
    value = os.environ.get("ROUGHLIGHT_EGL_DEVICE", "").strip()
    if value in ("", "auto", "None"):
        return None
    if not value.isdigit():
        raise EGLUnavailable(f"render.egl_device must be a device index (0, 1, ...) or empty, got {value!r}")
    return int(value)


def choose_device(found: list[Device], index: int | None = None, log=None) -> Device:
    """The device to render on.

    Parameters
    ----------
    found : list of Device, EGL's order
    index : int or None
        ``render.egl_device``: this device, whatever it is. None: the first hardware device, else the first
        software device (with a line to ``log`` saying so).
    log : callable taking a message, optional
        Default: this module's logger (a workflow job's log file).

    Raises
    ------
    EGLUnavailable
        An index beyond the devices, or no device.
    """
    if not found:
        raise EGLUnavailable(f"EGL offers no device (eglQueryDevicesEXT found none): {HELP}")
    if index is not None:
        if not 0 <= int(index) < len(found):
            listed = "; ".join(str(d) for d in found)
            raise EGLUnavailable(f"render.egl_device is {index} but EGL offers {len(found)} device(s): {listed}")
        return found[int(index)]
    hardware = [d for d in found if not d.software]
    if hardware:
        return hardware[0]
    (log or logging.getLogger(__name__).warning)(
        f"EGL: no hardware device, rendering on Mesa's software device ({found[0]})")
    return found[0]


class _Display:
    """The process's EGL display of the chosen device, initialised once and never terminated."""

    lib = None
    handle = None
    device = None

    @classmethod
    def get(cls):
        if cls.handle is None:
            lib = _library()[0]
            device = choose_device(devices(lib), device_index())
            display = _extension(lib, b"eglGetPlatformDisplayEXT", ctypes.c_void_p, ctypes.c_int, ctypes.c_void_p,
                                 ctypes.c_void_p)(_PLATFORM_DEVICE, device.handle, None)
            _prototypes(lib)
            major, minor = ctypes.c_int(), ctypes.c_int()
            if not display or not lib.eglInitialize(display, ctypes.byref(major), ctypes.byref(minor)):
                raise EGLUnavailable(f"could not initialise EGL on {device} (error {_error(lib)}): {HELP}")
            cls.lib, cls.handle, cls.device = lib, display, device
        return cls.lib, cls.handle


def _prototypes(lib) -> None:
    v, u, i = ctypes.c_void_p, ctypes.c_uint, ctypes.POINTER(ctypes.c_int)
    for name, restype, argtypes in (
        ("eglInitialize", u, [v, i, i]),
        ("eglChooseConfig", u, [v, i, ctypes.POINTER(v), ctypes.c_int, i]),
        ("eglBindAPI", u, [u]),
        ("eglCreateContext", v, [v, v, v, i]),
        ("eglCreatePbufferSurface", v, [v, v, i]),
        ("eglMakeCurrent", u, [v, v, v, v]),
        ("eglDestroySurface", u, [v, v]),
        ("eglDestroyContext", u, [v, v]),
        ("eglGetCurrentContext", v, []),
        ("eglGetError", ctypes.c_int, []),
    ):
        getattr(lib, name).restype, getattr(lib, name).argtypes = restype, argtypes


def _error(lib) -> str:
    return hex(lib.eglGetError())


def _ints(values) -> ctypes.Array:
    values = tuple(values) + (_NONE,)
    return (ctypes.c_int * len(values))(*values)


class EGLPlatform:
    """An EGL context with a ``width`` x ``height`` pbuffer as framebuffer 0, with pyrender's platform methods
    (``init_context``, ``make_current``, ``make_uncurrent``, ``delete_context``, ``supports_framebuffers``)."""

    def __init__(self, viewport_width: int, viewport_height: int):
        self.viewport_width, self.viewport_height = int(viewport_width), int(viewport_height)
        self._context = self._surface = None

    def init_context(self) -> None:
        lib, display = _Display.get()
        config, count = ctypes.c_void_p(), ctypes.c_int()
        if not lib.eglChooseConfig(display, _ints(_CONFIG), ctypes.byref(config), 1, ctypes.byref(count)) \
                or count.value < 1:
            raise EGLUnavailable(f"EGL on {_Display.device} has no RGBA8/depth-24 pbuffer config for OpenGL: {HELP}")
        lib.eglBindAPI(_OPENGL_API)
        self._context = lib.eglCreateContext(display, config, None, _ints(_CONTEXT))
        if not self._context:
            raise EGLUnavailable(f"EGL on {_Display.device} could not create an OpenGL 4.3 core context "
                                 f"(error {_error(lib)}): the renderer needs 4.3 (shader storage buffers)")
        size = (_WIDTH, self.viewport_width, _HEIGHT, self.viewport_height)
        self._surface = lib.eglCreatePbufferSurface(display, config, _ints(size))
        if not self._surface:
            raise EGLUnavailable(f"EGL could not make a {self.viewport_width} x {self.viewport_height} pbuffer "
                                 f"(error {_error(lib)})")
        self.make_current()

    def make_current(self) -> None:
        lib, display = _Display.get()
        if not lib.eglMakeCurrent(display, self._surface, self._surface, self._context):
            raise RuntimeError(f"eglMakeCurrent failed (error {_error(lib)})")

    def make_uncurrent(self) -> None:
        """Nothing to do: as OSMesa's, the context stays current until another is made current."""

    def delete_context(self) -> None:
        """Destroy this context and its pbuffer; the display stays, for the others."""
        lib, display = _Display.get()
        if lib.eglGetCurrentContext() == self._context:
            lib.eglMakeCurrent(display, None, None, None)
        if self._surface:
            lib.eglDestroySurface(display, self._surface)
        if self._context:
            lib.eglDestroyContext(display, self._context)
        self._context = self._surface = None

    def supports_framebuffers(self) -> bool:
        """False, as OSMesa's: pyrender draws into framebuffer 0 (the pbuffer), not its multisampled buffer."""
        return False
