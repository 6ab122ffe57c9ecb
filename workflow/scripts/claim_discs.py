"""Snakemake adapter: the random-roughness claim's lobes and their search discs, from geometry and the regular
surfaces alone."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.analysis.inputs import STUDY_COLUMNS  # noqa: E402
from roughlight.analysis.steps import claim_discs  # noqa: E402
from roughlight.atomic import write_frame  # noqa: E402
from roughlight.study.tables import read_study  # noqa: E402

log = _log.setup(snakemake)
study = read_study(snakemake.input.study, rows="regular_points", columns=STUDY_COLUMNS["claim_discs"])
geometry = claim_discs(study, snakemake.params.lighting)["random_claim_geometry"]
write_frame(geometry, snakemake.output.random_claim_geometry)
log(f"claim: {int(geometry['in_claim'].sum())} of {len(geometry)} lobes in the claim:\n" + geometry.round(3).to_string())
_log.end_job()
