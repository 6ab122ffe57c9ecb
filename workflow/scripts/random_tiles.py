"""Snakemake adapter: the random tiles' benchmark (tile-size convergence, accuracy against the exact reference,
views per second, pictures) at the plan its folder names."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform and the renderers' threads, before anything loads OpenGL

import _log  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.measurements import random_tiles as roughness_bench  # noqa: E402
from roughlight.render import methods, shading  # noqa: E402
from roughlight.report import figures  # noqa: E402

log = _log.setup(snakemake)
lighting = shading.Lighting(**snakemake.params.lighting)
settings = methods.settings("fast", snakemake.params.render)
plan = snakemake.wildcards.plan
convergence = roughness_bench.tile_convergence(plan, lighting=lighting, settings=settings, log=log,
                                               surface=snakemake.params.surface)
write_frame(convergence, snakemake.output.convergence)
summary = roughness_bench.convergence_summary(convergence)
accuracy = roughness_bench.random_accuracy(plan, lighting=lighting, settings=settings, log=log)
write_frame(accuracy, snakemake.output.accuracy)
pictures = roughness_bench.random_pictures(plan, lighting=lighting)
figures.make("random_tiles", snakemake.output.chart, summary=summary, accuracy=accuracy, pictures=pictures)
log(summary.drop(columns="why").round(4).to_string())
log(accuracy.round(4).to_string())
_log.end_job()  # outputs written: leave without the interpreter's teardown
