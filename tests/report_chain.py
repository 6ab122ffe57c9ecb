"""The whole report for a user's config, in one process: every sweep of the grid (the sweep rules' function),
the study table, the analysis steps (:mod:`roughlight.analysis.steps`, what the analysis rules' scripts call), the drawn
figures and the HTML page. The rendered pictures and the measurement sections (speed/accuracy, stability,
implicit, the random-tile benchmark) do not depend on the grid, but for the renderer validation's arc curves,
which are computed here too: the workflow tests build the rest.
"""

from __future__ import annotations

import base64
import copy
from pathlib import Path

import matplotlib.pyplot as plt
import pandas as pd
from matplotlib.backend_bases import RendererBase
from matplotlib.backends.backend_template import RendererTemplate

from roughlight.analysis import steps
from roughlight.atomic import atomic_path
from roughlight.measurements.renderer_validation import arc_smoothness
from roughlight.render.shading import Lighting
from roughlight.report import figures as F
from roughlight.report import page as R
from roughlight.report.explorer import explorer_data, study_columns
from roughlight.study import config as rl_config
from roughlight.study import plan
from roughlight.study.tables import aggregate, claim_rows, regular, renderers, run_sweep
from roughlight.surfaces.roughness import make_surface

from .conftest import REPO

SCHEMA = REPO / "workflow" / "schemas" / "config.schema.yaml"

#: The chain checks the page's structure, not its pictures: every figure is drawn by its own function (so a figure
#: that falls back to its placeholder still shows), then each of its artists is drawn at this resolution by a
#: renderer that lays out the text with the fonts' real metrics (mathtext parsed) and maps the images through their
#: colour maps, but paints no pixel (:class:`_Layout`). Rasterising with Agg (even at 30 dots per inch, without the
#: tight bounding box) took 2.2 s of an example's 3.8 s of figures; this takes 0.7 s (issue 46). The workflow tests
#: rasterise every figure.
DRAFT_DPI = 30
#: What the page embeds for a draft figure: a PNG of one white pixel.
DRAFT_PNG = base64.b64decode("iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAIAAACQd1PeAAAADElEQVR4nGP4//8/AAX+Av4N70a4AAAAAElFTkSuQmCC")


class _Layout(RendererTemplate):
    """matplotlib's template renderer (every draw call a no-op) with the real text metrics and the figure's dpi."""

    get_text_width_height_descent = RendererBase.get_text_width_height_descent

    def points_to_pixels(self, points):
        return points * self.dpi / 72.0


def draft(fig, path) -> str:
    """Draw every artist of ``fig`` without painting (:class:`_Layout`, :data:`DRAFT_DPI`), close it and write
    :data:`DRAFT_PNG` to ``path``: an artist that fails to draw raises here as it would in the workflow."""
    try:
        fig.set_dpi(DRAFT_DPI)
        fig.draw(_Layout(DRAFT_DPI))
    finally:
        plt.close(fig)
    with atomic_path(path) as tmp:
        Path(tmp).write_bytes(DRAFT_PNG)
    return str(path)


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


def claim_chain(cfg: dict, study: pd.DataFrame, workdir: Path) -> dict:
    """The claim's rules in one process: its lobes and discs (claim_discs), its pilot and tested tiles at its views
    and tile size (claim_sweeps), its design from the pilots (claim_design, without rule claim_grid's
    measurements); returns the design's tables and analysis_random's ``claim`` (the tested rows, geometry, margins,
    design)."""
    from roughlight.analysis.claim_instrument import claim_views

    lighting, sweep = plan.lighting(cfg), plan.sweep_settings(cfg)
    steps_ = (float(sweep["azimuth_step"]), float(sweep["elevation_step"]))
    geometry = steps.claim_discs(study, lighting)["random_claim_geometry"]
    folders = {role: [] for role in rl_config.CLAIM_ROLES}
    for role in rl_config.CLAIM_ROLES:
        for i in plan.grid(cfg, "incidence"):
            for kind, t, a, seeds in plan.ensembles(cfg, role):
                folder = workdir / plan.ensemble_folder(kind, t, a, i, plan.claim_folder(role))
                folder.mkdir(parents=True, exist_ok=True)
                views = claim_views(geometry, (t, a, float(i)), *steps_)
                for seed in seeds:
                    surface = make_surface(**plan.surface_settings(cfg, kind, t, a, seed, claim=True))
                    run_sweep(str(folder / f"s{seed}.parquet"), surface, i, sweep, lighting, cfg["render"]["method"],
                              plan.render_settings(cfg, "random"), views=views)
                folders[role].append(folder)
    design = steps.claim_design(study, geometry, None, rl_config.claim_settings(cfg), steps_,
                                pilots=steps.pilot_readings(claim_rows(folders["pilots"]), geometry, steps_))
    return {"random_claim_geometry": geometry, **design, "rows": claim_rows(folders["tested"]), "geometry": geometry,
            "margins": design["random_claim_margins"], "design": design["random_claim_design"], "steps": steps_}


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
        claim = claim_chain(cfg, study, workdir)
        outputs.update({name: claim.pop(name) for name in list(claim) if name.startswith("random_claim")})
        outputs.update(steps.analysis_random(study, settings, lighting, rl_config.claim_settings(cfg), claim))
        # the charts rule analysis_random draws (the page is built without them: the chain checks the tables)
        draft(F.draw("random_ensembles", summary=outputs["random_ensembles"]), workdir / "figures" / "random_ensembles.png")
        draft(F.draw("random_maps", study=study), workdir / "figures" / "random_maps.png")
    if cfg["report"]["explorer"]["enabled"]:  # rule explorer_data
        outputs["explorer_data"] = explorer_data(study_columns(study), budget=cfg["report"]["explorer"]["budget"])
    ran_on = renderers(sorted((workdir / "results" / "sweeps").rglob("*.parquet")))  # as study_table records them
    return R.build_report(outputs, figures, config=cfg, provenance={"settings": settings, "renderers": ran_on},
                          followed=followed,
                          surface_settings=rl_config.page_surface_settings(cfg),
                          table_aspects=settings["table_aspects"], table_incidence=settings["table_incidence"])


def whole_report(user: dict, workdir: Path) -> tuple[str, dict, list[str], pd.DataFrame]:
    """A user's config -> (the page, the config it ran with, the follow notes, the study table)."""
    cfg, followed = resolved(user)
    study = measure_study(cfg, workdir)
    return build_page(cfg, followed, study, workdir), cfg, followed, study
