"""Generalised linear models over the whole grid (truncation x aspect x incidence).

Each lobe statistic (and the diffuse level) is regressed on the surface's
parameters with a Gaussian GLM fitted by IRLS (statsmodels), as the thesis's
S-Plus runs: the design (:func:`design`), a collinearity check that drops
what cannot be told apart (:func:`collinearity`), the fit (:func:`fit`) and
its diagnostics (:func:`diagnostics`), each a small step of
:func:`grid_glm`.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..study.selection import SURFACE_KEYS
from .lobes import HORIZON_CUT

#: The suffix of a response's column that says which surfaces' lobe the horizon cuts (:func:`horizon_cut`).
CUT_BY_HORIZON = "_cut_by_horizon"


@dataclass
class GLMResult:
    """One response's grid GLM: summary row, coefficient rows, diagnostic rows, messages."""

    response: str
    summary: dict
    coefficients: pd.DataFrame
    diagnostics: pd.DataFrame
    messages: list


def scaled_condition(X: np.ndarray) -> float:
    """Belsley's scaled condition number: the design, intercept column included, with every column scaled to
    unit length and *not* centred (Belsley, Kuh and Welsch 1980, ch. 3: centring hides the collinearity with
    the intercept). Its thresholds, 30 ("moderate") and 100 ("strong"), assume this scaling."""
    norms = np.linalg.norm(X, axis=0)
    keep = norms > 0
    if not keep.any():
        return np.nan
    return float(np.linalg.cond(X[:, keep] / norms[keep]))


def fitted_surfaces(data: pd.DataFrame, response: str, messages: list) -> pd.DataFrame:
    """The surfaces a grid GLM is fitted on: no plate, no lobe the horizon cuts, no missing value.

    Plate surfaces (truncation 0 or aspect 0) are the same surface whatever
    the other parameter is (zero-variance cells); a surface whose lobe the
    horizon cuts (``data``'s column ``{response}_cut_by_horizon`` true: its
    maximum on the first or last rendered view, e = 1 or 179, its true peak
    perhaps beyond; :func:`roughlight.analysis.lobes.profile_lobe`) has no
    peak; other surfaces without a value have no lobe. Each kind is kept out
    and counted in a message appended to ``messages``.
    """
    d = data[SURFACE_KEYS + [response]].copy()
    plate = is_plate_row(d)
    if plate.any():
        messages.append(
            f"{response}: {int(plate.sum())} plate surfaces (truncation 0 or aspect 0: the same flat plate "
            "whatever the other parameter) kept out of the fit"
        )
    cut = horizon_cut(data, response) & ~plate
    if cut.any():
        messages.append(f"{response}: {int(cut.sum())} surfaces whose lobe the horizon cuts (the maximum on the "
                        "first or last rendered view, e = 1 or 179: the peak may lie beyond) kept out of the fit")
    n_nan = int((d[response].isna() & ~plate & ~cut).sum())
    if n_nan:
        messages.append(f"{response}: {n_nan} surfaces without a value (no lobe found) kept out of the fit")
    return d[~plate & ~cut].dropna()


def is_plate_row(data: pd.DataFrame) -> pd.Series:
    """Whether each surface (row) of ``data`` is the flat plate: truncation 0 or aspect 0."""
    return (data["truncation"] * data["aspect"]) < 1e-9


def horizon_cut(data: pd.DataFrame, response: str) -> pd.Series:
    """Whether each surface (row) of ``data`` has a lobe the horizon cuts for ``response``: its column
    ``{response}_cut_by_horizon`` (false where it is missing or NaN, or ``data`` has no such column)."""
    column = f"{response}{CUT_BY_HORIZON}"
    if column not in data:
        return pd.Series(False, index=data.index)
    return data[column].fillna(False).astype(bool)


def candidate_terms(d: pd.DataFrame, response: str, messages: list) -> list[str]:
    """The predictors that vary over ``d`` (and truncation x aspect when both do), in design order."""
    terms = []
    for name in ("truncation", "aspect", "incidence"):
        nun = d[name].nunique()
        if nun > 1:
            terms.append(name)
        elif name != "incidence":
            messages.append(f"{response}: {name} takes {nun} value(s) outside the plate: dropped (zero variance)")
    if "truncation" in terms and "aspect" in terms:
        terms.insert(2, "truncation:aspect")
    return terms


def design(d: pd.DataFrame, terms: list[str]) -> np.ndarray:
    """Design matrix, shape (surfaces, 1 + terms): a constant column, then each term (``a:b`` is a product)."""
    cols = [np.ones(len(d))]
    for term in terms:
        if ":" in term:
            a_, b_ = term.split(":")
            cols.append(d[a_].to_numpy(float) * d[b_].to_numpy(float))
        else:
            cols.append(d[term].to_numpy(float))
    return np.column_stack(cols)


def collinearity(d: pd.DataFrame, terms: list[str], response: str, limit: float, messages: list) -> list[str]:
    """Drop terms (interaction first, then incidence, then the last) until the design is full rank and its
    Belsley-scaled condition number (:func:`scaled_condition`) is at most ``limit``. Removes them from
    ``terms``; returns the dropped."""
    dropped = []
    while terms:
        X = design(d, terms)
        rank = np.linalg.matrix_rank(X)
        kappa = scaled_condition(X)
        if rank == X.shape[1] and kappa <= limit:
            break
        victim = next((x for x in ("truncation:aspect", "incidence") if x in terms), terms[-1])
        why = "rank deficient" if rank < X.shape[1] else f"scaled condition number {kappa:.3g} > {limit:g}"
        messages.append(f"{response}: near-collinear design ({why}): term {victim} kept out of the fit")
        terms.remove(victim)
        dropped.append(victim)
    return dropped


def fit(X: np.ndarray, y: np.ndarray, response: str, messages: list):
    """Gaussian GLM fitted by IRLS (statsmodels); warnings become messages. None when the fit raised."""
    import statsmodels.api as sm

    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            res = sm.GLM(y, X, family=sm.families.Gaussian()).fit(method="IRLS", maxiter=100)
        for w in caught:
            messages.append(f"{response}: warning during the fit: {w.message}")
    except Exception as exc:
        messages.append(f"{response}: the GLM failed ({exc}): not fitted")
        return None
    return res


def coefficients(res, names: list[str], response: str) -> pd.DataFrame:
    """One row per term: estimate, std error, z, p and the 95% interval."""
    ci = np.asarray(res.conf_int())
    return pd.DataFrame({
        "response": response, "term": names, "estimate": np.asarray(res.params), "std_error": np.asarray(res.bse),
        "z": np.asarray(res.tvalues), "p_value": np.asarray(res.pvalues), "ci_low": ci[:, 0], "ci_high": ci[:, 1],
    })


def diagnostics(res, d: pd.DataFrame, y: np.ndarray, response: str) -> pd.DataFrame:
    """Per surface: observed, fitted, response and Pearson residuals, leverage (hat) and Cook's distance."""
    infl = res.get_influence()
    diag = d[SURFACE_KEYS].copy()
    diag["response"] = response
    diag["observed"] = y
    diag["fitted"] = np.asarray(res.fittedvalues)
    diag["residual"] = y - diag["fitted"]
    diag["pearson_residual"] = np.asarray(res.resid_pearson)
    diag["leverage"] = np.asarray(infl.hat_matrix_diag)
    diag["cooks_distance"] = np.asarray(infl.cooks_distance[0])
    return diag.reset_index(drop=True)


def grid_glm(data: pd.DataFrame, response: str, collinearity_limit: float = 100.0) -> GLMResult:
    """Gaussian GLM (IRLS) of one response over the grid: truncation, aspect, their interaction (and incidence).

    Plates, surfaces whose lobe the horizon cuts and surfaces without a value
    are kept out (:func:`fitted_surfaces`);
    predictors without variance are dropped (:func:`candidate_terms`); terms are
    dropped while the design is near-collinear (:func:`collinearity`). Every such
    decision is a message; nothing raises.

    Parameters
    ----------
    data : DataFrame with ``truncation``, ``aspect``, ``incidence`` and ``response`` columns, and optionally
        ``{response}_cut_by_horizon`` (bool: the surface's lobe is cut by the horizon, :func:`horizon_cut`).
    response : str
    collinearity_limit : float
        Largest acceptable condition number of the scaled design (30 is
        Belsley's "moderate", 100 "strong" dependence).

    Returns
    -------
    GLMResult
        ``summary``: n (surfaces fitted), cut_by_horizon (rough surfaces kept
        out because the horizon cuts their lobe), terms, dropped terms,
        converged, iterations, deviance, AIC, pseudo R^2, condition numbers (raw and scaled), status;
        ``coefficients``: term, estimate, std error, z, p, 95% CI;
        ``diagnostics``: per surface fitted value, response/Pearson residuals,
        leverage (hat), Cook's distance.
    """
    messages = []
    summary = {"response": response, "n": 0, "cut_by_horizon": 0, "terms": "", "dropped": "", "converged": False,
               "iterations": np.nan, "deviance": np.nan, "aic": np.nan, "pseudo_r2": np.nan, "condition_raw": np.nan,
               "condition_scaled": np.nan, "status": "not fitted"}
    prepared = _fit_inputs(data, response, collinearity_limit, summary, messages)
    if prepared is None:
        return _unfitted(response, summary, messages)
    d, terms, X, y = prepared
    summary["terms"] = " + ".join(terms)
    summary["condition_raw"] = float(np.linalg.cond(X))
    summary["condition_scaled"] = scaled_condition(X)
    res = fit(X, y, response, messages)
    if res is None:
        summary["status"] = "failed"
        return _unfitted(response, summary, messages)
    summary["converged"] = bool(res.converged)
    summary["iterations"] = int(res.fit_history.get("iteration", np.nan))
    if not res.converged:
        messages.append(f"{response}: IRLS did not converge: coefficients not reported")
        summary["status"] = "not converged"
        return _unfitted(response, summary, messages)
    summary.update(goodness_of_fit(res, y))
    coefs = coefficients(res, ["const"] + terms, response)
    return GLMResult(response, summary, coefs, diagnostics(res, d, y, response), messages)


def _unfitted(response: str, summary: dict, messages: list) -> GLMResult:
    """A response's result without a fit: its summary and messages, no coefficients, no diagnostics."""
    return GLMResult(response, summary, pd.DataFrame(), pd.DataFrame(), messages)


def _fit_inputs(data: pd.DataFrame, response: str, collinearity_limit: float, summary: dict, messages: list):
    """What :func:`grid_glm` fits: the surfaces ``d``, the terms, the design ``X`` (surfaces, 1 + terms) and the
    response ``y`` (surfaces,); or None when there is nothing to fit, with a message saying why. Records the
    dropped terms and the number of surfaces in ``summary``."""
    if response not in data:
        messages.append(f"{response}: no such column")
        return None
    d = fitted_surfaces(data, response, messages)
    summary["cut_by_horizon"] = int((horizon_cut(data, response) & ~is_plate_row(data)).sum())
    terms = candidate_terms(d, response, messages)
    summary["dropped"] = ", ".join(collinearity(d, terms, response, collinearity_limit, messages))
    summary["n"] = int(len(d))
    if not terms:
        messages.append(f"{response}: no predictor varies: nothing to fit")
        return None
    X = design(d, terms)
    if len(d) <= X.shape[1]:
        messages.append(f"{response}: {len(d)} surfaces for {X.shape[1]} coefficients: not fitted")
        return None
    y = d[response].to_numpy(float)
    if np.ptp(y) < 1e-12:
        messages.append(f"{response}: takes the one value {y[0]:g} on all {len(y)} surfaces: nothing to fit")
        return None
    return d, terms, X, y


def goodness_of_fit(res, y: np.ndarray) -> dict:
    """A converged fit's ``deviance``, ``aic``, ``pseudo_r2`` (1 - deviance / the null model's, NaN when ``y``
    does not vary) and ``status`` ok."""
    null = float(np.sum((y - y.mean()) ** 2))
    return {"deviance": float(res.deviance), "aic": float(res.aic),
            "pseudo_r2": float(1.0 - res.deviance / null) if null > 0 else np.nan, "status": "ok"}


def grid_glms(lobes: pd.DataFrame, levels: pd.DataFrame, collinearity_limit: float = 100.0):
    """Grid GLMs of the forward lobe peak, back lobe peak and diffuse level.

    A surface whose forward (back) lobe the horizon cuts, its maximum on the
    first or last rendered view (e = 1 or 179, beside the views not rendered,
    e = 0 and 180: :func:`roughlight.analysis.lobes.arc_lobes`' note
    :data:`roughlight.analysis.lobes.HORIZON_CUT`), has no peak: it is left
    out of that lobe's GLM, counted in the summary's ``cut_by_horizon`` and
    in a message, and stays in the other GLMs.

    Parameters
    ----------
    lobes : :func:`arc_lobes` output; levels : :func:`diffuse_levels` output.

    Returns
    -------
    summary, coefficients, diagnostics : DataFrames (one block per response)
    messages : list of str
    """
    data = levels[SURFACE_KEYS + ["diffuse_level"]].merge(lobe_peaks(lobes), on=SURFACE_KEYS, how="outer")
    results = [grid_glm(data, r, collinearity_limit) for r in ("forward_peak", "back_peak", "diffuse_level")]
    summary = pd.DataFrame([r.summary for r in results])
    coefs = pd.concat([r.coefficients for r in results if len(r.coefficients)], ignore_index=True) \
        if any(len(r.coefficients) for r in results) else pd.DataFrame()
    diags = pd.concat([r.diagnostics for r in results if len(r.diagnostics)], ignore_index=True) \
        if any(len(r.diagnostics) for r in results) else pd.DataFrame()
    messages = [m for r in results for m in r.messages]
    return summary, coefs, diags, messages


def lobe_peaks(lobes: pd.DataFrame) -> pd.DataFrame:
    """One row a surface: its keys, ``forward_peak`` and ``back_peak`` (0-255, NaN without a peak) and
    ``forward_peak_cut_by_horizon``, ``back_peak_cut_by_horizon`` (bool: the note of :func:`arc_lobes` says the
    horizon cuts the lobe)."""
    lobes = lobes[lobes["lobe"].isin(["forward", "back"])].assign(
        cut=lobes["note"].fillna("").astype(str).str.startswith(HORIZON_CUT))
    wide = lobes.pivot_table(index=SURFACE_KEYS, columns="lobe", values="peak", aggfunc="first", dropna=False)
    cut = lobes.pivot_table(index=SURFACE_KEYS, columns="lobe", values="cut", aggfunc="any")
    out = pd.DataFrame(index=cut.index)
    for lobe in ("forward", "back"):
        out[f"{lobe}_peak"] = wide[lobe] if lobe in wide else np.nan
        out[f"{lobe}_peak{CUT_BY_HORIZON}"] = cut[lobe].astype(bool) if lobe in cut else False
    return out.reset_index()
