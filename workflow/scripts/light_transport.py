"""Snakemake adapter: the study's surfaces in Mitsuba 3 (at the plan its folder names): direct light against the
exact reference, and what light that bounces adds to the diffuse, with its chart."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.threads(snakemake)  # Dr.Jit's threads, before Mitsuba loads

import _log  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.measurements import light_transport  # noqa: E402
from roughlight.render import shading  # noqa: E402
from roughlight.report import figures  # noqa: E402

log = _log.setup(snakemake)
out, params = snakemake.output, snakemake.params
lighting = shading.Lighting(**params.lighting)
plan = snakemake.wildcards.plan
agreement = light_transport.agreement(plan, lighting=lighting, settings=params.mitsuba, log=log)
write_frame(agreement, out.agreement)
frame = light_transport.interreflection(plan, lighting=lighting, bounces=params.bounces, albedo=params.albedo,
                                        settings=params.mitsuba, log=log)
write_frame(frame, out.interreflection)
summary = light_transport.interreflection_summary(frame)
write_frame(summary, out.summary)
figures.make("light_transport", out.chart, summary=summary, frame=frame)
log(agreement.round(4).to_string())
log(summary.round(3).to_string())
_log.end_job()  # outputs written: leave without the interpreter's teardown
