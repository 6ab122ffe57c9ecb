"""The report's "Findings": each statement's numbers are this run's, its link lands on the page, and a statement that
cannot be made says why.

The Tables 1-2 and share-law statements read the analysis of a small study measured here with the exact reference
(``make_study``); the measurements' frames (the speed/accuracy benchmark, the renderer's validation, the random
ensembles, the implicit surface's validation) are made here with known values.
"""

from __future__ import annotations

import math
import re
from html import unescape
from html.parser import HTMLParser

import numpy as np
import pandas as pd
import pytest

from roughlight.analysis.ensembles import seeds_needed
from roughlight.analysis.lobes import arc_lobes
from roughlight.analysis.share_laws import share_law_fits
from roughlight.analysis.thesis import exact_lobe_peaks, implied_scales, tables_at_implied_scale, thesis_tables
from roughlight.render.shading import Lighting
from roughlight.report import page as R
from roughlight.report.page_templates import render
from roughlight.report.sections import findings as PF
from roughlight.report.sections import speed as PS

from .test_analysis import make_study

S32 = math.sqrt(3.0) / 2.0
ASPECTS = [1.0, S32]
STATEMENTS = ("ranking", "exact", "implied", "laws", "implicit", "regular-lobe", "random", "light-transport", "accuracy",
              "speed")


# ---------------------------------------------------------------------------
# the frames


@pytest.fixture(scope="module")
def tables():
    """The analysis frames build_report reads for Tables 1-2 and the share laws, of a small exact study."""
    study = make_study([0.0, 0.5, 1.0], [0.0, 0.5, S32, 1.0], elevations=np.arange(0.0, 181.0, 2.0))
    lobes = arc_lobes(study)
    exact = exact_lobe_peaks(lobes, ASPECTS, 30.0, Lighting())
    thesis, _ = thesis_tables(lobes, ASPECTS, 30.0, m=127.0, exact=exact)
    return {"thesis_tables": thesis, "exact_peaks": exact, "implied_scales": implied_scales(),
            "tables_at_implied_scale": tables_at_implied_scale(lobes), "share_laws": share_law_fits(lobes)}


def speed_table() -> pd.DataFrame:
    """The speed/accuracy benchmark's rows: the naive method, the fast one at its default and at another setting."""
    rows = []
    for method, label, vps, mae, worst, default in (("naive", "naive <thesis>", 29.1, 1.968, 8.11, False),
                                                    ("fast", "fast lattice P=8", 6233.0, 1.41, 6.54, False),
                                                    ("fast", "fast adaptive <P=28>", 1177.2, 0.0406, 0.211, True)):
        for component, scale in (("diffuse", 0.9), ("specular", 0.1), ("total", 1.0)):
            rows.append({"method": method, "label": label, "component": component, "n_views": 72,
                         "views_per_second": vps, "mae": mae * scale, "max_error": worst * scale,
                         "speedup_vs_naive": vps / 29.1, "default": default})
    return pd.DataFrame(rows)


def validation_frame() -> pd.DataFrame:
    """The renderer's validation: two surfaces, two settings (the configured one and a coarser one)."""
    rows = []
    for setting, scale in (("configured", 1.0), ("lattice 24", 9.0)):
        for k, (t, a) in enumerate(((0.5, 1.0), (1.0, S32))):
            for component, worst, mae in (("diffuse", 0.49, 0.045), ("specular", 0.29, 0.004), ("total", 0.47, 0.046)):
                rows.append({"setting": setting, "truncation": t, "aspect": a, "incidence": 30.0, "component": component,
                             "n_views": 315, "mae": mae * scale * (1 - k / 4), "p99": worst * scale / 2,
                             "worst": worst * scale * (1 - k / 10), "grazing_worst": worst / 2,
                             "fast_views_per_second": 5270.0 / scale})
    return pd.DataFrame(rows)


def tiles_frame() -> pd.DataFrame:
    """Random tiles against the exact reference (rule random_tiles' random_accuracy)."""
    return pd.DataFrame([{"kind": kind, "truncation": 1.0, "aspect": 1.0, "cells": 4, "seed": 1, "component": c,
                          "views": 20, "reference_refused": 0, "mae": mae, "worst": worst}
                         for kind, mae, worst in (("random_pyramids", 0.086, 0.42), ("pyramids", 0.5, 3.0))
                         for c in ("diffuse", "specular", "total")])


def ensemble_row(kind, t, statistic, mean, half, regular, seeds=8) -> dict:
    """One row of random_ensembles.csv: the mean over seeds with a 95% interval of half-width ``half``."""
    return {"kind": kind, "truncation": t, "aspect": 1.0, "incidence": 30.0, "statistic": statistic,
            "unit": "deg" if statistic == "back_phase_shift" else "ratio", "seeds": seeds, "mean": mean,
            "sd": half * math.sqrt(seeds) / 2.36, "ci_low": mean - half, "ci_high": mean + half, "regular": regular,
            "boot_low": mean - half / 2, "boot_high": mean + half / 2}


def ensembles_frame() -> pd.DataFrame:
    """Rectangularity: 3 tests lower than the regular value, 1 where the regular surface has no lobe. Phase shift: 2
    higher, 1 within the ±2° tolerance (no difference), 1 undecided (a wide interval around the regular value)."""
    rows = [ensemble_row("random_pyramids", 0.5, "back_rectangularity", 0.60, 0.05, 0.78),
            ensemble_row("random_pyramids", 1.0, "back_rectangularity", 0.52, 0.05, 0.76),
            ensemble_row("random_heightfield", 0.5, "back_rectangularity", 0.64, 0.08, 0.78),
            ensemble_row("random_heightfield", 1.0, "back_rectangularity", 0.55, 0.08, np.nan),
            ensemble_row("random_pyramids", 0.5, "back_phase_shift", 13.7, 3.0, 0.53),
            ensemble_row("random_pyramids", 1.0, "back_phase_shift", 4.9, 2.0, 0.08),
            ensemble_row("random_heightfield", 0.5, "back_phase_shift", 0.9, 0.5, 0.53),
            ensemble_row("random_heightfield", 1.0, "back_phase_shift", 3.0, 6.0, 0.08),
            ensemble_row("random_pyramids", 0.5, "back_peak", 20.0, 2.0, 27.0)]  # not a test of the claim
    return pd.DataFrame(rows)


def claim_row(kind, t, test, verdict, mean, regular, agrees=pd.NA, seeds=12, reading="unrounded") -> dict:
    """One row of random_claims.csv (roughlight.analysis.claims.claim_table)."""
    return {"kind": kind, "truncation": t, "aspect": 0.5, "incidence": 30.0, "test": test, "reading": reading,
            "claim": f"claim of {test}", "regular": regular, "margin": 0.05 if "squareness" in test else 0.3,
            "level": 1 - 0.05 / 8, "seeds": seeds, "mean": mean, "se": 0.02, "low": mean - 0.1,
            "high": mean + 0.1, "verdict": verdict, "why": "why", "agrees": agrees, "seeds_to_decide": pd.NA}


def claims_frame() -> pd.DataFrame:
    """Unrounded: random pyramids have a back lobe at both points, heightfields none; squareness 1 difference
    against the claim, 1 no difference, 2 no lobe. The 8-bit reading: the same but one undecided."""
    rows = []
    for reading in ("unrounded", "8-bit"):
        rows += [claim_row("random_pyramids", 0.5, "back_contrast", "lobe", 3.1, 26.0, reading=reading),
                 claim_row("random_pyramids", 1.0, "back_contrast", "lobe", 4.9, 34.6, reading=reading),
                 claim_row("random_heightfield", 0.5, "back_contrast", "no lobe", 0.1, 26.0, reading=reading),
                 claim_row("random_heightfield", 1.0, "back_contrast", "no lobe", 0.2, 34.6, reading=reading),
                 claim_row("random_pyramids", 0.5, "back_squareness", "difference", -0.02, -0.178, agrees=False,
                           reading=reading),
                 claim_row("random_pyramids", 1.0, "back_squareness",
                           "no difference" if reading == "unrounded" else "undecided", -0.17, -0.178,
                           reading=reading),
                 claim_row("random_heightfield", 0.5, "back_squareness", "no lobe", np.nan, -0.178, reading=reading),
                 claim_row("random_heightfield", 1.0, "back_squareness", "no lobe", np.nan, -0.155, reading=reading)]
    return pd.DataFrame(rows)


def implicit_frame() -> pd.DataFrame:
    """The implicit surface's validation: two surfaces, both forms and the fast renderer."""
    rows = []
    for k, (t, a) in enumerate(((1.0, 1.0), (0.5, 0.5))):
        for method, mae, worst in (("implicit_exact", 0.015, 0.249), ("implicit_correction", 1.186, 15.67),
                                   ("fast", 0.04, 0.56)):
            for component, scale in (("diffuse", 0.9), ("specular", 0.01), ("total", 1.0)):
                rows.append({"truncation": t, "aspect": a, "incidence": 30.0, "kind": "grid", "band": f"band {k}",
                             "method": method, "component": component, "n_views": 174,
                             "mae": mae * scale / (1 + 10 * k), "p99": worst * scale / 2,
                             "worst": worst * scale / (1 + k)})
    return pd.DataFrame(rows)


def benchmarks() -> dict:
    """The speed/accuracy benchmark and the renderer's validation, named as rule report_html names them."""
    return {"speed_accuracy": speed_table(), "renderer_validation": validation_frame(), "random_accuracy": tiles_frame()}


def light_frames() -> dict:
    """Rule light_transport's tables: Mitsuba against the reference, and the gain of light that bounces on a 2 x 2
    grid at two albedos, of which the two surfaces of aspect 0.1 at albedo 0.5 stay within a level at every view."""
    from roughlight.measurements.light_transport import interreflection_summary

    agreement = pd.DataFrame([{"kind": kind, "truncation": t, "aspect": a, "seed": 0, "incidence": 30.0,
                               "component": c, "n_views": 28, "mae": 0.02 * (k + 1), "worst": w * (k + 1) / 3,
                               "variant": "mitsuba 3.9.1 llvm_ad_rgb"}
                              for k, (kind, t, a) in enumerate([("pyramids", 1.0, 1.0), ("control", 0.0, 0.0)])
                              for c, w in (("diffuse", 0.6), ("specular", 0.3), ("total", 0.7))])
    rows = []
    for t in (0.25, 1.0):
        for a in (0.1, 1.0):
            for albedo, scale in ((1.0, 1.0), (0.5, 0.4)):
                for e in (30.0, 90.0, 150.0):
                    gain = scale * (2.0 * t * a + 0.01 * e) * (10.0 if a == 1.0 else 1.0)
                    rows.append({"truncation": t, "aspect": a, "incidence": 30.0, "albedo": albedo,
                                 "views": "hemisphere", "azimuth": 0.0, "elevation": e, "direct": 60.0,
                                 "bounced": 60.0 + gain, "gain": gain, "gain_percent": 100 * gain / 60.0,
                                 "bounces": 8})
    return {"mitsuba_agreement": agreement, "interreflection_summary": interreflection_summary(pd.DataFrame(rows))}


def measured() -> dict:
    """The random and implicit sections' inputs, named as rule report_html names them."""
    ensembles = ensembles_frame()
    fits = ensembles[["kind", "truncation", "aspect", "incidence"]].drop_duplicates().assign(rmse_lambert=3.0)
    frames = pd.DataFrame({"field": [16, 16], "method": ["explicit", "implicit_exact"], "triangles": [1024, 2],
                           "frame_ms": [59.0, 97.0], "error": [2.3, 0.06]})
    return {"random_ensembles": ensembles, "random_claims": claims_frame(), "random_seeds_needed": seeds_needed(ensembles),
            "random_model_fits": fits,
            "implicit_validation": implicit_frame(), "implicit_frames": frames, "plan": "quick", **light_frames()}


# ---------------------------------------------------------------------------
# the page


class _Page(HTMLParser):
    """Every id of the page, and the findings: each statement's text and links."""

    def __init__(self):
        super().__init__()
        self.ids, self.statements, self._in = set(), [], None
        self._depth = 0

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        if tag == "section" and a.get("id") == "findings":
            self._depth = 1
        elif self._depth and tag == "li":
            self._in = {"finding": a.get("data-finding"), "text": "", "links": []}
            self.statements.append(self._in)
        elif self._in is not None and tag == "a":
            self._in["links"].append(a["href"])

    def handle_endtag(self, tag):
        if tag == "li":
            self._in = None
        elif tag == "section":
            self._depth = 0

    def handle_data(self, data):
        if self._in is not None:
            self._in["text"] += data


def parse(html: str) -> _Page:
    p = _Page()
    p.feed(html)
    for s in p.statements:
        s["text"] = re.sub(r"\s+", " ", unescape(s["text"])).strip()
    return p


def statement(page: _Page, finding: str) -> str:
    return next(s["text"] for s in page.statements if s["finding"] == finding)


def assert_links_land(page: _Page):
    """At most ten statements, each links only to ids on the page."""
    assert 1 <= len(page.statements) <= 10
    for s in page.statements:
        for href in s["links"]:
            assert href.startswith("#") and href[1:] in page.ids, (s["finding"], href)


@pytest.fixture(scope="module")
def full_page(tables):
    html = R.build_report({**tables, **benchmarks(), **measured()}, {}, table_aspects=ASPECTS)
    return parse(html)


def test_every_statement_is_made_and_links_to_its_evidence(full_page):
    assert [s["finding"] for s in full_page.statements] == list(STATEMENTS)
    assert_links_land(full_page)
    targets = {s["finding"]: s["links"] for s in full_page.statements}
    assert targets["ranking"] == ["#tables"] and targets["laws"] == ["#share-laws"]
    assert targets["random"] == ["#random-claim"] and targets["speed"] == ["#speed-accuracy"]
    assert targets["accuracy"] == ["#renderer-validation"] and targets["implicit"] == ["#implicit-goal", "#implicit-validation"]
    assert targets["implied"] == ["#implied-scale"] and targets["exact"] == ["#exact-peaks"]
    assert targets["light-transport"] == ["#light-transport"]
    assert full_page.statements[0]["text"].startswith("Tables 1–2 rank the models")


def test_the_light_transport_statement_is_its_tables(full_page):
    frames = light_frames()
    summary = frames["interreflection_summary"]
    f = PF.light_transport(frames["mitsuba_agreement"], summary, True)
    assert f["agreement"] == [("diffuse", pytest.approx(0.4)), ("specular", pytest.approx(0.2)),
                              ("total", pytest.approx(0.7 * 2 / 3))]
    white, grey = f["albedos"]
    assert (white["albedo"], white["within"], white["surfaces"]) == (1.0, 0, 4)
    assert (grey["albedo"], grey["within"], grey["surfaces"]) == (0.5, 2, 4)  # aspect 0.1: at most 0.4 * 1.7 < 1
    assert white["worst"] == summary.loc[summary["albedo"] == 1.0, "worst_gain"].max()
    text = statement(full_page, "light-transport")
    assert text.startswith("Light that bounces between facets adds more than a level to the diffuse on every surface")
    assert "diffuse worst 0.40, specular worst 0.20, total worst 0.47" in text
    assert f"at worst {white['worst']:.1f}, 0 of 4 surfaces within a level" in text
    assert "albedo 0.5 adds" in text and "2 of 4 surfaces within a level at every view" in text
    assert PF.light_transport(None, None, False) == {"why": "switched_off"}
    assert PF.light_transport(None, summary, True) == {"why": "not_given"}


# ---------------------------------------------------------------------------
# the numbers are the frames'


def _mae(thesis, table, model, source):
    rows = thesis[(thesis["table"] == table) & (thesis["model"] == model) & (thesis["source"] == source)]
    return rows["Mean Abs Error"].to_numpy(float)


def test_the_ranking_is_tables_1_2s(tables, full_page):
    thesis = tables["thesis_tables"]
    r = PF.ranking(thesis)
    for lobe, (_, table, area_model) in zip(r["lobes"], PF.LOBES):
        ours_area, ours_regressed = _mae(thesis, table, area_model, "ours"), _mae(thesis, table, "Regressed Model", "ours")
        assert lobe["area"] == (ours_area.min(), ours_area.max())
        assert lobe["regressed"] == (ours_regressed.min(), ours_regressed.max())
        assert lobe["thesis_area"] == _mae(thesis, table, area_model, "thesis 2001")[0]
        assert lobe["thesis_regressed"] == _mae(thesis, table, "Regressed Model", "thesis 2001")[0]
        assert lobe["ours"] == "area" and lobe["thesis"] == "regressed"  # exact peaks: the area functions are exact
    assert r["verdict"] == "reversed" and r["labels"] == ["1", "√3/2"]
    text = statement(full_page, "ranking")
    assert "the other way round" in text
    assert (f"square area function {_mae(thesis, 1, 'Square Area Function', 'ours').max():.2f} against the regressed "
            f"model's {_mae(thesis, 1, 'Regressed Model', 'ours').max():.2f} (the thesis: 4.10 against 2.35)") in text


def test_the_ranking_follows_our_numbers():
    """Built from a thesis frame alone: our MAEs decide the verdict, the thesis's are read from its rows."""
    rows = []
    for table, area_model in ((1, "Square Area Function"), (2, "Triangle Area Function")):
        for model, ours, thesis in ((area_model, 1.0, 4.0), ("Regressed Model", 2.0, 3.0)):
            rows += [{"table": table, "aspect": 1.0, "model": model, "source": "ours", "Mean Abs Error": ours},
                     {"table": table, "aspect": 1.0, "model": model, "source": "thesis 2001", "Mean Abs Error": thesis}]
    frame = pd.DataFrame(rows)
    assert PF.ranking(frame)["verdict"] == "reversed"
    frame.loc[(frame["source"] == "thesis 2001") & frame["model"].str.contains("Area"), "Mean Abs Error"] = 1.5
    assert PF.ranking(frame)["verdict"] == "same"
    frame.loc[(frame["source"] == "ours") & (frame["table"] == 2), "Mean Abs Error"] = np.nan
    r = PF.ranking(frame)
    assert r["verdict"] == "mixed" and r["lobes"][1]["area"] is None and r["lobes"][1]["ours"] is None
    assert "back lobe, not compared" in render("findings.html", s=_section(ranking=r))


def _section(**changes) -> dict:
    """The findings' data with every statement saying why it is missing, but ``changes``."""
    s = PF.findings_section(table_aspects=ASPECTS, table_incidence=30.0)
    s.update(changes)
    return s


def test_the_exact_and_implied_statements_are_the_tables(tables, full_page):
    thesis, exact = tables["thesis_tables"], tables["exact_peaks"]
    e = PF.exact_law(thesis, exact)
    assert e["max"] == exact["error"].abs().max() and e["mean"] == pytest.approx(exact["error"].abs().mean())
    area_exact = thesis[(thesis["source"] == "exact geometry") & thesis["model"].str.contains("Area")]
    assert e["worst"] == area_exact["Mean Abs Error"].max() and e["worst"] < 1e-9
    i = PF.implied_scale(thesis, tables["implied_scales"], tables["tables_at_implied_scale"])
    scales = tables["implied_scales"].set_index("table")
    assert [(r["table"], r["low"], r["high"], r["possible"]) for r in i["scales"]] == [
        (t, scales.loc[t, "s_min_mae"], scales.loc[t, "s_max_mae"], bool(scales.loc[t, "stated_possible"]))
        for t in (1, 2)]  # the impossible scale (Table 1) first
    implied_rows = tables["tables_at_implied_scale"].query("scale == 'implied'")
    area = implied_rows[implied_rows["model"] == "Square Area Function"]["Mean Abs Error"]
    (at,) = i["at_scale"]
    assert at["table"] == 1 and at["scale"] == scales.loc[1, "s_min_mae"]
    assert at["area"] == (area.min(), area.max()) and at["area_wins"]
    text = statement(full_page, "implied")
    assert (f"a scale s in [{scales.loc[1, 's_min_mae']:.1f}, {scales.loc[1, 's_max_mae']:.1f}], not the stated 127"
            in text)
    assert f"At s = {scales.loc[1, 's_min_mae']:.1f}, the smallest allowed" in text and f"{area.max():.2f}" in text
    assert "The area functions are the law of the lobe peaks" in statement(full_page, "exact")


def test_the_share_laws_are_the_best_held_out(tables, full_page):
    laws = tables["share_laws"]
    found = PF.share_law_finding(tables["share_laws"])
    assert [b["lobe"] for b in found["best"]] == ["forward", "back"]
    for b in found["best"]:
        rows = laws[laws["lobe"] == b["lobe"]]
        best = rows.loc[rows["rmse_held_out"].idxmin()]
        assert (b["model"], b["rmse_held_out"], b["n"]) == (best["model"], best["rmse_held_out"], best["n"])
        np.testing.assert_equal(b["baseline"], rows[rows["model"] == "linear GLM (baseline)"]["rmse_held_out"].iloc[0])
    text = statement(full_page, "laws")
    forward, back = found["best"]
    assert f"back lobe, {back['model']}: {back['rmse_held_out']:.2f} against {back['baseline']:.2f}" in text
    # 3 rough surfaces with a forward lobe: the linear GLM's 4 parameters are not fitted, and the page says so
    assert math.isnan(forward["baseline"]) and forward["n"] == 3
    assert (f"forward lobe, {forward['model']}: {forward['rmse_held_out']:.2f} (the linear GLM not scored: fewer "
            "surfaces than parameters) (3 surfaces, incidence 30)") in text


def test_the_random_claims_are_the_claim_tables(full_page):
    found = PF.random_claim_finding(claims_frame(), shown=True)
    unrounded, eight = found["readings"]["unrounded"], found["readings"]["8-bit"]
    contrast, square = unrounded["tests"]
    assert (square["name"], square["n"]) == ("back_squareness", 4)
    assert contrast["verdicts"] == [("lobe", 2), ("no lobe", 2)]
    assert square["verdicts"] == [("no lobe", 2), ("difference against the claim", 1), ("no difference", 1)]
    assert eight["tests"][1]["verdicts"] == [("no lobe", 2), ("difference against the claim", 1), ("undecided", 1)]
    # the random means are of the tests made: none where there is no lobe
    assert square["mean"] == (-0.17, -0.02) and square["regular"] == (-0.178, -0.155)
    assert (found["points"], found["kinds"], unrounded["n_tests"]) == (2, 2, 8)
    assert found["regular"]["back"]["shape"] == "ellipse" and unrounded["headline"] == "refuted"
    assert eight["headline"] == "unsupported" and found["level"] == pytest.approx(1 - 0.05 / 8)
    text = statement(full_page, "random")
    assert text.startswith("No test of the thesis's random-roughness claim finds the difference it claims.")
    assert "back lobe: squareness: no lobe in 2, difference against the claim in 1, no difference in 1 of 4" in text
    assert "(random -0.170 to -0.020 against the regular -0.178 to -0.155)" in text
    assert "Read at 8 bits, as the thesis's framebuffer: " in text and "undecided in 1" in text
    no_lobes = claims_frame().assign(verdict="no lobe")
    assert PF.random_claim_finding(no_lobes, shown=True)["readings"]["unrounded"]["headline"] == "no lobe"
    # one difference as the thesis claims beside one against it is a mixed verdict; every one as claimed supports it
    both = claims_frame()
    both.loc[(both["test"] == "back_squareness") & (both["truncation"] == 1.0), ["verdict", "agrees"]] = [
        "difference", True]
    assert PF.random_claim_finding(both, shown=True)["readings"]["unrounded"]["headline"] == "mixed"
    both.loc[both["verdict"] == "difference", "agrees"] = True
    assert PF.random_claim_finding(both, shown=True)["readings"]["unrounded"]["headline"] == "supported"


def test_the_claims_later_rounds_are_named_with_the_familys_bound_over_them():
    """A third round (round 3 rows) and a fifth round of the claim's direction (round 5 rows, which stand only after
    the fourth): the finding names both direction rounds, counts what they decided, and bounds the family error by
    the second round's 0.05 and 0.05 for each later round (0.20 over four rounds); a run with none says none."""
    claims = claims_frame().assign(round=2)
    third = (claims["test"] == "back_contrast") & (claims["kind"] == "random_heightfield")
    claims.loc[third, ["round", "level"]] = [3, 1 - 0.05 / 2]
    fifth = (claims["test"] == "back_squareness") & (claims["truncation"] == 1.0) & (claims["kind"] == "random_pyramids")
    claims.loc[fifth, ["round", "level", "verdict"]] = [5, 0.975, "not as claimed"]
    found = PF.random_claim_finding(claims, shown=True)
    assert found["third"] == {"n": 2, "level": pytest.approx(0.975)}
    assert found["direction"] == {"tests": 1, "decided": 1, "rounds": ["fourth", "fifth"], "level": 0.975}
    assert found["together"] == pytest.approx(0.80)
    square = found["readings"]["unrounded"]["tests"][1]
    assert ("not as claimed", 1) in square["verdicts"]
    assert found["readings"]["unrounded"]["headline"] == "refuted"  # not as claimed is decided, not as the thesis claims
    plain = PF.random_claim_finding(claims_frame(), shown=True)
    assert plain["third"] is None and plain["direction"] is None and plain["together"] == pytest.approx(0.95)


def test_a_registered_round_the_verdict_did_not_take_is_named_on_the_page(tmp_path):
    """A registered round made stale (by a change to the settings or to the rounds before it) is named in the
    finding and under the claim table with its ensemble and why, so that it is seen (in Chromium, as a reader sees
    the page); with none, the finding says nothing of it."""
    from .browser import Browser

    untaken = pd.DataFrame([{"round": 3, "kind": "random_heightfield", "truncation": 0.5, "aspect": 0.5,
                             "incidence": 30.0, "why": "planned from other readings of the earlier rounds"}])
    found = PF.random_claim_finding(claims_frame(), shown=True, untaken=untaken)
    assert found["untaken"] == [{"round": "third", "ensemble": "random heightfield t 0.5, a 0.5",
                                 "why": "planned from other readings of the earlier rounds"}]
    html = R.build_report({**benchmarks(), **measured(), "random_claims_untaken": untaken}, {}, table_aspects=ASPECTS)
    text = statement(parse(html), "random")
    assert ("Registered rounds not taken, their tests left as the rounds before decided them: the third round's "
            "random heightfield t 0.5, a 0.5 (planned from other readings of the earlier rounds)") in text
    path = tmp_path / "report.html"
    path.write_text(html, encoding="utf-8")
    with Browser(1280, 900, workdir=tmp_path) as browser:
        browser.open(path)
        seen = browser.evaluate("""(() => [...document.querySelectorAll('p, li')]
            .filter(e => e.innerText.includes('Registered rounds not taken'))
            .map(e => ({text: e.innerText, shown: e.getBoundingClientRect().height > 0 || !!e.closest('details')})))()""")
    assert len(seen) == 2 and all(e["shown"] for e in seen)
    assert all("the third round's random heightfield t 0.5, a 0.5" in e["text"] for e in seen)
    assert PF.random_claim_finding(claims_frame(), shown=True)["untaken"] == []
    plain = statement(parse(R.build_report({**benchmarks(), **measured()}, {}, table_aspects=ASPECTS)), "random")
    assert "not taken" not in plain


def test_the_renderer_statements_are_the_benchmarks(full_page):
    b = benchmarks()
    acc = PF.renderer_accuracy(PS.speed_section(**b))
    configured = b["renderer_validation"].query("setting == 'configured'")
    assert acc["worst"] == configured["worst"].max() and acc["mae"] == configured["mae"].max()
    assert acc["component"] == configured.loc[configured["worst"].idxmax(), "component"]
    assert (acc["n_surfaces"], acc["views"]) == (2, 315)
    assert acc["tiles"]["worst"] == 0.42 and acc["tiles"]["largest_mae"] == 0.086  # the random kinds' tiles only
    sp = PF.speed(PS.speed_section(**b))
    total = b["speed_accuracy"].query("component == 'total'")
    fast, naive = total[total["default"]].iloc[0], total[total["method"] == "naive"].iloc[0]
    assert (sp["fast_vps"], sp["naive_vps"], sp["speedup"]) == (fast["views_per_second"], naive["views_per_second"],
                                                               fast["speedup_vs_naive"])
    assert (sp["fast_worst"], sp["naive_worst"], sp["fast_mae"]) == (fast["max_error"], naive["max_error"], fast["mae"])
    text = statement(full_page, "speed")
    assert f"{fast['speedup_vs_naive']:.3g} times as fast as the naive method and more accurate" in text
    assert "(fast adaptive <P=28>) it draws 1,177 views/s against the naive method's 29" in text
    assert "worst view 0.21 from the exact reference against 8.11" in text
    assert "worst view 0.49 (diffuse), MAE at most 0.046 (2 surfaces × 315 views); random tiles: worst view 0.42" in (
        statement(full_page, "accuracy"))


def test_the_implicit_statement_is_its_validation(full_page):
    found = PF.implicit(implicit_frame(), shown=True)
    v = implicit_frame().query("component == 'total'")
    exact, correction = v[v["method"] == "implicit_exact"], v[v["method"] == "implicit_correction"]
    assert found["exact"]["worst"] == exact["worst"].max() and found["exact"]["max_mae"] == exact["mae"].max()
    assert found["correction"]["median_mae"] == correction["mae"].median()
    assert (found["n_surfaces"], found["n_views"]) == (2, 174)
    assert f"within {exact['worst'].max():.2f} of the exact reference at every view" in statement(full_page, "implicit")


# ---------------------------------------------------------------------------
# what cannot be computed says why


def test_without_inputs_every_statement_says_why():
    """No tables, no benchmarks, no random kind, the implicit surface switched off: no crash, each statement says why
    and links nowhere."""
    page = parse(R.build_report({}, {}))
    assert_links_land(page)
    assert [s["finding"] for s in page.statements] == ["ranking", "exact", "implied", "laws", "implicit", "random",
                                                       "light-transport", "accuracy", "speed"]
    assert all(not s["links"] for s in page.statements)
    text = {s["finding"]: s["text"] for s in page.statements}
    assert text["ranking"].startswith("Tables 1–2 could not be computed: none of the table aspects (1, √3/2) at "
                                      "incidence 30 is in the study")
    assert text["exact"].startswith("No lobe peak was compared") and "Tables 1–2 could not be computed" in text["implied"]
    assert text["laws"].startswith("No share law could be fitted")
    assert text["implicit"] == "The implicit rough surface was not measured (report.implicit: false)."
    assert text["random"].startswith("Random roughness was not measured: surface.kind lists no random kind")
    assert text["accuracy"].endswith("(report.speed_accuracy: false).")
    assert text["speed"] == "The renderers' speed was not measured (report.speed_accuracy: false)."
    assert text["light-transport"] == ("The surfaces were not rendered with light that bounces "
                                       "(report.light_transport.enabled: false).")


def test_a_partial_run_says_what_it_lacks(tables):
    """The tables without their exact peaks, a benchmark without a naive row or a validation: each of those
    statements says why; the others are made. The random and implicit sections shown without their frames (which a
    page built from its inputs cannot be: a section's frames are its inputs) say so too."""
    partial = dict(tables, exact_peaks=None)
    table = speed_table().query("method != 'naive'")
    page = parse(R.build_report({**partial, "speed_accuracy": table}, {}, table_aspects=ASPECTS))
    assert_links_land(page)
    text = {s["finding"]: s["text"] for s in page.statements}
    assert text["exact"] == "The lobe peaks were not compared with the exact reference (report.exact_check: false)."
    assert text["speed"] == "The speed/accuracy benchmark has no row of the naive method to compare with."
    assert text["accuracy"] == "The renderer's check against the exact reference at every view was not given."
    assert text["ranking"].startswith("Tables 1–2 rank the models the other way round")
    html = render("findings.html", s=PF.findings_section(table_aspects=ASPECTS, shown={"random": True, "implicit": True}))
    assert "The random-roughness claim table was not given." in html
    assert "The implicit surface's validation was not given." in html


def test_no_claim_row_and_no_lobe_say_why():
    no_claim = claims_frame().iloc[:0]
    assert PF.random_claim_finding(no_claim, shown=True) == {"why": "no_claim"}
    assert PF.random_claim_finding(claims_frame(), shown=False) == {"why": "no_kind"}
    html = render("findings.html", s=_section(random=PF.random_claim_finding(no_claim, shown=True)))
    assert "No test of the thesis's random-roughness claim could be computed" in html
    assert PF.share_law_finding(pd.DataFrame()) == {"why": "no_laws"}


def test_the_claim_its_design_and_its_finding_show_in_chromium(tables, tmp_path):
    """The page as a reader sees it in Chromium: the random-roughness finding, the claim's design with its margins
    and family, which lobes enter it, the pilot's plan, and the verdict table, a test a row with its two readings
    side by side."""
    from .browser import Browser

    claims = claims_frame()
    unrounded = claims[claims["reading"] == "unrounded"]
    design = unrounded[["kind", "truncation", "aspect", "incidence", "test"]].assign(
        lobe="back", role=["lobe"] * 4 + ["shape"] * 4, family=8, level=1 - 0.05 / 8, margin=unrounded["margin"],
        regular=unrounded["regular"], pilot_seeds=4, pilot_width=9.0, pilot_mean=1.0, pilot_se=0.1,
        seeds_needed=pd.array([12] * 8, dtype="Int64"), plan="a lobe expected from the pilot", seeds_configured=12,
        ensemble_seeds=12)
    margins = claims[["kind", "truncation", "aspect", "incidence", "test", "reading", "regular", "margin"]].assign(
        rendering_noise=0.001, sampling_error=0.0, grid_effect=0.004, rounding=np.nan, matters=0.05,
        **{"from": "difference that matters"})
    geometry = pd.DataFrame([{"truncation": t, "aspect": 0.5, "incidence": 30.0, "lobe": "back", "centre_azimuth": 0.0,
                              "centre_elevation": 60.0, "width": 8.4, "radius": 25.2, "clearance": 59.0, "cap": 45.0,
                              "in_claim": True, "why": ""} for t in (0.5, 1.0)])
    html = R.build_report({**tables, **benchmarks(), **measured(), "random_claim_design": design,
                           "random_claim_margins": margins, "random_claim_geometry": geometry},
                          {}, table_aspects=ASPECTS)
    path = tmp_path / "report.html"
    path.write_text(html, encoding="utf-8")
    with Browser(1280, 900, workdir=tmp_path) as browser:
        browser.open(path)
        text = browser.evaluate("""(() => { const out = {};
            for (const id of ['random-claim-design', 'random-claim-verdict', 'random-claim', 'random-claim-plan',
                              'random-claim-geometry']) {
              const e = document.getElementById(id);
              out[id] = e ? {shown: e.getBoundingClientRect().height > 0 || !!e.closest('details'),
                             text: e.innerText} : null; }
            out.rows = [...document.querySelectorAll('#random-claim tbody tr')].map(r => [...r.cells].map(
              c => c.innerText));
            out.head = [...document.querySelectorAll('#random-claim thead th')].map(c => c.innerText);
            out.design = document.getElementById('random-claim-design').parentElement.innerText;
            out.finding = document.querySelector('[data-finding="random"]').innerText;
            return out; })()""")
        assert browser.errors() == []
    for name in ("random-claim-design", "random-claim-verdict", "random-claim", "random-claim-plan",
                 "random-claim-geometry"):
        assert text[name] is not None and text[name]["shown"], name
    head = [h.replace("\u200b", "") for h in text["head"]]
    assert head[:3] == ["kind", "truncation", "aspect"]
    assert "unrounded: verdict" in head and "8-bit: verdict" in head
    # a test a row, both readings' verdicts side by side
    assert [row[head.index("unrounded: verdict")] for row in text["rows"]] == list(unrounded["verdict"])
    eight = claims[claims["reading"] == "8-bit"]
    assert [row[head.index("8-bit: verdict")] for row in text["rows"]] == list(eight["verdict"])
    assert "Margin 0.05 over the grid points, set most often by the difference that matters" in text["design"]
    assert "the 8 planned tests are corrected together (Bonferroni)" in text["design"]
    assert text["finding"].startswith("No test of the thesis's random-roughness claim finds the difference it claims.")


def test_the_light_transport_section_and_its_finding_show_in_chromium(tmp_path):
    """Beyond the OpenGL equation as a reader sees it in Chromium: its chart decoded, its two tables, the gain a
    surface at every albedo, and the finding's link landing on the section, nothing wider than the page."""
    from roughlight.measurements.light_transport import interreflection_summary
    from roughlight.report import figures as F

    from .browser import read_page

    frames = light_frames()
    summary = frames["interreflection_summary"]
    rows = [{"truncation": r.truncation, "aspect": r.aspect, "incidence": 30.0, "albedo": r.albedo,
             "views": v, "azimuth": 0.0, "elevation": e, "direct": 60.0, "bounced": 60.0 + r.mean_gain,
             "gain": r.mean_gain, "gain_percent": 100 * r.mean_gain / 60.0, "bounces": 8}
            for r in summary.itertuples() for v in ("arc", "hemisphere") for e in (30.0, 90.0, 150.0)]
    chart = F.make("light_transport", tmp_path / "light_transport.png", summary=interreflection_summary(
        pd.DataFrame(rows)), frame=pd.DataFrame(rows))
    html = R.build_report({**frames, "light_transport_png": chart}, {})
    seen = read_page(html, tmp_path, """(() => { const s = document.getElementById('light-transport');
        const img = document.querySelector('#fig-light-transport img');
        const link = document.querySelector('[data-finding="light-transport"] a');
        return {img: !!img && img.complete && img.naturalWidth > 0,
                tables: ['mitsuba-agreement-table', 'interreflection-table'].map(
                  id => !!document.getElementById(id)),
                text: s.parentElement.innerText, link: link && link.getAttribute('href'),
                wide: [...document.querySelectorAll('body *')].filter(
                  e => e.getBoundingClientRect().right > 1280 + 1).map(e => e.tagName).slice(0, 3)}; })()""")
    assert seen["img"] and seen["tables"] == [True, True] and seen["link"] == "#light-transport"
    assert seen["wide"] == []
    assert "views. Every view is within one level" in seen["text"]  # two sentences, the bounces named
    assert "With light that bounces 8 times between facets" in seen["text"]
    assert "albedo 1: a mean gain of" in seen["text"] and "albedo 0.5: a mean gain of" in seen["text"]
