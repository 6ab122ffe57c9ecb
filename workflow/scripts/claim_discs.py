"""Snakemake adapter: the random-roughness claim's lobes and search discs, from geometry, the regular surfaces and
the pilot seeds (no tested seed is read)."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.analysis.inputs import STUDY_COLUMNS  # noqa: E402
from roughlight.analysis.steps import claim_discs  # noqa: E402
from roughlight.atomic import write_frame  # noqa: E402
from roughlight.study.tables import read_study  # noqa: E402

log = _log.setup(snakemake)
study = read_study(snakemake.input.study, rows="random_points", columns=STUDY_COLUMNS["claim_discs"])
tables = claim_discs(study, snakemake.params.lighting)
for name, frame in tables.items():
    write_frame(frame, snakemake.output[name])
geometry, radii = tables["random_claim_geometry"], tables["random_claim_radii"]
log(f"claim: {int(geometry['in_claim'].sum())} of {len(geometry)} lobes in the claim; search discs:\n"
    + radii.round(3).to_string())
_log.end_job()
