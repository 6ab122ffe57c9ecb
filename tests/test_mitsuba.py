"""Mitsuba 3 as a method (render.method mitsuba): the study's scale to the 8-bit level, the exact reference held to
one level by a renderer nobody here wrote, light that bounces, the variant's fallback and the settings' checks.
Small films and few views: a few seconds in all (docs/mitsuba.md has the full-sweep numbers)."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from roughlight.render import methods, shading
from roughlight.render.mitsuba import MitsubaSettings, check_mitsuba, identity, variant_in_use
from roughlight.surfaces.roughness import make_surface
from roughlight.surfaces.surface import PLATE, Surface

from .conftest import REPO

#: The variant the llvm one renders in here: itself after `make setup` (Debian's libllvm19), else scalar_rgb.
LLVM = variant_in_use("llvm_ad_rgb")
#: A small film: 16 pixels a period over two periods, 8 samples a pixel.
SMALL = {"pixels_per_period": 16, "periods": 2, "samples_per_pixel": 8}
#: Views of t 0.5, a 1 under incidence 30 where the default film's diffuse is furthest from the reference over a
#: 5 x 15 degree grid (e 175 and 15 at azimuth 0), and a spread of others: the back lobe, the forward lobe, beyond
#: the zenith, a grazing one, and 0 (grazing, left at zero).
AZ = np.array([0.0, 0.0, 0.0, 0.0, 30.0, 60.0, 90.0, 150.0, 45.0, 0.0])
EL = np.array([175.0, 15.0, 60.0, 150.0, 30.0, 90.0, 45.0, 120.0, 3.0, 0.0])


def closed_form(lighting, incidence, azimuth, elevation):
    """The plate's 8-bit value of each component: one facet, every pixel alike."""
    views = shading.view_direction(elevation, azimuth)
    values = shading.facet_components(np.array([0.0, 0.0, 1.0]), shading.light_direction(incidence), views, lighting)
    return dict(zip(shading.COMPONENTS, (shading.quantize(v) for v in values)))


def test_mitsuba_is_a_method_of_the_registry():
    assert "mitsuba" in methods.NAMES and not methods.method("mitsuba").opengl
    assert isinstance(methods.settings("mitsuba"), MitsubaSettings)
    assert methods.renderer_identity("mitsuba").startswith("mitsuba 3.9.1 (drjit 1.5.0)")
    assert identity(MitsubaSettings()).startswith(f"mitsuba 3.9.1 {LLVM}")
    assert f"renders in {LLVM}" in check_mitsuba()


@pytest.mark.parametrize("incidence", [30.0, 50.0])
def test_the_plate_matches_the_closed_form_exactly(incidence):
    """Incidence 30 is 127 sin 30 = 63.5, a tie Mitsuba computes as 63.4999962, and its mirror view's total
    63.5 + 127: both round up, as the study's framebuffer. With an ambient term too, and light that bounces (a
    plane passes none to itself)."""
    az, el = np.array([0.0, 0.0, 40.0, 90.0]), np.array([60.0, 180.0 - incidence, 100.0, 20.0])
    for lighting, knobs in ((shading.Lighting(), {}), (shading.Lighting(ambient=0.1, shininess=8.0), {"bounces": 3})):
        out = methods.sweep("mitsuba", PLATE, incidence, az, el, lighting,
                            MitsubaSettings(pixels_per_period=4, periods=1, samples_per_pixel=2, **knobs))
        expected = closed_form(lighting, incidence, az, el)
        for component in shading.COMPONENTS:
            np.testing.assert_array_equal(out[component], expected[component], err_msg=component)
        np.testing.assert_array_equal(out["coverage"], 1.0)
        assert out["renderer"].startswith(f"mitsuba 3.9.1 {LLVM}")


def test_a_regular_surface_is_within_a_level_of_the_exact_reference():
    surface, lighting = Surface(0.5, 1.0), shading.Lighting()
    out = methods.sweep("mitsuba", surface, 30, AZ, EL, lighting, MitsubaSettings(**SMALL))
    exact = methods.sweep("reference", surface, 30, AZ, EL, lighting)
    for component in shading.COMPONENTS:
        error = np.abs(out[component] - exact[component])
        assert error.max() <= 1.0 and error.mean() < 0.3, (component, error)
        # its film is float: the mean before rounding, within half a level (and its tie slack) of the 8-bit one and
        # within a level of the reference's; none without shadows (its light always casts them)
        unrounded = out[f"{component}_unrounded"]
        assert np.all(np.abs(unrounded - out[component])[:-1] <= 0.5 + 2e-3), component  # its ties: 2e-3
        assert np.abs(unrounded - exact[f"{component}_unrounded"]).max() <= 1.0, component
        assert np.isnan(out[f"{component}_unshadowed"][:-1]).all() and out[f"{component}_unshadowed"][-1] == 0
    assert out["diffuse"][-1] == 0 and out["coverage"][-1] == 0  # grazing: not measured
    np.testing.assert_allclose(out["coverage"][:-1], 1.0, atol=1e-3)
    assert methods.recorded("mitsuba", MitsubaSettings(**SMALL), surface) == {
        "pixels_per_period": 16, "sampling": f"mitsuba {LLVM}, 8 spp, direct light", "shadow_map_size": 0}


def test_a_random_tile_and_blinn_phong_are_within_a_level_of_the_reference():
    tile = make_surface("random_pyramids", 0.5, 1.0, seed=1, cells=2)
    lighting = shading.Lighting(specular_model="blinn", shininess=16.0)
    az, el = AZ[[1, 2, 3, 4, 7]], EL[[1, 2, 3, 4, 7]]
    settings = MitsubaSettings(pixels_per_period=12, periods=1, samples_per_pixel=8)
    out = methods.sweep("mitsuba", tile, 40, az, el, lighting, settings)
    exact = methods.sweep("reference", tile, 40, az, el, lighting)
    for component in shading.COMPONENTS:
        assert np.abs(out[component] - exact[component]).max() <= 1.0, component
    assert settings.resolution(tile) == 24  # a random tile's pixels are per cell


def test_light_that_bounces_adds_to_the_diffuse_of_a_rough_surface():
    """With 4 bounces the pyramids pass light between facets: more diffuse than direct light alone, less with a
    darker albedo; the albedo keeps direct light on the study's scale, and leaves the specular unmeasured."""
    surface, az, el = Surface(0.5, 1.0), AZ[[2, 4, 6]], EL[[2, 4, 6]]

    def diffuse(**knobs):
        return methods.sweep("mitsuba", surface, 30, az, el, None, MitsubaSettings(**SMALL, **knobs))

    direct, white, grey = diffuse(), diffuse(bounces=4), diffuse(bounces=4, albedo=0.5)
    assert np.all(white["diffuse"] > direct["diffuse"] + 5) and np.all(grey["diffuse"] > direct["diffuse"] + 1)
    assert np.all(grey["diffuse"] < white["diffuse"] - 3)
    assert np.all(np.isnan(grey["specular"])) and np.all(np.isnan(grey["total"]))
    np.testing.assert_array_equal(diffuse(albedo=0.5)["diffuse"], direct["diffuse"])
    alone = diffuse(specular=False)
    np.testing.assert_array_equal(alone["diffuse"], direct["diffuse"])
    assert np.all(np.isnan(alone["specular"]))


def test_the_variant_falls_back_and_the_kernel_cache_stays_out_of_home(tmp_path):
    """Without a libLLVM the llvm variant renders in scalar_rgb, saying so once in the log, in the renderer and in
    the sampling; Dr.Jit's kernel cache is the project's, never under $HOME."""
    home = tmp_path / "home"
    home.mkdir()
    code = ("import logging, numpy as np; logging.basicConfig(level=logging.WARNING, format='%(message)s'); "
            "from roughlight.render import methods; from roughlight.surfaces.surface import PLATE; "
            "from roughlight.render.mitsuba import MitsubaSettings; "
            "s = MitsubaSettings(pixels_per_period=2, periods=1, samples_per_pixel=1); "
            "out = methods.sweep('mitsuba', PLATE, 30, np.array([0.0]), np.array([60.0]), None, s); "
            "print(out['renderer'], '|', methods.recorded('mitsuba', s)['sampling'], '|', out['diffuse'][0])")
    env = {**os.environ, "HOME": str(home), "DRJIT_LIBLLVM_PATH": str(tmp_path / "libLLVM-19.so")}
    env.pop("DRJIT_CACHE_DIR", None)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    renderer, sampling, value = proc.stdout.strip().splitlines()[-1].split(" | ")
    assert renderer == "mitsuba 3.9.1 scalar_rgb (fallback from llvm_ad_rgb)"
    assert sampling == "mitsuba scalar_rgb, 1 spp, direct light" and float(value) == 64.0
    said = [line for line in proc.stderr.splitlines() if "cannot render here" in line]
    assert len(said) == 1 and "libllvm19" in said[0] and "scalar_rgb" in said[0]
    assert not (home / ".drjit").exists()


def test_llvm_15_is_never_taken(tmp_path):
    from roughlight.render.mitsuba import runtime

    for name in ("libLLVM-15.so.1", "libLLVM-14.so.1", "libLLVM.so.1"):
        (tmp_path / name).write_bytes(b"")
    assert runtime.find_llvm([tmp_path]) is None
    for name in ("libLLVM-17.so", "libLLVM.so.19.1", "libLLVM-20.so.1"):
        (tmp_path / name).write_bytes(b"")
    assert runtime.find_llvm([tmp_path]) == (19, str(tmp_path / "libLLVM.so.19.1"))
    (tmp_path / "libLLVM.so.19.1").unlink()
    assert runtime.find_llvm([tmp_path]) == (20, str(tmp_path / "libLLVM-20.so.1"))
    # no CUDA driver here: cuda_ad_rgb falls to the next variant
    assert variant_in_use("cuda_ad_rgb") == LLVM


@pytest.mark.parametrize("knobs,error,match", [
    ({"bounces": 0}, ValueError, "bounces must be within"),
    ({"samples_per_pixel": 2.5}, ValueError, "samples_per_pixel must be an integer"),
    ({"variant": "llvm_ad_mono"}, ValueError, "variant must be one of"),
    ({"albedo": 1.5}, ValueError, "albedo must be a number in"),
    ({"specular": "yes"}, TypeError, "specular must be true or false"),
    ({"pixels_per_period": 512, "periods": 16}, ValueError, "more than 4096"),
    ({"window": (400, 300)}, TypeError, "window"),
])
def test_bad_settings_are_named(knobs, error, match):
    with pytest.raises(error, match=match):
        methods.settings("mitsuba", knobs)


def test_what_mitsuba_cannot_measure_is_refused_before_rendering():
    az, el = np.array([0.0]), np.array([60.0])
    with pytest.raises(ValueError, match="render.shadows: false"):
        methods.sweep("mitsuba", Surface(0.5, 1.0), 30, az, el, shading.Lighting(shadows=False))
    with pytest.raises(ValueError, match="render.specular_shadows: false"):
        methods.sweep("mitsuba", Surface(0.5, 1.0), 30, az, el, shading.Lighting(specular_shadows=False))
    with pytest.raises(TypeError, match="'mitsuba' takes MitsubaSettings"):
        methods.sweep("mitsuba", Surface(0.5, 1.0), 30, az, el, settings=methods.settings("reference"))
    # the plate casts no shadow: the control's lighting (shadows off) is measured
    out = methods.sweep("mitsuba", PLATE, 30, az, el, shading.Lighting(shadows=False),
                        MitsubaSettings(pixels_per_period=2, periods=1, samples_per_pixel=1))
    assert out["diffuse"][0] == 64.0


def test_the_config_reaches_the_method():
    import yaml

    from roughlight.study import config as rl_config
    from roughlight.study import plan

    cfg = rl_config.validate_config(yaml.safe_load((REPO / "config" / "config.yaml").read_text()))
    cfg["render"]["method"] = "mitsuba"
    cfg["render"]["mitsuba"].update(bounces=8, albedo=0.5)
    for group in plan.GROUPS:
        assert methods.settings("mitsuba", plan.render_settings(cfg, group)) == MitsubaSettings(bounces=8, albedo=0.5)
    assert MitsubaSettings.from_config(MitsubaSettings().config()) == MitsubaSettings()
    defaults = rl_config.validate_config({})
    assert MitsubaSettings.from_config(rl_config.mitsuba_settings_from_config(defaults)) == MitsubaSettings()


def test_a_tall_tiles_sweep_is_split_by_azimuth_into_fields_within_the_budget():
    """A sweep's views reach 1 degree from the horizon: one field for all of them would hold 3 million triangles
    of a tall heightfield tile, so each group of azimuths gets its own strip; every view is in one group, and a
    grazing view of such a tile sees no edge of its field."""
    from roughlight.render import views
    from roughlight.render.mitsuba import field

    tile = make_surface("random_heightfield", 1.0, 1.0, seed=1)
    az, el = views.view_grid(1, 5)
    keep = ~views.is_grazing(el)
    directions = shading.view_direction(el[keep], az[keep])
    per_period = len(field.tile_triangles(tile))
    groups = field.view_groups(per_period, field.surface_height(tile), shading.light_direction(30), directions, 2)
    assert len(groups) > 1 and max(len(cells) for _, cells in groups) * per_period <= field.FIELD_BUDGET
    np.testing.assert_array_equal(np.sort(np.concatenate([rows for rows, _ in groups])), np.arange(keep.sum()))
    regular = field.view_groups(10, 0.5, shading.light_direction(30), directions, 2)
    assert len(regular) == 1  # t 0.5, a 1: one field of 3,174 periods
    out = methods.sweep("mitsuba", tile, 30, np.array([60.0, 60.0]), np.array([2.0, 178.0]), None,
                        MitsubaSettings(pixels_per_period=2, periods=1, samples_per_pixel=2, specular=False))
    np.testing.assert_allclose(out["coverage"], 1.0, atol=1e-3)


def test_one_detector_is_moved_from_view_to_view_and_films_are_the_same():
    """FieldScene builds its sensor once (far enough for its lowest view) and moves it to each view: Dr.Jit keeps
    one kernel instead of compiling one a view, and each film is the bit-for-bit film of a sensor built for that
    view alone."""
    from roughlight.render.mitsuba.field import sensor_matrix, surface_height, tile_triangles, view_groups
    from roughlight.render.mitsuba.scene import FieldScene

    surface, settings = Surface(0.5, 1.0), MitsubaSettings(variant=LLVM, **SMALL)
    views = shading.view_direction(np.array([70.0, 20.0, 45.0]), np.array([0.0, 30.0, 120.0]))
    (rows, cells), = view_groups(len(tile_triangles(surface)), surface_height(surface), shading.light_direction(30.0),
                                 views, settings.periods)
    field = FieldScene(surface, 30.0, cells, shading.Lighting(), settings, lowest=float(views[:, 2].min()))
    films, sensors = [], set()
    for k in rows:
        films.append(field.render(views[k], seed=int(k)))
        sensors.add(id(field.detector))
    assert len(sensors) == 1  # the 20-degree view came second and needed no new far clip
    for k, film in zip(rows, films):
        matrix, far = sensor_matrix(views[k], settings.periods, field.height)
        alone = field.mi.render(field.scene, sensor=field.new_sensor(matrix, far), seed=int(k))
        np.testing.assert_array_equal(film, field.film(alone))
    assert not np.array_equal(films[0], films[1])  # the views differ (the test can fail)
