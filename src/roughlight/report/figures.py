"""Figures of the report: the thesis's Figures 9-29 regenerated from our study, and beyond.

Every ``fig*`` function takes frames of the analysis (:mod:`roughlight.analysis.lobes`,
:mod:`roughlight.analysis.thesis`, ...), the study table or what :mod:`roughlight.render.pictures`
rendered, and returns a :class:`matplotlib.figure.Figure`; :func:`save_figure`
writes it as a PNG atomically and closes it. Nothing here renders. The figures
of the report are :data:`roughlight.report.registry.FIGURES`; a figure's function names
the tables it draws by its parameter names (``study``, ``lobes``, ``sine``, ...),
and ``aspects`` / ``incidence`` are the table aspects and incidence
(``report.table_aspects``, ``report.table_incidence``). The benchmark's and the
stability scans' charts are here too (:func:`plot_speed_accuracy`,
:func:`plot_stability`). Intensities are on the 0-255 scale, angles in degrees.
"""

from __future__ import annotations

import math
import os

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import seaborn as sns  # noqa: E402

from ..analysis.areas import front_facet_share  # noqa: E402
from ..analysis.diffuse import continuous_part, diffuse_breakpoints, exponential_part  # noqa: E402
from ..analysis.lobes import MIN_LOBE_PEAK, lobe_directions  # noqa: E402
from ..analysis.surface_models import MODEL_COLUMNS  # noqa: E402
from ..analysis.thesis import TABLE_ASPECTS, THESIS_INCIDENCE, table_data, thesis_model_predictions  # noqa: E402
from ..atomic import atomic_path  # noqa: E402
from ..render.shading import phase_angle, view_direction  # noqa: E402
from ..study.selection import ASPECT_TOL, arc, find_aspect, surface_grids  # noqa: E402
from ..surfaces.geometry import lobe_centres  # noqa: E402
from ..surfaces.surface import (  # noqa: E402
    SQRT3_2,
    aspect_label,
    is_plate,  # noqa: E402
)
from .registry import title as figure_title  # noqa: E402

__all__ = [
    "save_figure",
    "placeholder",
    "fig17_clipping",
    "fig19_topdown",
    "fig20_plate_incidence",
    "fig21_specular_truncation",
    "fig23_forward_models",
    "fig24_reflecting_areas",
    "fig25_back_models",
    "fig26_specular_aspect",
    "fig27_diffuse_plate",
    "fig28_diffuse_truncation",
    "fig29_diffuse_aspect",
    "fig_lobe_geometry",
    "fig_diffuse_parts",
    "fig_glm_diagnostics",
    "fig_model_fits",
    "fig_hapke",
    "fig_timings",
    "fig_pictures",
]

#: File stem -> short title of every figure the report shows (in report order).

DPI = 110


def _heatmap(ax, p: pd.DataFrame, cmap="viridis", vmin=None, vmax=None, annot=False, fmt=".1f", label=None):
    """A pivot table as a heatmap (rows top to bottom as given), with a colour bar.

    Like ``seaborn.heatmap`` but without its per-call redraw of the whole
    figure (which makes a grid of heatmaps quadratic in time).
    """
    z = p.to_numpy(float)
    cmap = sns.color_palette(cmap, as_cmap=True) if isinstance(cmap, str) else cmap
    im = ax.imshow(np.ma.masked_invalid(z), cmap=cmap, vmin=vmin, vmax=vmax, aspect="auto", interpolation="nearest")
    ax.set_xticks(range(z.shape[1]), [f"{c:g}" if isinstance(c, (int, float, np.floating)) else str(c)
                                      for c in p.columns], rotation=90, fontsize=7)
    ax.set_yticks(range(z.shape[0]), [f"{r:g}" if isinstance(r, (int, float, np.floating)) else str(r)
                                      for r in p.index], fontsize=7)
    ax.set_xlabel(p.columns.name or "")
    ax.set_ylabel(p.index.name or "")
    ax.grid(False)
    if annot:
        lo, hi = np.nanmin(z) if np.isfinite(z).any() else 0, np.nanmax(z) if np.isfinite(z).any() else 1
        mid = (lo + hi) / 2
        for (i, j), v in np.ndenumerate(z):
            if np.isfinite(v):
                ax.text(j, i, format(v, fmt), ha="center", va="center", fontsize=6,
                        color="white" if v < mid else "black")
    ax.figure.colorbar(im, ax=ax, shrink=0.8, label=label)
    return im


def _theme():
    sns.set_theme(style="whitegrid", context="paper", font_scale=1.05)


def drawn_figures(tables, settings: dict):
    """Draw every figure of :data:`roughlight.report.registry.FIGURES` that is drawn, not rendered, giving each function
    what its parameters name: the settings' table aspects and incidence and Hapke's phase limit, the study's light,
    and tables by the names of the figures rule's inputs.

    Parameters
    ----------
    tables : mapping name -> DataFrame (the figures rule's inputs: ``study``, ``lobes``, ``sine``, ...); a name it
        lacks leaves that parameter at its default
    settings : the ``report:`` section (:func:`roughlight.study.config.report_settings`)

    Yields
    ------
    (name, matplotlib Figure) in the registry's order.
    """
    import inspect

    from .registry import figures as registered

    values = {"aspects": settings["table_aspects"], "incidence": settings["table_incidence"],
              "hapke_max_phase": settings["hapke_max_phase"]}
    for figure in registered(rendered=False):
        draw = globals()[figure.draw]
        kwargs = {}
        for name in inspect.signature(draw).parameters:
            if name in values:
                kwargs[name] = values[name]
            elif name == "light":
                kwargs[name] = float(tables["study"]["light"].iloc[0])
            elif name in tables:
                kwargs[name] = tables[name]
        try:
            fig = draw(**kwargs)
        except Exception as exc:  # a study no check foresaw: the page says why, the run goes on
            fig = placeholder(figure_title(figure.name), f"could not be drawn for this study: "
                                                         f"{type(exc).__name__}: {exc}"[:300])
        yield figure.name, fig


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
    _theme()
    fig, ax = plt.subplots(figsize=(6.5, 2.2))
    ax.axis("off")
    ax.set_title(title, loc="left")
    ax.text(0.0, 0.5, message, va="center", ha="left", wrap=True, fontsize=10, transform=ax.transAxes)
    return fig


def _aspects_present(frame, wanted):
    out = []
    for a in wanted:
        found = find_aspect(frame["aspect"], a)
        if found is not None:
            out.append(found)
    return out


def _no_table_aspect(aspects) -> str:
    return "none of the table aspects (" + ", ".join(aspect_label(a) for a in aspects) + ") is in the study"


def _arc_panels(study, component, stem, height, aspects, incidence):
    """The phi = 0 arc of one component, its incidence, and a figure with one panel per table aspect
    present (``report.table_aspects``): ``(arc, incidence, fig, [(ax, aspect), ...])``; the list is empty
    and ``fig`` a placeholder when none of them is in the study."""
    views = arc(study, component)
    inc = _incidence(views, incidence)
    present = _aspects_present(views, aspects)
    if not present:
        return views, inc, placeholder(figure_title(stem), _no_table_aspect(aspects)), []
    fig, axes = plt.subplots(1, len(aspects), figsize=(6.2 * len(aspects), height), squeeze=False, sharey=True)
    return views, inc, fig, list(zip(axes[0], present))


def _sel(frame, aspect=None, truncation=None, incidence=None):
    m = np.ones(len(frame), bool)
    if aspect is not None:
        m &= np.abs(frame["aspect"].to_numpy(float) - aspect) <= ASPECT_TOL
    if truncation is not None:
        m &= np.isclose(frame["truncation"].to_numpy(float), truncation)
    if incidence is not None:
        m &= np.isclose(frame["incidence"].to_numpy(float), incidence)
    return frame.loc[m]


def _incidence(frame, wanted=THESIS_INCIDENCE):
    inc = np.unique(frame["incidence"].to_numpy(float))
    return float(wanted) if np.any(np.isclose(inc, wanted)) else float(inc[0])


def _hue_palette(n, name="viridis"):
    return sns.color_palette(name, n_colors=max(n, 1))


def fig17_clipping(plates: pd.DataFrame):
    """Fig. 17: the plate's specular and total at source 127 and 255 (phi = 0 arc)."""
    _theme()
    d = plates[plates["component"].isin(["specular", "total"])].copy()
    if d.empty:
        return placeholder(figure_title("fig17_clipping"), "no plate sweeps")
    d["source J"] = d["light"].map(lambda j: f"{j:g}")
    g = sns.relplot(data=d, x="elevation", y="value", hue="source J", col="component", kind="line",
                    height=3.2, aspect=1.3, palette=["#1f77b4", "#d62728"], facet_kws={"sharey": True})
    for ax in g.axes.flat:
        ax.axhline(255, color="k", lw=0.8, ls=":")
        ax.text(2, 258, "8-bit ceiling 255", fontsize=8, va="bottom")
        ax.set_xlim(0, 180)
        ax.set_xlabel("view elevation (deg), azimuth 0")
    g.set_ylabels("mean pixel value (0-255)")
    g.figure.suptitle(f"Flat plate, incidence {d['incidence'].iloc[0]:g}: the specular lobe clips at source 255",
                      y=1.04)
    return g.figure


def fig20_plate_incidence(plates: pd.DataFrame):
    """Fig. 20: specular of the smooth surface for incidences 0-90 (phi = 0 arc)."""
    _theme()
    d = plates[plates["component"] == "specular"].copy()
    if d.empty:
        return placeholder(figure_title("fig20_plate_incidence"), "no plate sweeps")
    d["incidence (deg)"] = d["incidence"].map(lambda i: f"{i:g}")
    n = d["incidence (deg)"].nunique()
    fig, ax = plt.subplots(figsize=(7.5, 3.6))
    sns.lineplot(data=d, x="elevation", y="value", hue="incidence (deg)", palette=_hue_palette(n, "crest"), ax=ax)
    ax.set_xlim(0, 180)
    ax.set_xlabel("view elevation (deg), azimuth 0 (mirror direction at 180 - incidence)")
    ax.set_ylabel("specular (0-255)")
    ax.set_title(f"Specular reflection on a smooth surface, source J = {d['light'].iloc[0]:g}", loc="left")
    ax.legend(title="incidence", ncol=2, fontsize=8, title_fontsize=8, loc="upper left")
    return fig


# ---------------------------------------------------------------------------
# specular figures


def fig21_specular_truncation(study: pd.DataFrame, aspects=TABLE_ASPECTS, incidence: float = THESIS_INCIDENCE):
    """Fig. 21: specular on the phi = 0 arc against truncation, one panel per table aspect."""
    _theme()
    spec, inc, fig, panels = _arc_panels(study, "specular", "fig21_specular_truncation", 3.8, aspects, incidence)
    for ax, a in panels:
        d = _sel(spec, aspect=a, incidence=inc).copy()
        d["truncation"] = d["truncation"].map(lambda t: f"{t:g}")
        n = d["truncation"].nunique()
        sns.lineplot(data=d, x="elevation", y="rough", hue="truncation", palette=_hue_palette(n), ax=ax, lw=1.2)
        c = lobe_centres(inc, a)
        for name, e in (("back", c["back"]), ("forward", c["forward"])):
            if e is not None:
                ax.axvline(e, color="0.4", ls="--", lw=0.8)
                ax.text(e + 1, ax.get_ylim()[1] * 0.95, f"{name} mirror {e:.1f}°", fontsize=8, va="top")
        ax.axvline(inc, color="orange", ls=":", lw=1)
        ax.set_xlim(0, 180)
        ax.set_xlabel("view elevation (deg), azimuth 0; dotted: zero phase")
        ax.set_ylabel("specular (0-255)")
        ax.set_title(f"aspect {aspect_label(a)}, incidence {inc:g}", loc="left")
        ax.legend(title="truncation", ncol=2, fontsize=7, title_fontsize=8)
    return fig


def _model_panel(ax, lobes, sine, aspect, lobe, m, k, inc, exact=None):
    data = table_data(lobes, aspect, inc)
    if lobe not in data:
        ax.text(0.5, 0.5, f"no {lobe} lobe", ha="center", transform=ax.transAxes)
        return
    t = data.index.to_numpy(float)
    tt = np.linspace(0, 1, 201)
    if k is None:
        k = front_facet_share(aspect, inc) if lobe == "back" else 0.5
    pred = thesis_model_predictions(tt, m, k)
    ax.plot(t, data[lobe], "o", color="k", label="our data (lobe peak)", zorder=5)
    if exact is not None and len(exact):
        ex = exact[(np.abs(exact["aspect"] - aspect) <= ASPECT_TOL) & (exact["lobe"] == lobe)
                   & np.isclose(exact["incidence"], inc)]
        if len(ex):
            ax.plot(ex["truncation"], ex["exact_peak"], "o", mfc="none", mec="#ff7f0e", ms=9, mew=1.4,
                    label="exact peak (polygon clipping)", zorder=6)
    if lobe == "forward":
        ax.plot(tt, pred["square_area"], color="#1f77b4", label="square area  m(1-t)²")
        ax.plot(tt, pred["forward_regressed"], color="#d62728", label="regressed  m(1-sin(tπ/2))")
    else:
        ax.plot(tt, pred["triangle_area"], color="#1f77b4", label=f"triangle area  {k:.3g}m(1-(1-t)²)")
        ax.plot(tt, pred["back_regressed"], color="#d62728", label="regressed  m sin(tπ/2)/2")
    s = sine[(np.abs(sine["aspect"] - aspect) <= ASPECT_TOL) & (sine["lobe"] == lobe)] if len(sine) else sine
    if len(s) == 2 and np.isfinite(s["estimate"]).all():
        A = float(s.loc[s["parameter"] == "A", "estimate"].iloc[0])
        w = float(s.loc[s["parameter"] == "omega", "estimate"].iloc[0])
        y = A * (1 - np.sin(w * tt)) if lobe == "forward" else A * np.sin(w * tt)
        outside = "; ω > π/2: turns down before t = 1, outside the physical range" if w > np.pi / 2 else ""
        ax.plot(tt, y, color="#2ca02c", ls="--", label=f"refit  A={A:.1f}, ω={w:.3f}{outside}")
    ax.set_xlabel("truncation t")
    ax.set_ylabel(f"{lobe} lobe peak (0-255)")
    ax.set_title(f"aspect {aspect_label(aspect)}, incidence {inc:g}", loc="left")
    ax.legend(fontsize=7)


def _models_figure(lobes, sine, lobe, m, k, key, exact, aspects, incidence):
    _theme()
    inc = _incidence(lobes, incidence)
    present = _aspects_present(lobes, aspects)
    if not present:
        return placeholder(figure_title(key), _no_table_aspect(aspects))
    fig, axes = plt.subplots(1, len(present), figsize=(5.6 * len(present), 3.8), squeeze=False, sharey=True)
    for ax, a in zip(axes[0], present):
        _model_panel(ax, lobes, sine, a, lobe, m, k, inc, exact)
    return fig


def fig23_forward_models(lobes: pd.DataFrame, sine: pd.DataFrame, light: float = 127.0, exact=None,
                         aspects=TABLE_ASPECTS, incidence: float = THESIS_INCIDENCE):
    """Fig. 23: forward lobe peak against truncation with the square area and regressed models.

    ``exact``: optional :func:`roughlight.analysis.thesis.exact_lobe_peaks` frame, drawn as open circles.
    """
    return _models_figure(lobes, sine, "forward", light, None, "fig23_forward_models", exact, aspects, incidence)


def fig25_back_models(lobes: pd.DataFrame, sine: pd.DataFrame, light: float = 127.0, k: float | None = None,
                      exact=None, aspects=TABLE_ASPECTS, incidence: float = THESIS_INCIDENCE):
    """Fig. 25: back lobe peak against truncation with the triangle area and regressed models.

    ``k`` (the triangle area's factor) defaults to geometry, :func:`roughlight.surfaces.geometry.front_facet_share`.
    """
    return _models_figure(lobes, sine, "back", light, k, "fig25_back_models", exact, aspects, incidence)


def fig24_reflecting_areas(reflecting_areas: pd.DataFrame):
    """Fig. 24: visible-lit area of the top (forward) and the front facet (back) against truncation.

    Parameters
    ----------
    reflecting_areas : :func:`roughlight.surfaces.geometry.reflecting_areas` frames of the aspects, stacked
    """
    areas = ({a: g.reset_index(drop=True) for a, g in reflecting_areas.groupby("aspect", sort=False)}
             if len(reflecting_areas) else {})
    _theme()
    if not areas:
        return placeholder(figure_title("fig24_reflecting_areas"), "no aspect to draw")
    fig, axes = plt.subplots(1, len(areas), figsize=(5.4 * len(areas), 3.6), squeeze=False, sharey=True)
    for ax, (a, d) in zip(axes[0], areas.items()):
        ax.plot(d["truncation"], d["top"], "o", color="#1f77b4", label="top, seen from the forward mirror")
        ax.plot(d["truncation"], d["square_area"], "-", color="#1f77b4", lw=1, label="(1-t)²")
        ax.plot(d["truncation"], d["front"], "s", color="#d62728", label="front facet, seen from the back mirror")
        ax.plot(d["truncation"], d["triangle_area"], "-", color="#d62728", lw=1,
                label=f"k(1-(1-t)²), k = {d['k'].iloc[0]:.3g}")
        ax.set_xlabel("truncation t")
        ax.set_ylabel("visible lit share of the image")
        ax.set_title(f"aspect {aspect_label(a)}", loc="left")
        ax.legend(fontsize=7)
    return fig


def fig26_specular_aspect(study: pd.DataFrame, truncations=(0.2, 1.0), incidence: float = THESIS_INCIDENCE):
    """Fig. 26: specular on the phi = 0 arc against aspect, at a few truncations."""
    _theme()
    spec = arc(study, "specular")
    inc = _incidence(spec, incidence)
    have = np.unique(spec["truncation"].to_numpy(float))
    ts = [t for t in truncations if np.any(np.isclose(have, t))] or [float(have.max())]
    fig, axes = plt.subplots(1, len(ts), figsize=(6.2 * len(ts), 3.8), squeeze=False, sharey=True)
    for ax, t in zip(axes[0], ts):
        d = _sel(spec, truncation=t, incidence=inc).copy()
        d["aspect"] = d["aspect"].map(aspect_label)
        n = d["aspect"].nunique()
        sns.lineplot(data=d, x="elevation", y="rough", hue="aspect", palette=_hue_palette(n, "rocket_r"), ax=ax,
                     lw=1.1)
        ax.set_xlim(0, 180)
        ax.set_xlabel("view elevation (deg), azimuth 0")
        ax.set_ylabel("specular (0-255)")
        ax.set_title(f"truncation {t:g}, incidence {inc:g}", loc="left")
        ax.legend(title="aspect", ncol=2, fontsize=7, title_fontsize=8)
    return fig


def hemisphere_map_problem(n_azimuths: int, n_elevations: int) -> str | None:
    """Why a sweep's views cannot be mapped over the hemisphere (a triangulation of them), or None."""
    if n_azimuths >= 2 and n_elevations >= 3:
        return None
    return (f"a map of the hemisphere needs views on two half great circles or more, each with three elevations or "
            f"more: this sweep has {n_azimuths} azimuth(s) and {n_elevations} elevation(s) (sweep.azimuth_step, "
            "sweep.elevation_step)")


def _topdown_xy(az, el):
    """Orthographic top-down coordinates of views (x toward the light's azimuth)."""
    A, E = np.meshgrid(np.radians(az), np.radians(el), indexing="ij")
    x = np.cos(E) * np.cos(A)
    y = np.cos(E) * np.sin(A)
    return x, y


def fig19_topdown(study: pd.DataFrame, surfaces=None, max_angle: float = 45.0, incidence: float = THESIS_INCIDENCE):
    """Fig. 19: top-down maps of the specular over the hemisphere, and the back lobe's track.

    The top row maps the specular component seen from every direction
    (orthographic projection of the hemisphere, the light ★ at azimuth 0 on
    the right; the lower half mirrors the measured upper half, as the surface
    is symmetric about the light's plane), each panel on its own scale. White
    dots mark, on every half great circle that passes within ``max_angle``
    of the back (light-facing facet's) mirror direction, the brightest view
    near it. The bottom row gives that maximum and its phase angle against
    the dot's azimuth: a lobe centred on zero phase would keep phase 0.
    """
    _theme()
    grids = {key: (az, el, v) for key, az, el, v in surface_grids(study, "specular")}
    inc = _incidence(study, incidence)
    if surfaces is None:
        surfaces = []
        for t, a in ((0.0, 0.0), (0.5, 1.0), (1.0, 1.0), (1.0, SQRT3_2)):
            hit = [k for k in grids if np.isclose(k[0], t) and abs(k[1] - a) <= ASPECT_TOL and np.isclose(k[2], inc)]
            if t == 0.0 and not hit:
                hit = [k for k in grids if is_plate(k[0], k[1]) and np.isclose(k[2], inc)]
            if hit:
                surfaces.append(hit[0])
    if not surfaces:
        return placeholder(figure_title("fig19_topdown"), "none of the example surfaces is in the study")
    problem = hemisphere_map_problem(*map(len, grids[surfaces[0]][:2]))
    if problem:
        return placeholder(figure_title("fig19_topdown"), problem)
    n = len(surfaces)
    fig = plt.figure(figsize=(3.4 * n + 0.6, 7.2))
    gs = fig.add_gridspec(2, 2 * n, height_ratios=[1.25, 1])
    track_rows = []
    for j, key in enumerate(surfaces):
        az, el, v = grids[key]
        t, a, i = key
        x, y = _topdown_xy(az, el)
        X = np.concatenate([x.ravel(), x.ravel()])
        Y = np.concatenate([y.ravel(), -y.ravel()])
        Z = np.concatenate([v.ravel(), v.ravel()])
        ok = np.isfinite(Z)
        vmax = max(float(np.nanmax(Z)), 1.0)
        ax = fig.add_subplot(gs[0, 2 * j:2 * j + 2])
        ax.tricontourf(X[ok], Y[ok], Z[ok], levels=np.linspace(0, vmax, 16), cmap="magma")
        ax.set_aspect("equal")
        ax.set_xlim(-1.05, 1.05)
        ax.set_ylim(-1.05, 1.05)
        ax.add_patch(plt.Circle((0, 0), 1, fill=False, color="0.5", lw=0.6))
        ax.plot([math.cos(math.radians(i))], [0], marker="*", color="gold", ms=11, mec="k", mew=0.5, ls="none")
        ax.set_title(f"t {t:g}, aspect {aspect_label(a)} (max {vmax:.0f})", loc="left", fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
        label = f"t {t:g}, a {aspect_label(a)}"
        dirs = lobe_directions(t, a, i)
        if "back" in dirs and not is_plate(t, a):
            A, E = np.meshgrid(az, el, indexing="ij")
            V = view_direction(E, A)
            near = (V @ dirs["back"]) >= math.cos(math.radians(max_angle))
            for k_ in range(len(az)):
                sel = near[k_] & np.isfinite(v[k_])
                if not sel.any():
                    continue
                jj = np.flatnonzero(sel)[int(np.argmax(v[k_, sel]))]
                if v[k_, jj] < MIN_LOBE_PEAK:
                    continue
                d = V[k_, jj]
                track_rows.append({"surface": label, "azimuth": math.degrees(math.atan2(d[1], d[0])),
                                   "value": float(v[k_, jj]), "phase": float(phase_angle(i, el[jj], az[k_])),
                                   "x": d[0], "y": d[1]})
            tr = [r for r in track_rows if r["surface"] == label]
            if tr:
                ax.plot([r["x"] for r in tr], [r["y"] for r in tr], ".", color="white", ms=3.5)
                ax.plot([r["x"] for r in tr], [-r["y"] for r in tr], ".", color="white", ms=3.5)
    ax1 = fig.add_subplot(gs[1, :n])
    ax2 = fig.add_subplot(gs[1, n:])
    if track_rows:
        tr = pd.DataFrame(track_rows)
        sns.lineplot(data=tr, x="azimuth", y="value", hue="surface", marker="o", ax=ax1, ms=4)
        sns.lineplot(data=tr, x="azimuth", y="phase", hue="surface", marker="o", ax=ax2, ms=4, legend=False)
        ax1.set_xlabel("azimuth of the brightest view near the back mirror direction (deg)")
        ax2.set_xlabel("azimuth of the brightest view near the back mirror direction (deg)")
        ax1.set_ylabel("back-lobe maximum on the arc (0-255)")
        ax2.set_ylabel("phase angle at that maximum (deg)")
        ax1.legend(fontsize=7)
    else:
        for ax in (ax1, ax2):
            ax.text(0.5, 0.5, "no back lobe on these surfaces", ha="center", transform=ax.transAxes)
    fig.suptitle(f"Specular from above (light ★ at azimuth 0, elevation {inc:g}) and the back lobe's track",
                 y=0.995)
    fig.tight_layout()
    return fig


# ---------------------------------------------------------------------------
# diffuse figures


def fig27_diffuse_plate(study: pd.DataFrame, incidence: float = THESIS_INCIDENCE):
    """Fig. 27: diffuse of the smooth surface (plate and control) against view elevation."""
    _theme()
    diff = arc(study, "diffuse")
    inc = _incidence(diff, incidence)
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
    ax.legend(fontsize=8, loc="lower center")
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


def fig28_diffuse_truncation(study: pd.DataFrame, diffuse_parts: pd.DataFrame, aspects=TABLE_ASPECTS,
                             incidence: float = THESIS_INCIDENCE):
    """Fig. 28: diffuse on the phi = 0 arc against truncation, with the fitted three-part model."""
    _theme()
    parts = diffuse_parts
    diff, inc, fig, panels = _arc_panels(study, "diffuse", "fig28_diffuse_truncation", 3.9, aspects, incidence)
    for ax, a in panels:
        d = _sel(diff, aspect=a, incidence=inc)
        d = d[d["coverage"] > 0]
        ts = np.unique(d["truncation"].to_numpy(float))
        pal = _hue_palette(len(ts))
        ee = np.linspace(0.5, 179.5, 360)
        for color, t in zip(pal, ts):
            dt = d[np.isclose(d["truncation"], t)]
            ax.plot(dt["elevation"], dt["rough"], color=color, lw=1.1, label=f"{t:g}")
            pr = _sel(parts, aspect=a, truncation=t, incidence=inc)
            if len(pr):
                y = _three_part_curve(pr.iloc[0], ee)
                if y is not None:
                    ax.plot(ee, y, color=color, lw=0.8, ls="--")
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
        ax.legend(title="truncation", ncol=2, fontsize=7, title_fontsize=8, loc="upper right")
    return fig


def fig29_diffuse_aspect(study: pd.DataFrame, truncation: float = 1.0, incidence: float = THESIS_INCIDENCE):
    """Fig. 29: diffuse on the phi = 0 arc against aspect (full pyramids by default)."""
    _theme()
    diff = arc(study, "diffuse")
    inc = _incidence(diff, incidence)
    have = np.unique(diff["truncation"].to_numpy(float))
    t = truncation if np.any(np.isclose(have, truncation)) else float(have.max())
    d = _sel(diff, truncation=t, incidence=inc)
    d = d[d["coverage"] > 0].copy()
    aspects = np.unique(d["aspect"].to_numpy(float))
    fig, ax = plt.subplots(figsize=(7.5, 3.9))
    for color, a in zip(_hue_palette(len(aspects), "rocket_r"), aspects):
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
    ax.legend(title="aspect", ncol=2, fontsize=7, title_fontsize=8, loc="upper right")
    return fig


# ---------------------------------------------------------------------------
# beyond the thesis


def fig_lobe_geometry(lobes: pd.DataFrame, incidence: float = THESIS_INCIDENCE):
    """Measured lobe centres against the geometric mirror directions, and lobe widths."""
    _theme()
    d = lobes[np.isfinite(lobes["peak_elevation"]) & ~lobes["plate"]].copy()
    if d.empty:
        return placeholder(figure_title("lobe_geometry"), "no lobes outside the plate")
    fig, axes = plt.subplots(1, 3, figsize=(15, 3.9))
    inc = _incidence(d, incidence)
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
    ax.legend(fontsize=7)
    ax = axes[1]
    sns.scatterplot(data=d[d["peak"] >= 4], x="truncation", y="fwhm", hue="lobe", style="lobe", ax=ax, s=22)
    ax.set_ylabel("FWHM on the arc (deg); peaks >= 4 only")
    ax.set_title("Lobe widths: truncation changes height, not width", loc="left")
    ax = axes[2]
    sns.scatterplot(data=d, x="aspect", y="offset", hue="lobe", style="lobe", ax=ax, s=22)
    ax.axhline(0, color="k", lw=0.8)
    ax.set_ylabel("peak minus predicted (deg)")
    ax.set_title("Offset from the mirror direction", loc="left")
    return fig


def fig_diffuse_parts(diffuse_parts: pd.DataFrame, incidence: float = THESIS_INCIDENCE):
    """Heatmaps over (truncation, aspect) of the three-part diffuse model's parameters."""
    parts = diffuse_parts
    _theme()
    d = parts[np.isfinite(parts["rate"])]
    if d.empty:
        return placeholder(figure_title("diffuse_parts"), "no surface with a fitted decay (all plates?)")
    inc = _incidence(d, incidence)
    d = d[np.isclose(d["incidence"], inc)].copy()
    d["aspect"] = d["aspect"].map(lambda a: round(a, 3))
    fig, axes = plt.subplots(1, 4, figsize=(17, 3.9))
    for ax, (col, label, fmt) in zip(axes, (("level1", "level of part 1 (0-255)", ".0f"),
                                            ("level3", "level of part 3 (0-255)", ".0f"),
                                            ("decay_length", "decay length 1/k (deg)", ".0f"),
                                            ("rmse", "RMSE of the model (0-255)", ".1f"))):
        p = d.pivot_table(index="aspect", columns="truncation", values=col).sort_index(ascending=False)
        _heatmap(ax, p, cmap="viridis", annot=p.size <= 150, fmt=fmt)
        ax.set_title(label, loc="left", fontsize=9)
    return fig


def fig_glm_diagnostics(glm_diagnostics: pd.DataFrame, glm_summary: pd.DataFrame):
    """Residuals against fitted values and influence (leverage, Cook's distance) of each grid GLM."""
    diag, summary = glm_diagnostics, glm_summary
    _theme()
    if diag is None or diag.empty:
        return placeholder(figure_title("glm_diagnostics"), "no GLM was fitted (see the messages in the report)")
    responses = list(dict.fromkeys(diag["response"]))
    fig, axes = plt.subplots(2, len(responses), figsize=(4.8 * len(responses), 7), squeeze=False)
    for j, r in enumerate(responses):
        d = diag[diag["response"] == r].copy()
        d["aspect "] = d["aspect"].map(lambda a: round(a, 2))
        ax = axes[0, j]
        sns.scatterplot(data=d, x="fitted", y="residual", hue="truncation", palette="viridis", ax=ax, s=18,
                        legend=j == len(responses) - 1)
        ax.axhline(0, color="k", lw=0.8)
        srow = summary[summary["response"] == r]
        sub = ""
        if len(srow):
            s = srow.iloc[0]
            sub = (f"\nconverged {bool(s['converged'])}, κ(scaled) {s['condition_scaled']:.1f}, "
                   f"pseudo-R² {s['pseudo_r2']:.3f}")
        ax.set_title(f"{r}{sub}", loc="left", fontsize=9)
        ax.set_ylabel("residual (0-255)")
        ax = axes[1, j]
        n, p = len(d), max(1, len(srow.iloc[0]["terms"].split(" + ")) + 1) if len(srow) else 2
        size = 10 + 400 * d["cooks_distance"] / max(d["cooks_distance"].max(), 1e-12)
        ax.scatter(d["leverage"], d["pearson_residual"], s=size,
                   c=d["aspect"], cmap="rocket_r", alpha=0.8, edgecolor="k", linewidth=0.3)
        ax.axvline(2 * p / max(n, 1), color="0.4", ls=":", lw=1)
        ax.axhline(0, color="k", lw=0.8)
        top = d.nlargest(3, "cooks_distance")
        for _, row in top.iterrows():
            ax.annotate(f"t{row['truncation']:g},a{aspect_label(row['aspect'])}",
                        (row["leverage"], row["pearson_residual"]), fontsize=7)
        ax.set_xlabel("leverage (hat); dotted 2p/n")
        ax.set_ylabel("Pearson residual")
        ax.set_title("influence: size ∝ Cook's distance, colour = aspect", loc="left", fontsize=9)
    fig.tight_layout()
    return fig


def fig_model_fits(model_fits: pd.DataFrame, incidence: float = THESIS_INCIDENCE):
    """Heatmaps of each analytic model's RMSE over (truncation, aspect)."""
    fits = model_fits
    _theme()
    if fits is None or fits.empty:
        return placeholder(figure_title("model_fits"), "no model fits")
    inc = _incidence(fits, incidence)
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
        _heatmap(ax, p, cmap="mako_r", vmin=0, vmax=vmax[comp_of[col]] or 1)
        ax.set_title(f"{title}\nmedian RMSE {np.nanmedian(p.to_numpy()):.2f}", loc="left", fontsize=8)
    for ax in list(axes.flat)[len(panels):]:
        ax.axis("off")
    fig.tight_layout()
    return fig


def fig_hapke(study: pd.DataFrame, model_fits: pd.DataFrame, hapke_max_phase: float = 60.0, surfaces=None,
              incidence: float = THESIS_INCIDENCE):
    """The total component against phase near opposition, with Hapke's fitted curve, for a few surfaces."""
    fits, max_phase = model_fits, hapke_max_phase
    _theme()
    inc = _incidence(study, incidence)
    if surfaces is None:
        surfaces = []
        for t, a in ((0.5, 1.0), (1.0, 1.0), (1.0, SQRT3_2), (1.0, 0.5)):
            r = fits[np.isclose(fits["truncation"], t) & (np.abs(fits["aspect"] - a) <= ASPECT_TOL)
                     & np.isclose(fits["incidence"], inc)]
            if len(r):
                surfaces.append((float(r["truncation"].iloc[0]), float(r["aspect"].iloc[0]), inc))
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
        g = np.linspace(0, max_phase, 200)
        if np.isfinite(r["hapke_c"]):
            bg = r["hapke_c"] + r["hapke_d"] * g
            ax.plot(g, bg, color="#1f77b4", ls="--", lw=1, label="background term of the Hapke fit")
            if np.isfinite(r["hapke_h"]):
                y = bg + r["hapke_S"] / (1 + np.tan(np.radians(g) / 2) / r["hapke_h"])
                ax.plot(g, y, color="#d62728", label=f"+ Hapke B(g): B0 {r['hapke_B0']:.3g}, h {r['hapke_h']:.3g}")
        ax.set_xlabel("phase angle g (deg)")
        ax.set_ylabel("total (0-255)")
        ax.set_title(f"t {t:g}, aspect {aspect_label(a)}: RMSE {r['rmse_hapke']:.1f} (a background-only fit, "
                     f"not drawn: {r['rmse_constant_near_opposition']:.1f})", loc="left", fontsize=8)
        ax.legend(fontsize=7)
    return fig


def fig_timings(render_timings: pd.DataFrame):
    """Render seconds per sweep over (truncation, aspect), one panel per incidence."""
    per_sweep = render_timings
    _theme()
    if per_sweep is None or per_sweep.empty:
        return placeholder(figure_title("timings"), "no timings")
    d = per_sweep.copy()
    d["aspect"] = d["aspect"].map(lambda a: round(a, 3))
    incs = sorted(d["incidence"].unique())
    fig, axes = plt.subplots(1, len(incs), figsize=(6 * len(incs), 4.2), squeeze=False)
    for ax, inc in zip(axes[0], incs):
        p = d[d["incidence"] == inc].pivot_table(index="aspect", columns="truncation", values="seconds")
        _heatmap(ax, p.sort_index(ascending=False), cmap="rocket_r", annot=p.size <= 150, fmt=".1f",
                 label="seconds per sweep")
        ax.set_title(f"incidence {inc:g}: render wall time per sweep", loc="left", fontsize=9)
    return fig


# ---------------------------------------------------------------------------
# pictures of the surfaces (the thesis's Figs. 9, 10, 13)

def fig_pictures(stem: str, pictures):
    """A row of rendered pictures with their labels (Figs. 9, 10, 13)."""
    _theme()
    from ..render.pictures import PICTURE_SETS

    title = PICTURE_SETS[stem][0] if stem in PICTURE_SETS else stem
    n = len(pictures)
    if n == 0:
        return placeholder(title, "no pictures")
    fig, axes = plt.subplots(1, n, figsize=(3.2 * n, 2.9), squeeze=False)
    for ax, (label, img) in zip(axes[0], pictures):
        ax.imshow(img)
        ax.set_title(label, fontsize=9)
        ax.axis("off")
    fig.suptitle(title, fontsize=10, y=1.02)
    return fig


# ---------------------------------------------------------------------------
# speed against accuracy (the benchmark) and where methods fail (the stability scans)


def plot_speed_accuracy(table, path, floor: float = 1e-3) -> None:
    """Error against time per view, log scales: the mean error (top row) and the worst view (bottom row), one
    column per component, Pareto front of the mean error marked.

    The reference's error is zero (up to floating point); it is drawn at
    ``floor`` so that it shows on the log scale.
    """
    from ..render.sampling import RenderSettings

    data = table[table["component"].isin(["diffuse", "specular"])].copy()
    data["ms per view"] = data["ms_per_view"]
    sns.set_theme(style="whitegrid")
    components = list(dict.fromkeys(data["component"]))
    fig, axes = plt.subplots(2, len(components), figsize=(5.2 * len(components), 8.4), squeeze=False)
    rows = (("mae", "mean abs error (0-255)", 0.5), ("max_error", "worst view, abs error (0-255)", 1.0))
    for r, (column, label, line_at) in enumerate(rows):
        for ax, component in zip(axes[r], components):
            sub = data[data["component"] == component].copy()
            sub[label] = sub[column].clip(lower=floor)
            sns.scatterplot(data=sub, x="ms per view", y=label, hue="method", style="sampling", s=70, ax=ax,
                            legend=(r == 0 and component == components[-1]))
            if r == 0:
                front = sub[sub["pareto"]].sort_values("ms per view")
                ax.plot(front["ms per view"], front[label], color="black", lw=1, ls="--", label="Pareto front")
            for _, row in sub.iterrows():
                default_bias = np.isclose(row["shadow_bias"], RenderSettings().shadow_bias)
                labelled = row["sampling"] in ("lattice", "adaptive") and row["shadow_map_size"] == 512
                if row["method"] == "fast" and labelled and default_bias:
                    ax.annotate(f"P={row['pixels_per_period']}", (row["ms per view"], row[label]),
                                fontsize=7, xytext=(3, 3), textcoords="offset points")
            ax.axhline(line_at, color="grey", lw=0.8, ls=":")
            ax.set(xscale="log", yscale="log", title=f"{component}: {'mean error' if r == 0 else 'worst view'}")
    if axes[0, -1].get_legend() is not None:
        sns.move_legend(axes[0, -1], "upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7)
    fig.suptitle("Speed against accuracy: error against the exact reference vs time per view "
                 "(dotted: the 0.5 tolerance of the mean, one 8-bit level at the worst view)", y=1.01)
    fig.tight_layout()
    save_figure(fig, path, dpi=120)


def plot_renderer_validation(validation, smoothness, path) -> None:
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
    if len(smoothness):
        sns.lineplot(data=smoothness, x="truncation", y="largest_deviation", hue="figure", style="aspect",
                     marker="o", ax=axes[1])
    else:
        axes[1].text(0.5, 0.5, "no table aspect in the study", ha="center", transform=axes[1].transAxes)
    axes[1].axhline(1.0, color="grey", lw=0.8, ls=":")
    axes[1].set(ylabel="largest deviation from the exact curve (0-255)",
                title="the arc curves of Figs. 21 (specular) and 28 (diffuse)")
    fig.suptitle("The default renderer against the exact reference (dotted: one 8-bit level)", y=1.02)
    fig.tight_layout()
    save_figure(fig, path, dpi=120)


def plot_stability(frames, path, pictures=None) -> None:
    """Worst-component MAE against pixels per period, jitter spread, elevation, incidence
    by shadow bias, shadow-map size and shininess; the clipped lobes; averaged normals
    by component, and ``pictures`` ({shading model: (H, W, 3) uint8}, from
    :func:`roughlight.measurements.stability.normals_pictures`) when given."""
    from ..measurements.stability import TOLERANCE

    frame = frames if isinstance(frames, pd.DataFrame) else pd.concat(list(frames), ignore_index=True)
    sns.set_theme(style="whitegrid")
    fig, axes = plt.subplots(3, 4, figsize=(20, 13.5))
    floor = 1e-2

    def worst(experiment, by=("method", "setting", "x")):
        d = frame[(frame["experiment"] == experiment) & (frame["metric"] == "mae")]
        d = d.groupby(list(by), as_index=False)["value"].max()
        d["value"] = d["value"].clip(lower=floor)
        return d

    def log_panel(ax, data, hue, xlabel, ylabel, title):
        sns.lineplot(data=data, x="x", y="value", hue=hue, marker="o", ax=ax)
        ax.set(xscale="log", yscale="log", xlabel=xlabel, ylabel=ylabel, title=title)
        ax.axhline(TOLERANCE, ls=":", c="k", lw=1)

    mae = "worst-component MAE (0-255)"
    log_panel(axes[0, 0], worst("pixels"), "method", "pixels per period", mae, "pixelation / aliasing")
    d = frame[(frame["experiment"] == "pixels") & (frame["metric"] == "jitter_sd")].copy()
    d["value"] = d["value"].clip(lower=floor)
    log_panel(axes[0, 1], d, "method", "pixels per period", "SD over sub-pixel jitter (0-255)",
              "flashing lines: jitter spread of total")
    ax = axes[0, 2]
    log_panel(ax, worst("elevation"), "method", "view elevation above horizon (deg, e and 180-e)", mae,
              "grazing views")
    d = frame[(frame["experiment"] == "elevation") & (frame["metric"] == "coverage")]
    ax2 = ax.twinx()
    sns.lineplot(data=d, x="x", y="value", hue="method", ls="--", legend=False, ax=ax2)
    ax2.set(ylabel="coverage (dashed)", ylim=(0, 1.05))
    ax2.grid(False)
    log_panel(axes[0, 3], worst("shadow_bias"), "setting", "incidence (deg)", mae,
              "shadow acne / peter-panning (fast by bias; naive)")
    log_panel(axes[1, 0], worst("shadow_map"), "setting", "fast shadow map (texels per period)", mae,
              "shadow-map resolution by incidence")
    log_panel(axes[1, 1], worst("shininess"), "method", "shininess", mae, "specular exponent")
    ax = axes[1, 2]
    d = frame[(frame["experiment"] == "clipping") & (frame["metric"] == "curve")].copy()
    d["surface"] = d["setting"].str.split(" ").str[0]
    d["source"] = d["setting"].str.split(" ").str[1]
    sns.lineplot(data=d, x="x", y="value", hue="surface", style="source", ax=ax)
    ax.axhline(255, c="r", lw=1)
    ax.set(xlabel="view elevation at azimuth 0 (deg)", ylabel="total (0-255)", title="clipping at 255 (Fig. 17)")
    ax = axes[1, 3]
    d = frame[(frame["experiment"] == "clipping") & frame["metric"].isin(["peak_shift", "centre_shift"])].copy()
    sns.barplot(data=d, y="setting", x="value", hue="metric", orient="h", ax=ax)
    ax.set(xlabel="lobe shift, source 127 -> 255 (deg elevation)", ylabel="", title="how far clipping moves the lobes")
    ax = axes[2, 0]
    d = frame[(frame["experiment"] == "normals") & frame["metric"].isin(["mae", "mae_vs_flat"])].copy()
    d = d[~((d["setting"] == "flat") & (d["metric"] == "mae_vs_flat"))]  # zero by construction
    d["value"] = d["value"].clip(lower=floor)
    d["what"] = d["setting"] + np.where(d["metric"] == "mae", " vs reference", " vs flat")
    if len(d):
        sns.barplot(data=d, x="component", y="value", hue="what", ax=ax)
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2, title=None)
    ax.set(yscale="log", ylabel="MAE (0-255)", title="averaged vertex normals (naive)")
    ax.axhline(TOLERANCE, ls=":", c="k", lw=1)
    for ax, (model, picture) in zip(axes[2, 1:], (pictures or {}).items()):
        ax.imshow(picture)
        ax.set(title=f"{model} shading", xticks=[], yticks=[])
        ax.grid(False)
    for ax in axes[2, 1 + len(pictures or {}):]:
        ax.axis("off")
    fig.tight_layout()
    save_figure(fig, path, dpi=80, bbox_inches=None)


def plot_implicit(validation, frames, path, pictures=None) -> None:
    """The implicit rough surface: per-surface MAE by method (left) and frame time against field size (right);
    below, when given, ``pictures`` (method -> 2-D uint8 image) side by side."""
    sns.set_theme(style="whitegrid")
    pictures = pictures or {}
    if pictures:
        fig = plt.figure(figsize=(11, 8.4))
        top = fig.add_gridspec(2, 1, height_ratios=[1, 1.05])
        axes = top[0].subgridspec(1, 2).subplots()
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
    axes[0].tick_params(axis="x", labelrotation=15)
    f = frames.groupby(["field", "method"], as_index=False)["frame_ms"].mean()
    sns.lineplot(data=f, x="field", y="frame_ms", hue="method", marker="o", ax=axes[1])
    axes[1].set(xscale="log", yscale="log", xlabel="field side N (periods)", ylabel="frame time (ms)",
                title="N x N field: explicit mesh against one implicit quad")
    fig.tight_layout()
    save_figure(fig, path, dpi=120)


def plot_implicit_maps(maps, path, component: str = "total") -> None:
    """Hemisphere maps (top-down, light on the right) of the exact reference and of each implicit model's
    difference from it, one row per surface (:func:`roughlight.measurements.implicit_surface.hemisphere_maps`)."""
    _theme()
    surfaces = maps[["truncation", "aspect", "incidence"]].drop_duplicates().to_numpy()
    columns = ("reference", "implicit_exact", "implicit_correction")
    fig, axes = plt.subplots(len(surfaces), 3, figsize=(11, 3.6 * len(surfaces)), squeeze=False)
    for row, (t, a, i) in zip(axes, surfaces):
        sel = maps[(maps.truncation == t) & (maps.aspect == a) & (maps.incidence == i)]
        ref = sel[sel.method == "reference"].sort_values(["azimuth", "elevation"])
        for ax, method in zip(row, columns):
            cur = sel[sel.method == method].sort_values(["azimuth", "elevation"])
            value = cur[component].to_numpy() - (0 if method == "reference" else ref[component].to_numpy())
            e, phi = np.radians(cur["elevation"].to_numpy()), np.radians(cur["azimuth"].to_numpy())
            x, y = np.cos(e) * np.cos(phi), np.cos(e) * np.sin(phi)
            X, Y, Z = np.concatenate([x, x]), np.concatenate([y, -y]), np.concatenate([value, value])
            if method == "reference":
                levels, cmap = np.linspace(0, max(float(Z.max()), 1.0), 16), "magma"
                title = f"t {t:g}, aspect {aspect_label(a)}, i {i:g}: exact {component}"
            else:
                span = max(float(np.abs(Z).max()), 0.05)
                levels, cmap = np.linspace(-span, span, 17), "RdBu_r"
                title = f"{method.replace('_', ' ')} − exact (max |Δ| {span:.2f})"
            mappable = ax.tricontourf(X, Y, Z, levels=levels, cmap=cmap)
            fig.colorbar(mappable, ax=ax, shrink=0.8)
            ax.add_patch(plt.Circle((0, 0), 1, fill=False, color="0.5", lw=0.6))
            ax.plot([math.cos(math.radians(i))], [0], marker="*", color="gold", ms=11, mec="k", mew=0.5)
            ax.set(aspect="equal", xlim=(-1.05, 1.05), ylim=(-1.05, 1.05), xticks=[], yticks=[])
            ax.set_title(title, loc="left", fontsize=8)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)


#: The statistics the random-roughness chart shows, in reading order (see :data:`roughlight.analysis.ensembles.STATISTICS`).
RANDOM_CHART_STATISTICS = ("back_peak", "back_width", "back_rectangularity", "back_phase_shift",
                           "forward_peak", "diffuse_level", "diffuse_level1", "diffuse_level3")
#: Marker colour of each surface kind.
KIND_COLOURS = {"pyramids": "k", "random_pyramids": "tab:orange", "random_heightfield": "tab:blue"}


def plot_random_ensembles(summary: pd.DataFrame, path) -> None:
    """One panel per statistic: the regular surface (black cross) and each random kind's ensemble mean with
    its 95% interval over seeds, at every random grid point (:func:`roughlight.analysis.ensembles.ensemble_summary`)."""
    from ..analysis.ensembles import ELLIPSE_FILL

    _theme()
    names = [s for s in RANDOM_CHART_STATISTICS if s in set(summary["statistic"])]
    ncol = 4
    nrow = max(1, math.ceil(len(names) / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.4 * ncol, 3.0 * nrow), squeeze=False)
    points = summary[["truncation", "aspect", "incidence"]].drop_duplicates().sort_values(
        ["incidence", "aspect", "truncation"]).to_numpy()
    labels = [f"t {t:g}\na {aspect_label(a)}\ni {i:g}" for t, a, i in points]
    kinds = [k for k in KIND_COLOURS if k in set(summary["kind"])]
    for ax, name in zip(axes.ravel(), names):
        sel = summary[summary["statistic"] == name]
        for p, (t, a, i) in enumerate(points):
            at = sel[(sel.truncation == t) & (sel.aspect == a) & (sel.incidence == i)]
            if at.empty:
                continue
            ax.plot(p, at["regular"].iloc[0], marker="x", color="k", ms=8, ls="none",
                    label="regular pyramids" if p == 0 else None)
            for k, kind in enumerate(kinds):
                row = at[at["kind"] == kind]
                if row.empty:
                    continue
                r = row.iloc[0]
                x = p + 0.18 * (k + 1)
                ax.errorbar(x, r["mean"], yerr=[[r["mean"] - r["ci_low"]], [r["ci_high"] - r["mean"]]],
                            fmt="o", color=KIND_COLOURS[kind], ms=5, capsize=3,
                            label=f"{kind.replace('_', ' ')} (mean, 95% CI)" if p == 0 else None)
        if name == "back_rectangularity":
            ax.axhline(ELLIPSE_FILL, color="0.5", ls=":", lw=1)
            ax.axhline(1.0, color="0.5", ls="--", lw=1)
        unit = sel["unit"].iloc[0] if len(sel) else ""
        ax.set_title(f"{name.replace('_', ' ')} ({unit})", fontsize=9)
        ax.set_xticks(range(len(points)))
        ax.set_xticklabels(labels, fontsize=7)
    for ax in axes.ravel()[len(names):]:
        ax.axis("off")
    handles, texts = axes.ravel()[0].get_legend_handles_labels()
    fig.legend(handles, texts, loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    save_figure(fig, path)


def plot_random_maps(study: pd.DataFrame, path, component: str = "specular", seed: int = 1) -> None:
    """Top-down hemisphere maps (light on the right, star) of the regular surface and of one seed of each random
    kind, one row per random grid point: the thesis's Fig. 19 view of the lobes' shapes."""
    from ..analysis.ensembles import random_points

    _theme()
    data = random_points(study)
    data = data[data["component"].astype(str) == component]
    problem = hemisphere_map_problem(data["azimuth"].nunique(), data["elevation"].nunique())
    if problem:
        save_figure(placeholder("Random roughness: maps of the hemisphere", problem), path)
        return
    kinds = [k for k in KIND_COLOURS if k in set(data["kind"].astype(str))]
    points = data[["truncation", "aspect", "incidence"]].drop_duplicates().sort_values(
        ["incidence", "aspect", "truncation"]).to_numpy()
    fig, axes = plt.subplots(max(1, len(points)), len(kinds), figsize=(3.6 * len(kinds), 3.4 * max(1, len(points))),
                             squeeze=False)
    for row, (t, a, i) in zip(axes, points):
        at = data[(data.truncation == t) & (data.aspect == a) & (data.incidence == i)]
        for ax, kind in zip(row, kinds):
            sel = at[at["kind"].astype(str) == kind]
            sel = sel[sel["seed"] == (0 if kind == "pyramids" else sel["seed"].min())]
            e, phi = np.radians(sel["elevation"].to_numpy(float)), np.radians(sel["azimuth"].to_numpy(float))
            x, y = np.cos(e) * np.cos(phi), np.cos(e) * np.sin(phi)
            X, Y = np.concatenate([x, x]), np.concatenate([y, -y])
            Z = np.concatenate([sel["rough"].to_numpy(float)] * 2)
            top = max(float(Z.max()), 1.0)  # each map on its own scale: the shapes are compared, not the levels
            mappable = ax.tricontourf(X, Y, Z, levels=np.linspace(0, top, 16), cmap="magma")
            fig.colorbar(mappable, ax=ax, shrink=0.7)
            ax.add_patch(plt.Circle((0, 0), 1, fill=False, color="0.5", lw=0.6))
            ax.plot([math.cos(math.radians(i))], [0], marker="*", color="gold", ms=11, mec="k", mew=0.5)
            ax.set(aspect="equal", xlim=(-1.05, 1.05), ylim=(-1.05, 1.05), xticks=[], yticks=[])
            seed_text = "" if kind == "pyramids" else f", seed {int(sel['seed'].iloc[0])}"
            ax.set_title(f"{kind.replace('_', ' ')}{seed_text}\nt {t:g}, a {aspect_label(a)}, i {i:g}", fontsize=8,
                         loc="left")
    fig.suptitle(f"{component} (0-255), each map on its own scale", fontsize=9)
    fig.tight_layout()
    save_figure(fig, path)


def plot_random_tiles(summary: pd.DataFrame, accuracy: pd.DataFrame, pictures, path) -> None:
    """The random tiles' benchmark on one page: each followed statistic against tile size (ensemble mean and
    95% interval over seeds, the regular surface dashed), the fast renderer's views per second against tile size,
    and pictures of each kind as rendered at the thesis's telling views (kinds by rows)."""
    _theme()
    names = list(dict.fromkeys(summary["statistic"]))
    ncol = 3
    n_pictures = len(pictures)
    picture_rows = math.ceil(n_pictures / ncol) if n_pictures else 0
    chart_rows = math.ceil((len(names) + 1) / ncol)
    fig = plt.figure(figsize=(4.0 * ncol, 3.0 * (chart_rows + picture_rows)))
    grid = fig.add_gridspec(chart_rows + picture_rows, ncol)
    for k, name in enumerate(names + ["views_per_second"]):
        ax = fig.add_subplot(grid[k // ncol, k % ncol])
        for kind, g in summary.groupby("kind"):
            g = g[g["statistic"] == (name if name != "views_per_second" else names[0])].sort_values("cells")
            y = g["views_per_second"] if name == "views_per_second" else g["mean"]
            err = None if name == "views_per_second" else g["ci_half_width"]
            ax.errorbar(g["cells"], y, yerr=err, marker="o", capsize=3, color=KIND_COLOURS.get(kind),
                        label=kind.replace("_", " "))
            if name != "views_per_second" and np.isfinite(g["regular"].iloc[0]):
                ax.axhline(g["regular"].iloc[0], color="k", ls="--", lw=1)
        if name == "views_per_second":
            regular = summary["regular_views_per_second"].dropna()
            if len(regular):
                ax.axhline(float(regular.iloc[0]), color="k", ls="--", lw=1, label="regular surface")
            ax.set_yscale("log")
        ax.set_title(name.replace("_", " ") + (" (fast renderer)" if name == "views_per_second" else ""), fontsize=9)
        ax.set_xlabel("tile size (cells a side)", fontsize=8)
        if k == 0:
            ax.legend(fontsize=7)
    for k, (label, image) in enumerate(pictures):
        ax = fig.add_subplot(grid[chart_rows + k // ncol, k % ncol])
        ax.imshow(image)
        ax.set_title(label, fontsize=8)
        ax.axis("off")
    fig.tight_layout()
    save_figure(fig, path)
