"""Snakemake adapter: join every rough sweep to its control into results/study.parquet."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.study.tables import RENDERERS_KEY, renderers, write_study  # noqa: E402

log = _log.setup(snakemake)
random = list(snakemake.params.random)  # the random tiles' files, in their ensembles' folders (input.random)
sweep_paths = list(snakemake.input.rough) + random + list(snakemake.input.control)
ran_on = renderers(sweep_paths)
rows = write_study(list(snakemake.input.rough) + random, snakemake.input.control, snakemake.output[0],
                   metadata={RENDERERS_KEY: json.dumps(ran_on)})
log(f"rendered on: {'; '.join(ran_on) or 'not recorded'}")
sweeps = len(snakemake.input.rough) + len(random)
log(f"study table: {rows} rows ({rows // 3} views of {sweeps} sweeps, {len(random)} of "
    f"them random tiles) -> {snakemake.output[0]}")
_log.end_job()
