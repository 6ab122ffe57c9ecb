"""The reflection lobes of each surface: where they are, how high and how wide.

On the ``phi = 0`` arc a facet whose normal lies in the x-z plane at angle
``theta_n`` from +x mirrors the light to elevation ``2 theta_n - i``. The top
(and the plate) has ``theta_n = 90``: the *forward* lobe at ``180 - i``. The
side facet facing the light ("east") has ``theta_n = 90 - s`` with
``s = atan(2 aspect)`` its tilt: the *back* lobe at ``180 - 2 s - i``; at
aspect sqrt(3)/2 (s = 60) and i = 30 that is elevation 30, zero phase. The
facet facing away ("west") mirrors to ``180 + 2 s - i``, on the arc only while
``2 s < i`` (the thesis's second lobe at very low aspect, Fig. 26). The
predicted centres are :func:`roughlight.surfaces.geometry.lobe_centres`.

Lobes are measured on the arc (:func:`arc_lobes`: peak, centre, half-maximum
width) and over the hemisphere (:func:`hemisphere_lobes`: peak, where it is
and the solid angle above half maximum). Angles are degrees; values 0-255.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..render.shading import light_direction, phase_angle, view_direction
from ..study.selection import SURFACE_KEYS, solid_angle_weights
from ..surfaces.geometry import facets, lobe_centres
from ..surfaces.surface import is_plate
from .grids import arc, surface_value_grids

#: A lobe whose peak is below this (0-255 scale) is "no lobe" (less than an 8-bit step).
MIN_LOBE_PEAK = 0.5

#: How the note of a lobe the horizon cuts starts (:func:`profile_lobe`): its maximum is on the first or last
#: rendered view of the arc (e = 1 or 179 by default), beside views that were not rendered (e = 0, 180).
HORIZON_CUT = "cut by the horizon"


def profile_lobe(elevation, values, centre: float, window: tuple[float, float]) -> dict:
    """Peak, centre and full width at half maximum of one lobe of a 1-D profile.

    Parameters
    ----------
    elevation : (n,) array, degrees, ascending
    values : (n,) array, 0-255 scale
    centre : float
        Predicted centre (degrees); only used to report the offset.
    window : (lo, hi)
        Elevations (degrees, inclusive) that belong to this lobe.

    Returns
    -------
    dict
        ``peak`` (max value in the window; NaN when that maximum sits on a
        window edge that the arc ``elevation`` continues past: the tail of
        another lobe, not a peak of this one; or, where the views past that
        edge have no value (NaN: not rendered, e = 0 or 180), a lobe the
        horizon cuts, whose true peak may lie beyond; the note then starts
        with :data:`HORIZON_CUT`), ``peak_elevation`` (mean of the
        elevations attaining it), ``centroid`` (value-weighted mean elevation
        over the part above half maximum), ``fwhm`` (degrees, half-maximum
        crossings interpolated linearly; NaN when a crossing lies outside the
        window), ``note`` (why something is NaN, else '').
    """
    e = np.asarray(elevation, float)
    v = np.asarray(values, float)
    inside = (e >= window[0]) & (e <= window[1]) & np.isfinite(v)
    out = {"peak": np.nan, "peak_elevation": np.nan, "centroid": np.nan, "fwhm": np.nan, "note": ""}
    if inside.sum() < 1:
        out["note"] = "no views in the lobe's window"
        return out
    ew, vw = e[inside], v[inside]
    peak = float(vw.max())
    out["peak"] = peak
    if peak < MIN_LOBE_PEAK:
        out["note"] = "no lobe (peak below one 8-bit step)"
        return out
    at = np.flatnonzero(vw == peak)
    # a maximum on the window's edge, where the arc goes on, is the tail of a neighbouring lobe rising out of
    # the window, or a lobe the horizon cuts (the arc goes on past it to views not rendered), not a peak of this
    # one: no value enters a fit or a table
    edge = _edge_maxima(e, ew, at)
    if edge:
        out["peak"] = np.nan
        out["note"] = _edge_note(e, v, ew, edge[0], peak)
        return out
    out["peak_elevation"] = float(ew[at].mean())
    half = peak / 2.0
    left, right = _above_half(vw, at, half)
    above = slice(left, right + 1)
    out["centroid"] = float(np.sum(ew[above] * vw[above]) / np.sum(vw[above]))
    if left == 0 or right == len(vw) - 1:
        out["note"] = "half maximum not reached inside the window"
        return out
    out["fwhm"] = _crossing(ew, vw, right + 1, right, half) - _crossing(ew, vw, left - 1, left, half)
    return out


def _edge_maxima(e, ew, at) -> list:
    """The elevations (degrees) among the first and last maximum ``at`` (indices into the window's elevations
    ``ew``) that lie on an edge of the window past which the whole arc ``e`` goes on."""
    last = len(ew) - 1
    return [ew[j] for j in (at[0], at[-1]) if (j == 0 and ew[0] > e.min()) or (j == last and ew[-1] < e.max())]


def _edge_note(e, v, ew, edge: float, peak: float) -> str:
    """Why a maximum ``peak`` on the edge at elevation ``edge`` (degrees) of the window's views ``ew`` is no peak:
    another lobe's tail where the arc (elevations ``e``, values ``v``) was measured past that edge; the horizon
    where no view past it has a value (the views not rendered, e = 0 or 180)."""
    beyond = v[e < edge] if edge == ew[0] and edge > e.min() else v[e > edge]
    if not np.isfinite(beyond).any():
        return (f"{HORIZON_CUT}: the maximum ({peak:.3g}) is on the rendered view nearest the horizon, at "
                f"{edge:g} deg; the peak may lie beyond")
    return f"no lobe: the maximum ({peak:.3g}) is on the window's edge at {edge:g} deg, another lobe's tail"


def _above_half(vw, at, half: float) -> tuple[int, int]:
    """The first and last index of the run of values ``vw`` at or above ``half`` around the maxima ``at``,
    walking outwards from the first maximum to the left and from the last to the right."""
    left = int(at[0])
    while left > 0 and vw[left - 1] >= half:
        left -= 1
    right = int(at[-1])
    while right < len(vw) - 1 and vw[right + 1] >= half:
        right += 1
    return left, right


def _crossing(ew, vw, i_out: int, i_in: int, half: float) -> float:
    """The elevation (degrees) where the profile crosses ``half``, linear between the views ``i_out`` (below
    it) and ``i_in`` (at or above it)."""
    e0, e1, v0, v1 = ew[i_out], ew[i_in], vw[i_out], vw[i_in]
    return float(e0 + (half - v0) * (e1 - e0) / (v1 - v0))


def _arc_windows(centres: dict, max_halfwidth: float) -> dict:
    """Each lobe's elevation window: its Voronoi cell among the distinct centres, capped."""
    live = {k: c for k, c in centres.items() if c is not None}
    out = {}
    for name, c in live.items():
        lo, hi = max(0.0, c - max_halfwidth), min(180.0, c + max_halfwidth)
        for other, c2 in live.items():
            if other == name or abs(c2 - c) < 1e-9:
                continue
            mid = 0.5 * (c + c2)
            if c2 > c:
                hi = min(hi, mid)
            else:
                lo = max(lo, mid)
        out[name] = (lo, hi)
    return out


def arc_lobes(study: pd.DataFrame, azimuth: float = 0.0, max_halfwidth: float = 40.0) -> pd.DataFrame:
    """Forward, back (and west) specular lobes of every surface on one arc.

    Parameters
    ----------
    study : DataFrame
        The study table.
    azimuth : float
        The arc (degrees); the thesis's plots are the light's plane, 0.
    max_halfwidth : float
        A lobe's window reaches at most this far from its predicted centre
        (degrees), and never past the midpoint to a neighbouring lobe's.

    Returns
    -------
    DataFrame, one row per surface x lobe: surface keys, ``lobe``
    ('forward' | 'back' | 'west'), ``predicted`` (elevation, degrees),
    ``window_lo``/``window_hi``, ``peak`` (0-255), ``peak_elevation``,
    ``centroid``, ``fwhm`` (degrees), ``phase_at_peak`` (degrees),
    ``offset`` (peak elevation minus predicted, degrees), ``plate`` (bool),
    ``note``. The views that were not rendered (coverage 0: e = 0 and 180)
    have no value; a maximum beside them, on the first or last rendered view
    (e = 1 or 179), is a lobe the horizon cuts (:func:`profile_lobe`): no
    peak (NaN), and the note starts with :data:`HORIZON_CUT`.
    """
    spec = arc(study, "specular", azimuth)
    rows = []
    for key, group in spec.groupby(SURFACE_KEYS, sort=True):
        rows += _surface_arc_lobes(key, group, max_halfwidth)
    out = pd.DataFrame(rows)
    out["phase_at_peak"] = np.where(
        np.isfinite(out["peak_elevation"]),
        phase_angle(out["incidence"].to_numpy(float), out["peak_elevation"].fillna(0).to_numpy(float), azimuth),
        np.nan,
    )
    out["offset"] = out["peak_elevation"] - out["predicted"]
    cols = SURFACE_KEYS + ["lobe", "plate", "predicted", "window_lo", "window_hi", "peak", "peak_elevation",
                           "centroid", "fwhm", "phase_at_peak", "offset", "note"]
    return out[cols]


def _surface_arc_lobes(key, group: pd.DataFrame, max_halfwidth: float) -> list[dict]:
    """:func:`arc_lobes`' rows of one surface ``key`` (truncation, aspect, incidence) from its arc's specular
    views ``group``: forward and back always, west where its mirror direction is on the arc."""
    t, a, i = (float(k) for k in key)
    centres = lobe_centres(i, a)
    windows = _arc_windows(centres, max_halfwidth)
    e = group["elevation"].to_numpy(float)
    # a view that was not rendered (e = 0, 180) is no dark view: no value, but the arc goes on there, so that a
    # maximum on the last rendered view is a lobe the horizon cuts (profile_lobe)
    v = np.where(group["coverage"].to_numpy(float) > 0, group["rough"].to_numpy(float), np.nan)
    rows = []
    for lobe in ("forward", "back", "west"):
        if centres[lobe] is None and lobe == "west":
            continue  # not on the arc: nothing to report
        row = {"truncation": t, "aspect": a, "incidence": i, "lobe": lobe, "plate": is_plate(t, a)}
        row.update(_arc_lobe(lobe, centres, windows, a, e, v))
        rows.append(row)
    return rows


def _arc_lobe(lobe: str, centres: dict, windows: dict, aspect: float, e, v) -> dict:
    """One lobe on the arc (elevations ``e``, degrees; values ``v``, 0-255): its predicted centre, window and
    :func:`profile_lobe`, or NaNs and a note where there is no lobe to measure."""
    c = centres[lobe]
    missing = dict(window_lo=np.nan, window_hi=np.nan, peak=np.nan, peak_elevation=np.nan, centroid=np.nan,
                   fwhm=np.nan)
    if c is None:
        return dict(predicted=np.nan, **missing,
                    note="aspect 0: no side facets" if aspect <= 0 else "mirror direction below the horizon")
    if lobe == "back" and abs(c - centres["forward"]) < 1e-9:
        return dict(predicted=c, **missing, note="back lobe coincides with the forward lobe")
    lo, hi = windows[lobe]
    return dict(predicted=c, window_lo=lo, window_hi=hi, **profile_lobe(e, v, c, (lo, hi)))


def _mirror(normal, incidence) -> np.ndarray | None:
    L = light_direction(incidence)
    nl = float(np.dot(normal, L))
    if nl <= 0:
        return None
    r = 2.0 * nl * np.asarray(normal, float) - L
    return r if r[2] > 1e-9 else None


def lobe_directions(truncation, aspect, incidence) -> dict:
    """Unit mirror directions of the named lobes (forward always, from the plane)."""
    out = {"forward": _mirror(np.array([0.0, 0.0, 1.0]), incidence)}
    if aspect > 0:
        for name, n, _ in facets(max(truncation, 0.5), aspect):
            if name in ("east", "west", "north", "south"):
                r = _mirror(n, incidence)
                if r is not None:
                    out["back" if name == "east" else name] = r
    return {k: v for k, v in out.items() if v is not None}


def hemisphere_lobes(study: pd.DataFrame, max_angle: float = 40.0) -> pd.DataFrame:
    """Forward and back specular lobes over the whole hemisphere.

    Each view is assigned to the nearest (3-D angle) facet mirror direction,
    within ``max_angle`` degrees; a lobe's statistics are over its views.

    Returns
    -------
    DataFrame, one row per surface x lobe ('forward', 'back'): surface keys,
    ``lobe``, ``peak`` (0-255), ``peak_azimuth``/``peak_elevation``
    (degrees), ``phase_at_peak`` (degrees), ``angle_from_mirror`` (degrees
    between the peak view and the predicted mirror direction),
    ``solid_angle`` (sr above half maximum) and ``cone_fwhm`` (degrees, full
    apex angle of the cone with that solid angle), ``note``.
    """
    rows = []
    for (t, a, i), az, el, grids in surface_value_grids(study, "specular", ("rough", "coverage")):
        vals = np.where(grids["coverage"] > 0, grids["rough"], np.nan)  # views not rendered: no views at all
        rows += _surface_hemisphere_lobes(t, a, i, az, el, vals, max_angle)
    out = pd.DataFrame(rows)
    for col in ("peak_azimuth", "peak_elevation", "phase_at_peak", "angle_from_mirror", "solid_angle", "cone_fwhm"):
        if col not in out:
            out[col] = np.nan
    out["note"] = out["note"].fillna("")
    cols = SURFACE_KEYS + ["lobe", "peak", "peak_azimuth", "peak_elevation", "phase_at_peak",
                           "angle_from_mirror", "solid_angle", "cone_fwhm", "note"]
    return out[cols]


def _surface_hemisphere_lobes(t: float, a: float, i: float, az, el, vals, max_angle: float) -> list[dict]:
    """:func:`hemisphere_lobes`' forward and back rows of one surface from its specular values ``vals`` (A, E)
    at azimuths ``az`` (A,) and elevations ``el`` (E,), degrees."""
    dirs = lobe_directions(t, a, i)
    A, E = np.meshgrid(az, el, indexing="ij")
    V = view_direction(E, A)  # (A, E, 3)
    w = solid_angle_weights(az, el)
    names = list(dirs)  # empty where no mirror direction is above the horizon (incidence 0 on the plate)
    if names:  # each view's nearest mirror direction, and its cosine
        cosang = np.stack([V @ dirs[n] for n in names], axis=-1)  # (A, E, K)
        nearest, best = np.argmax(cosang, axis=-1), np.max(cosang, axis=-1)
    rows = []
    for lobe in ("forward", "back"):
        row = {"truncation": t, "aspect": a, "incidence": i, "lobe": lobe}
        missing = _missing_lobe(lobe, dirs)
        region = None
        if not missing:
            region = (nearest == names.index(lobe)) & (best >= math.cos(math.radians(max_angle))) & np.isfinite(vals)
            missing = "" if region.any() else "no views near the mirror direction"
        if missing:
            row.update(peak=np.nan, note=missing)
        else:
            row.update(_hemisphere_peak(region, vals, V, w, az, el, i, dirs[lobe]))
        rows.append(row)
    return rows


def _missing_lobe(lobe: str, dirs: dict) -> str:
    """Why the hemisphere has no ``lobe`` among the mirror directions ``dirs`` (:func:`lobe_directions`): none
    above the horizon, or a back lobe on the forward one; '' when it has one."""
    if lobe not in dirs:
        return "no mirror direction above the horizon"
    if (lobe == "back" and "forward" in dirs
            and np.degrees(np.arccos(np.clip(dirs["back"] @ dirs["forward"], -1, 1))) < 1e-6):
        return "back lobe coincides with the forward lobe"
    return ""


def _hemisphere_peak(region, vals, V, w, az, el, i: float, mirror) -> dict:
    """A lobe over its views ``region`` (A, E) bool: the peak (0-255), where it is (degrees), its phase and
    angle from the unit ``mirror`` direction, and the solid angle above half maximum (sr, the views' weights
    ``w``) with the apex angle of the cone that has it."""
    rv = np.where(region, vals, -np.inf)
    peak = float(rv.max())
    ia, ie = np.unravel_index(int(np.argmax(rv)), rv.shape)
    row = dict(peak=peak, peak_azimuth=float(az[ia]), peak_elevation=float(el[ie]))
    row["phase_at_peak"] = float(phase_angle(i, el[ie], az[ia]))
    row["angle_from_mirror"] = float(np.degrees(np.arccos(np.clip(V[ia, ie] @ mirror, -1, 1))))
    if peak < MIN_LOBE_PEAK:
        row.update(solid_angle=np.nan, cone_fwhm=np.nan, note="no lobe (peak below one 8-bit step)")
    else:
        omega = float(np.sum(w[region & (vals >= peak / 2.0)]))
        row["solid_angle"] = omega
        row["cone_fwhm"] = float(2.0 * np.degrees(np.arccos(max(-1.0, 1.0 - omega / (2.0 * math.pi)))))
        row["note"] = ""
    return row
