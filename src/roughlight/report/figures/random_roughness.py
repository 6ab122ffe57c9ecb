"""Random roughness: the random kinds' ensembles against the regular surface, their hemisphere maps, and the
random tiles' benchmark (tile size, speed, pictures)."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ...surfaces.surface import aspect_label
from .common import (
    hemisphere_frame,
    hemisphere_map,
    hemisphere_map_problem,
    legend_below,
    placeholder,
    rendered_values,
    theme,
)

__all__ = ["RANDOM_CHART_STATISTICS", "KIND_COLOURS", "fig_random_ensembles", "fig_random_maps",
           "fig_random_tiles"]

#: The statistics the random-roughness chart shows, in reading order (see :data:`roughlight.analysis.ensembles.STATISTICS`).
RANDOM_CHART_STATISTICS = ("back_peak", "back_width", "back_squareness", "back_phase_shift",
                           "forward_peak", "diffuse_level", "diffuse_level1", "diffuse_level3")
#: Marker colour of each surface kind.
KIND_COLOURS = {"pyramids": "k", "random_pyramids": "tab:orange", "random_heightfield": "tab:blue"}


def _grid_points(frame) -> np.ndarray:
    """The random grid points (truncation, aspect, incidence) of a frame, by incidence, aspect, truncation."""
    return frame[["truncation", "aspect", "incidence"]].drop_duplicates().sort_values(
        ["incidence", "aspect", "truncation"]).to_numpy()


def _ensemble_panel(ax, sel, points, kinds) -> None:
    """One statistic: at each grid point the regular value (cross) and each kind's mean with its 95% interval."""
    for p, (t, a, i) in enumerate(points):
        at = sel[(sel.truncation == t) & (sel.aspect == a) & (sel.incidence == i)]
        if at.empty:
            continue
        ax.plot(p, at["regular"].iloc[0], marker="x", color="k", ms=8, ls="none",
                label="regular pyramids" if p == 0 else None)
        for k, kind in enumerate(kinds):
            row = at[at["kind"] == kind]
            if row.empty:
                continue
            r = row.iloc[0]
            ax.errorbar(p + 0.18 * (k + 1), r["mean"], yerr=[[r["mean"] - r["ci_low"]], [r["ci_high"] - r["mean"]]],
                        fmt="o", color=KIND_COLOURS[kind], ms=5, capsize=3,
                        label=f"{kind.replace('_', ' ')} (mean, 95% CI)" if p == 0 else None)


def fig_random_ensembles(summary: pd.DataFrame):
    """One panel per statistic: the regular surface (black cross) and each random kind's ensemble mean with
    its 95% interval over seeds, at every random grid point (:func:`roughlight.analysis.ensembles.ensemble_summary`)."""
    theme()
    names = [s for s in RANDOM_CHART_STATISTICS if s in set(summary["statistic"])]
    ncol = 4
    nrow = max(1, math.ceil(len(names) / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.4 * ncol, 3.0 * nrow), squeeze=False)
    points = _grid_points(summary)
    labels = [f"t {t:g}\na {aspect_label(a)}\ni {i:g}" for t, a, i in points]
    kinds = [k for k in KIND_COLOURS if k in set(summary["kind"])]
    for ax, name in zip(axes.ravel(), names):
        sel = summary[summary["statistic"] == name]
        _ensemble_panel(ax, sel, points, kinds)
        if name == "back_squareness":  # 0: as near a rectangle as an ellipse; below, nearer an ellipse
            ax.axhline(0.0, color="0.5", ls="--", lw=1)
        unit = sel["unit"].iloc[0] if len(sel) else ""
        ax.set_title(f"{name.replace('_', ' ')} ({unit})", fontsize=9)
        ax.set_xticks(range(len(points)))
        ax.set_xticklabels(labels, fontsize=7)
    for ax in axes.ravel()[len(names):]:
        ax.axis("off")
    handles, texts = axes.ravel()[0].get_legend_handles_labels()
    fig.legend(handles, texts, loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    return fig


def random_map(fig, ax, sel, kind, surface) -> None:
    """One kind's map (the regular surface, or one seed) from its measured views, on its own scale (15 bands from
    0 to its maximum): the shapes are compared, not the levels. ``sel``: the sweep's rows of one component
    (``azimuth``, ``elevation`` in degrees, ``rough`` 0-255), each view once; ``surface`` (truncation, aspect,
    incidence). A random tile is not symmetric about the light's plane: every view is drawn as measured
    (:func:`.common.hemisphere_map`), none mirrored; the views not rendered (e = 0, 180) are not drawn."""
    t, a, i = surface
    # the views not rendered (e = 0 and 180, coverage 0: stored as 0) are left out, never drawn as dark views
    value = rendered_values(sel["elevation"].to_numpy(float), sel["rough"].to_numpy(float),
                            sel["coverage"].to_numpy(float) if "coverage" in sel else None)
    top = max(float(np.nanmax(value)), 1.0)
    mappable = hemisphere_map(ax, sel["azimuth"].to_numpy(float), sel["elevation"].to_numpy(float), value,
                              levels=np.linspace(0, top, 16), cmap="magma")
    fig.colorbar(mappable, ax=ax, shrink=0.7)
    hemisphere_frame(ax, i)
    seed_text = "" if kind == "pyramids" else f", seed {int(sel['seed'].iloc[0])}"
    ax.set_title(f"{kind.replace('_', ' ')}{seed_text}\nt {t:g}, a {aspect_label(a)}, i {i:g}", fontsize=8,
                 loc="left")


def fig_random_maps(study: pd.DataFrame, component: str = "specular", seed: int = 1):
    """Top-down hemisphere maps (light on the right, star) of the regular surface and of one seed (the lowest) of
    each random kind, one row per random grid point: the thesis's Fig. 19 view of the lobes' shapes, each drawn
    from its measured views only (:func:`.common.hemisphere_map`)."""
    from ...analysis.ensembles import random_points

    theme()
    data = random_points(study)
    data = data[data["component"].astype(str) == component]
    problem = hemisphere_map_problem(data["azimuth"].nunique(), data["elevation"].nunique())
    if problem:
        return placeholder("Random roughness: maps of the hemisphere", problem)
        return
    kinds = [k for k in KIND_COLOURS if k in set(data["kind"].astype(str))]
    points = _grid_points(data)
    fig, axes = plt.subplots(max(1, len(points)), len(kinds), figsize=(3.6 * len(kinds), 3.4 * max(1, len(points))),
                             squeeze=False)
    for row, (t, a, i) in zip(axes, points):
        at = data[(data.truncation == t) & (data.aspect == a) & (data.incidence == i)]
        for ax, kind in zip(row, kinds):
            sel = at[at["kind"].astype(str) == kind]
            sel = sel[sel["seed"] == (0 if kind == "pyramids" else sel["seed"].min())]
            random_map(fig, ax, sel, kind, (t, a, i))
    fig.suptitle(f"{component} (0-255), each map on its own scale", fontsize=9)
    fig.tight_layout()
    return fig


def _convergence_panel(ax, summary, name, first) -> None:
    """One followed statistic of the mean surface (or the views per second) against tile size, per kind, with its
    95% interval over seeds; the regular surface dashed (its value in the same discs)."""
    speed = name == "views_per_second"
    for kind, g in summary.groupby("kind"):
        g = g[g["statistic"] == (first if speed else name)].sort_values("cells")
        y = g["views_per_second"] if speed else g["value"]
        err = None if speed else np.vstack([(g["value"] - g["low"]).to_numpy(float),
                                            (g["high"] - g["value"]).to_numpy(float)])
        ax.errorbar(g["cells"], y, yerr=err, marker="o", capsize=3, color=KIND_COLOURS.get(kind),
                    label=kind.replace("_", " "))
        if not speed and np.isfinite(g["regular"].iloc[0]):
            ax.axhline(g["regular"].iloc[0], color=KIND_COLOURS.get(kind), ls="--", lw=1)
    if speed:
        regular = summary["regular_views_per_second"].dropna()
        if len(regular):
            ax.axhline(float(regular.iloc[0]), color="k", ls="--", lw=1, label="regular surface")
        ax.set_yscale("log")
    unit = "" if speed else str(summary.loc[summary["statistic"] == name, "unit"].iloc[0])
    ax.set_title(name.replace("_", " ") + (" (fast renderer)" if speed else f" ({unit})" if unit else ""),
                 fontsize=9)
    ax.set_xlabel("tile size (cells a side)", fontsize=8)


def fig_random_tiles(summary: pd.DataFrame, accuracy: pd.DataFrame, pictures):
    """The random tiles' benchmark on one page: each followed statistic of each kind's mean surface against tile
    size (its 95% Student-t interval on the jackknife error over seeds; the regular surface, read in the same
    discs, dashed in the kind's colour), the fast renderer's views per second against tile size, and pictures of
    each kind as rendered at the thesis's telling views (kinds by rows)."""
    theme()
    names = list(dict.fromkeys(summary["statistic"]))
    ncol = 3
    n_pictures = len(pictures)
    picture_rows = math.ceil(n_pictures / ncol) if n_pictures else 0
    chart_rows = math.ceil((len(names) + 1) / ncol)
    fig = plt.figure(figsize=(4.0 * ncol, 3.0 * (chart_rows + picture_rows)))
    grid = fig.add_gridspec(chart_rows + picture_rows, ncol)
    for k, name in enumerate(names + ["views_per_second"]):
        ax = fig.add_subplot(grid[k // ncol, k % ncol])
        _convergence_panel(ax, summary, name, names[0])
    legend_below(ax, ncol=2, fontsize=7)  # the last chart's: the kinds and the regular surface (dashed everywhere)
    for k, (label, image) in enumerate(pictures):
        ax = fig.add_subplot(grid[chart_rows + k // ncol, k % ncol])
        ax.imshow(image)
        ax.set_title(label, fontsize=8)
        ax.axis("off")
    fig.tight_layout()
    return fig
