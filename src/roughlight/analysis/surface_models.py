"""Analytic rough-surface models fitted against the explicit surfaces.

The Torrance-Sparrow V-cavity facet model (:func:`facet_model`: the surface's
own facets, each lit and seen as far as V-cavity masking and shadowing
allow), Oren-Nayar's diffuse model (:func:`oren_nayar`, with sigma from the
facets' slopes or fitted) and Hapke's opposition term (:func:`fit_hapke`),
scored by RMSE on every rendered view of every surface, each once (the zenith counted once, not once per
azimuth: :func:`roughlight.render.views.distinct_views`; :func:`analytic_model_fits`)
and summarised per band of the grid (:func:`model_fit_summary`). Angles are
degrees; values 0-255.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..render.shading import light_direction, quantize, view_direction
from ..render.views import distinct_views
from ..study.selection import SURFACE_KEYS, recorded_lighting
from ..surfaces.geometry import facets, side_slope_deg
from ..surfaces.surface import is_plate


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
    if is_plate(truncation, aspect):
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
    curve, in-sample, 0-255), ``rmse_constant`` (the background ``c + d g``
    alone, in-sample: never below ``rmse``, the surge nests it),
    ``rmse_heldout`` and ``rmse_constant_heldout`` (two-fold held-out phase
    bins, :func:`_held_out`), ``aic`` and ``aic_constant`` (Gaussian AIC
    with 4 and 2 parameters: lower is better, and it charges the surge for its
    two extra parameters), ``n`` (phase bins), ``note``.
    """
    g, v = _phase_curve(phase, values, max_phase, bin_width)
    out = {"c": np.nan, "d": np.nan, "S": np.nan, "B0": np.nan, "h": np.nan, "rmse": np.nan,
           "rmse_constant": np.nan, "rmse_heldout": np.nan, "rmse_constant_heldout": np.nan, "aic": np.nan,
           "aic_constant": np.nan, "n": int(len(v)), "note": ""}
    if len(v) < 5:
        out["note"] = f"only {len(v)} phase bins within {max_phase:g} deg of opposition"
        return out
    base = np.column_stack([np.ones_like(g), g])
    coef0, *_ = np.linalg.lstsq(base, v, rcond=None)
    out["rmse_constant"] = float(np.sqrt(np.mean((v - base @ coef0) ** 2)))
    if np.ptp(v) < 1e-9:
        out.update(c=float(v[0]), d=0.0, S=0.0, B0=0.0, rmse=0.0, note="constant: no opposition surge")
        return out
    (c, d, S), log_h = _fit_surge(g, v, h_range)
    r = float(np.sum((v - _surge_curve(g, c, d, S, log_h)) ** 2))
    out.update(c=float(c), d=float(d), S=float(S), B0=float(S / c) if c > 0 else np.nan, h=math.exp(log_h),
               rmse=float(math.sqrt(r / len(v))))
    out.update(_held_out(g, v, h_range))
    # the background has 2 parameters, the surge 4 (c, d, S, h)
    out["aic"] = _aic(r, len(v), 4)
    out["aic_constant"] = _aic(float(np.sum((v - base @ coef0) ** 2)), len(v), 2)
    if S <= 0:
        out["h"] = np.nan
    out["note"] = _surge_note(c, S, log_h, h_range)
    return out


def _phase_curve(phase, values, max_phase: float, bin_width: float):
    """The phase curve of :func:`fit_hapke`: the finite views with phase ``g <= max_phase`` (degrees) averaged
    in bins of ``bin_width`` degrees. Returns each bin's mean phase and mean value, (n_bins,) each, in bin order.
    """
    g = np.asarray(phase, float)
    v = np.asarray(values, float)
    ok = (g <= max_phase) & np.isfinite(v) & np.isfinite(g)
    g, v = g[ok], v[ok]
    if len(g):
        idx = np.floor(g / bin_width).astype(int)
        uniq, inv = np.unique(idx, return_inverse=True)
        v = np.bincount(inv, weights=v) / np.bincount(inv)
        g = np.bincount(inv, weights=g) / np.bincount(inv)
    return g, v


def _aic(rss: float, n: int, k: int) -> float:
    """Gaussian AIC ``n ln(RSS / n) + 2 k`` of a least-squares fit with ``k`` parameters to ``n`` points."""
    return n * math.log(max(rss, 1e-300) / n) + 2 * k


def _surge_note(c: float, S: float, log_h: float, h_range) -> str:
    """What a fitted surge (:func:`fit_hapke`) cannot tell: no surge at all (``S <= 0``), a width ``h`` on the
    edge of ``h_range``, or no ``B0`` because the background's intercept ``c`` is not positive."""
    note = ""
    if S <= 0:
        note = "no surge: the background alone fits best"
    elif abs(log_h - math.log(h_range[0])) < 1e-3 or abs(log_h - math.log(h_range[1])) < 1e-3:
        note = f"h at the edge of its range ({h_range[0]:g}..{h_range[1]:g}): no distinct surge width"
    if S > 0 and not c > 0:
        note = (note + "; " if note else "") + "background intercept <= 0: B0 undefined"
    return note


def _surge_curve(g, c, d, S, log_h):
    return c + d * g + S / (1.0 + np.tan(np.radians(g) / 2.0) / math.exp(log_h))


def _fit_surge(g, v, h_range):
    """Least squares ``(c, d, S)`` (``S >= 0``) and ``log h`` of the surge on a linear background (see
    :func:`fit_hapke`); a surge that does not add light falls back to the background alone (``S = 0``)."""
    from scipy.optimize import minimize_scalar

    base = np.column_stack([np.ones_like(g), g])
    coef0, *_ = np.linalg.lstsq(base, v, rcond=None)
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
    (c, d, S), _ = solve(log_h)
    if S <= 1e-9 * max(1.0, float(np.abs(v).max())):  # rounding, not a surge
        (c, d), S = coef0, 0.0
    return (float(c), float(d), float(S)), log_h


def _held_out(g, v, h_range) -> dict:
    """Two-fold held-out error of the surge model and of the background alone: fitted on the even phase bins,
    scored on the odd ones, and the other way round (RMSE over all bins, 0-255). Unlike the in-sample RMSEs,
    the four-parameter surge can lose to its two-parameter background here."""
    folds = np.arange(len(g)) % 2
    err, err0 = np.zeros(len(g)), np.zeros(len(g))
    for k in (0, 1):
        train, test = folds != k, folds == k
        if train.sum() < 5:
            return {"rmse_heldout": np.nan, "rmse_constant_heldout": np.nan}
        (c, d, S), log_h = _fit_surge(g[train], v[train], h_range)
        err[test] = v[test] - _surge_curve(g[test], c, d, S, log_h)
        base = np.column_stack([np.ones(train.sum()), g[train]])
        coef0, *_ = np.linalg.lstsq(base, v[train], rcond=None)
        err0[test] = v[test] - (coef0[0] + coef0[1] * g[test])
    return {"rmse_heldout": float(np.sqrt(np.mean(err**2))), "rmse_constant_heldout": float(np.sqrt(np.mean(err0**2)))}


#: RMSEs closer than this (0-255 scale) are a tie; the simpler model (listed first) wins it.
RMSE_TIE = 1e-6
#: Oren-Nayar's sigma is fitted within these bounds (radians); a fit that ends on one is flagged.
SIGMA_BOUNDS = (0.0, 1.5)


def _best(errors: dict):
    """The first key whose error is within :data:`RMSE_TIE` of the smallest (None if all are NaN)."""
    vals = {k: v for k, v in errors.items() if v is not None and np.isfinite(v)}
    if not vals:
        return None
    lo = min(vals.values())
    return next(k for k, v in vals.items() if v <= lo + RMSE_TIE)


def _rmse(a, b, mask=None):
    """Root mean square of ``a - b`` (0-255) over the rows ``mask`` (bool, default all) with a finite difference;
    NaN when there is none."""
    d = np.asarray(a, float) - np.asarray(b, float)
    if mask is not None:
        d = d[mask]
    d = d[np.isfinite(d)]
    return float(np.sqrt(np.mean(d**2))) if len(d) else np.nan


def seen_views(views: pd.DataFrame) -> np.ndarray:
    """The rows of one surface's views of one component (``azimuth``, ``elevation``, ``coverage``) that its scores
    count: rendered (coverage above 0), each view once (:func:`roughlight.render.views.distinct_views`)."""
    return distinct_views(views["azimuth"], views["elevation"], views["coverage"])


def analytic_model_fits(study: pd.DataFrame, lighting: dict | None = None,
                        hapke_max_phase: float = 60.0) -> pd.DataFrame:
    """Fit errors of analytic rough-surface models against every surface of the study.

    Over the views of each surface that were rendered (coverage above 0), each view once: the zenith, on every
    half great circle, counts once (:func:`seen_views`):

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
    ``sigma_fitted`` (radians; ``sigma_fitted_at_bound`` when the fit ended on a bound of
    :data:`SIGMA_BOUNDS`), the ``rmse_*`` columns (0-255; every model scored on quantized,
    8-bit predictions),
    ``hapke_B0``, ``hapke_h``, ``best_diffuse``, ``best_specular``.
    """
    light = _model_lighting(study, lighting)
    comp = study["component"].astype(str)
    cols = SURFACE_KEYS + ["azimuth", "elevation", "phase", "rough", "control", "coverage"]
    diff = study.loc[comp == "diffuse", cols]
    spec = study.loc[comp == "specular", cols]
    tot = study.loc[comp == "total", cols]
    spec_groups = dict(list(spec.groupby(SURFACE_KEYS, sort=True)))
    tot_groups = dict(list(tot.groupby(SURFACE_KEYS, sort=True)))
    rows = [_surface_fits(key, gd, spec_groups[key], tot_groups[key], light, hapke_max_phase)
            for key, gd in diff.groupby(SURFACE_KEYS, sort=True)]
    return pd.DataFrame(rows)


def _model_lighting(study: pd.DataFrame, lighting: dict | None) -> dict:
    """The models' lighting as :func:`facet_model`'s keywords: the light level (0-255), shininess and ambient
    the study recorded (:func:`roughlight.study.selection.recorded_lighting`), the reflectances of
    ``lighting`` (default 1)."""
    lighting = dict(lighting or {})
    st = recorded_lighting(study)
    return dict(light=st["light"], shininess=st["shininess"],
                diffuse_reflectance=float(lighting.get("diffuse_reflectance", 1.0)),
                specular_reflectance=float(lighting.get("specular_reflectance", 1.0)), ambient=st["ambient"],
                ambient_reflectance=float(lighting.get("ambient_reflectance", 1.0)))


def _surface_fits(key, gd: pd.DataFrame, gs: pd.DataFrame, gt: pd.DataFrame, light: dict,
                  hapke_max_phase: float) -> dict:
    """One row of :func:`analytic_model_fits`: the surface ``key`` (truncation, aspect, incidence), its diffuse,
    specular and total views ``gd``, ``gs``, ``gt``, and ``light`` (:func:`_model_lighting`)."""
    t, a, i = (float(k) for k in key)
    seen = seen_views(gd)
    row = {"truncation": t, "aspect": a, "incidence": i}
    row.update(_diffuse_fits(t, a, i, gd, seen, light))
    row.update(_specular_fits(t, a, i, gs, light))
    row.update(_opposition_fits(gd, gt, seen, hapke_max_phase))
    for component in ("diffuse", "specular"):
        row[f"best_{component}"] = _best({name: row[col] for col, name in MODEL_COLUMNS[component].items()})
    row["plate"] = is_plate(t, a)
    return row


def _diffuse_fits(t: float, a: float, i: float, gd: pd.DataFrame, seen, light: dict) -> dict:
    """RMSEs (0-255) of the diffuse models on the seen views ``seen`` of one surface: Lambert (the plate's
    ``control`` values), Oren-Nayar with the geometric and the fitted sigma (:func:`_oren_nayar_fits`) and the
    V-cavity facet model."""
    e, phi = gd["elevation"].to_numpy(float), gd["azimuth"].to_numpy(float)
    yd = gd["rough"].to_numpy(float)
    row = {"rmse_lambert": _rmse(yd, gd["control"].to_numpy(float), seen)}
    sig = oren_nayar_sigma(t, a)
    row["sigma_geometric"] = sig
    row.update(_oren_nayar_fits(yd, seen, i, e, phi, sig, light))
    fm = facet_model(t, a, i, e, phi, masking="v-cavity", **light)
    row["rmse_facet_vcavity_diffuse"] = _rmse(yd, fm["diffuse"], seen)
    return row


def _oren_nayar_fits(yd, seen, i: float, e, phi, sig: float, light: dict) -> dict:
    """Oren-Nayar against the diffuse values ``yd`` at the views (elevation ``e``, azimuth ``phi``, degrees):
    with the geometric sigma ``sig`` (radians) and with sigma fitted within :data:`SIGMA_BOUNDS`.

    The fit minimises the smooth unquantized error, but both are scored as every other model, on the 8-bit
    values the framebuffer would store, and the geometric sigma is a candidate the fit must beat.
    Returns ``rmse_oren_nayar``, ``sigma_fitted``, ``rmse_oren_nayar_fitted``, ``sigma_fitted_at_bound``.
    """
    from scipy.optimize import minimize_scalar

    J, md, amb, ma = light["light"], light["diffuse_reflectance"], light["ambient"], light["ambient_reflectance"]
    geometric = _rmse(yd, quantize(oren_nayar(i, e, phi, sig, J, md, amb, ma)), seen)

    def score(s):
        return _rmse(yd, oren_nayar(i, e, phi, s, J, md, amb, ma), seen)

    res = minimize_scalar(score, bounds=SIGMA_BOUNDS, method="bounded", options={"xatol": 1e-4})
    fitted = _rmse(yd, quantize(oren_nayar(i, e, phi, float(res.x), J, md, amb, ma)), seen)
    sigma, rmse = (float(res.x), fitted) if fitted <= geometric else (sig, geometric)
    return {"rmse_oren_nayar": geometric, "sigma_fitted": sigma, "rmse_oren_nayar_fitted": rmse,
            "sigma_fitted_at_bound": bool(min(abs(sigma - b) for b in SIGMA_BOUNDS) < 1e-3 and sigma != sig)}


def _specular_fits(t: float, a: float, i: float, gs: pd.DataFrame, light: dict) -> dict:
    """RMSEs (0-255) of the specular models on one surface's seen specular views ``gs``: Phong on the plate
    (``control``), the facet model without masking and with V-cavity masking-shadowing."""
    es, ps = gs["elevation"].to_numpy(float), gs["azimuth"].to_numpy(float)
    ys = gs["rough"].to_numpy(float)
    seen = seen_views(gs)
    fs = facet_model(t, a, i, es, ps, masking="v-cavity", **light)["specular"]
    fs0 = facet_model(t, a, i, es, ps, masking="none", **light)["specular"]
    return {"rmse_phong_plate": _rmse(ys, gs["control"].to_numpy(float), seen),
            "rmse_facet_nomask_specular": _rmse(ys, fs0, seen), "rmse_facet_vcavity_specular": _rmse(ys, fs, seen)}


def _opposition_fits(gd: pd.DataFrame, gt: pd.DataFrame, seen, hapke_max_phase: float) -> dict:
    """Hapke's surge (:func:`fit_hapke`) near opposition on one surface's seen total views ``gt`` and on its
    diffuse views ``gd`` at ``seen``: the ``rmse_hapke*``, ``hapke_*`` and background columns."""
    mt = seen_views(gt)
    hp = fit_hapke(gt["phase"].to_numpy(float)[mt], gt["rough"].to_numpy(float)[mt], hapke_max_phase)
    row = dict(rmse_hapke=hp["rmse"], rmse_constant_near_opposition=hp["rmse_constant"],
               rmse_hapke_heldout=hp["rmse_heldout"], rmse_constant_heldout=hp["rmse_constant_heldout"],
               hapke_aic=hp["aic"], hapke_aic_constant=hp["aic_constant"],
               hapke_c=hp["c"], hapke_d=hp["d"], hapke_S=hp["S"], hapke_B0=hp["B0"], hapke_h=hp["h"],
               hapke_note=hp["note"])
    hd = fit_hapke(gd["phase"].to_numpy(float)[seen], gd["rough"].to_numpy(float)[seen], hapke_max_phase)
    row.update(rmse_hapke_diffuse=hd["rmse"], rmse_constant_diffuse_near_opposition=hd["rmse_constant"],
               hapke_diffuse_B0=hd["B0"], hapke_diffuse_h=hd["h"])
    return row


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
        "rmse_constant_near_opposition": "linear phase background (in-sample)",
        "rmse_hapke": "background + Hapke B(g) (in-sample)",
        "rmse_constant_heldout": "linear phase background (held-out phase bins)",
        "rmse_hapke_heldout": "background + Hapke B(g) (held-out phase bins)",
    },
    "near opposition (diffuse)": {
        "rmse_constant_diffuse_near_opposition": "linear phase background (in-sample)",
        "rmse_hapke_diffuse": "background + Hapke B(g) (in-sample)",
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
