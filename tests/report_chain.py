"""The whole report for a user's config, in one process: every sweep of the grid (the sweep rules' function),
the study table, the analysis steps (:mod:`roughlight.analysis.steps`, what the analysis rules' scripts call), the drawn
figures and the HTML page. The rendered pictures and the measurement sections (speed/accuracy, stability,
implicit, the random-tile benchmark) do not depend on the grid, but for the renderer validation's arc curves,
which are computed here too: the workflow tests build the rest.
"""

from __future__ import annotations

import copy
from pathlib import Path

import pandas as pd

from roughlight.analysis import steps
from roughlight.measurements.renderer_validation import arc_smoothness
from roughlight.render.shading import Lighting
from roughlight.report import figures as F
from roughlight.report import page as R
from roughlight.report.explorer import explorer_data, study_columns
from roughlight.study import config as rl_config
from roughlight.study.tables import aggregate, regular, run_sweep
from roughlight.surfaces.roughness import make_surface

from .conftest import REPO

SCHEMA = REPO / "workflow" / "schemas" / "config.schema.yaml"


def resolved(user: dict) -> tuple[dict, list[str]]:
    """The config the workflow runs with (defaults filled, the grid's followers set) and the follow notes."""
    notes: list[str] = []
    return rl_config.validate_config(copy.deepcopy(user), SCHEMA, notes=notes), notes


def measure_study(cfg: dict, workdir: Path) -> pd.DataFrame:
    """Every sweep of the config's grid written as the sweep rules write them, then the study table."""
    lighting = rl_config.lighting_from_config(cfg).as_dict()
    control_lighting = {**lighting, "shadows": False, "specular_shadows": True}
    method = cfg["render"]["method"]
    render = rl_config.render_settings_from_config(cfg) if method == "fast" else {}
    tile_render = rl_config.render_settings_from_config(cfg, random_tiles=True) if method == "fast" else {}
    sweep = {key: float(cfg["sweep"][key]) for key in ("elevation_step", "azimuth_step")}
    rough, random, control = [], [], []
    for incidence in (float(i) for i in cfg["grid"]["incidence"]):
        folder = workdir / f"i{rl_config.label(incidence)}"
        folder.mkdir(parents=True, exist_ok=True)
        control.append(str(folder / "control.parquet"))
        run_sweep(control[-1], make_surface("pyramids", 0.0, 0.0), incidence, sweep, control_lighting, method, render)
        for t, a in rl_config.surfaces(cfg):
            rough.append(str(folder / f"t{rl_config.label(t)}_a{rl_config.label(a)}.parquet"))
            run_sweep(rough[-1], make_surface("pyramids", t, a), incidence, sweep, lighting, method, render)
        for kind, t, a, seed in rl_config.random_surfaces(cfg):
            random.append(str(folder / f"{kind}_t{rl_config.label(t)}_a{rl_config.label(a)}_s{seed}.parquet"))
            surface = make_surface(kind, t, a, seed, **rl_config.random_surface_settings(cfg))
            run_sweep(random[-1], surface, incidence, sweep, lighting, method, tile_render)
    return aggregate(rough + random, control)


def build_page(cfg: dict, followed: list[str], study: pd.DataFrame, workdir: Path) -> str:
    """The analysis steps, the drawn figures and the page, as the report rules chain them."""
    settings = rl_config.report_settings(cfg)
    lighting = rl_config.lighting_from_config(cfg).as_dict()
    regular_study = regular(study)
    tables, summary = steps.analysis_tables(regular_study, settings, lighting, log=lambda message: None)
    glm, glm_messages = steps.analysis_glm(tables["lobes"], tables["diffuse_levels"], settings, lighting)
    models = steps.analysis_models(regular_study, settings, lighting)
    inputs = {"study": regular_study, "lobes": tables["lobes"], "diffuse_parts": tables["diffuse_parts"],
              "sine": tables["sine"], "exact": tables["exact"], "reflecting_areas": tables["areas"],
              "render_timings": tables["timings"], "glm_summary": glm["summary"],
              "glm_diagnostics": glm["diagnostics"], "model_fits": models["fits"]}
    figures = {name: F.save_figure(fig, workdir / "figures" / f"{name}.png")
               for name, fig in F.drawn_figures(inputs, settings)}
    # the renderer validation's arc curves (rule renderer_validation) follow the table aspects and the grid's arcs
    smoothness = arc_smoothness(study, settings["table_aspects"], settings["table_incidence"], Lighting(**lighting))
    assert set(smoothness["aspect"]) <= set(settings["table_aspects"])
    random_html = None
    if rl_config.random_surfaces(cfg):
        random = steps.analysis_random(study, settings, lighting)
        charts = (F.plot_random_ensembles(random["ensembles"], workdir / "figures" / "random_ensembles.png"),
                  F.plot_random_maps(study, workdir / "figures" / "random_maps.png"))
        random_html = R.random_section(random["ensembles"], random["seeds_needed"], random["model_fits"],
                                       *charts, surface_settings=rl_config.random_surface_settings(cfg))
    page_tables = {
        "study_summary": summary["study"], "timings_summary": summary["timings"],
        "lobes": tables["lobes"], "lobes_hemisphere": tables["hemisphere"], "diffuse_parts": tables["diffuse_parts"],
        "exact_peaks": tables["exact"], "thesis_tables": tables["thesis_tables"],
        "bootstrap_tables": tables["bootstrap"], "sine_refits": tables["sine"],
        "implied_scales": tables["implied_scales"], "tables_at_implied_scale": tables["tables_at_implied_scale"],
        "timings": tables["timings"], "glm_summary": glm["summary"], "glm_coefficients": glm["coefficients"],
        "share_laws": glm["share_laws"], "glm_messages": glm_messages, "model_fits": models["fits"],
        "model_fits_summary": models["summary"],
    }
    explorer = None
    if cfg["report"]["explorer"]["enabled"]:  # rule explorer_data
        explorer = explorer_data(study_columns(study), budget=cfg["report"]["explorer"]["budget"])
    return R.build_report(page_tables, figures, config=cfg, provenance={"settings": settings},
                          messages=summary["messages"], table_aspects=settings["table_aspects"],
                          table_incidence=settings["table_incidence"], random_html=random_html, followed=followed,
                          explorer=explorer)


def whole_report(user: dict, workdir: Path) -> tuple[str, dict, list[str], pd.DataFrame]:
    """A user's config -> (the page, the config it ran with, the follow notes, the study table)."""
    cfg, followed = resolved(user)
    study = measure_study(cfg, workdir / "sweeps")
    return build_page(cfg, followed, study, workdir), cfg, followed, study
