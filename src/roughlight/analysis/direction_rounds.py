"""The random-roughness claim's rounds of its own direction (the fourth to the eighth): the shape tests that no number
of seeds decides two-sided, asked one-sided (docs/random-roughness.md, "A fourth round" to "An eighth round").

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

From the sixth round on, a round's standard errors come from a bootstrap over seeds in place of the design's
delete-one jackknife, which multiplies the cell-sized steps of a statistic read from a region by n - 1
(:func:`roughlight.analysis.claim_readings.pooled_readings`); the eighth also holds the second round's *no
difference* (:data:`ROUNDS` ``matters``), so that its planned interval decides wherever its mean lies.

A round's tests are every shape test still *undecided* (unrounded) after the rounds before it; its family their own
(:data:`ALPHA` shared, Bonferroni), its seeds planned by the design's own rule
(:func:`roughlight.analysis.claims.planned_seeds`, ``role`` "direction") from the latest readings of each test, fresh
seeds from its own base (:data:`ROUNDS`; none a tested tile's, a pilot's or an earlier round's). Each round is
measured once and registered as the third round is (:mod:`roughlight.analysis.third_round`; ``make
claim-fourth-round`` ... ``make claim-eighth-round``; ``claims.registered_fourth_round`` ...), and a run's verdict
(rule ``analysis_random``, :func:`with_direction_rounds`) takes an ensemble's registered readings only where they
were measured with today's settings and planned from today's earlier rounds."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from . import claims as C
from . import third_round as T

__all__ = ["ROUNDS", "ALPHA", "INSTRUMENT", "instrument_margin", "threshold", "matters_of", "plan", "direction_verdict",
           "with_direction_round", "with_direction_rounds", "later_rounds", "UNTAKEN_COLUMNS",
           "registered_spread", "earlier_spread", "registered_rounds", "main"]

#: Each round of the claim's direction: its seeds (``base`` + 1 ...: above the pilots' 501-600 and the third round's
#: 301 on, and below the next round's), the most its plan may ask of an ensemble, and its name (its config key
#: ``claims.registered_{name}_round``, its file ``config/claim_{name}_round.csv``).
#: ``error``: the standard error a round's readings carry (:func:`roughlight.analysis.claim_readings.pooled_readings`);
#: a round whose error is not the design's jackknife plans from the same error of the round before's tiles.
#: ``matters``: the round's verdicts also hold the second round's *no difference* (the interval within the
#: difference that matters around the regular value, which takes precedence), so that every interval narrower than
#: the difference that matters less the instrument's margin decides, wherever its mean lies; its seeds are planned
#: for that width (:func:`plan`).
ROUNDS = {
    4: {"name": "fourth", "base": 600, "max_seeds": 200, "error": "jackknife"},
    5: {"name": "fifth", "base": 800, "max_seeds": 1000, "error": "jackknife"},
    6: {"name": "sixth", "base": 1800, "max_seeds": 1000, "error": "bootstrap"},
    7: {"name": "seventh", "base": 2800, "max_seeds": 1000, "error": "bootstrap"},
    8: {"name": "eighth", "base": 3800, "max_seeds": 1000, "error": "bootstrap", "matters": True},
}
#: A registered round's statistic holding the error its plan took for a test (``PLAN_SE.format(test)``), where the
#: plan did not take the earlier round's own.
PLAN_SE = "plan_{}_se"
#: A round's family error, shared by its tests.
ALPHA = 0.05
#: The parts of a margin that are the instrument's own (:func:`roughlight.analysis.claims.margins`).
INSTRUMENT = ("rendering_noise", "sampling_error", "grid_effect")


def _margin_rows(margins: pd.DataFrame, row, reading: str) -> pd.DataFrame:
    """The margin table's rows (:func:`roughlight.analysis.claims.margins`) of a test (``row``: its ensemble and
    ``test``) in ``reading``."""
    return margins[(margins["kind"] == row["kind"]) & np.isclose(margins["truncation"], float(row["truncation"]))
                   & np.isclose(margins["aspect"], float(row["aspect"]))
                   & np.isclose(margins["incidence"], float(row["incidence"]))
                   & (margins["test"] == row["test"]) & (margins["reading"] == reading)]


def instrument_margin(margins: pd.DataFrame, row, reading: str) -> float:
    """The instrument's own margin of a test (``row``: its ensemble and ``test``) in ``reading``: the largest of
    :data:`INSTRUMENT` in the margin table (:func:`roughlight.analysis.claims.margins`), and at 8 bits rounding,
    never the difference that matters; 0 where none is known."""
    at = _margin_rows(margins, row, reading)
    if not len(at):
        raise ValueError(f"no margin for {row['kind']} t {row['truncation']:g}, a {row['aspect']:g}, "
                         f"{row['test']} ({reading})")
    parts = list(INSTRUMENT) + (["rounding"] if reading == "8-bit" else [])
    values = [float(at.iloc[0][p]) for p in parts if p in at.columns and np.isfinite(float(at.iloc[0][p]))]
    return max(values, default=0.0)


def matters_of(margins: pd.DataFrame, row, reading: str) -> float:
    """The smallest difference that matters of a test (``row``: its ensemble and ``test``) in ``reading``: the margin
    table's ``matters`` (:data:`roughlight.analysis.claims.TESTS`)."""
    at = _margin_rows(margins, row, reading)
    return float(at.iloc[0]["matters"]) if len(at) else float(C.TESTS[row["test"]]["matters"])


def threshold(regular: float, margin: float, expected: str) -> float:
    """The value a random lobe must pass, the claim's way (``expected`` "below" or "above"), to differ from the
    regular value by more than the instrument's ``margin``."""
    return regular - margin if expected == "below" else regular + margin


def plan(claims: pd.DataFrame, margins: pd.DataFrame, number: int = 4, reading: str = "unrounded",
         alpha: float = ALPHA, spread: dict | None = None) -> tuple[pd.DataFrame, float]:
    """Round ``number``'s plan from the verdict of the rounds before it (``claims``: rule ``analysis_random``'s
    second round with the registered later ones, :func:`roughlight.analysis.third_round.with_third_round` and
    :func:`with_direction_rounds`): a row a shape test with a direction still *undecided* in ``reading`` (the
    ensemble, ``test``, its latest ``mean``, ``se`` and ``seeds``, ``regular``, the instrument's ``margin`` and the
    ``threshold``; ``fresh`` seeds planned, 0 where no count up to the round's ``max_seeds`` decides it; ``why``),
    and the round's level ``1 - alpha / their count``. ``spread``: (kind, truncation, aspect, incidence, test) ->
    the standard error to plan from in place of the row's (the round's own error of the same tiles)."""
    shape = claims["test"].map(lambda t: C.TESTS[t]["role"] == "shape" and "expected" in C.TESTS[t])
    open_ = claims[(claims["reading"] == reading) & (claims["verdict"] == "undecided") & shape]
    open_ = open_[np.isfinite(open_["mean"].astype(float))]  # a shape test waiting on its lobe has no reading
    level = 1.0 - alpha / max(len(open_), 1)
    rows = []
    for _, row in open_.iterrows():
        margin = instrument_margin(margins, row, reading)
        edge = threshold(float(row["regular"]), margin, C.TESTS[row["test"]]["expected"])
        se = (spread or {}).get(tuple(row[T.ENSEMBLE]) + (row["test"],), row["se"])
        if ROUNDS[number].get("matters"):  # a width at which every interval decides
            width = matters_of(margins, row, reading) - margin
            n, why = C.planned_seeds(row["mean"], se, int(row["seeds"]), row["regular"], width, level, "decisive",
                                     ROUNDS[number]["max_seeds"])
        else:
            n, why = C.planned_seeds(row["mean"], se, int(row["seeds"]), row["regular"], edge, level,
                                     "direction", ROUNDS[number]["max_seeds"])
        rows.append({**{k: row[k] for k in T.ENSEMBLE + ["test", "mean", "regular"]}, "se": se, "margin": margin,
                     "threshold": edge, "seeds": int(row["seeds"]), "fresh": int(n or 0),
                     "why": why.replace("the pilot", "the earlier rounds' tested seeds")})
    columns = T.ENSEMBLE + ["test", "mean", "se", "regular", "margin", "threshold", "seeds", "fresh", "why"]
    return pd.DataFrame(rows, columns=columns), level


def direction_verdict(low: float, high: float, edge: float, expected: str,
                      band: tuple[float, float] | None = None) -> tuple[str, str]:
    """A test of the claim's direction from its interval [low, high] against the threshold ``edge``: "difference"
    (wholly beyond it the claim's way), "not as claimed" (wholly on the other side), or "undecided"; with ``band``
    (the regular value less and plus the difference that matters), "no difference" first, where the interval lies
    wholly within it. Returns (verdict, why)."""
    if band is not None and band[0] <= low and high <= band[1]:
        return "no difference", (f"the interval lies within the difference that matters around the regular value "
                                 f"[{band[0]:.3g}, {band[1]:.3g}]")
    beyond, short = (high < edge, low > edge) if expected == "below" else (low > edge, high < edge)
    if beyond:
        return "difference", f"the interval lies {expected} the threshold {edge:.3g} (as the thesis claims)"
    if short:
        return "not as claimed", (f"the interval lies wholly {'above' if expected == 'below' else 'below'} the "
                                  f"threshold {edge:.3g}: no further the claim's way than the regular lobe by "
                                  "anything the instrument can tell")
    return "undecided", f"the interval reaches across the threshold {edge:.3g}"


def _decided_row(row: pd.Series, pooled: dict, margins: pd.DataFrame, level: float, number: int) -> dict:
    """One test's values in round ``number`` (columns of :data:`roughlight.analysis.claims.VERDICT_COLUMNS`) from
    the round's pooled readings of its ensemble in the row's reading."""
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
    matters = matters_of(margins, row, row["reading"]) if ROUNDS[number].get("matters") else None
    band = None if matters is None else (float(row["regular"]) - matters, float(row["regular"]) + matters)
    out["verdict"], out["why"] = direction_verdict(out["low"], out["high"], edge, spec["expected"], band)
    if out["verdict"] == "difference":
        out["agrees"] = True
    if out["verdict"] == "undecided":
        need = C.fewest_seeds(se * np.sqrt(n), abs(mean - edge), level, 10_000)
        out["seeds_to_decide"] = pd.NA if need is None else need
    return out


def with_direction_round(claims: pd.DataFrame, registered: pd.DataFrame, margins: pd.DataFrame, measured: dict,
                         number: int = 4) -> pd.DataFrame:
    """The verdict with round ``number`` where it applies: each shape test the rounds before it (``claims``) left
    undecided, whose ensemble the registered round (:func:`roughlight.analysis.third_round.read_registered`)
    measured with today's settings and planned from today's earlier rounds, decided one-sided by that round's tiles
    alone (``round`` ``number``; its ``margin`` the instrument's, its ``why`` naming the round); every other row as
    it was."""
    return _round_applied(claims, registered, margins, measured, number)[0]


def _round_applied(claims: pd.DataFrame, registered: pd.DataFrame, margins: pd.DataFrame, measured: dict,
                   number: int) -> tuple[pd.DataFrame, list]:
    """:func:`with_direction_round`'s verdict, and the registered ensembles it did not take (``(ensemble and
    reading, why)`` pairs, :func:`roughlight.analysis.third_round.applicable`'s)."""
    out = claims.copy()
    if "round" not in out:
        out["round"] = 2
    if not len(registered):
        return out, []
    planned, level = plan(claims, margins, number, spread=registered_spread(registered))
    rounds, stale = T.applicable(registered, T.basis(planned, level), measured, ROUNDS[number]["base"])
    tests = {tuple(r[T.ENSEMBLE]) + (r["test"],) for _, r in planned.iterrows()}
    for n, row in out.iterrows():
        key = tuple(row[T.ENSEMBLE])
        if row["verdict"] != "undecided" or key + (row["test"],) not in tests or key + (row["reading"],) not in rounds:
            continue
        decided = _decided_row(row, rounds[key + (row["reading"],)][0], margins, level, number)
        for column, value in decided.items():
            out.at[n, column] = value
        out.at[n, "why"] = (f"round {number} ({decided['seeds']} fresh seeds at {level:.2%}, one-sided, the claim's "
                            f"direction against the instrument's margin {decided['margin']:.3g}"
                            f"{', or within the difference that matters' if ROUNDS[number].get('matters') else ''}): "
                            f"{decided['why']}")
        out.at[n, "round"] = number
    return out, stale


def with_direction_rounds(claims: pd.DataFrame, registered: dict, margins: pd.DataFrame, measured: dict,
                          until: int | None = None) -> pd.DataFrame:
    """The verdict after the third round (``claims``) with each registered round of the claim's direction
    (``registered``: round number -> its table, :func:`roughlight.analysis.third_round.read_registered`) in turn,
    each planned from the verdict the rounds before it left; rounds from ``until`` on are left out."""
    return _rounds_applied(claims, registered, margins, measured, until)[0]


def _rounds_applied(claims: pd.DataFrame, registered: dict, margins: pd.DataFrame, measured: dict,
                    until: int | None = None) -> tuple[pd.DataFrame, list]:
    """:func:`with_direction_rounds`' verdict, and every registered ensemble it did not take, as ``(round number,
    ensemble and reading, why)``."""
    out, stale = claims, []
    for number in sorted(ROUNDS):
        if until is not None and number >= until:
            break
        out, gone = _round_applied(out, registered.get(number, T.read_registered(None)), margins, measured, number)
        stale += [(number, key, why) for key, why in gone]
    return out, stale


#: :func:`later_rounds`' columns of the rounds it does not take.
UNTAKEN_COLUMNS = ["round", "kind", "truncation", "aspect", "incidence", "why"]


def later_rounds(second: pd.DataFrame, third: pd.DataFrame, registered: dict, design: pd.DataFrame,
                 margins: pd.DataFrame, measured: dict) -> tuple[pd.DataFrame, pd.DataFrame]:
    """A run's verdict with its registered later rounds, each taken where it applies, in one pass: the second
    round's verdict (``second``) with the third round (``third``,
    :func:`roughlight.analysis.third_round.with_third_round`), then each round of the claim's direction
    (``registered``: round number -> its table, :func:`with_direction_rounds`); and every registered round's
    ensemble the verdict does not take, among the ensembles the run tests: a row each (:data:`UNTAKEN_COLUMNS`),
    with why (planned from other readings of the earlier rounds, measured with other settings, or not the tiles its
    plan asked for). A run's page says so: a round it does not take leaves its tests as the rounds before decided
    them."""
    tested = {tuple(k) for k in second[T.ENSEMBLE].drop_duplicates().itertuples(index=False)} if len(second) else set()
    after = T.with_third_round(second, third, design, margins, measured)
    verdict, stale = _rounds_applied(after, registered, margins, measured)
    rows = [(3, *key[:4], why) for key, why in T.stale(second, third, measured)]
    rows += [(number, *key[:4], why) for number, key, why in stale]
    out = pd.DataFrame(sorted(set(rows)), columns=UNTAKEN_COLUMNS)
    keep = [tuple(r) in tested for r in out[T.ENSEMBLE].itertuples(index=False)] if len(out) else []
    return verdict, out[keep].reset_index(drop=True) if len(out) else out


def registered_spread(registered: pd.DataFrame) -> dict | None:
    """(kind, truncation, aspect, incidence, test) -> the error a registered round's plan took in place of the
    earlier round's (its :data:`PLAN_SE` rows, unrounded); None where it took the earlier round's own."""
    rows = registered[(registered["claim_reading"] == "unrounded")
                      & registered["statistic"].astype(str).str.match(r"^plan_.+_se$")] if len(registered) else []
    if not len(rows):
        return None
    return {(r.kind, float(r.truncation), float(r.aspect), float(r.incidence), r.statistic[5:-3]): float(r.value)
            for r in rows.itertuples(index=False)}


def earlier_spread(claims: pd.DataFrame, margins: pd.DataFrame, number: int, geometry: pd.DataFrame,
                   steps: tuple[float, float], claim_rows, root: Path = Path("results/claims")) -> dict:
    """(kind, truncation, aspect, incidence, test) -> the standard error, in round ``number``'s own error (its
    ``ROUNDS`` ``error``), of each test it would plan from the round before's tiles (measured under ``root``; the
    unrounded reading). Raises FileNotFoundError naming the ``make`` target that draws them when they are gone."""
    before = ROUNDS[number - 1]["name"]
    wanted = plan(claims, margins, number)[0]
    out = {}
    for (kind, t, a, i), tests in wanted.groupby(T.ENSEMBLE, sort=False):
        folder = root / before / f"i{i:g}" / kind / f"t{t:g}_a{a:g}"
        if not any(folder.glob("s*.parquet")):
            raise FileNotFoundError(f"{folder}: the {before} round's tiles are gone (`make claim-"
                                    f"{ROUNDS[number]['name']}-round` draws them again, the same seeds)")
        pooled = T.round_readings(claim_rows([str(folder)]), geometry, steps, ROUNDS[number]["error"])
        reading = pooled[(kind, float(t), float(a), float(i), "unrounded")]
        out.update({(kind, float(t), float(a), float(i), test): float(reading[f"{test}_se"]) for test in tests["test"]})
    return out


def registered_rounds(claims_settings: dict, until: int | None = None) -> dict:
    """Round number -> its registered table, for each round of :data:`ROUNDS` (before ``until``) that the claim's
    settings (``claims:``) name a file for (``registered_{name}_round``)."""
    return {number: T.read_registered(claims_settings[f"registered_{spec['name']}_round"])
            for number, spec in ROUNDS.items() if (until is None or number < until)
            and claims_settings.get(f"registered_{spec['name']}_round")}


def main(argv=None) -> None:
    """``python -m roughlight.analysis.direction_rounds ANALYSIS REGISTERED --round N [--work DIR] [--config FILE]``:
    plan round N (:data:`ROUNDS`) from a finished run's verdict before it (``ANALYSIS``: its results/analysis; the
    second round's verdict ``random_claims_round2.csv`` with the config's registered third round and earlier
    rounds of the claim's direction), measure its tiles under ``DIR`` and write their readings to ``REGISTERED``
    (atomically), printing the plan and the round's verdicts."""
    import yaml

    from ..atomic import write_text_atomic
    from ..study import config as rl_config
    from ..study import plan as rl_plan
    from ..study.tables import claim_rows

    parser = argparse.ArgumentParser(description=main.__doc__.split("\n\n")[0])
    parser.add_argument("analysis", type=Path)
    parser.add_argument("registered", type=Path)
    parser.add_argument("--round", type=int, choices=sorted(ROUNDS), required=True, dest="number")
    parser.add_argument("--work", type=Path, default=None)
    parser.add_argument("--config", type=Path, default=Path("config/config.yaml"))
    args = parser.parse_args(argv)
    number, spec = args.number, ROUNDS[args.number]
    config = rl_config.validate_config(yaml.safe_load(args.config.read_text()))
    settings, measured = rl_config.claims(config), rl_plan.claim_measurement(config)
    design = pd.read_csv(args.analysis / "random_claim_design.csv")
    margins = pd.read_csv(args.analysis / "random_claim_margins.csv")
    third = T.read_registered(settings.get("registered_third_round") or None)
    earlier = registered_rounds(settings, until=number)
    after_third = T.with_third_round(pd.read_csv(args.analysis / "random_claims_round2.csv"), third, design, margins,
                                     measured)
    claims = with_direction_rounds(after_third, earlier, margins, measured, number)
    geometry = pd.read_csv(args.analysis / "random_claim_geometry.csv")
    sweep = rl_plan.sweep_settings(config)
    steps = (float(sweep["azimuth_step"]), float(sweep["elevation_step"]))
    spread = None
    if spec["error"] != ROUNDS[number - 1]["error"]:  # plan from the round's own error of the round before's tiles
        before = number - 1  # its tiles drawn again where they are gone (the same seeds: the same tiles), never
        # registered again: its registered readings stay as they were
        previous = plan(with_direction_rounds(after_third, earlier, margins, measured, before), margins, before,
                        spread=registered_spread(earlier.get(before, T.read_registered(None))))[0]
        T.render_round(previous, config, geometry, Path("results/claims") / ROUNDS[before]["name"], print,
                       ROUNDS[before]["base"])
        spread = earlier_spread(claims, margins, number, geometry, steps, claim_rows)
    planned, level = plan(claims, margins, number, spread=spread)
    print(f"{len(planned)} shape tests undecided (unrounded) before round {number}, the round's level {level:.4f}:\n"
          + planned.to_string(index=False))
    taken = [*(T.round_seeds(int(third["seeds"].max())) if len(third) else []),
             *(seed for k, table in earlier.items() if len(table)
               for seed in T.round_seeds(int(table["seeds"].max()), ROUNDS[k]["base"]))]
    work = args.work or Path(f"results/claims/{spec['name']}")
    folders = T.render_round(planned, config, geometry, work, print, spec["base"], tuple(taken))
    readings = T.round_readings(claim_rows(folders), geometry, steps, spec["error"]) if folders else {}
    for key, pooled in readings.items():  # the errors the plan took, where not the earlier round's own
        pooled.update({PLAN_SE.format(test): se for (*ensemble, test), se in (spread or {}).items()
                       if tuple(ensemble) == key[:4]})
    table = T.register(readings, planned, level, measured, spec["base"])
    write_text_atomic(args.registered, table.to_csv(index=False))
    decided = with_direction_round(claims, table, margins, measured, number)
    print(decided[decided["round"] == number][T.ENSEMBLE + ["test", "reading", "seeds", "mean", "low", "high",
                                                           "margin", "regular", "verdict"]].to_string(index=False))


if __name__ == "__main__":
    main()
