"""Every statistic over a sweep's views counts each view once (roughlight.render.views.distinct_views).

A sweep's half great circles all pass through the zenith (e = 90): one direction, one row per azimuth. An error
there must weigh as much as an error at any one other view, not once per azimuth; the views that were not rendered
(e = 0 and 180, coverage 0) are no views at all. Each test puts the same error once at the zenith (on every azimuth)
and once at one other view, and the statistic must not tell them apart.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from roughlight.render import views as sweeps
from roughlight.render.shading import COMPONENTS
from roughlight.surfaces.surface import Surface

from .test_analysis import make_study

#: A coarse sweep with the zenith on each of its four half great circles: elevation every 15, azimuth every 45.
AZIMUTH, ELEVATION = sweeps.view_grid(15.0, 45.0)
#: The other view the same error is put at.
OTHER = (45.0, 60.0)
#: The error, 8-bit levels.
ERROR = 6.0
#: The coarse sweep's views, each once: those rendered (0 < e < 180), the zenith at azimuth 0 alone.
ONCE = (ELEVATION > 0) & (ELEVATION < 180) & ~((ELEVATION == 90) & (AZIMUTH != 0))


def at(where: str, azimuth=AZIMUTH, elevation=ELEVATION) -> np.ndarray:
    """(n,) bool: the zenith's rows (every azimuth) or the one other view's row."""
    azimuth, elevation = np.asarray(azimuth, float), np.asarray(elevation, float)
    if where == "zenith":
        return elevation == 90.0
    return (azimuth == OTHER[0]) & (elevation == OTHER[1])


def test_distinct_views_keep_each_rendered_view_once():
    azimuth, elevation = sweeps.view_grid()  # the default sweep
    rendered = (elevation > 0) & (elevation < 180)
    zenith = elevation == 90
    kept = sweeps.distinct_views(azimuth, elevation)
    assert kept.sum() == rendered.sum() - (zenith.sum() - 1) and not kept[~rendered].any()
    assert azimuth[kept & zenith].tolist() == [0.0]  # the zenith at the smallest azimuth
    # in any order the same views, the zenith still at azimuth 0
    order = np.random.default_rng(7).permutation(azimuth.size)
    shuffled = sweeps.distinct_views(azimuth[order], elevation[order])
    assert sorted(zip(azimuth[order][shuffled], elevation[order][shuffled])) == sorted(zip(azimuth[kept],
                                                                                           elevation[kept]))
    # coverage 0 is no view (the zenith then kept at the next azimuth); each sweep keeps its own zenith
    coverage = np.where(zenith & (azimuth == 0.0), 0.0, 1.0)
    covered = sweeps.distinct_views(azimuth, elevation, coverage)
    assert covered.sum() == kept.sum() and azimuth[covered & zenith].tolist() == [5.0]
    two = sweeps.distinct_views(np.r_[azimuth, azimuth], np.r_[elevation, elevation], sweep=np.repeat([0, 1], azimuth.size))
    assert two.sum() == 2 * kept.sum()
    # a view given twice in one sweep (the same direction) counts once too
    assert sweeps.distinct_views(np.r_[azimuth, azimuth], np.r_[elevation, elevation]).sum() == kept.sum()


@pytest.fixture(scope="module")
def study():
    """The exact reference's study of one rough surface on the coarse sweep, its control on the same views."""
    return make_study([0.5], [1.0], azimuths=np.unique(AZIMUTH), elevations=np.unique(ELEVATION))


def _with_error(study: pd.DataFrame, where: str, column: str = "rough") -> pd.DataFrame:
    """The study with its ``column`` set to the control's values plus :data:`ERROR` at ``where``, elsewhere equal
    to the control (rendered views only: the grazing ones keep their 0)."""
    out = study.copy()
    rendered = out["coverage"] > 0
    out.loc[rendered, column] = out.loc[rendered, "control"] + ERROR * at(where, out["azimuth"], out["elevation"])[rendered]
    return out


def test_model_scores_weigh_the_zenith_as_one_view(study):
    from roughlight.analysis.surface_models import analytic_model_fits

    zenith = analytic_model_fits(_with_error(study, "zenith")).iloc[0]
    other = analytic_model_fits(_with_error(study, "other")).iloc[0]
    n = ONCE.sum()
    for column in ("rmse_lambert", "rmse_phong_plate"):  # the rough surface is the plate plus the one error
        assert zenith[column] == pytest.approx(other[column], rel=1e-12)
        assert zenith[column] == pytest.approx(ERROR / np.sqrt(n), rel=1e-12)


def test_a_tiles_error_against_the_regular_surface_weighs_the_zenith_as_one_view(study):
    from roughlight.analysis.ensembles import ensemble_model_fits

    regular = study.assign(kind="pyramids", seed=0)
    rmse = {}
    for where in ("zenith", "other"):
        tile = _with_error(study.assign(control=study["rough"]), where).assign(control=study["control"])
        fits = ensemble_model_fits(pd.concat([regular, tile.assign(kind="random_pyramids", seed=1)],
                                             ignore_index=True))
        rmse[where] = fits.set_index("kind").loc["random_pyramids", ["rmse_regular_diffuse", "rmse_regular_specular"]]
    np.testing.assert_allclose(rmse["zenith"].to_numpy(float), rmse["other"].to_numpy(float), rtol=1e-12)
    assert rmse["zenith"].iloc[0] == pytest.approx(ERROR / np.sqrt(ONCE.sum()))


def _sweeps(where: str) -> tuple[dict, dict]:
    """A made-up exact sweep on the coarse views and a rendered one off by :data:`ERROR` at ``where``."""
    exact = {c: np.where(sweeps.is_grazing(ELEVATION), 0.0, 50.0 + ELEVATION / 10.0) for c in COMPONENTS}
    rendered = {c: exact[c] + ERROR * at(where) for c in COMPONENTS}
    return rendered, exact


def test_the_renderers_errors_weigh_the_zenith_as_one_view():
    from roughlight.measurements.renderer_validation import view_errors

    rows = {where: pd.DataFrame(view_errors(*_sweeps(where), AZIMUTH, ELEVATION)) for where in ("zenith", "other")}
    for column in ("mae", "p99", "worst", "n_views"):
        np.testing.assert_array_equal(rows["zenith"][column], rows["other"][column])
    assert (rows["zenith"]["n_views"] == ONCE.sum()).all()


def _rendering(monkeypatch, where: str) -> None:
    """Every method's sweep is :func:`_sweeps`' rendered one (off at ``where``, half the window covered at the
    zenith), the exact reference its exact one."""
    from roughlight.measurements import comparison
    from roughlight.render import methods

    rendered, exact = _sweeps(where)
    monkeypatch.setattr(comparison, "reference", lambda *args, **kwargs: exact)
    monkeypatch.setattr(methods, "sweep", lambda *args, **kwargs: {**rendered, "seconds": 1.0,
                                                                   "coverage": np.where(at("zenith"), 0.5, 1.0)})


def test_pooled_errors_and_the_benchmark_count_each_view_once(monkeypatch):
    from roughlight.measurements import comparison, speed_accuracy

    surfaces = [(Surface(1.0, 1.0), 30.0), (Surface(0.5, 0.5), 30.0)]
    tables = {}
    for where in ("zenith", "other"):
        _rendering(monkeypatch, where)
        tables[where] = speed_accuracy.run_benchmark([speed_accuracy.Config("fast")], surfaces, (AZIMUTH, ELEVATION),
                                                     repeats=1)
    np.testing.assert_array_equal(tables["zenith"]["mae"], tables["other"]["mae"])
    assert (tables["zenith"]["n_views"] == 2 * AZIMUTH.size).all()  # the views rendered: the speed's
    pooled = comparison.pooled_errors([_sweeps("zenith"), _sweeps("other")], ONCE)
    assert all(len(error) == 2 * ONCE.sum() for error in pooled.values())


def test_the_stability_scans_weigh_the_zenith_as_one_view(monkeypatch):
    from roughlight.measurements import stability

    scans = {}
    for where in ("zenith", "other"):
        _rendering(monkeypatch, where)
        scan = stability.pixel_scan([(Surface(1.0, 1.0), 30.0)], fast_pixels=(8,), naive_pixels=(), n_jitter=2,
                                    fast_views=(AZIMUTH, ELEVATION))
        scans[where] = scan.set_index(["component", "metric"])["value"]
    np.testing.assert_array_equal(scans["zenith"], scans["other"])
    assert scans["zenith"][("all", "coverage")] == pytest.approx(1.0 - 0.5 / ONCE.sum())


def test_every_view_summary_and_the_light_transport_gain_weigh_the_zenith_as_one_view():
    from roughlight.measurements.light_transport import interreflection_summary
    from roughlight.measurements.random_tiles import every_view_summary

    tile = {"kind": "random_pyramids", "truncation": 1.0, "aspect": 1.0, "seed": 1}
    summaries, gains = {}, {}
    for where in ("zenith", "other"):
        rendered, exact = _sweeps(where)
        errors = pd.concat([pd.DataFrame({**tile, "azimuth": AZIMUTH, "elevation": ELEVATION, "component": c,
                                          "fast": rendered[c], "exact": exact[c], "reference_seconds": 1.0})
                            for c in COMPONENTS], ignore_index=True)
        errors["error"] = (errors["fast"] - errors["exact"]).abs()
        summaries[where] = every_view_summary(errors).set_index("component")
        frame = pd.DataFrame({"truncation": 1.0, "aspect": 1.0, "incidence": 30.0, "albedo": 1.0,
                              "views": "hemisphere", "bounces": 8, "azimuth": AZIMUTH, "elevation": ELEVATION,
                              "gain": rendered["diffuse"] - exact["diffuse"],
                              "gain_percent": 100.0 * (rendered["diffuse"] - exact["diffuse"]) / 50.0})
        gains[where] = interreflection_summary(frame[~sweeps.is_grazing(ELEVATION)]).iloc[0]
    for column in ("views", "mae", "worst", "views_over_one_level"):
        np.testing.assert_array_equal(summaries["zenith"][column], summaries["other"][column])
    for column in ("n_views", "mean_gain", "mean_percent", "worst_gain"):
        assert gains["zenith"][column] == gains["other"][column]
