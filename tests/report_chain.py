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
from roughlight.study import plan
from roughlight.study.tables import aggregate, regular, renderers, run_sweep
from roughlight.surfaces.roughness import make_surface

from .conftest import REPO

SCHEMA = REPO / "workflow" / "schemas" / "config.schema.yaml"

#: The chain checks the page's structure, not its pictures: every figure is drawn by its own function (so a figure
#: that falls back to its placeholder still shows), then saved at this resolution without the tight bounding box,
#: which took a third of an example's time (issue 46).
DRAFT_DPI = 30


def draft(fig, path) -> str:
    """Save a drawn figure as the chain's draft (:data:`DRAFT_DPI`, no tight bounding box)."""
    return F.save_figure(fig, path, dpi=DRAFT_DPI, bbox_inches=None)


def resolved(user: dict) -> tuple[dict, list[str]]:
    """The config the workflow runs with (defaults filled, the grid's followers set) and the follow notes."""
    notes: list[str] = []
    return rl_config.validate_config(copy.deepcopy(user), SCHEMA, notes=notes), notes


def measure_study(cfg: dict, workdir: Path) -> pd.DataFrame:
    """Every sweep of the config's plan (:mod:`roughlight.study.plan`, what the sweep rules run) written under
    ``workdir`` as the sweep rules write them under the workflow's directory, then the study table."""
    method, sweep = cfg["render"]["method"], plan.sweep_settings(cfg)
    files = {}
    for group in plan.GROUPS:
        files[group] = []
        for s in plan.sweeps(cfg, group):
            path = workdir / s.path
            path.parent.mkdir(parents=True, exist_ok=True)
            run_sweep(str(path), make_surface(**s.surface), s.incidence, sweep, plan.lighting(cfg, group), method,
                      plan.render_settings(cfg, group))
            files[group].append(str(path))
    return aggregate(files["rough"] + files["random"], files["control"])


def build_page(cfg: dict, followed: list[str], study: pd.DataFrame, workdir: Path) -> str:
    """The analysis steps, the drawn figures and the page, as the report rules chain them: every output is named as
    the rules name it (its file's stem; a chart's stem and _png) and handed to the next step by that name."""
    settings = rl_config.report_settings(cfg)
    lighting = plan.lighting(cfg)
    regular_study = regular(study)
    outputs, study_summary = steps.analysis_tables(regular_study, settings, lighting, log=lambda message: None)
    outputs["study_summary"] = study_summary
    glm, outputs["glm_messages"] = steps.analysis_glm(outputs["lobes_arc"], outputs["diffuse_levels"], settings,
                                                      lighting)
    outputs.update(glm, **steps.analysis_models(regular_study, settings, lighting))
    figures = {name: draft(fig, workdir / "figures" / f"{name}.png")
               for name, fig in F.drawn_figures({"study": regular_study, **outputs}, settings)}
    # the renderer validation's arc curves (rule renderer_validation) follow the table aspects and the grid's arcs
    smoothness = arc_smoothness(study, settings["table_aspects"], settings["table_incidence"], Lighting(**lighting))
    assert set(smoothness["aspect"]) <= set(settings["table_aspects"])
    if rl_config.random_surfaces(cfg):
        outputs.update(steps.analysis_random(study, settings, lighting))
        # the charts rule analysis_random draws (the page is built without them: the chain checks the tables)
        draft(F.draw("random_ensembles", summary=outputs["random_ensembles"]), workdir / "figures" / "random_ensembles.png")
        draft(F.draw("random_maps", study=study), workdir / "figures" / "random_maps.png")
    if cfg["report"]["explorer"]["enabled"]:  # rule explorer_data
        outputs["explorer_data"] = explorer_data(study_columns(study), budget=cfg["report"]["explorer"]["budget"])
    ran_on = renderers(sorted((workdir / "results" / "sweeps").rglob("*.parquet")))  # as study_table records them
    return R.build_report(outputs, figures, config=cfg, provenance={"settings": settings, "renderers": ran_on},
                          followed=followed,
                          surface_settings=rl_config.random_surface_settings(cfg),
                          table_aspects=settings["table_aspects"], table_incidence=settings["table_incidence"])


def whole_report(user: dict, workdir: Path) -> tuple[str, dict, list[str], pd.DataFrame]:
    """A user's config -> (the page, the config it ran with, the follow notes, the study table)."""
    cfg, followed = resolved(user)
    study = measure_study(cfg, workdir)
    return build_page(cfg, followed, study, workdir), cfg, followed, study
