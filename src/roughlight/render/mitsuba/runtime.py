"""Mitsuba 3 and Dr.Jit in this process: the environment they need, set before they load, and the variant in use.

Dr.Jit's LLVM backend loads a system libLLVM. Left to itself it takes the first ``libLLVM*.so.*`` it finds, and
with Debian 12's LLVM 15 the first render aborts the whole process (``LLVM ERROR: Cannot select: f32 =
fmaximum``). So the project names the library itself, before Dr.Jit is imported (``DRJIT_LIBLLVM_PATH``,
:func:`environment`): Debian's ``libllvm19`` (``make setup`` installs it), else the newest LLVM of at least
:data:`OLDEST_LLVM`, never 15 or older. A ``DRJIT_LIBLLVM_PATH`` the user set is kept.

Dr.Jit caches its compiled kernels under ``$HOME/.drjit``; the project keeps them out of the user's home
(``DRJIT_CACHE_DIR``, :func:`cache_dir`): under ``.snakemake/drjit`` of the workflow's directory (where jobs
run), else under the system's temporary directory. A ``DRJIT_CACHE_DIR`` the user set is kept.

:func:`load` imports Mitsuba in the requested variant, or, when its backend is missing, in the next of
:data:`VARIANTS` (``llvm_ad_rgb`` falls back to ``scalar_rgb``), with one line
in the log. Nothing here imports Mitsuba or Dr.Jit at import time.
"""

from __future__ import annotations

import ctypes.util
import functools
import glob
import logging
import os
import re
import sys
import tempfile
from importlib import metadata, util
from pathlib import Path

__all__ = ["VARIANTS", "OLDEST_LLVM", "PREFERRED_LLVM", "MitsubaUnavailable", "llvm_libraries", "find_llvm", "cache_dir",
           "environment", "load", "variant_in_use", "identity", "check_mitsuba", "THREADS_VARIABLES"]

LOG = logging.getLogger(__name__)

#: Mitsuba variants the method renders in, each falling back to the next when its backend is missing (:func:`load`):
#: CUDA (a GPU node), LLVM (Debian's libllvm19), scalar. RGB only: the three channels carry the diffuse, the specular
#: and the total (:mod:`roughlight.render.mitsuba.bsdf`).
VARIANTS = ("cuda_ad_rgb", "llvm_ad_rgb", "scalar_rgb")

#: The LLVM the method is tested on (Debian 12's ``libllvm19``), taken first when present.
PREFERRED_LLVM = 19
#: The oldest LLVM taken at all: Dr.Jit 1.5's kernels abort LLVM 15 (and older are untested).
OLDEST_LLVM = 16
#: Where libLLVM is looked for (with ``LD_LIBRARY_PATH``'s folders first and ``/usr/lib/llvm-*/lib`` last).
LIBRARY_DIRS = ("/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu", "/usr/lib64", "/usr/lib",
                "/usr/local/lib")
#: The environment variables that set Dr.Jit's worker threads, the first set above 0 winning (a workflow job sets
#: ``ROUGHLIGHT_THREADS`` to its rule's ``threads``, and ``LP_NUM_THREADS`` to 0 at one thread: workflow/scripts/_gl.py).
THREADS_VARIABLES = ("ROUGHLIGHT_THREADS", "LP_NUM_THREADS")
#: What to do when LLVM is missing, the end of the fallback's line.
LLVM_HELP = "install Debian's libllvm19 (`apt-get install libllvm19`, or `make setup`, which does it)"
#: What to do when Mitsuba is missing.
HELP = "install the pinned packages (`make setup`: requirements.lock's mitsuba and drjit)"

_NAMES = (re.compile(r"libLLVM-(\d+)(?:\.\d+)*\.so(?:\.\d+)*"), re.compile(r"libLLVM\.so\.(\d+)(?:\.\d+)*"))


class MitsubaUnavailable(RuntimeError):
    """Mitsuba or Dr.Jit is not installed, or no variant of the chain loads; the message says what to do."""


def llvm_libraries(dirs=None) -> list[tuple[int, str]]:
    """Every libLLVM in ``dirs`` (default: ``LD_LIBRARY_PATH``, :data:`LIBRARY_DIRS`, ``/usr/lib/llvm-*/lib``)
    as ``(major version, path)``, read from the file name (``libLLVM-19.so``, ``libLLVM.so.19.1``)."""
    if dirs is None:
        dirs = [d for d in os.environ.get("LD_LIBRARY_PATH", "").split(":") if d]
        dirs += [*LIBRARY_DIRS, *sorted(glob.glob("/usr/lib/llvm-*/lib"))]
    found = []
    for folder in dict.fromkeys(dirs):
        for path in sorted(glob.glob(os.path.join(folder, "libLLVM*.so*"))):
            for pattern in _NAMES:
                match = pattern.fullmatch(os.path.basename(path))
                if match and os.path.isfile(path):
                    found.append((int(match.group(1)), path))
                    break
    return found


def find_llvm(dirs=None) -> tuple[int, str] | None:
    """The libLLVM Dr.Jit is to load: :data:`PREFERRED_LLVM` when present, else the newest of at least
    :data:`OLDEST_LLVM`; None when there is none."""
    usable = [(major, path) for major, path in llvm_libraries(dirs) if major >= OLDEST_LLVM]
    if not usable:
        return None
    preferred = [item for item in usable if item[0] == PREFERRED_LLVM]
    return preferred[0] if preferred else max(usable, key=lambda item: item[0])


def cache_dir() -> Path:
    """Dr.Jit's kernel cache for this process: ``.snakemake/drjit`` of the working directory when it is a
    workflow's (it holds a ``Snakefile`` or ``.snakemake/``), else ``roughlight-drjit-<uid>`` in the temporary
    directory; never the user's home."""
    here = Path.cwd()
    if (here / "Snakefile").is_file() or (here / ".snakemake").is_dir():
        try:
            (here / ".snakemake" / "drjit").mkdir(parents=True, exist_ok=True)
            return here / ".snakemake" / "drjit"
        except OSError:
            pass
    folder = Path(tempfile.gettempdir()) / f"roughlight-drjit-{os.getuid()}"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


@functools.lru_cache(maxsize=1)
def environment() -> dict:
    """Set Dr.Jit's environment once a process, before it loads: ``DRJIT_LIBLLVM_PATH`` (:func:`find_llvm`; a
    path that does not exist when there is none, so that Dr.Jit never takes LLVM 15 on its own) and
    ``DRJIT_CACHE_DIR`` (:func:`cache_dir`), each unless the user set it.

    Returns
    -------
    dict: ``llvm`` (the library's path, or None), ``llvm_major`` (int or None), ``cache`` (the kernel cache).
    """
    if "drjit" in sys.modules:
        LOG.warning("Dr.Jit was imported before roughlight set its environment: its LLVM and kernel cache are "
                    "whatever it chose")
    user = os.environ.get("DRJIT_LIBLLVM_PATH")
    if user:
        match = [int(m.group(1)) for p in _NAMES if (m := p.fullmatch(os.path.basename(user)))]
        llvm = (match[0] if match else None, user) if os.path.isfile(user) else None
    else:
        llvm = find_llvm()
        os.environ["DRJIT_LIBLLVM_PATH"] = llvm[1] if llvm else "/nonexistent/no-libLLVM-16-or-newer.so"
    os.environ.setdefault("DRJIT_CACHE_DIR", str(cache_dir()))
    return {"llvm": llvm[1] if llvm else None, "llvm_major": llvm[0] if llvm else None,
            "cache": os.environ["DRJIT_CACHE_DIR"]}


def _threads() -> int | None:
    for name in THREADS_VARIABLES:
        value = os.environ.get(name, "").strip()
        if value.isdigit() and int(value) > 0:
            return int(value)
    return None


#: requested variant -> (variant in use, why the ones before it were passed over)
_CHOSEN: dict = {}


def _backend_missing(variant: str, env: dict) -> str | None:
    """Why ``variant``'s backend cannot load here, found without importing Mitsuba; None when it may."""
    if variant.startswith("llvm") and env["llvm"] is None:
        return f"no libLLVM {OLDEST_LLVM} or newer ({LLVM_HELP})"
    if variant.startswith("cuda") and ctypes.util.find_library("cuda") is None:
        return "no CUDA driver (libcuda)"
    return None


def _choose(mi, requested: str, env: dict) -> tuple[str, str]:
    reasons = []
    for variant in VARIANTS[VARIANTS.index(requested):]:
        missing = _backend_missing(variant, env)
        if missing is None:
            try:
                mi.set_variant(variant)
            except (ImportError, RuntimeError, AttributeError) as exc:
                missing = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        if missing is None:
            why = "; ".join(reasons)
            if reasons:
                LOG.warning(f"Mitsuba: {requested} cannot render here ({why}): rendering in {variant}")
            return variant, why
        reasons.append(f"{variant}: {missing}")
    raise MitsubaUnavailable(f"Mitsuba loads in none of {VARIANTS[VARIANTS.index(requested):]}: {'; '.join(reasons)}")


def load(requested: str = "llvm_ad_rgb"):
    """Mitsuba in ``requested`` or the variant it falls back to (:data:`VARIANTS`' order), made current.

    Returns
    -------
    mi : the ``mitsuba`` module, its variant set
    variant : str, the variant in use
    """
    if requested not in VARIANTS:
        raise ValueError(f"render.mitsuba.variant must be one of {VARIANTS}, got {requested!r}")
    env = environment()
    try:
        import drjit as dr
        import mitsuba as mi
    except ImportError as exc:
        raise MitsubaUnavailable(f"Mitsuba cannot be imported ({exc}): {HELP}") from exc
    if requested not in _CHOSEN:
        if _threads() is not None:
            dr.set_thread_count(_threads())
        _CHOSEN[requested] = _choose(mi, requested, env)
        used = _CHOSEN[requested][0]
        LOG.info(f"Mitsuba {_version('mitsuba')} in {used}" + (f" on {env['llvm']}" if used.startswith("llvm") else "")
                 + f", {dr.thread_count()} thread(s), kernel cache {env['cache']}")
    variant = _CHOSEN[requested][0]
    if mi.variant() != variant:
        mi.set_variant(variant)
    return mi, variant


def variant_in_use(requested: str = "llvm_ad_rgb") -> str:
    """The variant a sweep asking for ``requested`` renders (or rendered) in: what :func:`load` chose in this
    process, else the first of the chain whose backend library is here (found without importing Mitsuba)."""
    if requested in _CHOSEN:
        return _CHOSEN[requested][0]
    env = environment()
    chain = VARIANTS[VARIANTS.index(requested):]
    return next((v for v in chain if _backend_missing(v, env) is None), chain[-1])


def _version(name: str) -> str:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "absent"


def identity(settings=None) -> str:
    """What a sweep is drawn on, as the sweep store's key and the sweep file name it: with ``settings``
    (:class:`MitsubaSettings`), ``mitsuba 3.9.1 llvm_ad_rgb, LLVM 19`` (the variant in use, and the requested one
    when it fell back); without, the machine's Mitsuba, Dr.Jit and LLVM."""
    env = environment()
    llvm = f"LLVM {env['llvm_major'] or '?'}" if env["llvm"] else f"no LLVM {OLDEST_LLVM} or newer"
    if settings is None:
        return f"mitsuba {_version('mitsuba')} (drjit {_version('drjit')}), {llvm}"
    used = variant_in_use(settings.variant)
    text = f"mitsuba {_version('mitsuba')} {used}" + (f", {llvm}" if used.startswith("llvm") else "")
    return text if used == settings.variant else f"{text} (fallback from {settings.variant})"


def check_mitsuba(variant: str = "llvm_ad_rgb") -> str:
    """Before any job: Mitsuba and Dr.Jit installed (else :class:`MitsubaUnavailable` saying what to do), and
    the variant ``variant`` renders in here, as one line for the log (a fallback named with what is missing).
    Imports neither."""
    missing = [name for name in ("mitsuba", "drjit") if util.find_spec(name) is None]
    if missing:
        raise MitsubaUnavailable(f"{' and '.join(missing)} not installed: {HELP}")
    env = environment()
    used = variant_in_use(variant)
    line = f"Mitsuba {_version('mitsuba')} (drjit {_version('drjit')}) renders in {used}"
    if used.startswith("llvm"):
        line += f" on {env['llvm']}"
    if used != variant:
        reasons = [f"{v}: {_backend_missing(v, env)}" for v in VARIANTS[VARIANTS.index(variant):VARIANTS.index(used)]]
        line += f", not {variant} ({'; '.join(reasons)})"
    return line + f"; kernel cache {env['cache']}"
