"""An implicit rough surface: the implicit shader's error and frame time, and its hemisphere maps against the
exact reference."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import seaborn as sns
from matplotlib.ticker import FixedLocator, NullLocator

from ...render.views import is_grazing
from ...surfaces.surface import aspect_label
from .common import hemisphere_frame, hemisphere_map, legend_below, theme

__all__ = ["fig_implicit", "fig_implicit_maps"]


def fig_implicit(validation, frames, pictures=None):
    """The implicit rough surface: per-surface MAE by method (left) and frame time against field size (right);
    below, when given, ``pictures`` (method -> 2-D uint8 image) side by side."""
    sns.set_theme(style="whitegrid")
    pictures = pictures or {}
    if pictures:
        fig = plt.figure(figsize=(11, 8.4))
        top = fig.add_gridspec(2, 1, height_ratios=[1, 1.05])
        axes = top[0].subgridspec(1, 2, wspace=0.3).subplots()  # tight_layout leaves a subgrid's spacing alone
        for ax, (name, image) in zip(top[1].subgridspec(1, len(pictures)).subplots(squeeze=False)[0],
                                     pictures.items()):
            ax.imshow(image, cmap="gray", vmin=0, vmax=255)
            ax.set_title(name.replace("_", " "), fontsize=9)
            ax.axis("off")
    else:
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    d = validation[validation["component"] == "diffuse"].copy()
    d["mae (0-255)"] = d["mae"].clip(lower=1e-3)
    sns.stripplot(data=d, x="method", y="mae (0-255)", hue="kind", dodge=True, ax=axes[0], size=4)
    axes[0].set(yscale="log", xlabel="", title="Error against the exact reference, diffuse, per surface")
    axes[0].axhline(0.1, color="grey", lw=0.8, ls=":")
    # six methods: names slanted enough that neighbours do not overlap, each ending under its own strip
    plt.setp(axes[0].get_xticklabels(), rotation=30, ha="right", rotation_mode="anchor")
    legend_below(axes[0], ncol=3, below=80.0, title="kind", fontsize=8, title_fontsize=8)  # under the slanted names
    f = frames.groupby(["field", "method"], as_index=False)["frame_ms"].mean()
    sns.lineplot(data=f, x="field", y="frame_ms", hue="method", marker="o", ax=axes[1])
    axes[1].set(xscale="log", yscale="log", xlabel="field side N (periods)", ylabel="frame time (ms)",
                title="N x N field: explicit mesh against one implicit quad")
    # the fields timed, and only those, named on the axis (a log axis from 16 to 512 names its minor ticks too, and
    # they ran into each other)
    fields = sorted(f["field"].unique())
    axes[1].xaxis.set_major_locator(FixedLocator(fields))
    axes[1].xaxis.set_minor_locator(NullLocator())
    axes[1].set_xticklabels([str(int(n)) for n in fields])
    legend_below(axes[1], ncol=3, below=42.0, title="method", fontsize=8, title_fontsize=8)
    fig.tight_layout()
    return fig


def map_panel(fig, ax, cur, ref, method, component, surface) -> None:
    """The exact map of one surface (15 bands from 0 to its maximum), or an implicit model's difference from it
    on a symmetric scale (16 bands), drawn from the measured views (:func:`.common.hemisphere_map`). ``cur`` and
    ``ref``: the method's and the reference's rows of one surface, ``azimuth`` and ``elevation`` in degrees and
    the components 0-255; the difference is taken view by view, so both must hold the same views. The views that
    were not rendered (e = 0 and 180: coverage 0) are left out whatever their rows hold, never drawn as a value."""
    t, a, i = surface
    keys = ["azimuth", "elevation"]
    if method == "reference":
        views, value = cur, cur[component].to_numpy(float)
    else:
        views = cur[keys + [component]].merge(ref[keys + [component]], on=keys, how="outer",
                                              suffixes=("", "_ref"), validate="one_to_one")
        if len(views) != len(cur) or len(views) != len(ref):
            raise ValueError(f"{method} and the reference were not measured on the same views")
        value = views[component].to_numpy(float) - views[f"{component}_ref"].to_numpy(float)
    azimuth, elevation = views["azimuth"].to_numpy(float), views["elevation"].to_numpy(float)
    value = np.where(is_grazing(elevation), np.nan, value)
    if method == "reference":
        levels, cmap = np.linspace(0, max(float(np.nanmax(value)), 1.0), 16), "magma"
        title = f"t {t:g}, aspect {aspect_label(a)}, i {i:g}: exact {component}"
    else:
        span = max(float(np.nanmax(np.abs(value))), 0.05)
        levels, cmap = np.linspace(-span, span, 17), "RdBu_r"
        title = f"{method.replace('_', ' ')} − exact (max |Δ| {span:.2f})"
    mappable = hemisphere_map(ax, azimuth, elevation, value, levels=levels, cmap=cmap)
    fig.colorbar(mappable, ax=ax, shrink=0.8)
    hemisphere_frame(ax, i)
    ax.set_title(title, loc="left", fontsize=8)


def fig_implicit_maps(maps, component: str = "total"):
    """Hemisphere maps (top-down, light on the right) of the exact reference and of each implicit model's
    difference from it, one row per surface (:func:`roughlight.measurements.implicit_surface.hemisphere_maps`),
    each drawn from the measured views only (:func:`.common.hemisphere_map`)."""
    theme()
    surfaces = maps[["truncation", "aspect", "incidence"]].drop_duplicates().to_numpy()
    # the table model where a surface has a table (rule share_table's), beside the two closed forms
    columns = [m for m in ("reference", "implicit_exact", "implicit_correction", "implicit_table")
               if m in set(maps["method"])]
    fig, axes = plt.subplots(len(surfaces), len(columns), figsize=(3.7 * len(columns), 3.6 * len(surfaces)),
                             squeeze=False)
    for row, (t, a, i) in zip(axes, surfaces):
        sel = maps[(maps.truncation == t) & (maps.aspect == a) & (maps.incidence == i)]
        ref = sel[sel.method == "reference"].sort_values(["azimuth", "elevation"])
        for ax, method in zip(row, columns):
            cur = sel[sel.method == method].sort_values(["azimuth", "elevation"])
            if cur.empty:  # no table of this surface
                ax.axis("off")
                ax.set_title(f"{method.replace('_', ' ')}: no table of this surface", loc="left", fontsize=8)
                continue
            map_panel(fig, ax, cur, ref, method, component, (t, a, i))
    fig.tight_layout()
    return fig
