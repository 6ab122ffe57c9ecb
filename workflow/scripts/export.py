"""Snakemake adapter: one surface's share table (rule share_table) exported as a Mitsuba file, and both checked."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform and the renderers' threads, before anything loads OpenGL

import _log  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.measurements import brdf_export  # noqa: E402
from roughlight.render import shading  # noqa: E402
from roughlight.render.implicit import load_table  # noqa: E402

log = _log.setup(snakemake)
inp, out, params = snakemake.input, snakemake.output, snakemake.params
with open(inp.table) as handle:
    table_seconds = json.load(handle)["seconds"]
exported = brdf_export.export_surface(load_table(inp.shares), {"shares": inp.shares, "mitsuba": out.mitsuba},
                                      params.export["mitsuba"], params.export["check"],
                                      shading.Lighting(**params.lighting), table_seconds)
write_frame(exported["check"], out.check)
write_frame(exported["summary"], out.summary)
log(exported["summary"].round(3).to_string())
_log.end_job()  # outputs written: leave without the interpreter's teardown
