"""Snakemake adapter: the speed/accuracy benchmark to a Parquet table and a chart."""
import os
import sys

os.environ.setdefault("LP_NUM_THREADS", str(snakemake.threads))
os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")
sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
from roughlight import benchmark, shading  # noqa: E402
from roughlight.atomic import atomic_path  # noqa: E402
from roughlight.study import write_table_atomic  # noqa: E402

log = _log.setup(snakemake)
table = benchmark.run_benchmark(lighting=shading.Lighting(**snakemake.params.lighting), log=log)
write_table_atomic(table, snakemake.output.table)
with atomic_path(snakemake.output.chart) as tmp:
    benchmark.plot_speed_accuracy(table, tmp)
log(table[table.component != "total"].round(4).to_string())
