"""Where methods fail: small versions of each measurement, with assertions that can fail."""
import numpy as np
import pandas as pd
import pytest

from roughlight.measurements import stability
from roughlight.report import figures
from roughlight.report import page as report
from roughlight.surfaces.surface import PLATE, Surface

SURFACE = [(Surface(1.0, 1.0), 30.0)]


def _mae(frame, method, x, component="total", setting=None, experiment=None):
    sel = (frame["method"] == method) & (frame["x"] == x) & (frame["component"] == component) & (frame["metric"] == "mae")
    if setting is not None:
        sel &= frame["setting"] == setting
    if experiment is not None:
        sel &= frame["experiment"] == experiment
    values = frame.loc[sel, "value"]
    assert len(values) == 1
    return float(values.iloc[0])


@pytest.fixture(scope="module")
def frames():
    views = (np.array([0.0, 90.0, 0.0, 45.0]), np.array([45.0, 70.0, 120.0, 150.0]))
    pixels = stability.pixel_scan(
        SURFACE, fast_pixels=(2, 8, 32), naive_pixels=(0.25, 10.0), n_jitter=3, naive_jitter_pixels=(10.0,),
        fast_views=views, naive_views=(np.array([0.0]), np.array([60.0])),
    )
    elevation = stability.elevation_scan(SURFACE, elevations=(1.0, 45.0, 90.0), azimuths=(0.0,), methods=("fast",))
    shadows = stability.shadow_scan(SURFACE, incidences=(5.0, 45.0), biases=(0.0, 1e-4), map_sizes=(16, 512),
                                     views=views, naive=False)
    shininess = stability.shininess_scan(SURFACE, shininess=(8.0, 128.0), views=views, methods=("fast",))
    clipping = stability.clipping_scan(((PLATE, 30.0), (Surface(1.0, 1.0), 30.0)), elevation_step=5.0)
    normals = stability.normals_scan([(Surface(0.5, 1.0), 30.0)], views=(np.array([0.0, 0.0, 45.0, 90.0]),
                                                                 np.array([60.0, 150.0, 120.0, 40.0])))
    tiles = stability.tile_pixel_scan(kinds=("random_pyramids",), pixels=(4, 16), views=(30.0, 60.0))
    return pd.concat([pixels, elevation, shadows, shininess, clipping, normals, tiles], ignore_index=True)


def test_long_format(frames):
    assert list(frames.columns) == ["experiment", "method", "variable", "x", "setting", "component", "metric", "value"]
    assert set(frames["experiment"]) == {"pixels", "elevation", "shadow_bias", "shadow_map", "shininess", "clipping",
                                         "normals", "tile_pixels"}


def test_fast_error_and_jitter_fall_with_pixels(frames):
    fast = frames[frames["experiment"] == "pixels"]
    errors = [_mae(fast, "fast", p) for p in (2, 8, 32)]
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] <= stability.TOLERANCE
    sd = fast[(fast["method"] == "fast") & (fast["metric"] == "jitter_sd")].set_index("x")["value"]
    assert sd[2] > sd[32] and sd[2] > 1.0


def test_naive_fails_with_sub_pixel_pyramids(frames):
    pixels = frames[frames["experiment"] == "pixels"]
    assert _mae(pixels, "naive", 0.25) > 3 * _mae(pixels, "naive", 10.0)
    assert _mae(pixels, "naive", 0.25) > 5.0


def test_shadow_bias_zero_gives_acne(frames):
    bias = frames[frames["experiment"] == "shadow_bias"]
    for incidence in (5.0, 45.0):
        zero = _mae(bias, "fast", incidence, "diffuse", "bias=0")
        default = _mae(bias, "fast", incidence, "diffuse", "bias=0.0001")
        assert zero > stability.TOLERANCE and default < stability.TOLERANCE and zero > 3 * default


def test_clipping_only_at_255(frames):
    clipping = frames[(frames["experiment"] == "clipping") & (frames["metric"] == "clipped_fraction")]
    clip = clipping.set_index(["setting", "x"])["value"]
    assert clip[("t0_a0_i30", 127.0)] == 0.0
    assert clip[("t0_a0_i30", 255.0)] > 0.0
    assert clip[("t1_a1_i30", 255.0)] > 0.0
    ratio = frames[(frames["metric"] == "peak_ratio") & (frames["setting"] == "t0_a0_i30 forward")]["value"].iloc[0]
    assert ratio < 0.9  # the plate's mirror peak is flattened by clipping


def test_safe_domain_and_report(frames, tmp_path):
    safe = stability.safe_domain(frames)
    assert list(safe["method"]) == ["naive", "fast", "fast tiles (random pyramids, adaptive)",
                                    "fast tiles (random pyramids, lattice)"]
    fast = safe.set_index("method").loc["fast"]
    for column in ("min_pixels_per_period", "min_elevation", "min_incidence", "max_shininess", "min_shadow_map_size"):
        assert np.isfinite(fast[column]), column
    assert 8 < fast["min_pixels_per_period"] <= 32
    naive = safe.set_index("method").loc["naive"]
    assert np.isfinite(naive["best_mae_pixels"]) and naive["best_mae_pixels"] > 0
    assert naive["shading_ok"] == "flat"  # averaged normals are never within tolerance of true ones
    path = tmp_path / "stability.png"
    pictures = stability.normals_pictures(size=(80, 60), periods=2)
    assert set(pictures) == {"flat", "phong", "gouraud"}
    assert not np.array_equal(pictures["flat"], pictures["gouraud"])  # the normals change the picture
    figures.make("stability", path, frames=frames, pictures=pictures)
    assert path.stat().st_size > 20_000
    html = report.render_section("stability", safe_domain=safe, stability=frames, stability_png=path)
    assert html.startswith('<section id="stability"><h2>Where methods fail</h2>')
    assert "data:image/png;base64," in html and html.endswith("</section>")
    assert html.count('<table class="stability">') == 1 and html.count('<table class="stability-normals">') == 1
    assert html.count("<tr>") == 5 + 4  # safe domain: head + 2 methods + 2 tile samplings; normals: head + 3 models


def test_averaged_normals_change_every_lit_component(frames):
    table = stability.normals_table(frames)
    assert list(table.index) == ["flat", "phong", "gouraud"]
    assert (table.loc["flat", ["mae_vs_flat diffuse", "mae_vs_flat specular", "mae_vs_flat total"]] == 0).all()
    for model in ("phong", "gouraud"):
        assert table.loc[model, "mae_vs_flat diffuse"] > 1.0, model  # levels, not rounding
        assert table.loc[model, "mae_vs_flat total"] > stability.TOLERANCE
        assert table.loc[model, "mae total"] > table.loc["flat", "mae total"]


def test_importing_stability_loads_no_opengl():
    """The workflow reads stability.MEASUREMENTS while it parses: that must not load OpenGL."""
    import subprocess
    import sys

    code = ("import sys, roughlight.measurements.stability; "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('OpenGL', 'pyrender')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
    with pytest.raises(ValueError, match="no stability measurement 'moire'"):
        stability.run_measurement("moire")
    with pytest.raises(ValueError, match="no stability plan 'huge'"):
        stability.run_measurement("pixels", plan="huge")


def test_every_plan_names_every_measurement():
    assert set(stability.PLANS) == {"full", "quick", "smoke"} == set(stability.JOBS)
    for plan in stability.PLANS.values():
        assert set(plan) == set(stability.MEASUREMENTS)


def test_random_tiles_sampling_converges_and_adaptive_beats_lattice(frames):
    """The random tiles' scan (pixels a cell): each sampling's error falls as the pixels grow, the default
    (adaptive, counted on the GL side) is within tolerance at its 16 pixels a cell and below lattice sampling
    there, and the safe domain says from how many pixels each is within tolerance."""
    tiles = frames[(frames["experiment"] == "tile_pixels") & (frames["metric"] == "mae")]
    worst = tiles.groupby(["method", "x"])["value"].max()
    adaptive, lattice = "fast tiles (random pyramids, adaptive)", "fast tiles (random pyramids, lattice)"
    for method in (adaptive, lattice):
        assert worst[(method, 16.0)] < worst[(method, 4.0)]
    assert worst[(adaptive, 16.0)] <= stability.TOLERANCE and worst[(adaptive, 16.0)] < worst[(lattice, 16.0)]
    safe = stability.safe_domain(frames).set_index("method")
    assert safe.loc[adaptive, "min_pixels_per_period"] in (4.0, 16.0)
    assert np.isnan(safe.loc[adaptive, "min_elevation"])  # the tiles are scanned on pixels only
