"""Snakemake adapter: lobe peaks and diffuse levels -> grid GLMs with diagnostics."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.atomic import read_frame, write_frame, write_text_atomic  # noqa: E402
from roughlight.glm import grid_glms  # noqa: E402
from roughlight.shading import Lighting  # noqa: E402
from roughlight.share_laws import share_law_fits  # noqa: E402

log = _log.setup(snakemake)
out = snakemake.output
lobes = pd.read_parquet(snakemake.input.lobes)
levels = read_frame(snakemake.input.diffuse_levels)
summary, coefficients, diagnostics, messages = grid_glms(
    lobes, levels, collinearity_limit=float(snakemake.params.settings["collinearity_limit"])
)
for msg in messages:
    log(msg)
write_frame(summary, out.summary)
write_frame(coefficients, out.coefficients)
write_frame(diagnostics, out.diagnostics)
write_text_atomic(out.messages, json.dumps(messages, indent=1))
log(f"GLMs: {summary[['response', 'status', 'converged']].to_dict('records')}")
lighting = Lighting(**snakemake.params.lighting)
laws = share_law_fits(lobes, m=lighting.light * lighting.specular_reflectance)
write_frame(laws, out.share_laws)
log(f"share laws: {laws[['lobe', 'model', 'rmse', 'rmse_held_out']].round(3).to_dict('records')}")
