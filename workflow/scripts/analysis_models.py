"""Snakemake adapter: the study table -> fit errors of analytic rough-surface models."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.analysis.inputs import STUDY_COLUMNS  # noqa: E402
from roughlight.analysis.steps import analysis_models  # noqa: E402
from roughlight.atomic import write_frame  # noqa: E402
from roughlight.study.tables import read_study  # noqa: E402

log = _log.setup(snakemake)
# the regular surface (the random ensembles: analysis_random.py), only the columns the models read
study = read_study(snakemake.input.study, rows="regular", columns=STUDY_COLUMNS["analysis_models"])
tables = analysis_models(study, snakemake.params.settings, snakemake.params.lighting)
for name, frame in tables.items():
    write_frame(frame, snakemake.output[name])
fits = tables["model_fits"]
log(f"model fits: {len(fits)} surfaces; best diffuse {fits['best_diffuse'].value_counts().to_dict()}, "
    f"best specular {fits['best_specular'].value_counts().to_dict()}")
_log.end_job()
