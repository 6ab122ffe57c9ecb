"""Snakemake adapter: the speed/accuracy benchmark (at the plan its folder names) to a Parquet table and a chart."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform and the renderers' threads, before anything loads OpenGL

import _log  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.measurements import speed_accuracy as benchmark  # noqa: E402
from roughlight.render import shading  # noqa: E402
from roughlight.report import figures  # noqa: E402

log = _log.setup(snakemake)
lighting = shading.Lighting(**snakemake.params.lighting)
table = benchmark.run_plan(snakemake.wildcards.plan, lighting=lighting, log=log)
write_frame(table, snakemake.output.table)
figures.make("speed_accuracy", snakemake.output.chart, table=table)
log(table[table.component != "total"].round(4).to_string())
_log.end_job()  # outputs written: leave without the interpreter's teardown
