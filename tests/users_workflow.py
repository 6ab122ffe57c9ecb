"""The user-grid issue's grid through snakemake, once a test session, for two tests to read.

The grid runs in one workflow copy, a user's ``--configfile`` over config/config.yaml as shipped (every report
section). What its report and tables say is kept in ``grids/<k>/`` (:data:`KEPT`), for ``tests/test_user_grids.py``
to check the whole report; the copy itself ends finished, for ``tests/test_report.py`` to check it is, build
Snakemake's own report and follow report settings from it. One run serves both: apart, each built a whole workflow
of its own (issue 46).

Of the issue's two grids (:data:`ISSUE_GRIDS`), the second runs here: its four truncations and two aspects give the
report a table aspect to follow to, and one random kind. The first runs no rule the second does not: it is built
in one process instead (``tests/report_chain.py``, an example of ``test_any_users_grid_gives_the_whole_report``),
8 CPU-seconds against the 50 s its snakemake run added to the session's longest fixture.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import yaml

from .report_chain import resolved
from .workflow_copy import REPO, SNAKEMAKE, copy_workflow

#: config/config.yaml as shipped: what a user's --configfile edits.
DEFAULT = yaml.safe_load((REPO / "config" / "config.yaml").read_text())

#: The study's seeds and the claim's tested seeds of each random kind in the user-grid tests:
#: they vary the grid, and the ensembles' size and the claim's design have tests of their own (tests/test_random.py,
#: tests/test_claims.py); the shipped counts would add half again to every report built there (issue 46: the random
#: sweeps were most of an example's time).
SEEDS = 2
CLAIM_SEEDS = 2
#: The claim's pilots and tile size there: its tiles are a design's (tests/test_claims.py has the design's tests);
#: two pilots of two cells a side cost these runs what the claim's two tested 4-cell tiles did before it had them.
CLAIM_TILES = {"seeds": CLAIM_SEEDS, "pilots": 2, "cells": 2}
#: The measurements' size in these runs (measurements.plan): the grid-independent sections (speed and accuracy,
#: stability, the implicit surface, light transport, the random tiles' benchmark) are on the page whatever the grid,
#: and each measurement has tests of its own; at the shipped quick plan they were 57 of the runs' 97 job-seconds
#: (issue 46).
MEASUREMENTS = {"plan": "smoke"}
#: An export of a few nodes (rule export's scripts run end to end in seconds; its accuracy has tests of its own).
TINY_EXPORT = {"surfaces": [[0.5, 1.0]],
               "table": {"incidence": [0, 30, 60, 90], "edge_on": False, "light_azimuth": [0, 45],
                         "elevation": [5, 30, 90], "azimuth_step": 45},
               "mitsuba": {"elevation": [10, 45, 90], "phi_nodes": 3, "resolution": 8},
               "check": {"lights": 1, "views": 20}}

#: The issue's grids, each a user's --configfile.
ISSUE_GRIDS = [
    {"grid": {"truncation": [0.3, 1.0], "aspect": [0.6]}, "sweep": {"elevation_step": 30, "azimuth_step": 90},
     "surface": {"seeds": SEEDS}, "claims": CLAIM_TILES, "export": TINY_EXPORT,
     "measurements": MEASUREMENTS},
    {"grid": {"truncation": [0.2, 0.5, 0.8, 1.0], "aspect": [0.4, 0.9], "incidence": [45]},
     "sweep": {"elevation_step": 30, "azimuth_step": 90}, "surface": {"kind": "random_pyramids", "seeds": SEEDS},
     "claims": CLAIM_TILES, "export": TINY_EXPORT, "measurements": MEASUREMENTS},
]
#: The grids snakemake runs, one after the other in one directory (the module's docstring says why the second alone).
GRIDS = ISSUE_GRIDS[1:]

#: What each grid's run leaves that the tests read, kept under ``grids/<k>/`` by its name there (the run's log as
#: ``snakemake.log``).
KEPT = {"report.html": "reports/roughlight_report.html", "study.parquet": "results/study.parquet",
        "thesis_tables.csv": "results/analysis/thesis_tables.csv", "export_summary.csv": "results/export/summary.csv"}


def merged(base: dict, edits: dict) -> dict:
    """``edits`` over ``base``, mapping by mapping (as snakemake merges a --configfile over the Snakefile's)."""
    out = json.loads(json.dumps(base))
    for key, value in edits.items():
        out[key] = merged(out.get(key, {}), value) if isinstance(value, dict) else value
    return out


def grid_config(k: int) -> tuple[dict, list[str]]:
    """The config grid ``k``'s run ran with (defaults filled, the grid's followers set) and its follow notes."""
    return resolved(merged(DEFAULT, GRIDS[k]))


def user_file(workdir: Path, k: int) -> Path:
    """The --configfile of grid ``k``."""
    return workdir / f"user{k}.yaml"


def kept(workdir: Path, k: int) -> Path:
    """Where grid ``k``'s run left its log, report and tables (:data:`KEPT`)."""
    return workdir / "grids" / str(k)


def run_grids(workdir: Path) -> Path:
    """Copy the workflow into ``workdir`` and run :data:`GRIDS` there one after the other (``snakemake --cores 2
    --configfile user<k>.yaml``), keeping what each run left (:func:`kept`). A failed run raises with its log."""
    copy_workflow(workdir)
    env = {**os.environ, "PYOPENGL_PLATFORM": "osmesa"}
    for k, grid in enumerate(GRIDS):
        user = user_file(workdir, k)
        user.write_text(yaml.safe_dump(grid))
        proc = subprocess.run([SNAKEMAKE, "--cores", "2", "--configfile", str(user)], cwd=workdir,
                              capture_output=True, text=True, timeout=900, env=env)
        log = proc.stdout + proc.stderr
        assert proc.returncode == 0, log[-4000:]
        out = kept(workdir, k)
        out.mkdir(parents=True)
        (out / "snakemake.log").write_text(log)
        for name, path in KEPT.items():
            shutil.copy2(workdir / path, out / name)
    return workdir
