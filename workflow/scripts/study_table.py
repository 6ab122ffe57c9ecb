"""Snakemake adapter: join every rough sweep to its control into results/study.parquet."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.study.tables import aggregate  # noqa: E402

log = _log.setup(snakemake)
study = aggregate(list(snakemake.input.rough) + list(snakemake.input.random), snakemake.input.control)
write_frame(study, snakemake.output[0])
sweeps = len(snakemake.input.rough) + len(snakemake.input.random)
log(f"study table: {len(study)} rows ({len(study) // 3} views of {sweeps} sweeps, {len(snakemake.input.random)} of "
    f"them random tiles) -> {snakemake.output[0]}")
