"""Snakemake adapter: one surface's measured BRDF exported (its share table and Mitsuba file) and checked."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform and the renderers' threads, before anything loads OpenGL

import _log  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.measurements import brdf_export  # noqa: E402
from roughlight.render import shading  # noqa: E402
from roughlight.surfaces.surface import Surface  # noqa: E402

log = _log.setup(snakemake)
out, params = snakemake.output, snakemake.params
surface = Surface(*params.surface)
settings = params.export
exported = brdf_export.export_surface(surface, {"shares": out.shares, "mitsuba": out.mitsuba}, settings["table"],
                                      settings["mitsuba"], settings["check"], shading.Lighting(**params.lighting), log)
write_frame(exported["check"], out.check)
write_frame(exported["summary"], out.summary)
log(exported["summary"].round(3).to_string())
_log.end_job()  # outputs written: leave without the interpreter's teardown
