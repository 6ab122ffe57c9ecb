"""Snakemake adapter: the study and the analysis tables -> the report's drawn figures (no rendering).

Which figures: :data:`roughlight.registry.FIGURES` (those not rendered). Each figure's function in
:mod:`roughlight.figures` names what it needs by its parameters; they are given from the inputs
(tables, by input name) and the settings (the table aspects and incidence, the light, ...).
"""
import inspect
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight import figures as F  # noqa: E402
from roughlight import registry  # noqa: E402
from roughlight.atomic import read_frame  # noqa: E402
from roughlight.study import regular  # noqa: E402

log = _log.setup(snakemake)
inp, out, settings = snakemake.input, snakemake.output, snakemake.params.settings
tables = {}


def table(name):
    """An input table, read once when a figure first needs it."""
    if name not in tables:
        path = inp[name]
        tables[name] = pd.read_parquet(path) if path.endswith(".parquet") else read_frame(path)
        if name == "study":  # the thesis's figures are of the regular surface; the random ones: analysis_random.py
            tables[name] = regular(tables[name])
    return tables[name]


values = {
    "aspects": settings["table_aspects"],
    "incidence": settings["table_incidence"],
    "hapke_max_phase": settings["hapke_max_phase"],
}
for figure in registry.figures(rendered=False):
    draw = getattr(F, figure.draw)
    kwargs = {}
    for name in inspect.signature(draw).parameters:
        if name in values:
            kwargs[name] = values[name]
        elif name == "light":
            kwargs[name] = float(table("study")["light"].iloc[0])
        elif name in inp.keys():
            kwargs[name] = table(name)
    F.save_figure(draw(**kwargs), out[figure.name])
    log(f"{figure.name} -> {out[figure.name]}")
