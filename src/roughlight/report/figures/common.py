"""What every figure module shares: the theme, writing a PNG, the placeholder that says why a figure is missing,
heatmaps, picking the table aspects and incidence out of a frame, and the top-down map of the hemisphere."""

from __future__ import annotations

import math
import os

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import seaborn as sns  # noqa: E402
from matplotlib.transforms import Bbox, offset_copy  # noqa: E402

from ...analysis.thesis import THESIS_INCIDENCE  # noqa: E402
from ...atomic import atomic_path  # noqa: E402
from ...study.selection import ASPECT_TOL, arc, find_aspect  # noqa: E402
from ...surfaces.surface import aspect_label  # noqa: E402
from ..registry import title as figure_title  # noqa: E402

#: Resolution of the report's PNGs.
DPI = 110


def theme():
    """The report's seaborn theme (white grid, paper context)."""
    sns.set_theme(style="whitegrid", context="paper", font_scale=1.05)


def save_figure(fig, path, dpi: int = DPI, bbox_inches="tight") -> str:
    """Write ``fig`` as a PNG to ``path`` (temporary name in the same directory, then rename); close it."""
    path = os.fspath(path)
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format="png", dpi=dpi, bbox_inches=bbox_inches)
    finally:
        plt.close(fig)
    return path


def placeholder(title: str, message: str):
    """A small figure that says why the real one could not be drawn."""
    theme()
    fig, ax = plt.subplots(figsize=(6.5, 2.2))
    ax.axis("off")
    ax.set_title(title, loc="left")
    ax.text(0.0, 0.5, message, va="center", ha="left", wrap=True, fontsize=10, transform=ax.transAxes)
    return fig


def heatmap(ax, p: pd.DataFrame, cmap="viridis", vmin=None, vmax=None, annot=False, fmt=".1f", label=None):
    """A pivot table as a heatmap (rows top to bottom as given), with a colour bar.

    Like ``seaborn.heatmap`` but without its per-call redraw of the whole
    figure (which makes a grid of heatmaps quadratic in time).
    """
    z = p.to_numpy(float)
    cmap = sns.color_palette(cmap, as_cmap=True) if isinstance(cmap, str) else cmap
    im = ax.imshow(np.ma.masked_invalid(z), cmap=cmap, vmin=vmin, vmax=vmax, aspect="auto", interpolation="nearest")
    ax.set_xticks(range(z.shape[1]), [_tick(c) for c in p.columns], rotation=90, fontsize=7)
    ax.set_yticks(range(z.shape[0]), [_tick(r) for r in p.index], fontsize=7)
    ax.set_xlabel(p.columns.name or "")
    ax.set_ylabel(p.index.name or "")
    ax.grid(False)
    if annot:
        for (i, j), v in np.ndenumerate(z):
            if np.isfinite(v):
                ax.text(j, i, format(v, fmt), ha="center", va="center", fontsize=6,
                        color=_ink(im.cmap(im.norm(v))))
    ax.figure.colorbar(im, ax=ax, shrink=0.8, label=label)
    return im


def _ink(rgba) -> str:
    """Black on a light cell, white on a dark one (relative luminance of the cell's colour)."""
    r, g, b = rgba[:3]
    return "black" if 0.2126 * r + 0.7152 * g + 0.0722 * b > 0.45 else "white"


def _tick(value) -> str:
    return f"{value:g}" if isinstance(value, (int, float, np.floating)) else str(value)


def legend_beside(ax, handles=None, labels=None, **kwargs):
    """``ax``'s legend to the right of it, outside the axes, so that it covers no data (none when nothing is
    labelled, e.g. a panel without data)."""
    if handles is None:
        handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return None
    return ax.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, **kwargs)


def legend_below(ax, ncol: int = 1, below: float = 38.0, **kwargs):
    """``ax``'s legend under it, ``below`` points under the axes' bottom edge (clear of the tick labels and the x
    label), so that it covers no data (none when nothing is labelled)."""
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return None
    anchor = offset_copy(ax.transAxes, fig=ax.figure, y=-below, units="points")
    return ax.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, 0.0), bbox_transform=anchor,
                     ncol=ncol, borderaxespad=0.0, **kwargs)


def panels_legend(axes, **kwargs):
    """One legend for panels that share their colours, beside the last panel: every label of every panel once (the
    first panel's handle); the panels' own legends are removed."""
    seen = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            seen.setdefault(label, handle)
        if ax.get_legend() is not None:
            ax.get_legend().remove()
    return legend_beside(axes[-1], list(seen.values()), list(seen), **kwargs)


#: Where :func:`label_points` tries a label, in points from its point: upper right, lower right, upper left, lower left.
LABEL_SPOTS = ((3, 3), (3, -9), (-3, 3), (-3, -9))


def label_points(ax, points, fontsize: float = 7, marker: float = 5.0) -> None:
    """Name points of ``ax`` (``[(x, y, text), ...]``, data coordinates), each at the first of :data:`LABEL_SPOTS`
    where the label stays inside the axes and covers no marker of the axes (``marker``: half a marker's width, in
    points) and no label placed before it; at the first spot when none is free. Call it once the layout is final."""
    ax.get_xlim(), ax.get_ylim()  # the limits autoscaling gives, before reading positions
    renderer = ax.figure.canvas.get_renderer()
    half = marker * ax.figure.dpi / 72.0
    centres = [xy for c in ax.collections for xy in c.get_offset_transform().transform(c.get_offsets())]
    frame, taken = ax.get_window_extent(renderer), []

    def annotate(text, x, y, dx, dy):
        label = ax.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points", fontsize=fontsize,
                            ha="left" if dx > 0 else "right")
        return label, label.get_window_extent(renderer)

    for x, y, text in points:
        own = ax.transData.transform((x, y))
        covered = taken + [Bbox.from_bounds(cx - half, cy - half, 2 * half, 2 * half) for cx, cy in centres
                           if np.hypot(cx - own[0], cy - own[1]) > 1.0]
        for dx, dy in LABEL_SPOTS:
            label, box = annotate(text, x, y, dx, dy)
            inside = frame.contains(box.x0, box.y0) and frame.contains(box.x1, box.y1)
            if inside and not any(box.overlaps(other) for other in covered):
                break
            label.remove()
        else:
            label, box = annotate(text, x, y, *LABEL_SPOTS[0])
        taken.append(box)


def aspects_present(frame, wanted) -> list:
    """The aspects of ``wanted`` that ``frame`` holds, as the frame spells them."""
    out = []
    for a in wanted:
        found = find_aspect(frame["aspect"], a)
        if found is not None:
            out.append(found)
    return out


def no_table_aspect(aspects) -> str:
    return "none of the table aspects (" + ", ".join(aspect_label(a) for a in aspects) + ") is in the study"


def arc_panels(study, component, stem, height, aspects, incidence):
    """The phi = 0 arc of one component, its incidence, and a figure with one panel per table aspect
    present (``report.table_aspects``): ``(arc, incidence, fig, [(ax, aspect), ...])``; the list is empty
    and ``fig`` a placeholder when none of them is in the study."""
    views = arc(study, component)
    inc = pick_incidence(views, incidence)
    present = aspects_present(views, aspects)
    if not present:
        return views, inc, placeholder(figure_title(stem), no_table_aspect(aspects)), []
    fig, axes = plt.subplots(1, len(aspects), figsize=(6.2 * len(aspects), height), squeeze=False, sharey=True)
    return views, inc, fig, list(zip(axes[0], present))


def select(frame, aspect=None, truncation=None, incidence=None):
    """The rows of ``frame`` at an aspect (within :data:`~roughlight.study.selection.ASPECT_TOL`), truncation and
    incidence; None keeps every value."""
    m = np.ones(len(frame), bool)
    if aspect is not None:
        m &= np.abs(frame["aspect"].to_numpy(float) - aspect) <= ASPECT_TOL
    if truncation is not None:
        m &= np.isclose(frame["truncation"].to_numpy(float), truncation)
    if incidence is not None:
        m &= np.isclose(frame["incidence"].to_numpy(float), incidence)
    return frame.loc[m]


def pick_incidence(frame, wanted=THESIS_INCIDENCE) -> float:
    """``wanted`` when the frame has it, else the frame's first incidence."""
    inc = np.unique(frame["incidence"].to_numpy(float))
    return float(wanted) if np.any(np.isclose(inc, wanted)) else float(inc[0])


def hue_palette(n, name="viridis"):
    return sns.color_palette(name, n_colors=max(n, 1))


def hemisphere_map_problem(n_azimuths: int, n_elevations: int) -> str | None:
    """Why a sweep's views cannot be mapped over the hemisphere (a triangulation of them), or None."""
    if n_azimuths >= 2 and n_elevations >= 3:
        return None
    return (f"a map of the hemisphere needs views on two half great circles or more, each with three elevations or "
            f"more: this sweep has {n_azimuths} azimuth(s) and {n_elevations} elevation(s) (sweep.azimuth_step, "
            "sweep.elevation_step)")


def topdown_xy(az, el):
    """Orthographic top-down coordinates of views on a grid of azimuths x elevations (x toward the light)."""
    A, E = np.meshgrid(np.radians(az), np.radians(el), indexing="ij")
    x = np.cos(E) * np.cos(A)
    y = np.cos(E) * np.sin(A)
    return x, y


def mirrored(x, y, z):
    """Top-down points and values with the lower half mirrored from the measured upper half (the surfaces are
    symmetric about the light's plane)."""
    x, y, z = np.ravel(x), np.ravel(y), np.ravel(z)
    return np.concatenate([x, x]), np.concatenate([y, -y]), np.concatenate([z, z])


def hemisphere_frame(ax, incidence: float) -> None:
    """The horizon's circle, the light (star) at azimuth 0, equal axes without ticks."""
    ax.add_patch(plt.Circle((0, 0), 1, fill=False, color="0.5", lw=0.6))
    ax.plot([math.cos(math.radians(incidence))], [0], marker="*", color="gold", ms=11, mec="k", mew=0.5, ls="none")
    ax.set(aspect="equal", xlim=(-1.05, 1.05), ylim=(-1.05, 1.05), xticks=[], yticks=[])
