"""Snakemake adapter: the random-roughness claim's design (margins, family, the seeds each test needs) from the
regular surfaces, the exact reference and the pilots' readings (rule claim_pilots) alone: no tested seed is read."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.analysis.inputs import STUDY_COLUMNS  # noqa: E402
from roughlight.analysis.steps import claim_design  # noqa: E402
from roughlight.atomic import write_frame  # noqa: E402
from roughlight.study.pilots import read_readings  # noqa: E402
from roughlight.study.tables import read_study  # noqa: E402

log = _log.setup(snakemake)
study = read_study(snakemake.input.study, rows="regular_points", columns=STUDY_COLUMNS["claim_discs"])
steps = (float(snakemake.params.sweep["azimuth_step"]), float(snakemake.params.sweep["elevation_step"]))
pilots = read_readings(snakemake.input.pilots)
tables = claim_design(study, pd.read_csv(snakemake.input.geometry), pd.read_parquet(snakemake.input.claim_grid),
                      snakemake.params.claims, steps, pilots=pilots)
for name, frame in tables.items():
    write_frame(frame, snakemake.output[name])
design = tables["random_claim_design"]
ensembles = pilots.drop_duplicates(["kind", "truncation", "aspect", "incidence"])
log(f"claim design: {len(design)} tests, planned from the pilots' readings of {len(ensembles)} ensembles "
    f"({', '.join(f'{n} {s}' for s, n in ensembles['source'].value_counts().items())}); each ensemble's plan:\n"
    + design.drop_duplicates(["kind", "truncation", "aspect", "incidence"])[
        ["kind", "truncation", "aspect", "incidence", "ensemble_seeds", "seeds_configured"]].to_string(index=False))
_log.end_job()
