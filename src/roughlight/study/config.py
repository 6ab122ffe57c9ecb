"""The study's configuration: validation with readable errors, and the settings it implies.

The schema (``workflow/schemas/config.schema.yaml``) is the single source of
allowed values and defaults; :func:`validate_config` fills the defaults (as
``snakemake.utils.validate`` does) and turns every violation into one line
that names the key, the value and what is allowed.
"""

from __future__ import annotations

import copy
import functools
import math
from pathlib import Path
from typing import NamedTuple

import yaml

from ..render.shading import Lighting
from ..surfaces.surface import label

__all__ = [
    "ConfigError",
    "SCHEMA_PATH",
    "load_schema",
    "validate_config",
    "lighting_from_config",
    "render_settings_from_config",
    "mitsuba_settings_from_config",
    "label",
    "surfaces",
    "kinds",
    "random_kinds",
    "pilot_seeds",
    "seeds",
    "random_surfaces",
    "claim_seeds",
    "claim_surfaces",
    "random_points",
    "CLAIM_SEED_BASE",
    "CLAIM_PILOT_BASE",
    "LATER_ROUNDS",
    "CLAIM_ROLES",
    "claim_surface_settings",
    "random_surface_settings",
    "page_surface_settings",
    "report_settings",
    "claim_settings",
    "claims",
    "FOLLOWS_GRID",
    "follow_grid",
]

#: the schema, shipped with the package (workflow/schemas/config.schema.yaml links to it)
SCHEMA_PATH = Path(__file__).resolve().parent / "config.schema.yaml"


class ConfigError(ValueError):
    """The configuration is invalid; the message lists every problem found."""


def load_schema(path=None) -> dict:
    """The config schema (a copy of its parse, kept a process per file and modification time: validation reads it
    for every config, the tests' many)."""
    path = Path(path or SCHEMA_PATH)
    return copy.deepcopy(_parsed_schema(str(path), path.stat().st_mtime_ns))


@functools.lru_cache(maxsize=4)
def _parsed_schema(path: str, mtime_ns: int) -> dict:
    with open(path) as fh:  # libyaml's parser where PyYAML has it: the pure-Python one took 0.2 s a workflow start
        return yaml.load(fh, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))


def _key(path) -> str:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out or "(top level)"


def _describe(error, schema: dict) -> str:
    """One readable line for a jsonschema error."""
    key = _key(error.absolute_path)
    # the description of the property the error is about (items inherit their array's)
    sub = schema
    for part in error.absolute_path:
        if isinstance(part, int):
            sub = sub.get("items", {}) if isinstance(sub, dict) else {}
            continue
        sub = sub.get("properties", {}).get(part, {}) if isinstance(sub, dict) else {}
    desc = sub.get("description") if isinstance(sub, dict) else None
    parent_desc = None
    if error.absolute_path and isinstance(error.absolute_path[-1], int):
        parent = schema
        for part in list(error.absolute_path)[:-1]:
            if isinstance(part, int):
                parent = parent.get("items", {})
            else:
                parent = parent.get("properties", {}).get(part, {})
        parent_desc = parent.get("description")
    allowed = desc or parent_desc
    if error.validator == "additionalProperties":
        allowed_keys = sorted(error.schema.get("properties", {}))
        return f"config: unknown key under {key}: {error.message}; allowed keys: {', '.join(allowed_keys)}"
    value = error.instance
    bound = error.validator_value
    if error.validator == "enum":
        what = f"must be one of {', '.join(map(str, bound))}"
    elif error.validator == "oneOf":
        what = "is not allowed"
    elif error.validator == "minItems":
        what = "must list at least one value"
    else:
        what = {
            "type": f"must be of type {bound}",
            "minimum": f"must be >= {bound}",
            "maximum": f"must be <= {bound}",
            "exclusiveMinimum": f"must be > {bound}",
            "exclusiveMaximum": f"must be < {bound}",
        }.get(error.validator, error.message)
    line = f"config: {key} = {value!r} {what}"
    if allowed:
        line += f" ({key.split('[')[0]}: {allowed})"
    return line


def validate_config(config: dict, schema_path=None, notes: list | None = None) -> dict:
    """Validate ``config`` in place against the schema, filling defaults; the keys that follow the grid
    (:data:`FOLLOWS_GRID`), where unset, take the grid values nearest to their defaults.

    Parameters
    ----------
    notes : list, optional
        Receives one line a key that followed the grid (:func:`follow_grid`).

    Raises
    ------
    ConfigError
        Listing every invalid key, one per line, each with what is allowed.
    """
    import jsonschema

    schema = load_schema(schema_path)
    validator_cls = jsonschema.validators.validator_for(schema)

    def set_defaults(validator, properties, instance, sub_schema):
        if isinstance(instance, dict):
            for name, prop in properties.items():
                if isinstance(prop, dict) and "default" in prop:
                    instance.setdefault(name, copy.deepcopy(prop["default"]))
        yield from validator_cls.VALIDATORS["properties"](validator, properties, instance, sub_schema)

    def is_number(checker, instance):
        # booleans are not numbers here (YAML's yes/no must not pass as 1/0)
        return isinstance(instance, (int, float)) and not isinstance(instance, bool)

    type_checker = validator_cls.TYPE_CHECKER.redefine("number", is_number).redefine(
        "integer", lambda checker, x: is_number(checker, x) and float(x).is_integer()
    )
    extended = jsonschema.validators.extend(
        validator_cls, {"properties": set_defaults}, type_checker=type_checker
    )
    if not isinstance(config, dict):
        raise ConfigError("config: the configuration must be a mapping of keys (see config/README.md)")
    errors = sorted(extended(schema).iter_errors(config), key=lambda e: list(map(str, e.absolute_path)))
    problems = [_describe(e, schema) for e in errors]
    problems += _semantic_problems(config) if not problems else []
    if problems:
        raise ConfigError("invalid configuration:\n  " + "\n  ".join(problems))
    followed = follow_grid(config)
    if notes is not None:
        notes.extend(followed)
    return config


def _semantic_problems(config: dict) -> list[str]:
    problems = []
    for key in ("truncation", "aspect", "incidence"):
        values = config["grid"][key]
        if any(not math.isfinite(float(v)) for v in values):
            problems.append(f"config: grid.{key} must hold finite numbers, got {values!r}")
            continue
        labels = [label(v) for v in values]
        dupes = sorted({lab for lab in labels if labels.count(lab) > 1})
        if dupes:
            problems.append(f"config: grid.{key} lists the same value twice: {', '.join(dupes)}")
    return problems + _surface_problems(config) + _export_problems(config)


def _ascending(values) -> bool:
    return all(b > a for a, b in zip(values, values[1:]))


def _export_problems(config: dict) -> list[str]:
    """What the schema cannot say about ``export:``: truncations in [0, 1], nodes ascending and spanning their range,
    steps that divide the circle or the quarter."""
    export = config.get("export") or {}
    problems = [f"config: export.surfaces: truncation must be in [0, 1], got [{t}, {a}]"
                for t, a in export.get("surfaces", []) if float(t) > 1]
    spans = {("table", "incidence"): (0, 90), ("table", "light_azimuth"): (0, 45), ("table", "elevation"): (None, 90),
             ("mitsuba", "elevation"): (None, 90)}
    for (block, key), (first, last) in spans.items():
        nodes = [float(v) for v in (export.get(block) or {}).get(key, [])]
        if not nodes:
            continue
        ends = (first is None or nodes[0] == first) and nodes[-1] == last
        if not _ascending(nodes) or not ends:
            start = f"from {first} " if first is not None else ""
            problems.append(f"config: export.{block}.{key} must ascend {start}to {last}, got {nodes!r}")
    steps = (export.get("table") or {}).get("light_azimuth_steps") or []
    if not _ascending([float(pair[0]) for pair in steps]):
        problems.append(f"config: export.table.light_azimuth_steps' incidences must ascend, got {steps!r}")
    problems += [f"config: export.table.light_azimuth_steps: a step must divide 45 degrees, got {size!r}"
                 for _, size in steps if abs(45.0 / float(size) - round(45.0 / float(size))) > 1e-9]
    step = (export.get("table") or {}).get("azimuth_step")
    if step is not None and abs(360.0 / float(step) - round(360.0 / float(step))) > 1e-9:
        problems.append(f"config: export.table.azimuth_step must divide 360 degrees, got {step!r}")
    return problems


def _surface_problems(config: dict) -> list[str]:
    surface = config.get("surface", {})
    problems = []
    spread = surface.get("spread", {})
    if spread.get("apex", 0.5) + spread.get("corner", 0.3) >= 1:
        problems.append(f"config: surface.spread.apex + surface.spread.corner = {spread.get('apex', 0.5)} + "
                        f"{spread.get('corner', 0.3)} must be < 1 (else an apex can leave its cell's base: an "
                        "overhanging or vertical side)")
    for key, value in (("surface.seeds", surface.get("seeds")), ("claims.seeds", config.get("claims", {}).get("seeds"))):
        for name, listed in _seed_sets(value):
            if isinstance(listed, list) and len(set(listed)) != len(listed):
                problems.append(f"config: {key}{'.' + name if name else ''} lists the same seed twice: {listed!r}")
        if isinstance(value, dict):
            missing = [k for k in random_kinds(config) if k not in value]
            if missing:
                problems.append(f"config: {key} gives seeds per kind but none for {', '.join(missing)} "
                                "(surface.kind measures it): add it, or give one count or list for every kind")
    return problems + _pilot_problems(config)


def _pilot_problems(config: dict) -> list[str]:
    """A tested seed of the claim that is one of its pilots (a pilot plans the test and is never tested)."""
    problems = []
    pilots = pilot_seeds(config)
    for name, listed in _seed_sets(claims(config)["seeds"]):
        shared = sorted(set(_seed_list(listed, CLAIM_SEED_BASE)) & set(pilots))
        if shared:
            problems.append(f"config: claims.seeds{'.' + name if name else ''} takes the claim's pilot seeds "
                            f"{shared[0]}..{shared[-1]} (claims.pilots: seeds {pilots[0]}..{pilots[-1]}): a pilot "
                            "plans the test and is never tested; give fewer or other seeds")
    registered = claims(config).get("registered_pilots")
    if registered:
        if not Path(registered).is_file():
            problems.append(f"config: claims.registered_pilots: {registered} does not exist (`make claim-pilots` "
                            "writes it; null renders every ensemble's pilots)")
        else:
            header = Path(registered).read_text().partition("\n")[0].strip().split(",")
            missing = [column for column in PILOT_READING_COLUMNS if column not in header]
            if missing:
                problems.append(f"config: claims.registered_pilots: {registered} is not a table of the claim's pilot "
                                f"readings (no column {', '.join(missing)})")
    for name in LATER_ROUNDS:
        registered = claims(config).get(f"registered_{name}_round")
        if registered and not Path(registered).is_file():
            problems.append(f"config: claims.registered_{name}_round: {registered} does not exist (`make claim-{name}-round` "
                            "writes it; null reads none)")
    return problems + _follower_problems(config)


class Follower(NamedTuple):
    """A key that follows the grid: the grid axis it takes values of, the values it prefers (its old default),
    whether it holds one value rather than a list, and why its values must be the grid's."""

    axis: str
    preferred: list
    scalar: bool
    why: str


_RANDOM_WHY = "each random ensemble is compared with the regular surface at the same grid point"

#: The keys that follow the grid when left unset, by key path. Unset, each takes the grid values nearest to its
#: preferred ones (:func:`follow_grid`); set, each value must be a value of its grid axis.
FOLLOWS_GRID = {
    ("surface", "random_grid", "truncation"): Follower("truncation", [0.5, 1.0], False, _RANDOM_WHY),
    ("surface", "random_grid", "aspect"): Follower("aspect", [0.5, 1.0], False, _RANDOM_WHY),
    ("report", "table_aspects"): Follower("aspect", [1.0, math.sqrt(3.0) / 2.0], False,
                                          "Tables 1-2 are of the study's own surfaces"),
    ("report", "table_incidence"): Follower("incidence", [30.0], True, "Tables 1-2 are of the study's own sweeps"),
}


def _get(config: dict, path):
    """The value at ``path`` (a tuple of keys), or None where any key on the way is missing."""
    for key in path:
        if not isinstance(config, dict) or key not in config:
            return None
        config = config[key]
    return config


def _unused(config: dict, path) -> bool:
    """The random grid is not used where no random kind is measured."""
    return path[0] == "surface" and len(kinds(config)) == 1


def _follower_problems(config: dict) -> list[str]:
    """A key that follows the grid, set explicitly to a value outside it, stops the run (one line a key)."""
    problems = []
    for path, follower in FOLLOWS_GRID.items():
        value = _get(config, path)
        if value is None or _unused(config, path):
            continue
        grid_labels = {label(v) for v in config["grid"][follower.axis]}
        missing = [v for v in (value if isinstance(value, list) else [value]) if label(v) not in grid_labels]
        if missing:
            key = ".".join(path)
            problems.append(f"config: {key} = {missing!r} must be values of grid.{follower.axis} ({follower.why}); "
                            f"leave {key} unset to follow the grid")
    return problems


def _nearest(preferred: list[float], values: list[float]) -> list[float]:
    """For each preferred value the nearest of ``values`` (the first of a tie), each listed once, in order."""
    chosen = []
    for want in preferred:
        best = min(values, key=lambda v: abs(float(v) - want))
        if float(best) not in chosen:
            chosen.append(float(best))
    return chosen


def follow_grid(config: dict) -> list[str]:
    """Fill, in place, every key of :data:`FOLLOWS_GRID` the config leaves unset with the grid values nearest to
    its preferred values; the default grid gets exactly the preferred values.

    Returns
    -------
    list of str: one line a filled key, naming the key, the values used and why (for the log and the report).
    """
    notes = []
    for path, follower in FOLLOWS_GRID.items():
        if _get(config, path) is not None:
            continue
        chosen = _nearest(follower.preferred, [float(v) for v in config["grid"][follower.axis]])
        parent = config
        for key in path[:-1]:
            parent = parent.setdefault(key, {})
        parent[path[-1]] = chosen[0] if follower.scalar else chosen
        if _unused(config, path):
            continue  # no random kind is measured: nothing to say
        how = ("as by default" if [label(v) for v in chosen] == [label(v) for v in follower.preferred]
               else "the grid values nearest to the default " + ", ".join(f"{v:g}" for v in follower.preferred))
        shown = ", ".join(f"{v:g}" for v in chosen)
        notes.append(f"{'.'.join(path)} is not set: it follows grid.{follower.axis}, {shown} ({how})")
    return notes


def kinds(config: dict) -> list[str]:
    """The surface kinds measured (``surface.kind``, a name or a list), regular pyramids first: the regular grid
    is always measured, listed or not."""
    kind = config.get("surface", {}).get("kind", ["pyramids"])
    listed = [kind] if isinstance(kind, str) else list(kind)
    return sorted(set(listed) | {"pyramids"}, key=["pyramids", "random_pyramids", "random_heightfield"].index)


def random_kinds(config: dict) -> list[str]:
    """The random kinds measured (:func:`kinds` without the regular pyramids), in :func:`kinds`' order."""
    return [k for k in kinds(config) if k != "pyramids"]


def _seed_sets(value, name: str = ""):
    """Every count or list of seeds in ``surface.seeds`` (a count, a list, or mappings of them), with its key path."""
    if not isinstance(value, dict):
        yield name, value
        return
    for key, inner in value.items():
        yield from _seed_sets(inner, f"{name}.{key}" if name else str(key))


def seeds(config: dict, kind: str, point: tuple[float, float] | None = None, key: str = "surface") -> list[int]:
    """The seeds of the random kind ``kind``'s ensemble at the random grid point ``point`` (truncation, aspect):
    ``surface.seeds`` (the study's tiles, a count n giving 1..n) or, with ``key`` "claims", ``claims.seeds`` (the
    claim's tested tiles, a count n giving :data:`CLAIM_SEED_BASE` + 1 ...). A mapping gives each kind its own
    count or list, or a ``default`` and the grid points, named ``t{truncation}_a{aspect}``, that take their own;
    a named point not in the random grid is not measured."""
    value = config.get(key, {}).get("seeds", 1)
    base = CLAIM_SEED_BASE if key == "claims" else 0
    if isinstance(value, dict):
        value = value[kind]
    if isinstance(value, dict):
        own = {_point_of(key): inner for key, inner in value.items() if key != "default"}
        value = own.get(None if point is None else (label(point[0]), label(point[1])), value["default"])
    return _seed_list(value, base)


def _seed_list(value, base: int = 0) -> list[int]:
    """A count n (seeds ``base`` + 1 ... ``base`` + n) or a list of seeds, as the sorted seeds it names."""
    return list(range(base + 1, base + int(value) + 1)) if not isinstance(value, list) else sorted(int(s) for s in value)


def _point_of(key: str) -> tuple[str, str]:
    """A grid point's name in ``surface.seeds`` (``t0.5_a1``) as the labels of its truncation and aspect."""
    t, a = key[1:].split("_a")
    return label(float(t)), label(float(a))


#: A count of the claim's tested seeds (``claims.seeds``) numbers them from here + 1: tiles no seed of the study's
#: (``surface.seeds``, counts up to 200), of the claim's first round (101-112, read in November 2026, when the
#: claim's tiles were the study's 4-cell ones) or of its pilots (:data:`CLAIM_PILOT_BASE`) is.
CLAIM_SEED_BASE = 200

#: The claim's pilots (``claims.pilots``, a count n) are seeds here + 1 ... + n, at the claim's tile size.
CLAIM_PILOT_BASE = 500
#: The claim's later rounds, each registered once (``claims.registered_{name}_round``): the third, and the rounds of
#: the claim's direction (:data:`roughlight.analysis.direction_rounds.ROUNDS`).
LATER_ROUNDS = ("third", "fourth", "fifth", "sixth", "seventh", "eighth")

#: The columns of a table of the claim's pilot readings (``claims.registered_pilots``; :mod:`roughlight.study.pilots`
#: reads and writes it): an ensemble (kind, grid point, incidence, the digest of its pilots' settings) and one of its
#: readings a row.
PILOT_READING_COLUMNS = ("kind", "truncation", "aspect", "incidence", "key", "reading", "value")
#: The claim's tiles by role: the pilots plan the seeds and are never tested; the tested tiles decide.
CLAIM_ROLES = ("pilots", "tested")


def claims(config: dict) -> dict:
    """The config's ``claims:`` section with the schema's defaults for what it leaves unset (a config that was not
    validated has no defaults filled): the random-roughness claim's design."""
    schema = _parsed_schema(str(SCHEMA_PATH), SCHEMA_PATH.stat().st_mtime_ns)["properties"]["claims"]["properties"]
    return {**{key: spec["default"] for key, spec in schema.items()}, **config.get("claims", {})}


def random_points(config: dict) -> list[tuple[float, float]]:
    """The random grid points (truncation, aspect), grid values exactly as in grid:, in the grid's order."""
    wanted = config["surface"]["random_grid"]
    return [(float(t), float(a)) for t in config["grid"]["truncation"] for a in config["grid"]["aspect"]
            if label(t) in {label(v) for v in wanted["truncation"]} and label(a) in {label(v) for v in wanted["aspect"]}]


def random_surfaces(config: dict) -> list[tuple[str, float, float, int]]:
    """Every random tile of the study: (kind, truncation, aspect, seed), an ensemble's ``surface.seeds``, each
    measured at every view (the claim's own tiles are :func:`claim_surfaces`)."""
    return [(k, t, a, s) for k in random_kinds(config) for t, a in random_points(config)
            for s in seeds(config, k, (t, a))]


def claim_seeds(config: dict, kind: str, point: tuple[float, float], role: str = "tested") -> list[int]:
    """The seeds of a random ensemble of the claim in ``role`` (:data:`CLAIM_ROLES`): the tested tiles
    (``claims.seeds``, from :data:`CLAIM_SEED_BASE` + 1) or the pilots (``claims.pilots``, a count n: seeds
    :data:`CLAIM_PILOT_BASE` + 1 ... + n, the same at every grid point)."""
    if role == "pilots":
        return pilot_seeds(config)
    if role != "tested":
        raise ValueError(f"a claim tile's role is one of {CLAIM_ROLES}, got {role!r}")
    return seeds(config, kind, point, "claims")


def pilot_seeds(config: dict) -> list[int]:
    """The claim's pilot seeds (``claims.pilots``, a count n): :data:`CLAIM_PILOT_BASE` + 1 ... + n, the same for
    every random ensemble."""
    return _seed_list(int(claims(config)["pilots"]), CLAIM_PILOT_BASE)


def claim_surfaces(config: dict, role: str = "tested") -> list[tuple[str, float, float, int]]:
    """Every random tile of the claim in ``role`` (:func:`claim_seeds`), measured at its own views (rule
    ``claim_sweeps``): (kind, truncation, aspect, seed)."""
    return [(k, t, a, s) for k in random_kinds(config) for t, a in random_points(config)
            for s in claim_seeds(config, k, (t, a), role)]


def claim_surface_settings(config: dict) -> dict:
    """How the claim's tiles are built: ``claims.cells`` cells a side, ``surface.spread`` as the study's tiles."""
    return {**random_surface_settings(config), "cells": int(claims(config)["cells"])}


def every_view_surfaces(config: dict, n_seeds: int = 2) -> list[tuple[str, float, float, int]]:
    """The random surfaces ``make every-view`` checks at every view: each random kind's first ``n_seeds`` seeds
    at the lowest and the highest corner of the random grid (its smallest and its largest truncation and aspect),
    as :func:`random_surfaces` gives them."""
    measured = random_surfaces(config)
    if not measured:
        return []
    t = sorted({s[1] for s in measured})
    a = sorted({s[2] for s in measured})
    corners = {(t[0], a[0]), (t[-1], a[-1])}
    return [(k, tt, aa, s) for k, tt, aa, s in measured
            if (tt, aa) in corners and s in seeds(config, k, (tt, aa))[:n_seeds]]


def random_surface_settings(config: dict) -> dict:
    """How random tiles are built (``surface.cells`` and ``surface.spread``), as plain types for params."""
    surface = config["surface"]
    return {"cells": int(surface["cells"]), "spread": {k: float(v) for k, v in surface["spread"].items()}}


def page_surface_settings(config: dict) -> dict:
    """How the study's random tiles are built (:func:`random_surface_settings`) and the claim's tiles' size and
    pilots (``claim_cells``, ``claim_pilots``, ``claim_registered_pilots``: the registered readings' file or ""), for
    the page's text."""
    claim = claims(config)
    return {**random_surface_settings(config), "claim_cells": int(claim["cells"]), "claim_pilots": int(claim["pilots"]),
            "claim_registered_pilots": claim.get("registered_pilots") or ""}


def report_settings(config: dict) -> dict:
    """The ``report:`` section (validated, defaults filled, the grid's followers set), as plain types for params;
    without ``report.explorer``, which reaches rule ``explorer_data`` alone (so that a changed budget reruns the
    explorer and the page, not the analysis)."""
    settings = {k: v for k, v in config["report"].items() if k != "explorer"}
    settings["table_aspects"] = [float(a) for a in settings["table_aspects"]]
    settings["table_incidence"] = float(settings["table_incidence"])
    return settings


def claim_settings(config: dict) -> dict:
    """The random-roughness claim's design (``claims:``, defaults filled) and the tested seeds each random ensemble
    of the claim has (``tested``: [kind, truncation, aspect, count] lists), as plain types for params."""
    settings = claims(config)
    settings["tested"] = [[k, t, a, len(claim_seeds(config, k, (t, a)))]
                          for k in random_kinds(config) for t, a in random_points(config)]
    settings["pilots"], settings["cells"] = int(settings["pilots"]), int(settings["cells"])
    # where the pilots' readings (or the later rounds') come from is not the design: the readings themselves are
    # rules claim_design's and analysis_random's inputs
    for key in ("registered_pilots",
                *(f"registered_{name}_round" for name in LATER_ROUNDS)):
        settings.pop(key, None)
    return settings


def export_surfaces(config: dict) -> list[tuple[float, float]]:
    """The (truncation, aspect) pairs ``export.surfaces`` names, each once, in config order."""
    pairs = [(float(t), float(a)) for t, a in (config.get("export") or {}).get("surfaces", [])]
    return list(dict.fromkeys(pairs))


def export_settings(config: dict) -> dict:
    """``export:``'s nodes and checks (defaults filled), as plain types for params (the surfaces name the jobs)."""
    export = config["export"]
    table = {k: (bool(v) if k == "hot_spot_views" or isinstance(v, bool) else float(v) if k == "azimuth_step"
                 else [[float(x) for x in pair] for pair in v] if k == "light_azimuth_steps"
                 else [float(x) for x in v]) for k, v in export["table"].items()}
    mitsuba = {k: ([float(x) for x in v] if k == "elevation" else bool(v) if k == "warp" else int(v))
               for k, v in export["mitsuba"].items()}
    return {"table": table, "mitsuba": mitsuba, "check": {k: int(v) for k, v in export["check"].items()}}


def surfaces(config: dict) -> list[tuple[float, float]]:
    """All (truncation, aspect) pairs of the grid, in config order."""
    return [(float(t), float(a)) for t in config["grid"]["truncation"] for a in config["grid"]["aspect"]]


def lighting_from_config(config: dict) -> Lighting:
    light, material, render = config["light"], config["material"], config["render"]
    return Lighting(
        light=float(light["intensity"]),
        ambient=float(light["ambient"]),
        ambient_reflectance=float(material["ambient"]),
        diffuse_reflectance=float(material["diffuse"]),
        specular_reflectance=float(material["specular"]),
        shininess=float(material["shininess"]),
        specular_model=str(material["specular_model"]),
        shadows=bool(render["shadows"]),
        specular_shadows=bool(render.get("specular_shadows", True)),
    )


def mitsuba_settings_from_config(config: dict) -> dict:
    """The ``mitsuba`` method's knobs (``render.mitsuba``, defaults filled; a plain dict: it travels through
    Snakemake params), as :class:`roughlight.render.mitsuba.MitsubaSettings` takes them."""
    knobs = dict(config["render"].get("mitsuba") or {})
    out = {key: int(knobs[key]) for key in ("bounces", "samples_per_pixel", "pixels_per_period", "periods")
           if key in knobs}
    if "variant" in knobs:
        out["variant"] = str(knobs["variant"])
    if "albedo" in knobs:
        out["albedo"] = None if knobs["albedo"] is None else float(knobs["albedo"])
    if "specular" in knobs:
        out["specular"] = bool(knobs["specular"])
    return out


def render_settings_from_config(config: dict, random_tiles: bool = False) -> dict:
    """The ``fast`` renderer's knobs (plain dict: it travels through Snakemake params); with ``random_tiles`` also
    how random tiles are sampled (``render.random_tiles``), which only their jobs get, so that changing it reruns
    only them."""
    render = config["render"]
    settings = {
        "pixels_per_period": int(render["pixels_per_period"]),
        "sampling": str(render["sampling"]),
        "shadow_map_size": int(render["shadow_map_size"]),
        "average_lattices_above": float(render["average_lattices_above"]),
    }
    if random_tiles:
        settings["tile_sampling"] = str(render["random_tiles"]["sampling"])
        settings["tile_pixels_per_period"] = int(render["random_tiles"]["pixels_per_period"])
        settings["tile_shadow_map_size"] = int(render["random_tiles"]["shadow_map_size"])
        settings["tile_grazing_scale"] = float(render["random_tiles"]["grazing_scale"])
    return settings
