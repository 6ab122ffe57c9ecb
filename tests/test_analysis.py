"""Tests of the analysis: lobes, diffuse parts, the thesis's tables, GLMs, analytic models.

The data are made here: small studies from the exact polygon-clipping
reference (``make_study``) or synthetic curves with known parameters.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from roughlight.analysis.areas import reflecting_areas
from roughlight.analysis.diffuse import diffuse_breakpoints, diffuse_levels, diffuse_three_part
from roughlight.analysis.glm import grid_glm, grid_glms
from roughlight.analysis.lobes import arc_lobes, hemisphere_lobes, profile_lobe
from roughlight.analysis.surface_models import (
    analytic_model_fits,
    facet_model,
    fit_hapke,
    model_fit_summary,
    oren_nayar,
    oren_nayar_sigma,
)
from roughlight.analysis.thesis import (
    TABLE_METRICS,
    bootstrap_statistics,
    exact_lobe_peaks,
    fit_statistics,
    sine_refits,
    thesis_tables,
)
from roughlight.analysis.timings import render_timings
from roughlight.render.shading import Lighting, phase_angle, quantize
from roughlight.surfaces.geometry import lobe_centres
from roughlight.surfaces.surface import Surface

J = 127.0
S32 = math.sqrt(3.0) / 2.0


def make_study(truncations, aspects, incidence=30.0, azimuths=(0.0,), elevations=None, method="reference",
               lighting=None, settings=None):
    """A study table (the columns of results/study.parquet) measured here.

    ``method`` 'reference' uses the exact polygon clipping, 'fast' the renderer.
    """
    from roughlight.render import methods

    lighting = lighting or Lighting()
    elevations = np.arange(0.0, 181.0, 1.0) if elevations is None else np.asarray(elevations, float)
    az, el = np.meshgrid(np.asarray(azimuths, float), elevations, indexing="ij")
    az, el = az.ravel(), el.ravel()
    rs = methods.settings(method, settings)
    plate_lighting = Lighting(**{**lighting.as_dict(), "shadows": False})
    control = methods.sweep(method, Surface(0.0, 0.0), incidence, az, el, plate_lighting, rs)
    frames = []
    for t in truncations:
        for a in aspects:
            out = methods.sweep(method, Surface(t, a), incidence, az, el, lighting, rs)
            for comp in ("diffuse", "specular", "total"):
                frames.append(pd.DataFrame({
                    "truncation": float(t), "aspect": float(a), "incidence": float(incidence),
                    "azimuth": az, "elevation": el, "phase": phase_angle(incidence, el, az), "component": comp,
                    "rough": np.asarray(out[comp], float), "control": np.asarray(control[comp], float),
                    "coverage": np.asarray(out["coverage"], float), "light": lighting.light,
                    "ambient": lighting.ambient, "shininess": lighting.shininess,
                    "specular_model": lighting.specular_model, "shadows": lighting.shadows, "method": method,
                    "pixels_per_period": rs.pixels_per_period if method == "fast" else 0,
                    "shadow_map_size": rs.shadow_map_size if method == "fast" else 0,
                    "render_seconds": float(out["seconds"]),
                }))
    return pd.concat(frames, ignore_index=True)


@pytest.fixture(scope="module")
def exact_study():
    """Exact values on the light's plane (and one cross arc) for the thesis's key surfaces."""
    return make_study([0.0, 0.3, 0.5, 1.0], [1.0, S32], azimuths=(0.0, 90.0))


# ---------------------------------------------------------------------------
# geometry of lobes and diffuse parts


def test_lobe_centres_follow_the_facets():
    c = lobe_centres(30, S32)
    assert c["forward"] == pytest.approx(150.0)
    assert c["back"] == pytest.approx(30.0, abs=1e-9)  # zero phase: the facet faces the light
    assert c["west"] is None
    c1 = lobe_centres(30, 1.0)
    assert c1["back"] == pytest.approx(180 - 2 * math.degrees(math.atan(2.0)) - 30)  # 23.13
    # the back side's mirror lobe exists only while 2 s < i (thesis Fig. 26, aspect 0.1)
    c01 = lobe_centres(30, 0.1)
    assert c01["west"] == pytest.approx(180 + 2 * math.degrees(math.atan(0.2)) - 30)
    assert lobe_centres(30, 0.2)["west"] is None
    assert lobe_centres(30, 0.0)["back"] is None


def test_diffuse_breakpoints_are_the_thesis_domains_at_60_degree_facets():
    assert diffuse_breakpoints(30, S32) == pytest.approx((30.0, 120.0))
    e1, e2 = diffuse_breakpoints(30, 1.0)
    assert (e1, e2) == pytest.approx((30.0, 180 - math.degrees(math.atan(2.0))))


# ---------------------------------------------------------------------------
# lobe profiles


def test_profile_lobe_recovers_peak_centre_and_width():
    e = np.arange(0.0, 181.0, 1.0)
    sigma = 7.0
    v = 100 * np.exp(-0.5 * ((e - 37.0) / sigma) ** 2) + 40 * np.exp(-0.5 * ((e - 120.0) / 5.0) ** 2)
    out = profile_lobe(e, v, 37.0, (0.0, 78.0))
    assert out["peak"] == pytest.approx(100.0)
    assert out["peak_elevation"] == 37.0
    assert out["fwhm"] == pytest.approx(2 * math.sqrt(2 * math.log(2)) * sigma, abs=0.2)
    assert out["centroid"] == pytest.approx(37.0, abs=0.05)
    other = profile_lobe(e, v, 120.0, (78.0, 180.0))
    assert other["peak"] == pytest.approx(40.0, abs=1e-6) and other["peak_elevation"] == 120.0
    # a window cutting the lobe before half maximum gives no width, and says so
    cut = profile_lobe(e, v, 37.0, (30.0, 40.0))
    assert np.isnan(cut["fwhm"]) and "half maximum" in cut["note"]
    none = profile_lobe(e, np.zeros_like(e), 37.0, (0.0, 90.0))
    assert none["peak"] == 0 and np.isnan(none["peak_elevation"]) and "no lobe" in none["note"]


def test_arc_lobes_on_exact_data_follow_the_area_laws(exact_study):
    lobes = arc_lobes(exact_study)
    for (t, a), g in lobes.groupby(["truncation", "aspect"]):
        fwd = g[g["lobe"] == "forward"].iloc[0]
        back = g[g["lobe"] == "back"].iloc[0]
        assert fwd["peak"] == pytest.approx(J * (1 - t) ** 2, abs=1e-6)
        assert back["peak"] == pytest.approx(0.5 * J * (1 - (1 - t) ** 2), abs=0.02)
        if 0 < t < 1:
            assert fwd["peak_elevation"] == 150.0
            # Phong 64: full width at half maximum 2 acos(0.5^(1/64)) = 16.8 deg; the 8-bit steps move it a little
            assert fwd["fwhm"] == pytest.approx(2 * math.degrees(math.acos(0.5 ** (1 / 64))), abs=0.6)
        if t > 0:
            expected = lobe_centres(30, a)["back"]
            assert abs(back["peak_elevation"] - expected) <= 0.5 + 1e-9  # the 1-degree grid
    sq = lobes[(lobes["aspect"] == S32) & (lobes["lobe"] == "back") & (lobes["truncation"] == 1.0)].iloc[0]
    assert sq["phase_at_peak"] == pytest.approx(0.0, abs=1e-9)  # zero phase: the thesis's retro lobe


def test_hemisphere_lobes_find_the_mirror_directions():
    study = make_study([0.5], [S32], azimuths=np.arange(0.0, 180.0, 30.0), elevations=np.arange(0.0, 181.0, 3.0))
    h = hemisphere_lobes(study)
    fwd = h[h["lobe"] == "forward"].iloc[0]
    back = h[h["lobe"] == "back"].iloc[0]
    assert (fwd["peak_azimuth"], fwd["peak_elevation"]) == (0.0, 150.0)
    assert fwd["peak"] == pytest.approx(J * 0.25)
    assert back["phase_at_peak"] == pytest.approx(0.0) and back["angle_from_mirror"] == pytest.approx(0.0, abs=1e-9)
    # the forward lobe is one Phong lobe: its half-maximum cone is ~17 deg wide (coarse grid: loose)
    assert 10.0 < fwd["cone_fwhm"] < 25.0


def test_exact_lobe_peaks_agree_with_an_exact_study(exact_study):
    lobes = arc_lobes(exact_study)
    ex = exact_lobe_peaks(lobes)
    assert len(ex) == 2 * 4 * 2  # aspects x truncations x lobes
    np.testing.assert_allclose(ex["error"], 0.0, atol=1e-9)


# ---------------------------------------------------------------------------
# Tables 1 and 2


def test_fit_statistics_is_the_thesis_glm():
    rng = np.random.default_rng(5)
    pred = np.linspace(0, 127, 11)
    obs = 2.0 + 1.1 * pred + rng.normal(0, 1.5, pred.size)
    st = fit_statistics(obs, pred)
    b1, b0 = np.polyfit(pred, obs, 1)  # a Gaussian GLM with identity link is least squares
    assert st["b0"] == pytest.approx(b0, rel=1e-8) and st["b1"] == pytest.approx(b1, rel=1e-8)
    assert st["RSS"] == pytest.approx(np.sum((obs - (b0 + b1 * pred)) ** 2), rel=1e-8)
    err = obs - pred
    assert st["Mean Abs Error"] == pytest.approx(np.mean(np.abs(err)))
    assert st["Standard Deviation"] == pytest.approx(np.std(err, ddof=1))
    assert st["converged"] and st["n"] == 11


@pytest.mark.parametrize("pred, why", [(np.full(11, 5.0), "one value"), (np.arange(2.0), "only 2 points")])
def test_fit_statistics_degenerate_inputs_are_reported(pred, why):
    st = fit_statistics(pred + 1.0, pred)
    assert np.isnan(st["b0"]) and why in st["note"]


def _synthetic_lobes(aspects, law="area"):
    rows = []
    for a in aspects:
        for t in np.round(np.arange(0, 1.01, 0.1), 10):
            fwd = J * (1 - t) ** 2 if law == "area" else J * (1 - math.sin(t * math.pi / 2))
            back = 0.5 * J * (1 - (1 - t) ** 2) if law == "area" else J * math.sin(t * math.pi / 2) / 2
            for lobe, peak in (("forward", fwd), ("back", back)):
                rows.append({"truncation": t, "aspect": a, "incidence": 30.0, "lobe": lobe, "peak": peak})
    return pd.DataFrame(rows)


def test_thesis_tables_rank_the_true_law_first():
    for law, winner in (("area", "Area Function"), ("sine", "Regressed Model")):
        tables, messages = thesis_tables(_synthetic_lobes([1.0, S32], law))
        assert messages == []
        ours = tables[tables["source"] == "ours"]
        assert len(ours) == 8  # 2 aspects x 2 tables x 2 models
        for _, g in ours.groupby(["table", "aspect"]):
            best = g.sort_values("Mean Abs Error").iloc[0]
            assert winner in best["model"]
            assert best["Mean Abs Error"] == pytest.approx(0.0, abs=1e-9)
            assert best["b1"] == pytest.approx(1.0) and best["RSS"] == pytest.approx(0.0, abs=1e-9)
        thesis = tables[(tables["source"] == "thesis 2001") & (tables["table"] == 1)
                        & (tables["model"] == "Square Area Function")]
        assert thesis[TABLE_METRICS].iloc[0].tolist() == [4.10, 3.08, -4.684, 1.012, 122.407]


def test_thesis_tables_without_sqrt3_2_say_so():
    tables, messages = thesis_tables(_synthetic_lobes([1.0]))
    assert set(tables["aspect"]) == {1.0}
    assert any("√3/2" in m and "not in the study" in m for m in messages)
    empty, messages = thesis_tables(_synthetic_lobes([0.5]))
    assert empty.empty and len(messages) == 2


def test_sine_refits_recover_parameters_and_intervals():
    rows = []
    rng = np.random.default_rng(1)
    for t in np.linspace(0, 1, 11):
        rows.append({"truncation": t, "aspect": 1.0, "incidence": 30.0, "lobe": "forward",
                     "peak": 120 * (1 - math.sin(1.8 * t)) + rng.normal(0, 0.3)})
        rows.append({"truncation": t, "aspect": 1.0, "incidence": 30.0, "lobe": "back",
                     "peak": 60 * math.sin(1.3 * t) + rng.normal(0, 0.3)})
    fits = sine_refits(pd.DataFrame(rows), aspects=(1.0,))
    got = {(r.lobe, r.parameter): r for r in fits.itertuples()}
    truth = {("forward", "A"): 120, ("forward", "omega"): 1.8, ("back", "A"): 60, ("back", "omega"): 1.3}
    for key, true in truth.items():
        r = got[key]
        assert r.ci_low < true < r.ci_high
        assert r.estimate == pytest.approx(true, rel=0.03)
    assert not got[("forward", "omega")].thesis_inside  # pi/2 is far from 1.8


def test_reflecting_areas_are_the_normalised_area_functions():
    areas = reflecting_areas(S32, 30.0, truncations=[0.0, 0.25, 0.5, 1.0])
    np.testing.assert_allclose(areas["top"], (1 - areas["truncation"]) ** 2, atol=1e-9)
    np.testing.assert_allclose(areas["front"], 0.5 * (1 - (1 - areas["truncation"]) ** 2), atol=1e-9)
    assert areas["k"].iloc[0] == pytest.approx(0.5)


# ---------------------------------------------------------------------------
# the diffuse component


def _diffuse_frame(levels):
    rows = []
    e = np.arange(0.0, 181.0, 1.0)
    for (t, a), (L1, L3, k) in levels.items():
        e1, e2 = diffuse_breakpoints(30, a)
        v = np.where(e <= e1, L1, np.where(e >= e2, L3, L3 + (L1 - L3) * np.exp(-k * (e - e1))))
        cov = ((e > 0) & (e < 180)).astype(float)
        rows.append(pd.DataFrame({"truncation": t, "aspect": a, "incidence": 30.0, "azimuth": 0.0, "elevation": e,
                                  "phase": phase_angle(30, e, 0.0), "component": "diffuse", "rough": v * cov,
                                  "control": 63.5 * cov, "coverage": cov}))
    return pd.concat(rows, ignore_index=True)


def test_diffuse_three_part_recovers_levels_and_decay():
    frame = _diffuse_frame({(0.5, 1.0): (75.0, 27.0, 0.03), (0.0, 1.0): (64.0, 64.0, 0.0)})
    parts = diffuse_three_part(frame).set_index("truncation")
    r = parts.loc[0.5]
    assert (r["level1"], r["level3"]) == pytest.approx((75.0, 27.0))
    assert r["rate"] == pytest.approx(0.03, rel=1e-3) and r["rmse"] < 1e-6
    assert r["e2"] == pytest.approx(180 - math.degrees(math.atan(2.0)))
    plate = parts.loc[0.0]
    assert np.isnan(plate["rate"]) and "plate" in plate["note"]


def test_diffuse_three_part_on_exact_data(exact_study):
    parts = diffuse_three_part(exact_study)
    full = parts[(parts["truncation"] == 1.0) & (parts["aspect"] == S32)].iloc[0]
    # part one: only lit facets are seen (no shadow below zero phase); part three: the lit front facet is hidden
    assert full["level1"] > full["level3"] and np.isfinite(full["rate"]) and full["rate"] > 0
    assert full["n_part1"] == 30 and full["n_part3"] == 60


# ---------------------------------------------------------------------------
# GLMs over the grid


def _grid(ts, as_, f, noise=0.0, seed=0):
    rng = np.random.default_rng(seed)
    rows = [{"truncation": t, "aspect": a, "incidence": 30.0, "y": f(t, a) + rng.normal(0, noise)}
            for t in ts for a in as_]
    return pd.DataFrame(rows)


def test_grid_glm_recovers_an_interaction_model():
    g = np.round(np.arange(0, 1.01, 0.1), 10)
    data = _grid(g, g, lambda t, a: 1 + 2 * t + 3 * a + 4 * t * a, noise=0.05)
    res = grid_glm(data, "y")
    assert res.summary["status"] == "ok" and res.summary["converged"]
    assert res.summary["n"] == 100  # the 21 plate surfaces are kept out
    assert any("plate" in m for m in res.messages)
    est = dict(zip(res.coefficients["term"], res.coefficients["estimate"]))
    assert est["truncation:aspect"] == pytest.approx(4, abs=0.1) and est["aspect"] == pytest.approx(3, abs=0.1)
    assert res.diagnostics["leverage"].sum() == pytest.approx(4.0)  # trace of the hat matrix = p
    assert res.summary["condition_scaled"] < 30


def test_scaled_condition_is_belsleys_uncentred_unit_length_scaling():
    from roughlight.analysis.glm import scaled_condition

    # a column nearly constant is collinear with the intercept: centring would hide it, Belsley's scaling shows it
    x = 10 + 1e-3 * np.arange(20)
    X = np.column_stack([np.ones(20), x])
    assert scaled_condition(X) > 1e3
    # orthogonal columns of any lengths: 1
    Q = np.column_stack([np.r_[1, 1, 1, 1], 5 * np.r_[1, -1, 1, -1], 0.1 * np.r_[1, 1, -1, -1]]).astype(float)
    assert scaled_condition(Q) == pytest.approx(1.0)


def test_grid_glm_degenerate_grids_never_crash():
    # only plates: nothing left to fit
    res = grid_glm(_grid([0.0], [0.0, 0.5, 1.0], lambda t, a: 5.0), "y")
    assert res.summary["status"] == "not fitted" and res.coefficients.empty
    assert any("nothing to fit" in m or "zero variance" in m for m in res.messages)
    # one truncation: zero variance, the fit keeps aspect only
    res = grid_glm(_grid([0.5], [0.2, 0.4, 0.6, 0.8, 1.0], lambda t, a: 2 * a, noise=0.01), "y")
    assert "truncation" in " ".join(res.messages) and "zero variance" in " ".join(res.messages)
    assert list(res.coefficients["term"]) == ["const", "aspect"]
    # aspect tied to truncation: collinear, a term is kept out with a message
    data = pd.DataFrame({"truncation": np.linspace(0.1, 1, 10), "incidence": 30.0})
    data["aspect"] = data["truncation"]
    data["y"] = np.arange(10.0)
    res = grid_glm(data, "y")
    assert any("near-collinear" in m for m in res.messages)
    assert res.summary["dropped"]
    # missing responses (no lobe) are reported and skipped
    data = _grid([0.5, 1.0], [0.5, 1.0], lambda t, a: t + a)
    data.loc[0, "y"] = np.nan
    res = grid_glm(data, "y")
    assert any("without a value" in m for m in res.messages)


def test_grid_glms_on_lobes(exact_study):
    lobes = arc_lobes(exact_study)
    levels = diffuse_levels(exact_study)
    summary, coefs, diags, messages = grid_glms(lobes, levels)
    assert list(summary["response"]) == ["forward_peak", "back_peak", "diffuse_level"]
    assert (summary["n"] == 6).all()  # 3 rough truncations x 2 aspects
    assert isinstance(messages, list) and any("plate" in m for m in messages)


# ---------------------------------------------------------------------------
# analytic models


def test_oren_nayar_limits():
    e = np.array([30.0, 90.0, 150.0])
    lam = oren_nayar(30, e, np.zeros(3), 0.0)
    np.testing.assert_allclose(lam, J * math.sin(math.radians(30)))
    rough = oren_nayar(30, e, np.zeros(3), 0.5)
    assert rough[0] > rough[2]  # backscatter: brighter toward the light than away from it
    assert oren_nayar_sigma(0.0, 1.0) == 0.0
    assert oren_nayar_sigma(1.0, S32) == pytest.approx(math.radians(60.0))


def test_facet_model_is_exact_on_the_plate():
    e = np.arange(1.0, 180.0, 1.0)
    out = facet_model(0.0, 0.0, 30.0, e, np.zeros_like(e))
    i = math.radians(30)
    rdotv = -math.cos(i) * np.cos(np.radians(e)) + math.sin(i) * np.sin(np.radians(e))
    np.testing.assert_allclose(out["specular"], quantize(J * np.maximum(rdotv, 0) ** 64))
    np.testing.assert_allclose(out["diffuse"], quantize(J * math.sin(i)))


def test_vcavity_masking_improves_the_facet_model(exact_study):
    comp = exact_study[(exact_study["component"] == "specular") & (exact_study["truncation"] == 1.0)
                       & (exact_study["aspect"] == 1.0) & (exact_study["coverage"] > 0)]
    e, phi = comp["elevation"].to_numpy(), comp["azimuth"].to_numpy()
    masked = facet_model(1.0, 1.0, 30.0, e, phi)["specular"]
    plain = facet_model(1.0, 1.0, 30.0, e, phi, masking="none")["specular"]
    err_m = np.sqrt(np.mean((masked - comp["rough"].to_numpy()) ** 2))
    err_p = np.sqrt(np.mean((plain - comp["rough"].to_numpy()) ** 2))
    assert err_m < err_p and err_m < 2.0


def test_fit_hapke_recovers_a_surge():
    g = np.repeat(np.arange(0.0, 60.0, 0.5), 3)
    c, d, S, h = 50.0, -0.3, 40.0, 0.05
    v = c + d * g + S / (1 + np.tan(np.radians(g) / 2) / h)
    fit = fit_hapke(g, v)
    assert fit["h"] == pytest.approx(h, rel=0.02) and fit["B0"] == pytest.approx(S / c, rel=0.02)
    assert fit["rmse"] < 0.05 < fit["rmse_constant"]
    flat = fit_hapke(g, 70 - 0.2 * g)
    assert flat["S"] == 0 and "no surge" in flat["note"]
    few = fit_hapke(np.array([1.0, 2.0]), np.array([3.0, 4.0]))
    assert np.isnan(few["rmse"]) and "only" in few["note"]


def test_analytic_model_fits_rank_the_models(exact_study):
    fits = analytic_model_fits(exact_study)
    rough = fits[~fits["plate"]]
    assert len(rough) == 6
    # the explicit surfaces are V-cavity-like: the facet model beats the plate's Phong lobe
    assert (rough["rmse_facet_vcavity_specular"] < rough["rmse_phong_plate"]).all()
    plate = fits[fits["plate"]]
    np.testing.assert_allclose(plate["rmse_lambert"], 0.0, atol=1e-9)
    summary = model_fit_summary(fits)
    assert {"plate", "all"} <= set(summary["band"])
    by = summary.groupby(["component", "band"])
    assert (by["best_in"].sum() == by["surfaces"].first()).all()  # every surface has exactly one best model


def test_render_timings():
    study = make_study([0.0, 1.0], [1.0], elevations=np.arange(0.0, 181.0, 30.0))
    per, summary = render_timings(study)
    # 7 elevations a sweep, of which 0 and 180 were not rendered (coverage 0): 5 views drawn
    assert (study.loc[study["elevation"].isin([0.0, 180.0]), "coverage"] == 0).all()
    assert len(per) == 2 and (per["views"] == 5).all()
    assert summary["sweeps"] == 2 and summary["views"] == 10
    assert summary["total_seconds"] == pytest.approx(per["seconds"].sum())


def _arc_study(truncations, aspects, incidences):
    """A made-up study of the light's plane (azimuth 0, elevations 0..180 by 1): each surface's specular has a
    forward lobe at the mirror elevation 180 - i and a back lobe at 180 - 2 atan(2 aspect) - i (Gaussian, 6 deg
    wide, heights from truncation and aspect); e = 0 and 180 were not rendered (coverage 0, value 0)."""
    e = np.arange(0.0, 181.0, 1.0)
    frames = []
    for t in truncations:
        for a in aspects:
            for i in incidences:
                centres = lobe_centres(i, a)
                rough = (100 * (1 - t) ** 2 + 10 * a) * np.exp(-0.5 * ((e - centres["forward"]) / 6.0) ** 2)
                rough += 40 * t * a * np.exp(-0.5 * ((e - centres["back"]) / 6.0) ** 2)
                rendered = (e > 0) & (e < 180)
                frames.append(pd.DataFrame({"truncation": t, "aspect": a, "incidence": i, "azimuth": 0.0,
                                            "elevation": e, "phase": phase_angle(i, e, 0.0), "component": "specular",
                                            "rough": np.where(rendered, rough, 0.0), "control": 0.0,
                                            "coverage": rendered.astype(float)}))
    return pd.concat(frames, ignore_index=True)


def test_a_lobe_the_horizon_cuts_is_left_out_of_its_glm_and_counted():
    """At incidence 1 the forward lobe's maximum is on the last rendered view, e = 179, beside the unrendered 180:
    the horizon cuts it, its peak may lie beyond. It is no peak (arc_lobes says why) and the forward peak's GLM
    leaves those surfaces out and counts them; the back peak's GLM keeps them."""
    from roughlight.analysis.lobes import HORIZON_CUT

    ts, as_ = [0.25, 0.5, 0.75, 1.0], [0.5, 0.75, 1.0]
    lobes = arc_lobes(_arc_study(ts, as_, [1.0, 30.0]))
    forward = lobes[lobes["lobe"] == "forward"]
    cut = forward[forward["incidence"] == 1.0]
    assert cut["peak"].isna().all() and cut["note"].str.startswith(HORIZON_CUT).all()
    assert (cut["note"].str.contains("179 deg")).all()
    kept = forward[forward["incidence"] == 30.0]
    assert np.isfinite(kept["peak"]).all() and (kept["peak_elevation"] == 150.0).all()
    levels = lobes[["truncation", "aspect", "incidence"]].drop_duplicates().assign(diffuse_level=lambda d: d["aspect"])
    summary, _, diagnostics, messages = grid_glms(lobes, levels)
    rows = summary.set_index("response")
    n = len(ts) * len(as_)
    assert rows.loc["forward_peak", "n"] == n and rows.loc["forward_peak", "cut_by_horizon"] == n
    assert rows.loc["back_peak", "n"] == 2 * n and rows.loc["back_peak", "cut_by_horizon"] == 0
    assert f"forward_peak: {n} surfaces whose lobe the horizon cuts" in " ".join(messages)
    fitted = diagnostics[diagnostics["response"] == "forward_peak"]
    assert (fitted["incidence"] == 30.0).all()


def test_grid_glm_uses_incidence_when_the_grid_has_several():
    g = np.round(np.arange(0.1, 1.01, 0.1), 10)
    a = _grid(g, g, lambda t, a_: 1 + 2 * t + 3 * a_, noise=0.05)
    b = a.copy()
    b["incidence"] = 45.0
    b["y"] += 5.0
    res = grid_glm(pd.concat([a, b], ignore_index=True), "y")
    est = dict(zip(res.coefficients["term"], res.coefficients["estimate"]))
    assert est["incidence"] == pytest.approx(5.0 / 15.0, abs=0.01)


def test_bootstrap_intervals_cover_the_statistics_and_match_statsmodels():
    import numpy as np

    rng = np.random.default_rng(3)
    t = np.linspace(0, 1, 11)
    predicted = 127 * (1 - t) ** 2
    observed = predicted + rng.normal(0, 2.0, size=t.size)
    stats = fit_statistics(observed, predicted)
    ci = bootstrap_statistics(observed, predicted, n_boot=2000, seed=0)
    assert ci["n_boot_used"] == 2000
    for metric in TABLE_METRICS:
        low, high = ci[metric]
        assert low < high, metric
        assert low <= stats[metric] <= high or metric == "RSS", (metric, low, stats[metric], high)
    # the closed-form least-squares line the bootstrap uses is the statsmodels Gaussian GLM's
    b1, b0 = np.polyfit(predicted, observed, 1)
    assert b0 == pytest.approx(stats["b0"], abs=1e-9) and b1 == pytest.approx(stats["b1"], abs=1e-12)
    assert np.sum((observed - b0 - b1 * predicted) ** 2) == pytest.approx(stats["RSS"], rel=1e-9)
    # an exact model has zero-width error intervals; seeded resampling is reproducible
    exact = bootstrap_statistics(predicted, predicted, n_boot=200, seed=1)
    assert exact["Mean Abs Error"] == (0.0, 0.0)
    assert bootstrap_statistics(observed, predicted, n_boot=300, seed=5) == bootstrap_statistics(
        observed, predicted, n_boot=300, seed=5)
    # a model that predicts one value everywhere gives no line, and says so by using no resample
    flat = bootstrap_statistics(observed, np.full(11, 50.0), n_boot=100, seed=0)
    assert flat["n_boot_used"] == 0 and np.isnan(flat["b1"][0])


# ---------------------------------------------------------------------------
# errors a referee found (issue 14): each of these failed on the earlier code


def test_the_plates_diffuse_level_is_J_sin_i():
    """Views that see no surface (e = 0, 180: coverage 0, value 0) stay out of the hemisphere mean."""
    from roughlight.study.selection import solid_angle_weights

    study = make_study([0.0], [0.0], azimuths=np.arange(0.0, 180.0, 45.0), elevations=np.arange(0.0, 181.0, 5.0))
    level = diffuse_levels(study).iloc[0]
    assert level["diffuse_level"] == 64.0 and level["control_level"] == 64.0  # quantize(127 sin 30) = 64
    for az, el in ((np.arange(0.0, 180.0, 5.0), np.arange(0.0, 181.0, 1.0)), (np.arange(0.0, 180.0, 45.0),
                                                                            np.arange(0.0, 181.0, 5.0))):
        assert solid_angle_weights(az, el).sum() == pytest.approx(2 * math.pi, abs=1e-12)


def test_a_maximum_on_the_windows_edge_is_no_lobe():
    """A back-lobe window whose maximum is its edge holds the forward lobe's tail: no peak, and why."""
    e = np.arange(0.0, 181.0, 1.0)
    values = np.exp(-((e - 150.0) / 15.0) ** 2) * 100.0  # one forward lobe at 150
    tail = profile_lobe(e, values, centre=100.0, window=(60.0, 138.0))
    assert np.isnan(tail["peak"]) and "window's edge at 138" in tail["note"]
    real = profile_lobe(e, values, centre=150.0, window=(110.0, 180.0))
    assert real["peak"] == pytest.approx(100.0) and real["note"] == ""
    # where the profile ends (no view past its last one) nothing lies beyond: a maximum there stays a peak
    rising = profile_lobe(e, e, centre=170.0, window=(140.0, 180.0))
    assert rising["peak"] == 180.0
    # a view past the edge without a value (not rendered: e = 0, 180) is the horizon: the lobe is cut, no peak
    unrendered = np.where((e > 0) & (e < 180), e, np.nan)
    cut = profile_lobe(e, unrendered, centre=170.0, window=(140.0, 180.0))
    assert np.isnan(cut["peak"]) and cut["note"].startswith("cut by the horizon") and "179 deg" in cut["note"]
    falling = profile_lobe(e, np.where((e > 0) & (e < 180), 200.0 - e, np.nan), centre=10.0, window=(0.0, 40.0))
    assert np.isnan(falling["peak"]) and falling["note"].startswith("cut by the horizon") and "at 1 deg" in falling["note"]


def test_the_three_part_model_is_continuous_at_its_second_break():
    from roughlight.analysis.diffuse import continuous_part, exponential_part

    L1, L3, k, e1, e2 = 80.0, 20.0, 0.05, 30.0, 120.0
    assert continuous_part(e1, L1, L3, k, e1, e2) == pytest.approx(L1)
    assert continuous_part(e2, L1, L3, k, e1, e2) == pytest.approx(L3)
    assert exponential_part(e2, L1, L3, k, e1) - L3 == pytest.approx((L1 - L3) * math.exp(-k * (e2 - e1)))
    assert continuous_part(75.0, L1, L3, 1e-12, e1, e2) == pytest.approx(50.0)  # k -> 0: the straight line
    study = make_study([1.0], [1.0], elevations=np.arange(0.0, 181.0, 2.0))
    row = diffuse_three_part(study).iloc[0]
    assert abs(row["jump_at_e2"]) > 0.5  # the thesis's form jumps at e2
    assert np.isfinite(row["rate_continuous"]) and np.isfinite(row["rmse_continuous"])
    e = np.array([row["e2"] - 1e-9])
    assert continuous_part(e, row["level1"], row["level3"], row["rate_continuous"], row["e1"], row["e2"])[0] == \
        pytest.approx(row["level3"], abs=1e-6)


def test_every_model_is_scored_on_the_same_8_bit_values():
    """The fitted Oren-Nayar sigma is scored as the geometric one (quantized): on the plate it cannot lose
    to its own special case, and a fit that ends on a bound is flagged."""
    study = make_study([0.0, 1.0], [0.0, 1.0], azimuths=np.arange(0.0, 180.0, 45.0),
                       elevations=np.arange(0.0, 181.0, 5.0))
    fits = analytic_model_fits(study)
    assert (fits["rmse_oren_nayar_fitted"] <= fits["rmse_oren_nayar"] + 1e-12).all()
    plate = fits[fits["truncation"] * fits["aspect"] == 0]
    assert (plate["rmse_oren_nayar_fitted"] == 0.0).all()
    assert fits["sigma_fitted_at_bound"].dtype == bool


def test_the_report_flags_sigma_fits_on_a_bound():
    from roughlight.report import page as report

    fits = pd.DataFrame({"truncation": [0.0, 0.5, 1.0], "aspect": [0.0, 1.0, 1.0],
                         "sigma_fitted_at_bound": [False, True, False]})
    text = report.render_section("models", model_fits=fits, figures={}, provenance={})
    assert "ended on a bound" in text and "1 of 2 rough surfaces" in text
    fits["sigma_fitted_at_bound"] = False
    assert "ended on a bound" not in report.render_section("models", model_fits=fits, figures={}, provenance={})


def test_the_thesis_rows_carry_only_what_the_thesis_printed():
    lobes = arc_lobes(make_study([0.0, 0.5, 1.0], [1.0], elevations=np.arange(0.0, 181.0, 2.0)))
    tables, _ = thesis_tables(lobes, [1.0], 30.0)
    rows = tables[tables["source"] == "thesis 2001"]
    assert len(rows) == 4
    assert rows["n"].isna().all() and rows["converged"].isna().all() and (rows["truncations"] == "").all()


def test_the_sd_identity_tells_which_sd_a_table_gives():
    """RSS of the least-squares line <= (n - 1) SD^2 for the SD of the raw errors, never for SD of |error|
    necessarily; the thesis's Table 1 rows break the first at n = 11."""
    from roughlight.analysis.thesis import THESIS_TABLES, sd_bound

    rng = np.random.default_rng(7)
    for _ in range(20):
        predicted = rng.uniform(0, 127, 11)
        observed = predicted + rng.normal(0, 3, 11)
        stats = fit_statistics(observed, predicted)
        assert stats["RSS"] <= sd_bound(stats["Standard Deviation"], 11) * (1 + 1e-9)
    # errors of one size and both signs: SD of |error| is 0, yet the line leaves a residual
    predicted = np.linspace(0, 100, 11)
    observed = predicted + 2.0 * np.array([1, -1] * 5 + [1])
    stats = fit_statistics(observed, predicted)
    assert stats["SD of |error|"] == pytest.approx(0.0, abs=1e-12)
    assert stats["RSS"] > sd_bound(stats["SD of |error|"], 11)
    assert stats["RSS"] <= sd_bound(stats["Standard Deviation"], 11) * (1 + 1e-9)
    t1 = {m: dict(zip(["MAE", "SD", "b0", "b1", "RSS"], v)) for m, v in THESIS_TABLES[1]["rows"].items()}
    assert all(row["RSS"] > sd_bound(row["SD"], 11) for row in t1.values())  # 122.4 > 94.9, 51.9 > 35.3


def test_hapke_is_charged_for_its_parameters_and_scored_on_held_out_bins():
    from roughlight.analysis.surface_models import fit_hapke

    g = np.linspace(0, 60, 121)
    # no surge, a little scatter: the nested four-parameter fit always wins in-sample, and loses where it counts
    flat = 40 + 0.1 * g + np.random.default_rng(1).normal(0, 0.5, g.size)
    fit = fit_hapke(g, flat)
    assert fit["rmse"] <= fit["rmse_constant"]
    assert fit["rmse_heldout"] > fit["rmse_constant_heldout"]
    assert fit["aic"] > fit["aic_constant"]
    # a real surge wins on every score
    surge = 40 + 0.1 * g + 20 / (1 + np.tan(np.radians(g) / 2) / 0.05)
    fit = fit_hapke(g, surge)
    assert fit["rmse_heldout"] < fit["rmse_constant_heldout"] / 10
    assert fit["aic"] < fit["aic_constant"]


def test_share_laws_fit_what_they_should_and_are_scored_held_out():
    from roughlight.analysis.share_laws import MODELS, share_law_fits

    m = 127.0
    rows = []
    ts = np.round(np.arange(0.1, 1.01, 0.1), 10)
    for a, k in ((0.5, 0.3), (1.0, 0.5)):
        for t in ts:
            rows.append({"truncation": t, "aspect": a, "incidence": 30.0, "lobe": "forward",
                         "peak": m * (1 - t) ** 2 if t < 1 else np.nan, "note": "" if t < 1 else "no lobe"})
            rows.append({"truncation": t, "aspect": a, "incidence": 30.0, "lobe": "back",
                         "peak": m * k * (1 - (1 - t) ** 2), "note": ""})
    fits = share_law_fits(pd.DataFrame(rows), m=m).set_index(["lobe", "model"])
    forward = fits.loc[("forward", "share law (no free parameter)")]
    assert forward["rmse"] < 1e-9 and forward["rmse_held_out"] < 1e-9 and forward["parameters"] == 0
    fitted = fits.loc[("back", MODELS[1])]
    assert fitted["rmse"] < 1e-9 and fitted["rmse_held_out"] < 1e-9 and fitted["parameters"] == 2
    # the linear GLM cannot follow the curvature: it is worse held out than in-sample, and worse than the share law
    linear = fits.loc[("back", MODELS[3])]
    assert linear["rmse_held_out"] > linear["rmse"] > 0.5
    quasi = fits.loc[("back", MODELS[2])]
    assert np.isfinite(quasi["rmse_held_out"]) and quasi["rmse_held_out"] >= quasi["rmse"]


def test_the_theses_own_numbers_bound_the_scale_of_its_area_functions():
    from roughlight.analysis.thesis import implied_scales

    scales = implied_scales().set_index("table")
    square = scales.loc[1]
    # the mean error at m = 127 is b0 + (b1 - 1) 127 * 0.35 = -4.15, larger in size than the reported MAE 4.10
    assert square["mean_error_at_stated"] == pytest.approx(-4.684 + 0.012 * 127 * 0.35)
    assert not square["stated_possible"]
    assert square["s_min_mae"] == pytest.approx((4.684 - 4.10) / (0.012 * 0.35))
    assert square["s_min_sd"] >= square["s_min_mae"] and square["s_max_sd"] <= square["s_max_mae"]
    assert scales.loc[2, "stated_possible"]  # 63.5 for the triangle row fits
