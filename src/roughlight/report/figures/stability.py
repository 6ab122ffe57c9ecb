"""Where methods fail: the stability scans' chart (aliasing, grazing views, shadow acne, shadow-map size,
shininess, clipping at 255, averaged vertex normals)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import seaborn as sns
from matplotlib.ticker import NullFormatter

from .common import legend_below

__all__ = ["fig_stability"]

#: Errors below this are drawn at it, so that they show on the log scales.
FLOOR = 1e-2
#: The y label of the worst-component panels.
MAE = "worst-component MAE (0-255)"


def _worst(frame, experiment, by=("method", "setting", "x")):
    """The largest MAE over components of one experiment, per method, setting and x."""
    d = frame[(frame["experiment"] == experiment) & (frame["metric"] == "mae")]
    d = d.groupby(list(by), as_index=False)["value"].max()
    d["value"] = d["value"].clip(lower=FLOOR)
    return d


def _log_panel(ax, data, hue, xlabel, ylabel, title, tolerance):
    sns.lineplot(data=data, x="x", y="value", hue=hue, marker="o", ax=ax)
    ax.set(xscale="log", yscale="log", xlabel=xlabel, ylabel=ylabel, title=title)
    ax.axhline(tolerance, ls=":", c="k", lw=1)
    _measured_ticks(ax, data["x"])
    if ax.get_legend() is not None:
        legend_below(ax, ncol=3, below=42.0, fontsize=8, title=hue, title_fontsize=8)


def _measured_ticks(ax, xs, most: int = 8) -> None:
    """Tick a log x axis at the measured values (when there are few), instead of minor-tick labels that run into
    each other over less than a decade."""
    values = np.unique(np.asarray(xs, float)[np.isfinite(np.asarray(xs, float))])
    if 0 < len(values) <= most:
        ax.set_xticks(values, [f"{v:g}" for v in values])
        ax.xaxis.set_minor_formatter(NullFormatter())


def _scan_panels(axes, frame, tolerance) -> None:
    """The scans: pixels per period (error and jitter spread), elevation (with coverage), shadow bias,
    shadow-map size and shininess; ``axes`` in that order."""
    ax_pixels, ax_jitter, ax_grazing, ax_bias, ax_map, ax_shininess = axes
    pixels = pd.concat([_worst(frame, "pixels"), _worst(frame, "tile_pixels")], ignore_index=True)
    _log_panel(ax_pixels, pixels, "method", "pixels per period (random tiles: per cell)", MAE,
               "pixelation / aliasing", tolerance)
    d = frame[(frame["experiment"] == "pixels") & (frame["metric"] == "jitter_sd")].copy()
    d["value"] = d["value"].clip(lower=FLOOR)
    _log_panel(ax_jitter, d, "method", "pixels per period", "SD over sub-pixel jitter (0-255)",
               "flashing lines: jitter spread of total", tolerance)
    _log_panel(ax_grazing, _worst(frame, "elevation"), "method", "view elevation above horizon (deg, e and 180-e)",
               MAE, "grazing views", tolerance)
    d = frame[(frame["experiment"] == "elevation") & (frame["metric"] == "coverage")]
    twin = ax_grazing.twinx()
    sns.lineplot(data=d, x="x", y="value", hue="method", ls="--", legend=False, ax=twin)
    twin.set(ylabel="coverage (dashed)", ylim=(0, 1.05))
    twin.grid(False)
    _log_panel(ax_bias, _worst(frame, "shadow_bias"), "setting", "incidence (deg)", MAE,
               "shadow acne / peter-panning\n(fast by bias; naive)", tolerance)
    _log_panel(ax_map, _worst(frame, "shadow_map"), "setting", "fast shadow map (texels per period)", MAE,
               "shadow-map resolution by incidence", tolerance)
    _log_panel(ax_shininess, _worst(frame, "shininess"), "method", "shininess", MAE, "specular exponent", tolerance)


def _clipping_panels(ax_curve, ax_shift, frame) -> None:
    """The total on the arc at source 127 and 255 (Fig. 17), and how far the clipping moves each lobe."""
    d = frame[(frame["experiment"] == "clipping") & (frame["metric"] == "curve")].copy()
    d["surface"] = d["setting"].str.split(" ").str[0]
    d["source"] = d["setting"].str.split(" ").str[1]
    sns.lineplot(data=d, x="x", y="value", hue="surface", style="source", ax=ax_curve)
    legend_below(ax_curve, ncol=2, below=42.0, fontsize=8)
    ax_curve.axhline(255, c="r", lw=1)
    ax_curve.set(xlabel="view elevation at azimuth 0 (deg)", ylabel="total (0-255)", title="clipping at 255 (Fig. 17)")
    d = frame[(frame["experiment"] == "clipping") & frame["metric"].isin(["peak_shift", "centre_shift"])].copy()
    sns.barplot(data=d, y="setting", x="value", hue="metric", orient="h", ax=ax_shift)
    legend_below(ax_shift, ncol=2, below=42.0, fontsize=8, title="metric", title_fontsize=8)
    ax_shift.set(xlabel="lobe shift, source 127 -> 255 (deg elevation)", ylabel="",
                 title="how far clipping moves the lobes")


def _normals_panel(ax, frame, tolerance) -> None:
    """Averaged vertex normals (naive renderer): each shading model's MAE against the reference and against flat."""
    d = frame[(frame["experiment"] == "normals") & frame["metric"].isin(["mae", "mae_vs_flat"])].copy()
    d = d[~((d["setting"] == "flat") & (d["metric"] == "mae_vs_flat"))]  # zero by construction
    d["value"] = d["value"].clip(lower=FLOOR)
    d["what"] = d["setting"] + np.where(d["metric"] == "mae", " vs reference", " vs flat")
    if len(d):
        sns.barplot(data=d, x="component", y="value", hue="what", ax=ax)
        legend_below(ax, ncol=2, below=42.0, fontsize=8)
    ax.set(yscale="log", ylabel="MAE (0-255)", title="averaged vertex normals (naive)")
    ax.axhline(tolerance, ls=":", c="k", lw=1)


def _picture_panels(axes, pictures) -> None:
    """One picture per shading model; the panels left over are blank."""
    for ax, (model, picture) in zip(axes, pictures.items()):
        ax.imshow(picture)
        ax.set(title=f"{model} shading", xticks=[], yticks=[])
        ax.grid(False)
    for ax in axes[len(pictures):]:
        ax.axis("off")


def fig_stability(frames, pictures=None):
    """Worst-component MAE against pixels per period, jitter spread, elevation, incidence
    by shadow bias, shadow-map size and shininess; the clipped lobes; averaged normals
    by component, and ``pictures`` ({shading model: (H, W, 3) uint8}, from
    :func:`roughlight.measurements.stability.normals_pictures`) when given."""
    from ...measurements.stability import TOLERANCE

    frame = frames if isinstance(frames, pd.DataFrame) else pd.concat(list(frames), ignore_index=True)
    sns.set_theme(style="whitegrid")
    fig, axes = plt.subplots(3, 4, figsize=(20, 13.5))
    _scan_panels([*axes[0], axes[1, 0], axes[1, 1]], frame, TOLERANCE)
    _clipping_panels(axes[1, 2], axes[1, 3], frame)
    _normals_panel(axes[2, 0], frame, TOLERANCE)
    _picture_panels(axes[2, 1:], pictures or {})
    fig.tight_layout()
    return fig
