"""The diffuse component on the light's arc: its levels and the thesis's three-part model.

The thesis (Ch. V.F) reads the diffuse curve against elevation as three
parts: a level ``L1`` up to a first break ``e1``, an exponential fall toward
a level ``L3`` up to the second break ``e2``, and ``L3`` after it; the breaks
follow from the facets' tilt (:func:`diffuse_breakpoints`). Angles are
degrees; values 0-255.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..study.selection import SURFACE_KEYS, solid_angle_weights
from ..surfaces.geometry import side_slope_deg
from ..surfaces.surface import is_plate
from .grids import arc, surface_value_grids


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


def exponential_part(e, level1, level3, rate, e1):
    """The thesis's part two, ``L3 + (L1 - L3) exp(-k (e - e1))``: level one at e1, but not level three at e2."""
    return level3 + (level1 - level3) * np.exp(-rate * (e - e1))


def continuous_part(e, level1, level3, rate, e1, e2):
    """Part two continuous at both breaks: the same exponential decay rescaled to run from L1 at e1 to L3 at e2.

    ``L3 + (L1 - L3) (exp(-k (e - e1)) - exp(-k (e2 - e1))) / (1 - exp(-k (e2 - e1)))``; it tends to the
    straight line from (e1, L1) to (e2, L3) as ``k`` goes to 0. Angles in degrees, ``k`` in 1/degree.
    """
    span = e2 - e1
    if rate * span < 1e-9:
        return level1 + (level3 - level1) * (np.asarray(e, float) - e1) / span
    far = np.exp(-rate * span)
    return level3 + (level1 - level3) * (np.exp(-rate * (np.asarray(e, float) - e1)) - far) / (1.0 - far)


def diffuse_three_part(study: pd.DataFrame, azimuth: float = 0.0) -> pd.DataFrame:
    """The thesis's three-part model of the diffuse component (Ch. V.F), fitted per surface.

    On the arc, part one (``0 < e <= e1``) and part three (``e >= e2``) are
    constant levels (their means); part two decays exponentially from level
    one to level three. Two forms of part two are fitted by least squares:
    the thesis's, ``L3 + (L1 - L3) exp(-k (e - e1))`` (:func:`exponential_part`),
    which does not reach L3 at e2 (the model jumps there by ``jump_at_e2``), and
    the same decay made continuous at both breaks (:func:`continuous_part`).
    Breakpoints from :func:`diffuse_breakpoints` (geometry). Grazing views
    (coverage 0) are left out.

    Returns
    -------
    DataFrame, one row per surface: keys, ``e1``/``e2`` (degrees),
    ``level1``/``level3`` (0-255), ``rate`` (k, 1/degree), ``decay_length``
    (1/k, degrees), ``rmse`` (whole arc, 0-255), ``rmse_part2``, ``jump_at_e2``
    (the thesis's form at e2 minus L3, 0-255); ``rate_continuous``,
    ``rmse_continuous``, ``rmse_part2_continuous`` (the continuous form);
    ``n_part1``, ``n_part2``, ``n_part3``, ``note``.
    """
    frame = arc(study, "diffuse", azimuth)
    return pd.DataFrame([_three_part_row(key, g[g["coverage"] > 0]) for key, g in frame.groupby(SURFACE_KEYS, sort=True)])


def _three_part_row(key, g: pd.DataFrame) -> dict:
    """One row of :func:`diffuse_three_part`: the surface ``key`` (truncation, aspect, incidence) and its arc's
    seen diffuse views ``g`` (elevation in degrees, ``rough`` 0-255)."""
    t, a, i = (float(k) for k in key)
    e = g["elevation"].to_numpy(float)
    v = g["rough"].to_numpy(float)
    e1, e2 = diffuse_breakpoints(i, a)
    p1, p3 = (e > 0) & (e <= e1), (e >= e2) & (e < 180)
    p2 = (e > e1) & (e < e2)
    row = {"truncation": t, "aspect": a, "incidence": i, "e1": e1, "e2": e2,
           "n_part1": int(p1.sum()), "n_part2": int(p2.sum()), "n_part3": int(p3.sum()),
           "level1": float(v[p1].mean()) if p1.any() else np.nan,
           "level3": float(v[p3].mean()) if p3.any() else np.nan,
           "rate": np.nan, "decay_length": np.nan, "rmse": np.nan, "rmse_part2": np.nan, "jump_at_e2": np.nan,
           "rate_continuous": np.nan, "rmse_continuous": np.nan, "rmse_part2_continuous": np.nan, "note": ""}
    if is_plate(t, a):
        row["note"] = "plate: one constant level, no decay"
        pred = np.full_like(v, float(v.mean())) if len(v) else v
        row["rmse"] = float(np.sqrt(np.mean((v - pred) ** 2))) if len(v) else np.nan
        return row
    if not (p1.any() and p3.any()) or p2.sum() < 3:
        row["note"] = "too few views in a part to fit"
        return row
    L1, L3 = row["level1"], row["level3"]
    row.update(_thesis_decay(e, v, p2, L1, L3, e1))
    row.update(_thesis_errors(e, v, (p1, p2, p3), L1, L3, e1, e2, row["rate"]))
    if abs(L1 - L3) >= 1e-9:
        row.update(_continuous_fit(e, v, p1, p2, p3, L1, L3, e1, e2))
    return row


def _thesis_decay(e, v, p2, L1: float, L3: float, e1: float) -> dict:
    """The rate ``k`` (1/degree, in [0, 10]) of the thesis's part two (:func:`exponential_part`) fitted by least
    squares to the views ``p2`` (elevations ``e``, values ``v``), and its ``decay_length`` 1/k (degrees); or a
    ``note`` saying why there is none (equal levels, a failed fit)."""
    from scipy.optimize import curve_fit

    if abs(L1 - L3) < 1e-9:
        return {"note": "levels one and three equal: no decay to fit"}
    try:
        def decay(x, k, L1=L1, L3=L3, e1=e1):
            return exponential_part(x, L1, L3, k, e1)

        (rate,), _ = curve_fit(decay, e[p2], v[p2], p0=[0.05], bounds=([0.0], [10.0]))
        return {"rate": float(rate), "decay_length": float(1.0 / rate) if rate > 0 else np.inf}
    except (RuntimeError, ValueError) as exc:
        return {"note": f"decay fit failed: {exc}"}


def _thesis_errors(e, v, parts, L1: float, L3: float, e1: float, e2: float, rate: float) -> dict:
    """Errors (0-255) of the thesis's three-part model with part two's ``rate`` (NaN: none fitted): ``rmse``
    over the arc's views with a prediction, ``rmse_part2``, and ``jump_at_e2``, its part two at e2 minus L3.
    ``parts`` are the three parts' masks of the views (elevations ``e``, values ``v``)."""
    p1, p2, p3 = parts
    out = {}
    decay = exponential_part(e, L1, L3, rate, e1) if np.isfinite(rate) else np.nan
    pred = np.where(p1, L1, np.where(p3, L3, decay))
    ok = np.isfinite(pred)
    out["rmse"] = float(np.sqrt(np.mean((v[ok] - pred[ok]) ** 2)))
    out["rmse_part2"] = float(np.sqrt(np.mean((v[p2] - pred[p2]) ** 2))) if np.isfinite(rate) else np.nan
    if np.isfinite(rate):
        out["jump_at_e2"] = float(exponential_part(e2, L1, L3, rate, e1) - L3)
    return out


def _continuous_fit(e, v, p1, p2, p3, L1, L3, e1, e2) -> dict:
    """Rate and errors of the three-part model with part two continuous at both breaks."""
    from scipy.optimize import curve_fit

    def decay(x, k):
        return continuous_part(x, L1, L3, k, e1, e2)

    try:
        (rate,), _ = curve_fit(decay, e[p2], v[p2], p0=[0.05], bounds=([0.0], [10.0]))
    except (RuntimeError, ValueError):
        return {}
    pred = np.where(p1, L1, np.where(p3, L3, decay(e, rate)))
    return {"rate_continuous": float(rate), "rmse_continuous": float(np.sqrt(np.mean((v - pred) ** 2))),
            "rmse_part2_continuous": float(np.sqrt(np.mean((v[p2] - pred[p2]) ** 2)))}


def diffuse_levels(study: pd.DataFrame) -> pd.DataFrame:
    """Solid-angle-weighted hemisphere mean of the diffuse component per surface, over the views that see
    the surface (coverage > 0: the grazing views, which see none, are left out).

    Returns
    -------
    DataFrame: surface keys, ``diffuse_level`` (rough, 0-255),
    ``control_level`` (the plate's), ``ratio`` (rough / control).
    """
    rows = []
    for key, az, el, grids in surface_value_grids(study, "diffuse", ("rough", "control", "coverage")):
        vals, cv, seen = grids["rough"], grids["control"], grids["coverage"] > 0
        w = solid_angle_weights(az, el)
        # views that see no surface (the grazing ones, coverage 0) measure nothing: out of the average
        ok = np.isfinite(vals) & seen
        level = float(np.sum(w[ok] * vals[ok]) / np.sum(w[ok]))
        cok = np.isfinite(cv) & seen
        control = float(np.sum(w[cok] * cv[cok]) / np.sum(w[cok]))
        rows.append({"truncation": key[0], "aspect": key[1], "incidence": key[2], "diffuse_level": level,
                     "control_level": control, "ratio": level / control if control > 0 else np.nan})
    return pd.DataFrame(rows)
