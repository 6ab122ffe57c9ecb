"""What every figure module shares: the theme, writing a PNG, the placeholder that says why a figure is missing,
heatmaps, picking the table aspects and incidence out of a frame, and the top-down map of the hemisphere."""

from __future__ import annotations

import io
import math
import os

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import seaborn as sns  # noqa: E402
from matplotlib.transforms import Bbox, offset_copy  # noqa: E402
from PIL import Image  # noqa: E402

from ...analysis.grids import arc  # noqa: E402
from ...analysis.thesis import THESIS_INCIDENCE  # noqa: E402
from ...atomic import atomic_path  # noqa: E402
from ...study.selection import ASPECT_TOL, find_aspect  # noqa: E402
from ...surfaces.surface import aspect_label  # noqa: E402
from ..registry import title as figure_title  # noqa: E402

#: Resolution of the report's PNGs.
DPI = 110


def theme():
    """The report's seaborn theme (white grid, paper context)."""
    sns.set_theme(style="whitegrid", context="paper", font_scale=1.05)


def save_figure(fig, path, dpi: int = DPI, bbox_inches="tight") -> str:
    """Write ``fig`` as a PNG to ``path`` (temporary name in the same directory, then rename); close it.

    The report's figures are opaque, so the PNG is written as RGB: the same pixels as matplotlib's RGBA, in about
    a tenth fewer bytes (the report embeds every figure), and a little faster. A figure with any transparent pixel
    keeps its alpha."""
    path = os.fspath(path)
    buffer = io.BytesIO()
    try:
        # stored, not deflated: it is read straight back (deflating it twice made saving 15% slower)
        fig.savefig(buffer, format="png", dpi=dpi, bbox_inches=bbox_inches, pil_kwargs={"compress_level": 0})
    finally:
        plt.close(fig)
    buffer.seek(0)
    with Image.open(buffer) as image:
        image.load()
        opaque = image.mode == "RGBA" and image.getchannel("A").getextrema() == (255, 255)
        with atomic_path(path) as tmp:
            (image.convert("RGB") if opaque else image).save(tmp, format="PNG", compress_level=6)
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
    """Why a sweep's views cannot be mapped over the hemisphere (:func:`hemisphere_triangulation`), or None."""
    if n_azimuths >= 2 and n_elevations >= 3:
        return None
    return (f"a map of the hemisphere needs views on two half great circles or more, each with three elevations or "
            f"more: this sweep has {n_azimuths} azimuth(s) and {n_elevations} elevation(s) (sweep.azimuth_step, "
            "sweep.elevation_step)")


def topdown_xy(az, el):
    """Orthographic top-down coordinates of views on a grid of azimuths x elevations (degrees): ``x`` toward the
    light, ``x = cos e cos phi``, ``y = cos e sin phi``, each (len(az), len(el))."""
    A, E = np.meshgrid(np.radians(az), np.radians(el), indexing="ij")
    x = np.cos(E) * np.cos(A)
    y = np.cos(E) * np.sin(A)
    return x, y


#: Views whose azimuths or elevations differ by less than this (degrees) are the same view.
VIEW_TOL = 1e-6


def _grid_axis(angles) -> np.ndarray:
    """The distinct angles of ``angles`` (degrees), ascending; angles within :data:`VIEW_TOL` are one."""
    a = np.sort(np.asarray(angles, float))
    return a[np.concatenate([[True], np.diff(a) > VIEW_TOL])] if len(a) else a


def hemisphere_triangulation(azimuth, elevation, values):
    """A sweep's measured views as a triangulation of the top-down disc whose nodes are those views only.

    The nodes are the sweep's views at their top-down positions; neighbouring
    azimuths are joined by triangles between neighbouring elevations
    (:func:`_grid_triangles` says how the disc is covered and closed). Nothing
    is mirrored across the light's plane: a surface need not be symmetric
    about it (a random tile is not), and the sweep measures both sides of it.

    Parameters
    ----------
    azimuth, elevation : (n,) array-like
        Each view's azimuth phi in [0, 180) and elevation e in [0, 180],
        degrees (the direction to the detector is (cos e cos phi,
        cos e sin phi, sin e); the light is at azimuth 0). Each view once.
    values : (n,) array-like
        The value measured at each view (any unit); a NaN view is left out
        with the triangles that touch it.

    Returns
    -------
    triangulation : matplotlib.tri.Triangulation
        Its nodes are the A x E grid of the sweep's A azimuths and E
        elevations (ascending), azimuth-major, at ``x = cos e cos phi``
        (toward the light), ``y = cos e sin phi``; only measured ones are in
        a triangle.
    z : (A * E,) float array
        Each node's measured value, NaN where the grid's view was not
        measured (in no triangle).

    Raises
    ------
    ValueError
        When the arrays differ in length, an angle is outside its range, a
        view occurs twice, or no triangle joins measured views (fewer than
        two azimuths: :func:`hemisphere_map_problem`).
    """
    from matplotlib.tri import Triangulation

    az_axis, el_axis, z = _sweep_grid(azimuth, elevation, values)
    x, y = topdown_xy(az_axis, el_axis)
    X, Y, Z = x.ravel(), y.ravel(), z.ravel()
    triangles = _grid_triangles(az_axis, el_axis, X, Y)
    p, q, r = triangles.T
    area = 0.5 * np.abs((X[q] - X[p]) * (Y[r] - Y[p]) - (X[r] - X[p]) * (Y[q] - Y[p]))
    keep = (area > 1e-14) & np.isfinite(Z[triangles]).all(axis=1)
    if not keep.any():
        raise ValueError("no two neighbouring half great circles with measured views: nothing to map "
                         "(hemisphere_map_problem)")
    return Triangulation(X, Y, triangles[keep]), Z


def _sweep_grid(azimuth, elevation, values):
    """A sweep's views on the grid of its azimuths x elevations: (azimuths, elevations, (A, E) values, NaN where a
    grid view was not measured); the checks of :func:`hemisphere_triangulation`."""
    az, el, v = (np.asarray(a, float).ravel() for a in (azimuth, elevation, values))
    if not len(az) == len(el) == len(v):
        raise ValueError(f"azimuth, elevation and values differ in length: {len(az)}, {len(el)}, {len(v)}")
    if np.any((az < -VIEW_TOL) | (az >= 180.0 - VIEW_TOL)) or np.any((el < -VIEW_TOL) | (el > 180.0 + VIEW_TOL)):
        raise ValueError("a view's azimuth must be in [0, 180) and its elevation in [0, 180] (degrees)")
    az_axis, el_axis = _grid_axis(az), _grid_axis(el)
    n_az, n_el = len(az_axis), len(el_axis)
    k = np.clip(np.searchsorted(az_axis, az - VIEW_TOL), 0, max(n_az - 1, 0))
    j = np.clip(np.searchsorted(el_axis, el - VIEW_TOL), 0, max(n_el - 1, 0))
    if len(np.unique(k * n_el + j)) < len(az):
        raise ValueError("a view occurs twice: a map shows one sweep (one surface, seed, component and method)")
    z = np.full((n_az, n_el), np.nan)
    z[k, j] = v
    return az_axis, el_axis, z


def _grid_triangles(az_axis, el_axis, X, Y) -> np.ndarray:
    """Every triangle of :func:`hemisphere_triangulation`'s grid ((m, 3) node indices, azimuth-major nodes at
    ``X``, ``Y``), the zero-area ones at the zenith and those touching unmeasured views included.

    Seen from above, the views of one azimuth phi (a half great circle) lie on a diameter of the unit disc, from
    the horizon at phi (e = 0) through the zenith (e = 90, where every azimuth's views meet) to the horizon at
    phi + 180 (e = 180). So the sweep's azimuths 0 to the last one (< 180) cover the whole disc, but for the two
    wedges between the last azimuth and 180 (and 360). Each quad of neighbouring views is split in two. When no
    elevation is 90 (a step such as 4 that does not divide 90), the last elevation below 90 and the first above
    it lie on opposite sides of the centre: the ring of their views around the zenith is filled by triangles of
    its own. The wedges are closed by the azimuth-0 views: the view at azimuth 180 and elevation e is the view at
    azimuth 0 and elevation 180 - e, the same node. They are closed only when all of those are views of the sweep
    (azimuth 0 measured and, with every elevation e, 180 - e too, as with every elevation step that divides 180);
    otherwise they stay empty (but for the ring's part)."""
    n_az, n_el = len(az_axis), len(el_axis)
    node = np.arange(n_az * n_el).reshape(n_az, n_el)
    opposite = np.clip(np.searchsorted(el_axis, 180.0 - el_axis - VIEW_TOL), 0, max(n_el - 1, 0))
    closed = (n_az > 0 and n_el > 0 and abs(az_axis[0]) <= VIEW_TOL
              and bool(np.all(np.abs(el_axis[opposite] - (180.0 - el_axis)) <= VIEW_TOL)))
    columns = np.vstack([node, node[0, opposite]]) if closed else node  # azimuth 180, elevation e = (0, 180 - e)
    # rows j and j + 1 on either side of the zenith without a view at 90 lie on opposite sides of the centre: their
    # quads would cross there; the ring of their views is filled on its own instead
    across = (el_axis[:-1] < 90.0 - VIEW_TOL) & (el_axis[1:] > 90.0 + VIEW_TOL)
    rows = np.flatnonzero(~across)
    a, b = columns[:-1, rows].ravel(), columns[1:, rows].ravel()  # each quad (a, b, c, d), c above b, d above a
    c, d = columns[1:, rows + 1].ravel(), columns[:-1, rows + 1].ravel()
    triangles = [np.stack([a, b, c], axis=1), np.stack([a, c, d], axis=1)]
    if across.any() and n_az >= 2:
        j0 = int(np.flatnonzero(across)[0])
        ring = np.concatenate([node[:, j0], node[:, j0 + 1]])  # azimuths phi, then phi + 180: counter-clockwise
        triangles.append(ring[_fill_polygon(X[ring], Y[ring])])
    return np.concatenate(triangles).reshape(-1, 3)


def _fill_polygon(px, py) -> np.ndarray:
    """Triangles (index triples, (m, 3) int) that fill the simple polygon of vertices ``px``, ``py`` given
    counter-clockwise, by its own vertices: a fan when it is convex, else ear clipping."""
    n = len(px)
    if n < 3:
        return np.zeros((0, 3), int)
    nxt, prv = np.roll(np.arange(n), -1), np.roll(np.arange(n), 1)
    turn = (px[nxt] - px) * (py[prv] - py) - (py[nxt] - py) * (px[prv] - px)  # > 0 where the polygon turns left
    if np.all(turn >= -1e-15):
        return np.stack([np.zeros(n - 2, int), np.arange(1, n - 1), np.arange(2, n)], axis=1)
    left, out = list(range(n)), []

    def cross(o, u, w):
        return (px[u] - px[o]) * (py[w] - py[o]) - (py[u] - py[o]) * (px[w] - px[o])

    while len(left) > 3:
        for m in range(len(left)):
            p, c, q = left[m - 1], left[m], left[(m + 1) % len(left)]
            if cross(p, c, q) <= 0:  # a reflex (or straight) corner is no ear
                continue
            others = np.array([v for v in left if v not in (p, c, q)])
            inside = ((cross(p, c, others) >= 0) & (cross(c, q, others) >= 0) & (cross(q, p, others) >= 0))
            if not inside.any():
                out.append((p, c, q))
                del left[m]
                break
        else:  # no ear: a degenerate polygon; what is left stays empty
            break
    if len(left) == 3:
        out.append(tuple(left))
    return np.array(out, int).reshape(-1, 3)


def rendered_values(elevation, values, coverage=None) -> np.ndarray:
    """``values`` with NaN at the views that were not rendered: the grazing ones (e = 0 and 180,
    :func:`roughlight.render.views.is_grazing`) and any whose ``coverage`` (when given) is 0. A sweep stores 0
    there, which is no measurement: a map draws them as NaN, never as dark views. Arrays of one shape (or
    ``elevation`` broadcastable against ``values``)."""
    from ...render.views import is_grazing

    out = np.array(values, float)
    gone = np.broadcast_to(is_grazing(elevation), out.shape)
    if coverage is not None:
        gone = gone | ~(np.asarray(coverage, float) > 0)
    out[gone] = np.nan
    return out


def hemisphere_map(ax, azimuth, elevation, values, levels, cmap="magma"):
    """Filled contours of a sweep's values over the hemisphere, seen from above, from its measured views only.

    The contours interpolate linearly between measured neighbours on
    :func:`hemisphere_triangulation` (arguments as there; ``levels`` and
    ``cmap`` as :meth:`matplotlib.axes.Axes.tricontourf`'s): every measured
    view lies in the band of its own value, and no view is mirrored or made
    up. Call :func:`hemisphere_frame` after it. Returns the contour set (for a
    colour bar)."""
    triangulation, z = hemisphere_triangulation(azimuth, elevation, values)
    return ax.tricontourf(triangulation, z, levels=levels, cmap=cmap)


def hemisphere_frame(ax, incidence: float) -> None:
    """The horizon's circle, the light (star) at azimuth 0 and elevation ``incidence`` (degrees), equal axes
    without ticks."""
    ax.add_patch(plt.Circle((0, 0), 1, fill=False, color="0.5", lw=0.6))
    ax.plot([math.cos(math.radians(incidence))], [0], marker="*", color="gold", ms=11, mec="k", mew=0.5, ls="none")
    ax.set(aspect="equal", xlim=(-1.05, 1.05), ylim=(-1.05, 1.05), xticks=[], yticks=[])
