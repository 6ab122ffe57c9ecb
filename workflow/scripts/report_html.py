"""Snakemake adapter: analysis tables and figures -> reports/roughlight_report.html (self-contained)."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.atomic import read_frame  # noqa: E402
from roughlight.report import page as R  # noqa: E402

log = _log.setup(snakemake)
inp = snakemake.input
with open(inp.summary) as fh:
    summary = json.load(fh)
with open(inp.glm_messages) as fh:
    glm_messages = json.load(fh)
tables = {
    "study_summary": summary["study"],
    "timings_summary": summary["timings"],
    "lobes": pd.read_parquet(inp.lobes),
    "lobes_hemisphere": pd.read_parquet(inp.hemisphere),
    "diffuse_parts": read_frame(inp.diffuse_parts),
    "exact_peaks": read_frame(inp.exact),
    "thesis_tables": read_frame(inp.thesis_tables),
    "bootstrap_tables": read_frame(inp.bootstrap),
    "sine_refits": read_frame(inp.sine),
    "implied_scales": read_frame(inp.implied_scales),
    "tables_at_implied_scale": read_frame(inp.tables_at_implied_scale),
    "timings": read_frame(inp.timings),
    "glm_summary": read_frame(inp.glm_summary),
    "glm_coefficients": read_frame(inp.glm_coefficients),
    "share_laws": read_frame(inp.share_laws),
    "glm_messages": glm_messages,
    "model_fits": pd.read_parquet(inp.fits),
    "model_fits_summary": read_frame(inp.fits_summary),
}
figures = {os.path.splitext(os.path.basename(p))[0]: p for p in inp.figures}
benchmarks = None
if "speed_accuracy_chart" in inp.keys():  # report.speed_accuracy
    benchmarks = {"png": inp.speed_accuracy_chart, "table": pd.read_parquet(inp.speed_accuracy_table),
                  "validation": pd.read_parquet(inp.renderer_validation),
                  "smoothness": pd.read_parquet(inp.arc_smoothness), "validation_png": inp.renderer_validation_chart}
stability_html = None
if "stability_chart" in inp.keys():  # report.stability
    stability_html = R.stability_section(
        {"safe_domain": pd.read_csv(inp.stability_safe), "stability": pd.read_parquet(inp.stability_table)},
        inp.stability_chart, plan=snakemake.params.plan,
        renderer_validation=benchmarks["validation"] if benchmarks else None,
    )
measured = {}  # the frames of the sections rendered apart that the findings read
implicit_html = None
if "implicit_chart" in inp.keys():  # report.implicit
    measured["implicit_validation"] = pd.read_parquet(inp.implicit_validation)
    implicit_html = R.implicit_section(measured["implicit_validation"], pd.read_parquet(inp.implicit_frames),
                                       inp.implicit_chart, plan=snakemake.params.plan,
                                       maps_png_path=inp.implicit_maps_chart)
random_html = None
if "random_ensembles" in inp.keys():  # surface.kind lists a random kind
    tile_accuracy = pd.read_parquet(inp.random_accuracy)
    if benchmarks:  # "Accuracy at every view" lists the random tiles too
        benchmarks["tiles"] = tile_accuracy
    measured["random_ensembles"] = read_frame(inp.random_ensembles)
    random_html = R.random_section(measured["random_ensembles"], read_frame(inp.random_seeds_needed),
                                   pd.read_parquet(inp.random_model_fits), inp.random_ensembles_chart,
                                   inp.random_maps_chart, surface_settings=snakemake.params.surface,
                                   accuracy=tile_accuracy,
                                   convergence=pd.read_parquet(inp.tile_convergence),
                                   tiles_png=inp.random_tiles_chart, plan=snakemake.params.plan)
explorer = None
if "explorer" in inp.keys():  # report.explorer.enabled
    with open(inp.explorer) as fh:
        explorer = json.load(fh)
provenance = {
    "versions": R.package_versions(),
    "inputs": [R.file_provenance(inp.study)],
    "settings": dict(snakemake.params.settings),
}
settings = snakemake.params.settings
html = R.build_report(tables, figures, config=dict(snakemake.params.config), provenance=provenance,
                      messages=summary["messages"], benchmarks=benchmarks, stability_html=stability_html,
                      table_aspects=settings["table_aspects"], table_incidence=settings["table_incidence"],
                      implicit_html=implicit_html, random_html=random_html,
                      followed=list(snakemake.params.followed), explorer=explorer, measured=measured)
R.write_report(snakemake.output[0], html)
log(f"report: {len(html) / 1e6:.1f} MB -> {snakemake.output[0]}")
