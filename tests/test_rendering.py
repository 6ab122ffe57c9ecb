"""Lighting invariants measured from renders of the fast method (pyrender over OSMesa)."""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from roughlight.render import methods, shading
from roughlight.render import views as sweeps
from roughlight.render.exact import reference
from roughlight.render.fast import periodic
from roughlight.render.fast.settings import FastSettings
from roughlight.render.gl import context as gl
from roughlight.render.gl import osmesa
from roughlight.render.naive import procedure as naive
from roughlight.render.naive.settings import NaiveSettings
from roughlight.surfaces.surface import Surface

AZ, EL = sweeps.view_grid(10, 30)  # coarse orbit: 19 elevations x 6 azimuths
INNER = (EL > 0) & (EL < 180)


def render(t, a, i, lighting=None, az=AZ, el=EL, **kw):
    return periodic.fast_sweep(Surface(t, a), i, az, el, lighting or shading.Lighting(), FastSettings.from_config(kw))


@pytest.mark.parametrize("incidence", [10, 30, 45, 60, 90])
def test_control_diffuse_is_lambert(incidence):
    out = render(0.0, 0.0, incidence)
    expected = 127 * np.sin(np.radians(incidence))
    assert np.all(np.abs(out["diffuse"][INNER] - expected) <= 0.5 + 1e-9)
    assert np.all(out["coverage"][INNER] == 1.0)
    assert np.all(out["coverage"][~INNER] == 0.0) and np.all(out["total"][~INNER] == 0.0)


@pytest.mark.parametrize("incidence", [20, 30, 60])
def test_control_specular_peaks_in_the_mirror_direction(incidence):
    az, el = sweeps.view_grid(1, 5)
    for m_s in (1.0, 0.5):
        out = render(0.0, 0.0, incidence, shading.Lighting(specular_reflectance=m_s), az=az, el=el)
        peak = np.argmax(out["specular"])
        assert az[peak] == 0 and el[peak] == 180 - incidence
        assert abs(out["specular"][peak] - 127 * m_s) <= 0.5 + 1e-9


def test_zero_truncation_rough_equals_control():
    control = render(0.0, 0.0, 30)
    for t, a in [(0.0, 1.0), (0.6, 0.0)]:
        rough = render(t, a, 30)
        for c in ("diffuse", "specular", "total", "coverage"):
            np.testing.assert_array_equal(rough[c], control[c])


@pytest.mark.parametrize("t,a,i", [(0.5, 1.0, 30), (1.0, 0.7, 20), (0.3, 0.4, 60)])
def test_mirror_symmetry_about_the_lights_plane(t, a, i):
    # the mirror of view (e, phi) in the plane y = 0 is (180 - e, 180 - phi) on this orbit
    az, el = sweeps.view_grid(10, 15)
    # the square pixel grid is itself symmetric about y = 0: mirror views sample mirror points
    out = render(t, a, i, az=az, el=el, sampling="grid", pixels_per_period=24)
    lattice = render(t, a, i, az=az, el=el)
    index = {(round(x), round(y)): k for k, (x, y) in enumerate(zip(az, el))}
    pairs = [(k, index[(180 - round(x), 180 - round(y))]) for k, (x, y) in enumerate(zip(az, el))
             if 0 < x < 180 and (180 - round(x), 180 - round(y)) in index]
    assert len(pairs) > 50
    first, second = np.array(pairs).T
    for c in ("diffuse", "specular", "total"):
        diff = np.abs(out[c][first] - out[c][second])
        # equal up to pixel sampling (a facet edge through a pixel centre goes to one side)
        assert diff.max() <= 1.0 and diff.mean() <= 0.1, (c, diff.max(), diff.mean())
        # the rotated lattice is not: there the symmetry holds to its sampling error
        diff = np.abs(lattice[c][first] - lattice[c][second])
        assert diff.max() <= 3.0 and diff.mean() <= 0.5, (c, diff.max(), diff.mean())
    # and the test can fail: phi -> 180 - phi alone is not a symmetry
    naive = [(k, index[(180 - round(x), round(y))]) for k, (x, y) in enumerate(zip(az, el))
             if 0 < x < 180 and (180 - round(x), round(y)) in index]
    f2, s2 = np.array(naive).T
    assert np.max(np.abs(out["total"][f2] - out["total"][s2])) > 5


def test_shadows_darken_at_low_incidence():
    lit = shading.Lighting(shadows=False)
    shadowed = shading.Lighting(shadows=True)
    low_on, low_off = render(1.0, 1.0, 10, shadowed), render(1.0, 1.0, 10, lit)
    # shadows only ever darken, and at 10 deg they darken the diffuse component a lot
    assert np.all(low_on["total"] <= low_off["total"] + 0.5)
    assert np.mean(low_off["diffuse"][INNER] - low_on["diffuse"][INNER]) > 5
    # with the light overhead nothing is shadowed
    high_on, high_off = render(1.0, 1.0, 90, shadowed), render(1.0, 1.0, 90, lit)
    np.testing.assert_allclose(high_on["total"], high_off["total"], atol=0.5)
    # the shadowed amount is right: the east facets, facing the light, are partly
    # shadowed by the next pyramid; at e = 90 the exact lit area says how much
    fine = render(1.0, 1.0, 10, shadowed, az=[0.0], el=[90.0], pixels_per_period=128)
    exact = reference.reference_sweep(Surface(1.0, 1.0), 10, [0.0], [90.0], shadowed)
    assert abs(fine["diffuse"][0] - exact["diffuse"][0]) < 0.5


@pytest.mark.parametrize("t,a,i", [(0.5, 1.0, 30), (1.0, 1.0, 30), (0.8, 0.8660254037844386, 30), (0.3, 0.5, 60)])
def test_fast_agrees_with_the_exact_reference(t, a, i):
    lighting = shading.Lighting()
    exact = reference.reference_sweep(Surface(t, a), i, AZ, EL, lighting)
    keep = (EL >= 10) & (EL <= 170)
    errors = {}
    for pixels in (32, 64):
        fast = render(t, a, i, lighting, pixels_per_period=pixels)
        errors[pixels] = {c: np.abs(fast[c] - exact[c])[keep] for c in ("diffuse", "specular", "total")}
    for c, err in errors[32].items():  # measured: mean <= 0.23, worst view <= 2.44 (bounds about twice that)
        assert err.mean() < 0.45 and err.max() < 4.0, (c, err.mean(), err.max())
    # pixel sampling is the only error: it shrinks as the tiles get finer
    for c, err in errors[64].items():
        assert err.mean() < 0.5 and err.max() < 2.5, (c, err.mean(), err.max())
    assert errors[64]["diffuse"].mean() < errors[32]["diffuse"].mean()


def test_blinn_and_phong_differ_and_both_peak_at_the_mirror():
    az, el = sweeps.view_grid(1, 45)
    phong = render(0.0, 0.0, 30, shading.Lighting(specular_model="phong"), az=az, el=el)
    blinn = render(0.0, 0.0, 30, shading.Lighting(specular_model="blinn"), az=az, el=el)
    for out in (phong, blinn):
        top = out["specular"] == out["specular"].max()
        assert out["specular"].max() == 127
        assert set(az[top]) == {0} and np.mean(el[top]) == 150  # centred on the mirror direction
    # Blinn's lobe is wider at the same exponent
    assert np.sum(blinn["specular"] > 10) > np.sum(phong["specular"] > 10)


def test_a_sweep_gives_the_same_numbers_whatever_the_process_drew_before():
    """A sweep draws in a context of its own: after a sweep that needed a larger framebuffer (the whole view grid
    of a neighbouring aspect, as a truncation's job renders its row), three views of t 0.6, a 0.9 that moved by
    0.13 of a level in a reused context come out as in a fresh process, bit for bit."""
    az, el = np.array([5.0, 45.0, 170.0]), np.array([43.0, 34.0, 148.0])
    gl.release_contexts()
    fresh = render(0.6, 0.9, 30, az=az, el=el)
    small = next(iter(gl.CONTEXTS))
    full_az, full_el = sweeps.view_grid(1, 5)
    render(0.6, 0.8660254037844386, 30, az=full_az, el=full_el)
    assert max(size[0] for size in gl.CONTEXTS) > small[0]  # the row's sweep drew in a larger framebuffer
    again = render(0.6, 0.9, 30, az=az, el=el)
    for component in ("diffuse", "specular", "total", "coverage"):
        np.testing.assert_array_equal(again[component], fresh[component])
    assert list(gl.CONTEXTS) == [small]  # one context a sweep, as large as the sweep needs


def test_a_sweeps_passes_share_its_context_and_programs():
    gl.release_contexts()
    render(0.5, 1.0, 30, sampling="lattice")
    (ctx,) = gl.CONTEXTS.values()
    assert len(ctx.programs._programs) == 2  # the shadow map's and the views': compiled once for all the passes


def test_bad_incidence_and_shapes_are_refused():
    with pytest.raises(ValueError, match="incidence"):
        render(0.5, 1.0, 95)
    with pytest.raises(ValueError, match="same shape"):
        periodic.fast_sweep(Surface(0.5, 1.0), 30, [0, 5], [10])


def test_naive_method_measures_the_same_quantity():
    az, el = sweeps.view_grid(40, 60)
    keep = (el >= 10) & (el <= 170)
    plate = methods.sweep("naive", Surface(0.0, 0.0), 30, az, el)
    assert np.all(np.abs(plate["diffuse"][keep] - 127 * 0.5) <= 0.5 + 1e-9)
    assert np.all(plate["coverage"][keep] == 1.0)
    rough = methods.sweep("naive", Surface(0.5, 1.0), 30, az[keep], el[keep])
    exact = reference.reference_sweep(Surface(0.5, 1.0), 30, az[keep], el[keep], shading.Lighting())
    # a finite window of whole pixels: close to the truth, but not as close as the fast method
    assert np.mean(np.abs(rough["total"] - exact["total"])) < 5.0
    assert rough["seconds"] > 0
    # pyrender compiles its programs anew every render; none may pile up (they leaked 2 MB a render)
    for renderer in naive.NAIVE_RENDERERS.values():
        assert len(renderer._renderer._program_cache._program_cache) == 0


def test_reference_is_a_method():
    out = methods.sweep("reference", Surface(0.5, 1.0), 30, AZ, EL)
    assert set(out) >= {"diffuse", "specular", "total", "coverage", "seconds"}
    with pytest.raises(ValueError, match="render.method"):
        methods.sweep("raytrace", Surface(0.5, 1.0), 30, AZ, EL)


def test_each_method_takes_only_its_own_settings_and_they_check_themselves():
    """The registry hands a method its own settings type, refuses another's, and each type refuses a bad knob."""
    for name in methods.NAMES:
        assert type(methods.settings(name)).__name__.endswith("Settings")
    with pytest.raises(TypeError, match="naive.*NaiveSettings.*FastSettings"):
        methods.sweep("naive", Surface(0.5, 1.0), 30, AZ, EL, settings=FastSettings())
    with pytest.raises(ValueError, match="model='correction'"):
        methods.settings("implicit_exact", {"model": "correction"})
    with pytest.raises(TypeError, match="view_periods"):  # a knob of another method: named
        methods.settings("fast", {"view_periods": 10})
    for bad in ({"capture": 500}, {"view_periods": 0}, {"shading_model": "toon"}, {"window": (0, 300)}):
        with pytest.raises(ValueError):
            NaiveSettings(**bad)
    with pytest.raises(ValueError, match="tile_sampling"):
        methods.settings("fast", {"tile_sampling": "random"})
    with pytest.raises(ValueError, match="samples"):
        methods.settings("implicit_correction", {"samples": 1000})
    with pytest.raises(TypeError, match="quantized"):
        methods.settings("reference", {"quantized": "yes"})
    # the config's flat keys and the settings are one value both ways
    knobs = {"pixels_per_period": 20, "tile_sampling": "grid", "tile_grazing_scale": 2.0}
    fast = methods.settings("fast", knobs)
    assert fast.tile.sampling == "grid" and fast.config()["tile_grazing_scale"] == 2.0
    assert FastSettings.from_config(fast.config()) == fast


def test_the_naive_shadow_map_recorded_is_pyrenders():
    from pyrender.constants import SHADOW_TEX_SZ

    from roughlight.render.naive.settings import NAIVE_SHADOW_MAP

    assert NAIVE_SHADOW_MAP == SHADOW_TEX_SZ


def test_missing_osmesa_ends_with_one_clear_message(monkeypatch):
    def broken(self):
        raise ImportError("Unable to load OpenGL library", "libOSMesa.so.8: cannot open shared object file")

    monkeypatch.setattr(gl.OSMesaPlatform, "init_context", broken)
    monkeypatch.setattr(gl, "CONTEXTS", {})
    with pytest.raises(RuntimeError, match="apt-get install libosmesa6"):
        periodic.fast_sweep(Surface(0.5, 1.0), 30, [0.0], [45.0])


def test_missing_or_broken_osmesa_is_named(broken_osmesa):
    with pytest.raises(osmesa.OSMesaUnavailable, match="libOSMesa is missing .*apt-get install libosmesa6"):
        osmesa.check_osmesa(names=("libNoSuchOSMesa.so", "libNoSuchOSMesa.so.8"))
    broken = str(broken_osmesa / "libOSMesa.so")
    with pytest.raises(osmesa.OSMesaUnavailable, match="libOSMesa is broken: .* lacks OSMesaCreateContextAttribs"):
        osmesa.check_osmesa(names=(broken,))
    assert osmesa.check_osmesa().startswith("libOSMesa.so")  # the machine's own is whole


def test_broken_osmesa_on_the_library_path_stops_the_import_with_one_message(broken_osmesa):
    env = {**os.environ, "LD_LIBRARY_PATH": str(broken_osmesa), "PYOPENGL_PLATFORM": "osmesa"}
    proc = subprocess.run([sys.executable, "-c", "import roughlight.render.fast.periodic"], env=env, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode != 0
    last = proc.stderr.strip().splitlines()[-1]
    assert last.startswith("roughlight.render.gl.osmesa.OSMesaUnavailable: libOSMesa is broken")
    assert "apt-get install libosmesa6" in last


def test_jitter_moves_sampled_values_but_not_their_mean():
    az, el = sweeps.view_grid(20, 45)
    keep = (el >= 10) & (el <= 170)
    exact = reference.reference_sweep(Surface(0.5, 1.0), 30, az, el, shading.Lighting())["total"][keep]
    runs = [render(0.5, 1.0, 30, az=az, el=el, jitter=(dx, dy))["total"][keep]
            for dx, dy in [(0, 0), (0.5, 0), (0, 0.5), (0.25, 0.75), (0.8, 0.3)]]
    spread = np.std(runs, axis=0)
    assert spread.max() > 0.05  # the pixels do fall elsewhere
    # and each jittered run is as close to the truth as the unjittered one
    for run in runs:
        assert np.mean(np.abs(run - exact)) < 0.5
    plate = [render(0.0, 0.0, 30, jitter=j)["total"] for j in [(0, 0), (0.37, 0.61)]]
    np.testing.assert_array_equal(plate[0], plate[1])
    shifted = [naive.naive_sweep(Surface(0.5, 1.0), 30, [0.0], [60.0], settings=NaiveSettings(jitter=j))["total"][0]
               for j in [(0, 0), (0.5, 0.5)]]
    assert shifted[0] != shifted[1]


def test_averaged_normals_shading_is_wrong_where_flat_is_right():
    az, el = sweeps.view_grid(20, 45)
    keep = (el >= 10) & (el <= 170)
    az, el = az[keep], el[keep]
    lighting = shading.Lighting()
    # on the plate the averaged normals are the face normal: all three shadings agree
    plate = [naive.naive_sweep(Surface(0.0, 0.0), 30, az, el, lighting, NaiveSettings(shading_model=m))["total"]
             for m in shading.SHADINGS]
    np.testing.assert_allclose(plate[1], plate[0], atol=0.5)
    np.testing.assert_allclose(plate[2], plate[0], atol=0.5)
    exact = reference.reference_sweep(Surface(0.5, 1.0), 30, az, el, lighting)
    rough = {m: naive.naive_sweep(Surface(0.5, 1.0), 30, az, el, lighting, NaiveSettings(shading_model=m))
             for m in shading.SHADINGS}
    errors = {m: np.mean(np.abs(out["total"] - exact["total"])) for m, out in rough.items()}
    assert errors["phong"] > 2 * errors["flat"] and errors["gouraud"] > 2 * errors["flat"]
    with pytest.raises(ValueError, match="shading_model"):
        naive.naive_sweep(Surface(0.5, 1.0), 30, az, el, lighting, NaiveSettings(shading_model="toon"))


def test_each_method_records_how_it_sampled(tmp_path):
    """The study table names the naive method's window and pyrender's shadow map, not the fast defaults."""
    import pyarrow.parquet as pq

    from roughlight.study import tables as study

    sweep = {"elevation_step": 60, "azimuth_step": 90}  # 4 views
    lighting = shading.Lighting().as_dict()
    from roughlight.measurements.brdf_export import measure_table

    # the table model draws from a table of the surface's shares: a small one
    tables = {"implicit_table": {"table": measure_table(Surface(0.5, 1.0), [0, 30, 90], [0, 45], [10, 45, 90], 45)}}
    seen = {}
    for method in methods.NAMES:
        path = tmp_path / f"{method}.parquet"
        study.run_sweep(str(path), Surface(0.5, 1.0), 30.0, sweep, lighting, method, tables.get(method, {}))
        table = pq.read_table(path).to_pandas()
        seen[method] = {c: table[c].astype(object).unique().tolist()
                        for c in ("method", "pixels_per_period", "sampling", "shadow_map_size")}
    assert seen["fast"] == {"method": ["fast"], "pixels_per_period": [28], "sampling": ["adaptive"],
                            "shadow_map_size": [512]}
    # a random tile is drawn, and recorded, with the tile settings (per cell)
    from roughlight.surfaces.roughness import make_surface

    path = tmp_path / "tile.parquet"
    study.run_sweep(str(path), make_surface("random_pyramids", 0.5, 0.5, 1, cells=2), 30.0, sweep, lighting, "fast",
                    {"tile_sampling": "grid", "tile_pixels_per_period": 12})
    table = pq.read_table(path).to_pandas()
    assert table["sampling"].unique().tolist() == ["grid"] and table["pixels_per_period"].unique().tolist() == [12]
    assert seen["naive"] == {"method": ["naive"], "pixels_per_period": [10], "sampling": ["window"],
                             "shadow_map_size": [2048]}
    assert seen["reference"] == {"method": ["reference"], "pixels_per_period": [0], "sampling": ["exact"],
                                 "shadow_map_size": [0]}
    assert seen["implicit_table"] == {"method": ["implicit_table"], "pixels_per_period": [65], "sampling": ["table"],
                                      "shadow_map_size": [0]}
    # the clipped scene: 128-pixel pictures over 8 periods
    assert seen["implicit_clipped"] == {"method": ["implicit_clipped"], "pixels_per_period": [16],
                                        "sampling": ["clipped"], "shadow_map_size": [0]}
    with pytest.raises(ValueError, match="render.method"):
        methods.recorded("raytrace")


def test_a_sweep_job_imports_only_what_it_renders_with():
    """A sweep job is a fresh process: pandas, scipy, trimesh or the whole of pyrender would each cost it
    a large share of its start-up (pandas alone 0.4 s), so the measuring path must not import them."""
    code = ("import sys, roughlight.study.tables, roughlight.render.methods, roughlight.render.fast.periodic, "
            "roughlight.render.views; "
            "print(sorted(m for m in ('pandas', 'scipy', 'trimesh', 'shapely', 'matplotlib') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={**os.environ, "PYOPENGL_PLATFORM": "osmesa"}).stdout
    assert out.strip() == "[]"


def test_the_reference_method_loads_no_opengl():
    """The registry imports a method only when it runs: the exact reference needs no renderer."""
    code = ("import sys; from roughlight.render import methods; from roughlight.surfaces.surface import Surface; "
            "out = methods.sweep('reference', Surface(0.5, 1.0), 30.0, [0.0], [60.0]); "
            "print(sorted({m.split('.')[0] for m in sys.modules} & {'OpenGL', 'pyrender'}), out['diffuse'][0] > 0)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={**os.environ, "PYOPENGL_PLATFORM": "osmesa"}).stdout
    assert out.split() == ["[]", "True"]


def test_fast_renderer_follows_the_specular_shadows_setting():
    from roughlight.render.exact.reference import reference_sweep
    from roughlight.render.fast.periodic import fast_sweep
    from roughlight.render.shading import Lighting
    from roughlight.surfaces.surface import Surface

    surface = Surface(1.0, 1.0)
    azimuth, elevation = sweeps.view_grid(10, 45)
    lighting = Lighting(specular_shadows=False)
    fast = fast_sweep(surface, 30, azimuth, elevation, lighting)
    exact = reference_sweep(surface, 30, azimuth, elevation, lighting)
    shadowed = reference_sweep(surface, 30, azimuth, elevation, Lighting())
    assert np.abs(fast["specular"] - exact["specular"]).mean() < 0.1
    assert np.abs(fast["diffuse"] - exact["diffuse"]).mean() < 0.5
    assert np.abs(exact["specular"] - shadowed["specular"]).max() > 0.5  # the setting matters on these views


def test_naive_method_refuses_unshadowed_specular():
    from roughlight.render.naive.procedure import naive_sweep
    from roughlight.render.shading import Lighting
    from roughlight.surfaces.surface import Surface

    with pytest.raises(ValueError, match="render.specular_shadows"):
        naive_sweep(Surface(1.0, 1.0), 30, [0.0], [60.0], Lighting(specular_shadows=False))


def test_one_lighting_equation_in_glsl():
    """Every program's lighting is lighting.glsl's: each shader that lights a surface includes it, and no other
    shader file computes a specular power."""
    from roughlight.render.gl.context import SHADER_DIR

    shaders = {p.name: p.read_text() for p in Path(SHADER_DIR).iterdir()}
    assert "pow(" in shaders["lighting.glsl"]
    assert [name for name, text in shaders.items() if "pow(" in text] == ["lighting.glsl"]
    for name in ("periodic.frag", "implicit_model.glsl", "naive.vert", "naive.frag"):
        assert '#include "lighting.glsl"' in shaders[name], name
    for name in ("implicit.vert", "implicit.frag"):
        assert '#include "implicit_model.glsl"' in shaders[name], name
