"""Snakemake adapter: analysis tables and figures -> reports/roughlight_report.html (self-contained).

Every input is handed to the page's sections by its name in the rule (the analysis outputs' file stems, a chart's
stem and _png: roughlight.report.sections), with the params by theirs.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.report import page as R  # noqa: E402
from roughlight.study.tables import renderers  # noqa: E402

log = _log.setup(snakemake)
inp, params = snakemake.input, snakemake.params
inputs = R.read_inputs({name: inp[name] for name in inp.keys() if name != "study"})  # the study: its provenance
settings = dict(params.settings)
provenance = {"versions": R.package_versions(), "inputs": [R.file_provenance(inp.study)], "settings": settings,
              "renderers": renderers([inp.study])}
html = R.build_report(inputs, config=dict(params.config), provenance=provenance, followed=list(params.followed),
                      plan=params.plan, surface_settings=params.surface_settings,
                      table_aspects=settings["table_aspects"], table_incidence=settings["table_incidence"])
R.write_report(snakemake.output[0], html)
log(f"report: {len(html) / 1e6:.1f} MB -> {snakemake.output[0]}")
_log.end_job()
