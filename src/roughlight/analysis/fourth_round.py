"""The random-roughness claim's fourth round: the claim's own direction, for the shape tests that no number of seeds
decides two-sided (docs/random-roughness.md, "A fourth round").

Rounds 2 and 3 read a shape test two-sided: a *difference* when its interval lies beyond the margin around the
regular value, *no difference* when within it, where the margin is the larger of the instrument's and the smallest
difference that matters (:data:`roughlight.analysis.claims.TESTS`' ``matters``). A test whose mean sits on that
margin's edge stays *undecided* at any number of seeds: a verdict the instrument cannot reach. The thesis's claim,
though, has a direction (``TESTS[test]["expected"]``: random lobes rounder, less phase-shifted), and this round asks
that question alone, one-sided: does the random lobe lie further the claim's way than the regular one, by more than
the instrument alone can make of the regular surface? The **threshold** is the regular value less (for
``expected`` "below"; plus, for "above") the instrument's margin: the largest of the regular surface's rendering
noise, the fast method's sampling error and the view grid's effect, and, at 8 bits, rounding (the margin of rounds 2
and 3 without ``matters``). The verdict, on the round's fresh tiles alone:

* *difference* (as claimed): the interval lies wholly beyond the threshold, the claim's way;
* *not as claimed*: wholly on the regular value's side of it: the random lobe is not rounder (less shifted) than
  the regular one by anything the instrument can tell; it may be the same, or further the other way;
* *undecided* otherwise.

Its tests are every shape test still *undecided* (unrounded) after the third round; its family their own (:data:`ALPHA`
shared, Bonferroni), its seeds planned by the design's own rule (:func:`roughlight.analysis.claims.planned_seeds`,
``role`` "direction") from the earlier rounds' readings of each test, fresh seeds from :data:`FOURTH_ROUND_BASE` + 1
(none a tested tile's, a pilot's or the third round's). It is measured once and registered as the third round is
(:mod:`roughlight.analysis.third_round`; ``make claim-fourth-round``, ``claims.registered_fourth_round``), and a run's
verdict (rule ``analysis_random``, :func:`with_fourth_round`) takes an ensemble's registered readings only where
they were measured with today's settings and planned from today's earlier rounds.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from . import claims as C
from . import third_round as T

__all__ = ["FOURTH_ROUND_BASE", "ALPHA", "MAX_SEEDS", "INSTRUMENT", "instrument_margin", "threshold", "plan",
           "direction_verdict", "with_fourth_round", "stale_ensembles", "main"]

#: The fourth round's seeds are this + 1, + 2, ...: above the pilots' (501 on) and the third round's (301 on).
FOURTH_ROUND_BASE = 600
#: The round's family error, shared by its tests.
ALPHA = 0.05
#: The most fresh seeds the round's plan may ask of an ensemble (seeds up to 800).
MAX_SEEDS = 200
#: The parts of a margin that are the instrument's own (:func:`roughlight.analysis.claims.margins`).
INSTRUMENT = ("rendering_noise", "sampling_error", "grid_effect")


def instrument_margin(margins: pd.DataFrame, row, reading: str) -> float:
    """The instrument's own margin of a test (``row``: its ensemble and ``test``) in ``reading``: the largest of
    :data:`INSTRUMENT` in the margin table (:func:`roughlight.analysis.claims.margins`), and at 8 bits rounding,
    never the difference that matters; 0 where none is known."""
    at = margins[(margins["kind"] == row["kind"]) & np.isclose(margins["truncation"], float(row["truncation"]))
                 & np.isclose(margins["aspect"], float(row["aspect"]))
                 & np.isclose(margins["incidence"], float(row["incidence"]))
                 & (margins["test"] == row["test"]) & (margins["reading"] == reading)]
    if not len(at):
        raise ValueError(f"no margin for {row['kind']} t {row['truncation']:g}, a {row['aspect']:g}, "
                         f"{row['test']} ({reading})")
    parts = list(INSTRUMENT) + (["rounding"] if reading == "8-bit" else [])
    values = [float(at.iloc[0][p]) for p in parts if p in at.columns and np.isfinite(float(at.iloc[0][p]))]
    return max(values, default=0.0)


def threshold(regular: float, margin: float, expected: str) -> float:
    """The value a random lobe must pass, the claim's way (``expected`` "below" or "above"), to differ from the
    regular value by more than the instrument's ``margin``."""
    return regular - margin if expected == "below" else regular + margin


def plan(claims: pd.DataFrame, margins: pd.DataFrame, reading: str = "unrounded",
         alpha: float = ALPHA) -> tuple[pd.DataFrame, float]:
    """The fourth round's plan from the verdict after the third round (``claims``: rule ``analysis_random``'s,
    :func:`roughlight.analysis.third_round.with_third_round`): a row a shape test with a direction still
    *undecided* in ``reading`` (the ensemble, ``test``, its latest ``mean``, ``se`` and ``seeds``, ``regular``,
    the instrument's ``margin`` and the ``threshold``; ``fresh`` seeds planned, 0 where no count up to
    :data:`MAX_SEEDS` decides it; ``why``), and the round's level ``1 - alpha / their count``."""
    shape = claims["test"].map(lambda t: C.TESTS[t]["role"] == "shape" and "expected" in C.TESTS[t])
    open_ = claims[(claims["reading"] == reading) & (claims["verdict"] == "undecided") & shape]
    open_ = open_[np.isfinite(open_["mean"].astype(float))]  # a shape test waiting on its lobe has no reading
    level = 1.0 - alpha / max(len(open_), 1)
    rows = []
    for _, row in open_.iterrows():
        margin = instrument_margin(margins, row, reading)
        edge = threshold(float(row["regular"]), margin, C.TESTS[row["test"]]["expected"])
        n, why = C.planned_seeds(row["mean"], row["se"], int(row["seeds"]), row["regular"], edge, level,
                                 "direction", MAX_SEEDS)
        rows.append({**{k: row[k] for k in T.ENSEMBLE + ["test", "mean", "se", "regular"]}, "margin": margin,
                     "threshold": edge, "seeds": int(row["seeds"]), "fresh": int(n or 0),
                     "why": why.replace("the pilot", "the earlier rounds' tested seeds")})
    columns = T.ENSEMBLE + ["test", "mean", "se", "regular", "margin", "threshold", "seeds", "fresh", "why"]
    return pd.DataFrame(rows, columns=columns), level


def direction_verdict(low: float, high: float, edge: float, expected: str) -> tuple[str, str]:
    """A test of the claim's direction from its interval [low, high] against the threshold ``edge``: "difference"
    (wholly beyond it the claim's way), "not as claimed" (wholly on the other side), or "undecided". Returns
    (verdict, why)."""
    beyond, short = (high < edge, low > edge) if expected == "below" else (low > edge, high < edge)
    if beyond:
        return "difference", f"the interval lies {expected} the threshold {edge:.3g} (as the thesis claims)"
    if short:
        return "not as claimed", (f"the interval lies wholly {'above' if expected == 'below' else 'below'} the "
                                  f"threshold {edge:.3g}: no further the claim's way than the regular lobe by "
                                  "anything the instrument can tell")
    return "undecided", f"the interval reaches across the threshold {edge:.3g}"


def _decided_row(row: pd.Series, pooled: dict, margins: pd.DataFrame, level: float) -> dict:
    """One test's round-4 values (columns of :data:`roughlight.analysis.claims.VERDICT_COLUMNS`) from the round's
    pooled readings of its ensemble in the row's reading."""
    spec = C.TESTS[row["test"]]
    mean, se, n = float(pooled.get(row["test"], np.nan)), float(pooled.get(f"{row['test']}_se", np.nan)), \
        int(pooled.get("seeds", 0))
    margin = instrument_margin(margins, row, row["reading"])
    edge = threshold(float(row["regular"]), margin, spec["expected"])
    out = {"seeds": n, "mean": mean, "se": se, "margin": margin, "level": level, "low": np.nan, "high": np.nan,
           "agrees": pd.NA, "seeds_to_decide": pd.NA}
    if not (np.isfinite(mean) and np.isfinite(se)) or n < 2:
        return {**out, "verdict": "undecided", "why": pooled.get(f"{spec['lobe']}_why") or "not read on every resample"}
    half = float(C.t_quantile(level, n) * se)
    lo, hi = spec["range"]
    out["low"], out["high"] = max(lo, mean - half), min(hi, mean + half)
    out["verdict"], out["why"] = direction_verdict(out["low"], out["high"], edge, spec["expected"])
    if out["verdict"] == "difference":
        out["agrees"] = True
    if out["verdict"] == "undecided":
        need = C.fewest_seeds(se * np.sqrt(n), abs(mean - edge), level, 10_000)
        out["seeds_to_decide"] = pd.NA if need is None else need
    return out


def with_fourth_round(claims: pd.DataFrame, registered: pd.DataFrame, margins: pd.DataFrame,
                      measured: dict) -> pd.DataFrame:
    """The verdict with the fourth round where it applies: each shape test the earlier rounds (``claims``, after
    :func:`roughlight.analysis.third_round.with_third_round`) left undecided, whose ensemble the registered round
    (:func:`roughlight.analysis.third_round.read_registered`) measured with today's settings and planned from
    today's earlier rounds, decided one-sided by that round's tiles alone (``round`` 4; its ``margin`` the
    instrument's, its ``why`` naming the round); every other row as it was."""
    out = claims.copy()
    if "round" not in out:
        out["round"] = 2
    if not len(registered):
        return out
    planned, level = plan(claims, margins)
    rounds = T.applicable(registered, T.basis(planned, level), measured, FOURTH_ROUND_BASE)[0]
    tests = {tuple(r[T.ENSEMBLE]) + (r["test"],) for _, r in planned.iterrows()}
    for n, row in out.iterrows():
        key = tuple(row[T.ENSEMBLE])
        if row["verdict"] != "undecided" or key + (row["test"],) not in tests or key + (row["reading"],) not in rounds:
            continue
        decided = _decided_row(row, rounds[key + (row["reading"],)][0], margins, level)
        for column, value in decided.items():
            out.at[n, column] = value
        out.at[n, "why"] = (f"round 4 ({decided['seeds']} fresh seeds at {level:.2%}, one-sided, the claim's direction "
                            f"against the instrument's margin {decided['margin']:.3g}): {decided['why']}")
        out.at[n, "round"] = 4
    return out


def stale_ensembles(claims: pd.DataFrame, registered: pd.DataFrame, margins: pd.DataFrame,
                    measured: dict) -> list[str]:
    """The registered fourth round's ensembles a run does not take (each reading once), as lines for its log
    (``claims``: the verdict after the third round)."""
    if not len(registered):
        return []
    planned, level = plan(claims, margins)
    _, stale = T.applicable(registered, T.basis(planned, level), measured, FOURTH_ROUND_BASE)
    return sorted({f"{k[0]} t {k[1]:g}, a {k[2]:g}, incidence {k[3]:g}: {why}" for k, why in stale})


def main(argv=None) -> None:
    """``python -m roughlight.analysis.fourth_round ANALYSIS REGISTERED [--work DIR] [--config FILE]``: plan the
    round from a finished run's verdict before it (``ANALYSIS``: its results/analysis; the second round's verdict
    ``random_claims_round2.csv`` with the registered third round of the config), measure its tiles under ``DIR``
    and write their readings to ``REGISTERED`` (atomically), printing the plan and the round's verdicts."""
    import yaml

    from ..atomic import write_text_atomic
    from ..study import config as rl_config
    from ..study import plan as rl_plan
    from ..study.tables import claim_rows

    parser = argparse.ArgumentParser(description=main.__doc__.split("\n\n")[0])
    parser.add_argument("analysis", type=Path)
    parser.add_argument("registered", type=Path)
    parser.add_argument("--work", type=Path, default=Path("results/claims/fourth"))
    parser.add_argument("--config", type=Path, default=Path("config/config.yaml"))
    args = parser.parse_args(argv)
    config = rl_config.validate_config(yaml.safe_load(args.config.read_text()))
    measured = rl_plan.claim_measurement(config)
    design = pd.read_csv(args.analysis / "random_claim_design.csv")
    margins = pd.read_csv(args.analysis / "random_claim_margins.csv")
    third = T.read_registered(rl_config.claims(config).get("registered_third_round") or None)
    claims = T.with_third_round(pd.read_csv(args.analysis / "random_claims_round2.csv"), third, design, margins,
                                measured)
    planned, level = plan(claims, margins)
    print(f"{len(planned)} shape tests undecided (unrounded) after round 3, the round's level {level:.4f}:\n"
          + planned.to_string(index=False))
    geometry = pd.read_csv(args.analysis / "random_claim_geometry.csv")
    sweep = rl_plan.sweep_settings(config)
    steps = (float(sweep["azimuth_step"]), float(sweep["elevation_step"]))
    taken = tuple(T.round_seeds(int(third["seeds"].max()))) if len(third) else ()
    folders = T.render_round(planned, config, geometry, args.work, print, FOURTH_ROUND_BASE, taken)
    readings = T.round_readings(claim_rows(folders), geometry, steps) if folders else {}
    table = T.register(readings, planned, level, measured, FOURTH_ROUND_BASE)
    write_text_atomic(args.registered, table.to_csv(index=False))
    decided = with_fourth_round(claims, table, margins, measured)
    print(decided[decided["round"] == 4][T.ENSEMBLE + ["test", "reading", "seeds", "mean", "low", "high", "margin",
                                                      "regular", "verdict"]].to_string(index=False))


if __name__ == "__main__":
    main()
