"""Snakemake adapter: the study and the analysis tables -> the report's figures (no rendering)."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight import figures as F  # noqa: E402
from roughlight.atomic import read_frame  # noqa: E402

log = _log.setup(snakemake)
inp, out = snakemake.input, snakemake.output
study = pd.read_parquet(inp.study)
lobes = pd.read_parquet(inp.lobes)
parts = read_frame(inp.diffuse_parts)
sine = read_frame(inp.sine)
exact = read_frame(inp.exact)
areas = read_frame(inp.areas)
fits = pd.read_parquet(inp.fits)
hapke_max_phase = float(snakemake.params.settings["hapke_max_phase"])
area_sets = {a: g.reset_index(drop=True) for a, g in areas.groupby("aspect", sort=False)} if len(areas) else {}

makers = {
    "fig19_topdown": lambda: F.fig19_topdown(study),
    "fig21_specular_truncation": lambda: F.fig21_specular_truncation(study),
    "fig23_forward_models": lambda: F.fig23_forward_models(lobes, sine, m=float(study["light"].iloc[0]), exact=exact),
    "fig24_reflecting_areas": lambda: F.fig24_reflecting_areas(area_sets),
    "fig25_back_models": lambda: F.fig25_back_models(lobes, sine, m=float(study["light"].iloc[0]), exact=exact),
    "fig26_specular_aspect": lambda: F.fig26_specular_aspect(study),
    "fig27_diffuse_plate": lambda: F.fig27_diffuse_plate(study),
    "fig28_diffuse_truncation": lambda: F.fig28_diffuse_truncation(study, parts),
    "fig29_diffuse_aspect": lambda: F.fig29_diffuse_aspect(study),
    "lobe_geometry": lambda: F.fig_lobe_geometry(lobes),
    "diffuse_parts": lambda: F.fig_diffuse_parts(parts),
    "glm_diagnostics": lambda: F.fig_glm_diagnostics(read_frame(inp.glm_diagnostics), read_frame(inp.glm_summary)),
    "model_fits": lambda: F.fig_model_fits(fits),
    "hapke": lambda: F.fig_hapke(study, fits, hapke_max_phase),
    "timings": lambda: F.fig_timings(read_frame(inp.timings)),
}
for stem, make in makers.items():
    F.save_figure(make(), out[stem])
    log(f"{stem} -> {out[stem]}")
