"""Snakemake adapter: the study table -> lobes, Tables 1-2, sine refits, diffuse model, timings."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.analysis.inputs import STUDY_COLUMNS  # noqa: E402
from roughlight.analysis.steps import analysis_tables  # noqa: E402
from roughlight.atomic import write_frame, write_text_atomic  # noqa: E402
from roughlight.study.tables import read_study  # noqa: E402

log = _log.setup(snakemake)
# the regular surface (the random ensembles: analysis_random.py), only the columns the tables read
study = read_study(snakemake.input.study, rows="regular", columns=STUDY_COLUMNS["analysis_tables"])
log(f"study: {len(study)} rows from {snakemake.input.study}")
tables, summary = analysis_tables(study, snakemake.params.settings, snakemake.params.lighting, log=log)
for name, frame in tables.items():
    write_frame(frame, snakemake.output[name])
write_text_atomic(snakemake.output.study_summary, json.dumps(summary, indent=1))
log(f"done: {len(tables['thesis_tables'])} table rows, {len(summary['messages'])} messages")
_log.end_job()
