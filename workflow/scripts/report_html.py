"""Snakemake adapter: analysis tables and figures -> reports/roughlight_report.html (self-contained)."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight import report as R  # noqa: E402
from roughlight.atomic import read_frame  # noqa: E402

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
    "timings": read_frame(inp.timings),
    "glm_summary": read_frame(inp.glm_summary),
    "glm_coefficients": read_frame(inp.glm_coefficients),
    "glm_messages": glm_messages,
    "model_fits": pd.read_parquet(inp.fits),
    "model_fits_summary": read_frame(inp.fits_summary),
}
figures = {os.path.splitext(os.path.basename(p))[0]: p for p in inp.figures}
benchmarks = None
bench = list(inp.benchmarks)
if bench:
    png = next((p for p in bench if p.endswith(".png")), None)
    table = next((pd.read_parquet(p) for p in bench if p.endswith(".parquet")), None)
    benchmarks = {"png": png, "table": table}
stability_html = None
if len(inp.stability) == 3:
    from roughlight import stability as rl_stability

    png, safe_csv, table = inp.stability
    stability_html = rl_stability.report_section(
        {"safe_domain": pd.read_csv(safe_csv), "stability": pd.read_parquet(table)}, png
    )
provenance = {
    "versions": R.package_versions(),
    "inputs": [R.file_provenance(inp.study)],
    "settings": dict(snakemake.params.settings),
}
html = R.build_report(tables, figures, config=dict(snakemake.params.config), provenance=provenance,
                      messages=summary["messages"], benchmarks=benchmarks, stability_html=stability_html)
R.write_report(snakemake.output[0], html)
log(f"report: {len(html) / 1e6:.1f} MB -> {snakemake.output[0]}")
