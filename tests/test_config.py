import copy

import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from roughlight.study import config as rl_config

from .conftest import REPO

SCHEMA = REPO / "workflow" / "schemas" / "config.schema.yaml"


def default_config():
    with open(REPO / "config" / "config.yaml") as fh:
        return yaml.safe_load(fh)


def test_default_config_is_valid_and_documented():
    cfg = rl_config.validate_config(default_config(), SCHEMA)
    assert cfg["sweep"] == {"elevation_step": 1, "azimuth_step": 5}
    readme = (REPO / "config" / "README.md").read_text()
    schema = rl_config.load_schema(SCHEMA)
    for section, body in schema["properties"].items():
        for key in body["properties"]:
            assert f"`{section}.{key}`" in readme, f"config/README.md does not document {section}.{key}"


def test_defaults_fill_an_empty_config():
    cfg = rl_config.validate_config({}, SCHEMA)
    assert cfg["grid"]["incidence"] == [30]
    assert cfg["render"]["method"] == "fast"
    assert cfg["light"]["intensity"] == 127


BAD = [
    (("grid", "truncation"), [0.0, 1.5], "grid.truncation[1]", "<= 1"),
    (("grid", "truncation"), [-0.1], "grid.truncation[0]", ">= 0"),
    (("grid", "aspect"), [-1], "grid.aspect[0]", ">= 0"),
    (("grid", "incidence"), [95], "grid.incidence[0]", "<= 90"),
    (("grid", "incidence"), [-5], "grid.incidence[0]", ">= 0"),
    (("grid", "incidence"), [], "grid.incidence", "at least one"),
    (("sweep", "elevation_step"), 0, "sweep.elevation_step", "> 0"),
    (("sweep", "azimuth_step"), -5, "sweep.azimuth_step", "> 0"),
    (("material", "specular_model"), "cook", "material.specular_model", "phong, blinn"),
    (("render", "method"), "raytrace", "render.method", "fast, naive, reference"),
    (("grid", "truncation"), ["abc"], "grid.truncation[0]", "type number"),
    (("sweep", "elevation_step"), "1", "sweep.elevation_step", "type number"),
    (("render", "shadows"), "yes", "render.shadows", "type boolean"),
    (("render", "pixels_per_period"), 2.5, "render.pixels_per_period", "type integer"),
    (("light", "intensity"), 300, "light.intensity", "<= 255"),
    (("grid", "truncation"), [0.1, 0.1], "grid.truncation", "same value twice"),
]


@pytest.mark.parametrize("path,value,key,allowed", BAD)
def test_bad_values_name_the_key_and_what_is_allowed(path, value, key, allowed):
    cfg = default_config()
    cfg[path[0]][path[1]] = value
    with pytest.raises(rl_config.ConfigError) as info:
        rl_config.validate_config(cfg, SCHEMA)
    message = str(info.value)
    assert key in message
    assert allowed in message


def test_unknown_keys_are_refused():
    cfg = default_config()
    cfg["render"]["methd"] = "fast"
    with pytest.raises(rl_config.ConfigError, match="methd"):
        rl_config.validate_config(cfg, SCHEMA)


def test_every_problem_is_listed_at_once():
    cfg = default_config()
    cfg["grid"]["truncation"] = [2]
    cfg["sweep"]["azimuth_step"] = 0
    with pytest.raises(rl_config.ConfigError) as info:
        rl_config.validate_config(cfg, SCHEMA)
    assert "grid.truncation[0]" in str(info.value) and "sweep.azimuth_step" in str(info.value)


def test_labels_are_exact_and_distinct():
    assert rl_config.label(0.1) == "0.1"
    assert rl_config.label(1.0) == "1"
    assert rl_config.label(30) == "30"
    assert rl_config.label(0.8660254037844386) == "0.8660254037844386"
    assert float(rl_config.label(0.30000000000000004)) == 0.30000000000000004


numbers = st.floats(-1e3, 1e3, allow_nan=False)


@settings(max_examples=80, deadline=None)
@given(st.lists(numbers, min_size=1, max_size=4), st.lists(numbers, min_size=1, max_size=4),
       st.lists(numbers, min_size=1, max_size=3), numbers, numbers)
def test_validation_accepts_exactly_the_valid_grids(truncation, aspect, incidence, el_step, az_step):
    cfg = {
        "grid": {"truncation": truncation, "aspect": aspect, "incidence": incidence},
        "sweep": {"elevation_step": el_step, "azimuth_step": az_step},
    }
    valid = (
        all(0 <= t <= 1 for t in truncation)
        and all(0 <= a <= 10 for a in aspect)
        and all(0 <= i <= 90 for i in incidence)
        and 0 < el_step <= 180
        and 0 < az_step <= 180
        and all(len({rl_config.label(v) for v in vals}) == len(vals) for vals in (truncation, aspect, incidence))
    )
    if valid:
        rl_config.validate_config(copy.deepcopy(cfg), SCHEMA)
    else:
        with pytest.raises(rl_config.ConfigError):
            rl_config.validate_config(copy.deepcopy(cfg), SCHEMA)


# ---------------------------------------------------------------------------
# the defaults are written in three places: the schema, the code's types, the shipped config


def _leaves(tree: dict, path=()):
    for key, value in tree.items():
        if isinstance(value, dict):
            yield from _leaves(value, path + (key,))
        else:
            yield path + (key,), value


def test_the_codes_defaults_are_the_schemas():
    """An empty config's lighting and renderer (the schema's defaults) are Lighting()'s and FastSettings()'s."""
    from roughlight.render.fast.settings import FastSettings
    from roughlight.render.shading import Lighting

    cfg = rl_config.validate_config({}, SCHEMA)
    assert rl_config.lighting_from_config(cfg) == Lighting()
    render = rl_config.render_settings_from_config(cfg, random_tiles=True)
    code = FastSettings().config()
    assert {key: code[key] for key in render} == render
    assert FastSettings.from_config(render) == FastSettings()


def test_the_shipped_config_sets_the_schemas_defaults_but_for_the_studys_grid_and_kinds():
    """config/config.yaml writes most defaults out for its readers: each equals the schema's. Only the study's own
    choices differ: its grid (the thesis's, with sqrt(3)/2), its surfaces (the random kinds and their seeds), its
    claim design's tested seeds, its registered pilots (config/claim_pilots.csv: none by default, where a config
    of one's own renders its pilots) and third round (config/claim_third_round.csv: none by default) and the
    surface it exports (none by default, so that a small user grid renders
    no more than it asks for)."""
    defaults = rl_config.validate_config({}, SCHEMA)
    differ = []
    for path, value in _leaves(default_config()):
        here = defaults
        for key in path:
            here = here.get(key, "<no default>") if isinstance(here, dict) else "<no default>"
        if here != value:
            differ.append(path)
    registered = {("claims", f"registered_{name}")
                  for name in ("pilots", "third_round", "fourth_round", "fifth_round", "sixth_round", "seventh_round",
                               "eighth_round")}
    assert {path[0] for path in differ if path[:2] not in {("claims", "seeds"), ("claims", "max_seeds"),
                                                           ("export", "surfaces")} | registered
            } <= {"grid", "surface"}, differ
    assert defaults["claims"]["registered_pilots"] is None
    assert defaults["claims"]["registered_third_round"] is None
    assert all(defaults["claims"][f"registered_{n}_round"] is None for n in ("fourth", "fifth", "sixth", "seventh", "eighth"))
    # the study exports one surface; a user's config exports none unless it names one
    assert defaults["export"]["surfaces"] == [] and default_config()["export"]["surfaces"] == [[1.0, 1.0]]


EXPORT_BAD = [
    ({"surfaces": [[1.5, 1.0]]}, "export.surfaces: truncation must be in [0, 1]"),
    ({"surfaces": [[0.5]]}, "export.surfaces[0]"),
    ({"table": {"incidence": [0, 50, 40, 90]}}, "export.table.incidence must ascend from 0 to 90"),
    ({"table": {"incidence": [5, 90]}}, "export.table.incidence must ascend from 0 to 90"),
    ({"table": {"light_azimuth": [0, 30]}}, "export.table.light_azimuth must ascend from 0 to 45"),
    ({"table": {"elevation": [1, 45]}}, "export.table.elevation must ascend to 90"),
    ({"table": {"azimuth_step": 7}}, "export.table.azimuth_step must divide 360"),
    ({"table": {"light_azimuth_steps": [[50, 2.5], [25, 1.5]]}}, "light_azimuth_steps' incidences must ascend"),
    ({"table": {"light_azimuth_steps": [[25, 2]]}}, "light_azimuth_steps: a step must divide 45"),
    ({"table": {"light_azimuth_steps": [[25]]}}, "export.table.light_azimuth_steps"),
    ({"mitsuba": {"elevation": [10, 5, 90]}}, "export.mitsuba.elevation must ascend to 90"),
    ({"mitsuba": {"phi_nodes": 2}}, "export.mitsuba.phi_nodes"),
    ({"check": {"lights": 0}}, "export.check.lights"),
]


@pytest.mark.parametrize("export,message", EXPORT_BAD)
def test_bad_export_settings_name_the_key(export, message):
    cfg = default_config()
    cfg["export"] = {**cfg.get("export", {}), **export}
    with pytest.raises(rl_config.ConfigError) as info:
        rl_config.validate_config(cfg, SCHEMA)
    assert message in str(info.value)


def test_the_export_settings_reach_the_jobs_as_plain_values():
    """export.surfaces names the jobs (each pair once, in order); the nodes and checks reach rules share_table and
    export whole."""
    from roughlight.study import plan as rl_plan

    cfg = default_config()
    cfg["export"] = {"surfaces": [[0.5, 1], [1, 1], [0.5, 1.0]], "table": {"azimuth_step": 5}}
    cfg = rl_config.validate_config(cfg, SCHEMA)
    assert rl_config.export_surfaces(cfg) == [(0.5, 1.0), (1.0, 1.0)]
    settings = rl_config.export_settings(cfg)
    assert settings["table"]["azimuth_step"] == 5.0 and settings["table"]["edge_on"] == [0.0, 45.0]
    assert settings["table"]["light_azimuth"] == [float(p) for p in range(0, 46, 5)]
    for edge_on in (True, False):  # either form reaches the job as it is written
        cfg["export"]["table"]["edge_on"] = edge_on
        assert rl_config.export_settings(rl_config.validate_config(cfg, SCHEMA))["table"]["edge_on"] is edge_on
    cfg["export"]["table"]["edge_on"] = [50]
    with pytest.raises(Exception, match="edge_on"):
        rl_config.validate_config(cfg, SCHEMA)
    del cfg["export"]["table"]["edge_on"]
    assert settings["table"]["hot_spot_views"] is True and settings["mitsuba"]["warp"] is True
    assert settings["mitsuba"]["resolution"] == 32 and settings["check"] == {"lights": 3, "views": 400, "seed": 2001}
    assert rl_plan.export_files(cfg)[:3] == ["results/export/t0.5_a1/shares.npz", "results/export/t0.5_a1/table.json",
                                             "results/export/t0.5_a1/brdf.bsdf"]
    cfg["export"]["surfaces"] = []
    assert rl_plan.export_files(cfg) == []


def test_every_measurement_has_every_plan_the_config_allows():
    """measurements.plan names a size of every measurement (each module's PLANS), and the workflow's plan wildcard
    matches exactly those names: a plan the schema allows that one measurement lacks would fail in its job."""
    import re

    from roughlight.measurements import (
        implicit_surface,
        light_transport,
        random_tiles,
        renderer_validation,
        speed_accuracy,
        stability,
    )

    schema = yaml.safe_load(SCHEMA.read_text())
    plans = set(schema["properties"]["measurements"]["properties"]["plan"]["enum"])
    assert plans == {"smoke", "quick", "full"}
    for module in (implicit_surface, light_transport, random_tiles, renderer_validation, speed_accuracy, stability):
        assert set(module.PLANS) == plans, module.__name__
    common = (REPO / "workflow" / "rules" / "common.smk").read_text()
    assert set(re.search(r'plan="([^"]+)"', common).group(1).split("|")) == plans
