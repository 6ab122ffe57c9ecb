"""Snakemake adapter: one job of the stability measurements (roughlight.measurements.stability.JOBS: one
measurement, or all of them) to Parquet."""
import os
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform and the renderers' threads, before anything loads OpenGL

import _log  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.measurements import stability  # noqa: E402
from roughlight.render import shading  # noqa: E402

log = _log.setup(snakemake)
name, plan = snakemake.wildcards.measurement, snakemake.wildcards.plan
log(f"stability measurement {name} ({plan} plan): started")
start = time.perf_counter()
table = stability.run_job(name, lighting=shading.Lighting(**snakemake.params.lighting), plan=plan)
write_frame(table, snakemake.output[0])
log(f"stability measurement {name}: {len(table)} rows in {time.perf_counter() - start:.1f} s")
_log.end_job()  # outputs written: leave without the interpreter's teardown
