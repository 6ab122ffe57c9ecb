"""The thesis's models and its Tables 1-2, recomputed from our lobes.

Slattery (2001, Ch. V.E) models the forward lobe's peak by the top's area
(the "square area function", ``m (1 - t)^2``, and its sine refit) and the back
lobe's by the light-facing side's ("triangle area function"), each also as a
regression, and reports for each the mean absolute error, the standard
deviation, the regression's ``b0``, ``b1`` and the RSS (:data:`THESIS_TABLES`,
verbatim). Here the same statistics on our peaks (:func:`thesis_tables`), on
the exact reference's (:func:`exact_lobe_peaks`), their bootstrap spread
(:func:`bootstrap_tables`) and the sine models refitted
(:func:`sine_refits`). Values 0-255; truncation in [0, 1].
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pandas as pd

from ..study.selection import ASPECT_TOL, SURFACE_KEYS, find_aspect
from ..surfaces.surface import SQRT3_2, Surface, aspect_label
from .areas import front_facet_share
from .exact_arc import ExactArc, arc_elevations, exact_widths
from .lobes import MIN_LOBE_PEAK

#: The thesis's analysis ran at this incidence (Ch. V.B).
THESIS_INCIDENCE = 30.0
#: The aspects of Tables 1-2 by default (``report.table_aspects``): the thesis's runs, 1, and its
#: 30-degree facets, sqrt(3)/2 (side facets facing a light at incidence 30).
TABLE_ASPECTS = (1.0, SQRT3_2)


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
        data = table_data(lobes, found, incidence)
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
    ddof = 1); ``SD of |error|`` is the SD of their absolute values, the other
    reading of the thesis's column (see :func:`sd_bound`); ``b0``, ``b1`` and ``RSS`` (the deviance: residual sum of
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
        "SD of |error|": float(np.std(np.abs(err), ddof=1)) if len(err) > 1 else np.nan,
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
    if np.ptp(y) < 1e-12:
        out["note"] = f"the peaks take one value ({y[0]:g}) at every truncation: no regression line"
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


def sd_bound(sd: float, n: int) -> float:
    """The largest RSS a least-squares line can leave when ``sd`` is the SD (ddof 1) of the raw errors.

    The line of slope 1 through the mean error already leaves ``(n - 1) sd^2``, and least squares does no
    worse: ``RSS <= (n - 1) sd^2``. A table whose RSS exceeds this cannot have ``sd`` of the raw errors at
    that ``n`` (the thesis's Table 1 rows at n = 11: 122.4 > 94.9 and 51.9 > 35.3).
    """
    return (n - 1) * sd**2


def table_data(lobes: pd.DataFrame, aspect: float, incidence: float, value: str = "peak"):
    sel = lobes[(np.abs(lobes["aspect"] - aspect) <= ASPECT_TOL) & np.isclose(lobes["incidence"], incidence)]
    piv = sel.pivot_table(index="truncation", columns="lobe", values=value, aggfunc="first", dropna=False)
    return piv.sort_index()


def exact_lobe_peaks(lobes: pd.DataFrame, aspects=TABLE_ASPECTS, incidence: float = THESIS_INCIDENCE,
                     lighting=None, halfwidth: float = 10.0, step: float = 1.0,
                     width_halfwidth: float = 25.0) -> pd.DataFrame:
    """Exact (polygon-clipping reference) lobe peaks beside the measured ones, for the table surfaces.

    For each surface of the tabulated aspects and each of the forward and
    back lobes, :func:`roughlight.render.exact.reference.reference_sweep` evaluates the
    phi = 0 arc on the study's elevation grid (``step`` degrees) within
    ``halfwidth`` of the predicted mirror elevation; the exact peak is the
    largest of those values.

    Parameters
    ----------
    lobes : :func:`arc_lobes` output
    lighting : :class:`roughlight.render.shading.Lighting` (default: the study's)

    Returns
    -------
    DataFrame: surface keys, ``lobe``, ``peak`` (measured), ``exact_peak``
    (0-255), ``exact_peak_elevation`` (degrees), ``error`` (measured - exact),
    and the lobe under both specular protocols, exact on the arc within
    ``width_halfwidth`` of the mirror elevation: ``exact_fwhm`` (degrees,
    with the study's specular shadows setting), ``exact_peak_no_specular_shadows``
    and ``exact_fwhm_no_specular_shadows`` (the thesis's specular runs: no
    inner shadows on the specular, Ch. V.D).
    """
    from ..render.shading import Lighting

    lighting = lighting or Lighting()
    rows = []
    for wanted in aspects:
        a = find_aspect(lobes["aspect"], wanted)
        if a is None:
            continue
        sel = lobes[(np.abs(lobes["aspect"] - a) <= ASPECT_TOL) & np.isclose(lobes["incidence"], incidence)
                    & lobes["lobe"].isin(["forward", "back"])]
        for _, r in sel.iterrows():
            rows.append(_exact_lobe(r, a, lighting, halfwidth, step, width_halfwidth))
    out = pd.DataFrame(rows, columns=SURFACE_KEYS + ["lobe", "peak", "exact_peak", "exact_peak_elevation",
                                                     "exact_fwhm", "exact_peak_no_specular_shadows",
                                                     "exact_fwhm_no_specular_shadows"])
    out["error"] = out["peak"] - out["exact_peak"]
    return out


def _exact_lobe(r, aspect: float, lighting, halfwidth: float, step: float, width_halfwidth: float) -> dict:
    """One row of :func:`exact_lobe_peaks`: the measured lobe ``r`` (a row of :func:`arc_lobes`) beside the exact
    reference's peak within ``halfwidth`` of its predicted elevation and its widths (:func:`exact_widths`), both
    from one :class:`ExactArc` (the peak's views are among the widths')."""
    c = r["predicted"]
    row = {"truncation": r["truncation"], "aspect": aspect, "incidence": r["incidence"], "lobe": r["lobe"],
           "peak": r["peak"], "exact_peak": np.nan, "exact_peak_elevation": np.nan}
    if not np.isfinite(c):
        return row
    exact = ExactArc(Surface(r["truncation"], aspect), r["incidence"], lighting.shadows)
    el = arc_elevations(c, halfwidth, step)
    if len(el):
        specular = exact.sweep(el, lighting)["specular"]
        k = int(np.argmax(specular))
        peak = float(specular[k])
        row.update(exact_peak=peak, exact_peak_elevation=float(el[k]) if peak >= MIN_LOBE_PEAK else np.nan)
    row.update(exact_widths(exact.surface, r["incidence"], c, lighting, width_halfwidth, step, exact=exact))
    return row


def thesis_tables(
    lobes: pd.DataFrame,
    aspects=TABLE_ASPECTS,
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
            exact_data = table_data(ex, found, incidence, "_exact").reindex(data.index)
            if lobe in exact_data:
                stats = fit_statistics(exact_data[lobe].to_numpy(float), pred)
                rows.append({**common, "source": "exact geometry", **stats, "m": m, "k": k_used,
                             "truncations": truncations})
        thesis = dict(zip(TABLE_METRICS, THESIS_TABLES[table]["rows"][model]))
        # only what the thesis printed: it gives neither its n, nor whether its fit converged, nor its truncations
        rows.append({**common, "source": "thesis 2001", **thesis, "n": np.nan, "SSE": np.nan, "converged": None,
                     "note": f"Slattery (2001), Table {table}", "truncations": ""})
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


def bootstrap_tables(lobes: pd.DataFrame, aspects=TABLE_ASPECTS, incidence: float = THESIS_INCIDENCE,
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
    for table, found, data, _t, _k, lobe, model, pred in _table_cells(lobes, aspects, incidence, m, k, []):
        ci = bootstrap_statistics(data[lobe].to_numpy(float), pred, n_boot=n_boot, seed=seed)
        for metric in TABLE_METRICS:
            rows.append({"table": table, "aspect": found, "aspect_label": aspect_label(found), "model": model,
                         "metric": metric, "low": ci[metric][0], "high": ci[metric][1], "n": ci["n"],
                         "n_boot": n_boot, "n_boot_used": ci["n_boot_used"]})
    return pd.DataFrame(rows, columns=["table", "aspect", "aspect_label", "model", "metric", "low", "high", "n",
                                       "n_boot", "n_boot_used"])


def sine_refits(lobes: pd.DataFrame, aspects=TABLE_ASPECTS, incidence: float = THESIS_INCIDENCE,
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
    models = {
        "forward": (lambda t, A, w: A * (1.0 - np.sin(w * t)), m),
        "back": (lambda t, A, w: A * np.sin(w * t), m / 2.0),
    }
    rows = []
    for wanted in aspects:
        found = find_aspect(lobes["aspect"], wanted)
        if found is None:
            continue
        data = table_data(lobes, found, incidence)
        t = data.index.to_numpy(float)
        for lobe, (f, A0) in models.items():
            base = {"aspect": found, "aspect_label": aspect_label(found), "lobe": lobe}
            y = data[lobe].to_numpy(float) if lobe in data else np.array([])
            ok = np.isfinite(y)
            rows += _sine_rows(base, A0, len(y[ok]), *_sine_fit(f, A0, t[ok], y[ok]))
    return pd.DataFrame(rows, columns=["aspect", "aspect_label", "lobe", "parameter", "estimate", "ci_low",
                                       "ci_high", "thesis_value", "thesis_inside", "rss", "n", "note"])


def _sine_fit(f, A0: float, tt, yy):
    """One sine model ``f(t, A, w)`` fitted to the peaks ``yy`` (0-255) against truncation ``tt``, from the
    thesis's ``A0`` and ``w = pi/2``.

    Returns
    -------
    est : [A, w], NaN without a fit
    ci : [(lo, hi), (lo, hi)], the 95% intervals ``estimate +- t_{0.975, n-2} se``; NaN without them
    rss : float, the residual sum of squares (NaN without a fit)
    note : str, why there is no fit or no interval ('' otherwise)
    """
    from scipy import stats
    from scipy.optimize import curve_fit

    note, est, ci, rss = "", [np.nan, np.nan], [(np.nan, np.nan)] * 2, np.nan
    if len(yy) < 3:
        return est, ci, rss, f"only {len(yy)} points: no fit"
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
    return est, ci, rss, note


def _sine_rows(base: dict, A0: float, n: int, est, ci, rss, note: str) -> list[dict]:
    """:func:`sine_refits`' two rows of one aspect and lobe (``base``): ``A`` against the thesis's ``A0`` and
    ``omega`` against pi/2, each with the fit (:func:`_sine_fit`) over ``n`` points."""
    rows = []
    for j, (param, thesis_value) in enumerate((("A", A0), ("omega", np.pi / 2))):
        lo, hi = ci[j]
        rows.append({**base, "parameter": param, "estimate": est[j], "ci_low": lo, "ci_high": hi,
                     "thesis_value": thesis_value, "thesis_inside": bool(np.isfinite(lo) and lo <= thesis_value <= hi),
                     "rss": rss, "n": int(n), "note": note})
    return rows


#: The area functions the thesis tabulates (Tables 1-2), as shares of the image against truncation, and the
#: table that reports each: an area row's predictions are ``scale * share(t)``.
AREA_FUNCTIONS = {
    1: ("Square Area Function", lambda t: (1.0 - t) ** 2),
    2: ("Triangle Area Function", lambda t: 1.0 - (1.0 - t) ** 2),
}


def _scale_interval(b0, slope, sign, lo, hi):
    """The scales s >= 0 with lo <= |b0 + slope s| <= hi, on the side of the mean error whose sign is ``sign``."""
    ends = sorted(((sign * lo - b0) / slope, (sign * hi - b0) / slope))
    return max(ends[0], 0.0), ends[1]


def implied_scales(truncations=None) -> pd.DataFrame:
    """The scale of its area functions that the thesis's own Table 1-2 numbers allow.

    An area row predicts ``x = s f(t)`` at the tabulated truncations (the 11
    values 0-1 by default) and reports MAE, SD, and the regression of observed
    on predicted, ``y = b0 + b1 x``. Its mean error is then
    ``e = b0 + (b1 - 1) s mean(f)``, whatever the observations were, and
    two identities bound it:

    * ``|e| <= MAE`` (a mean is at most the mean of absolute values);
    * ``MAE^2 <= e^2 + (n - 1)/n SD^2`` when SD is of the raw errors (the mean
      square error is ``e^2`` plus the variance), i.e. ``|e|`` is at least
      ``sqrt(MAE^2 - (n - 1)/n SD^2)``.

    Each gives an interval of ``s`` (a back lobe's ``s`` is ``m k``). The
    thesis's stated scale, ``m = 127`` (and ``m k = 63.5`` for the back lobe
    with ``k = 1/2``), is inside it or not.

    Returns
    -------
    DataFrame, one row per area row: ``table``, ``model``, ``n``, ``mean_share``,
    ``mean_error_at_stated`` (``e`` at the stated scale), ``mae``,
    ``s_min_mae`` / ``s_max_mae`` (the first bound), ``s_min_sd`` /
    ``s_max_sd`` (both bounds, SD of raw errors), ``stated_scale``,
    ``stated_possible`` (bool, first bound).
    """
    t = np.round(np.linspace(0.0, 1.0, 11), 10) if truncations is None else np.asarray(truncations, float)
    n = len(t)
    rows = []
    for table, (model, share) in AREA_FUNCTIONS.items():
        mae, sd, b0, b1, _ = THESIS_TABLES[table]["rows"][model]
        f_bar = float(np.mean(share(t)))
        slope = (b1 - 1.0) * f_bar  # e = b0 + slope * s
        stated = 127.0 if table == 1 else 63.5

        floor = math.sqrt(max(mae**2 - (n - 1) / n * sd**2, 0.0))
        sign = float(np.sign(b0 + slope * stated)) or 1.0
        lo_mae, hi_mae = _scale_interval(b0, slope, sign, 0.0, mae)
        lo_sd, hi_sd = _scale_interval(b0, slope, sign, floor, mae)
        e_stated = b0 + slope * stated
        rows.append({"table": table, "model": model, "n": n, "mean_share": f_bar, "mean_error_at_stated": e_stated,
                     "mae": mae, "s_min_mae": lo_mae, "s_max_mae": hi_mae, "s_min_sd": lo_sd, "s_max_sd": hi_sd,
                     "stated_scale": stated, "stated_possible": bool(abs(e_stated) <= mae)})
    return pd.DataFrame(rows)


def tables_at_implied_scale(lobes: pd.DataFrame, aspects=TABLE_ASPECTS, incidence: float = THESIS_INCIDENCE,
                            k: float | None = None) -> pd.DataFrame:
    """Our Tables 1-2 rows recomputed with the area functions at the smallest scale the thesis's numbers allow
    (:func:`implied_scales`, ``s_min_mae``) for every table whose stated scale they contradict, beside our rows at
    the stated scale: the comparison on comparable functions. A back-lobe scale would be ``m k`` (``m = 2 s``
    with ``k = 1/2``).

    Returns
    -------
    DataFrame: ``scale`` (``stated`` | ``implied``) and the :func:`thesis_tables` columns of our rows (``m`` among
    them).
    """
    scales = implied_scales().set_index("table")
    frames = []
    for table in (1, 2):
        stated_m = 127.0
        runs = [("stated", stated_m)]
        if not scales.loc[table, "stated_possible"]:  # only where the stated scale contradicts the thesis's numbers
            s_min = float(scales.loc[table, "s_min_mae"])
            runs.append(("implied", s_min if table == 1 else 2.0 * s_min))
        for label, m in runs:
            rows, _ = thesis_tables(lobes, aspects, incidence, m=m, k=k)
            if rows.empty:  # no table aspect at this incidence has lobes: thesis_tables' messages say why
                continue
            rows = rows[(rows["table"] == table) & (rows["source"] == "ours")].copy()
            rows.insert(0, "scale", label)
            frames.append(rows)
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame(columns=["scale", "table", "source"])
