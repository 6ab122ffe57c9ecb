"""Combined truncation x aspect models of the lobe peaks: the share laws the geometry dictates, beside a
flexible statistical model and the linear grid GLM, each scored over the grid and on held-out surfaces.

A lobe's peak is the reflecting facets' share of the image times their 8-bit
specular value at the mirror direction, ``m`` (``J * m_s``, 127 by default):

* forward (the tops): ``m (1 - t)^2``, no free parameter;
* back (the light-facing sides): ``m k(a) (1 - (1 - t)^2)``, with ``k(a)`` the
  full pyramid's share of the image seen from its back mirror direction,
  from geometry (:func:`roughlight.surfaces.geometry.front_facet_share`, exact
  polygon clipping) or fitted, one ``k`` per aspect (least squares);
* flexible: a quasi-binomial GLM with a logit link on the share ``peak / m``
  with truncation, aspect and their interaction (statsmodels, Pearson
  scale), so predictions stay within ``[0, m]``;
* baseline: the linear Gaussian GLM ``peak ~ t + a + t:a`` of :mod:`roughlight.analysis.glm`.

Held-out errors are leave-one-surface-out: each surface predicted by the
model fitted without it (a model with no free parameter scores the same
in-sample and held out). The data are deterministic: these are errors of
fit and of interpolation, not sampling uncertainty.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..study.selection import SURFACE_KEYS

__all__ = ["MODELS", "lobe_peaks", "share_law_fits"]

#: The combined models, in the order the tables show them.
MODELS = ("share law, geometric k", "share law, k fitted per aspect", "quasi-binomial GLM (logit share)",
          "linear GLM (baseline)")


def lobe_peaks(lobes: pd.DataFrame, lobe: str) -> pd.DataFrame:
    """The flag-free peaks of one lobe on rough surfaces (plates and flagged maxima left out)."""
    sel = lobes[(lobes["lobe"] == lobe) & np.isfinite(lobes["peak"]) & (lobes["note"].fillna("") == "")]
    sel = sel[(sel["truncation"] * sel["aspect"]) > 1e-9]
    return sel[SURFACE_KEYS + ["peak"]].reset_index(drop=True)


def _triangle(t):
    return 1.0 - (1.0 - np.asarray(t, float)) ** 2


def _geometric_k(aspects, incidence) -> dict:
    from .areas import front_facet_share

    return {float(a): float(front_facet_share(a, incidence)) for a in np.unique(aspects)}


def _predict_physics(lobe, train, test, m, k_mode, k_geo):
    t = test["truncation"].to_numpy(float)
    if lobe == "forward":
        return m * (1.0 - t) ** 2
    if k_mode == "geometric":
        k = test["aspect"].map(lambda a: k_geo[float(a)]).to_numpy(float)
        return m * k * _triangle(t)
    out = np.full(len(test), np.nan)
    for a, rows in test.groupby("aspect").groups.items():
        tr = train[train["aspect"] == a]
        x = m * _triangle(tr["truncation"].to_numpy(float))
        if len(tr) == 0 or not np.any(x > 0):
            continue
        k = float(x @ tr["peak"].to_numpy(float) / (x @ x))
        out[test.index.get_indexer(rows)] = m * k * _triangle(test.loc[rows, "truncation"].to_numpy(float))
    return out


def _design(frame):
    t, a = frame["truncation"].to_numpy(float), frame["aspect"].to_numpy(float)
    return np.column_stack([np.ones_like(t), t, a, t * a])


def _predict_glm(train, test, m, family):
    import statsmodels.api as sm

    X, Xt = _design(train), _design(test)
    y = train["peak"].to_numpy(float)
    if family == "quasi-binomial":
        share = np.clip(y / m, 0.0, 1.0)
        res = sm.GLM(share, X, family=sm.families.Binomial()).fit(scale="X2")
        return m * res.predict(Xt)
    res = sm.GLM(y, X, family=sm.families.Gaussian()).fit()
    return res.predict(Xt)


def _predict(model, lobe, train, test, m, k_geo):
    if model == MODELS[0]:
        return _predict_physics(lobe, train, test, m, "geometric", k_geo)
    if model == MODELS[1]:
        return _predict_physics(lobe, train, test, m, "fitted", k_geo)
    return _predict_glm(train, test, m, "quasi-binomial" if model == MODELS[2] else "gaussian")


def share_law_fits(lobes: pd.DataFrame, m: float = 127.0) -> pd.DataFrame:
    """In-sample and leave-one-surface-out errors of every combined model, per lobe and incidence.

    Parameters
    ----------
    lobes : :func:`roughlight.analysis.lobes.arc_lobes` output (the regular surface's).
    m : float
        The facets' 8-bit specular value at the mirror direction, ``J * m_s``.

    Returns
    -------
    DataFrame: ``lobe``, ``incidence``, ``model``, ``parameters`` (free parameters fitted), ``n`` (surfaces),
    ``rmse`` (in-sample, 0-255), ``rmse_held_out`` (leave one surface out), ``max_error_held_out``, ``note``.
    For the forward lobe the two share laws are the same model (no ``k``).
    """
    rows = []
    for lobe in ("forward", "back"):
        peaks = lobe_peaks(lobes, lobe)
        for incidence, data in peaks.groupby("incidence"):
            data = data.reset_index(drop=True)
            k_geo = _geometric_k(data["aspect"], incidence) if lobe == "back" else {}
            n_aspects = data["aspect"].nunique()
            for model in MODELS:
                if lobe == "forward" and model == MODELS[1]:
                    continue
                parameters = {MODELS[0]: 0, MODELS[1]: n_aspects, MODELS[2]: 4, MODELS[3]: 4}[model]
                note = ""
                if len(data) <= parameters:
                    rows.append({"lobe": lobe, "incidence": incidence, "model": model, "parameters": parameters,
                                 "n": len(data), "rmse": np.nan, "rmse_held_out": np.nan,
                                 "max_error_held_out": np.nan, "note": "fewer surfaces than parameters"})
                    continue
                y = data["peak"].to_numpy(float)
                fitted = _predict(model, lobe, data, data, m, k_geo)
                held = np.array([_predict(model, lobe, data.drop(index=j), data.loc[[j]], m, k_geo)[0]
                                 for j in data.index])
                if np.isnan(held).any():
                    note = f"{int(np.isnan(held).sum())} surfaces alone at their aspect: no held-out prediction"
                err, err_held = fitted - y, held - y
                rows.append({"lobe": lobe, "incidence": incidence,
                             "model": "share law (no free parameter)" if lobe == "forward" and model == MODELS[0]
                             else model, "parameters": parameters, "n": len(data),
                             "rmse": float(np.sqrt(np.nanmean(err**2))),
                             "rmse_held_out": float(np.sqrt(np.nanmean(err_held**2))),
                             "max_error_held_out": float(np.nanmax(np.abs(err_held))), "note": note})
    # the columns even where no lobe has a peak to fit (a coarse grid whose half maxima fall between views)
    return pd.DataFrame(rows, columns=["lobe", "incidence", "model", "parameters", "n", "rmse", "rmse_held_out",
                                       "max_error_held_out", "note"])
