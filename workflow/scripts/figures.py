"""Snakemake adapter: the study and the analysis tables -> the report's drawn figures (no rendering).

Which figures: :data:`roughlight.report.registry.FIGURES` (those rule ``figures`` draws). Each figure's function in
:mod:`roughlight.report.figures` names what it needs by its parameters; they are given from the inputs
(tables, by input name) and the settings (the table aspects and incidence, the light, ...).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.analysis.inputs import STUDY_COLUMNS  # noqa: E402
from roughlight.atomic import read_frame  # noqa: E402
from roughlight.report import figures as F  # noqa: E402
from roughlight.study.tables import read_study  # noqa: E402

log = _log.setup(snakemake)


class Inputs(dict):
    """The rule's input tables by name, each read when a figure first asks for it."""

    def __contains__(self, name):
        return name in snakemake.input.keys()

    def __missing__(self, name):
        path = snakemake.input[name]
        if name == "study":  # the thesis's figures are of the regular surface; the random ones: analysis_random.py
            frame = read_study(path, rows="regular", columns=STUDY_COLUMNS["figures"])
        else:
            frame = pd.read_parquet(path) if path.endswith(".parquet") else read_frame(path)
        self[name] = frame
        return frame


for name, fig in F.drawn_figures(Inputs(), snakemake.params.settings):
    F.save(name, fig, snakemake.output[name])
    log(f"{name} -> {snakemake.output[name]}")
_log.end_job()
