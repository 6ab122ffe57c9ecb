"""The sweep store: a sweep is measured once for the same settings and the same code.

The workflow renders the regular grid a truncation at a time (rule ``rough_sweeps``: one job for a truncation's
sweeps at every grid aspect), so that 132 sweeps do not each pay a process's start-up. Snakemake deletes all of a
job's outputs before it runs the job again, so without a store, adding an aspect to the grid would re-render every
row. Every sweep job therefore keeps a copy of each sweep it writes under ``results/sweep_store/``, named by a
digest of everything the sweep's file depends on, and takes a sweep from there instead of rendering it when the
digest matches:

- the sweep files' format (:data:`roughlight.study.tables.SWEEP_FORMAT`: 2 since each view's means before
  rounding and without inner shadows were added), so that a sweep stored without a column the study table now
  carries is never handed back;
- the sweep's settings, as the rule's params pass them (surface, incidence, views, lighting, method, renderer
  knobs, OpenGL platform);
- the source of the ``roughlight`` package (every file of it: a changed renderer never serves an old sweep);
- the versions of the libraries that draw and write it (numpy, trimesh, pyrender2, PyOpenGL, pyarrow); the random
  tiles' counting kernel is C in the package (``render/fast/raster.c``), and the compiler that built it is recorded
  as what counted them;
- what draws it: the OpenGL renderer, its version and driver and the platform, as the GL reports them
  (``llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6, osmesa``;
  :func:`roughlight.render.methods.renderer_identity`), so that a GPU run never takes llvmpipe's sweeps, nor the
  other way round; the exact reference, which draws nothing, names no renderer.

A reused sweep is the same file, byte for byte, as the one measured first (its ``render_seconds`` included: the time
that sweep took). ``rm -r results/sweep_store`` measures everything anew; a fresh ``results/`` has no store.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import shutil
import time
from importlib import metadata
from pathlib import Path

from ..atomic import atomic_path

__all__ = ["STORE", "LIBRARIES", "code_digest", "sweep_key", "stored", "fetch", "keep", "measure_sweeps"]

#: The store's folder, relative to the workflow's directory.
STORE = "results/sweep_store"
#: The distributions (as pip names them) whose version is part of every sweep's key.
LIBRARIES = ("numpy", "trimesh", "pyrender2", "PyOpenGL", "pyarrow")


@functools.lru_cache(maxsize=1)
def code_digest() -> str:
    """SHA-256 (hex) of the installed ``roughlight`` package's files (paths and bytes, caches left out) and of
    :data:`LIBRARIES`' versions."""
    package = Path(__file__).resolve().parents[1]
    digest = hashlib.sha256()
    for path in sorted(package.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts:
            digest.update(str(path.relative_to(package)).encode() + b"\0" + path.read_bytes() + b"\0")
    for name in LIBRARIES:
        try:
            version = metadata.version(name)
        except metadata.PackageNotFoundError:
            version = "absent"
        digest.update(f"{name}={version}\0".encode())
    return digest.hexdigest()


def sweep_key(settings: dict) -> str:
    """The store's name for a sweep: SHA-256 (hex) of the sweep files' format
    (:data:`roughlight.study.tables.SWEEP_FORMAT`), its settings (JSON, keys sorted; any JSON-able dict) and
    :func:`code_digest`."""
    from .tables import SWEEP_FORMAT

    text = json.dumps(settings, sort_keys=True, default=str)
    return hashlib.sha256(f"format {SWEEP_FORMAT}\0{code_digest()}\0{text}".encode()).hexdigest()


def stored(store, key: str) -> Path:
    """The store's file for ``key``."""
    return Path(store) / key[:2] / f"{key}.parquet"


def _copy(source, target) -> None:
    """Copy ``source`` to ``target`` atomically (a temporary name in the target's folder, then rename)."""
    with atomic_path(target) as tmp:
        shutil.copyfile(source, tmp)


def fetch(store, key: str, path) -> bool:
    """Write the stored sweep ``key`` to ``path`` (atomically); False when the store has none."""
    source = stored(store, key)
    if not source.is_file():
        return False
    _copy(source, path)
    return True


def keep(store, key: str, path) -> None:
    """Keep a copy of the sweep file ``path`` in the store under ``key`` (atomically)."""
    _copy(path, stored(store, key))


def measure_sweeps(paths, surfaces, settings: dict, measure, store=STORE, log=None) -> dict:
    """Write each sweep's file, from the store when it holds the sweep, else measured and then kept there.

    Parameters
    ----------
    paths : list of str
        Output Parquet files, one per surface.
    surfaces : list of dict
        Each sweep's surface, as :func:`roughlight.surfaces.roughness.make_surface` takes it (JSON-able).
    settings : dict
        What else decides the sweeps' files (incidence, views, lighting, method, renderer knobs, platform):
        JSON-able, the same for every sweep of the call. Its ``renderer``, when not given, is what this process
        draws the method on (:func:`roughlight.render.methods.renderer_identity`).
    measure : callable ``measure(path, surface)``
        Measures one sweep and writes its file to ``path`` atomically (as
        :func:`roughlight.study.tables.run_sweep`).
    store : path-like
        The store's folder (:data:`STORE`); None measures every sweep and keeps none.
    log : callable taking a message, optional

    Returns
    -------
    dict
        ``measured`` and ``reused``: the paths of each.
    """
    if len(paths) != len(surfaces):
        raise ValueError(f"{len(paths)} output files for {len(surfaces)} surfaces")
    log = log or (lambda message: None)
    if store is not None and "renderer" not in settings:
        from ..render.methods import renderer_identity

        settings = {**settings, "renderer": renderer_identity(settings.get("method", "fast"))}
        log(f"the store's key names the renderer: {settings['renderer']}")
    done = {"measured": [], "reused": []}
    start = time.perf_counter()
    for number, (path, surface) in enumerate(zip(paths, surfaces), start=1):
        key = None if store is None else sweep_key({**settings, "surface": surface})
        if key is not None and fetch(store, key, path):
            done["reused"].append(os.fspath(path))
            log(f"sweep {number}/{len(paths)} {path}: taken from the store ({stored(store, key)})")
            continue
        measure(path, surface)
        if key is not None:
            keep(store, key, path)
        done["measured"].append(os.fspath(path))
        log(f"sweep {number}/{len(paths)} {path}: measured ({time.perf_counter() - start:.1f} s into the job)")
    log(f"{len(done['measured'])} sweeps measured, {len(done['reused'])} taken from the store")
    return done
