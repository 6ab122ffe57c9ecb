"""Snakemake adapter: one sweep (a rough surface or the control) to a Parquet file."""
import os
import sys

# llvmpipe's worker threads: as many as the rule's `threads`, set before OpenGL loads
os.environ.setdefault("LP_NUM_THREADS", str(snakemake.threads))
sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform, before anything loads OpenGL

import _log  # noqa: E402

from roughlight.study.tables import run_sweep  # noqa: E402
from roughlight.surfaces.roughness import make_surface  # noqa: E402

log = _log.setup(snakemake)
run_sweep(
    snakemake.output[0],
    surface=make_surface(**snakemake.params.surface),
    incidence=snakemake.params.incidence,
    sweep=snakemake.params.sweep,
    lighting=snakemake.params.lighting,
    method=snakemake.params.method,
    render=snakemake.params.render,
    log=log,
)
_log.end_job()
