"""The random-roughness claim's statistics, design and verdict (roughlight.analysis.lobe_shape, .hot_spot,
.claim_readings, .claims): from the views that were measured, each once; the design from geometry, the regular
surface and the pilot seeds only; a family of tests with its error controlled."""

import math

import numpy as np
import pandas as pd
import pytest

from roughlight.analysis import claim_instrument as I
from roughlight.analysis import claim_readings as R
from roughlight.analysis import claims as C
from roughlight.analysis import ensembles as E
from roughlight.analysis import hot_spot as H
from roughlight.analysis import lobe_shape as S
from roughlight.analysis import steps
from roughlight.render import views as sweeps
from roughlight.render.shading import light_direction, view_direction
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
    circle = _shape(S.synthetic_lobe(AZ, EL, centre, (10, 10)))
    ellipse = _shape(S.synthetic_lobe(AZ, EL, centre, (12, 5), rotation=30))
    rectangle = _shape(S.synthetic_lobe(AZ, EL, centre, (12, 6), soft=0.5, rotation=30))
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
        field = _field(S.synthetic_lobe(AZ, EL, centre, (width, width)))
        X, Y, values, directions = S.tangent_patch(field, centre)
        np.testing.assert_array_equal(values, S.field_values(field, directions))
        assert X.shape == values.shape == directions.shape[:2] and not directions.flags.writeable
    assert np.nanmax(values) > 0 and np.isfinite(values).mean() > 0.9


def test_a_lobe_the_horizon_cuts_or_below_the_floor_is_not_measured():
    low = _shape(S.synthetic_lobe(AZ, EL, S.direction(0.0, 8.0), (10, 10)))
    assert not low["measurable"] and "horizon" in low["why"]
    faint = S.lobe_statistics(_field(S.synthetic_lobe(AZ, EL, S.direction(0.0, 60.0), (8, 8), peak=6.0)),
                              S.direction(0.0, 60.0), min_peak=10.0)
    assert not faint["measurable"] and faint["why"].startswith("below the 8-bit floor: peak 6.00 levels, the floor 10")


def _slope(gradient=0.05, level=20.0):
    """A field that rises linearly along x (toward the light's azimuth) at every view: no lobe anywhere."""
    A, El = np.meshgrid(AZ, EL, indexing="ij")
    return level + gradient * np.degrees(view_direction(El, A)[..., 0])


def test_a_lobe_reads_against_its_own_background_and_a_slope_has_none():
    centre = S.direction(0.0, 60.0)
    lobe = S.synthetic_lobe(AZ, EL, centre, (8, 8), peak=5.0)
    on_slope = S.lobe_reading(_field(lobe + _slope()), centre, 25.0)
    alone = S.lobe_reading(_field(lobe), centre, 25.0)
    assert on_slope["measurable"] and alone["measurable"]
    # the cap's mean over 3 deg: a little below the peak; the rim's mean cancels the slope (to its curvature)
    assert alone["contrast"] == pytest.approx(on_slope["contrast"], abs=0.15) and 4.5 < alone["contrast"] < 5.0
    assert on_slope["squareness"] < -0.15 and abs(on_slope["squareness"] - alone["squareness"]) < 0.02
    flat = S.lobe_reading(_field(_slope(0.4)), centre, 25.0)
    assert abs(flat["contrast"]) < 0.15 * abs(flat["peak"] - flat["background"]) and not flat["measurable"]
    assert flat["why"].startswith("no lobe") or flat["why"].startswith("wider than the search disc")
    cut = S.lobe_reading(_field(lobe), S.direction(0.0, 15.0), 25.0)
    assert not cut["measurable"] and np.isnan(cut["contrast"]) and cut["why"].startswith("cut by the horizon")


def _halo(incidence, radius, flat: bool, contrast=0.2, azimuth=AZ):
    """A synthetic shadow-hiding function around the light: 1 at and below it on its azimuth, falling to 1 -
    ``contrast`` above; its half-contrast edge a circle of ``radius`` around the light (``flat`` False) or a
    straight line ``radius`` above it (``flat`` True)."""
    A, El = np.meshgrid(azimuth, EL, indexing="ij")
    V = view_direction(El, A)
    L = light_direction(incidence)
    u1, u2 = S.tangent_basis(L)
    cos_d = V @ L
    x, y = np.degrees((V @ u1) / cos_d), np.degrees((V @ u2) / cos_d)
    reach = np.maximum(x, 0.0) if flat else np.hypot(np.maximum(x, 0.0), y)
    return np.where(cos_d > 0, 1.0 - contrast / (1.0 + np.exp(-(reach - radius) / 1.0)), 1.0 - contrast)


def _grid_field(values, azimuth):
    """A field of (A, E) values on ``azimuth`` x :data:`EL` (the grazing elevations not rendered)."""
    coverage = np.ones((len(azimuth), len(EL)))
    coverage[:, [0, -1]] = 0.0
    return S.measured_field(azimuth, EL, values, coverage)


def test_the_hot_spot_tells_a_round_halo_from_a_flat_one():
    """On views 1 deg apart in azimuth a round halo's edge meets the light's level one width to either side
    (flatness near 0) and a flat one keeps its height (1); on the study's 5 deg the bilinear reading between
    arcs lifts the round one's a little (what rule claim_grid measures on the regular surface)."""
    light, fine = light_direction(40.0), np.arange(0, 180, 1.0)
    for azimuth, round_most in ((fine, 0.1), (AZ, 0.3)):
        diffuse = _grid_field(np.full((len(azimuth), len(EL)), 80.0), azimuth)
        round_, flat = (H.hot_spot_reading(_grid_field(_halo(40.0, 8.0, f, azimuth=azimuth), azimuth), diffuse,
                                           light, 25.0) for f in (False, True))
        for spot in (round_, flat):
            assert spot["measurable"] and spot["width"] == pytest.approx(8.0, abs=0.6)
            assert spot["contrast"] == pytest.approx(0.2, abs=0.05)
            assert spot["contrast_levels"] == pytest.approx(80 * spot["contrast"])
        assert round_["flatness"] < round_most and flat["flatness"] > 0.95
    assert H.shadow_hiding([50.0, 0.0], [100.0, 0.0])[0] == 0.5 and np.isnan(H.shadow_hiding([1.0], [0.0])[0])


def _tile_study():
    """A random tile and the regular surface at one grid point, coarse views, as a study table (with the unrounded
    and unshadowed means)."""
    from roughlight.render.fast.periodic import fast_sweep
    from roughlight.render.shading import Lighting
    from roughlight.study.tables import join_controls, sweep_table

    azimuth, elevation = sweeps.view_grid(2, 10)
    recorded = {"pixels_per_period": 24, "sampling": "adaptive", "shadow_map_size": 512}
    frames = []
    for kind, seed in (("pyramids", 0), ("random_pyramids", 1), ("random_pyramids", 2), ("random_pyramids", 1001),
                       ("random_pyramids", 1002)):
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


def _claim_readings(study):
    """Every surface's claim readings (unrounded, then 8-bit) in fixed discs."""
    out = {}
    for stack in R.seed_stacks(study):
        for reading in R.READINGS:
            out[stack.kind, reading] = R.pooled_readings(stack, R.lobe_centres(stack.key),
                                                         {"back": 30.0, "hot_spot": 20.0}, reading)
    return pd.DataFrame(out).T


def test_a_tile_mirrored_in_the_lights_plane_gives_the_same_statistics(tile_study):
    """Nothing is mirrored or filled in, so a tile and its mirror image give the same numbers: the old analysis
    added a mirror copy of every view near the back lobe, which lands on a measured view with another value."""
    tile = tile_study[(tile_study["kind"] == "random_pyramids") & (tile_study["seed"] == 1)]
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
    # the claim's readings of both lobes, pooled over seeds with their jackknife errors, likewise
    claimed, claimed_mirrored = _claim_readings(tile_study), _claim_readings(_mirrored(tile_study))
    numbers = [c for c in claimed.columns if not c.endswith("_why")]
    assert np.isfinite(claimed.loc[("random_pyramids", "unrounded"), ["hot_spot_contrast", "back_contrast"]]
                       .astype(float)).all()
    pd.testing.assert_frame_equal(claimed[numbers].astype(float), claimed_mirrored[numbers].astype(float),
                                  rtol=1e-6, atol=1e-9)


def test_views_that_were_not_rendered_hold_any_number_without_effect(tile_study):
    grazing = tile_study["coverage"] == 0
    assert set(tile_study.loc[grazing, "elevation"]) == {0.0, 180.0}
    filled = tile_study.copy()
    for column in ("rough", "rough_unrounded", "rough_unshadowed"):
        filled.loc[grazing, column] = 255.0
    pd.testing.assert_series_equal(_values(E.seed_statistics(tile_study)).sort_index(),
                                   _values(E.seed_statistics(filled)).sort_index())
    numbers = lambda f: f[[c for c in f.columns if not c.endswith("_why")]].astype(float)  # noqa: E731
    pd.testing.assert_frame_equal(numbers(_claim_readings(tile_study)), numbers(_claim_readings(filled)))


def test_every_view_below_the_light_on_its_azimuth_hides_every_shadow(tile_study):
    """On a heightfield the shadow-hiding function is 1 at V = L and at every view below the light on its
    azimuth, regular surface and random tile alike: the halo is open below the light."""
    diffuse = tile_study[(tile_study["component"] == "diffuse") & (tile_study["azimuth"] == 0)
                         & (tile_study["elevation"] > 0) & (tile_study["elevation"] <= 30)]
    hiding = H.shadow_hiding(diffuse["rough_unrounded"], diffuse["rough_unshadowed"])
    np.testing.assert_allclose(hiding, 1.0, atol=1e-9)
    above = tile_study[(tile_study["component"] == "diffuse") & (tile_study["azimuth"] == 0)
                       & (tile_study["elevation"] == 50)]
    assert (H.shadow_hiding(above["rough_unrounded"], above["rough_unshadowed"]) < 0.95).all()


def test_the_design_reads_no_tested_seed(tile_study):
    """The lobes, search discs, margins and seed plan come from geometry, the regular surface and the pilots (the
    study's own tiles): the claim's tested tiles may hold any number without moving them; the verdict moves."""
    lighting = {"shininess": 64.0, "specular_model": "phong"}
    claims = {"alpha": 0.05, "max_seeds": 12, "tested": [["random_pyramids", 1.0, 0.5, 2]]}
    steps_ = (10.0, 2.0)
    study = tile_study[tile_study["seed"] < 1000]  # the regular surface and the study's tiles, seeds 1 and 2
    tiles = tile_study[tile_study["seed"] > 1000]  # the claim's tested tiles
    pilots = study[study["kind"].astype(str) != "pyramids"]  # the pilots: the study's tiles here
    tables = steps.claim_tables(study, tiles, None, claims, lighting, steps_, pilots=pilots)
    geometry = tables["random_claim_geometry"]
    assert set(geometry["lobe"]) == {"back", "hot_spot"} and geometry["in_claim"].all()
    np.testing.assert_allclose(geometry["radius"], C.CLEARANCE * geometry["width"])
    scrambled = tiles.copy()
    rng = np.random.default_rng(7)
    for column in ("rough", "rough_unrounded", "rough_unshadowed"):
        scrambled[column] *= rng.uniform(0.5, 1.5, len(scrambled))
    moved = steps.claim_tables(study, scrambled, None, claims, lighting, steps_, pilots=pilots)
    for name in ("random_claim_geometry", "random_claim_margins", "random_claim_design"):
        pd.testing.assert_frame_equal(moved[name], tables[name])
    assert not moved["random_claims"]["mean"].equals(tables["random_claims"]["mean"])
    verdicts = tables["random_claims"]
    assert set(verdicts["reading"]) == set(R.READINGS) and set(verdicts["test"]) == set(C.TESTS)
    assert set(verdicts["seeds"]) == {2} and set(tables["random_claim_design"]["pilot_seeds"]) == {2}
    assert verdicts["level"].iloc[0] == pytest.approx(1 - 0.05 / len(tables["random_claim_design"]))
    # the claim's tiles at its own views read as at every view: the views outside the discs are not read
    views = I.claim_views(geometry, (1.0, 0.5, 30.0), *steps_)
    seen = set(zip(views[0], views[1]))
    inside = tiles[[(a, e) in seen for a, e in zip(tiles["azimuth"], tiles["elevation"])]]
    assert 0 < len(inside) < len(tiles)
    cut = steps.claim_tables(study, inside, None, claims, lighting, steps_, pilots=pilots)
    pd.testing.assert_frame_equal(cut["random_claims"], tables["random_claims"])


def test_registered_pilot_readings_give_the_design_their_tiles_give(tile_study, tmp_path):
    """The pilots' readings written as rule claim_pilots writes them and read back as a registered file
    (claims.registered_pilots) plan the same design, to the bit, as the tiles they came from."""
    from roughlight.atomic import write_frame
    from roughlight.study import pilots as P

    claims = {"alpha": 0.05, "max_seeds": 12, "tested": [["random_pyramids", 1.0, 0.5, 2]]}
    steps_ = (10.0, 2.0)
    study = tile_study[tile_study["seed"] < 1000]
    tiles = tile_study[tile_study["seed"] > 1000]
    geometry = steps.claim_discs(study, {"shininess": 64.0, "specular_model": "phong"})["random_claim_geometry"]
    read = steps.pilot_readings(tiles, geometry, steps_, keys={("random_pyramids", 1.0, 0.5, 30.0): "0123abcd"})
    assert list(read.columns) == P.COLUMNS and set(read["key"]) == {"0123abcd"}
    assert {"back_contrast", "back_contrast_se", "seeds", "hot_spot_flatness"} <= set(read["reading"])
    write_frame(read, tmp_path / "pilots.csv")
    back = P.read_readings(tmp_path / "pilots.csv")
    pd.testing.assert_frame_equal(back, read, check_exact=True)
    design = steps.claim_design(study, geometry, None, claims, steps_, pilots=read)["random_claim_design"]
    again = steps.claim_design(study, geometry, None, claims, steps_, pilots=back)["random_claim_design"]
    pd.testing.assert_frame_equal(again, design, check_exact=True)
    assert design["pilot_mean"].notna().any()


def test_the_claims_own_pilots_plan_it_and_the_studys_tiles_do_not(tile_study):
    """Given the claim's own pilot tiles (rule claim_sweeps' pilots), the design plans from them alone: the study's
    random tiles may hold any number without moving it, and the plan is the pilots' own."""
    claims = {"alpha": 0.05, "max_seeds": 12, "tested": [["random_pyramids", 1.0, 0.5, 2]]}
    steps_ = (10.0, 2.0)
    study = tile_study[tile_study["seed"] < 1000]
    pilots = tile_study[tile_study["seed"] > 1000]
    geometry = steps.claim_discs(study, {"shininess": 64.0, "specular_model": "phong"})["random_claim_geometry"]
    read = steps.pilot_readings(pilots, geometry, steps_)
    design = steps.claim_design(study, geometry, None, claims, steps_, pilots=read)["random_claim_design"]
    scrambled = study.copy()
    random = scrambled["kind"].astype(str) != "pyramids"
    for column in ("rough", "rough_unrounded", "rough_unshadowed"):
        scrambled.loc[random, column] *= np.random.default_rng(3).uniform(0.5, 1.5, int(random.sum()))
    moved = steps.claim_design(scrambled, geometry, None, claims, steps_, pilots=read)["random_claim_design"]
    pd.testing.assert_frame_equal(moved, design)
    own = R.pooled_readings(C.seed_stacks_of(pilots, steps_)[("random_pyramids", 1.0, 0.5, 30.0)],
                            R.lobe_centres((1.0, 0.5, 30.0)), C.discs(geometry, (1.0, 0.5, 30.0)))
    row = design.set_index("test").loc["back_contrast"]
    assert row["pilot_mean"] == pytest.approx(own["back_contrast"]) and row["pilot_seeds"] == own["seeds"]
    study_tiles = steps.claim_design(study, geometry, None, claims, steps_,
                                     pilots=steps.pilot_readings(study[random.to_numpy()], geometry,
                                                                 steps_))["random_claim_design"]
    assert not np.allclose(study_tiles["pilot_mean"].astype(float), design["pilot_mean"].astype(float),
                           equal_nan=True)


def test_a_regular_lobe_near_the_horizon_stays_out_of_the_claim():
    """The back mirror direction lies at elevation 180 - (i + 2 alpha): at aspect 1 under a light at incidence 30
    it is 23 deg up, less than three of its lobe's widths, so the design leaves it out, and says why."""
    assert 180 - (30 + 2 * math.degrees(math.atan(2.0))) == pytest.approx(23.13, abs=0.01)
    width = C.lobe_width(64.0)
    assert width == pytest.approx(math.degrees(math.acos(0.5 ** (1 / 64))))
    assert C.CLEARANCE * width > 23.13 - 1 and C.CLEARANCE * width < 60 - 1


def _readings(mean, se, seeds, lobe="back", contrast=5.0, contrast_se=0.5):
    out = {"seeds": seeds, f"{lobe}_contrast": contrast, f"{lobe}_contrast_se": contrast_se, f"{lobe}_why": ""}
    out.update({name: mean for name, spec in C.TESTS.items() if spec["lobe"] == lobe and spec["role"] == "shape"})
    out.update({f"{name}_se": se for name, spec in C.TESTS.items() if spec["lobe"] == lobe and spec["role"] == "shape"})
    return out


def _design_and_margins(margin=0.02, family=2, alpha=0.05, regular=-0.18, contrast_margin=0.1):
    key = {"kind": "random_pyramids", "truncation": 1.0, "aspect": 0.5, "incidence": 30.0}
    rows, design = [], []
    for test in ("back_contrast", "back_squareness"):
        m = contrast_margin if test == "back_contrast" else margin
        reg = 30.0 if test == "back_contrast" else regular
        for reading in R.READINGS:
            rows.append({**key, "test": test, "reading": reading, "regular": reg, "margin": m})
        design.append({**key, "test": test, "lobe": "back", "role": C.TESTS[test]["role"], "family": family,
                       "level": 1 - alpha / family, "margin": m, "regular": reg})
    return pd.DataFrame(design), pd.DataFrame(rows)


def _verdict(readings, **kw):
    design, margins = _design_and_margins(**kw)
    tested = {("random_pyramids", 1.0, 0.5, 30.0, r): readings for r in R.READINGS}
    table = C.claim_table(tested, design, margins)
    return table[table["reading"] == "unrounded"].set_index("test")


def test_the_verdict_decides_lobes_and_shapes_at_the_familys_level():
    found = _verdict(_readings(-0.10, 0.005, 12))
    assert found.loc["back_contrast", "verdict"] == "lobe"
    square = found.loc["back_squareness"]
    assert square["verdict"] == "difference" and not square["agrees"]  # above the regular: against the claim
    assert square["high"] - square["low"] == pytest.approx(2 * 0.005 * C.t_quantile(1 - 0.05 / 2, 12), rel=1e-9)
    same = _verdict(_readings(-0.181, 0.001, 12))
    assert same.loc["back_squareness", "verdict"] == "no difference"
    wide = _verdict(_readings(-0.15, 0.02, 6))
    assert wide.loc["back_squareness", "verdict"] == "undecided"
    assert "would decide it" in wide.loc["back_squareness", "why"] and wide.loc["back_squareness", "seeds_to_decide"] > 6
    faint = _verdict(_readings(-0.10, 0.005, 12, contrast=0.3, contrast_se=0.02), contrast_margin=1.0)
    assert faint.loc["back_contrast", "verdict"] == "no lobe"
    assert faint.loc["back_squareness", "verdict"] == "no lobe" and "found none" in faint.loc["back_squareness", "why"]
    # a contrast whose interval reaches across the margin decides nothing, and no shape is compared
    unsure = _verdict(_readings(-0.10, 0.005, 12, contrast=1.2, contrast_se=0.3), contrast_margin=1.0)
    assert unsure.loc["back_contrast", "verdict"] == "undecided" and unsure.loc["back_contrast", "seeds_to_decide"] > 12
    assert unsure.loc["back_squareness", "verdict"] == "undecided"
    # a wider family widens every interval
    wider = _verdict(_readings(-0.10, 0.005, 12), family=40)
    assert (wider.loc["back_squareness", "high"] - wider.loc["back_squareness", "low"]
            > square["high"] - square["low"])


def test_the_pilot_plans_more_seeds_for_a_wider_spread():
    narrow, _ = C.planned_seeds(-0.10, 0.01, 4, regular=-0.18, margin=0.02, level=0.998, role="shape")
    wide, _ = C.planned_seeds(-0.10, 0.03, 4, regular=-0.18, margin=0.02, level=0.998, role="shape")
    assert 2 <= narrow < wide
    assert C.planned_seeds(-0.10, np.nan, 4, -0.18, 0.02, 0.998, "shape")[0] is None
    none, why = C.planned_seeds(0.05, 0.1, 4, np.nan, 1.0, 0.998, "lobe")
    lobe, why_lobe = C.planned_seeds(3.0, 0.5, 4, np.nan, 1.0, 0.998, "lobe")
    assert why == "no lobe expected from the pilot" and why_lobe == "a lobe expected from the pilot"
    assert 2 <= none and 2 <= lobe


def test_the_rendering_noise_of_a_symmetric_lobe_is_zero_and_its_halves_are_its_own():
    values = S.synthetic_lobe(AZ, EL, S.direction(0.0, 60.0), (10, 6), peak=60.0)
    for side in (1, -1):
        np.testing.assert_allclose(R.mirrored_half(values, side), values, atol=1e-9)
    uneven = values.copy()
    uneven[3:8, 40:60] *= 1.3  # one side of the plane only
    assert not np.allclose(R.mirrored_half(uneven, 1), R.mirrored_half(uneven, -1))


def test_the_reference_views_cover_each_claimed_lobe_and_come_back_as_its_field():
    geometry = pd.DataFrame([{"truncation": 1.0, "aspect": 0.5, "incidence": 30.0, "lobe": "back", "width": 8.4,
                              "radius": 25.2, "in_claim": True},
                             {"truncation": 1.0, "aspect": 0.5, "incidence": 30.0, "lobe": "hot_spot", "width": 5.3,
                              "radius": 15.9, "in_claim": True},
                             {"truncation": 1.0, "aspect": 1.0, "incidence": 30.0, "lobe": "back", "width": 8.4,
                              "radius": 25.2, "in_claim": False}])
    views = I.reference_views(geometry, I.reference_steps(5.0))
    assert sorted(views["step"].unique()) == [1.0, 2.5, 5.0] and set(views["aspect"]) == {0.5}
    coarse = views[views["step"] == 5.0]
    assert len(views[views["step"] == 1.0]) > 2.5 * len(coarse)
    V = view_direction(coarse["elevation"].to_numpy(), coarse["azimuth"].to_numpy())
    back = R.lobe_centres((1.0, 0.5, 30.0))["back"]
    assert np.degrees(np.arccos(np.clip(V @ back, -1, 1))).min() < 1e-4  # the mirror direction itself
    rows = []
    for component in ("diffuse", "specular"):
        rows.append(coarse.assign(method="reference", component=component, rough_unrounded=coarse["elevation"],
                                  rough_unshadowed=2 * coarse["elevation"]))
    stacks = I.reference_stacks(pd.concat(rows))[(1.0, 0.5, 30.0)]["reference", 5.0]
    assert stacks.specular["unrounded"].shape == (1, 36, 181)
    seen = np.isfinite(stacks.specular["unrounded"][0])
    assert seen.sum() == len(coarse) and (stacks.coverage[seen] == 1).all() and (stacks.coverage[~seen] == 0).all()


def test_the_third_round_plans_the_undecided_tests_alone_at_a_family_level_of_their_own():
    """The third round's plan: only the tests round 2 left undecided (in the reading asked for), each planned by the
    design's own rule (``planned_seeds``) at the level 1 - alpha / (their count); a shape test with no spread to
    plan from gets no seeds and says why; its fresh seeds lie between the tested tiles' and the pilots'."""
    from roughlight.analysis.third_round import THIRD_ROUND_BASE, plan, round_seeds

    keys = {"kind": "random_heightfield", "truncation": 0.5, "incidence": 30.0}
    rows = [
        {**keys, "aspect": 0.5, "test": "back_contrast", "reading": "unrounded", "verdict": "undecided",
         "mean": 0.285, "se": 0.159, "seeds": 6, "regular": 25.95, "margin": 1.0},
        {**keys, "aspect": 0.5, "test": "back_squareness", "reading": "unrounded", "verdict": "undecided",
         "mean": -0.13, "se": float("nan"), "seeds": 6, "regular": -0.179, "margin": 0.05},
        {**keys, "aspect": 1.0, "test": "hot_spot_flatness", "reading": "unrounded", "verdict": "undecided",
         "mean": 0.897, "se": 0.025, "seeds": 4, "regular": 0.929, "margin": 0.272},
        {**keys, "aspect": 1.0, "test": "hot_spot_contrast", "reading": "unrounded", "verdict": "lobe",
         "mean": 19.9, "se": 0.5, "seeds": 4, "regular": 15.3, "margin": 1.0},
        {**keys, "aspect": 0.5, "test": "back_contrast", "reading": "8-bit", "verdict": "undecided",
         "mean": 0.285, "se": 0.159, "seeds": 6, "regular": 25.96, "margin": 1.0},
    ]
    planned, level = plan(pd.DataFrame(rows))
    assert level == pytest.approx(1.0 - 0.05 / 3)
    assert list(planned["test"]) == ["back_contrast", "back_squareness", "hot_spot_flatness"]
    for _, row in planned.iterrows():
        role = "lobe" if row["test"].endswith("contrast") else "shape"
        n, why = C.planned_seeds(row["mean"], row["se"], row["seeds"], next(
            r["regular"] for r in rows if r["test"] == row["test"]), next(
            r["margin"] for r in rows if r["test"] == row["test"]), level, role)
        assert row["fresh"] == (n or 0) and row["why"] == why
    assert planned.loc[planned["test"] == "back_contrast", "fresh"].item() > 6
    assert planned.loc[planned["test"] == "back_squareness", "fresh"].item() == 0
    assert "no spread to plan from" in planned.loc[planned["test"] == "back_squareness", "why"].item()
    assert round_seeds(3) == [THIRD_ROUND_BASE + 1, THIRD_ROUND_BASE + 2, THIRD_ROUND_BASE + 3]
    from roughlight.study.config import CLAIM_PILOT_BASE, CLAIM_SEED_BASE

    assert CLAIM_SEED_BASE < THIRD_ROUND_BASE < CLAIM_PILOT_BASE  # fresh seeds between the tested and the pilots'


def _stale_lines(T, claims, registered, measured) -> list[str]:
    """The registered third round's ensembles not taken (``third_round.stale``), a line each as the run's log says
    them: ensemble, then why."""
    return sorted({f"{k[0]} t {k[1]:g}, a {k[2]:g}, incidence {k[3]:g}: {why}" for k, why in T.stale(claims, registered,
                                                                                                     measured)})


def _third_round_case():
    """A second round with a back lobe undecided (and its shape tests waiting on it) beside a hot spot found, and
    a third round's readings of the fresh tiles its plan asks for, whose back lobe lies wholly below the margin."""
    from roughlight.analysis import third_round as T

    ensemble = {"kind": "random_heightfield", "truncation": 0.5, "aspect": 0.5, "incidence": 30.0}
    tests = ["back_contrast", "back_squareness", "hot_spot_contrast"]
    design = pd.DataFrame([{**ensemble, "test": t, "level": 1 - 0.05 / 28} for t in tests])
    regular = {"back_contrast": 25.95, "back_squareness": -0.179, "hot_spot_contrast": 8.7}
    margin = {"back_contrast": 1.0, "back_squareness": 0.05, "hot_spot_contrast": 1.0}
    margins = pd.DataFrame([{**ensemble, "test": t, "reading": r, "regular": regular[t], "margin": margin[t]}
                            for t in tests for r in R.READINGS])
    key = tuple(ensemble.values())

    def pooled(contrast, se, seeds):
        return {"back_contrast": contrast, "back_contrast_se": se, "back_squareness": -0.1,
                "back_squareness_se": float("nan"), "back_why": "", "hot_spot_contrast": 5.0,
                "hot_spot_contrast_se": 0.2, "hot_spot_why": "", "seeds": seeds}

    second = C.claim_table({key + (r,): pooled(0.285, 0.159, 6) for r in R.READINGS}, design, margins)
    measured = {"claim_surface": {"cells": 8}, "sweep": {"elevation_step": 1.0, "azimuth_step": 5.0},
                "lighting": {"light": 127.0}, "method": "fast", "render": {}}
    planned, level = T.plan(second)
    fresh = int(planned["fresh"].max())  # the tiles the plan asks for
    registered = T.register({key + (r,): pooled(0.22, 0.078, fresh) for r in R.READINGS}, planned, level, measured)
    return second, registered, design, margins, measured


def test_a_registered_third_round_decides_only_what_the_second_left_undecided_and_only_where_it_applies(tmp_path):
    """The registered round (read back from its CSV) decides the undecided back lobe (no lobe, wholly below its
    margin at the round's level) and with it the shape test that waited on it, each row saying it is round 3; the
    hot spot the second round found stays its. Registered readings measured with other settings, planned from
    another second round or of other tiles than planned decide nothing, and the run's log says which and why."""
    from roughlight.analysis import third_round as T

    second, registered, design, margins, measured = _third_round_case()
    assert set(second.loc[second["test"] != "hot_spot_contrast", "verdict"]) == {"undecided"}
    path = tmp_path / "third.csv"
    registered.to_csv(path, index=False)
    decided = T.with_third_round(second, T.read_registered(path), design, margins, measured)
    third = decided[decided["round"] == 3]
    assert len(third) == 4 and set(third["test"]) == {"back_contrast", "back_squareness"}
    fresh = int(registered["seeds"].iloc[0])
    assert fresh > 6 and set(third["verdict"]) == {"no lobe"} and (third["seeds"] == fresh).all()
    assert np.allclose(third["level"], 1 - 0.05 / 2)  # the round's family: the 2 tests left undecided
    assert third["why"].str.startswith(f"round 3 ({fresh} fresh seeds at 97.50%)").all()
    kept = decided[decided["round"] == 2]
    assert set(kept["test"]) == {"hot_spot_contrast"} and set(kept["verdict"]) == {"lobe"}
    assert _stale_lines(T, second, registered, measured) == []
    other = {**measured, "lighting": {"light": 255.0}}
    assert (T.with_third_round(second, registered, design, margins, other)["round"] == 2).all()
    assert _stale_lines(T, second, registered, other) == [
        "random_heightfield t 0.5, a 0.5, incidence 30: measured with other settings"]
    moved = second.copy()
    moved.loc[moved["test"] == "back_contrast", "mean"] += 0.01
    assert (T.with_third_round(moved, registered, design, margins, measured)["round"] == 2).all()
    assert _stale_lines(T, moved, registered, measured)[0].endswith("planned from other readings of the earlier rounds")
    assert (T.with_third_round(second, T.read_registered(None), design, margins, measured)["round"] == 2).all()
    fewer = registered.copy()
    fewer.loc[fewer["statistic"] == "seeds", "value"] = fresh - 1  # not the tiles the plan asked for
    assert (T.with_third_round(second, fewer, design, margins, measured)["round"] == 2).all()
    assert _stale_lines(T, second, fewer, measured)[0].endswith("not the tiles its plan asked for")
    (tmp_path / "bad.csv").write_text("a,b\n1,2\n")
    with pytest.raises(ValueError, match="not a registered third round"):
        T.read_registered(tmp_path / "bad.csv")
