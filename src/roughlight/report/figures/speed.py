"""How fast and how exact: the speed/accuracy benchmark, the default renderer against the exact reference, and
the study's render times."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import seaborn as sns

from ..registry import title as figure_title
from .common import heatmap, label_points, legend_beside, placeholder, theme

__all__ = ["fig_speed_accuracy", "fig_renderer_validation", "fig_timings"]


def _fast_point_labels(sub, label) -> list:
    """The fast renderer's lattice and adaptive points (default bias, 512 shadow map), named by pixels per period."""
    from ...render import methods

    out = []
    for _, row in sub.iterrows():
        if row["method"] == "fast tiles":
            out.append((row["ms per view"], row[label], f"P={row['pixels_per_period']}/cell"))
            continue
        default_bias = np.isclose(row["shadow_bias"], methods.settings("fast").shadow_bias)
        labelled = row["sampling"] in ("lattice", "adaptive") and row["shadow_map_size"] == 512
        if row["method"] == "fast" and labelled and default_bias:
            out.append((row["ms per view"], row[label], f"P={row['pixels_per_period']}"))
    return out


def fig_speed_accuracy(table, floor: float = 1e-3):
    """Error against time per view, log scales: the mean error (top row) and the worst view (bottom row), one
    column per component, Pareto front of the mean error marked.

    The reference's error is zero (up to floating point); it is drawn at
    ``floor`` so that it shows on the log scale.
    """
    data = table[table["component"].isin(["diffuse", "specular"])].copy()
    data["ms per view"] = data["ms_per_view"]
    sns.set_theme(style="whitegrid")
    components = list(dict.fromkeys(data["component"]))
    fig, axes = plt.subplots(2, len(components), figsize=(5.2 * len(components), 8.4), squeeze=False)
    rows = (("mae", "mean abs error (0-255)", 0.5), ("max_error", "worst view, abs error (0-255)", 1.0))
    labels = {}
    for r, (column, label, line_at) in enumerate(rows):
        for ax, component in zip(axes[r], components):
            sub = data[data["component"] == component].copy()
            sub[label] = sub[column].clip(lower=floor)
            sns.scatterplot(data=sub, x="ms per view", y=label, hue="method", style="sampling", s=70, ax=ax,
                            legend=(r == 0 and component == components[-1]))
            if r == 0:  # the regular surfaces' front (random tiles are other surfaces)
                regular = sub["surfaces"] == "regular surfaces" if "surfaces" in sub else True
                front = sub[sub["pareto"] & regular].sort_values("ms per view")
                ax.plot(front["ms per view"], front[label], color="black", lw=1, ls="--", label="Pareto front")
            labels[ax] = _fast_point_labels(sub, label)
            ax.axhline(line_at, color="grey", lw=0.8, ls=":")
            ax.set(xscale="log", yscale="log", title=f"{component}: {'mean error' if r == 0 else 'worst view'}")
    if axes[0, -1].get_legend() is not None:
        sns.move_legend(axes[0, -1], "upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7)
    fig.suptitle("Speed against accuracy: error against the exact reference vs time per view "
                 "(dotted: the 0.5 tolerance of the mean, one 8-bit level at the worst view)", y=1.01)
    fig.tight_layout()
    for ax, points in labels.items():  # once the layout is final: each label clear of the markers
        label_points(ax, points)
    return fig


def fig_renderer_validation(validation, smoothness):
    """The fast renderer against the exact reference: each surface's worst view and MAE per component (the most
    of diffuse, specular and total), by setting (left), and the largest deviation of each arc curve of Figs. 21
    and 28 from the exact curve against truncation (right)."""
    sns.set_theme(style="whitegrid")
    fig, axes = plt.subplots(1, 2, figsize=(14, 4.6))
    data = validation.copy()
    if "setting" not in data.columns:
        data["setting"] = "configured"
    data["surface"] = [f"t {t:.2g}, a {a:.3g}" for t, a in zip(data["truncation"], data["aspect"])]
    long = data.melt(id_vars=["surface", "component", "setting"], value_vars=["worst", "mae"], var_name="statistic",
                     value_name="abs error (0-255)")
    long["setting, statistic"] = long["setting"] + ": " + long["statistic"]
    sns.stripplot(data=long, x="surface", y="abs error (0-255)", hue="setting, statistic", dodge=False, ax=axes[0],
                  marker="o", size=6, jitter=False)
    axes[0].set_yscale("symlog", linthresh=0.1)
    axes[0].axhline(1.0, color="grey", lw=0.8, ls=":")
    axes[0].tick_params(axis="x", rotation=70, labelsize=7)
    axes[0].set_title("every view of each sweep (diffuse, specular, total)")
    legend_beside(axes[0], title="setting, statistic", fontsize=8, title_fontsize=8)
    if len(smoothness):
        sns.lineplot(data=smoothness, x="truncation", y="largest_deviation", hue="figure", style="aspect",
                     marker="o", ax=axes[1])
        legend_beside(axes[1], fontsize=8)
    else:
        axes[1].text(0.5, 0.5, "no table aspect in the study", ha="center", transform=axes[1].transAxes)
    axes[1].axhline(1.0, color="grey", lw=0.8, ls=":")
    axes[1].set(ylabel="largest deviation from the exact curve (0-255)",
                title="the arc curves of Figs. 21 (specular) and 28 (diffuse)")
    fig.suptitle("The default renderer against the exact reference (dotted: one 8-bit level)", y=1.02)
    fig.tight_layout()
    return fig


def fig_timings(render_timings: pd.DataFrame):
    """Render seconds per sweep over (truncation, aspect), one panel per incidence."""
    per_sweep = render_timings
    theme()
    if per_sweep is None or per_sweep.empty:
        return placeholder(figure_title("timings"), "no timings")
    d = per_sweep.copy()
    d["aspect"] = d["aspect"].map(lambda a: round(a, 3))
    incs = sorted(d["incidence"].unique())
    fig, axes = plt.subplots(1, len(incs), figsize=(6 * len(incs), 4.2), squeeze=False)
    for ax, inc in zip(axes[0], incs):
        p = d[d["incidence"] == inc].pivot_table(index="aspect", columns="truncation", values="seconds")
        heatmap(ax, p.sort_index(ascending=False), cmap="rocket_r", annot=p.size <= 150, fmt=".1f",
                label="seconds per sweep")
        ax.set_title(f"incidence {inc:g}: render wall time per sweep", loc="left", fontsize=9)
    fig.tight_layout()
    return fig
