"""The implicit rough surface: exact form and first-order correction, shader against numpy against the reference."""

import numpy as np
import pytest

from roughlight.measurements import implicit_surface as implicit_bench
from roughlight.render import methods, shading, sweep
from roughlight.render import views as sweeps
from roughlight.render.exact import reference
from roughlight.render.implicit import model as implicit
from roughlight.surfaces.geometry import FACET_NAMES
from roughlight.surfaces.surface import SQRT3_2, Surface

# a coarse sweep: elevations 0..180 by 6, azimuths 0..150 by 30 (grazing views included)
AZIMUTH, ELEVATION = sweeps.view_grid(6.0, 30.0)
SEEN = ~sweeps.is_grazing(ELEVATION)

#: thin facets, steep facets, the thesis's 30-degree facets, and a surface between grid values
SURFACES = [(Surface(1.0, 1.0), 30.0), (Surface(0.1, 1.0), 10.0), (Surface(1.0, SQRT3_2), 30.0),
            (Surface(0.37, 0.63), 47.0)]


def _errors(out, exact):
    return {c: np.abs(np.asarray(out[c]) - exact[c])[SEEN] for c in shading.COMPONENTS}


@pytest.mark.parametrize("surface,incidence", SURFACES)
def test_exact_form_shader_equals_the_reference_on_every_view(surface, incidence):
    exact = reference.reference_sweep(surface, incidence, AZIMUTH, ELEVATION)
    out = methods.sweep("implicit_exact", surface, incidence, AZIMUTH, ELEVATION)
    for component, err in _errors(out, exact).items():
        assert err.mean() <= 0.1, (component, err.mean())
        assert err.max() <= 1.0, (component, err.max())
    assert np.all(out["coverage"][SEEN] == 1.0) and np.all(out["coverage"][~SEEN] == 0.0)


def test_shader_and_numpy_agree_for_both_models():
    surface, incidence = Surface(0.6, 0.8), 30.0
    az, el = AZIMUTH[::3], ELEVATION[::3]
    from roughlight.render.implicit.settings import ImplicitSettings
    from roughlight.render.implicit.shader import implicit_sweep

    samples = 4181
    gl_exact = implicit_sweep(surface, incidence, az, el, settings=ImplicitSettings("exact", samples))
    np_exact = implicit.exact_sweep(surface, incidence, az, el, samples=samples)
    gl_corr = implicit_sweep(surface, incidence, az, el, settings=ImplicitSettings("correction"))
    np_corr = implicit.correction_sweep(surface, incidence, az, el)
    for c in shading.COMPONENTS:
        # the same pixels: only float32 against float64 at facet edges and shadow boundaries differ
        assert np.abs(gl_exact[c] - np_exact[c]).max() < 0.1, c
        # the correction's pixels dither its shares: within 1/M of each facet value's weight
        assert np.abs(gl_corr[c] - np_corr[c]).max() < 0.1, c
    # the shader reads an 8-bit framebuffer: NaN before rounding and without shadows at every measured view; the
    # numpy models weight facet values by shares: both, within half a level of the 8-bit means
    seen = gl_exact["coverage"] > 0
    for key in sweep.EXTRA_KEYS:
        for out in (gl_exact, gl_corr):
            assert np.isnan(out[key][seen]).all() and (out[key][~seen] == 0).all(), key
        for out in (np_exact, np_corr):
            assert np.isfinite(out[key]).all(), key
            c = key.split("_")[0]
            assert np.all(np.abs(out[f"{c}_unrounded"] - out[c])[seen] <= 0.5 + 1e-6), key
            assert np.all(out[f"{c}_unshadowed"] >= out[f"{c}_unrounded"] - 1e-9), key


@pytest.mark.parametrize("elevation, azimuth", [(90.0, 0.0), (60.0, 20.0), (45.0, 135.0)])
def test_the_correction_scene_averages_to_its_facet_sum(elevation, azimuth):
    """A scene drawn with the correction (shares once a vertex, a dither a pixel) has the facet sum as its mean."""
    from roughlight.render.implicit.shader import render_field

    surface = Surface(0.6, 0.8)
    image, _ = render_field("correction", surface, 30.0, elevation, azimuth, 16, 128)
    expected = implicit.correction_sweep(surface, 30.0, [azimuth], [elevation])
    assert (image[..., 3] == 255).all()  # the field fills the picture
    for channel, name in enumerate(("diffuse", "specular", "total")):
        assert abs(image[..., channel].mean() - expected[name][0]) < 0.05, name
    assert len(np.unique(image[..., 2])) > 2  # the pixels dither between facets


@pytest.mark.parametrize("plate", [Surface(0.0, 0.7), Surface(0.8, 0.0)])
@pytest.mark.parametrize("method", ["implicit_correction", "implicit_exact"])
def test_both_models_reduce_to_the_plain_opengl_equation_on_the_plate(plate, method):
    for incidence in (10.0, 50.0):
        out = methods.sweep(method, plate, incidence, AZIMUTH, ELEVATION)
        L = shading.light_direction(incidence)
        V = shading.view_direction(ELEVATION, AZIMUTH)
        plain = shading.facet_components(np.array([0.0, 0.0, 1.0]), L, V, shading.Lighting())
        for c, value in zip(shading.COMPONENTS, plain):
            expected = np.broadcast_to(shading.quantize(value), ELEVATION.shape)[SEEN]
            np.testing.assert_allclose(out[c][SEEN], expected, atol=1e-9, err_msg=c)
    lit, shadow = implicit.correction_shares(plate, 30.0, AZIMUTH, ELEVATION)
    assert np.all(lit[SEEN, 0] == 1.0) and not lit[:, 1:].any() and not shadow.any()


def test_correction_shares_cover_the_image_and_are_exact_in_the_light_plane():
    """Shares are >= 0 and sum to 1; in the light's plane (azimuth 0) the V-groove terms are exact."""
    for surface, incidence in SURFACES:
        lit, shadow = implicit.correction_shares(surface, incidence, AZIMUTH, ELEVATION)
        assert (lit >= -1e-12).all() and (shadow >= -1e-12).all()
        np.testing.assert_allclose((lit + shadow).sum(axis=1)[SEEN], 1.0, atol=1e-12)
        in_plane = SEEN & (AZIMUTH == 0)
        exact = reference.reference_sweep(surface, incidence, AZIMUTH[in_plane], ELEVATION[in_plane])
        model = implicit.correction_sweep(surface, incidence, AZIMUTH[in_plane], ELEVATION[in_plane])
        for c in shading.COMPONENTS:
            np.testing.assert_allclose(model[c], exact[c], atol=1e-6, err_msg=f"{surface} {c}")


def test_exact_form_rays_meet_the_facet_under_them():
    """Straight down, every ray meets the facet whose plan footprint holds its start."""
    surface = Surface(0.5, 1.0)
    points = implicit.fibonacci_lattice(987)
    origins = np.column_stack([points, np.full(len(points), surface.height)])
    hit, tau, facet, _ = implicit.cast_rays(surface, origins, np.tile([0.0, 0.0, -1.0], (len(points), 1)),
                                            np.full(len(points), surface.height + 1e-9))
    assert hit.all()
    x, y = points[:, 0], points[:, 1]
    height = np.minimum(2 * surface.aspect * np.minimum.reduce([x, 1 - x, y, 1 - y]), surface.height)
    np.testing.assert_allclose(surface.height - tau, height, atol=1e-12)
    on_top = (np.abs(x - 0.5) < 0.25 - 1e-9) & (np.abs(y - 0.5) < 0.25 - 1e-9)
    assert (facet[on_top] == 0).all() and (facet[~on_top] != 0).all()


@pytest.mark.parametrize("truncation,aspect,message", [(1.5, 1.0, "truncation must be within"),
                                                        (-0.1, 1.0, "truncation must be within"),
                                                        (0.5, -1.0, "aspect must be"),
                                                        (0.5, float("nan"), "aspect must be")])
def test_bad_uniforms_are_refused_with_a_clear_error(truncation, aspect, message):
    with pytest.raises(ValueError, match=f"implicit shader: {message}"):
        implicit.check_uniforms(truncation, aspect)


def test_unknown_model_and_bad_samples_are_refused():
    with pytest.raises(ValueError, match="implicit model must be one of"):
        implicit.model_samples("smooth")
    with pytest.raises(ValueError, match="Fibonacci"):
        implicit.fibonacci_lattice(1000)
    with pytest.raises(ValueError, match="render.method must be one of"):
        methods.sweep("implicit_smooth", Surface(1.0, 1.0), 30.0, [0.0], [45.0])


def test_benchmark_measures_and_reports(tmp_path, monkeypatch):
    """The validation and frame-time tables on a tiny plan, their chart and the report's section."""
    from roughlight.report import figures
    from roughlight.report import page as report

    tiny = {"grid": ((1.0, 1.0),), "incidences": (30.0,), "random": 1, "steps": (15.0, 60.0), "fields": (4,),
            "frame_views": ((60.0, 20.0),), "repeats": 1, "held_out": {"lights": 1, "views": 6}}
    from roughlight.measurements.brdf_export import measure_table

    monkeypatch.setitem(implicit_bench.PLANS, "tiny", tiny)
    # the table model on the surface a (small) table holds, as rule export's tables reach the validation
    tables = {(1.0, 1.0): measure_table(Surface(1.0, 1.0), [0, 30, 60, 90], [0, 45], [5, 30, 60, 90], 30)}
    table = implicit_bench.validation("tiny", tables=tables)
    assert set(table["method"]) == set(implicit_bench.VALIDATED)
    assert set(table["kind"]) == {"grid", "random", implicit_bench.HELD_OUT}
    # the random surface has no table; the table's surface has one under its held-out light too
    assert set(table.loc[table["method"] == "implicit_table", "kind"]) == {"grid", implicit_bench.HELD_OUT}
    held = table[table["kind"] == implicit_bench.HELD_OUT]
    assert len(held.groupby(["truncation", "aspect"])) == 2 and (held["light_azimuth"] != 0).all()
    assert "v_cavity" not in set(held["method"])  # it lights from azimuth 0 only
    assert (held["n_views"] == 6).all()
    assert (table.loc[table["kind"] != implicit_bench.HELD_OUT, "light_azimuth"] == 0).all()
    bands = implicit_bench.summary(table)
    held_band = bands[bands["band"] == implicit_bench.HELD_OUT_BAND]  # its "surfaces": the lights checked
    assert dict(zip(held_band["method"], held_band["surfaces"])) == {**dict.fromkeys(implicit_bench.SWEPT, 2),
                                                                     "implicit_clipped": 2, "implicit_table": 1}
    assert (table.loc[table["method"] == "implicit_table", "memory_bytes"] == tables[(1.0, 1.0)].nbytes).all()
    exact = table[(table.method == "implicit_exact") & (table.component == "diffuse")]
    fast = table[(table.method == "fast") & (table.component == "diffuse")]
    assert exact["mae"].max() < fast["mae"].max()
    pictures = {}
    frames = implicit_bench.frame_times("tiny", size=64, pictures=pictures, tables=tables)
    once = implicit_bench.EXACT_ONCE_A_FRAME  # the exact form's shares once a frame: timed, its picture not kept
    assert set(pictures) == set(frames["method"]) - {once} and all(p.shape == (64, 64) for p in pictures.values())
    assert set(frames["method"]) == {"explicit", "implicit_exact", "implicit_correction", "implicit_clipped",
                                     "implicit_table", once}
    goal = {g["method"]: g for g in implicit_bench.goal(table, frames)}
    assert set(goal) == set(implicit_bench.MODEL_METHODS) | {once} and goal["implicit_table"]["memory_bytes"] > 0
    # the clipped scene: the exact reference's shares, drawn within a level; it holds its facets and the light
    clipped = goal["implicit_clipped"]
    assert clipped["worst"] < 1.0 and clipped["accurate"] and 0 < clipped["memory_bytes"] < 1000
    assert frames.loc[frames.method == "implicit_clipped", "error"].max() < 0.5
    # drawn once a frame at the sweep's samples, the exact form keeps its validation; its frame time is its own
    assert goal[once]["worst"] == goal["implicit_exact"]["worst"] and goal[once]["surfaces"] >= 1
    assert goal[once]["frame_ms"] != goal["implicit_exact"]["frame_ms"]
    assert frames.loc[frames.method == once, "error"].max() < 1.0
    # each frame's drawing alone and its read-back, within its time (the explicit field's read-back timed again)
    quads = frames[frames.method != "explicit"]
    assert ((quads["draw_ms"] > 0) & (quads["read_ms"] > 0)).all()
    assert (quads["draw_ms"] + quads["read_ms"] <= quads["frame_ms"] + 1e-9).all()
    assert ((frames["draw_ms"] > 0) & (frames["read_ms"] > 0)).all()
    assert all(g["draw_speedup"] > 0 for g in goal.values())
    assert all(g["meets"] == (g["accurate"] and g["fast"]) for g in goal.values())
    assert (frames.loc[frames.method != "explicit", "triangles"] == 2).all()
    assert frames.loc[frames.method == "implicit_exact", "error"].max() < 1.0
    figures.make("implicit", tmp_path / "implicit.png", validation=table, frames=frames, pictures=pictures)
    monkeypatch.setattr(implicit_bench, "MAP_SURFACES", implicit_bench.MAP_SURFACES[:1])
    maps = implicit_bench.hemisphere_maps("tiny")
    assert set(maps["method"]) == {"reference", "implicit_exact", "implicit_correction"}
    # the views not rendered (e = 0, 180: coverage 0) are no measurement: NaN, never a value of 0 to draw
    components = list(shading.COMPONENTS)
    grazing = maps["elevation"].isin([0.0, 180.0])
    assert grazing.any() and maps.loc[grazing, components].isna().all().all()
    assert maps.loc[~grazing, components].notna().all().all()
    figures.make("implicit_maps", tmp_path / "maps.png", maps=maps)
    html = report.render_section("implicit", implicit_validation=table, implicit_frames=frames,
                                 implicit_png=str(tmp_path / "implicit.png"), plan="tiny",
                                 implicit_maps_png=str(tmp_path / "maps.png"))
    assert 'id="fig-implicit-maps"' in html and 'id="implicit-validation"' in html
    assert 'id="implicit-frames"' in html and "data:image/png" in html


def test_random_validation_triples_are_seeded_and_off_the_grid():
    first = implicit_bench.validation_surfaces("full")
    assert first == implicit_bench.validation_surfaces("full")
    grid = [s for s in first if s[2] == "grid"]
    random = [s for s in first if s[2] == "random"]
    assert len(grid) == 24 and len(random) == 20
    for surface, incidence, _ in random:
        assert min(abs(surface.truncation * 10 - round(surface.truncation * 10)),
                   abs(surface.aspect * 10 - round(surface.aspect * 10))) >= 0.05
        assert 5 <= incidence <= 85


def test_views_the_reference_refuses_are_left_out_and_counted(monkeypatch):
    """A view whose exact clipping fails its own check is not compared, and the table says how many."""
    from roughlight.render.exact import reference as ref_module

    real = ref_module.reference_sweep

    def refusing(surface, incidence, azimuth, elevation, lighting=None, settings=None, light_azimuth=0.0):
        if np.any(np.asarray(elevation) > 170):
            raise RuntimeError("reference clipping failed")
        return real(surface, incidence, azimuth, elevation, lighting, settings, light_azimuth)

    monkeypatch.setattr(ref_module, "reference_sweep", refusing)
    az, el = sweeps.view_grid(30.0, 90.0)
    rows = implicit_bench.validate_surface(Surface(1.0, 1.0), 30.0, "grid", az, el)
    refused = int((el > 170).sum())
    assert refused and all(r["reference_failures"] == refused for r in rows)
    # each view once: the zenith, on both half great circles (azimuths 0 and 90), counts once
    assert all(r["n_views"] == int((~sweeps.is_grazing(el) & (el <= 170)).sum()) - 1 for r in rows)
    assert all(np.isfinite(r["mae"]) for r in rows)


def test_held_out_lights_are_seeded_and_off_every_node():
    """Issue 58: the validation draws its own lights (incidence 5-85, any azimuth) and views, the same each run, on
    every validation surface, none on the study's nodes."""
    first = implicit_bench.held_out_lights("full")
    again = implicit_bench.held_out_lights("full")
    assert [(s, i, p) for s, i, p, *_ in first] == [(s, i, p) for s, i, p, *_ in again]
    assert all(np.array_equal(a[3], b[3]) and np.array_equal(a[4], b[4]) for a, b in zip(first, again))
    surfaces = {s for s, *_ in implicit_bench.validation_surfaces("full")}
    assert {s for s, *_ in first} == surfaces and len(first) == 3 * len(surfaces)
    incidence = np.array([i for _, i, *_ in first])
    light_azimuth = np.array([p for _, _, p, *_ in first])
    assert ((incidence >= 5) & (incidence <= 85)).all() and light_azimuth.max() > 270 and light_azimuth.min() < 90
    views = np.concatenate([np.column_stack(v[3:]) for v in first])
    assert len(views) == 40 * len(first) and ((views[:, 1] > 1) & (views[:, 1] < 179)).all()
    assert not np.isclose(views % 1.0, 0.0).any()  # off the study's whole-degree nodes


def test_a_held_out_light_reaches_the_reference_and_every_model():
    """validate_surface under a light from azimuth 123.4: each row is the method's error against the reference under
    that light (not the light at azimuth 0), and the V-cavity model, which lights from azimuth 0 only, has none."""
    surface, incidence, psi = Surface(1.0, 0.7), 40.0, 123.4
    azimuth, elevation = np.array([10.0, 77.7, 201.3, 300.0]), np.array([25.0, 61.2, 140.5, 88.0])
    rows = implicit_bench.validate_surface(surface, incidence, implicit_bench.HELD_OUT, azimuth, elevation,
                                           light_azimuth=psi)
    assert {r["method"] for r in rows} == set(implicit_bench.SWEPT) | {"implicit_clipped"}
    exact = methods.sweep("reference", surface, incidence, azimuth, elevation, light_azimuth=psi)
    for method in implicit_bench.SWEPT + ("implicit_clipped",):
        out = methods.sweep(method, surface, incidence, azimuth, elevation, light_azimuth=psi)
        row = next(r for r in rows if r["method"] == method and r["component"] == "total")
        assert row["mae"] == pytest.approx(np.abs(out["total"] - exact["total"]).mean(), abs=1e-9)
        assert row["light_azimuth"] == psi
    at_zero = methods.sweep("reference", surface, incidence, azimuth, elevation)
    assert np.abs(at_zero["total"] - exact["total"]).max() > 10  # the light's azimuth changes what is measured


@pytest.mark.parametrize("model", implicit.MODELS + ("clipped",))
def test_the_shader_sources_stand_alone_and_the_api_sets_every_uniform(model):
    """What a graphics programmer takes away: the two sources compile and link with plain PyOpenGL (no
    pyrender, no #include left), and shader_uniforms plus the scene's four name every uniform they use (the clipped
    scene: the correction's uniforms and its frame's shares, ``given_lit`` and ``given_shadow``)."""
    from OpenGL.GL import shaders as gl_shaders

    from roughlight.render.gl.context import context, gl
    from roughlight.render.implicit.shader import shader_sources

    vertex, fragment = shader_sources(model)
    assert not any(line.startswith("#include") for line in (vertex + fragment).splitlines())
    context(16, 16, 1)
    program = gl_shaders.compileProgram(gl_shaders.compileShader(vertex, gl.GL_VERTEX_SHADER),
                                        gl_shaders.compileShader(fragment, gl.GL_FRAGMENT_SHADER),
                                        validate=False)
    try:
        active = set()
        for index in range(gl.glGetProgramiv(program, gl.GL_ACTIVE_UNIFORMS)):
            name = gl.glGetActiveUniform(program, index)[0]
            active.add((name.decode() if isinstance(name, bytes) else name).split("[")[0])
    finally:
        gl.glDeleteProgram(program)
    uniforms = implicit.shader_uniforms("correction" if model == "clipped" else model, Surface(0.7, 0.9), 40.0)
    given = set(uniforms) | {"camera", "field_size", "scene_view", "fb_width"}
    if model == "clipped":  # each frame's shares, clipped on the CPU (render.exact.pyramid)
        given |= {"given_lit", "given_shadow"}
    if model == "table":  # and the table's: its light's nodes, its extent, its node elevations and its samplers
        import numpy as np

        from roughlight.render.implicit.shader import TABLE_UNITS, table_uniforms
        from roughlight.render.implicit.table import CHANNELS, ShareTable

        table = ShareTable(0.7, 0.9, True, [0.0, 90.0], [0.0, 45.0], [10.0, 90.0], 4,
                           np.zeros((2, 2, 2, 4, CHANNELS), np.uint16))
        given |= set(table_uniforms(table, 40.0, 10.0)) | {"table_elevation"} | set(TABLE_UNITS)
    sweep_only = {"views", "n_views", "views_width"}  # the exact form's program also draws sweeps
    assert active - given <= (sweep_only if model == "exact" else set())
    # the table's shares and the clipped scene's are the surface: their shaders read no truncation
    assert {"aspect", "light_dir", "scene_view"} | ({"truncation"} if model in ("exact", "correction") else set()) <= active
    if model == "clipped":
        assert {"given_lit", "given_shadow"} <= active


# ---------------------------------------------------------------------------
# any light: every implicit model called as a user calls it (issue 58)

#: a surface off the study's grid, lights off the lattice's axes and diagonals, and a view grid the same
OFF_GRID = Surface(0.65, 0.8)
LIGHTS = [(40.0, 37.0), (22.0, 200.0)]


@pytest.mark.parametrize("incidence, light_azimuth", LIGHTS)
def test_the_exact_form_lights_from_any_azimuth_within_a_level(incidence, light_azimuth):
    """methods.sweep("implicit_exact", ..., light_azimuth=psi) with no settings: within a level of the exact
    reference under the same light at every view (and its numpy form too); a light turned back to azimuth 0 would
    not be (the test can fail)."""
    exact = reference.reference_sweep(OFF_GRID, incidence, AZIMUTH, ELEVATION, light_azimuth=light_azimuth)
    drawn = methods.sweep("implicit_exact", OFF_GRID, incidence, AZIMUTH, ELEVATION, light_azimuth=light_azimuth)
    numpy_form = implicit.exact_sweep(OFF_GRID, incidence, AZIMUTH, ELEVATION, samples=4181,
                                      light_azimuth=light_azimuth)
    for out, mean in ((drawn, 0.1), (numpy_form, 0.25)):
        for component, err in _errors(out, exact).items():
            assert err.max() <= 1.0 and err.mean() <= mean, (component, err.max(), err.mean())
    at_zero = reference.reference_sweep(OFF_GRID, incidence, AZIMUTH, ELEVATION)
    assert np.abs(at_zero["total"] - exact["total"])[SEEN].max() > 5.0


def test_the_correction_lights_from_any_azimuth_as_its_numpy_form():
    """The correction's shader under a light at azimuth 37 is its numpy form's facet sum under that light."""
    az, el = AZIMUTH[::3], ELEVATION[::3]
    drawn = methods.sweep("implicit_correction", OFF_GRID, 40.0, az, el, light_azimuth=37.0)
    numpy_form = implicit.correction_sweep(OFF_GRID, 40.0, az, el, light_azimuth=37.0)
    at_zero = implicit.correction_sweep(OFF_GRID, 40.0, az, el)
    for c in shading.COMPONENTS:
        assert np.abs(drawn[c] - numpy_form[c]).max() < 0.1, c
    assert np.abs(at_zero["total"] - numpy_form["total"]).max() > 5.0


def test_the_table_model_tabulates_a_surface_the_first_time_and_keeps_it(tmp_path, monkeypatch):
    """methods.sweep("implicit_table", ...) with no table: the surface's table is measured once at the default
    nodes (here made small), kept in the cache under a name of the surface and the nodes, and read from there after;
    its sweep is the sweep with that table given."""
    from roughlight.render.implicit import load_table, tabulate

    monkeypatch.setenv("ROUGHLIGHT_TABLE_CACHE", str(tmp_path))
    monkeypatch.setattr(tabulate, "TABLE", {"incidence": [0.0, 30.0, 60.0, 90.0], "edge_on": False,
                                            "light_azimuth": [0.0, 45.0], "elevation": [10.0, 45.0, 90.0],
                                            "azimuth_step": 45.0})
    az, el = AZIMUTH[::5], ELEVATION[::5]
    first = methods.sweep("implicit_table", OFF_GRID, 35.0, az, el, light_azimuth=100.0)
    kept = sorted(tmp_path.iterdir())
    assert len(kept) == 1 and kept[0].name.startswith("t0.65_a0.8_shadows_") and kept[0].suffix == ".npz"
    given = methods.sweep("implicit_table", OFF_GRID, 35.0, az, el, settings={"table": load_table(kept[0])},
                          light_azimuth=100.0)
    for c in shading.COMPONENTS:
        np.testing.assert_array_equal(first[c], given[c])

    def measured_again(*args, **kwargs):
        raise AssertionError("the kept table was measured again")

    monkeypatch.setattr(tabulate, "tabulate_surface", measured_again)
    again = methods.sweep("implicit_table", OFF_GRID, 35.0, az, el, light_azimuth=100.0)
    np.testing.assert_array_equal(again["total"], first["total"])
    # other nodes, another surface or no shadows: another table
    assert len({tabulate.table_key(OFF_GRID), tabulate.table_key(OFF_GRID, {"azimuth_step": 30.0}),
                tabulate.table_key(Surface(0.65, 0.81)), tabulate.table_key(OFF_GRID, shadows=False)}) == 4


@pytest.mark.parametrize("name", ["implicit_exact", "implicit_correction", "implicit_table"])
def test_what_the_implicit_models_cannot_draw_is_named(name, tmp_path, monkeypatch):
    """A random tile (no two uniforms make it) and a light below the horizon are refused with what to do."""
    from roughlight.surfaces.roughness import make_surface

    monkeypatch.setenv("ROUGHLIGHT_TABLE_CACHE", str(tmp_path))
    tile = make_surface("random_pyramids", 0.5, 0.5, 1, cells=2)
    with pytest.raises(ValueError, match="regular surfaces.*render.method fast"):
        methods.sweep(name, tile, 30.0, [0.0], [30.0], light_azimuth=20.0)
    with pytest.raises(ValueError, match=r"incidence must be within \[0, 90\]"):
        methods.sweep(name, OFF_GRID, -5.0, [0.0], [30.0], light_azimuth=20.0)
    assert not list(tmp_path.iterdir())  # nothing was tabulated


@pytest.mark.parametrize("elevation, azimuth", [(60.0, 20.0), (25.0, 135.0)])
def test_the_exact_form_scene_with_shares_once_a_frame_averages_to_its_sweep(elevation, azimuth):
    """render_field(..., frame_samples=M): the exact form's rays cast once a frame at M points of a period, each
    pixel showing the sample its dither picks: the picture's mean is the exact form's sweep of that view at M
    samples, and within a level of the exact reference."""
    from roughlight.render.implicit.shader import render_field

    surface, samples = Surface(0.6, 0.8), 6765
    phases = {}
    image, seconds = render_field("exact", surface, 30.0, elevation, azimuth, 16, 128, frame_samples=samples,
                                  phases=phases)
    assert set(phases) == {"first_pass", "clear", "draw", "read"}
    assert sum(phases.values()) == pytest.approx(seconds, rel=1e-6)
    swept = methods.sweep("implicit_exact", surface, 30.0, [azimuth], [elevation], settings={"samples": samples})
    exact = reference.reference_sweep(surface, 30.0, [azimuth], [elevation])
    field = image[..., 3] == 255  # the field's pixels (below elevation 30 the picture reaches past the field)
    assert field.mean() > 0.5 and seconds > 0
    for channel, name in enumerate(("diffuse", "specular", "total")):
        assert abs(image[..., channel][field].mean() - swept[name][0]) < 0.15, name
        assert abs(image[..., channel][field].mean() - exact[name][0]) < 1.0, name
    assert len(np.unique(image[..., 2][field])) > 2  # the pixels dither between samples
    with pytest.raises(ValueError, match="exact form's shares once a frame"):
        render_field("correction", surface, 30.0, elevation, azimuth, 16, 128, frame_samples=samples)


def test_the_clipped_scene_draws_the_exact_shares_within_a_level_under_any_light():
    """The clipped scene (render.implicit: each frame's facet shares clipped exactly on the CPU, one quad drawing them
    as the correction draws its own): its shares are the exact reference's, they sum to one, and its pictures'
    means are within a level of the reference on every view of a coarse grid, under a light from azimuth 0 and one
    from anywhere; a frame times its shares, and a grazing view has no image to clip."""
    from roughlight.render.implicit import clipped_shares, clipped_state_bytes, clipped_sweep, render_field

    surface, incidence, psi = Surface(0.65, 0.8), 22.0, 200.0
    scene = reference.lit_scene(surface, incidence, True, psi)
    lit, shadow = clipped_shares(surface, incidence, 12.0, 120.0, True, psi)
    exact_lit, exact_shadow = scene.areas(12.0, 120.0)
    whole = exact_lit.sum() + exact_shadow.sum()
    order = [FACET_NAMES.index(name) for name in scene.surf.names]
    assert lit[order] == pytest.approx(exact_lit / whole) and shadow[order] == pytest.approx(exact_shadow / whole)
    assert lit.sum() + shadow.sum() == pytest.approx(1.0)
    assert 0 < clipped_state_bytes(surface, incidence, True, psi) < 100_000
    azimuth, elevation = sweeps.view_grid(10.0, 45.0)
    seen = ~sweeps.is_grazing(elevation)
    for light_azimuth in (0.0, psi):
        exact = reference.reference_sweep(surface, incidence, azimuth, elevation, light_azimuth=light_azimuth)
        out = clipped_sweep(surface, incidence, azimuth, elevation, light_azimuth=light_azimuth)
        assert (out["coverage"][seen] == 1.0).all()  # the field fills every picture, down to elevation 1
        for name in ("diffuse", "specular", "total"):
            error = np.abs(out[name] - exact[name])[seen]
            assert error.max() < 0.5 and error.mean() < 0.05, (light_azimuth, name)
    phases = {}
    image, seconds = render_field("clipped", surface, incidence, 60.0, 20.0, 16, 128, phases=phases)
    assert set(phases) == {"shares", "clear", "draw", "read"} and sum(phases.values()) == pytest.approx(seconds)
    assert len(np.unique(image[..., 2])) > 2  # the pixels dither between facets
    with pytest.raises(ValueError, match="grazing"):
        clipped_shares(surface, incidence, 0.0, 30.0)
    # a user's call through the registry, as any method's: a regular surface under a light above the horizon
    out = methods.sweep("implicit_clipped", surface, incidence, azimuth[:3], np.array([20.0, 60.0, 100.0]),
                        light_azimuth=psi)
    assert np.isfinite(out["total"]).all() and out["coverage"].min() == 1.0
    from roughlight.surfaces.roughness import make_surface

    with pytest.raises(ValueError, match="regular surfaces"):
        methods.sweep("implicit_clipped", make_surface("random_pyramids", 0.5, 0.5, 1, cells=2), 30.0, azimuth[:1],
                      elevation[:1])
    with pytest.raises(ValueError, match="incidence"):
        methods.sweep("implicit_clipped", surface, -5.0, azimuth[:1], elevation[:1])
