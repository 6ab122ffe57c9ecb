"""Snakemake adapter: the default renderer against the exact reference at every view of the plan's surfaces, and
the arc curves of Figs. 21 and 28 against the exact curves."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform and the renderers' threads, before anything loads OpenGL

import _log  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.measurements import renderer_validation  # noqa: E402
from roughlight.render import methods, shading  # noqa: E402
from roughlight.report import figures  # noqa: E402

log = _log.setup(snakemake)
lighting = shading.Lighting(**snakemake.params.lighting)
settings = methods.settings("fast", snakemake.params.render)
validation = renderer_validation.validate_renderer(snakemake.wildcards.plan, lighting=lighting, settings=settings,
                                                   log=log)
write_frame(validation, snakemake.output.validation)
smoothness = renderer_validation.arc_smoothness(renderer_validation.read_arcs(snakemake.input.study),
                                                aspects=snakemake.params.table_aspects,
                                                incidence=snakemake.params.table_incidence, lighting=lighting)
write_frame(smoothness, snakemake.output.smoothness)
figures.make("renderer_validation", snakemake.output.chart, validation=validation, smoothness=smoothness)
log(renderer_validation.validation_summary(validation).round(3).to_string())
log(smoothness.round(3).to_string())
_log.end_job()  # outputs written: leave without the interpreter's teardown
