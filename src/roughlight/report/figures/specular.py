"""The thesis's specular figures (Figs. 17-26): the plate's lobe, the lobes against truncation and aspect, the
thesis's area models of the lobe peaks, and the top-down maps of Fig. 19."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import seaborn as sns

from ...analysis.areas import front_facet_share
from ...analysis.grids import arc, surface_value_grids
from ...analysis.lobes import MIN_LOBE_PEAK, lobe_directions
from ...analysis.thesis import TABLE_ASPECTS, THESIS_INCIDENCE, table_data, thesis_model_predictions
from ...render.shading import phase_angle, view_direction
from ...study.selection import ASPECT_TOL
from ...surfaces.geometry import lobe_centres
from ...surfaces.surface import SQRT3_2, aspect_label, is_plate
from ..registry import title as figure_title
from .common import (
    arc_panels,
    aspects_present,
    hemisphere_frame,
    hemisphere_map,
    hemisphere_map_problem,
    hue_palette,
    legend_below,
    legend_beside,
    no_table_aspect,
    panels_legend,
    pick_incidence,
    placeholder,
    rendered_values,
    select,
    theme,
)

__all__ = ["fig17_clipping", "fig19_topdown", "fig20_plate_incidence", "fig21_specular_truncation",
           "fig23_forward_models", "fig24_reflecting_areas", "fig25_back_models", "fig26_specular_aspect"]


def fig17_clipping(plates: pd.DataFrame):
    """Fig. 17: the plate's specular and total at source 127 and 255 (phi = 0 arc)."""
    theme()
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
    theme()
    d = plates[plates["component"] == "specular"].copy()
    if d.empty:
        return placeholder(figure_title("fig20_plate_incidence"), "no plate sweeps")
    d["incidence (deg)"] = d["incidence"].map(lambda i: f"{i:g}")
    n = d["incidence (deg)"].nunique()
    fig, ax = plt.subplots(figsize=(7.5, 3.6))
    sns.lineplot(data=d, x="elevation", y="value", hue="incidence (deg)", palette=hue_palette(n, "crest"), ax=ax)
    ax.set_xlim(0, 180)
    ax.set_xlabel("view elevation (deg), azimuth 0 (mirror direction at 180 - incidence)")
    ax.set_ylabel("specular (0-255)")
    ax.set_title(f"Specular reflection on a smooth surface, source J = {d['light'].iloc[0]:g}", loc="left")
    legend_beside(ax, title="incidence", fontsize=8, title_fontsize=8)
    return fig


def fig21_specular_truncation(study: pd.DataFrame, aspects=TABLE_ASPECTS, incidence: float = THESIS_INCIDENCE):
    """Fig. 21: specular on the phi = 0 arc against truncation, one panel per table aspect."""
    theme()
    spec, inc, fig, panels = arc_panels(study, "specular", "fig21_specular_truncation", 3.8, aspects, incidence)
    for ax, a in panels:
        d = select(spec, aspect=a, incidence=inc).copy()
        d["truncation"] = d["truncation"].map(lambda t: f"{t:g}")
        n = d["truncation"].nunique()
        sns.lineplot(data=d, x="elevation", y="rough", hue="truncation", palette=hue_palette(n), ax=ax, lw=1.2)
        _mirror_marks(ax, lobe_centres(inc, a))
        ax.axvline(inc, color="orange", ls=":", lw=1)
        ax.set_xlim(0, 180)
        ax.set_xlabel("view elevation (deg), azimuth 0; dotted: zero phase")
        ax.set_ylabel("specular (0-255)")
        ax.set_title(f"aspect {aspect_label(a)}, incidence {inc:g}", loc="left")
    if panels:
        panels_legend([ax for ax, _ in panels], title="truncation", fontsize=7, title_fontsize=8)
    return fig


def _mirror_marks(ax, centres) -> None:
    """The back and forward mirror directions: dashed lines, named on a scale above the axes (not over the lobes)."""
    marks = [(e, f"{name} mirror\n{e:.1f}°") for name, e in (("back", centres["back"]), ("forward", centres["forward"]))
             if e is not None]
    for e, _ in marks:
        ax.axvline(e, color="0.4", ls="--", lw=0.8)
    top = ax.secondary_xaxis("top")
    top.set_xticks([e for e, _ in marks], [label for _, label in marks], fontsize=8)
    top.tick_params(length=3, pad=1)


def _model_curves(ax, lobe, tt, m, k):
    """The thesis's two models of a lobe peak against truncation: the area model and the regressed one."""
    pred = thesis_model_predictions(tt, m, k)
    if lobe == "forward":
        ax.plot(tt, pred["square_area"], color="#1f77b4", label="square area  m(1-t)²")
        ax.plot(tt, pred["forward_regressed"], color="#d62728", label="regressed  m(1-sin(tπ/2))")
    else:
        ax.plot(tt, pred["triangle_area"], color="#1f77b4", label=f"triangle area  {k:.3g}m(1-(1-t)²)")
        ax.plot(tt, pred["back_regressed"], color="#d62728", label="regressed  m sin(tπ/2)/2")


def _sine_refit(ax, sine, aspect, lobe, tt):
    """Our refit of the regressed model's sine (A, omega), when it was fitted for this aspect and lobe."""
    s = sine[(np.abs(sine["aspect"] - aspect) <= ASPECT_TOL) & (sine["lobe"] == lobe)] if len(sine) else sine
    if len(s) == 2 and np.isfinite(s["estimate"]).all():
        A = float(s.loc[s["parameter"] == "A", "estimate"].iloc[0])
        w = float(s.loc[s["parameter"] == "omega", "estimate"].iloc[0])
        y = A * (1 - np.sin(w * tt)) if lobe == "forward" else A * np.sin(w * tt)
        outside = ";\nω > π/2: turns down before t = 1, outside the physical range" if w > np.pi / 2 else ""
        ax.plot(tt, y, color="#2ca02c", ls="--", label=f"refit  A={A:.1f}, ω={w:.3f}{outside}")


def _model_panel(ax, lobes, sine, aspect, lobe, m, k, inc, exact=None):
    data = table_data(lobes, aspect, inc)
    if lobe not in data:
        ax.text(0.5, 0.5, f"no {lobe} lobe", ha="center", transform=ax.transAxes)
        return
    t = data.index.to_numpy(float)
    tt = np.linspace(0, 1, 201)
    if k is None:
        k = front_facet_share(aspect, inc) if lobe == "back" else 0.5
    ax.plot(t, data[lobe], "o", color="k", label="our data (lobe peak)", zorder=5)
    if exact is not None and len(exact):
        ex = exact[(np.abs(exact["aspect"] - aspect) <= ASPECT_TOL) & (exact["lobe"] == lobe)
                   & np.isclose(exact["incidence"], inc)]
        if len(ex):
            ax.plot(ex["truncation"], ex["exact_peak"], "o", mfc="none", mec="#ff7f0e", ms=9, mew=1.4,
                    label="exact peak (polygon clipping)", zorder=6)
    _model_curves(ax, lobe, tt, m, k)
    _sine_refit(ax, sine, aspect, lobe, tt)
    ax.set_xlabel("truncation t")
    ax.set_ylabel(f"{lobe} lobe peak (0-255)")
    ax.set_title(f"aspect {aspect_label(aspect)}, incidence {inc:g}", loc="left")
    legend_below(ax, fontsize=7)


def _models_figure(lobes, sine, lobe, m, k, key, exact, aspects, incidence):
    theme()
    inc = pick_incidence(lobes, incidence)
    present = aspects_present(lobes, aspects)
    if not present:
        return placeholder(figure_title(key), no_table_aspect(aspects))
    fig, axes = plt.subplots(1, len(present), figsize=(5.6 * len(present), 3.8), squeeze=False, sharey=True)
    for ax, a in zip(axes[0], present):
        _model_panel(ax, lobes, sine, a, lobe, m, k, inc, exact)
    return fig


def fig23_forward_models(lobes_arc: pd.DataFrame, sine_refits: pd.DataFrame, light: float = 127.0, exact_peaks=None,
                         aspects=TABLE_ASPECTS, incidence: float = THESIS_INCIDENCE):
    """Fig. 23: forward lobe peak against truncation with the square area and regressed models.

    ``exact_peaks``: optional :func:`roughlight.analysis.thesis.exact_lobe_peaks` frame, drawn as open circles.
    """
    return _models_figure(lobes_arc, sine_refits, "forward", light, None, "fig23_forward_models", exact_peaks,
                          aspects, incidence)


def fig25_back_models(lobes_arc: pd.DataFrame, sine_refits: pd.DataFrame, light: float = 127.0, k: float | None = None,
                      exact_peaks=None, aspects=TABLE_ASPECTS, incidence: float = THESIS_INCIDENCE):
    """Fig. 25: back lobe peak against truncation with the triangle area and regressed models.

    ``k`` (the triangle area's factor) defaults to geometry, :func:`roughlight.surfaces.geometry.front_facet_share`.
    """
    return _models_figure(lobes_arc, sine_refits, "back", light, k, "fig25_back_models", exact_peaks, aspects,
                          incidence)


def fig24_reflecting_areas(reflecting_areas: pd.DataFrame):
    """Fig. 24: visible-lit area of the top (forward) and the front facet (back) against truncation.

    Parameters
    ----------
    reflecting_areas : :func:`roughlight.surfaces.geometry.reflecting_areas` frames of the aspects, stacked
    """
    areas = ({a: g.reset_index(drop=True) for a, g in reflecting_areas.groupby("aspect", sort=False)}
             if len(reflecting_areas) else {})
    theme()
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
        legend_below(ax, fontsize=7)
    return fig


def fig26_specular_aspect(study: pd.DataFrame, truncations=(0.2, 1.0), incidence: float = THESIS_INCIDENCE):
    """Fig. 26: specular on the phi = 0 arc against aspect, at a few truncations."""
    theme()
    spec = arc(study, "specular")
    inc = pick_incidence(spec, incidence)
    have = np.unique(spec["truncation"].to_numpy(float))
    ts = [t for t in truncations if np.any(np.isclose(have, t))] or [float(have.max())]
    fig, axes = plt.subplots(1, len(ts), figsize=(6.2 * len(ts), 3.8), squeeze=False, sharey=True)
    for ax, t in zip(axes[0], ts):
        d = select(spec, truncation=t, incidence=inc).copy()
        d["aspect"] = d["aspect"].map(aspect_label)
        n = d["aspect"].nunique()
        sns.lineplot(data=d, x="elevation", y="rough", hue="aspect", palette=hue_palette(n, "rocket_r"), ax=ax,
                     lw=1.1)
        ax.set_xlim(0, 180)
        ax.set_xlabel("view elevation (deg), azimuth 0")
        ax.set_ylabel("specular (0-255)")
        ax.set_title(f"truncation {t:g}, incidence {inc:g}", loc="left")
    panels_legend(list(axes[0]), title="aspect", fontsize=7, title_fontsize=8)
    return fig


# ---------------------------------------------------------------------------
# Fig. 19: the specular from above


def _example_surfaces(grids, inc) -> list:
    """Fig. 19's surfaces that the study has: the plate, t 0.5 and 1 at aspect 1, t 1 at aspect sqrt(3)/2."""
    surfaces = []
    for t, a in ((0.0, 0.0), (0.5, 1.0), (1.0, 1.0), (1.0, SQRT3_2)):
        hit = [k for k in grids if np.isclose(k[0], t) and abs(k[1] - a) <= ASPECT_TOL and np.isclose(k[2], inc)]
        if t == 0.0 and not hit:
            hit = [k for k in grids if is_plate(k[0], k[1]) and np.isclose(k[2], inc)]
        if hit:
            surfaces.append(hit[0])
    return surfaces


def _topdown_map(ax, az, el, v, key) -> None:
    """One surface's specular over the hemisphere from its measured views (:func:`.common.hemisphere_map`), on
    its own scale (15 bands from 0 to its maximum): ``az`` (A,) and ``el`` (E,) in degrees, ``v`` (A, E) 0-255,
    NaN where a view is missing; ``key`` (truncation, aspect, incidence)."""
    t, a, i = key
    A, E = np.meshgrid(az, el, indexing="ij")
    vmax = max(float(np.nanmax(v)), 1.0)
    hemisphere_map(ax, A.ravel(), E.ravel(), np.ravel(v), levels=np.linspace(0, vmax, 16), cmap="magma")
    hemisphere_frame(ax, i)
    ax.set_title(f"t {t:g}, aspect {aspect_label(a)} (max {vmax:.0f})", loc="left", fontsize=9)


def _back_lobe_track(az, el, v, key, max_angle) -> list[dict]:
    """On every half great circle passing within ``max_angle`` of the back mirror direction, the brightest view
    near it (at least :data:`~roughlight.analysis.lobes.MIN_LOBE_PEAK`): its azimuth, value, phase and x, y."""
    t, a, i = key
    dirs = lobe_directions(t, a, i)
    if "back" not in dirs or is_plate(t, a):
        return []
    A, E = np.meshgrid(az, el, indexing="ij")
    V = view_direction(E, A)
    near = (V @ dirs["back"]) >= math.cos(math.radians(max_angle))
    rows = []
    for k in range(len(az)):
        sel = near[k] & np.isfinite(v[k])
        if not sel.any():
            continue
        j = np.flatnonzero(sel)[int(np.argmax(v[k, sel]))]
        if v[k, j] < MIN_LOBE_PEAK:
            continue
        d = V[k, j]
        rows.append({"surface": f"t {t:g}, a {aspect_label(a)}", "azimuth": math.degrees(math.atan2(d[1], d[0])),
                     "value": float(v[k, j]), "phase": float(phase_angle(i, el[j], az[k])), "x": d[0], "y": d[1]})
    return rows


def _track_panels(ax1, ax2, track_rows) -> None:
    """The back lobe's maximum and its phase angle against the azimuth of the brightest view."""
    if not track_rows:
        for ax in (ax1, ax2):
            ax.text(0.5, 0.5, "no back lobe on these surfaces", ha="center", transform=ax.transAxes)
        return
    tr = pd.DataFrame(track_rows)
    sns.lineplot(data=tr, x="azimuth", y="value", hue="surface", marker="o", ax=ax1, ms=4)
    sns.lineplot(data=tr, x="azimuth", y="phase", hue="surface", marker="o", ax=ax2, ms=4, legend=False)
    ax1.set_xlabel("azimuth of the brightest view near the back mirror direction (deg)")
    ax2.set_xlabel("azimuth of the brightest view near the back mirror direction (deg)")
    ax1.set_ylabel("back-lobe maximum on the arc (0-255)")
    ax2.set_ylabel("phase angle at that maximum (deg)")
    ax1.get_legend().remove()


def fig19_topdown(study: pd.DataFrame, surfaces=None, max_angle: float = 45.0, incidence: float = THESIS_INCIDENCE):
    """Fig. 19: top-down maps of the specular over the hemisphere, and the back lobe's track.

    The top row maps the specular component seen from every direction
    (orthographic projection of the hemisphere, the light ★ at azimuth 0 on
    the right), each panel on its own scale: filled contours interpolated
    between measured neighbouring views (:func:`.common.hemisphere_map`; the
    sweep's half great circles, azimuths 0 to < 180 with elevations 0-180,
    cover the whole disc, and nothing is mirrored). White dots mark, on
    every half great circle that passes within ``max_angle`` of the back
    (light-facing facet's) mirror direction, the brightest view near it (on
    either side of the light's plane, as measured). The bottom row gives
    that maximum and its phase angle against the dot's azimuth: a lobe
    centred on zero phase would keep phase 0.
    """
    theme()
    # the views not rendered (e = 0 and 180, coverage 0: stored as 0) are left out, never drawn as dark views
    columns = ("rough", "coverage") if "coverage" in study else ("rough",)
    grids = {key: (az, el, rendered_values(el[None, :], g["rough"], g.get("coverage")))
             for key, az, el, g in surface_value_grids(study, "specular", columns)}
    inc = pick_incidence(study, incidence)
    surfaces = _example_surfaces(grids, inc) if surfaces is None else surfaces
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
        ax = fig.add_subplot(gs[0, 2 * j:2 * j + 2])
        _topdown_map(ax, *grids[key], key)
        track = _back_lobe_track(*grids[key], key, max_angle)
        if track:
            ax.plot([r["x"] for r in track], [r["y"] for r in track], ".", color="white", ms=3.5)
        track_rows += track
    ax1, ax2 = fig.add_subplot(gs[1, :n]), fig.add_subplot(gs[1, n:])
    _track_panels(ax1, ax2, track_rows)
    fig.suptitle(f"Specular from above (light ★ at azimuth 0, elevation {inc:g}) and the back lobe's track",
                 y=0.995)
    fig.tight_layout()
    if track_rows:  # under both track panels (they share the colours), not over them
        handles, labels = ax1.get_legend_handles_labels()
        fig.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=len(labels), fontsize=8,
                   title="surface", title_fontsize=8)
    return fig
