"""Is OSMesa (software OpenGL) here and whole? One clear answer before any rendering.

PyOpenGL's OSMesa platform loads the first of ``libOSMesa.so``,
``libOSMesa.so.9`` ... ``libOSMesa.so.0`` that the dynamic linker opens (so
``LD_LIBRARY_PATH`` counts). When none opens, or the one that opens lacks the
OpenGL entry points, PyOpenGL fails deep inside its import with an
``AttributeError`` or ``ImportError`` that does not say what to do. This module
repeats PyOpenGL's search with ctypes only (no OpenGL import, a few
milliseconds) so that the workflow can stop before any job with one message,
and the renderer can turn an import failure into the same message.
"""

from __future__ import annotations

import ctypes

__all__ = ["LIBRARY_NAMES", "REQUIRED_SYMBOLS", "OSMesaUnavailable", "HELP", "check_osmesa"]

#: The names PyOpenGL tries, in its order.
LIBRARY_NAMES = ("libOSMesa.so",) + tuple(f"libOSMesa.so.{i}" for i in range(9, -1, -1))

#: Entry points the renderer cannot start without (context creation and GL itself).
REQUIRED_SYMBOLS = ("OSMesaCreateContextAttribs", "OSMesaMakeCurrent", "OSMesaGetProcAddress", "glGetError")

#: What to do, the end of every message.
HELP = (
    "install Debian's libosmesa6 (`apt-get install libosmesa6`, or `make setup`, which does it), "
    "keep PYOPENGL_PLATFORM=osmesa, and rerun snakemake; sweeps already written are kept"
)


class OSMesaUnavailable(RuntimeError):
    """libOSMesa is missing or broken; the message says which and what to do."""


def check_osmesa(names=LIBRARY_NAMES, symbols=REQUIRED_SYMBOLS) -> str:
    """The libOSMesa PyOpenGL would load, checked for the entry points rendering needs.

    Parameters
    ----------
    names : sequence of str
        Library names tried in order (default: PyOpenGL's order).
    symbols : sequence of str
        Symbols the library must export.

    Returns
    -------
    str
        The name that loaded.

    Raises
    ------
    OSMesaUnavailable
        When no name loads ("missing"), or the first that loads lacks a symbol
        ("broken": PyOpenGL would use that one and fail).
    """
    errors = []
    for name in names:
        try:
            library = ctypes.CDLL(name, mode=ctypes.RTLD_GLOBAL)
        except OSError as exc:
            errors.append(str(exc))
            continue
        missing = [s for s in symbols if not hasattr(library, s)]
        if missing:
            raise OSMesaUnavailable(
                f"libOSMesa is broken: {name} loads but lacks {', '.join(missing)} "
                f"(check LD_LIBRARY_PATH for a stray copy): {HELP}"
            )
        return name
    last = f"; last: {errors[-1]}" if errors else ""
    raise OSMesaUnavailable(f"libOSMesa is missing (tried {names[0]} ... {names[-1]}{last}): {HELP}")
