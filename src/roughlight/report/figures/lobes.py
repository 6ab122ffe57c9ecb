"""Beyond the thesis: where the specular lobes sit and how wide they are."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import seaborn as sns

from ...analysis.thesis import THESIS_INCIDENCE
from ...surfaces.geometry import lobe_centres
from ..registry import title as figure_title
from .common import legend_below, pick_incidence, placeholder, theme

__all__ = ["fig_lobe_geometry"]


def fig_lobe_geometry(lobes_arc: pd.DataFrame, incidence: float = THESIS_INCIDENCE):
    """Measured lobe centres against the geometric mirror directions, and lobe widths."""
    lobes = lobes_arc
    theme()
    d = lobes[np.isfinite(lobes["peak_elevation"]) & ~lobes["plate"]].copy()
    if d.empty:
        return placeholder(figure_title("lobe_geometry"), "no lobes outside the plate")
    fig, axes = plt.subplots(1, 3, figsize=(15, 3.9))
    inc = pick_incidence(d, incidence)
    d = d[np.isclose(d["incidence"], inc)]
    aa = np.linspace(0.0, max(1.0, float(d["aspect"].max())), 200)
    pred_back = [lobe_centres(inc, a)["back"] for a in aa]
    ax = axes[0]
    ax.plot(aa, [np.nan if p is None else p for p in pred_back], "k-", lw=1, label="back: 180 - 2 atan(2a) - i")
    ax.axhline(180 - inc, color="k", ls="--", lw=1, label="forward: 180 - i")
    sns.scatterplot(data=d, x="aspect", y="peak_elevation", hue="lobe", style="lobe", ax=ax, s=22)
    ax.axhline(inc, color="orange", ls=":", lw=1, label="zero phase")
    ax.set_xlabel("aspect")
    ax.set_ylabel("elevation of the lobe peak (deg)")
    ax.set_title("Lobe centres, phi = 0 arc", loc="left")
    legend_below(ax, ncol=2, fontsize=7)
    ax = axes[1]
    sns.scatterplot(data=d[d["peak"] >= 4], x="truncation", y="fwhm", hue="lobe", style="lobe", ax=ax, s=22)
    ax.set_ylabel("FWHM on the arc (deg); peaks >= 4 only")
    ax.set_title("Lobe widths: truncation changes height, not width", loc="left")
    legend_below(ax, ncol=3, fontsize=7)
    ax = axes[2]
    sns.scatterplot(data=d, x="aspect", y="offset", hue="lobe", style="lobe", ax=ax, s=22)
    ax.axhline(0, color="k", lw=0.8)
    ax.set_ylabel("peak minus predicted (deg)")
    ax.set_title("Offset from the mirror direction", loc="left")
    legend_below(ax, ncol=3, fontsize=7)
    return fig
