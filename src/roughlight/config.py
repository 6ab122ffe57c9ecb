"""The study's configuration: validation with readable errors, and the settings it implies.

The schema (``workflow/schemas/config.schema.yaml``) is the single source of
allowed values and defaults; :func:`validate_config` fills the defaults (as
``snakemake.utils.validate`` does) and turns every violation into one line
that names the key, the value and what is allowed.
"""

from __future__ import annotations

import math
from pathlib import Path

import yaml

from .shading import Lighting

__all__ = [
    "ConfigError",
    "SCHEMA_PATH",
    "load_schema",
    "validate_config",
    "lighting_from_config",
    "render_settings_from_config",
    "label",
    "surfaces",
]

SCHEMA_PATH = Path(__file__).resolve().parents[2] / "workflow" / "schemas" / "config.schema.yaml"


class ConfigError(ValueError):
    """The configuration is invalid; the message lists every problem found."""


def load_schema(path=None) -> dict:
    with open(path or SCHEMA_PATH) as fh:
        return yaml.safe_load(fh)


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


def validate_config(config: dict, schema_path=None) -> dict:
    """Validate ``config`` in place against the schema, filling defaults.

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
                    instance.setdefault(name, _copy(prop["default"]))
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
    return config


def _copy(value):
    return yaml.safe_load(yaml.safe_dump(value))


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
    return problems


def label(value) -> str:
    """Exact, file-name-safe text of a grid value: 0.1 -> '0.1', 1.0 -> '1', 30 -> '30'."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


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
    )


def render_settings_from_config(config: dict) -> dict:
    """The ``fast`` renderer's knobs (plain dict: it travels through Snakemake params)."""
    render = config["render"]
    return {
        "pixels_per_period": int(render["pixels_per_period"]),
        "sampling": str(render["sampling"]),
        "shadow_map_size": int(render["shadow_map_size"]),
    }
