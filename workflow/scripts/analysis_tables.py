"""Snakemake adapter: the study table -> lobes, Tables 1-2, sine refits, diffuse model, timings."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight import analysis as an  # noqa: E402
from roughlight.atomic import write_frame, write_text_atomic  # noqa: E402
from roughlight.report import study_summary  # noqa: E402
from roughlight.shading import Lighting  # noqa: E402

log = _log.setup(snakemake)
out = snakemake.output
settings = snakemake.params.settings
lighting = Lighting(**snakemake.params.lighting)
aspects = settings["table_aspects"]
incidence = float(settings["table_incidence"])
m = lighting.light * lighting.specular_reflectance

study = pd.read_parquet(snakemake.input.study)
log(f"study: {len(study)} rows from {snakemake.input.study}")
messages = []

lobes = an.arc_lobes(study, max_halfwidth=float(settings["lobe_halfwidth"]))
write_frame(lobes, out.lobes)
write_frame(an.hemisphere_lobes(study, max_angle=float(settings["lobe_halfwidth"])), out.hemisphere)
log(f"lobes: {len(lobes)} arc lobes")

parts = an.diffuse_three_part(study)
write_frame(parts, out.diffuse_parts)
levels = an.diffuse_levels(study)
write_frame(levels, out.diffuse_levels)
log(f"diffuse: {int(parts['rate'].notna().sum())} of {len(parts)} surfaces with a fitted decay")

if settings["exact_check"]:
    exact = an.exact_lobe_peaks(lobes, aspects, incidence, lighting)
    log(f"exact peaks: {len(exact)}; max |measured - exact| = {exact['error'].abs().max():.3f}")
else:
    exact = pd.DataFrame(columns=an.SURFACE_KEYS + ["lobe", "peak", "exact_peak", "exact_peak_elevation", "error"])
    messages.append("the exact-reference check of the lobe peaks is switched off (report.exact_check)")
write_frame(exact, out.exact)

tables, table_messages = an.thesis_tables(lobes, aspects, incidence, m=m, k=None, exact=exact if len(exact) else None)
messages += table_messages
write_frame(tables, out.thesis_tables)
write_frame(an.bootstrap_tables(lobes, aspects, incidence, m=m), out.bootstrap)
write_frame(an.sine_refits(lobes, aspects, incidence, m=m), out.sine)
for msg in table_messages:
    log(msg)

areas = []
for wanted in aspects:
    found = an.find_aspect(study["aspect"], wanted)
    if found is not None:
        frame = an.reflecting_areas(found, incidence)
        frame.insert(0, "aspect", found)
        areas.append(frame)
write_frame(pd.concat(areas, ignore_index=True) if areas else pd.DataFrame(), out.areas)

per_sweep, timing_summary = an.render_timings(study)
write_frame(per_sweep, out.timings)
summary = {"study": study_summary(study), "timings": timing_summary, "messages": messages}
write_text_atomic(out.summary, json.dumps(summary, indent=1))
log(f"done: {len(tables)} table rows, {len(messages)} messages")
