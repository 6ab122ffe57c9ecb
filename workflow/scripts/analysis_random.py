"""Snakemake adapter: the study's random tiles -> per-seed statistics, ensemble means, seeds needed, model refits,
the random-roughness charts; and the claim's verdict from its tested tiles."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.analysis import direction_rounds  # noqa: E402
from roughlight.analysis.inputs import STUDY_COLUMNS  # noqa: E402
from roughlight.analysis.steps import analysis_random  # noqa: E402
from roughlight.analysis.third_round import read_registered  # noqa: E402
from roughlight.atomic import write_frame  # noqa: E402
from roughlight.report import figures as F  # noqa: E402
from roughlight.study.tables import claim_rows, read_study  # noqa: E402

log = _log.setup(snakemake)
out, inp = snakemake.output, snakemake.input
study = read_study(inp.study, rows="random_points", columns=STUDY_COLUMNS["analysis_random"])
claim = {"rows": claim_rows(inp.claims), "geometry": pd.read_csv(inp.geometry),
         "margins": pd.read_csv(inp.margins), "design": pd.read_csv(inp.design),
         "steps": (float(snakemake.params.sweep["azimuth_step"]), float(snakemake.params.sweep["elevation_step"])),
         "third_round": read_registered(inp.third_round[0] if inp.third_round else None),
         "direction_rounds": {number: read_registered(inp[f"{spec['name']}_round"][0])
                              for number, spec in direction_rounds.ROUNDS.items() if inp[f"{spec['name']}_round"]},
         "measured": snakemake.params.measured}
tables = analysis_random(study, snakemake.params.settings, snakemake.params.lighting, snakemake.params.claims, claim)
for name, frame in tables.items():
    write_frame(frame, out[name])
stats, summary = tables["random_statistics"], tables["random_ensembles"]
log(f"ensembles: {summary.groupby(['kind', 'truncation', 'aspect', 'incidence']).ngroups} random grid points, "
    f"{stats[stats.kind != 'pyramids'].groupby(['kind', 'seed', 'truncation', 'aspect', 'incidence']).ngroups} tiles")
F.make("random_ensembles", out.random_ensembles_png, summary=summary)
F.make("random_maps", out.random_maps_png, study=study)
claims = tables["random_claims"]
for reading, part in claims.groupby("reading", sort=False):
    later = ", ".join(f"{n} by the registered round {r}" for r, n in part["round"].value_counts().sort_index().items()
                      if r > 2) or "none by a later round"
    log(f"claim ({reading}): {len(part)} tests ({later}): "
        + ", ".join(f"{n} {v}" for v, n in part["verdict"].value_counts().items()))
for r in tables["random_claims_untaken"].itertuples(index=False):
    log(f"the registered round {r.round} is not taken for {r.kind} t {r.truncation:g}, a {r.aspect:g}, incidence "
        f"{r.incidence:g}: {r.why} (its `make claim-*-round` measures it again)")
log(f"model refits: {len(tables['random_model_fits'])} tiles and regular surfaces; charts -> {out.random_ensembles_png}, "
    f"{out.random_maps_png}")
_log.end_job()
