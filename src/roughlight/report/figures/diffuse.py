"""The thesis's diffuse figures (Figs. 27-29) and the parameters of its three-part diffuse model."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ...analysis.diffuse import continuous_part, diffuse_breakpoints, exponential_part
from ...analysis.grids import arc
from ...analysis.thesis import TABLE_ASPECTS, THESIS_INCIDENCE
from ...study.selection import ASPECT_TOL
from ...surfaces.surface import aspect_label
from ..registry import title as figure_title
from .common import (
    arc_panels,
    heatmap,
    hue_palette,
    legend_beside,
    panels_legend,
    pick_incidence,
    placeholder,
    select,
    theme,
)

__all__ = ["fig27_diffuse_plate", "fig28_diffuse_truncation", "fig29_diffuse_aspect", "fig_diffuse_parts"]


def fig27_diffuse_plate(study: pd.DataFrame, incidence: float = THESIS_INCIDENCE):
    """Fig. 27: diffuse of the smooth surface (plate and control) against view elevation."""
    theme()
    diff = arc(study, "diffuse")
    inc = pick_incidence(diff, incidence)
    d = diff[np.isclose(diff["incidence"], inc) & (diff["coverage"] > 0)]
    plate = d[(d["truncation"] * d["aspect"]) < 1e-9]
    fig, ax = plt.subplots(figsize=(7, 3.4))
    if len(plate):
        p = plate.groupby("elevation")["rough"].agg(["min", "max", "mean"]).reset_index()
        ax.fill_between(p["elevation"], p["min"], p["max"], color="#1f77b4", alpha=0.25, label="plate surfaces (range)")
        ax.plot(p["elevation"], p["mean"], color="#1f77b4", label="plate surfaces (mean)")
    c = d.groupby("elevation")["control"].mean()
    ax.plot(c.index, c.values, "k--", lw=1, label="control plate")
    J = float(study["light"].iloc[0])
    lam = J * math.sin(math.radians(inc))
    ax.axhline(lam, color="orange", ls=":", label=f"J sin(i) = {lam:.1f}")
    ax.set_xlim(0, 180)
    ax.set_ylim(0, max(1.0, float(d["rough"].max())) * 1.2)
    ax.set_xlabel("view elevation (deg), azimuth 0")
    ax.set_ylabel("diffuse (0-255)")
    ax.set_title(f"Diffuse on a smooth surface, incidence {inc:g}", loc="left")
    legend_beside(ax, fontsize=8)
    return fig


def _three_part_curve(row, e):
    """The fitted three-part model along ``e`` (degrees): part two continuous at both breaks when that form
    was fitted (:func:`roughlight.analysis.diffuse.continuous_part`), else the thesis's form."""
    e1, e2 = row["e1"], row["e2"]
    if np.isfinite(row.get("rate_continuous", np.nan)):
        part2 = continuous_part(e, row["level1"], row["level3"], row["rate_continuous"], e1, e2)
    elif np.isfinite(row.get("rate", np.nan)):
        part2 = exponential_part(e, row["level1"], row["level3"], row["rate"], e1)
    else:
        return None
    y = np.where(e <= e1, row["level1"], np.where(e >= e2, row["level3"], part2))
    return np.where((e <= 0) | (e >= 180), np.nan, y)


def _truncation_curves(ax, d, parts, a, inc) -> None:
    """Each truncation's diffuse curve at one aspect, and its three-part fit dashed in the same colour."""
    ts = np.unique(d["truncation"].to_numpy(float))
    ee = np.linspace(0.5, 179.5, 360)
    for color, t in zip(hue_palette(len(ts)), ts):
        dt = d[np.isclose(d["truncation"], t)]
        ax.plot(dt["elevation"], dt["rough"], color=color, lw=1.1, label=f"{t:g}")
        pr = select(parts, aspect=a, truncation=t, incidence=inc)
        if len(pr):
            y = _three_part_curve(pr.iloc[0], ee)
            if y is not None:
                ax.plot(ee, y, color=color, lw=0.8, ls="--")


def fig28_diffuse_truncation(study: pd.DataFrame, diffuse_three_part: pd.DataFrame, aspects=TABLE_ASPECTS,
                             incidence: float = THESIS_INCIDENCE):
    """Fig. 28: diffuse on the phi = 0 arc against truncation, with the fitted three-part model."""
    theme()
    diff, inc, fig, panels = arc_panels(study, "diffuse", "fig28_diffuse_truncation", 3.9, aspects, incidence)
    for ax, a in panels:
        d = select(diff, aspect=a, incidence=inc)
        _truncation_curves(ax, d[d["coverage"] > 0], diffuse_three_part, a, inc)
        e1, e2 = diffuse_breakpoints(inc, a)
        for e in (e1, e2):
            ax.axvline(e, color="0.3", ls=":", lw=1)
        ax.text(e1 / 2, 2, "part 1", ha="center", fontsize=8)
        ax.text((e1 + e2) / 2, 2, "part 2", ha="center", fontsize=8)
        ax.text((e2 + 180) / 2, 2, "part 3", ha="center", fontsize=8)
        ax.set_xlim(0, 180)
        ax.set_ylim(bottom=0)
        ax.set_xlabel(f"view elevation (deg), azimuth 0; breaks at {e1:g} and {e2:.1f}")
        ax.set_ylabel("diffuse (0-255)")
        ax.set_title(f"aspect {aspect_label(a)}, incidence {inc:g} (dashed: three-part fit)", loc="left")
    if panels:
        panels_legend([ax for ax, _ in panels], title="truncation", fontsize=7, title_fontsize=8)
    return fig


def fig29_diffuse_aspect(study: pd.DataFrame, truncation: float = 1.0, incidence: float = THESIS_INCIDENCE):
    """Fig. 29: diffuse on the phi = 0 arc against aspect (full pyramids by default)."""
    theme()
    diff = arc(study, "diffuse")
    inc = pick_incidence(diff, incidence)
    have = np.unique(diff["truncation"].to_numpy(float))
    t = truncation if np.any(np.isclose(have, truncation)) else float(have.max())
    d = select(diff, truncation=t, incidence=inc)
    d = d[d["coverage"] > 0].copy()
    aspects = np.unique(d["aspect"].to_numpy(float))
    fig, ax = plt.subplots(figsize=(7.5, 3.9))
    for color, a in zip(hue_palette(len(aspects), "rocket_r"), aspects):
        da = d[np.abs(d["aspect"] - a) <= ASPECT_TOL]
        ax.plot(da["elevation"], da["rough"], color=color, lw=1.1, label=aspect_label(a))
        if a > 0:
            e2 = diffuse_breakpoints(inc, a)[1]
            ax.plot([e2], [np.interp(e2, da["elevation"], da["rough"])], "v", color=color, ms=5)
    ax.axvline(inc, color="0.3", ls=":", lw=1)
    ax.set_xlim(0, 180)
    ax.set_ylim(bottom=0)
    ax.set_xlabel("view elevation (deg), azimuth 0; ▼: front facet edge-on (180 - atan(2·aspect))")
    ax.set_ylabel("diffuse (0-255)")
    ax.set_title(f"Diffuse against aspect, truncation {t:g}, incidence {inc:g}", loc="left")
    legend_beside(ax, title="aspect", fontsize=7, title_fontsize=8)
    return fig


def fig_diffuse_parts(diffuse_three_part: pd.DataFrame, incidence: float = THESIS_INCIDENCE):
    """Heatmaps over (truncation, aspect) of the three-part diffuse model's parameters."""
    parts = diffuse_three_part
    theme()
    d = parts[np.isfinite(parts["rate"])]
    if d.empty:
        return placeholder(figure_title("diffuse_parts"), "no surface with a fitted decay (all plates?)")
    inc = pick_incidence(d, incidence)
    d = d[np.isclose(d["incidence"], inc)].copy()
    d["aspect"] = d["aspect"].map(lambda a: round(a, 3))
    fig, axes = plt.subplots(1, 4, figsize=(17, 3.9))
    for ax, (col, label, fmt) in zip(axes, (("level1", "level of part 1 (0-255)", ".0f"),
                                            ("level3", "level of part 3 (0-255)", ".0f"),
                                            ("decay_length", "decay length 1/k (deg)", ".0f"),
                                            ("rmse", "RMSE of the model (0-255)", ".1f"))):
        p = d.pivot_table(index="aspect", columns="truncation", values=col).sort_index(ascending=False)
        heatmap(ax, p, cmap="viridis", annot=p.size <= 150, fmt=fmt)
        ax.set_title(label, loc="left", fontsize=9)
    fig.tight_layout()  # each colour bar's ticks clear of the next panel's y label
    return fig
