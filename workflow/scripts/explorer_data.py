"""Snakemake adapter: results/study.parquet -> the report's hemisphere explorer data (JSON)."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.atomic import write_text_atomic  # noqa: E402
from roughlight.report.explorer import explorer_data, read_study_columns  # noqa: E402

log = _log.setup(snakemake)
data = explorer_data(read_study_columns(snakemake.input.study), budget=snakemake.params.budget)
write_text_atomic(snakemake.output[0], json.dumps(data))
left = sum(g["count"] for g in data["left_out"])
log(f"explorer: {len(data['datasets'])} of {data['offered']} sweeps held in {data['bytes']:,} bytes "
    f"(budget {data['budget']:,}); {left} left out -> {snakemake.output[0]}")
_log.end_job()
