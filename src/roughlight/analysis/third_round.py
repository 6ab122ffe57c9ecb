"""The random-roughness claim's third round: fresh tiles for the tests the second round left *undecided*, measured
once and registered, and read by every run's verdict (docs/random-roughness.md, "A third round").

The second round's tested seeds are read, so a third round takes fresh seeds, never pooled with them (that would be
optional stopping), under a family of its own: the tests left undecided (in the unrounded reading), at the level
``1 - ALPHA / their count``. :func:`plan` gives each its seeds by the design's own rule
(:func:`roughlight.analysis.claims.planned_seeds`), with the second round's tested readings as its pilots; an
ensemble's fresh tiles are the most any of its tests asks for, seeds ``THIRD_ROUND_BASE + 1 ...`` (none a tested
tile's or a pilot's). The round costs more than the default workflow's budget allows (about 66 job-seconds), so it
is measured once (:func:`main`: ``make claim-third-round``), as rule ``claim_sweeps`` measures the tested tiles,
and its pooled readings registered (``claims.registered_third_round``, config/claim_third_round.csv, as the pilots'
are in config/claim_pilots.csv). A run's verdict (rule ``analysis_random``, :func:`with_third_round`) takes the
registered readings of an ensemble only where they were measured with today's settings (:func:`round_key`) and
planned from today's second round (:func:`basis`); each test the second round left undecided in either reading
is then decided by the third round's tiles alone, at its level, against the second round's margins.

Readings are :func:`roughlight.analysis.claim_readings.pooled_readings`' (degrees, 8-bit levels).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import time
from pathlib import Path

import numpy as np
import pandas as pd

from ..study import config as rl_config
from ..study import plan as rl_plan
from . import claims as C
from .claim_readings import READINGS, lobe_centres, pooled_readings

__all__ = ["THIRD_ROUND_BASE", "ALPHA", "COLUMNS", "plan", "basis", "round_seeds", "round_key", "round_readings",
           "register", "read_registered", "applicable", "render_round", "with_third_round", "stale", "main"]

#: The third round's seeds are this + 1, + 2, ...: above the tested tiles' (from 201) and below the pilots' (501).
THIRD_ROUND_BASE = 300
#: The claim's family error, shared by the round's tests.
ALPHA = 0.05
#: A registered round: an ensemble's pooled readings (``statistic``, a number in ``value``, or in ``text`` the reason
#: a lobe could not be read, ``{lobe}_why``)
#: in each of the claim's readings, with the settings they were measured with (``key``), the second round they were
#: planned from (``basis``), the round's ``level`` and its fresh ``seeds``.
COLUMNS = ["kind", "truncation", "aspect", "incidence", "key", "basis", "level", "seeds", "claim_reading",
           "statistic", "value", "text"]
ENSEMBLE = ["kind", "truncation", "aspect", "incidence"]


def plan(claims: pd.DataFrame, reading: str = "unrounded", alpha: float = ALPHA) -> tuple[pd.DataFrame, float]:
    """The third round's plan from a second round's verdict (:func:`roughlight.analysis.claims.claim_table`): a row
    a test left undecided in ``reading`` (the ensemble, ``test``, round 2's ``mean``, ``se``, ``seeds``,
    ``regular`` and ``margin``; ``fresh`` seeds planned, 0 where it waits on its lobe test or no number decides;
    ``why``), and the round's level."""
    undecided = claims[(claims["reading"] == reading) & (claims["verdict"] == "undecided")]
    level = 1.0 - alpha / max(len(undecided), 1)
    rows = []
    for _, row in undecided.iterrows():
        role = "lobe" if C.TESTS[row["test"]]["role"] == "lobe" else "shape"
        n, why = C.planned_seeds(row["mean"], row["se"], int(row["seeds"]), row["regular"], row["margin"], level, role)
        rows.append({**{k: row[k] for k in ENSEMBLE + ["test", "mean", "se", "regular", "margin"]},
                     "seeds": int(row["seeds"]), "fresh": int(n or 0), "why": why})
    columns = ENSEMBLE + ["test", "mean", "se", "regular", "margin", "seeds", "fresh", "why"]
    return pd.DataFrame(rows, columns=columns), level


def basis(planned: pd.DataFrame, level: float) -> str:
    """What a plan rests on, as a digest (SHA-256, 16 hex digits): each planned test's ensemble, round 2's reading
    and seeds, its margin and its fresh seeds, and the level. Numbers enter to 6 significant digits: the exact
    reference's own last digits (which moved by 1e-9 of a level when its clipper moved to C) must not stale a round
    whose plan they do not change."""
    rows = [[str(r["kind"]), *(f"{float(r[k]):.9g}" for k in ("truncation", "aspect", "incidence")), str(r["test"]),
             *(f"{float(r[k]):.6g}" for k in ("mean", "se", "regular", "margin")), int(r["seeds"]), int(r["fresh"])]
            for _, r in planned.iterrows()]
    return hashlib.sha256(json.dumps([rows, f"{level:.6g}"]).encode()).hexdigest()[:16]


def round_seeds(n: int, base: int = THIRD_ROUND_BASE) -> list[int]:
    """A registered round's first ``n`` seeds (``base`` + 1 ...; the third round's by default)."""
    return [base + k for k in range(1, int(n) + 1)]


def round_key(measured: dict, kind: str, truncation: float, aspect: float, incidence: float, n: int,
              base: int = THIRD_ROUND_BASE) -> str:
    """What an ensemble's ``n`` tiles of a registered round are measured with, as a digest: the pilots' key
    (:func:`roughlight.study.plan.claim_tiles_key`) of the round's seeds (``measured``:
    :func:`roughlight.study.plan.claim_measurement`; ``base``: the round's, :func:`round_seeds`)."""
    return rl_plan.claim_tiles_key(measured, kind, float(truncation), float(aspect), incidence,
                                   round_seeds(n, base))


def _fresh(planned: pd.DataFrame) -> dict:
    """Each planned ensemble's fresh tiles: the most any of its tests asks for (ensembles with none left out)."""
    most = planned.groupby(ENSEMBLE, sort=False)["fresh"].max()
    return {key: int(n) for key, n in most.items() if n > 0}


def round_readings(rows: pd.DataFrame, geometry: pd.DataFrame, steps: tuple[float, float],
                   error: str = "jackknife") -> dict:
    """(kind, truncation, aspect, incidence, reading) -> the ensemble's pooled readings in that claim reading, from
    its tiles' rows (:func:`roughlight.study.tables.claim_rows`), as rule ``analysis_random`` reads the tested
    tiles (``error``: their standard errors', :func:`roughlight.analysis.claim_readings.pooled_readings`)."""
    return {key + (reading,): pooled_readings(stack, lobe_centres(key[1:]), C.discs(geometry, key[1:]), reading,
                                              error)
            for key, stack in C.seed_stacks_of(rows, steps).items() for reading in READINGS}


def register(readings: dict, planned: pd.DataFrame, level: float, measured: dict,
             base: int = THIRD_ROUND_BASE) -> pd.DataFrame:
    """The registered table (:data:`COLUMNS`) of a measured round (seeds from ``base`` + 1): each ensemble's
    readings with its key, the plan's basis, the level and its fresh seeds."""
    fresh, digest, rows = _fresh(planned), basis(planned, level), []
    for (kind, t, a, i, reading), pooled in readings.items():
        n = fresh[(kind, t, a, i)]
        key = round_key(measured, kind, t, a, i, n, base)
        for statistic, value in pooled.items():
            text = statistic.endswith("_why")  # why a lobe could not be read ("" where it could); the rest numbers
            rows.append([kind, float(t), float(a), float(i), key, digest, level, n, reading, statistic,
                         np.nan if text else float(value), str(value) if text else ""])
    return pd.DataFrame(rows, columns=COLUMNS)


def read_registered(path) -> pd.DataFrame:
    """A registered round (:data:`COLUMNS`) from CSV; an empty table where ``path`` is empty or None. Raises
    ValueError naming a column that is missing."""
    if not path:
        return pd.DataFrame(columns=COLUMNS)
    table = pd.read_csv(path, keep_default_na=False, na_values={"value": ["", "nan", "NaN"]})
    missing = [c for c in COLUMNS if c not in table.columns]
    if missing:
        raise ValueError(f"{path}: not a registered third round (no column {', '.join(missing)})")
    return table


def _why_not(first, digest: str, measured: dict, key, base: int) -> str:
    """Why a registered ensemble's readings do not apply today ("" where they do)."""
    if first["basis"] != digest:
        return "planned from other readings of the earlier rounds"
    if first["key"] != round_key(measured, *key, int(first["seeds"]), base):
        return "measured with other settings"
    return ""


def applicable(registered: pd.DataFrame, digest: str, measured: dict,
               base: int = THIRD_ROUND_BASE) -> tuple[dict, list]:
    """(ensemble, reading) -> pooled readings of a registered round's ensembles (seeds from ``base`` + 1) measured
    with today's settings and planned from today's earlier rounds (``digest``: the plan's :func:`basis`), with
    their seeds and level; and the others, each with why not."""
    out, stale = {}, []
    for (kind, t, a, i, reading), part in registered.groupby(ENSEMBLE + ["claim_reading"], sort=False):
        first = part.iloc[0]
        pooled = {s: (text if s.endswith("_why") else float(v))
                  for s, v, text in zip(part["statistic"], part["value"], part["text"])}
        pooled["seeds"] = int(pooled.get("seeds", -1))
        why = _why_not(first, digest, measured, (kind, t, a, i), base) or (
            "not the tiles its plan asked for" if pooled["seeds"] != int(first["seeds"]) else "")
        if why:
            stale.append(((kind, float(t), float(a), float(i), reading), why))
            continue
        out[(kind, float(t), float(a), float(i), reading)] = (pooled, int(first["seeds"]), float(first["level"]))
    return out, stale


def stale(claims: pd.DataFrame, registered: pd.DataFrame, measured: dict) -> list:
    """The registered third round's ensembles a run (its second round's verdict, ``claims``) does not take:
    ``(ensemble and reading, why)`` pairs, :func:`applicable`'s (why: planned from other readings of the earlier
    rounds, measured with other settings, or not the tiles its plan asked for; ``make claim-third-round`` measures
    the round again)."""
    if not len(registered):
        return []
    planned, level = plan(claims)
    return applicable(registered, basis(planned, level), measured)[1]



def with_third_round(claims: pd.DataFrame, registered: pd.DataFrame, design: pd.DataFrame, margins: pd.DataFrame,
                     measured: dict) -> pd.DataFrame:
    """The verdict with the third round where it applies: each test the second round (``claims``) left undecided in
    a reading, whose ensemble a registered round (:func:`read_registered`) measured with today's settings and
    planned from today's second round, decided by that round's tiles alone at its level (``round`` 3, its ``why``
    saying so); every other row as it was (``round`` 2). ``measured``: the run's
    :func:`roughlight.study.plan.claim_measurement`."""
    out = claims.copy()
    out["round"] = 2
    planned, level = plan(claims)
    rounds = applicable(registered, basis(planned, level), measured)[0] if len(registered) else {}
    if not rounds:
        return out
    tested = {key: pooled for key, (pooled, _, _) in rounds.items()}
    ensembles = pd.DataFrame([key[:4] for key in rounds], columns=ENSEMBLE).drop_duplicates()
    third = C.claim_table(tested, design.merge(ensembles, on=ENSEMBLE).assign(level=level), margins)
    index = ENSEMBLE + ["test", "reading"]
    at = {tuple(r): n for n, r in enumerate(out[index].itertuples(index=False))}
    for _, row in third.iterrows():
        n = at.get(tuple(row[index]))
        if n is None or out.at[n, "verdict"] != "undecided":
            continue
        for column in third.columns:
            out.at[n, column] = row[column]
        out.at[n, "why"] = f"round 3 ({int(row['seeds'])} fresh seeds at {level:.2%}): {row['why']}"
        out.at[n, "round"] = 3
    return out


def render_round(planned: pd.DataFrame, config: dict, geometry: pd.DataFrame, out: Path, log,
                 base: int = THIRD_ROUND_BASE, taken: tuple = ()) -> list[str]:
    """Each planned ensemble's fresh tiles (seeds from ``base`` + 1) measured as rule ``claim_sweeps`` measures
    the tested ones, a file a seed under ``out`` (one kept from an interrupted run is not measured again); returns
    the ensembles' folders. Raises ValueError where a seed is a tested tile's, a pilot's or in ``taken``."""
    from ..study.tables import run_sweep
    from ..surfaces.roughness import make_surface
    from .claim_instrument import claim_views

    sweep, folders = rl_plan.sweep_settings(config), []
    for (kind, t, a, i), n in _fresh(planned).items():
        seeds = round_seeds(n, base)
        if set(seeds) & set(rl_config.claim_seeds(config, kind, (t, a)) + rl_config.pilot_seeds(config) + list(taken)):
            raise ValueError(f"the round's seeds {seeds[0]}-{seeds[-1]} meet the tested, the pilot or an earlier "
                             "round's tiles' seeds")
        views = claim_views(geometry, (t, a, i), sweep["azimuth_step"], sweep["elevation_step"])
        folder = out / f"i{i:g}" / kind / f"t{t:g}_a{a:g}"
        folder.mkdir(parents=True, exist_ok=True)
        start = time.perf_counter()
        for seed in seeds:
            path = folder / f"s{seed}.parquet"
            if not path.exists():
                run_sweep(str(path), surface=make_surface(**rl_plan.surface_settings(config, kind, t, a, seed,
                                                                                       claim=True)),
                          incidence=i, sweep=sweep, lighting=rl_plan.lighting(config),
                          method=config["render"]["method"], render=rl_plan.render_settings(config, "random"),
                          views=views)
        log(f"{kind} t {t:g}, a {a:g}: {n} fresh tiles (seeds {seeds[0]}-{seeds[-1]}, {len(views[0])} views each) "
            f"in {time.perf_counter() - start:.1f} s")
        folders.append(str(folder))
    return folders


def main(argv=None) -> None:
    """``python -m roughlight.analysis.third_round ANALYSIS REGISTERED [--work DIR] [--config FILE]``: plan the
    round from a finished run's second round (``ANALYSIS``: its results/analysis, whose
    ``random_claims_round2.csv`` is rule ``analysis_random``'s second-round verdict), measure its tiles under
    ``DIR`` and write their readings to ``REGISTERED`` (atomically), printing the plan and the round's verdicts."""
    from ..atomic import write_text_atomic
    from ..study.tables import claim_rows

    parser = argparse.ArgumentParser(description=main.__doc__.split("\n\n")[0])
    parser.add_argument("analysis", type=Path)
    parser.add_argument("registered", type=Path)
    parser.add_argument("--work", type=Path, default=Path("results/claims/third"))
    parser.add_argument("--config", type=Path, default=Path("config/config.yaml"))
    args = parser.parse_args(argv)
    import yaml

    config = rl_config.validate_config(yaml.safe_load(args.config.read_text()))
    claims = pd.read_csv(args.analysis / "random_claims_round2.csv")
    planned, level = plan(claims)
    print(f"{len(planned)} tests undecided (unrounded), the round's level {level:.4f}:\n"
          + planned.drop(columns=["regular", "margin"]).to_string(index=False))
    geometry = pd.read_csv(args.analysis / "random_claim_geometry.csv")
    sweep = rl_plan.sweep_settings(config)
    steps = (float(sweep["azimuth_step"]), float(sweep["elevation_step"]))
    folders = render_round(planned, config, geometry, args.work, print)
    readings = round_readings(claim_rows(folders), geometry, steps) if folders else {}
    if not folders:
        print("no test the second round left undecided can be planned: nothing to measure (an empty round registered)")
    measured = rl_plan.claim_measurement(config)
    table = register(readings, planned, level, measured)
    write_text_atomic(args.registered, table.to_csv(index=False))
    decided = with_third_round(claims, table, pd.read_csv(args.analysis / "random_claim_design.csv"),
                               pd.read_csv(args.analysis / "random_claim_margins.csv"), measured)
    print(decided[decided["round"] == 3][ENSEMBLE + ["test", "reading", "seeds", "mean", "low", "high", "margin",
                                                     "regular", "verdict"]].to_string(index=False))


if __name__ == "__main__":
    main()
