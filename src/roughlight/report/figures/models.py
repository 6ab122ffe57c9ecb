"""Beyond the thesis: how well the analytic surface models fit, and Hapke's opposition surge."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ...analysis.surface_models import MODEL_COLUMNS
from ...analysis.thesis import THESIS_INCIDENCE
from ...study.selection import ASPECT_TOL
from ...surfaces.surface import SQRT3_2, aspect_label
from ..registry import title as figure_title
from .common import heatmap, legend_below, pick_incidence, placeholder, theme

__all__ = ["fig_model_fits", "fig_hapke"]


def fig_model_fits(model_fits: pd.DataFrame, incidence: float = THESIS_INCIDENCE):
    """Heatmaps of each analytic model's RMSE over (truncation, aspect)."""
    fits = model_fits
    theme()
    if fits is None or fits.empty:
        return placeholder(figure_title("model_fits"), "no model fits")
    inc = pick_incidence(fits, incidence)
    d = fits[np.isclose(fits["incidence"], inc)].copy()
    d["aspect"] = d["aspect"].map(lambda a: round(a, 3))
    panels = [(col, f"{comp}: {name}") for comp, cols in MODEL_COLUMNS.items() for col, name in cols.items()
              if col in d]
    ncol = 4
    nrow = math.ceil(len(panels) / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.4 * ncol, 3.5 * nrow), squeeze=False)
    vmax = {comp: float(np.nanmax(d[[c for c in cols if c in d]].to_numpy())) for comp, cols in MODEL_COLUMNS.items()
            if any(c in d for c in cols)}
    comp_of = {col: comp for comp, cols in MODEL_COLUMNS.items() for col in cols}
    for ax, (col, title) in zip(axes.flat, panels):
        p = d.pivot_table(index="aspect", columns="truncation", values=col).sort_index(ascending=False)
        heatmap(ax, p, cmap="mako_r", vmin=0, vmax=vmax[comp_of[col]] or 1)
        ax.set_title(f"{title}\nmedian RMSE {np.nanmedian(p.to_numpy()):.2f}", loc="left", fontsize=8)
    for ax in list(axes.flat)[len(panels):]:
        ax.axis("off")
    fig.tight_layout()
    return fig


def _hapke_surfaces(fits, inc) -> list:
    """The example surfaces that have a fit: t 0.5 and 1 at aspect 1, t 1 at sqrt(3)/2 and 0.5."""
    surfaces = []
    for t, a in ((0.5, 1.0), (1.0, 1.0), (1.0, SQRT3_2), (1.0, 0.5)):
        r = fits[np.isclose(fits["truncation"], t) & (np.abs(fits["aspect"] - a) <= ASPECT_TOL)
                 & np.isclose(fits["incidence"], inc)]
        if len(r):
            surfaces.append((float(r["truncation"].iloc[0]), float(r["aspect"].iloc[0]), inc))
    return surfaces


def _hapke_curves(ax, r, max_phase) -> None:
    """The Hapke fit's linear background and, when fitted, background + B(g)."""
    g = np.linspace(0, max_phase, 200)
    if np.isfinite(r["hapke_c"]):
        bg = r["hapke_c"] + r["hapke_d"] * g
        ax.plot(g, bg, color="#1f77b4", ls="--", lw=1, label="background term of the Hapke fit")
        if np.isfinite(r["hapke_h"]):
            y = bg + r["hapke_S"] / (1 + np.tan(np.radians(g) / 2) / r["hapke_h"])
            ax.plot(g, y, color="#d62728", label=f"+ Hapke B(g): B0 {r['hapke_B0']:.3g}, h {r['hapke_h']:.3g}")


def fig_hapke(study: pd.DataFrame, model_fits: pd.DataFrame, hapke_max_phase: float = 60.0, surfaces=None,
              incidence: float = THESIS_INCIDENCE):
    """The total component against phase near opposition, with Hapke's fitted curve, for a few surfaces."""
    fits, max_phase = model_fits, hapke_max_phase
    theme()
    inc = pick_incidence(study, incidence)
    surfaces = _hapke_surfaces(fits, inc) if surfaces is None else surfaces
    if not surfaces:
        return placeholder(figure_title("hapke"), "none of the example surfaces is in the study")
    tot = study[study["component"].astype(str) == "total"]
    fig, axes = plt.subplots(1, len(surfaces), figsize=(4.3 * len(surfaces), 3.5), squeeze=False, sharey=True)
    for ax, (t, a, i) in zip(axes[0], surfaces):
        d = tot[np.isclose(tot["truncation"], t) & (np.abs(tot["aspect"] - a) <= ASPECT_TOL)
                & np.isclose(tot["incidence"], i) & (tot["coverage"] > 0) & (tot["phase"] <= max_phase)]
        ax.scatter(d["phase"], d["rough"], s=3, alpha=0.35, color="0.3", label="views (all azimuths)")
        curve = d.groupby(np.floor(d["phase"]))["rough"].mean()
        ax.plot(curve.index + 0.5, curve.values, color="k", lw=1.5, label="phase curve (fitted)")
        r = fits[np.isclose(fits["truncation"], t) & (np.abs(fits["aspect"] - a) <= ASPECT_TOL)
                 & np.isclose(fits["incidence"], i)].iloc[0]
        _hapke_curves(ax, r, max_phase)
        ax.set_xlabel("phase angle g (deg)")
        ax.set_ylabel("total (0-255)")
        ax.set_title(f"t {t:g}, aspect {aspect_label(a)}: RMSE {r['rmse_hapke']:.1f}\n(a background-only fit, "
                     f"not drawn: {r['rmse_constant_near_opposition']:.1f})", loc="left", fontsize=8)
        legend_below(ax, fontsize=7)
    return fig
