"""The random-roughness claim's rounds of its own direction (the fourth and fifth): the shape tests no number of
seeds decides two-sided, read one-sided against the instrument's own margin, planned from the earlier rounds,
registered and read by the verdict."""

import numpy as np
import pandas as pd
import pytest

from roughlight.analysis import claim_readings as R
from roughlight.analysis import claims as C
from roughlight.analysis import direction_rounds as F
from roughlight.analysis import third_round as T

ENSEMBLE = {"kind": "random_pyramids", "truncation": 1.0, "aspect": 0.5, "incidence": 30.0}
MEASURED = {"claim_surface": {"cells": 8}, "sweep": {"elevation_step": 1.0, "azimuth_step": 5.0},
            "lighting": {"light": 127.0}, "method": "fast", "render": {}}


def _margins(grid_effect=0.0046):
    """A margin table of the ensemble's back-lobe squareness and contrast: the instrument's parts small, the
    difference that matters 0.05 (squareness) and 1 level (contrast)."""
    rows = []
    for test, regular, matters in (("back_squareness", -0.179, 0.05), ("back_contrast", 26.0, 1.0)):
        for reading in R.READINGS:
            rows.append({**ENSEMBLE, "test": test, "reading": reading, "regular": regular, "rendering_noise": 0.0,
                         "sampling_error": 0.001, "grid_effect": grid_effect,
                         "rounding": 0.003 if reading == "8-bit" else np.nan, "matters": matters,
                         "margin": max(matters, grid_effect)})
    return pd.DataFrame(rows)


def _second_round(mean=-0.1417, se=0.0272, seeds=38):
    """A verdict whose back lobe is found and whose squareness sits on the two-sided margin's edge (the random
    pyramids at t 1, a 0.5 as the default run reads them)."""
    margins = _margins()
    design = pd.DataFrame([{**ENSEMBLE, "test": t, "level": 1 - 0.05 / 28} for t in ("back_contrast", "back_squareness")])
    pooled = {"back_contrast": 4.0, "back_contrast_se": 0.25, "back_squareness": mean, "back_squareness_se": se,
              "back_why": "", "seeds": seeds}
    key = tuple(ENSEMBLE.values())
    return C.claim_table({key + (r,): pooled for r in R.READINGS}, design, margins).assign(round=2), margins


def _stale_lines(claims, registered, margins, measured) -> list[str]:
    """The registered direction rounds' ensembles a run does not take (``later_rounds``' second table), a line each:
    "round N: ensemble: why"."""
    gone = F.later_rounds(claims, T.read_registered(None), registered, None, margins, measured)[1]
    return sorted({f"round {r.round}: {r.kind} t {r.truncation:g}, a {r.aspect:g}, incidence {r.incidence:g}: {r.why}"
                   for r in gone.itertuples(index=False)})


def test_the_instrument_margin_leaves_out_the_difference_that_matters_and_adds_rounding_at_8_bits():
    margins = _margins()
    row = {**ENSEMBLE, "test": "back_squareness"}
    assert F.instrument_margin(margins, row, "unrounded") == pytest.approx(0.0046)
    assert F.instrument_margin(margins, row, "8-bit") == pytest.approx(0.0046)  # rounding 0.003 is smaller
    assert F.instrument_margin(_margins(grid_effect=0.001), row, "8-bit") == pytest.approx(0.003)
    assert F.threshold(-0.179, 0.0046, "below") == pytest.approx(-0.1836)
    assert F.threshold(0.2, 0.01, "above") == pytest.approx(0.21)
    with pytest.raises(ValueError, match="no margin"):
        F.instrument_margin(margins, {**row, "test": "hot_spot_flatness"}, "unrounded")


def test_the_plan_takes_only_undecided_shape_tests_and_plans_their_seeds_by_the_designs_rule():
    """The squareness on the margin's edge is planned; the lobe test it rests on (found) is not; the seeds are
    those the design's rule asks for the one-sided question, at the round's own level, and the plan expects what
    the earlier rounds' mean says."""
    second, margins = _second_round()
    unrounded = second[second["reading"] == "unrounded"].set_index("test")
    assert unrounded.loc["back_squareness", "verdict"] == "undecided"
    assert unrounded.loc["back_contrast", "verdict"] == "lobe"
    planned, level = F.plan(second, margins)
    assert list(planned["test"]) == ["back_squareness"] and level == pytest.approx(1 - 0.05)
    row = planned.iloc[0]
    n, _ = C.planned_seeds(-0.1417, 0.0272, 38, -0.179, row["threshold"], level, "direction", F.ROUNDS[4]["max_seeds"])
    assert row["fresh"] == n and 38 < n <= F.ROUNDS[4]["max_seeds"]
    assert row["threshold"] == pytest.approx(-0.179 - 0.0046)
    assert row["why"] == "not as claimed expected from the earlier rounds' tested seeds"
    # the direction of the expectation follows the mean's side of the threshold
    rounder, _ = _second_round(mean=-0.25, se=0.05)
    assert F.plan(rounder, margins)[0].iloc[0]["why"].startswith("a difference as claimed expected")


def test_the_one_sided_verdict_reads_the_interval_against_the_threshold_the_claims_way():
    assert F.direction_verdict(-0.30, -0.20, -0.1836, "below")[0] == "difference"
    assert F.direction_verdict(-0.17, -0.10, -0.1836, "below")[0] == "not as claimed"
    assert F.direction_verdict(-0.20, -0.10, -0.1836, "below")[0] == "undecided"
    assert F.direction_verdict(0.5, 0.6, 0.4, "above")[0] == "difference"
    assert F.direction_verdict(0.1, 0.3, 0.4, "above")[0] == "not as claimed"


def _registered(second, margins, mean, se):
    """The round's readings of exactly the tiles its plan asks for, registered (both readings alike)."""
    planned, level = F.plan(second, margins)
    fresh = int(planned["fresh"].max())
    key = tuple(ENSEMBLE.values())
    pooled = {"back_contrast": 4.0, "back_contrast_se": 0.2, "back_squareness": mean, "back_squareness_se": se,
              "back_why": "", "seeds": fresh}
    return T.register({key + (r,): pooled for r in R.READINGS}, planned, level, MEASURED, F.ROUNDS[4]["base"]), fresh


def test_a_registered_fourth_round_decides_the_undecided_shape_test_alone_and_only_where_it_applies(tmp_path):
    second, margins = _second_round()
    registered, fresh = _registered(second, margins, mean=-0.14, se=0.012)
    path = tmp_path / "fourth.csv"
    registered.to_csv(path, index=False)
    decided = F.with_direction_round(second, T.read_registered(path), margins, MEASURED)
    fourth = decided[decided["round"] == 4]
    assert set(fourth["test"]) == {"back_squareness"} and len(fourth) == 2  # both readings
    assert set(fourth["verdict"]) == {"not as claimed"} and (fourth["seeds"] == fresh).all()
    assert np.allclose(fourth["margin"], 0.0046) and np.allclose(fourth["level"], 0.95)
    assert fourth["why"].str.startswith(f"round 4 ({fresh} fresh seeds at 95.00%, one-sided").all()
    assert (fourth["low"] > -0.179 - 0.0046).all()
    kept = decided[decided["round"] == 2]
    assert set(kept["test"]) == {"back_contrast"} and set(kept["verdict"]) == {"lobe"}
    assert _stale_lines(second, {4: registered}, margins, MEASURED) == []
    # a rounder random lobe is a difference as claimed
    rounder, _ = _registered(second, margins, mean=-0.25, se=0.01)
    claimed = F.with_direction_round(second, rounder, margins, MEASURED)
    assert set(claimed.loc[claimed["round"] == 4, "verdict"]) == {"difference"}
    assert claimed.loc[claimed["round"] == 4, "agrees"].astype(bool).all()
    # measured with other settings, planned from other readings, or other tiles than planned: nothing taken
    other = {**MEASURED, "lighting": {"light": 255.0}}
    assert (F.with_direction_round(second, registered, margins, other)["round"] == 2).all()
    assert _stale_lines(second, {4: registered}, margins, other) == [
        "round 4: random_pyramids t 1, a 0.5, incidence 30: measured with other settings"]
    moved = second.copy()
    moved.loc[moved["test"] == "back_squareness", "mean"] -= 0.01
    assert (F.with_direction_round(moved, registered, margins, MEASURED)["round"] == 2).all()
    fewer = registered.copy()
    fewer.loc[fewer["statistic"] == "seeds", "value"] = fresh - 1
    assert (F.with_direction_round(second, fewer, margins, MEASURED)["round"] == 2).all()
    assert (F.with_direction_round(second, T.read_registered(None), margins, MEASURED)["round"] == 2).all()


def test_a_fifth_round_plans_from_what_the_fourth_left_and_decides_only_that():
    """The fourth round's readings undecided, the fifth plans from them (its seeds above the fourth's, at most its
    own max), and its registered readings decide the test as round 5; the fourth's row is what the fifth replaces,
    and a fifth round registered without the fourth it was planned after is stale."""
    second, margins = _second_round()
    fourth, _ = _registered(second, margins, mean=-0.158, se=0.025)
    after = F.with_direction_rounds(second, {4: fourth}, margins, MEASURED)
    row = after[(after["test"] == "back_squareness") & (after["reading"] == "unrounded")].iloc[0]
    assert row["round"] == 4 and row["verdict"] == "undecided"
    planned, level = F.plan(after, margins, 5)
    assert list(planned["test"]) == ["back_squareness"] and planned.iloc[0]["mean"] == pytest.approx(-0.158)
    fresh = int(planned.iloc[0]["fresh"])
    assert F.ROUNDS[4]["max_seeds"] < fresh <= F.ROUNDS[5]["max_seeds"]
    key = tuple(ENSEMBLE.values())
    pooled = {"back_contrast": 4.0, "back_contrast_se": 0.2, "back_squareness": -0.158, "back_squareness_se": 0.006,
              "back_why": "", "seeds": fresh}
    fifth = T.register({key + (r,): pooled for r in R.READINGS}, planned, level, MEASURED, F.ROUNDS[5]["base"])
    decided = F.with_direction_rounds(second, {4: fourth, 5: fifth}, margins, MEASURED)
    five = decided[decided["round"] == 5]
    assert len(five) == 2 and set(five["verdict"]) == {"not as claimed"} and (five["seeds"] == fresh).all()
    assert _stale_lines(second, {4: fourth, 5: fifth}, margins, MEASURED) == []
    alone = F.with_direction_rounds(second, {5: fifth}, margins, MEASURED)
    assert 5 not in set(alone["round"])
    assert _stale_lines(second, {5: fifth}, margins, MEASURED)[0].startswith("round 5: random_pyramids")


def test_the_rounds_seeds_meet_no_other_tiles():
    """Each round's seeds lie above every pilot's (claims.pilots is at most 100: seeds 501-600), the third round's
    and the rounds' before it."""
    from roughlight.study.config import CLAIM_PILOT_BASE

    assert T.THIRD_ROUND_BASE < CLAIM_PILOT_BASE and CLAIM_PILOT_BASE + 100 <= F.ROUNDS[4]["base"]
    for number in sorted(F.ROUNDS)[:-1]:
        assert F.ROUNDS[number]["base"] + F.ROUNDS[number]["max_seeds"] <= F.ROUNDS[number + 1]["base"]
    assert T.round_seeds(2, F.ROUNDS[5]["base"]) == [801, 802]


def _lobe_stack(n=30, seed=5):
    """n tiles of a Gaussian back lobe (t 1, a 0.5, incidence 30) whose height varies from tile to tile (30 +- 6
    levels) over a flat specular, with flat diffuse fields: a statistic smooth in the tiles."""
    from roughlight.analysis import lobe_shape

    key = (1.0, 0.5, 30.0)
    azimuth, elevation = np.arange(0.0, 180.0, 5.0), np.arange(0.0, 181.0, 1.0)
    centre = R.lobe_centres(key)["back"]
    shape = lobe_shape.synthetic_lobe(azimuth, elevation, centre, (6.0, 4.0), peak=1.0)
    heights = np.random.default_rng(seed).normal(30.0, 6.0, n)
    specular = 2.0 + heights[:, None, None] * shape[None]
    coverage = np.ones(shape.shape)
    coverage[:, [0, -1]] = 0.0
    flat = np.full((n,) + shape.shape, 80.0)
    return R.SeedStack(key, "random_pyramids", np.arange(1, n + 1), azimuth, elevation, coverage,
                       {r: specular for r in R.READINGS}, {r: flat for r in R.READINGS}, flat * 1.1)


def test_the_bootstrap_error_is_the_jackknifes_on_a_smooth_statistic_and_repeats(monkeypatch):
    """On a lobe whose height alone varies (its contrast is smooth in the tiles) the bootstrap's error is the
    delete-one jackknife's within a third, and both are near the spread of the heights over sqrt(n); the same call
    gives the same error (a fixed seed); an unknown error is refused."""
    monkeypatch.setattr(R, "BOOTSTRAP_RESAMPLES", 80)
    stack = _lobe_stack()
    centres, radii = R.lobe_centres(stack.key), {"back": 20.0, "hot_spot": 10.0}
    jack = R.pooled_readings(stack, centres, radii)
    boot = R.pooled_readings(stack, centres, radii, error="bootstrap")
    assert boot["back_contrast"] == jack["back_contrast"] and boot["seeds"] == 30
    assert 0.67 < boot["back_contrast_se"] / jack["back_contrast_se"] < 1.5
    assert jack["back_contrast_se"] > 0.3  # the heights' spread (6 levels) over sqrt(30), as the contrast reads it
    assert R.pooled_readings(stack, centres, radii, error="bootstrap")["back_contrast_se"] == boot["back_contrast_se"]
    with pytest.raises(ValueError, match="jackknife"):
        R.pooled_readings(stack, centres, radii, error="delete-two")


def test_a_bootstrap_round_plans_from_the_error_it_registered_and_is_stale_when_that_moves():
    """Round 6 plans from the bootstrap error of the fifth round's tiles, which it registers (``plan_{test}_se``):
    a run re-plans from the registered error, takes the round, and decides the test by round 6's own
    (bootstrap) error; the same round with another registered plan error is not taken."""
    second, margins = _second_round()
    fourth, _ = _registered(second, margins, mean=-0.158, se=0.025)
    after4 = F.with_direction_rounds(second, {4: fourth}, margins, MEASURED)
    planned5, level5 = F.plan(after4, margins, 5)
    key = tuple(ENSEMBLE.values())

    def pooled(mean, se, seeds, **extra):
        return {"back_contrast": 4.0, "back_contrast_se": 0.2, "back_squareness": mean, "back_squareness_se": se,
                "back_why": "", "seeds": seeds, **extra}

    n5 = int(planned5["fresh"].max())
    fifth = T.register({key + (r,): pooled(-0.157, 0.0157, n5) for r in R.READINGS}, planned5, level5, MEASURED,
                       F.ROUNDS[5]["base"])
    after5 = F.with_direction_rounds(second, {4: fourth, 5: fifth}, margins, MEASURED)
    assert set(after5.loc[after5["round"] == 5, "verdict"]) == {"undecided"}
    spread = {key + ("back_squareness",): 0.0067}  # the fifth round's tiles, bootstrapped
    planned6, level6 = F.plan(after5, margins, 6, spread=spread)
    assert planned6.iloc[0]["se"] == 0.0067 and planned6.iloc[0]["mean"] == pytest.approx(-0.157)
    n6 = int(planned6.iloc[0]["fresh"])
    assert 2 <= n6 < F.plan(after5, margins, 6)[0].iloc[0]["fresh"]  # fewer than the jackknife's error asks
    sixth = T.register({key + (r,): pooled(-0.156, 0.0065, n6, plan_back_squareness_se=0.0067) for r in R.READINGS},
                       planned6, level6, MEASURED, F.ROUNDS[6]["base"])
    assert F.registered_spread(sixth) == spread
    decided = F.with_direction_rounds(second, {4: fourth, 5: fifth, 6: sixth}, margins, MEASURED)
    six = decided[decided["round"] == 6]
    assert len(six) == 2 and set(six["verdict"]) == {"not as claimed"} and (six["seeds"] == n6).all()
    assert _stale_lines(second, {4: fourth, 5: fifth, 6: sixth}, margins, MEASURED) == []
    moved = sixth.copy()
    moved.loc[moved["statistic"] == "plan_back_squareness_se", "value"] = 0.0157
    assert 6 not in set(F.with_direction_rounds(second, {4: fourth, 5: fifth, 6: moved}, margins, MEASURED)["round"])
    assert _stale_lines(second, {4: fourth, 5: fifth, 6: moved}, margins, MEASURED)[0].startswith("round 6:")


def test_a_round_that_holds_the_difference_that_matters_decides_wherever_the_mean_lies():
    """Round 8's verdicts hold *no difference* (within the difference that matters, first) beside the one-sided
    two: an interval across the threshold but within ±0.05 of the regular value decides; its seeds are those at
    which every interval is narrower than the difference that matters less the instrument's margin, the same
    wherever the earlier mean lies."""
    band = (-0.229, -0.129)
    assert F.direction_verdict(-0.193, -0.153, -0.1837, "below", band)[0] == "no difference"
    assert F.direction_verdict(-0.193, -0.153, -0.1837, "below")[0] == "undecided"
    assert F.direction_verdict(-0.14, -0.10, -0.1837, "below", band)[0] == "not as claimed"
    assert F.direction_verdict(-0.30, -0.24, -0.1837, "below", band)[0] == "difference"
    second, margins = _second_round()
    assert F.matters_of(margins, {**ENSEMBLE, "test": "back_squareness"}, "unrounded") == 0.05
    fresh = [F.plan(_second_round(mean=mean, se=0.03)[0], margins, 8)[0].iloc[0]["fresh"] for mean in (-0.16, -0.2)]
    assert fresh[0] == fresh[1]  # the width, not the mean, sets the seeds
    n = fresh[0]
    half = lambda k: C.t_quantile(1 - 0.05, k) * 0.03 * np.sqrt(38) * 1.118 / np.sqrt(k)  # noqa: E731
    assert half(n) <= 0.05 - 0.0046 < half(n - 1) + 0.01
    # registered and read after an undecided round: the interval across the threshold, within the band, decides
    fourth, _ = _registered(second, margins, mean=-0.17, se=0.025)
    after = F.with_direction_rounds(second, {4: fourth}, margins, MEASURED)
    assert set(after.loc[after["test"] == "back_squareness", "verdict"]) == {"undecided"}
    planned, level = F.plan(after, margins, 8)
    key = tuple(ENSEMBLE.values())
    eighth = T.register({key + (r,): {"back_contrast": 4.0, "back_contrast_se": 0.2, "back_squareness": -0.175,
                                      "back_squareness_se": 0.009, "back_why": "",
                                      "seeds": int(planned["fresh"].max())} for r in R.READINGS},
                        planned, level, MEASURED, F.ROUNDS[8]["base"])
    decided = F.with_direction_round(after, eighth, margins, MEASURED, 8)
    row = decided[(decided["test"] == "back_squareness") & (decided["reading"] == "unrounded")].iloc[0]
    assert row["round"] == 8 and row["verdict"] == "no difference" and "difference that matters" in row["why"]
    assert row["low"] < -0.1837 < row["high"]  # across the threshold: the one-sided question alone leaves it


def test_the_rounds_a_run_does_not_take_are_listed_with_why_and_only_for_its_own_ensembles():
    second, margins = _second_round()
    registered, _ = _registered(second, margins, mean=-0.14, se=0.012)
    design = pd.DataFrame([{**ENSEMBLE, "test": t, "level": 1 - 0.05 / 28} for t in ("back_contrast", "back_squareness")])
    none = T.read_registered(None)
    assert len(F.later_rounds(second, none, {4: registered}, design, margins, MEASURED)[1]) == 0
    other = {**MEASURED, "lighting": {"light": 255.0}}
    gone = F.later_rounds(second, none, {4: registered}, design, margins, other)[1]
    assert list(gone.columns) == F.UNTAKEN_COLUMNS
    assert gone.to_dict("records") == [{"round": 4, **ENSEMBLE, "why": "measured with other settings"}]
    elsewhere = second.assign(truncation=0.5)  # a run that does not test the registered ensemble
    assert len(F.later_rounds(elsewhere, none, {4: registered}, design.assign(truncation=0.5), margins.assign(
        truncation=0.5), other)[1]) == 0
