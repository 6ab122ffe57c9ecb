"""Snakemake adapter: lobe peaks and diffuse levels -> grid GLMs with diagnostics, and the share laws."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.analysis.steps import analysis_glm  # noqa: E402
from roughlight.atomic import read_frame, write_frame, write_text_atomic  # noqa: E402

log = _log.setup(snakemake)
tables, messages = analysis_glm(pd.read_parquet(snakemake.input.lobes_arc), read_frame(snakemake.input.diffuse_levels),
                                snakemake.params.settings, snakemake.params.lighting)
for msg in messages:
    log(msg)
for name, frame in tables.items():
    write_frame(frame, snakemake.output[name])
write_text_atomic(snakemake.output.glm_messages, json.dumps(messages, indent=1))
log(f"GLMs: {tables['glm_summary'][['response', 'status', 'converged']].to_dict('records')}")
log(f"share laws: {tables['share_laws'][['lobe', 'model', 'rmse', 'rmse_held_out']].round(3).to_dict('records')}")
_log.end_job()
