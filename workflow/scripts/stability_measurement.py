"""Snakemake adapter: one stability measurement (roughlight.stability.MEASUREMENTS) to Parquet."""
import os
import sys
import time

os.environ.setdefault("LP_NUM_THREADS", str(snakemake.threads))
os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")
sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
from roughlight import shading, stability  # noqa: E402
from roughlight.study import write_table_atomic  # noqa: E402

log = _log.setup(snakemake)
name = snakemake.wildcards.measurement
log(f"stability measurement {name}: started")
start = time.perf_counter()
table = stability.run_measurement(name, lighting=shading.Lighting(**snakemake.params.lighting))
write_table_atomic(table, snakemake.output[0])
log(f"stability measurement {name}: {len(table)} rows in {time.perf_counter() - start:.1f} s")
