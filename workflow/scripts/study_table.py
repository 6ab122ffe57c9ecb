"""Snakemake adapter: join every rough sweep to its control into results/study.parquet."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.study import aggregate  # noqa: E402

log = _log.setup(snakemake)
study = aggregate(snakemake.input.rough, snakemake.input.control)
write_frame(study, snakemake.output[0])
views = study.groupby(["truncation", "aspect", "incidence"]).size().sum() // 3
log(f"study table: {len(study)} rows ({views} views of {len(snakemake.input.rough)} sweeps) -> {snakemake.output[0]}")
