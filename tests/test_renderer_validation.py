"""The default renderer at every view: the validation's statistics, the arc curves' smoothness check, and the
renderer on hard surfaces (thin facets, steep facets, grazing light and views)."""
from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from roughlight import renderer_validation as rv
from roughlight import sweeps
from roughlight.shading import Lighting, phase_angle
from roughlight.surface import Surface

#: The default renderer's worst view on the hard surfaces below, as measured on 2026-11-23: 9.30 (diffuse, t 1,
#: aspect 1, light at 5 degrees, view e 176, azimuth 120; 4.73 at most elsewhere). Issue 11's goal of 1.0 is not
#: reached (README "Accuracy at every view"); a regression past this bound fails.
HARD_WORST_VIEW = 10.0


def test_view_errors_find_the_worst_view_and_leave_out_views_without_surface():
    elevation = np.array([0.0, 5.0, 45.0, 90.0, 176.0, 180.0])
    azimuth = np.array([0.0, 10.0, 20.0, 30.0, 40.0, 50.0])
    exact = {c: np.full(6, 50.0) for c in ("diffuse", "specular", "total")}
    rendered = {c: v.copy() for c, v in exact.items()}
    rendered["diffuse"][[0, 5]] = 200.0  # e = 0 and 180 show no surface: never counted
    rendered["diffuse"][2] += 3.0
    rendered["diffuse"][4] -= 1.5  # a grazing view (e > 170)
    rows = {r["component"]: r for r in rv.view_errors(rendered, exact, azimuth, elevation)}
    d = rows["diffuse"]
    assert d["n_views"] == 4
    assert d["worst"] == pytest.approx(3.0) and d["worst_elevation"] == 45.0 and d["worst_azimuth"] == 20.0
    assert d["mae"] == pytest.approx(4.5 / 4)
    assert d["grazing_worst"] == pytest.approx(1.5)
    assert rows["specular"]["worst"] == 0.0


def _arc_study(method, truncations=(0.5, 1.0), aspect=1.0, incidence=30.0):
    """A study table's rows on the light's plane (azimuth 0, every degree), measured here."""
    from roughlight.measure import measure_sweep
    from roughlight.sampling import RenderSettings

    lighting = Lighting()
    elevation = np.arange(0.0, 181.0)
    azimuth = np.zeros_like(elevation)
    frames = []
    for t in truncations:
        out = measure_sweep(method, Surface(t, aspect), incidence, azimuth, elevation, lighting, RenderSettings())
        for component in ("diffuse", "specular", "total"):
            frames.append(pd.DataFrame({
                "kind": "pyramids", "truncation": float(t), "aspect": float(aspect), "incidence": incidence,
                "azimuth": azimuth, "elevation": elevation, "phase": phase_angle(incidence, elevation, azimuth),
                "component": component, "rough": np.asarray(out[component], float), "control": 0.0,
                "coverage": np.asarray(out["coverage"], float)}))
    return pd.concat(frames, ignore_index=True)


def test_arc_smoothness_is_zero_on_exact_curves_and_the_largest_deviation_of_rendered_ones():
    exact = rv.arc_smoothness(_arc_study("reference"), aspects=(1.0,))
    assert len(exact) == 4  # two truncations x Figs. 21 and 28
    assert set(exact["figure"]) == {"Fig. 21", "Fig. 28"}
    assert exact["largest_deviation"].max() < 1e-9
    fast_study = _arc_study("fast")
    fast = rv.arc_smoothness(fast_study, aspects=(1.0,))
    assert fast["largest_deviation"].max() > 0.0
    # the deviation is the curve's own largest |rendered - exact| (recomputed here for one curve)
    from roughlight.reference import reference_sweep

    row = fast[(fast["figure"] == "Fig. 28") & (fast["truncation"] == 1.0)].iloc[0]
    curve = fast_study[(fast_study["truncation"] == 1.0) & (fast_study["component"] == "diffuse")]
    curve = curve.sort_values("elevation")
    ref = reference_sweep(Surface(1.0, 1.0), 30.0, curve["azimuth"].to_numpy(), curve["elevation"].to_numpy())
    err = np.abs(curve["rough"].to_numpy() - ref["diffuse"])[1:-1]
    assert row["largest_deviation"] == pytest.approx(err.max())
    assert row["at_elevation"] == curve["elevation"].to_numpy()[1:-1][np.argmax(err)]
    # no table aspect in the study: no curve, not an error
    assert rv.arc_smoothness(fast_study, aspects=(0.5,)).empty


def test_a_low_surface_casts_no_false_shadow_anywhere_in_a_large_framebuffer():
    """(t 0.1, a 0.1) casts no shadow at incidence 30, so shadows on and off must agree on every view. Far out
    in the framebuffer of a whole sweep the receiver plane taken from interpolated coordinates shadowed up to 3
    levels of it (issue 11)."""
    from roughlight.periodic import fast_sweep
    from roughlight.sampling import RenderSettings

    azimuth, elevation = sweeps.view_grid(2.0, 5.0)
    settings = RenderSettings(pixels_per_period=48)
    on = fast_sweep(Surface(0.1, 0.1), 30.0, azimuth, elevation, Lighting(shadows=True), settings)
    off = fast_sweep(Surface(0.1, 0.1), 30.0, azimuth, elevation, Lighting(shadows=False), settings)
    assert np.abs(on["diffuse"] - off["diffuse"]).max() < 0.05


@pytest.mark.parametrize("truncation,aspect,incidence", [(0.1, 1.0, 30.0), (1.0, 1.0, 5.0), (1.0, 1.0, 85.0),
                                                         (0.1, 0.1, 30.0)])
def test_default_renderer_on_hard_surfaces_and_grazing_views(truncation, aspect, incidence):
    from roughlight.periodic import fast_sweep
    from roughlight.reference import reference_sweep

    elevation = np.concatenate([np.arange(1.0, 10.0), np.arange(20.0, 170.0, 15.0), np.arange(171.0, 180.0)])
    azimuth, elevation = (g.ravel() for g in np.meshgrid(np.arange(0.0, 180.0, 15.0), elevation, indexing="ij"))
    surface = Surface(truncation, aspect)
    exact = reference_sweep(surface, incidence, azimuth, elevation)
    rows = rv.view_errors(fast_sweep(surface, incidence, azimuth, elevation), exact, azimuth, elevation)
    for row in rows:
        assert row["worst"] <= HARD_WORST_VIEW, row
        assert row["mae"] <= 0.5, row
