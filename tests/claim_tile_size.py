"""The claim's tile size from pilot seeds alone: how much each claim statistic of an ensemble's mean surface varies
from seed to seed, and what a tile costs, at several tile sizes (docs/random-roughness.md, "Its tiles").

    python tests/claim_tile_size.py                    # 8 pilots (seeds 501..508) at 4, 8 and 12 cells a side
    python tests/claim_tile_size.py --cells 4 8 --pilots 6
    python tests/claim_tile_size.py --cells 8 --azimuth-step 5 2.5 1   # the claim's tiles at finer view grids

Renders each random kind's pilot tiles at every random grid point of config/config.yaml, at the claim's views
(rule ``claim_sweeps``' views, from ``results/analysis/random_claim_geometry.csv`` of a finished run), in a temporary
folder; reads them as rule ``claim_design`` reads its pilots, against the margins of that run
(``random_claim_margins.csv``, unrounded). Prints, a test a row: the pilots' mean, their per-seed spread (the
jackknife error times sqrt(n)), the tested seeds the plan would ask for (:func:`roughlight.analysis.claims.
planned_seeds`, up to ``--max-seeds``) and the mean seconds a tile. Reads no tested seed.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")
os.environ.setdefault("LP_NUM_THREADS", "0")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import yaml  # noqa: E402

from roughlight.analysis import claims as C  # noqa: E402
from roughlight.analysis.claim_instrument import claim_views  # noqa: E402
from roughlight.analysis.claim_readings import lobe_centres, pooled_readings  # noqa: E402
from roughlight.study import config as rl_config  # noqa: E402
from roughlight.study import plan  # noqa: E402
from roughlight.study.tables import claim_rows, run_sweep  # noqa: E402
from roughlight.surfaces.roughness import make_surface  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def render_pilots(config: dict, geometry: pd.DataFrame, cells: int, pilots: int, folder: Path) -> dict:
    """Every random ensemble's pilots at ``cells`` cells a side, at the claim's views; returns the mean seconds a
    tile by (kind, truncation, aspect)."""
    sweep, lighting = plan.sweep_settings(config), plan.lighting(config)
    render, method = plan.render_settings(config, "random"), config["render"]["method"]
    seconds = {}
    for i in plan.grid(config, "incidence"):
        for kind, t, a, _ in plan.ensembles(config, "pilots"):
            views = claim_views(geometry, (t, a, float(i)), sweep["azimuth_step"], sweep["elevation_step"])
            out = folder / plan.ensemble_folder(kind, t, a, i, f"c{cells}")
            out.mkdir(parents=True, exist_ok=True)
            spent = []
            for seed in range(rl_config.CLAIM_PILOT_BASE + 1, rl_config.CLAIM_PILOT_BASE + pilots + 1):
                settings = {**plan.surface_settings(config, kind, t, a, seed, claim=True), "cells": cells}
                start = time.perf_counter()
                run_sweep(str(out / f"s{seed}.parquet"), make_surface(**settings), i, sweep, lighting, method, render,
                          views=views)
                spent.append(time.perf_counter() - start)
            seconds[(kind, t, a)] = float(np.mean(spent))
    return seconds


def spread_table(rows: pd.DataFrame, geometry: pd.DataFrame, margins: pd.DataFrame, steps, max_seeds: int) -> list:
    """A test a row of the pilots read as rule ``claim_design`` reads them."""
    plan_rows = margins[margins["reading"] == "unrounded"]
    level = 1.0 - 0.05 / len(plan_rows)
    out = []
    for key, stack in C.seed_stacks_of(rows, steps).items():
        read = pooled_readings(stack, lobe_centres(key[1:]), C.discs(geometry, key[1:]))
        for m in plan_rows[(plan_rows["kind"] == key[0]) & (plan_rows["truncation"] == key[1])
                           & (plan_rows["aspect"] == key[2])].itertuples(index=False):
            role = C.TESTS[m.test]["role"]
            mean, se = read.get(m.test, np.nan), read.get(f"{m.test}_se", np.nan)
            need, _ = C.planned_seeds(mean, se, read["seeds"], m.regular, m.margin, level, role, max_seeds)
            out.append({"kind": key[0], "truncation": key[1], "aspect": key[2], "test": m.test, "mean": mean,
                        "spread": se * np.sqrt(read["seeds"]), "regular": m.regular, "margin": m.margin,
                        "seeds_needed": need})
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cells", type=int, nargs="+", default=[4, 8, 12])
    parser.add_argument("--pilots", type=int, default=8)
    parser.add_argument("--max-seeds", type=int, default=400)
    parser.add_argument("--run", type=Path, default=ROOT, help="a finished run (its results/analysis/)")
    parser.add_argument("--azimuth-step", type=float, nargs="+", default=None,
                        help="the claim's views at these azimuth steps, degrees (default: the study's)")
    args = parser.parse_args()
    config = rl_config.validate_config(yaml.safe_load((ROOT / "config" / "config.yaml").read_text()))
    config["claims"]["pilots"] = args.pilots
    analysis = args.run / "results" / "analysis"
    geometry = pd.read_csv(analysis / "random_claim_geometry.csv")
    margins = pd.read_csv(analysis / "random_claim_margins.csv")
    table = []
    for azimuth_step in args.azimuth_step or [float(config["sweep"]["azimuth_step"])]:
        config["sweep"]["azimuth_step"] = azimuth_step
        steps = (float(azimuth_step), float(config["sweep"]["elevation_step"]))
        with tempfile.TemporaryDirectory() as tmp:
            for cells in args.cells:
                seconds = render_pilots(config, geometry, cells, args.pilots, Path(tmp))
                folders = sorted(str(p) for p in Path(tmp).glob(f"c{cells}/i*/*/*"))
                for row in spread_table(claim_rows(folders), geometry, margins, steps, args.max_seeds):
                    table.append({"cells": cells, "azimuth_step": azimuth_step, **row,
                                  "tile_s": seconds[(row["kind"], row["truncation"], row["aspect"])]})
    frame = pd.DataFrame(table).sort_values(["kind", "truncation", "aspect", "test", "cells", "azimuth_step"])
    frame["seeds_needed"] = pd.array(frame["seeds_needed"], dtype="Int64")
    with pd.option_context("display.width", 200, "display.max_rows", 500):
        print(frame.to_string(index=False, float_format=lambda v: f"{v:.3g}"))


if __name__ == "__main__":
    main()
