"""The project's C kernels, built by the machine's C compiler at first use and loaded with :mod:`ctypes`: the random
tiles' counting kernel (:mod:`roughlight.render.fast.raster`, ``raster.c``) and the regular surfaces' clipper
(:mod:`roughlight.render.exact.pyramid`, ``pyramid.c``). Each is compiled once a machine (``make setup`` does it)
into a shared library named by a digest of its source, the flags and the compiler."""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
from pathlib import Path

from ..atomic import atomic_path

__all__ = ["FLAGS", "build", "user_cache"]

#: How a kernel is compiled: optimised, as a shared library, and with no fused multiply-adds or fast-math, so that
#: every compiler gives the same results to the bit on a machine with IEEE double arithmetic, as x86-64 and arm64
#: have (the environment's CFLAGS are not read).
FLAGS = ("-O2", "-std=c99", "-ffp-contract=off", "-fno-fast-math", "-fPIC", "-shared")


def build(source: Path, what: str, cache=None) -> Path:
    """The shared library of the C file ``source``, built with :data:`FLAGS` if it is not yet there.

    It is named ``<stem>-<digest>.so`` by a digest of the source, the flags and the compiler, in ``__pycache__``
    beside the source (or, where that cannot be written, in :func:`user_cache`), and written under a temporary name,
    then renamed (:func:`roughlight.atomic.atomic_path`, which also gives it an ordinary file's permissions): jobs
    starting together may each build it, none loads half a file. The compiler is ``$CC``, else ``cc``: about
    0.2 s, once a machine.

    Parameters
    ----------
    source : Path
        The kernel's C source.
    what : str
        What the kernel is, for messages ("the random tiles' counting kernel").
    cache : path-like, optional
        The folder to keep it in, instead of the ones above.

    Raises
    ------
    RuntimeError
        No C compiler, or the compiler failed (its message is included).
    """
    source = Path(source)
    compiler = os.environ.get("CC") or "cc"
    if shutil.which(compiler) is None:
        raise RuntimeError(f"{what} ({source.name}) needs a C compiler, and {compiler!r} is not on PATH: install one "
                           "(Debian: apt-get install gcc; `make setup` does) or set CC")
    text = source.read_bytes()
    digest = hashlib.sha256(b"\0".join([text, " ".join(FLAGS).encode(), compiler.encode()])).hexdigest()[:16]
    folders = [Path(cache)] if cache is not None else [source.with_name("__pycache__"), user_cache()]
    name = f"{source.stem}-{digest}.so"
    for folder in folders:
        if (folder / name).is_file():
            return folder / name
    for folder in folders:
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError:
            continue
        if not os.access(folder, os.W_OK):
            continue
        with atomic_path(folder / name) as tmp:
            done = subprocess.run([compiler, *FLAGS, str(source), "-o", tmp, "-lm"], capture_output=True, text=True)
            if done.returncode != 0:
                raise RuntimeError(f"{compiler} could not build {what} {source}:\n{done.stderr.strip()}")
        return folder / name
    raise RuntimeError(f"no folder to keep {what} in: {', '.join(map(str, folders))} cannot be written")


def user_cache() -> Path:
    """``$XDG_CACHE_HOME/roughlight``, by default ``~/.cache/roughlight``."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "roughlight"
