"""Snakemake adapter: the implicit rough surface's validation and frame times (at the plan its folder names)."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform and the renderers' threads, before anything loads OpenGL

import _log  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.measurements import implicit_surface as implicit_bench  # noqa: E402
from roughlight.render import shading  # noqa: E402
from roughlight.report import figures  # noqa: E402

log = _log.setup(snakemake)
lighting = shading.Lighting(**snakemake.params.lighting)
plan = snakemake.wildcards.plan
# the exported surfaces' share tables (rule share_table), for implicit_table's rows
tables = implicit_bench.load_tables({tuple(pair): path for pair, path in zip(snakemake.params.exported,
                                                                            snakemake.input.tables)})
validation = implicit_bench.validation(plan, lighting=lighting, log=log, tables=tables)
write_frame(validation, snakemake.output.validation)
pictures = {}
frames = implicit_bench.frame_times(plan, lighting=lighting, log=log, pictures=pictures, tables=tables)
write_frame(frames, snakemake.output.frames)
figures.make("implicit", snakemake.output.chart, validation=validation, frames=frames, pictures=pictures)
maps = implicit_bench.hemisphere_maps(plan, lighting=lighting, tables=tables)
write_frame(maps, snakemake.output.maps)
figures.make("implicit_maps", snakemake.output.maps_chart, maps=maps)
log(implicit_bench.summary(validation).round(4).to_string())
log(frames.round(3).to_string())
_log.end_job()  # outputs written: leave without the interpreter's teardown
