"""Analysis of the study table: lobes, the thesis's models and Tables 1-2, GLMs, analytic models.

Everything here is a pure function of pandas frames / numpy arrays (no I/O, no
plotting); :mod:`roughlight.figures` draws the results and
:mod:`roughlight.report` writes them into the HTML report. The study table is
described in :mod:`roughlight.study` (one row per surface x view x
component; values on the 0-255 scale).

Conventions (see :mod:`roughlight.geometry` and :mod:`roughlight.shading`)
---------------------------------------------------------------------------
* Angles are degrees unless a name ends in ``_rad``. Elevation ``e`` runs
  0..180 along half great circles at azimuth ``phi`` in [0, 180); the light is
  at azimuth 0 and elevation ``i`` (the incidence).
* On the ``phi = 0`` arc a facet whose normal lies in the x-z plane at angle
  ``theta_n`` from +x mirrors the light to elevation ``2 theta_n - i``. The
  top (and the plate) has ``theta_n = 90``: the *forward* lobe at ``180 - i``.
  The side facet facing the light ("east") has ``theta_n = 90 - s`` with
  ``s = atan(2 aspect)`` its tilt: the *back* lobe at ``180 - 2 s - i``; at
  aspect sqrt(3)/2 (s = 60) and i = 30 that is elevation 30, zero phase.
  The facet facing away ("west") mirrors to ``180 + 2 s - i``, on the arc only
  while ``2 s < i`` (the thesis's second lobe at very low aspect, Fig. 26).
* "Plate" surfaces (truncation 0 or aspect 0) are the flat control whatever
  the other parameter is.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
import pandas as pd

from .geometry import facet_areas, is_plate, period_triangles, side_slope_deg
from .shading import light_direction, phase_angle, quantize, view_direction

__all__ = [
    "SQRT3_2",
    "SURFACE_KEYS",
    "THESIS_TABLES",
    "TABLE_METRICS",
    "THESIS_INCIDENCE",
    "aspect_label",
    "find_aspect",
    "lobe_centres",
    "diffuse_breakpoints",
    "surface_grids",
    "arc",
    "profile_lobe",
    "arc_lobes",
    "hemisphere_lobes",
    "lobe_track",
    "diffuse_three_part",
    "diffuse_levels",
    "thesis_model_predictions",
    "fit_statistics",
    "thesis_tables",
    "sine_refits",
    "reflecting_areas",
    "exact_lobe_peaks",
    "front_facet_share",
    "grid_glm",
    "grid_glms",
    "facets",
    "facet_model",
    "oren_nayar",
    "oren_nayar_sigma",
    "hapke_opposition",
    "fit_hapke",
    "analytic_model_fits",
    "model_fit_summary",
    "render_timings",
]

#: Aspect whose side facets face a light at incidence 30 (tilt 60 deg).
SQRT3_2 = math.sqrt(3.0) / 2.0
#: One row per surface (and light) in the per-surface tables.
SURFACE_KEYS = ["truncation", "aspect", "incidence"]
#: The thesis's analysis ran at this incidence (Ch. V.B).
THESIS_INCIDENCE = 30.0
#: Columns of Tables 1 and 2, as the thesis names them.
TABLE_METRICS = ["Mean Abs Error", "Standard Deviation", "b0", "b1", "RSS"]
#: The thesis's Tables 1-2 (Slattery 2001, Ch. V.E), verbatim.
THESIS_TABLES = {
    1: {
        "title": "Comparison Of Statistical Results For Forwards Reflection",
        "lobe": "forward",
        "rows": {
            "Square Area Function": [4.10, 3.08, -4.684, 1.012, 122.407],
            "Regressed Model": [2.35, 1.88, -2.268, 1.032, 51.918],
        },
    },
    2: {
        "title": "Comparison Of Statistical Results For Backwards Reflection",
        "lobe": "back",
        "rows": {
            "Triangle Area Function": [4.96, 2.30, 1.760, 1.077, 21.883],
            "Regressed Model": [1.71, 2.40, -0.92, 0.980, 8.858],
        },
    },
}
#: Aspects are matched to a wanted value within this.
ASPECT_TOL = 1e-9
#: A lobe whose peak is below this (0-255 scale) is "no lobe" (less than an 8-bit step).
MIN_LOBE_PEAK = 0.5


def aspect_label(aspect: float) -> str:
    """Readable label of an aspect: ``'√3/2'`` for sqrt(3)/2, else ``'%g'``."""
    return "√3/2" if abs(float(aspect) - SQRT3_2) < 1e-6 else f"{float(aspect):g}"


def find_aspect(values, wanted: float, tol: float = ASPECT_TOL):
    """The value in ``values`` equal to ``wanted`` within ``tol``, or None."""
    vals = np.unique(np.asarray(values, float))
    hit = vals[np.abs(vals - float(wanted)) <= tol]
    return float(hit[0]) if len(hit) else None


def _plate(truncation: float, aspect: float) -> bool:
    return is_plate(float(truncation), float(aspect))


# ---------------------------------------------------------------------------
# geometry of the lobes and of the diffuse parts


def lobe_centres(incidence: float, aspect: float) -> dict:
    """Predicted elevations (phi = 0 arc) of the facets' mirror directions.

    Parameters
    ----------
    incidence : float
        Light elevation ``i``, degrees.
    aspect : float
        Pyramid height / period (sets the side tilt ``s = atan(2 aspect)``).

    Returns
    -------
    dict
        ``forward``: ``180 - i`` (top facet / plate); ``back``: ``180 - 2s - i``
        (the side facet facing the light), None when it leaves [0, 180] or the
        aspect is 0 (no side facets); ``west``: ``180 + 2s - i`` when it lies
        below 180 (only while ``2 s < i``), else None. Degrees.
    """
    i = float(incidence)
    s = side_slope_deg(aspect)
    out = {"forward": 180.0 - i, "back": None, "west": None}
    if float(aspect) > 0:
        back = 180.0 - 2.0 * s - i
        out["back"] = back if 0.0 < back < 180.0 else None
        west = 180.0 + 2.0 * s - i
        out["west"] = west if west < 180.0 else None
    return out


def diffuse_breakpoints(incidence: float, aspect: float) -> tuple[float, float]:
    """Elevations bounding the three parts of the thesis's diffuse model (Ch. V.F).

    Part one runs from 0 to the incidence (zero phase); part two from there to
    the elevation at which the front (light-facing) side facet turns edge-on,
    ``180 - s`` with ``s = atan(2 aspect)``; part three from there to 180.
    At i = 30 and aspect sqrt(3)/2 this is the thesis's 0-30 / 31-120 / 121-180.

    Returns
    -------
    (e1, e2) : floats, degrees.
    """
    return float(incidence), 180.0 - side_slope_deg(aspect)


# ---------------------------------------------------------------------------
# access to the study table


def _component(study: pd.DataFrame, component: str) -> pd.DataFrame:
    comp = study["component"].astype(str)
    out = study.loc[comp == component]
    if out.empty:
        raise ValueError(f"the study table has no {component!r} rows")
    return out


def surface_grids(study: pd.DataFrame, component: str, value: str = "rough"):
    """Each surface's views as a regular azimuth x elevation grid.

    Parameters
    ----------
    study : DataFrame
        The study table.
    component : str
        ``'diffuse'``, ``'specular'`` or ``'total'``.
    value : str
        Column to grid (``'rough'`` or ``'control'``).

    Yields
    ------
    key : (truncation, aspect, incidence) floats
    azimuth : (A,) float array, degrees, ascending
    elevation : (E,) float array, degrees, ascending
    values : (A, E) float array (NaN where a view is missing)
    """
    frame = _component(study, component)
    for key, group in frame.groupby(SURFACE_KEYS, sort=True):
        grid = group.pivot_table(index="azimuth", columns="elevation", values=value, aggfunc="mean")
        yield (
            tuple(float(k) for k in key),
            grid.index.to_numpy(float),
            grid.columns.to_numpy(float),
            grid.to_numpy(float),
        )


def arc(study: pd.DataFrame, component: str, azimuth: float = 0.0) -> pd.DataFrame:
    """The views of one half great circle (default the light's plane, phi = 0).

    Returns
    -------
    DataFrame with the surface keys, ``elevation``, ``phase``, ``rough``,
    ``control`` and ``coverage``, sorted by surface and elevation.
    """
    frame = _component(study, component)
    out = frame.loc[np.isclose(frame["azimuth"].to_numpy(float), azimuth)]
    if out.empty:
        raise ValueError(f"the study table has no views at azimuth {azimuth}")
    cols = SURFACE_KEYS + ["elevation", "phase", "rough", "control", "coverage"]
    return out[cols].sort_values(SURFACE_KEYS + ["elevation"]).reset_index(drop=True)


def _settings(study: pd.DataFrame) -> dict:
    """Light settings recorded in the study (first row; they are constant per study)."""
    row = study.iloc[0]
    return {
        "light": float(row["light"]),
        "ambient": float(row.get("ambient", 0.0)),
        "shininess": float(row.get("shininess", 64.0)),
        "specular_model": str(row.get("specular_model", "phong")),
        "shadows": bool(row.get("shadows", True)),
    }


# ---------------------------------------------------------------------------
# lobes


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
        ``peak`` (max value in the window), ``peak_elevation`` (mean of the
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
    out["peak_elevation"] = float(ew[at].mean())
    half = peak / 2.0
    k = int(at[0])
    # walk outwards from the peak to the half-maximum crossings
    left = k
    while left > 0 and vw[left - 1] >= half:
        left -= 1
    k2 = int(at[-1])
    right = k2
    while right < len(vw) - 1 and vw[right + 1] >= half:
        right += 1
    above = slice(left, right + 1)
    out["centroid"] = float(np.sum(ew[above] * vw[above]) / np.sum(vw[above]))
    if left == 0 or right == len(vw) - 1:
        out["note"] = "half maximum not reached inside the window"
        return out

    def cross(i_out, i_in):
        e0, e1, v0, v1 = ew[i_out], ew[i_in], vw[i_out], vw[i_in]
        return float(e0 + (half - v0) * (e1 - e0) / (v1 - v0))

    out["fwhm"] = cross(right + 1, right) - cross(left - 1, left)
    return out


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
    ``note``.
    """
    spec = arc(study, "specular", azimuth)
    rows = []
    for key, group in spec.groupby(SURFACE_KEYS, sort=True):
        t, a, i = (float(k) for k in key)
        centres = lobe_centres(i, a)
        windows = _arc_windows(centres, max_halfwidth)
        e = group["elevation"].to_numpy(float)
        v = group["rough"].to_numpy(float)
        for lobe in ("forward", "back", "west"):
            c = centres[lobe]
            row = {"truncation": t, "aspect": a, "incidence": i, "lobe": lobe, "plate": _plate(t, a)}
            if c is None:
                if lobe == "west":
                    continue  # not on the arc: nothing to report
                row.update(predicted=np.nan, window_lo=np.nan, window_hi=np.nan, peak=np.nan,
                           peak_elevation=np.nan, centroid=np.nan, fwhm=np.nan,
                           note="aspect 0: no side facets" if a <= 0 else "mirror direction below the horizon")
                rows.append(row)
                continue
            if lobe == "back" and abs(c - centres["forward"]) < 1e-9:
                row.update(predicted=c, window_lo=np.nan, window_hi=np.nan, peak=np.nan,
                           peak_elevation=np.nan, centroid=np.nan, fwhm=np.nan,
                           note="back lobe coincides with the forward lobe")
                rows.append(row)
                continue
            lo, hi = windows[lobe]
            prof = profile_lobe(e, v, c, (lo, hi))
            row.update(predicted=c, window_lo=lo, window_hi=hi, **prof)
            rows.append(row)
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


def facets(truncation: float, aspect: float) -> list[tuple[str, np.ndarray, float]]:
    """The facets of one period with their unit normal and plan (x-y projected) area.

    Returns
    -------
    list of (name, normal (3,) array, plan_area float); plan areas sum to 1.
    """
    areas = facet_areas(truncation, aspect)
    _, normals, names = period_triangles(truncation, aspect)
    out = []
    for name, true_area in areas.items():
        n = normals[names.index(name)]
        out.append((name, np.asarray(n, float), float(true_area * n[2])))
    return out


def _mirror(normal, incidence) -> np.ndarray | None:
    L = light_direction(incidence)
    nl = float(np.dot(normal, L))
    if nl <= 0:
        return None
    r = 2.0 * nl * np.asarray(normal, float) - L
    return r if r[2] > 1e-9 else None


def _lobe_directions(truncation, aspect, incidence) -> dict:
    """Unit mirror directions of the named lobes (forward always, from the plane)."""
    out = {"forward": _mirror(np.array([0.0, 0.0, 1.0]), incidence)}
    if aspect > 0:
        for name, n, _ in facets(max(truncation, 0.5), aspect):
            if name in ("east", "west", "north", "south"):
                r = _mirror(n, incidence)
                if r is not None:
                    out["back" if name == "east" else name] = r
    return {k: v for k, v in out.items() if v is not None}


def _solid_angle_weights(azimuth, elevation) -> np.ndarray:
    """(A, E) solid angle (sr) of each view's cell: |cos e| de dphi (sums to ~2 pi)."""
    az = np.asarray(azimuth, float)
    el = np.asarray(elevation, float)
    dphi = math.radians(180.0 / len(az)) if len(az) else 0.0
    de = np.gradient(np.radians(el)) if len(el) > 1 else np.array([math.pi])
    return np.abs(np.cos(np.radians(el)))[None, :] * de[None, :] * dphi * np.ones((len(az), 1))


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
    for (t, a, i), az, el, vals in surface_grids(study, "specular"):
        dirs = _lobe_directions(t, a, i)
        A, E = np.meshgrid(az, el, indexing="ij")
        V = view_direction(E, A)  # (A, E, 3)
        w = _solid_angle_weights(az, el)
        names = list(dirs)
        cosang = np.stack([V @ dirs[n] for n in names], axis=-1)  # (A, E, K)
        nearest = np.argmax(cosang, axis=-1)
        best = np.max(cosang, axis=-1)
        for lobe in ("forward", "back"):
            row = {"truncation": t, "aspect": a, "incidence": i, "lobe": lobe}
            if lobe not in dirs:
                row.update(peak=np.nan, note="no mirror direction above the horizon")
                rows.append(row)
                continue
            k = names.index(lobe)
            region = (nearest == k) & (best >= math.cos(math.radians(max_angle))) & np.isfinite(vals)
            if lobe == "back" and np.degrees(np.arccos(np.clip(dirs["back"] @ dirs["forward"], -1, 1))) < 1e-6:
                row.update(peak=np.nan, note="back lobe coincides with the forward lobe")
                rows.append(row)
                continue
            if not region.any():
                row.update(peak=np.nan, note="no views near the mirror direction")
                rows.append(row)
                continue
            rv = np.where(region, vals, -np.inf)
            peak = float(rv.max())
            ia, ie = np.unravel_index(int(np.argmax(rv)), rv.shape)
            row.update(peak=peak, peak_azimuth=float(az[ia]), peak_elevation=float(el[ie]))
            row["phase_at_peak"] = float(phase_angle(i, el[ie], az[ia]))
            row["angle_from_mirror"] = float(np.degrees(np.arccos(np.clip(V[ia, ie] @ dirs[lobe], -1, 1))))
            if peak < MIN_LOBE_PEAK:
                row.update(solid_angle=np.nan, cone_fwhm=np.nan, note="no lobe (peak below one 8-bit step)")
            else:
                omega = float(np.sum(w[region & (vals >= peak / 2.0)]))
                row["solid_angle"] = omega
                row["cone_fwhm"] = float(2.0 * np.degrees(np.arccos(max(-1.0, 1.0 - omega / (2.0 * math.pi)))))
                row["note"] = ""
            rows.append(row)
    out = pd.DataFrame(rows)
    for col in ("peak_azimuth", "peak_elevation", "phase_at_peak", "angle_from_mirror", "solid_angle", "cone_fwhm"):
        if col not in out:
            out[col] = np.nan
    out["note"] = out["note"].fillna("")
    cols = SURFACE_KEYS + ["lobe", "peak", "peak_azimuth", "peak_elevation", "phase_at_peak",
                           "angle_from_mirror", "solid_angle", "cone_fwhm", "note"]
    return out[cols]


def lobe_track(azimuth, elevation, values, centre_elevation: float, halfwidth: float = 40.0) -> pd.DataFrame:
    """Where the lobe peaks on each half great circle (the thesis's "phase shift", Fig. 19).

    Parameters
    ----------
    azimuth : (A,) degrees; elevation : (E,) degrees; values : (A, E), 0-255
    centre_elevation : float
        The lobe's elevation on the phi = 0 arc (degrees); on every arc the
        peak is searched within ``halfwidth`` degrees of it.

    Returns
    -------
    DataFrame with ``azimuth``, ``elevation`` (of the arc's maximum),
    ``value`` (0-255); rows whose arc has no value above 0 get NaN elevation.
    """
    el = np.asarray(elevation, float)
    vals = np.asarray(values, float)
    sel = np.abs(el - centre_elevation) <= halfwidth
    rows = []
    for k, phi in enumerate(np.asarray(azimuth, float)):
        v = vals[k, sel]
        if v.size == 0 or not np.any(v > 0):
            rows.append({"azimuth": phi, "elevation": np.nan, "value": 0.0})
            continue
        j = int(np.nanargmax(v))
        rows.append({"azimuth": phi, "elevation": float(el[sel][j]), "value": float(v[j])})
    return pd.DataFrame(rows)


# ---------------------------------------------------------------------------
# the diffuse component


def _exp_part(e, level1, level3, rate, e1):
    return level3 + (level1 - level3) * np.exp(-rate * (e - e1))


def diffuse_three_part(study: pd.DataFrame, azimuth: float = 0.0) -> pd.DataFrame:
    """The thesis's three-part model of the diffuse component (Ch. V.F), fitted per surface.

    On the arc, part one (``0 < e <= e1``) and part three (``e >= e2``) are
    constant levels (their means); part two decays exponentially from level
    one to level three, ``L3 + (L1 - L3) exp(-k (e - e1))``, with ``k`` fitted
    by least squares. Breakpoints from :func:`diffuse_breakpoints` (geometry).
    Grazing views (coverage 0) are left out.

    Returns
    -------
    DataFrame, one row per surface: keys, ``e1``/``e2`` (degrees),
    ``level1``/``level3`` (0-255), ``rate`` (k, 1/degree), ``decay_length``
    (1/k, degrees), ``rmse`` (whole arc, 0-255), ``rmse_part2``, ``n_part1``,
    ``n_part2``, ``n_part3``, ``note``.
    """
    from scipy.optimize import curve_fit

    frame = arc(study, "diffuse", azimuth)
    rows = []
    for key, g in frame.groupby(SURFACE_KEYS, sort=True):
        t, a, i = (float(k) for k in key)
        g = g[g["coverage"] > 0]
        e = g["elevation"].to_numpy(float)
        v = g["rough"].to_numpy(float)
        e1, e2 = diffuse_breakpoints(i, a)
        p1, p3 = (e > 0) & (e <= e1), (e >= e2) & (e < 180)
        p2 = (e > e1) & (e < e2)
        row = {"truncation": t, "aspect": a, "incidence": i, "e1": e1, "e2": e2,
               "n_part1": int(p1.sum()), "n_part2": int(p2.sum()), "n_part3": int(p3.sum()),
               "level1": float(v[p1].mean()) if p1.any() else np.nan,
               "level3": float(v[p3].mean()) if p3.any() else np.nan,
               "rate": np.nan, "decay_length": np.nan, "rmse": np.nan, "rmse_part2": np.nan, "note": ""}
        if _plate(t, a):
            row["note"] = "plate: one constant level, no decay"
            pred = np.full_like(v, float(v.mean())) if len(v) else v
            row["rmse"] = float(np.sqrt(np.mean((v - pred) ** 2))) if len(v) else np.nan
            rows.append(row)
            continue
        if not (p1.any() and p3.any()) or p2.sum() < 3:
            row["note"] = "too few views in a part to fit"
            rows.append(row)
            continue
        L1, L3 = row["level1"], row["level3"]
        if abs(L1 - L3) < 1e-9:
            row["note"] = "levels one and three equal: no decay to fit"
        else:
            try:
                (rate,), _ = curve_fit(lambda x, k: _exp_part(x, L1, L3, k, e1), e[p2], v[p2], p0=[0.05],
                                       bounds=([0.0], [10.0]))
                row["rate"] = float(rate)
                row["decay_length"] = float(1.0 / rate) if rate > 0 else np.inf
            except (RuntimeError, ValueError) as exc:
                row["note"] = f"decay fit failed: {exc}"
        decay = _exp_part(e, L1, L3, row["rate"], e1) if np.isfinite(row["rate"]) else np.nan
        pred = np.where(p1, L1, np.where(p3, L3, decay))
        ok = np.isfinite(pred)
        row["rmse"] = float(np.sqrt(np.mean((v[ok] - pred[ok]) ** 2)))
        row["rmse_part2"] = float(np.sqrt(np.mean((v[p2] - pred[p2]) ** 2))) if np.isfinite(row["rate"]) else np.nan
        rows.append(row)
    return pd.DataFrame(rows)


def diffuse_levels(study: pd.DataFrame) -> pd.DataFrame:
    """Solid-angle-weighted hemisphere mean of the diffuse component per surface.

    Returns
    -------
    DataFrame: surface keys, ``diffuse_level`` (rough, 0-255),
    ``control_level`` (the plate's), ``ratio`` (rough / control).
    """
    rows = []
    controls = {key: (az, el, v) for key, az, el, v in surface_grids(study, "diffuse", "control")}
    for key, az, el, vals in surface_grids(study, "diffuse"):
        w = _solid_angle_weights(az, el)
        ok = np.isfinite(vals)
        level = float(np.sum(w[ok] * vals[ok]) / np.sum(w[ok]))
        caz, cel, cv = controls[key]
        cw = _solid_angle_weights(caz, cel)
        cok = np.isfinite(cv)
        control = float(np.sum(cw[cok] * cv[cok]) / np.sum(cw[cok]))
        rows.append({"truncation": key[0], "aspect": key[1], "incidence": key[2], "diffuse_level": level,
                     "control_level": control, "ratio": level / control if control > 0 else np.nan})
    return pd.DataFrame(rows)


# ---------------------------------------------------------------------------
# the thesis's models and Tables 1-2


def thesis_model_predictions(truncation, m: float, k: float = 0.5) -> dict:
    """The thesis's four lobe-peak models, normalised (0-255 scale).

    Parameters
    ----------
    truncation : (n,) array in [0, 1]
    m : float
        ``m_source``: the light's specular reach, ``J m_s`` (127 in the thesis).
    k : float
        Back-lobe area factor: the lit fraction of the image the full
        pyramid's light-facing facet fills when seen from its mirror direction
        (0.5 from geometry at both aspects 1 and sqrt(3)/2, which is also the
        thesis's stated ratio of the back lobe at t = 1 to the forward lobe at
        t = 0).

    Returns
    -------
    dict of (n,) arrays
        ``square_area`` = m (1 - t)^2 (the top's share of the image: forward),
        ``forward_regressed`` = m (1 - sin(t pi/2)),
        ``triangle_area`` = m k (1 - (1 - t)^2) (the front facet's share:
        back), ``back_regressed`` = m sin(t pi/2) / 2.
    """
    t = np.asarray(truncation, float)
    return {
        "square_area": m * (1.0 - t) ** 2,
        "forward_regressed": m * (1.0 - np.sin(t * np.pi / 2.0)),
        "triangle_area": m * k * (1.0 - (1.0 - t) ** 2),
        "back_regressed": m * np.sin(t * np.pi / 2.0) / 2.0,
    }


def _table_spec(truncation, m: float, k: float) -> dict:
    """Tables 1-2 layout: table -> (lobe, {thesis row label: predicted peaks}) at these truncations."""
    preds = thesis_model_predictions(truncation, m, k)
    return {
        1: ("forward", {"Square Area Function": preds["square_area"], "Regressed Model": preds["forward_regressed"]}),
        2: ("back", {"Triangle Area Function": preds["triangle_area"], "Regressed Model": preds["back_regressed"]}),
    }


def _table_cells(lobes, aspects, incidence, m, k, messages: list):
    """Every cell of Tables 1-2 that the lobes allow: (table, aspect, peaks, truncations, k, lobe, model, predicted).

    ``peaks`` is the truncation x lobe frame of measured peaks. What is missing
    (an aspect, its lobes at this incidence, a lobe, some truncations) is
    appended to ``messages``.
    """
    for wanted in aspects:
        found = find_aspect(lobes["aspect"], wanted)
        if found is None:
            messages.append(f"aspect {aspect_label(wanted)} ({wanted!r}) is not in the study: no Tables 1-2 for it")
            continue
        data = _table_data(lobes, found, incidence)
        if data.empty:
            messages.append(f"aspect {aspect_label(found)}: no lobes at incidence {incidence:g}")
            continue
        t = data.index.to_numpy(float)
        k_used = front_facet_share(found, incidence) if k is None else float(k)
        for table, (lobe, models) in _table_spec(t, m, k_used).items():
            if lobe not in data:
                messages.append(f"aspect {aspect_label(found)}: no {lobe} lobe measured")
                continue
            for model, pred in models.items():
                yield table, found, data, t, k_used, lobe, model, pred
        if len(t) < 11:
            messages.append(f"aspect {aspect_label(found)}: {len(t)} truncations (the thesis used 11)")


def fit_statistics(observed, predicted) -> dict:
    """The thesis's model-comparison statistics of observed against predicted values.

    MAE and SD are of the raw errors ``observed - predicted`` (SD with
    ddof = 1); ``b0``, ``b1`` and ``RSS`` (the deviance: residual sum of
    squares of the regression line) come from a Gaussian GLM fitted by IRLS,
    ``observed ~ b0 + b1 predicted``, as the thesis's S-Plus run.

    Returns
    -------
    dict with the :data:`TABLE_METRICS` keys, ``n``, ``SSE`` (sum of squared
    raw errors), ``converged`` (bool) and ``note``.
    """
    import statsmodels.api as sm

    y = np.asarray(observed, float)
    x = np.asarray(predicted, float)
    ok = np.isfinite(y) & np.isfinite(x)
    y, x = y[ok], x[ok]
    err = y - x
    out = {
        "Mean Abs Error": float(np.mean(np.abs(err))) if len(err) else np.nan,
        "Standard Deviation": float(np.std(err, ddof=1)) if len(err) > 1 else np.nan,
        "b0": np.nan, "b1": np.nan, "RSS": np.nan,
        "n": int(len(err)), "SSE": float(np.sum(err**2)) if len(err) else np.nan,
        "converged": False, "note": "",
    }
    if len(y) < 3:
        out["note"] = f"only {len(y)} points: no regression line"
        return out
    if np.ptp(x) < 1e-12:
        out["note"] = "the model predicts one value for every point: no regression line"
        return out
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            res = sm.GLM(y, sm.add_constant(x, has_constant="add"), family=sm.families.Gaussian()).fit(method="IRLS")
        out.update(b0=float(res.params[0]), b1=float(res.params[1]), RSS=float(res.deviance),
                   converged=bool(res.converged))
        if not res.converged:
            out["note"] = "IRLS did not converge"
        elif res.deviance <= 1e-9 * max(1.0, float(np.sum((y - y.mean()) ** 2))):
            out["note"] = "exact fit: the model reproduces every point"
        elif caught:
            out["note"] = "; ".join(sorted({str(w.message) for w in caught}))[:200]
    except Exception as exc:  # singular designs etc.: report, never crash
        out["note"] = f"GLM failed: {exc}"
    return out


def _table_data(lobes: pd.DataFrame, aspect: float, incidence: float, value: str = "peak"):
    sel = lobes[(np.abs(lobes["aspect"] - aspect) <= ASPECT_TOL) & np.isclose(lobes["incidence"], incidence)]
    piv = sel.pivot_table(index="truncation", columns="lobe", values=value, aggfunc="first", dropna=False)
    return piv.sort_index()


def exact_lobe_peaks(lobes: pd.DataFrame, aspects=(1.0, SQRT3_2), incidence: float = THESIS_INCIDENCE,
                     lighting=None, halfwidth: float = 10.0, step: float = 1.0) -> pd.DataFrame:
    """Exact (polygon-clipping reference) lobe peaks beside the measured ones, for the table surfaces.

    For each surface of the tabulated aspects and each of the forward and
    back lobes, :func:`roughlight.reference.reference_sweep` evaluates the
    phi = 0 arc on the study's elevation grid (``step`` degrees) within
    ``halfwidth`` of the predicted mirror elevation; the exact peak is the
    largest of those values.

    Parameters
    ----------
    lobes : :func:`arc_lobes` output
    lighting : :class:`roughlight.shading.Lighting` (default: the study's)

    Returns
    -------
    DataFrame: surface keys, ``lobe``, ``peak`` (measured), ``exact_peak``
    (0-255), ``exact_peak_elevation`` (degrees), ``error`` (measured - exact).
    """
    from .reference import reference_sweep
    from .shading import Lighting

    lighting = lighting or Lighting()
    rows = []
    for wanted in aspects:
        a = find_aspect(lobes["aspect"], wanted)
        if a is None:
            continue
        sel = lobes[(np.abs(lobes["aspect"] - a) <= ASPECT_TOL) & np.isclose(lobes["incidence"], incidence)
                    & lobes["lobe"].isin(["forward", "back"])]
        for _, r in sel.iterrows():
            c = r["predicted"]
            row = {"truncation": r["truncation"], "aspect": a, "incidence": r["incidence"], "lobe": r["lobe"],
                   "peak": r["peak"], "exact_peak": np.nan, "exact_peak_elevation": np.nan}
            if np.isfinite(c):
                el = np.arange(np.ceil((c - halfwidth) / step) * step, c + halfwidth + 1e-9, step)
                el = el[(el > 0) & (el < 180)]
                if len(el):
                    out = reference_sweep(r["truncation"], a, r["incidence"], np.zeros_like(el), el, lighting)
                    k = int(np.argmax(out["specular"]))
                    peak = float(out["specular"][k])
                    row.update(exact_peak=peak, exact_peak_elevation=float(el[k]) if peak >= MIN_LOBE_PEAK else np.nan)
            rows.append(row)
    out = pd.DataFrame(rows, columns=SURFACE_KEYS + ["lobe", "peak", "exact_peak", "exact_peak_elevation"])
    out["error"] = out["peak"] - out["exact_peak"]
    return out


def thesis_tables(
    lobes: pd.DataFrame,
    aspects=(1.0, SQRT3_2),
    incidence: float = THESIS_INCIDENCE,
    m: float = 127.0,
    k: float | None = None,
    exact: pd.DataFrame | None = None,
) -> tuple[pd.DataFrame, list[str]]:
    """Tables 1 and 2 of the thesis, from our lobe peaks, one pair per aspect.

    Parameters
    ----------
    lobes : DataFrame
        :func:`arc_lobes` output (phi = 0 arc).
    aspects : sequence of float
        Aspects to tabulate (matched within 1e-9); missing ones are reported
        in the messages, not an error.
    incidence : float
        Degrees (the thesis: 30).
    m, k : float
        See :func:`thesis_model_predictions`; ``k=None`` (default) takes it
        from geometry for each aspect (:func:`front_facet_share`).
    exact : DataFrame, optional
        :func:`exact_lobe_peaks` output: adds rows computed from the exact
        peaks (source 'exact geometry'), which separate the renderer's
        sampling error from the models' error.

    Returns
    -------
    table : DataFrame (long), one row per table x aspect x model x source:
        ``table`` (1 | 2), ``aspect``, ``aspect_label``, ``model`` (the
        thesis's row label), ``source`` ('ours' | 'exact geometry' |
        'thesis 2001'), the
        :data:`TABLE_METRICS`, ``n``, ``SSE``, ``converged``, ``note``.
        The thesis's rows are repeated for each aspect so that every table
        carries them.
    messages : list of str
    """
    rows, messages = [], []
    for table, found, data, t, k_used, lobe, model, pred in _table_cells(lobes, aspects, incidence, m, k, messages):
        common = {"table": table, "aspect": found, "aspect_label": aspect_label(found), "model": model}
        truncations = ", ".join(f"{x:g}" for x in t)
        stats = fit_statistics(data[lobe].to_numpy(float), pred)
        rows.append({**common, "source": "ours", **stats, "m": m, "k": k_used, "truncations": truncations})
        if exact is not None and len(exact):
            ex = exact.rename(columns={"exact_peak": "_exact"})
            exact_data = _table_data(ex, found, incidence, "_exact").reindex(data.index)
            if lobe in exact_data:
                stats = fit_statistics(exact_data[lobe].to_numpy(float), pred)
                rows.append({**common, "source": "exact geometry", **stats, "m": m, "k": k_used,
                             "truncations": truncations})
        thesis = dict(zip(TABLE_METRICS, THESIS_TABLES[table]["rows"][model]))
        rows.append({**common, "source": "thesis 2001", **thesis, "n": 11, "SSE": np.nan, "converged": True,
                     "note": "Slattery (2001), Table %d" % table, "truncations": "0, 0.1, ..., 1"})
    return pd.DataFrame(rows), messages


def bootstrap_statistics(observed, predicted, n_boot: int = 2000, seed: int = 0, level: float = 0.95) -> dict:
    """Percentile bootstrap intervals of the Tables 1-2 statistics.

    The (observed, predicted) pairs are resampled with replacement ``n_boot``
    times (seeded). For a Gaussian family with identity link IRLS converges
    to ordinary least squares, so ``b0``, ``b1`` and ``RSS`` are computed in
    closed form for every resample (:func:`fit_statistics` gives the same
    numbers on the original sample through statsmodels; a test checks it).

    Returns
    -------
    dict: metric -> (low, high) for the :data:`TABLE_METRICS`, plus
    ``n_boot_used`` (resamples whose predictions were not all equal: a
    regression line needs two distinct x) and ``n``.
    """
    y = np.asarray(observed, float)
    x = np.asarray(predicted, float)
    ok = np.isfinite(y) & np.isfinite(x)
    y, x = y[ok], x[ok]
    n = len(y)
    out = {metric: (np.nan, np.nan) for metric in TABLE_METRICS}
    out.update(n=n, n_boot_used=0)
    if n < 3:
        return out
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, n, size=(n_boot, n))
    ys, xs = y[idx], x[idx]
    err = ys - xs
    xm, ym = xs.mean(axis=1, keepdims=True), ys.mean(axis=1, keepdims=True)
    sxx = np.sum((xs - xm) ** 2, axis=1)
    usable = sxx > 1e-12
    b1 = np.where(usable, np.sum((xs - xm) * (ys - ym), axis=1) / np.where(usable, sxx, 1.0), np.nan)
    b0 = ym[:, 0] - b1 * xm[:, 0]
    rss = np.sum((ys - (b0[:, None] + b1[:, None] * xs)) ** 2, axis=1)
    draws = {
        "Mean Abs Error": np.mean(np.abs(err), axis=1),
        "Standard Deviation": np.std(err, axis=1, ddof=1),
        "b0": b0,
        "b1": b1,
        "RSS": rss,
    }
    tail = 100.0 * (1.0 - level) / 2.0
    for metric, values in draws.items():
        values = values[usable] if metric in ("b0", "b1", "RSS") else values
        if len(values):
            out[metric] = (float(np.percentile(values, tail)), float(np.percentile(values, 100.0 - tail)))
    out["n_boot_used"] = int(usable.sum())
    return out


def bootstrap_tables(lobes: pd.DataFrame, aspects=(1.0, SQRT3_2), incidence: float = THESIS_INCIDENCE,
                     m: float = 127.0, k: float | None = None, n_boot: int = 2000, seed: int = 0) -> pd.DataFrame:
    """95% bootstrap intervals of our Tables 1-2 statistics (the 'ours' rows of :func:`thesis_tables`).

    Returns
    -------
    DataFrame, one row per table x aspect x model x metric: ``table``,
    ``aspect``, ``aspect_label``, ``model``, ``metric``, ``low``, ``high``,
    ``n``, ``n_boot``, ``n_boot_used``. Aspects missing from the study are
    left out (thesis_tables reports them).
    """
    rows = []
    for table, found, data, t, k_used, lobe, model, pred in _table_cells(lobes, aspects, incidence, m, k, []):
        ci = bootstrap_statistics(data[lobe].to_numpy(float), pred, n_boot=n_boot, seed=seed)
        for metric in TABLE_METRICS:
            rows.append({"table": table, "aspect": found, "aspect_label": aspect_label(found), "model": model,
                         "metric": metric, "low": ci[metric][0], "high": ci[metric][1], "n": ci["n"],
                         "n_boot": n_boot, "n_boot_used": ci["n_boot_used"]})
    return pd.DataFrame(rows, columns=["table", "aspect", "aspect_label", "model", "metric", "low", "high", "n",
                                       "n_boot", "n_boot_used"])


def sine_refits(lobes: pd.DataFrame, aspects=(1.0, SQRT3_2), incidence: float = THESIS_INCIDENCE,
                m: float = 127.0) -> pd.DataFrame:
    """Nonlinear least-squares refits of the thesis's sine models with 95% confidence intervals.

    Forward: ``I = A (1 - sin(w t))``; back: ``I = A sin(w t)`` (the thesis
    fixed ``A = m`` resp. ``m / 2`` and ``w = pi/2``). Intervals are
    ``estimate +- t_{0.975, n-2} se`` from the covariance of
    :func:`scipy.optimize.curve_fit`.

    Returns
    -------
    DataFrame, one row per aspect x lobe x parameter: ``aspect``,
    ``aspect_label``, ``lobe``, ``parameter`` ('A' (0-255) | 'omega'
    (rad per unit truncation)), ``estimate``, ``ci_low``, ``ci_high``,
    ``thesis_value``, ``thesis_inside`` (bool), ``rss``, ``n``, ``note``.
    """
    from scipy import stats
    from scipy.optimize import curve_fit

    models = {
        "forward": (lambda t, A, w: A * (1.0 - np.sin(w * t)), m),
        "back": (lambda t, A, w: A * np.sin(w * t), m / 2.0),
    }
    rows = []
    for wanted in aspects:
        found = find_aspect(lobes["aspect"], wanted)
        if found is None:
            continue
        data = _table_data(lobes, found, incidence)
        t = data.index.to_numpy(float)
        for lobe, (f, A0) in models.items():
            base = {"aspect": found, "aspect_label": aspect_label(found), "lobe": lobe}
            y = data[lobe].to_numpy(float) if lobe in data else np.array([])
            ok = np.isfinite(y)
            tt, yy = t[ok], y[ok]
            note, est, ci, rss = "", [np.nan, np.nan], [(np.nan, np.nan)] * 2, np.nan
            if len(yy) < 3:
                note = f"only {len(yy)} points: no fit"
            else:
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        popt, pcov = curve_fit(f, tt, yy, p0=[A0, np.pi / 2], maxfev=20000)
                    est = list(map(float, popt))
                    rss = float(np.sum((yy - f(tt, *popt)) ** 2))
                    dof = len(yy) - 2
                    if dof > 0 and np.all(np.isfinite(pcov)):
                        q = stats.t.ppf(0.975, dof)
                        se = np.sqrt(np.diag(pcov))
                        ci = [(p - q * s, p + q * s) for p, s in zip(popt, se)]
                    else:
                        note = "no confidence interval (no residual degrees of freedom or singular covariance)"
                except (RuntimeError, ValueError) as exc:
                    note = f"fit failed: {exc}"
            for j, (param, thesis_value) in enumerate((("A", A0), ("omega", np.pi / 2))):
                lo, hi = ci[j]
                rows.append({**base, "parameter": param, "estimate": est[j], "ci_low": lo, "ci_high": hi,
                             "thesis_value": thesis_value,
                             "thesis_inside": bool(np.isfinite(lo) and lo <= thesis_value <= hi),
                             "rss": rss, "n": int(len(yy)), "note": note})
    return pd.DataFrame(rows, columns=["aspect", "aspect_label", "lobe", "parameter", "estimate", "ci_low",
                                       "ci_high", "thesis_value", "thesis_inside", "rss", "n", "note"])


def front_facet_share(aspect: float, incidence: float = THESIS_INCIDENCE) -> float:
    """The back-lobe area factor ``k`` from geometry.

    The share of the image that the full pyramid's light-facing facet fills,
    visible and lit, seen from its mirror direction (exact polygon clipping):
    0.5 at aspects 1 and sqrt(3)/2 with incidence 30. NaN when that mirror
    direction is below the horizon (no back lobe).
    """
    from .reference import visible_lit_areas

    back = lobe_centres(incidence, aspect)["back"]
    if back is None:
        return float("nan")
    return float(visible_lit_areas(1.0, aspect, incidence, 0.0, back).get("east", (0.0, 0.0))[0])


def reflecting_areas(aspect: float, incidence: float = THESIS_INCIDENCE, truncations=None) -> pd.DataFrame:
    """Visible-and-lit areas of the reflecting facets against truncation (the thesis's Fig. 24).

    For each truncation, the top's share of the image seen from the forward
    mirror direction and the light-facing facet's share seen from the back
    mirror direction (exact polygon clipping,
    :func:`roughlight.reference.visible_lit_areas`), beside the normalised
    square and triangle area functions ``(1 - t)^2`` and
    ``k (1 - (1 - t)^2)`` with ``k`` the full pyramid's value.

    Returns
    -------
    DataFrame: ``truncation``, ``top`` and ``front`` (fractions of the image,
    0-1), ``square_area`` and ``triangle_area`` (same scale), ``k``.
    """
    from .reference import visible_lit_areas

    t_values = np.linspace(0, 1, 21) if truncations is None else np.asarray(truncations, float)
    centres = lobe_centres(incidence, aspect)
    rows = []
    for t in t_values:
        top = visible_lit_areas(t, aspect, incidence, 0.0, centres["forward"]).get("top", (0.0, 0.0))[0]
        front = np.nan
        if centres["back"] is not None:
            front = visible_lit_areas(t, aspect, incidence, 0.0, centres["back"]).get("east", (0.0, 0.0))[0]
        rows.append({"truncation": float(t), "top": float(top), "front": float(front)})
    out = pd.DataFrame(rows)
    k = front_facet_share(aspect, incidence)
    out["square_area"] = (1 - out["truncation"]) ** 2
    out["triangle_area"] = k * (1 - (1 - out["truncation"]) ** 2)
    out["k"] = k
    return out


# ---------------------------------------------------------------------------
# GLMs over the whole grid


@dataclass
class GLMResult:
    """One response's grid GLM: summary row, coefficient rows, diagnostic rows, messages."""

    response: str
    summary: dict
    coefficients: pd.DataFrame
    diagnostics: pd.DataFrame
    messages: list


def _scaled_condition(X: np.ndarray) -> float:
    """Condition number of the design with every non-constant column centred and scaled to unit norm."""
    Z = []
    for col in X.T:
        c = col - col.mean()
        nrm = np.linalg.norm(c)
        if nrm > 0:
            Z.append(c / nrm)
    if not Z:
        return np.nan
    Z = np.column_stack(Z)
    return float(np.linalg.cond(Z))


def grid_glm(data: pd.DataFrame, response: str, collinearity_limit: float = 100.0) -> GLMResult:
    """Gaussian GLM (IRLS) of one response over the grid: truncation, aspect, their interaction (and incidence).

    Plate surfaces (truncation 0 or aspect 0) are the same surface whatever
    the other parameter is (zero-variance cells): they are kept out of the fit.
    Predictors without variance are dropped; terms are dropped (interaction
    first, then incidence) while the centred-and-scaled design's condition
    number exceeds ``collinearity_limit`` or the design is rank deficient.
    Every such decision is a message; nothing raises.

    Parameters
    ----------
    data : DataFrame with ``truncation``, ``aspect``, ``incidence`` and ``response`` columns.
    response : str
    collinearity_limit : float
        Largest acceptable condition number of the scaled design (30 is
        Belsley's "moderate", 100 "strong" dependence).

    Returns
    -------
    GLMResult
        ``summary``: n, terms, dropped terms, converged, iterations, deviance,
        AIC, pseudo R^2, condition numbers (raw and scaled), status;
        ``coefficients``: term, estimate, std error, z, p, 95% CI;
        ``diagnostics``: per surface fitted value, response/Pearson residuals,
        leverage (hat), Cook's distance.
    """
    import statsmodels.api as sm

    messages = []
    summary = {"response": response, "n": 0, "terms": "", "dropped": "", "converged": False, "iterations": np.nan,
               "deviance": np.nan, "aic": np.nan, "pseudo_r2": np.nan, "condition_raw": np.nan,
               "condition_scaled": np.nan, "status": "not fitted"}
    empty = GLMResult(response, summary, pd.DataFrame(), pd.DataFrame(), messages)
    if response not in data:
        messages.append(f"{response}: no such column")
        return empty
    d = data[SURFACE_KEYS + [response]].copy()
    plate = (d["truncation"] * d["aspect"]) < 1e-9
    if plate.any():
        messages.append(
            f"{response}: {int(plate.sum())} plate surfaces (truncation 0 or aspect 0: the same flat plate "
            "whatever the other parameter) kept out of the fit"
        )
    d = d[~plate]
    n_nan = int(d[response].isna().sum())
    if n_nan:
        messages.append(f"{response}: {n_nan} surfaces without a value (no lobe found) kept out of the fit")
    d = d.dropna()
    terms = []
    for name in ("truncation", "aspect", "incidence"):
        nun = d[name].nunique()
        if nun > 1:
            terms.append(name)
        elif name != "incidence" or len(d):
            if name != "incidence":
                messages.append(f"{response}: {name} takes {nun} value(s) outside the plate: dropped (zero variance)")
    if "truncation" in terms and "aspect" in terms:
        terms.insert(2, "truncation:aspect")

    def design(ts):
        cols = [np.ones(len(d))]
        for term in ts:
            if ":" in term:
                a_, b_ = term.split(":")
                cols.append(d[a_].to_numpy(float) * d[b_].to_numpy(float))
            else:
                cols.append(d[term].to_numpy(float))
        return np.column_stack(cols)

    dropped = []
    while terms:
        X = design(terms)
        rank = np.linalg.matrix_rank(X)
        kappa = _scaled_condition(X)
        if rank == X.shape[1] and kappa <= collinearity_limit:
            break
        victim = next((x for x in ("truncation:aspect", "incidence") if x in terms), terms[-1])
        why = "rank deficient" if rank < X.shape[1] else f"scaled condition number {kappa:.3g} > {collinearity_limit:g}"
        messages.append(f"{response}: near-collinear design ({why}): term {victim} kept out of the fit")
        terms.remove(victim)
        dropped.append(victim)
    summary["dropped"] = ", ".join(dropped)
    summary["n"] = int(len(d))
    if not terms:
        messages.append(f"{response}: no predictor varies: nothing to fit")
        return GLMResult(response, summary, pd.DataFrame(), pd.DataFrame(), messages)
    X = design(terms)
    if len(d) <= X.shape[1]:
        messages.append(f"{response}: {len(d)} surfaces for {X.shape[1]} coefficients: not fitted")
        return GLMResult(response, summary, pd.DataFrame(), pd.DataFrame(), messages)
    y = d[response].to_numpy(float)
    names = ["const"] + terms
    summary["terms"] = " + ".join(terms)
    summary["condition_raw"] = float(np.linalg.cond(X))
    summary["condition_scaled"] = _scaled_condition(X)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            res = sm.GLM(y, X, family=sm.families.Gaussian()).fit(method="IRLS", maxiter=100)
        for w in caught:
            messages.append(f"{response}: warning during the fit: {w.message}")
    except Exception as exc:
        messages.append(f"{response}: the GLM failed ({exc}): not fitted")
        summary["status"] = "failed"
        return GLMResult(response, summary, pd.DataFrame(), pd.DataFrame(), messages)
    summary["converged"] = bool(res.converged)
    summary["iterations"] = int(res.fit_history.get("iteration", np.nan))
    if not res.converged:
        messages.append(f"{response}: IRLS did not converge: coefficients not reported")
        summary["status"] = "not converged"
        return GLMResult(response, summary, pd.DataFrame(), pd.DataFrame(), messages)
    summary["deviance"] = float(res.deviance)
    summary["aic"] = float(res.aic)
    null = float(np.sum((y - y.mean()) ** 2))
    summary["pseudo_r2"] = float(1.0 - res.deviance / null) if null > 0 else np.nan
    summary["status"] = "ok"
    ci = np.asarray(res.conf_int())
    coefs = pd.DataFrame({
        "response": response, "term": names, "estimate": np.asarray(res.params), "std_error": np.asarray(res.bse),
        "z": np.asarray(res.tvalues), "p_value": np.asarray(res.pvalues), "ci_low": ci[:, 0], "ci_high": ci[:, 1],
    })
    infl = res.get_influence()
    diag = d[SURFACE_KEYS].copy()
    diag["response"] = response
    diag["observed"] = y
    diag["fitted"] = np.asarray(res.fittedvalues)
    diag["residual"] = y - diag["fitted"]
    diag["pearson_residual"] = np.asarray(res.resid_pearson)
    diag["leverage"] = np.asarray(infl.hat_matrix_diag)
    diag["cooks_distance"] = np.asarray(infl.cooks_distance[0])
    return GLMResult(response, summary, coefs, diag.reset_index(drop=True), messages)


def grid_glms(lobes: pd.DataFrame, levels: pd.DataFrame, collinearity_limit: float = 100.0):
    """Grid GLMs of the forward lobe peak, back lobe peak and diffuse level.

    Parameters
    ----------
    lobes : :func:`arc_lobes` output; levels : :func:`diffuse_levels` output.

    Returns
    -------
    summary, coefficients, diagnostics : DataFrames (one block per response)
    messages : list of str
    """
    wide = lobes.pivot_table(index=SURFACE_KEYS, columns="lobe", values="peak", aggfunc="first")
    wide = wide.rename(columns={"forward": "forward_peak", "back": "back_peak"}).reset_index()
    data = levels[SURFACE_KEYS + ["diffuse_level"]].merge(wide, on=SURFACE_KEYS, how="outer")
    results = [grid_glm(data, r, collinearity_limit) for r in ("forward_peak", "back_peak", "diffuse_level")]
    summary = pd.DataFrame([r.summary for r in results])
    coefs = pd.concat([r.coefficients for r in results if len(r.coefficients)], ignore_index=True) \
        if any(len(r.coefficients) for r in results) else pd.DataFrame()
    diags = pd.concat([r.diagnostics for r in results if len(r.diagnostics)], ignore_index=True) \
        if any(len(r.diagnostics) for r in results) else pd.DataFrame()
    messages = [m for r in results for m in r.messages]
    return summary, coefs, diags, messages


# ---------------------------------------------------------------------------
# analytic rough-surface models


def _view_vectors(elevation, azimuth):
    return view_direction(np.asarray(elevation, float), np.asarray(azimuth, float))


def facet_model(truncation, aspect, incidence, elevation, azimuth, light=127.0, shininess=64.0,
                diffuse_reflectance=1.0, specular_reflectance=1.0, ambient=0.0, ambient_reflectance=1.0,
                masking="v-cavity") -> dict:
    """Torrance-Sparrow style facet model of the explicit surface (no rendering).

    The image mean is the sum over the period's facets of each facet's 8-bit
    value times its share of the image: plan area x projected-area ratio
    ``(n.V)/(n_z V_z)`` x a masking-shadowing factor ``G``. With
    ``masking='v-cavity'`` ``G`` is Torrance and Sparrow's V-groove term with
    the facet normal as the groove's facet,
    ``G = min(1, 2 n_z V_z / (n.V), 2 n_z L_z / (n.L))``; ``'none'`` uses
    ``G = 1`` (no masking, no shadowing). Facets facing away from the view
    or the light contribute nothing (ambient only).

    Parameters
    ----------
    truncation, aspect, incidence : float (incidence in degrees)
    elevation, azimuth : (n,) arrays, degrees
    light ... ambient_reflectance : the lighting (0-255 scale for ``light``)
    masking : 'v-cavity' | 'none'

    Returns
    -------
    dict of (n,) arrays: 'diffuse', 'specular' (0-255 scale).
    """
    L = light_direction(incidence)
    V = _view_vectors(elevation, azimuth)
    Vz = np.maximum(V[..., 2], 1e-12)
    amb = light * ambient_reflectance * ambient
    diffuse = np.full(V.shape[:-1], amb)
    specular = np.zeros(V.shape[:-1])
    for _, n, plan in facets(truncation, aspect):
        nv = V @ n
        nl = float(n @ L)
        if nl <= 0 or plan <= 0:
            continue
        share = plan * np.maximum(nv, 0.0) / (n[2] * Vz)
        if masking == "v-cavity":
            with np.errstate(divide="ignore", invalid="ignore"):
                g = np.minimum(1.0, np.minimum(2 * n[2] * Vz / np.where(nv > 0, nv, np.inf), 2 * n[2] * L[2] / nl))
            share = share * np.clip(g, 0.0, 1.0)
        r = 2 * nl * n - L
        spec = quantize(light * specular_reflectance * np.maximum(V @ r, 0.0) ** shininess)
        diff = quantize(light * (ambient_reflectance * ambient + diffuse_reflectance * nl)) - quantize(amb)
        diffuse = diffuse + share * diff
        specular = specular + share * spec
    grazing = (np.asarray(elevation) <= 0) | (np.asarray(elevation) >= 180)
    return {"diffuse": np.where(grazing, 0.0, diffuse), "specular": np.where(grazing, 0.0, specular)}


def oren_nayar_sigma(truncation: float, aspect: float) -> float:
    """Oren-Nayar roughness sigma (radians) from the pyramid: the RMS facet slope angle.

    Plan-area weighted over one period: ``sigma = s sqrt(1 - (1 - t)^2)``
    with ``s = atan(2 aspect)`` (the top is flat, the sides tilt ``s``).
    """
    if _plate(truncation, aspect):
        return 0.0
    s = math.radians(side_slope_deg(aspect))
    return s * math.sqrt(1.0 - (1.0 - float(truncation)) ** 2)


def oren_nayar(incidence, elevation, azimuth, sigma: float, light=127.0, diffuse_reflectance=1.0,
               ambient=0.0, ambient_reflectance=1.0) -> np.ndarray:
    """Oren and Nayar's qualitative model (1994) of a rough diffuse surface, 0-255 scale.

    ``I = J m_d cos(theta_i) [A + B max(0, cos(phi_r - phi_i)) sin(alpha) tan(beta)]``
    with ``A = 1 - 0.5 s2/(s2 + 0.33)``, ``B = 0.45 s2/(s2 + 0.09)``,
    ``s2 = sigma^2``, ``alpha = max(theta_i, theta_r)``,
    ``beta = min(theta_i, theta_r)``; polar angles from the zenith. sigma = 0
    is Lambert (the plate).

    Parameters
    ----------
    incidence : float, degrees; elevation, azimuth : (n,) degrees; sigma : radians.

    Returns
    -------
    (n,) array
    """
    e = np.asarray(elevation, float)
    phi = np.asarray(azimuth, float)
    ti = math.radians(90.0 - float(incidence))
    tr = np.radians(np.abs(90.0 - e))
    cos_dphi = np.where(e <= 90.0, np.cos(np.radians(phi)), -np.cos(np.radians(phi)))
    s2 = float(sigma) ** 2
    A = 1.0 - 0.5 * s2 / (s2 + 0.33)
    B = 0.45 * s2 / (s2 + 0.09)
    alpha = np.maximum(ti, tr)
    beta = np.minimum(ti, tr)
    value = light * (ambient_reflectance * ambient + diffuse_reflectance * math.cos(ti)
                     * (A + B * np.maximum(0.0, cos_dphi) * np.sin(alpha) * np.tan(beta)))
    return np.where((e <= 0) | (e >= 180), 0.0, value)


def hapke_opposition(phase, B0: float, h: float) -> np.ndarray:
    """Hapke's shadow-hiding opposition term ``B(g) = B0 / (1 + tan(g/2) / h)`` (g in degrees)."""
    g = np.radians(np.asarray(phase, float))
    return B0 / (1.0 + np.tan(g / 2.0) / max(h, 1e-12))


def fit_hapke(phase, values, max_phase: float = 60.0, bin_width: float = 1.0, h_range=(1e-3, 1.0)) -> dict:
    """Fit Hapke's opposition surge on a linear phase background to a surface's phase curve.

    The views within ``max_phase`` of opposition are averaged in phase bins
    of ``bin_width`` degrees (the phase curve, as Hapke's law is fitted to
    phase curves); the curve is fitted by
    ``I(g) = c + d g + S / (1 + tan(g/2) / h)``, i.e. the surge
    ``c B(g)`` with ``B(g) = B0 / (1 + tan(g/2) / h)``, ``B0 = S / c``, on a
    background ``c + d g`` (a first-order phase function, which Hapke's full
    model supplies separately). For a given ``h`` the model is linear in
    ``(c, d, S)`` (least squares, ``S >= 0``); ``h`` comes from a grid search
    over ``h_range`` refined by a bounded scalar minimisation (log scale).

    Parameters
    ----------
    phase, values : (n,) arrays (degrees, 0-255)
    max_phase : float
        Only views with ``g <= max_phase`` degrees are used.
    bin_width : float
        Degrees per phase bin.
    h_range : (float, float)
        Range of the angular width parameter ``h``.

    Returns
    -------
    dict: ``c`` (0-255), ``d`` (0-255 per degree), ``S`` (surge amplitude,
    0-255), ``B0`` (S / c; NaN when c <= 0), ``h``, ``rmse`` (on the phase
    curve, 0-255), ``rmse_constant`` (the background ``c + d g`` alone),
    ``n`` (phase bins), ``note``.
    """
    from scipy.optimize import minimize_scalar

    g = np.asarray(phase, float)
    v = np.asarray(values, float)
    ok = (g <= max_phase) & np.isfinite(v) & np.isfinite(g)
    g, v = g[ok], v[ok]
    if len(g):
        idx = np.floor(g / bin_width).astype(int)
        uniq, inv = np.unique(idx, return_inverse=True)
        v = np.bincount(inv, weights=v) / np.bincount(inv)
        g = np.bincount(inv, weights=g) / np.bincount(inv)
    out = {"c": np.nan, "d": np.nan, "S": np.nan, "B0": np.nan, "h": np.nan, "rmse": np.nan,
           "rmse_constant": np.nan, "n": int(len(v)), "note": ""}
    if len(v) < 5:
        out["note"] = f"only {len(v)} phase bins within {max_phase:g} deg of opposition"
        return out
    base = np.column_stack([np.ones_like(g), g])
    coef0, *_ = np.linalg.lstsq(base, v, rcond=None)
    out["rmse_constant"] = float(np.sqrt(np.mean((v - base @ coef0) ** 2)))
    if np.ptp(v) < 1e-9:
        out.update(c=float(v[0]), d=0.0, S=0.0, B0=0.0, rmse=0.0, note="constant: no opposition surge")
        return out
    tg = np.tan(np.radians(g) / 2.0)

    def solve(log_h):
        b = 1.0 / (1.0 + tg / math.exp(log_h))
        X = np.column_stack([base, b])
        coef, *_ = np.linalg.lstsq(X, v, rcond=None)
        if coef[2] < 0:  # the surge must add light: fall back to the background alone
            coef = np.array([coef0[0], coef0[1], 0.0])
        r = v - X @ coef
        return coef, float(r @ r)

    lo, hi = math.log(h_range[0]), math.log(h_range[1])
    grid = np.linspace(lo, hi, 41)
    rss = np.array([solve(x)[1] for x in grid])
    j = int(np.argmin(rss))
    a_, b_ = grid[max(j - 1, 0)], grid[min(j + 1, len(grid) - 1)]
    best = minimize_scalar(lambda x: solve(x)[1], bounds=(a_, b_), method="bounded", options={"xatol": 1e-4})
    log_h = float(best.x) if best.fun <= rss[j] else float(grid[j])
    (c, d, S), r = solve(log_h)
    if S <= 1e-9 * max(1.0, float(np.abs(v).max())):  # rounding, not a surge
        (c, d), S, r = coef0, 0.0, float(np.sum((v - base @ coef0) ** 2))
    out.update(c=float(c), d=float(d), S=float(S), B0=float(S / c) if c > 0 else np.nan, h=math.exp(log_h),
               rmse=float(math.sqrt(r / len(v))))
    if S <= 0:
        out.update(h=np.nan, note="no surge: the background alone fits best")
    elif abs(log_h - lo) < 1e-3 or abs(log_h - hi) < 1e-3:
        out["note"] = f"h at the edge of its range ({h_range[0]:g}..{h_range[1]:g}): no distinct surge width"
    if S > 0 and not c > 0:
        out["note"] = (out["note"] + "; " if out["note"] else "") + "background intercept <= 0: B0 undefined"
    return out


#: RMSEs closer than this (0-255 scale) are a tie; the simpler model (listed first) wins it.
RMSE_TIE = 1e-6


def _best(errors: dict):
    """The first key whose error is within :data:`RMSE_TIE` of the smallest (None if all are NaN)."""
    vals = {k: v for k, v in errors.items() if v is not None and np.isfinite(v)}
    if not vals:
        return None
    lo = min(vals.values())
    return next(k for k, v in vals.items() if v <= lo + RMSE_TIE)


def _rmse(a, b, mask=None):
    d = np.asarray(a, float) - np.asarray(b, float)
    if mask is not None:
        d = d[mask]
    d = d[np.isfinite(d)]
    return float(np.sqrt(np.mean(d**2))) if len(d) else np.nan


def analytic_model_fits(study: pd.DataFrame, lighting: dict | None = None,
                        hapke_max_phase: float = 60.0) -> pd.DataFrame:
    """Fit errors of analytic rough-surface models against every surface of the study.

    Over all non-grazing views of each surface:

    * diffuse: Lambert (the plate, i.e. the ``control`` column); Oren-Nayar
      with sigma from the pyramid's slopes (:func:`oren_nayar_sigma`) and with
      sigma fitted (1 parameter); the Torrance-Sparrow V-cavity facet model
      (:func:`facet_model`).
    * specular: Phong on the plate (``control``); the facet model without
      masking and with the V-cavity masking-shadowing term.
    * opposition: Hapke's surge ``B(g)`` on a linear phase background
      (:func:`fit_hapke`) fitted to the total and to the diffuse component
      of the views within ``hapke_max_phase`` of zero phase, beside the
      background alone.

    Parameters
    ----------
    study : DataFrame; lighting : dict of Lighting fields (reflectances; the
    light level, shininess and ambient come from the study itself when present).

    Returns
    -------
    DataFrame, one row per surface: keys, ``sigma_geometric``,
    ``sigma_fitted`` (radians), the ``rmse_*`` columns (0-255),
    ``hapke_B0``, ``hapke_h``, ``best_diffuse``, ``best_specular``.
    """
    from scipy.optimize import minimize_scalar

    lighting = dict(lighting or {})
    st = _settings(study)
    J = st["light"]
    zeta = st["shininess"]
    amb = st["ambient"]
    md = float(lighting.get("diffuse_reflectance", 1.0))
    ms = float(lighting.get("specular_reflectance", 1.0))
    ma = float(lighting.get("ambient_reflectance", 1.0))
    comp = study["component"].astype(str)
    cols = SURFACE_KEYS + ["azimuth", "elevation", "phase", "rough", "control", "coverage"]
    diff = study.loc[comp == "diffuse", cols]
    spec = study.loc[comp == "specular", cols]
    tot = study.loc[comp == "total", cols]
    spec_groups = dict(list(spec.groupby(SURFACE_KEYS, sort=True)))
    tot_groups = dict(list(tot.groupby(SURFACE_KEYS, sort=True)))
    rows = []
    for key, gd in diff.groupby(SURFACE_KEYS, sort=True):
        t, a, i = (float(k) for k in key)
        gs, gt = spec_groups[key], tot_groups[key]
        m = gd["coverage"].to_numpy(float) > 0
        e, phi = gd["elevation"].to_numpy(float), gd["azimuth"].to_numpy(float)
        yd = gd["rough"].to_numpy(float)
        row = {"truncation": t, "aspect": a, "incidence": i}
        row["rmse_lambert"] = _rmse(yd, gd["control"].to_numpy(float), m)
        sig = oren_nayar_sigma(t, a)
        row["sigma_geometric"] = sig
        row["rmse_oren_nayar"] = _rmse(yd, quantize(oren_nayar(i, e, phi, sig, J, md, amb, ma)), m)
        res = minimize_scalar(lambda s: _rmse(yd, oren_nayar(i, e, phi, s, J, md, amb, ma), m),
                              bounds=(0.0, 1.5), method="bounded", options={"xatol": 1e-4})
        row["sigma_fitted"] = float(res.x)
        row["rmse_oren_nayar_fitted"] = float(res.fun)
        kw = dict(light=J, shininess=zeta, diffuse_reflectance=md, specular_reflectance=ms, ambient=amb,
                  ambient_reflectance=ma)
        es, ps = gs["elevation"].to_numpy(float), gs["azimuth"].to_numpy(float)
        ys = gs["rough"].to_numpy(float)
        ms_ = gs["coverage"].to_numpy(float) > 0
        fm = facet_model(t, a, i, e, phi, masking="v-cavity", **kw)
        row["rmse_facet_vcavity_diffuse"] = _rmse(yd, fm["diffuse"], m)
        fs = facet_model(t, a, i, es, ps, masking="v-cavity", **kw)["specular"]
        fs0 = facet_model(t, a, i, es, ps, masking="none", **kw)["specular"]
        row["rmse_phong_plate"] = _rmse(ys, gs["control"].to_numpy(float), ms_)
        row["rmse_facet_nomask_specular"] = _rmse(ys, fs0, ms_)
        row["rmse_facet_vcavity_specular"] = _rmse(ys, fs, ms_)
        mt = gt["coverage"].to_numpy(float) > 0
        hp = fit_hapke(gt["phase"].to_numpy(float)[mt], gt["rough"].to_numpy(float)[mt], hapke_max_phase)
        row.update(rmse_hapke=hp["rmse"], rmse_constant_near_opposition=hp["rmse_constant"],
                   hapke_c=hp["c"], hapke_d=hp["d"], hapke_S=hp["S"], hapke_B0=hp["B0"], hapke_h=hp["h"],
                   hapke_note=hp["note"])
        hd = fit_hapke(gd["phase"].to_numpy(float)[m], yd[m], hapke_max_phase)
        row.update(rmse_hapke_diffuse=hd["rmse"], rmse_constant_diffuse_near_opposition=hd["rmse_constant"],
                   hapke_diffuse_B0=hd["B0"], hapke_diffuse_h=hd["h"])
        dcols = {"Lambert (plate)": row["rmse_lambert"], "Oren-Nayar (geometric sigma)": row["rmse_oren_nayar"],
                 "Oren-Nayar (fitted sigma)": row["rmse_oren_nayar_fitted"],
                 "Torrance-Sparrow V-cavity facets": row["rmse_facet_vcavity_diffuse"]}
        scols = {"Phong (plate)": row["rmse_phong_plate"], "facets, no masking": row["rmse_facet_nomask_specular"],
                 "Torrance-Sparrow V-cavity facets": row["rmse_facet_vcavity_specular"]}
        row["best_diffuse"] = _best(dcols)
        row["best_specular"] = _best(scols)
        row["plate"] = _plate(t, a)
        rows.append(row)
    return pd.DataFrame(rows)


#: Model columns of :func:`analytic_model_fits` and their readable names.
MODEL_COLUMNS = {
    "diffuse": {
        "rmse_lambert": "Lambert (plate)",
        "rmse_oren_nayar": "Oren-Nayar (geometric sigma)",
        "rmse_oren_nayar_fitted": "Oren-Nayar (fitted sigma)",
        "rmse_facet_vcavity_diffuse": "Torrance-Sparrow V-cavity facets",
    },
    "specular": {
        "rmse_phong_plate": "Phong (plate)",
        "rmse_facet_nomask_specular": "facets, no masking",
        "rmse_facet_vcavity_specular": "Torrance-Sparrow V-cavity facets",
    },
    "near opposition (total)": {
        "rmse_constant_near_opposition": "linear phase background",
        "rmse_hapke": "background + Hapke B(g)",
    },
    "near opposition (diffuse)": {
        "rmse_constant_diffuse_near_opposition": "linear phase background",
        "rmse_hapke_diffuse": "background + Hapke B(g)",
    },
}


def _band(values, edges, labels):
    return pd.cut(values, edges, labels=labels, include_lowest=True)


def model_fit_summary(fits: pd.DataFrame) -> pd.DataFrame:
    """Where each analytic model fits best: median RMSE per model by surface band.

    Plate surfaces are one band; the rough surfaces are split into low and
    high truncation (t <= 0.5 / > 0.5) x low and high aspect (<= 0.5 / > 0.5).

    Returns
    -------
    DataFrame: ``component``, ``model``, ``band``, ``surfaces``,
    ``median_rmse`` (0-255), ``best_in`` (number of surfaces of the band for
    which the model has the smallest RMSE of its component).
    """
    if fits.empty:
        return pd.DataFrame(columns=["component", "model", "band", "surfaces", "median_rmse", "best_in"])
    f = fits.copy()
    tb = np.where(f["truncation"] <= 0.5, "t ≤ 0.5", "t > 0.5")
    ab = np.where(f["aspect"] <= 0.5, "aspect ≤ 0.5", "aspect > 0.5")
    f["band"] = np.where(f["plate"], "plate", pd.Series(tb).str.cat(pd.Series(ab), sep=", ").to_numpy())
    rows = []
    for component, cols in MODEL_COLUMNS.items():
        present = [c for c in cols if c in f]
        if not present:
            continue
        best = f[present].apply(lambda r: _best(r.to_dict()), axis=1)
        for band, g in f.groupby("band", sort=True):
            for c in present:
                rows.append({"component": component, "model": cols[c], "band": band, "surfaces": int(len(g)),
                             "median_rmse": float(g[c].median()), "best_in": int((best[g.index] == c).sum())})
        for c in present:
            rows.append({"component": component, "model": cols[c], "band": "all", "surfaces": int(len(f)),
                         "median_rmse": float(f[c].median()), "best_in": int((best == c).sum())})
    return pd.DataFrame(rows)


# ---------------------------------------------------------------------------
# provenance


def render_timings(study: pd.DataFrame) -> tuple[pd.DataFrame, dict]:
    """Per-sweep render timings recorded in the study (``render_seconds``).

    Returns
    -------
    per_sweep : DataFrame, one row per sweep: keys, ``method``, ``views``,
        ``seconds``, ``views_per_second``.
    summary : dict: sweeps, views, total/median/max seconds, slowest sweep,
        overall views per second, methods.
    """
    comp = study["component"].astype(str)
    first = study.loc[comp == comp.iloc[0]]
    g = first.groupby(SURFACE_KEYS, sort=True)
    per = g.agg(views=("elevation", "size"), seconds=("render_seconds", "first"),
                method=("method", lambda s: str(s.iloc[0]))).reset_index()
    per["views_per_second"] = per["views"] / per["seconds"].where(per["seconds"] > 0)
    slow = per.loc[per["seconds"].idxmax()] if len(per) else None
    summary = {
        "sweeps": int(len(per)),
        "views": int(per["views"].sum()),
        "total_seconds": float(per["seconds"].sum()),
        "median_seconds": float(per["seconds"].median()) if len(per) else np.nan,
        "max_seconds": float(per["seconds"].max()) if len(per) else np.nan,
        "slowest": (f"truncation {slow['truncation']:g}, aspect {aspect_label(slow['aspect'])}, "
                    f"incidence {slow['incidence']:g}") if slow is not None else "",
        "views_per_second": float(per["views"].sum() / per["seconds"].sum()) if per["seconds"].sum() > 0 else np.nan,
        "methods": ", ".join(sorted(per["method"].unique())),
    }
    return per, summary
