"""Snakemake adapter: the claim's regular lobes measured around each lobe at the study's azimuth step and finer, by
the fast method and the exact reference, at the plan its folder names."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform and the renderers' threads, before anything loads OpenGL

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.measurements.claim_grid import claim_grid  # noqa: E402
from roughlight.render import shading  # noqa: E402

log = _log.setup(snakemake)
geometry = pd.read_csv(snakemake.input.geometry)
table = claim_grid(geometry, snakemake.wildcards.plan, snakemake.params.sweep,
                   shading.Lighting(**snakemake.params.lighting), snakemake.params.render, log=log)
write_frame(table, snakemake.output[0])
_log.end_job()
