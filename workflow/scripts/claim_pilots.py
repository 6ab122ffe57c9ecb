"""Snakemake adapter: the claim's pilots' readings (what rule claim_design plans from), each ensemble's from its
pilot tiles (rule claim_sweeps' pilots) or, where claims.registered_pilots holds them under the same settings, from
there (roughlight.study.pilots)."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.analysis.steps import pilot_readings  # noqa: E402
from roughlight.atomic import write_frame  # noqa: E402
from roughlight.study.pilots import combined_readings, read_readings  # noqa: E402
from roughlight.study.tables import claim_rows  # noqa: E402

log = _log.setup(snakemake)
steps = (float(snakemake.params.sweep["azimuth_step"]), float(snakemake.params.sweep["elevation_step"]))
keys = {(kind, float(t), float(a), float(i)): key for kind, t, a, i, key in snakemake.params.ensembles}
rendered = pilot_readings(claim_rows(snakemake.input.pilots), pd.read_csv(snakemake.input.geometry), steps, keys)
registered = read_readings(snakemake.input.registered[0]) if snakemake.input.registered else None
table = combined_readings(rendered, registered, keys)
write_frame(table, snakemake.output.random_claim_pilots)
counts = table.drop_duplicates(["kind", "truncation", "aspect", "incidence"])["source"].value_counts()
log(f"the pilots' readings of {len(keys)} ensembles: "
    + ", ".join(f"{n} {source}" for source, n in counts.items()))
_log.end_job()
