"""Snakemake adapter: every exported surface's summary in one table, and the picture the report shows."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.measurements import brdf_export  # noqa: E402
from roughlight.render import shading  # noqa: E402
from roughlight.render.implicit import load_table  # noqa: E402
from roughlight.report import figures  # noqa: E402

log = _log.setup(snakemake)
inputs, out = snakemake.input, snakemake.output
summary, check = brdf_export.gather(inputs.summaries, inputs.checks)
write_frame(summary, out.summary)
figures.make("export", out.chart, tables=[load_table(path) for path in inputs.shares], check=check,
             lighting=shading.Lighting(**snakemake.params.lighting))
log(summary.round(3).to_string())
_log.end_job()  # outputs written: leave without the interpreter's teardown
