"""Snakemake adapter: the stability measurements to one long table, the safe-domain CSV and a chart."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform and the renderers' threads, before anything loads OpenGL

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.measurements import stability  # noqa: E402
from roughlight.render import shading  # noqa: E402
from roughlight.report import figures  # noqa: E402

log = _log.setup(snakemake)
lighting = shading.Lighting(**snakemake.params.lighting)
table = pd.concat([pd.read_parquet(path) for path in snakemake.input], ignore_index=True)
safe = stability.safe_domain(table)
write_frame(safe, snakemake.output.safe)
figures.make("stability", snakemake.output.chart, frames=table, pictures=stability.normals_pictures(lighting=lighting))
write_frame(table, snakemake.output.table)
log(safe.to_string())
_log.end_job()  # outputs written: leave without the interpreter's teardown
