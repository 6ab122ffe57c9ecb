"""The random-roughness claim's statistics, design and verdict (roughlight.analysis.lobe_shape, .claims): from the
views that were measured, each once; a family of tests with its error controlled; every seed accounted for."""

import math

import numpy as np
import pandas as pd
import pytest

from roughlight.analysis import claims as C
from roughlight.analysis import ensembles as E
from roughlight.analysis import lobe_shape as S
from roughlight.render import views as sweeps
from roughlight.surfaces.roughness import make_surface

AZ, EL = np.arange(0, 180, 5.0), np.arange(0, 181, 1.0)


def _field(values):
    coverage = np.ones_like(values)
    coverage[:, [0, -1]] = 0.0
    return S.measured_field(AZ, EL, values, coverage)


def _shape(values):
    field = _field(values)
    top = np.where(np.isfinite(field[2][:-1]), field[2][:-1], -1)
    ia, ie = np.unravel_index(np.argmax(top), top.shape)
    return S.lobe_statistics(field, S.direction(AZ[ia], EL[ie]))


def test_lobe_shape_tells_rectangles_from_ellipses():
    centre = S.direction(0.0, 120.0)
    circle = _shape(C.synthetic_lobe(AZ, EL, centre, (10, 10)))
    ellipse = _shape(C.synthetic_lobe(AZ, EL, centre, (12, 5), rotation=30))
    rectangle = _shape(C.synthetic_lobe(AZ, EL, centre, (12, 6), soft=0.5, rotation=30))
    for lobe in (circle, ellipse, rectangle):
        assert lobe["measurable"] and lobe["why"] == ""
    assert circle["ellipse_misfit"] < 0.02 and circle["squareness"] < -0.15
    assert circle["elongation"] == pytest.approx(1.0, abs=0.05) and circle["rectangularity"] == pytest.approx(
        math.pi / 4, abs=0.02)
    assert ellipse["ellipse_misfit"] < 0.03 and ellipse["squareness"] < -0.15 and ellipse["elongation"] > 2
    assert rectangle["rectangle_misfit"] < 0.06 and rectangle["squareness"] > 0.1
    # a circular lobe peaks where a circular lobe should on every arc, both sides of the plane; a tilted rectangle
    # does not
    assert circle["phase_shift"] < 0.1 and circle["arcs"] >= 5
    assert rectangle["phase_shift"] > 2.0


def test_a_tangent_patch_reads_each_field_on_the_same_views_afresh():
    """The patch's geometry is made once for a direction and a field's views (issue 46): every field on those
    views is still read at its own values, as :func:`field_values` reads it at the patch's directions."""
    centre = S.direction(0.0, 120.0)
    for width in (10, 6, 14):  # the second and third reuse the first's geometry
        field = _field(C.synthetic_lobe(AZ, EL, centre, (width, width)))
        X, Y, values, directions = S.tangent_patch(field, centre)
        np.testing.assert_array_equal(values, S.field_values(field, directions))
        assert X.shape == values.shape == directions.shape[:2] and not directions.flags.writeable
    assert np.nanmax(values) > 0 and np.isfinite(values).mean() > 0.9


def test_a_lobe_the_horizon_cuts_or_below_the_floor_is_not_measured():
    low = _shape(C.synthetic_lobe(AZ, EL, S.direction(0.0, 8.0), (10, 10)))
    assert not low["measurable"] and "horizon" in low["why"]
    faint = S.lobe_statistics(_field(C.synthetic_lobe(AZ, EL, S.direction(0.0, 60.0), (8, 8), peak=6.0)),
                              S.direction(0.0, 60.0), min_peak=10.0)
    assert not faint["measurable"] and faint["why"].startswith("below the 8-bit floor: peak 6.00 levels, the floor 10")


def _tile_study():
    """A random tile and the regular surface at one grid point, coarse views, as a study table."""
    from roughlight.render.fast.periodic import fast_sweep
    from roughlight.render.shading import Lighting
    from roughlight.study.tables import join_controls, sweep_table

    azimuth, elevation = sweeps.view_grid(2, 10)
    recorded = {"pixels_per_period": 24, "sampling": "lattice", "shadow_map_size": 512}
    frames = []
    for kind, seed in (("pyramids", 0), ("random_pyramids", 1)):
        surface = make_surface(kind, 1.0, 0.5, seed, cells=2)
        frames.append(sweep_table(fast_sweep(surface, 30, azimuth, elevation), surface, 30, azimuth, elevation,
                                  Lighting(), "fast", recorded).to_pandas())
    plate = make_surface("pyramids", 0.0, 0.0)
    unlit = Lighting(shadows=False)
    control = sweep_table(fast_sweep(plate, 30, azimuth, elevation, unlit), plate, 30, azimuth, elevation, unlit,
                          "fast", recorded).to_pandas()
    return join_controls(pd.concat(frames, ignore_index=True), control)


@pytest.fixture(scope="module")
def tile_study():
    return _tile_study()


def _mirrored(study):
    """The same study with every surface mirrored in the light's plane: the value measured at (phi, e) is the
    mirror surface's at (180 - phi, 180 - e); the azimuth-0 arc is its own mirror."""
    out = study.copy()
    off = out["azimuth"] > 0
    out.loc[off, "azimuth"] = 180.0 - out.loc[off, "azimuth"]
    out.loc[off, "elevation"] = 180.0 - out.loc[off, "elevation"]
    return out


def _values(stats):
    return stats.set_index(["kind", "seed", "statistic"])["value"]


def test_a_tile_mirrored_in_the_lights_plane_gives_the_same_statistics(tile_study):
    """Nothing is mirrored or filled in, so a tile and its mirror image give the same numbers: the old analysis
    added a mirror copy of every view near the back lobe, which lands on a measured view with another value."""
    tile = tile_study[tile_study["kind"] == "random_pyramids"]
    spec = tile[tile["component"] == "specular"].set_index(["azimuth", "elevation"])["rough"]
    # each view's value against its mirror view's (180 - phi, 180 - e): the tile is not mirror-symmetric
    mirror_values = np.array([spec.get((180.0 - a, 180.0 - e), np.nan) if a > 0 else spec[(a, e)]
                              for a, e in spec.index])
    assert np.nanmax(np.abs(mirror_values - spec.to_numpy())) > 1.0
    original = _values(E.seed_statistics(tile_study, min_peak=0.5))
    mirrored = _values(E.seed_statistics(_mirrored(tile_study), min_peak=0.5))
    shape = list(S.SHAPE_STATISTICS)
    assert original.loc[("random_pyramids", 1, shape)].notna().all()
    pd.testing.assert_series_equal(original.sort_index(), mirrored.sort_index(), rtol=1e-6, atol=1e-9)


def test_views_that_were_not_rendered_hold_any_number_without_effect(tile_study):
    grazing = tile_study["coverage"] == 0
    assert set(tile_study.loc[grazing, "elevation"]) == {0.0, 180.0}
    filled = tile_study.copy()
    filled.loc[grazing, "rough"] = 255.0
    pd.testing.assert_series_equal(_values(E.seed_statistics(tile_study)).sort_index(),
                                   _values(E.seed_statistics(filled)).sort_index())


def _stats(rows):
    """A per-seed statistics frame from (kind, seed, statistic, value, note) rows at one grid point."""
    return pd.DataFrame([{"kind": k, "seed": s, "truncation": 1.0, "aspect": 0.5, "incidence": 30.0,
                          "statistic": name, "value": v, "note": note} for k, s, name, v, note in rows])


def _design(stats, margin=0.05, alpha=0.05, configured=None):
    margins = pd.DataFrame([{"statistic": n, "rendering_noise": 0.0, "floor_effect": margin, "margin": margin,
                             "from": "8-bit floor"} for n in C.CLAIMS])
    return C.claim_design(stats, {"alpha": alpha, "max_seeds": 12}, margins, configured or {})


def test_the_verdict_uses_the_tested_seeds_at_the_familys_level_and_accounts_for_every_seed():
    regular = [("pyramids", 0, "back_squareness", -0.18, ""), ("pyramids", 0, "back_phase_shift", 0.3, "")]
    tested = [("random_pyramids", s, "back_squareness", v, "") for s, v in zip(range(1, 7), (0.10, 0.12, 0.11,
                                                                                           0.13, 0.09, 0.10))]
    tested += [("random_pyramids", s, "back_phase_shift", np.nan, "cut by the horizon: ...") for s in (1, 2, 3, 4)]
    tested += [("random_pyramids", s, "back_phase_shift", 1.0, "") for s in (5, 6)]
    pilots = [("random_pyramids", 1001, "back_squareness", 5.0, ""),  # a pilot never enters the verdict
              ("random_pyramids", 1002, "back_squareness", -5.0, "")]
    stats = _stats(regular + tested + pilots)
    design = _design(stats)
    assert design["family"].tolist() == [2, 2] and design["level"].iloc[0] == pytest.approx(1 - 0.05 / 2)
    table = C.claim_table(stats, design).set_index("test")
    square = table.loc["back_squareness"]
    assert square["seeds"] == 6 and square["measurable"] == 6 and square["left_out"] == ""
    assert square["mean"] == pytest.approx(0.10833, abs=1e-4)
    assert square["verdict"] == "difference" and not square["agrees"]  # above the regular value: against the claim
    phase = table.loc["back_phase_shift"]
    assert phase["verdict"] == "not measurable" and phase["measurable"] == 2
    assert phase["left_out"] == "4 cut by the horizon (seeds 1, 2, 3, 4)"
    # a wider family widens every interval
    wide = C.claim_table(stats, _design(stats, alpha=0.0001)).set_index("test").loc["back_squareness"]
    assert wide["high"] - wide["low"] > square["high"] - square["low"]


def test_no_difference_and_undecided_are_told_apart_by_the_margin():
    for values, margin, verdict in (([-0.17, -0.18, -0.19, -0.18, -0.175, -0.185], 0.05, "no difference"),
                                    ([-0.30, -0.05, -0.25, -0.10, -0.2, -0.15], 0.05, "undecided")):
        stats = _stats([("pyramids", 0, "back_squareness", -0.18, "")]
                       + [("random_pyramids", s + 1, "back_squareness", v, "") for s, v in enumerate(values)])
        row = C.claim_table(stats, _design(stats, margin)).set_index("test").loc["back_squareness"]
        assert row["verdict"] == verdict, row["why"]
        if verdict == "undecided":
            assert "would decide it" in row["why"] or "no number of seeds" in row["why"]


def test_the_pilot_plans_more_seeds_for_a_wider_spread():
    narrow, _ = C.planned_seeds([0.0, 0.02, -0.02], regular=-0.18, margin=0.05, level=0.997, max_seeds=1000)
    wide, _ = C.planned_seeds([0.0, 0.08, -0.08], regular=-0.18, margin=0.05, level=0.997, max_seeds=1000)
    assert 2 <= narrow < wide
    assert C.planned_seeds([0.1], -0.18, 0.05, 0.997)[0] is None  # one measurable pilot seed: no spread
    assert C.planned_seeds([0.1, 0.2], np.nan, 0.05, 0.997)[1] == "the regular lobe is not measurable"


def test_the_rendering_noise_of_a_symmetric_lobe_is_zero_and_its_halves_are_its_own():
    values = C.synthetic_lobe(AZ, EL, S.direction(0.0, 60.0), (10, 6), peak=60.0)
    coverage = np.ones_like(values)
    coverage[:, [0, -1]] = 0
    for side in (1, -1):
        np.testing.assert_allclose(C.mirrored_half(values, side), values, atol=1e-9)
    noise = C.rendering_noise({(1.0, 0.5, 30.0): (AZ, EL, values, coverage, S.direction(0.0, 60.0))}, 10.0)
    assert noise["back_squareness_noise"].iloc[0] == pytest.approx(0.0, abs=1e-9)
    uneven = values.copy()
    uneven[3:8, 40:60] *= 1.3  # one side of the plane only
    assert not np.allclose(C.mirrored_half(uneven, 1), C.mirrored_half(uneven, -1))


def test_rounding_to_8_bits_moves_a_faint_lobe_more_than_a_bright_one():
    floor = C.floor_effect([4.0, 32.0], 60.0, AZ[::2], EL)
    faint, bright = floor.iloc[0], floor.iloc[1]
    assert faint["back_squareness"] > bright["back_squareness"] > 0
