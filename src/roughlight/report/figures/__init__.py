"""Figures of the report: the thesis's Figures 9-29 regenerated from our study, and beyond.

One module a section of the report page, with what they share in :mod:`.common`:

- :mod:`.specular`: the thesis's specular figures, Figs. 17-26 (Fig. 19's top-down maps included)
- :mod:`.diffuse`: the diffuse figures, Figs. 27-29, and the three-part model's parameters
- :mod:`.pictures`: pictures of the surfaces, Figs. 9, 10, 13
- :mod:`.lobes`, :mod:`.glm`, :mod:`.models`: beyond the thesis (lobe geometry, the grid GLMs, the analytic models)
- :mod:`.speed`: speed against accuracy, the renderer against the exact reference, render times
- :mod:`.stability`: where methods fail
- :mod:`.implicit`: the implicit rough surface
- :mod:`.random_roughness`: random roughness (ensembles, maps, the random tiles' benchmark)
- :mod:`.light_transport`: beyond the OpenGL equation (what light that bounces adds, Mitsuba 3)
- :mod:`.export`: the measured BRDF exported (the share table over the hemisphere, both exports off their nodes)

Every ``fig*`` function takes frames of the analysis (:mod:`roughlight.analysis.lobes`,
:mod:`roughlight.analysis.thesis`, ...), the study table or what :mod:`roughlight.render.pictures`
rendered, and returns a :class:`matplotlib.figure.Figure`; :func:`save_figure`
writes it as a PNG atomically and closes it. Nothing here renders. The figures
of the report are :data:`roughlight.report.registry.FIGURES`; a figure's function names
the tables it draws by its parameter names (``study``, ``lobes``, ``sine``, ...),
and ``aspects`` / ``incidence`` are the table aspects and incidence
(``report.table_aspects``, ``report.table_incidence``). The measurement sections' charts are in the
registry too, each drawn by the rule that measures it. Whichever rule draws a figure, it goes one way:
:func:`draw` (the registry's function for it, given its data by name) and :func:`save` (at the registry's
resolution), or both at once, :func:`make`. Intensities are on the 0-255 scale,
angles in degrees. Every public name is importable from this package.
"""

from __future__ import annotations

import importlib
import inspect

from ..registry import figure as registered_figure
from ..registry import figures as registered
from ..registry import title as figure_title
from .common import DPI, hemisphere_map_problem, placeholder, save_figure
from .diffuse import fig27_diffuse_plate, fig28_diffuse_truncation, fig29_diffuse_aspect, fig_diffuse_parts
from .export import fig_export
from .glm import fig_glm_diagnostics
from .implicit import fig_implicit, fig_implicit_maps
from .light_transport import fig_light_transport
from .lobes import fig_lobe_geometry
from .models import fig_hapke, fig_model_fits
from .pictures import fig09_shadows, fig10_grazing, fig13_tops, fig_pictures
from .random_roughness import (
    KIND_COLOURS,
    RANDOM_CHART_STATISTICS,
    fig_random_ensembles,
    fig_random_maps,
    fig_random_tiles,
)
from .specular import (
    fig17_clipping,
    fig19_topdown,
    fig20_plate_incidence,
    fig21_specular_truncation,
    fig23_forward_models,
    fig24_reflecting_areas,
    fig25_back_models,
    fig26_specular_aspect,
)
from .speed import fig_renderer_validation, fig_speed_accuracy, fig_timings
from .stability import fig_stability

__all__ = [
    "DPI",
    "draw",
    "save",
    "make",
    "drawn_figures",
    "save_figure",
    "placeholder",
    "hemisphere_map_problem",
    "fig_export",
    "fig17_clipping",
    "fig19_topdown",
    "fig20_plate_incidence",
    "fig21_specular_truncation",
    "fig23_forward_models",
    "fig24_reflecting_areas",
    "fig25_back_models",
    "fig26_specular_aspect",
    "fig27_diffuse_plate",
    "fig28_diffuse_truncation",
    "fig29_diffuse_aspect",
    "fig_lobe_geometry",
    "fig_light_transport",
    "fig_diffuse_parts",
    "fig_glm_diagnostics",
    "fig_model_fits",
    "fig_hapke",
    "fig_timings",
    "fig_pictures",
    "fig09_shadows",
    "fig10_grazing",
    "fig13_tops",
    "fig_speed_accuracy",
    "fig_renderer_validation",
    "fig_stability",
    "fig_implicit",
    "fig_implicit_maps",
    "RANDOM_CHART_STATISTICS",
    "KIND_COLOURS",
    "fig_random_ensembles",
    "fig_random_maps",
    "fig_random_tiles",
]


def draw_function(figure):
    """The function that draws a registry figure: ``figure.draw`` of the module ``figure.module`` names."""
    return getattr(importlib.import_module(figure.module), figure.draw)


def draw(name: str, **data):
    """The registry's figure ``name`` drawn from ``data``, given by its function's parameter names."""
    return draw_function(registered_figure(name))(**data)


def save(name: str, fig, path) -> str:
    """Write ``fig``, the registry's figure ``name``, to ``path`` at its resolution and bounding box (atomically;
    :func:`save_figure`); return the path."""
    figure = registered_figure(name)
    return save_figure(fig, path, dpi=figure.dpi or DPI, bbox_inches="tight" if figure.tight else None)


def make(name: str, path, **data) -> str:
    """Draw the registry's figure ``name`` from ``data`` (:func:`draw`) and write it to ``path`` (:func:`save`)."""
    return save(name, draw(name, **data), path)


def _arguments(draw, tables, values: dict) -> dict:
    """What ``draw``'s parameters name: settings by name, the study's light, and tables by name (a table that
    ``tables`` lacks leaves its parameter at its default)."""
    kwargs = {}
    for name in inspect.signature(draw).parameters:
        if name in values:
            kwargs[name] = values[name]
        elif name == "light":
            kwargs[name] = float(tables["study"]["light"].iloc[0])
        elif name in tables:
            kwargs[name] = tables[name]
    return kwargs


def drawn_figures(tables, settings: dict):
    """Draw every figure of :data:`roughlight.report.registry.FIGURES` that rule ``figures`` draws, giving each function
    what its parameters name: the settings' table aspects and incidence and Hapke's phase limit, the study's light,
    and tables by the names of the figures rule's inputs.

    Parameters
    ----------
    tables : mapping name -> DataFrame (the figures rule's inputs: ``study``, ``lobes``, ``sine``, ...); a name it
        lacks leaves that parameter at its default
    settings : the ``report:`` section's ``table_aspects``, ``table_incidence`` and ``hapke_max_phase``
        (:func:`roughlight.study.config.report_settings`)

    Yields
    ------
    (name, matplotlib Figure) in the registry's order.
    """
    values = {"aspects": settings["table_aspects"], "incidence": settings["table_incidence"],
              "hapke_max_phase": settings["hapke_max_phase"]}
    for figure in registered(rule="figures"):
        function = draw_function(figure)
        try:
            fig = function(**_arguments(function, tables, values))
        except Exception as exc:  # a study no check foresaw: the page says why, the run goes on
            fig = placeholder(figure_title(figure.name), f"could not be drawn for this study: "
                                                         f"{type(exc).__name__}: {exc}"[:300])
        yield figure.name, fig
