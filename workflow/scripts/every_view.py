"""Snakemake adapter: one study sweep of a random tile (a file of its ensemble's folder, the rule's input) against the
exact reference at every view."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform, before anything loads OpenGL

import _log  # noqa: E402

from roughlight.atomic import read_frame, write_frame  # noqa: E402
from roughlight.measurements.random_tiles import every_view_errors, every_view_summary  # noqa: E402
from roughlight.render.shading import Lighting  # noqa: E402
from roughlight.study.plan import ensemble_member  # noqa: E402
from roughlight.surfaces.roughness import make_surface  # noqa: E402

log = _log.setup(snakemake)
sweep = ensemble_member(snakemake.input[0], snakemake.wildcards.seed)  # the tile's file in its ensemble's folder
errors = every_view_errors(read_frame(sweep), make_surface(**snakemake.params.surface),
                           snakemake.params.incidence, Lighting(**snakemake.params.lighting))
write_frame(errors, snakemake.output[0])
log(every_view_summary(errors).round(4).to_string())
_log.end_job()
