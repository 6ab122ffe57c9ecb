"""Snakemake adapter: where methods fail, to a long Parquet table, the safe-domain CSV and a chart."""
import os
import sys

os.environ.setdefault("LP_NUM_THREADS", str(snakemake.threads))
os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")
sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
from roughlight import shading, stability  # noqa: E402
from roughlight.atomic import atomic_path  # noqa: E402
from roughlight.study import write_table_atomic  # noqa: E402

log = _log.setup(snakemake)
table = stability.run_all(lighting=shading.Lighting(**snakemake.params.lighting), log=log)
safe = stability.safe_domain(table)
with atomic_path(snakemake.output.safe) as tmp:
    safe.to_csv(tmp, index=False)
with atomic_path(snakemake.output.chart) as tmp:
    stability.plot_stability(table, tmp)
write_table_atomic(table, snakemake.output.table)
log(safe.to_string())
