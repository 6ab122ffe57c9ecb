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

from .geometry import side_slope_deg
from .selection import SURFACE_KEYS, arc, solid_angle_weights, surface_grids
from .surface import is_plate


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
        if is_plate(t, a):
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
                def decay(x, k, L1=L1, L3=L3, e1=e1):
                    return exponential_part(x, L1, L3, k, e1)

                (rate,), _ = curve_fit(decay, e[p2], v[p2], p0=[0.05], bounds=([0.0], [10.0]))
                row["rate"] = float(rate)
                row["decay_length"] = float(1.0 / rate) if rate > 0 else np.inf
            except (RuntimeError, ValueError) as exc:
                row["note"] = f"decay fit failed: {exc}"
        decay = exponential_part(e, L1, L3, row["rate"], e1) if np.isfinite(row["rate"]) else np.nan
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
        w = solid_angle_weights(az, el)
        ok = np.isfinite(vals)
        level = float(np.sum(w[ok] * vals[ok]) / np.sum(w[ok]))
        caz, cel, cv = controls[key]
        cw = solid_angle_weights(caz, cel)
        cok = np.isfinite(cv)
        control = float(np.sum(cw[cok] * cv[cok]) / np.sum(cw[cok]))
        rows.append({"truncation": key[0], "aspect": key[1], "incidence": key[2], "diffuse_level": level,
                     "control_level": control, "ratio": level / control if control > 0 else np.nan})
    return pd.DataFrame(rows)
