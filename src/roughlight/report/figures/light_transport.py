"""Beyond the OpenGL equation: what light that bounces between facets adds to the study's diffuse (Mitsuba 3)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ...measurements.light_transport import LEVEL
from .common import heatmap, placeholder, theme

__all__ = ["fig_light_transport"]


def _gain_panel(ax, summary: pd.DataFrame, albedo: float, vmax: float) -> None:
    """One albedo's mean hemisphere gain over truncation x aspect, the line where the worst view's gain passes one
    level (dashed) and where the mean's does (solid)."""
    rows = summary[(summary["views"] == "hemisphere") & np.isclose(summary["albedo"], albedo)]
    mean = rows.pivot_table(index="truncation", columns="aspect", values="mean_gain").sort_index(ascending=False)
    worst = rows.pivot_table(index="truncation", columns="aspect", values="worst_gain").reindex_like(mean)
    mean.index.name, mean.columns.name = "truncation", "aspect"
    heatmap(ax, mean, cmap="magma", vmin=0.0, vmax=vmax, annot=True, fmt=".1f", label="mean gain (levels)")
    if min(mean.shape) >= 2:
        x, y = np.meshgrid(np.arange(mean.shape[1]), np.arange(mean.shape[0]))
        for values, style in ((worst, "--"), (mean, "-")):
            z = values.to_numpy(float)
            if np.nanmin(z) < LEVEL < np.nanmax(z):
                ax.contour(x, y, z, levels=[LEVEL], colors="white", linestyles=style, linewidths=1.5)
    ax.set_title(f"albedo {albedo:g}: over the hemisphere", fontsize=9)


def fig_light_transport(summary: pd.DataFrame, frame: pd.DataFrame):
    """Light that bounces against direct light alone, the diffuse (Mitsuba 3): per albedo, the mean gain over the
    hemisphere on the truncation x aspect grid (levels, annotated; the line where the worst view passes one level
    dashed, where the mean does solid), and the gain along the arc of Tables 1-2 at the study's albedo.

    Parameters
    ----------
    summary : :func:`roughlight.measurements.light_transport.interreflection_summary`'s frame.
    frame : :func:`roughlight.measurements.light_transport.interreflection`'s frame (the arc's views).
    """
    theme()
    if summary is None or summary.empty:
        return placeholder("What light that bounces adds", "no surfaces measured")
    albedos = sorted(summary["albedo"].unique(), reverse=True)
    fig, axes = plt.subplots(1, len(albedos) + 1, figsize=(4.6 * (len(albedos) + 1), 4.0))
    vmax = float(summary.loc[summary["views"] == "hemisphere", "mean_gain"].max())
    for ax, albedo in zip(axes, albedos):
        _gain_panel(ax, summary, albedo, max(vmax, LEVEL))
    ax = axes[-1]
    arc = frame[(frame["views"] == "arc") & np.isclose(frame["albedo"], albedos[0])]
    for (t, a), g in arc.groupby(["truncation", "aspect"], sort=True):
        ax.plot(g["elevation"], g["gain"], marker="o", markersize=3, lw=1, label=f"t {t:g}, a {a:.2g}")
    ax.axhline(LEVEL, color="0.4", ls=":", lw=1)
    ax.set_xlabel("view elevation on the arc (azimuth 0), degrees")
    ax.set_ylabel("gain (levels)")
    ax.set_title(f"albedo {albedos[0]:g}: the arc of Tables 1-2", fontsize=9)
    ax.set_ylim(top=ax.get_ylim()[1] * 1.3)  # room for the legend above the lines
    ax.legend(fontsize=6, ncol=3, loc="upper left")
    fig.suptitle("What light that bounces adds to the diffuse (Mitsuba 3, against direct light alone)", fontsize=10)
    fig.tight_layout()
    return fig
