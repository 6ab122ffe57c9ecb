"""Snakemake adapter: the study table -> lobes, Tables 1-2, sine refits, diffuse model, timings."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.atomic import write_frame, write_text_atomic  # noqa: E402
from roughlight.diffuse import diffuse_levels, diffuse_three_part  # noqa: E402
from roughlight.geometry import reflecting_areas  # noqa: E402
from roughlight.lobes import arc_lobes, hemisphere_lobes  # noqa: E402
from roughlight.report import study_summary  # noqa: E402
from roughlight.selection import SURFACE_KEYS, find_aspect  # noqa: E402
from roughlight.shading import Lighting  # noqa: E402
from roughlight.study import regular  # noqa: E402
from roughlight.thesis import (  # noqa: E402
    bootstrap_tables,
    exact_lobe_peaks,
    implied_scales,
    sine_refits,
    tables_at_implied_scale,
    thesis_tables,
)
from roughlight.timings import render_timings  # noqa: E402

log = _log.setup(snakemake)
out = snakemake.output
settings = snakemake.params.settings
lighting = Lighting(**snakemake.params.lighting)
aspects = settings["table_aspects"]
incidence = float(settings["table_incidence"])
m = lighting.light * lighting.specular_reflectance

study = regular(pd.read_parquet(snakemake.input.study))  # the random ensembles: analysis_random.py
log(f"study: {len(study)} rows from {snakemake.input.study}")
messages = []

lobes = arc_lobes(study, max_halfwidth=float(settings["lobe_halfwidth"]))
write_frame(lobes, out.lobes)
write_frame(hemisphere_lobes(study, max_angle=float(settings["lobe_halfwidth"])), out.hemisphere)
log(f"lobes: {len(lobes)} arc lobes")

parts = diffuse_three_part(study)
write_frame(parts, out.diffuse_parts)
levels = diffuse_levels(study)
write_frame(levels, out.diffuse_levels)
log(f"diffuse: {int(parts['rate'].notna().sum())} of {len(parts)} surfaces with a fitted decay")

if settings["exact_check"]:
    exact = exact_lobe_peaks(lobes, aspects, incidence, lighting)
    log(f"exact peaks: {len(exact)}; max |measured - exact| = {exact['error'].abs().max():.3f}")
else:
    exact = pd.DataFrame(columns=SURFACE_KEYS + ["lobe", "peak", "exact_peak", "exact_peak_elevation", "error"])
    messages.append("the exact-reference check of the lobe peaks is switched off (report.exact_check)")
write_frame(exact, out.exact)

tables, table_messages = thesis_tables(lobes, aspects, incidence, m=m, k=None, exact=exact if len(exact) else None)
messages += table_messages
write_frame(tables, out.thesis_tables)
write_frame(bootstrap_tables(lobes, aspects, incidence, m=m), out.bootstrap)
write_frame(sine_refits(lobes, aspects, incidence, m=m), out.sine)
scales = implied_scales()
write_frame(scales, out.implied_scales)
write_frame(tables_at_implied_scale(lobes, aspects, incidence), out.tables_at_implied_scale)
log(f"implied scales: {scales[['model', 's_min_mae', 's_max_mae', 'stated_possible']].to_dict('records')}")
for msg in table_messages:
    log(msg)

areas = []
for wanted in aspects:
    found = find_aspect(study["aspect"], wanted)
    if found is not None:
        frame = reflecting_areas(found, incidence)
        frame.insert(0, "aspect", found)
        areas.append(frame)
write_frame(pd.concat(areas, ignore_index=True) if areas else pd.DataFrame(), out.areas)

per_sweep, timing_summary = render_timings(study)
write_frame(per_sweep, out.timings)
summary = {"study": study_summary(study), "timings": timing_summary, "messages": messages}
write_text_atomic(out.summary, json.dumps(summary, indent=1))
log(f"done: {len(tables)} table rows, {len(messages)} messages")
