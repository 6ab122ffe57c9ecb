"""Snakemake adapter: the study's random tiles -> per-seed statistics, ensemble means, seeds needed, model refits,
and the random-roughness charts."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight import ensembles as E  # noqa: E402
from roughlight import figures as F  # noqa: E402
from roughlight.atomic import write_frame  # noqa: E402

log = _log.setup(snakemake)
out, settings = snakemake.output, snakemake.params.settings
study = pd.read_parquet(snakemake.input.study)
stats = E.seed_statistics(study, lobe_halfwidth=float(settings["lobe_halfwidth"]))
write_frame(stats, out.statistics)
pooled = E.pooled_statistics(study, lobe_halfwidth=float(settings["lobe_halfwidth"]))
summary = E.ensemble_summary(stats, pooled=pooled)
write_frame(summary, out.ensembles)
write_frame(E.seeds_needed(summary), out.seeds_needed)
log(f"ensembles: {summary.groupby(['kind', 'truncation', 'aspect', 'incidence']).ngroups} random grid points, "
    f"{stats[stats.kind != 'pyramids'].groupby(['kind', 'seed', 'truncation', 'aspect', 'incidence']).ngroups} tiles")
fits = E.ensemble_model_fits(study, lighting=snakemake.params.lighting,
                             hapke_max_phase=float(settings["hapke_max_phase"]))
write_frame(fits, out.model_fits)
F.plot_random_ensembles(summary, out.ensembles_chart)
F.plot_random_maps(study, out.maps_chart)
log(f"model refits: {len(fits)} tiles and regular surfaces; charts -> {out.ensembles_chart}, {out.maps_chart}")
