"""Snakemake adapter: the study table -> fit errors of analytic rough-surface models."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.surface_models import analytic_model_fits, model_fit_summary  # noqa: E402

log = _log.setup(snakemake)
from roughlight.study import regular  # noqa: E402

study = regular(pd.read_parquet(snakemake.input.study))  # the random ensembles: analysis_random.py
fits = analytic_model_fits(
    study, lighting=snakemake.params.lighting, hapke_max_phase=float(snakemake.params.settings["hapke_max_phase"])
)
write_frame(fits, snakemake.output.fits)
summary = model_fit_summary(fits)
write_frame(summary, snakemake.output.summary)
log(f"model fits: {len(fits)} surfaces; best diffuse {fits['best_diffuse'].value_counts().to_dict()}, "
    f"best specular {fits['best_specular'].value_counts().to_dict()}")
