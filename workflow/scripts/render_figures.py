"""Snakemake adapter: rendered figures (plate sweeps for Figs. 17 and 20; pictures for Figs. 9, 10, 13)."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform, before anything loads OpenGL

import _log  # noqa: E402

from roughlight.atomic import write_frame  # noqa: E402
from roughlight.render import pictures  # noqa: E402
from roughlight.render.shading import Lighting  # noqa: E402
from roughlight.report import figures as F  # noqa: E402

log = _log.setup(snakemake)
out, params = snakemake.output, snakemake.params
lighting = dict(params.lighting)
incidence = float(params.incidence)  # Fig. 17's: the tables' incidence

plates = pictures.plate_sweeps(
    sorted(set(float(i) for i in params.incidences) | {incidence}),
    [float(j) for j in params.lights],
    elevation_step=params.elevation_step,
    lighting=lighting,
    settings=params.render,
)
write_frame(plates, out.plates)
F.make("fig17_clipping", out.fig17_clipping, plates=plates[plates["incidence"] == incidence])
base_light = float(lighting["light"])
at_base = plates["light"] == base_light
F.make("fig20_plate_incidence", out.fig20_plate_incidence,
       plates=plates[at_base] if at_base.any() else plates[plates["light"] == plates["light"].min()])
log(f"plate sweeps: {plates.groupby(['incidence', 'light']).ngroups} sweeps")

picture_lighting = Lighting(**{**lighting, "shadows": True})
for stem in ("fig09_shadows", "fig10_grazing", "fig13_tops"):
    _, views = pictures.PICTURE_SETS[stem]
    F.make(stem, out[stem], pictures=pictures.surface_pictures(views, lighting=picture_lighting))
    log(f"{stem} -> {out[stem]}")
_log.end_job()
