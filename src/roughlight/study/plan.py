"""The study's plan: which sweeps and meshes a validated config asks for, their files, and each sweep's settings.

One builder for everything that runs a sweep: the workflow's rules (``workflow/rules/common.smk`` hands these to
``rough_sweeps``, ``random_sweeps``, ``control_sweep`` and the mesh rules) and the tests' in-process chain
(``tests/report_chain.py``) call the same functions, so that both name the same files and give each sweep the same
settings. Every function is pure: it reads the config (:func:`roughlight.study.config.validate_config` filled its
defaults) and returns plain types. Paths are relative to the workflow's directory.
"""

from __future__ import annotations

import hashlib
import json
from typing import NamedTuple

from . import config as rl_config

__all__ = [
    "CONTROL_SURFACE",
    "GROUPS",
    "Sweep",
    "grid",
    "sweep_settings",
    "lighting",
    "render_settings",
    "surface_settings",
    "claim_measurement",
    "claim_tiles_key",
    "sweeps",
    "sweep_files",
    "rough_row_files",
    "ensembles",
    "ensemble_folder",
    "ensemble_folders",
    "claim_folder",
    "ensemble_member",
    "rough_row_surfaces",
    "mesh_files",
    "random_mesh_files",
    "every_view_files",
]

#: The control's surface (the flat plate), as ``make_surface`` takes it.
CONTROL_SURFACE = {"truncation": 0.0, "aspect": 0.0}
#: The groups of sweeps: the control (a plate per incidence), the regular grid, the random tiles.
GROUPS = ("control", "rough", "random")


class Sweep(NamedTuple):
    """One sweep of the study: its file, the surface (``make_surface``'s arguments), the light's incidence."""

    path: str
    surface: dict
    incidence: float


def grid(config: dict, key: str) -> list[float]:
    """The grid's values of ``key`` (``truncation``, ``aspect`` or ``incidence``) as floats."""
    return [float(v) for v in config["grid"][key]]


def sweep_settings(config: dict) -> dict:
    """The views of every sweep: ``elevation_step`` and ``azimuth_step`` (degrees)."""
    return {key: float(config["sweep"][key]) for key in ("elevation_step", "azimuth_step")}


def lighting(config: dict, group: str | None = None) -> dict:
    """The lighting (:class:`roughlight.render.shading.Lighting` fields) of the study, or of a group's sweeps
    (:data:`GROUPS`): the control's plate casts no shadows, so the shadows switch does not touch it."""
    out = rl_config.lighting_from_config(config).as_dict()
    if group == "control":
        out.update(shadows=False, specular_shadows=True)
    return out


def render_settings(config: dict, group: str | None = None) -> dict:
    """The method's knobs for the study's sweeps, or a group's (:data:`GROUPS`): the fast renderer's (``random``:
    with those of random tiles, ``render.random_tiles``), Mitsuba's (``render.mitsuba``, every group's); empty for
    the other methods, which they do not affect."""
    method = config["render"]["method"]
    if method == "mitsuba":
        return rl_config.mitsuba_settings_from_config(config)
    if method != "fast":
        return {}
    return rl_config.render_settings_from_config(config, random_tiles=group == "random")


def surface_settings(config: dict, kind: str, truncation: float, aspect: float, seed: int | None = None,
                     claim: bool = False) -> dict:
    """A measured surface as ``make_surface`` takes it: a regular grid point (``pyramids``), or a random tile
    with its seed and how tiles are built (``surface.cells``, ``surface.spread``; with ``claim``, the claim's
    tiles' ``claims.cells``)."""
    if kind == "pyramids":
        return {"kind": kind, "truncation": truncation, "aspect": aspect}
    built = rl_config.claim_surface_settings(config) if claim else rl_config.random_surface_settings(config)
    return {"kind": kind, "truncation": truncation, "aspect": aspect, "seed": int(seed), **built}


def claim_measurement(config: dict) -> dict:
    """What the claim's tiles are measured with, as rule ``claim_sweeps`` gives them: how a claim tile is built
    (``claims.cells``, ``surface.spread``), the views' steps, the lighting, the method and its render settings
    (the registered third round's key, :func:`roughlight.analysis.third_round.round_key`; rule ``analysis_random``
    takes it as a param)."""
    return {"claim_surface": rl_config.claim_surface_settings(config), "sweep": sweep_settings(config),
            "lighting": lighting(config), "method": config["render"]["method"],
            "render": render_settings(config, "random")}


def claim_tiles_key(measured: dict, kind: str, truncation: float, aspect: float, incidence: float, seeds) -> str:
    """What a claim ensemble's tiles ``seeds`` are measured with, as a digest: SHA-256 (hex, first 16 digits) of
    their surfaces (as :func:`surface_settings` builds a claim tile), the incidence (degrees), the views' steps, the
    lighting, the method and its render settings (``measured``: :func:`claim_measurement`). The pilots'
    (:func:`roughlight.study.pilots.pilot_key`) and the third round's
    (:func:`roughlight.analysis.third_round.round_key`) registered readings are kept under it."""
    settings = {
        "surfaces": [{"kind": kind, "truncation": truncation, "aspect": aspect, "seed": int(seed),
                      **measured["claim_surface"]} for seed in seeds],
        "incidence": float(incidence), **{key: measured[key] for key in ("sweep", "lighting", "method", "render")},
    }
    return hashlib.sha256(json.dumps(settings, sort_keys=True, default=str).encode()).hexdigest()[:16]


def rough_row_files(config: dict, folder: str = "results/sweeps") -> list[str]:
    """The files of one job of rule ``rough_sweeps``: a truncation's sweeps at every grid aspect, in the grid's
    order, with the wildcards ``{incidence}`` and ``{truncation}`` left in."""
    return [f"{folder}/i{{incidence}}/t{{truncation}}_a{rl_config.label(a)}.parquet" for a in grid(config, "aspect")]


def rough_row_surfaces(config: dict, truncation: float) -> list[dict]:
    """The surfaces of :func:`rough_row_files` at ``truncation``, in the same order."""
    return [surface_settings(config, "pyramids", truncation, a) for a in grid(config, "aspect")]


def _rough(config: dict, folder: str) -> list[Sweep]:
    return [Sweep(path.format(incidence=rl_config.label(i), truncation=rl_config.label(t)), surface, i)
            for i in grid(config, "incidence") for t in grid(config, "truncation")
            for path, surface in zip(rough_row_files(config, folder), rough_row_surfaces(config, t))]


def ensemble_folder(kind: str, truncation: float, aspect: float, incidence="{incidence}",
                    folder: str = "results/sweeps") -> str:
    """The folder of one job of rule ``random_sweeps``: a random kind's ensemble at a grid point under one light
    (``incidence``, degrees; by default the wildcard ``{incidence}`` is left in), a file a seed in it
    (:func:`ensemble_member`)."""
    incidence = incidence if isinstance(incidence, str) else rl_config.label(incidence)
    return f"{folder}/i{incidence}/{kind}/t{rl_config.label(truncation)}_a{rl_config.label(aspect)}"


def ensemble_member(ensemble: str, seed: int) -> str:
    """A seed's sweep file in its ensemble's folder (:func:`ensemble_folder`)."""
    return f"{ensemble}/s{int(seed)}.parquet"


def ensembles(config: dict, role: str | None = None) -> list[tuple[str, float, float, list[int]]]:
    """Every random kind's ensemble at every random grid point: (kind, truncation, aspect, its seeds), in
    :func:`roughlight.study.config.random_surfaces`' order; with ``role`` ("pilots" or "tested"), the claim's own
    (:func:`roughlight.study.config.claim_surfaces`)."""
    found: dict[tuple[str, float, float], list[int]] = {}
    surfaces = rl_config.random_surfaces(config) if role is None else rl_config.claim_surfaces(config, role)
    for kind, t, a, seed in surfaces:
        found.setdefault((kind, t, a), []).append(seed)
    return [(kind, t, a, seeds) for (kind, t, a), seeds in found.items()]


def ensemble_folders(config: dict, role: str | None = None) -> list[str]:
    """The folders of every ensemble at every incidence: the outputs of rule ``random_sweeps``' jobs (with
    ``role``: of rule ``claim_sweeps``', under :func:`claim_folder`)."""
    folder = "results/sweeps" if role is None else claim_folder(role)
    return [ensemble_folder(kind, t, a, i, folder)
            for i in grid(config, "incidence") for kind, t, a, _ in ensembles(config, role)]


def claim_folder(role: str) -> str:
    """Where rule ``claim_sweeps`` writes the claim's tiles in ``role`` (pilots or tested), an ensemble a folder as
    the study's."""
    return f"{CLAIM_FOLDER}/{role}"


#: Where rule ``claim_sweeps`` writes the claim's tiles, an ensemble a folder as the study's.
CLAIM_FOLDER = "results/claims"


def _random(config: dict, folder: str) -> list[Sweep]:
    return [Sweep(ensemble_member(ensemble_folder(kind, t, a, i, folder), seed),
                  surface_settings(config, kind, t, a, seed), i)
            for i in grid(config, "incidence") for kind, t, a, seed in rl_config.random_surfaces(config)]


def sweeps(config: dict, group: str, folder: str = "results/sweeps") -> list[Sweep]:
    """The sweeps of one group (:data:`GROUPS`): ``control`` (one plate per incidence), ``rough`` (the grid:
    incidence x truncation x aspect) or ``random`` (each random surface of ``surface.kind`` x
    ``surface.random_grid`` x ``surface.seeds`` at each incidence), in the workflow's order, under ``folder``."""
    if group == "control":
        return [Sweep(f"{folder}/i{rl_config.label(i)}/control.parquet", dict(CONTROL_SURFACE), i)
                for i in grid(config, "incidence")]
    if group == "rough":
        return _rough(config, folder)
    if group == "random":
        return _random(config, folder)
    raise ValueError(f"no sweep group {group!r}: one of {', '.join(GROUPS)}")


def sweep_files(config: dict, group: str, folder: str = "results/sweeps") -> list[str]:
    """The files of :func:`sweeps`."""
    return [sweep.path for sweep in sweeps(config, group, folder)]


def meshes(config: dict) -> dict[str, dict]:
    """Every mesh file of the study, each with its surface as ``make_surface`` takes it: one period of every
    regular grid point, the control's plate, and every random tile (its kind and seed in the name)."""
    files = {f"results/meshes/t{rl_config.label(t)}_a{rl_config.label(a)}.ply": surface_settings(config, "pyramids",
                                                                                                  t, a)
             for t in grid(config, "truncation") for a in grid(config, "aspect")}
    files["results/meshes/control.ply"] = surface_settings(config, "pyramids", **CONTROL_SURFACE)
    files.update({f"results/meshes/{kind}_t{rl_config.label(t)}_a{rl_config.label(a)}_s{seed}.ply":
                  surface_settings(config, kind, t, a, seed) for kind, t, a, seed in rl_config.random_surfaces(config)})
    return files


def mesh_files(config: dict) -> list[str]:
    """One PLY per regular grid point, and the control's."""
    return [path for path, surface in meshes(config).items() if surface["kind"] == "pyramids"]


def random_mesh_files(config: dict) -> list[str]:
    """One PLY per random tile, its kind and seed in the name."""
    return [path for path, surface in meshes(config).items() if surface["kind"] != "pyramids"]


def every_view_files(config: dict) -> list[str]:
    """``make every-view``: the study's sweeps of each random kind's first two seeds at the random grid's lowest
    and highest corner, at the tables' incidence, each against the reference at every view."""
    incidence = rl_config.label(rl_config.report_settings(config)["table_incidence"])
    return [f"results/benchmarks/every_view/i{incidence}/{kind}/t{rl_config.label(t)}_a{rl_config.label(a)}_s{seed}"
            ".parquet" for kind, t, a, seed in rl_config.every_view_surfaces(config)]


#: What rules share_table (``shares``, ``table``: its measuring time) and export write for one surface, by name, in
#: ``results/export/t{truncation}_a{aspect}/``.
EXPORT_OUTPUTS = {"shares": "shares.npz", "table": "table.json", "mitsuba": "brdf.bsdf", "check": "check.parquet",
                  "summary": "summary.csv"}


def export_folder(truncation: float, aspect: float) -> str:
    """The folder of one exported surface (``export.surfaces``)."""
    return f"results/export/t{rl_config.label(truncation)}_a{rl_config.label(aspect)}"


def export_files(config: dict, outputs=tuple(EXPORT_OUTPUTS)) -> list[str]:
    """The files rules share_table and export write for each surface of ``export.surfaces``: its ``outputs``, named as in
    :data:`EXPORT_OUTPUTS` (all of them by default)."""
    return [f"{export_folder(t, a)}/{EXPORT_OUTPUTS[name]}" for t, a in rl_config.export_surfaces(config)
            for name in outputs]
