"""Beyond the thesis: diagnostics of the grid GLMs (residuals, leverage, Cook's distance)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import pandas as pd
import seaborn as sns

from ...surfaces.surface import aspect_label
from ..registry import title as figure_title
from .common import legend_beside, placeholder, theme

__all__ = ["fig_glm_diagnostics"]


def _residual_panel(ax, d, srow, response, legend: bool) -> None:
    """Residuals against fitted values, coloured by truncation; the fit's convergence and pseudo-R² in the title."""
    sns.scatterplot(data=d, x="fitted", y="residual", hue="truncation", palette="viridis", ax=ax, s=18, legend=legend)
    ax.axhline(0, color="k", lw=0.8)
    sub = ""
    if len(srow):
        s = srow.iloc[0]
        sub = (f"\nconverged {bool(s['converged'])}, κ(scaled) {s['condition_scaled']:.1f}, "
               f"pseudo-R² {s['pseudo_r2']:.3f}")
    ax.set_title(f"{response}{sub}", loc="left", fontsize=9)
    ax.set_ylabel("residual (0-255)")
    if legend:
        legend_beside(ax, title="truncation", fontsize=8, title_fontsize=8)


def _influence_panel(ax, d, srow) -> None:
    """Pearson residual against leverage, sized by Cook's distance; the three most influential surfaces named."""
    n, p = len(d), max(1, len(srow.iloc[0]["terms"].split(" + ")) + 1) if len(srow) else 2
    size = 10 + 400 * d["cooks_distance"] / max(d["cooks_distance"].max(), 1e-12)
    ax.scatter(d["leverage"], d["pearson_residual"], s=size,
               c=d["aspect"], cmap="rocket_r", alpha=0.8, edgecolor="k", linewidth=0.3)
    ax.axvline(2 * p / max(n, 1), color="0.4", ls=":", lw=1)
    ax.axhline(0, color="k", lw=0.8)
    top = d.nlargest(3, "cooks_distance")
    for _, row in top.iterrows():
        ax.annotate(f"t{row['truncation']:g},a{aspect_label(row['aspect'])}",  # beside the largest bubble
                    (row["leverage"], row["pearson_residual"]), xytext=(12, 0), textcoords="offset points",
                    va="center", fontsize=7)
    ax.set_xlabel("leverage (hat); dotted 2p/n")
    ax.set_ylabel("Pearson residual")
    ax.set_title("influence: size ∝ Cook's distance, colour = aspect", loc="left", fontsize=9)


def fig_glm_diagnostics(glm_diagnostics: pd.DataFrame, glm_summary: pd.DataFrame):
    """Residuals against fitted values and influence (leverage, Cook's distance) of each grid GLM."""
    diag, summary = glm_diagnostics, glm_summary
    theme()
    if diag is None or diag.empty:
        return placeholder(figure_title("glm_diagnostics"), "no GLM was fitted (see the messages in the report)")
    responses = list(dict.fromkeys(diag["response"]))
    fig, axes = plt.subplots(2, len(responses), figsize=(4.8 * len(responses), 7), squeeze=False)
    for j, r in enumerate(responses):
        d = diag[diag["response"] == r].copy()
        d["aspect "] = d["aspect"].map(lambda a: round(a, 2))
        srow = summary[summary["response"] == r]
        _residual_panel(axes[0, j], d, srow, r, legend=j == len(responses) - 1)
        _influence_panel(axes[1, j], d, srow)
    fig.tight_layout()
    return fig
