"""Random roughness measured as ensembles: per-seed statistics, ensemble means with intervals, against the regular
surface (Ch. IV.C, Fig. 19; Ch. VI: "incorporate this random nature").

Every statistic is computed per surface and seed from the views that were measured, each once: the lobes on the
light's plane and the diffuse with the functions the regular surface's analysis uses
(:mod:`roughlight.analysis.lobes`, :mod:`roughlight.analysis.diffuse`), and the back lobe's shape over the whole
hemisphere, both sides of the light's plane, with :mod:`roughlight.analysis.lobe_shape`: the two statistics of the
thesis's claim (``back_squareness``, ``back_phase_shift``; :mod:`roughlight.analysis.claims` gives their design
and verdict) and the shape's others. Where a lobe cannot be measured (cut by the horizon, below the 8-bit floor)
its statistics are NaN and the row's ``note`` says why.

The regular surface is one surface (its values have no seed-to-seed spread); each random kind is a sample of
seeds. :func:`ensemble_summary` describes each ensemble (95% intervals, a test a row, with no correction for the
family: the claim's inference is :func:`roughlight.analysis.claims.claim_table`, on tiles of its own).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..render.views import distinct_views
from ..study.selection import SURFACE_KEYS
from .grids import surface_value_grids

__all__ = [
    "ENSEMBLE_KEYS",
    "STATISTICS",
    "seed_statistics",
    "pooled_study",
    "pooled_statistics",
    "ensemble_summary",
    "seeds_needed",
    "bootstrap_interval",
    "ensemble_model_fits",
    "random_points",
]

#: One row per surface kind, seed and grid point.
ENSEMBLE_KEYS = ["kind", "seed"] + SURFACE_KEYS

#: The statistics compared, with their units (for tables and charts).
STATISTICS = {
    "forward_peak": "0-255",
    "forward_centre": "deg",
    "forward_width": "deg",
    "back_peak": "0-255",
    "back_centre": "deg",
    "back_width": "deg",
    "back_squareness": "ratio",
    "back_phase_shift": "deg",
    "back_ellipse_misfit": "ratio",
    "back_rectangle_misfit": "ratio",
    "back_rectangularity": "ratio",
    "back_elongation": "ratio",
    "diffuse_level": "0-255",
    "diffuse_level1": "0-255",
    "diffuse_level3": "0-255",
    "diffuse_rate": "1/deg",
}


def random_points(study: pd.DataFrame) -> pd.DataFrame:
    """The grid points that have random surfaces, with every kind's rows there (regular ones included); a
    table of regular surfaces only is returned whole (its statistics are the baseline)."""
    kind = study["kind"].astype(str)
    if (kind == "pyramids").all():
        return study
    points = study.loc[kind != "pyramids", ["truncation", "aspect"]].drop_duplicates()
    return study.merge(points, on=["truncation", "aspect"], how="inner")


def _per_sweep(study: pd.DataFrame):
    for (kind, seed), group in study.groupby([study["kind"].astype(str), "seed"], sort=True):
        yield str(kind), int(seed), group


def _shape_statistics(key, az, el, grids: dict, min_peak: float) -> dict:
    """The back lobe's shape statistics (:data:`roughlight.analysis.lobe_shape.SHAPE_STATISTICS`) of one surface
    from its specular and coverage grids, and why they are NaN where they are: {name: (value, note)}."""
    from .lobe_shape import SHAPE_STATISTICS, back_lobe_peak, lobe_statistics, measured_field

    peak_direction, why = back_lobe_peak(key, az, el, grids["rough"], grids["coverage"])
    if peak_direction is None:
        return {name: (np.nan, why) for name in SHAPE_STATISTICS}
    shape = lobe_statistics(measured_field(az, el, grids["rough"], grids["coverage"]), peak_direction, min_peak)
    if not shape["measurable"]:
        return {name: (np.nan, shape["why"]) for name in SHAPE_STATISTICS}
    out = {name: (float(shape[field]), "") for name, field in SHAPE_STATISTICS.items()}
    if not np.isfinite(out["back_phase_shift"][0]):
        out["back_phase_shift"] = (np.nan, "no measured arc crosses the lobe above half its peak")
    return out


def seed_statistics(study: pd.DataFrame, lobe_halfwidth: float = 40.0, min_peak: float = 0.5) -> pd.DataFrame:
    """Every statistic of :data:`STATISTICS` per kind, seed and grid point (random points only), from the views
    that were measured (coverage above 0), each once.

    Parameters
    ----------
    study : the study table's rows at the random grid points (:func:`random_points`): the surface keys, kind,
        seed, azimuth, elevation, component, rough, control, coverage
    lobe_halfwidth : a lobe's window on the light's plane, degrees (:func:`roughlight.analysis.lobes.arc_lobes`)
    min_peak : the 8-bit floor of the back lobe's shape (0-255): a lower lobe is not measurable

    Returns
    -------
    DataFrame: :data:`ENSEMBLE_KEYS`, ``statistic``, ``value`` (NaN where it cannot be measured) and ``note``
    ('' or why not).
    """
    from .diffuse import diffuse_levels, diffuse_three_part
    from .lobes import arc_lobes

    rows = []
    for kind, seed, group in _per_sweep(random_points(study)):
        lobes = arc_lobes(group, max_halfwidth=lobe_halfwidth)
        levels = diffuse_levels(group).set_index(SURFACE_KEYS)
        parts = diffuse_three_part(group).set_index(SURFACE_KEYS)
        for key, az, el, grids in surface_value_grids(group, "specular", ("rough", "coverage")):
            stats = {}
            for lobe in ("forward", "back"):
                row = lobes[(lobes[SURFACE_KEYS].to_numpy(float) == np.array(key)).all(axis=1) & (lobes["lobe"] == lobe)]
                # a flagged maximum (below one 8-bit step, on the window's edge) is not a lobe: no statistics
                found = not row.empty and np.isfinite(row["peak"].iloc[0]) and row["note"].iloc[0] == ""
                note = "" if found else (row["note"].iloc[0] if not row.empty else "no such lobe")
                stats[f"{lobe}_peak"] = (float(row["peak"].iloc[0]) if found else np.nan, note)
                stats[f"{lobe}_centre"] = (float(row["peak_elevation"].iloc[0]) if found else np.nan, note)
                stats[f"{lobe}_width"] = (float(row["fwhm"].iloc[0]) if found else np.nan, note)
            stats.update(_shape_statistics(key, az, el, grids, min_peak))
            stats["diffuse_level"] = (float(levels.loc[key, "diffuse_level"]), "")
            stats["diffuse_level1"] = (float(parts.loc[key, "level1"]), "")
            stats["diffuse_level3"] = (float(parts.loc[key, "level3"]), "")
            stats["diffuse_rate"] = (float(parts.loc[key, "rate_continuous"]), "")
            for name in STATISTICS:
                value, note = stats[name]
                rows.append({"kind": kind, "seed": seed, "truncation": key[0], "aspect": key[1], "incidence": key[2],
                             "statistic": name, "value": value, "note": note if not np.isfinite(value) else ""})
    return pd.DataFrame(rows, columns=ENSEMBLE_KEYS + ["statistic", "value", "note"])


def pooled_study(study: pd.DataFrame) -> pd.DataFrame:
    """Each random kind's seed-averaged views at every random grid point (seed 0): the reflectance of a surface
    made of many tiles, as a large random surface is, where each seed alone is a small patch of one."""
    data = random_points(study)
    data = data[data["kind"].astype(str) != "pyramids"]
    keys = ["kind"] + SURFACE_KEYS + ["azimuth", "elevation", "phase", "component"]
    pooled = data.groupby(keys, observed=True, as_index=False)[["rough", "control", "coverage"]].mean()
    pooled["kind"] = pooled["kind"].astype(str)
    pooled.insert(1, "seed", 0)
    return pooled


def pooled_statistics(study: pd.DataFrame, lobe_halfwidth: float = 40.0, min_peak: float = 0.5) -> pd.DataFrame:
    """:func:`seed_statistics` of each random kind's seed-averaged views (:func:`pooled_study`)."""
    pooled = pooled_study(study)
    if pooled.empty:
        return pd.DataFrame(columns=ENSEMBLE_KEYS + ["statistic", "value", "note"])
    return seed_statistics(pooled, lobe_halfwidth, min_peak)


def ensemble_summary(stats: pd.DataFrame, level: float = 0.95, pooled: pd.DataFrame | None = None) -> pd.DataFrame:
    """Ensemble means with Student-t intervals over seeds, beside the regular surface, and a t-test.

    Parameters
    ----------
    stats : DataFrame from :func:`seed_statistics`.

    Returns
    -------
    DataFrame, one row per random kind x grid point x statistic (the study's tiles, ``surface.seeds``; a descriptive
    table: each interval and test stands alone, with no correction for the family, which the claim's verdict
    has, :func:`roughlight.analysis.claims.claim_table`): ``kind``, surface keys, ``statistic``, ``unit``,
    ``rendered`` (tiles), ``seeds`` (n with a value),
    ``mean``, ``sd``, ``ci_low``, ``ci_high`` (the ``level`` interval of the
    mean), ``regular`` (the regular surface's value), ``difference``
    (mean - regular), ``t`` and ``p_value`` (two-sided one-sample t-test of
    the seeds against the regular value; NaN with fewer than 2 seeds or no
    spread), ``pooled`` (the statistic of the seed-averaged views,
    :func:`pooled_statistics`, when ``pooled`` is given), ``boot_low``,
    ``boot_high`` (the percentile bootstrap interval of the mean over seeds,
    :func:`bootstrap_interval`: within the range the statistic takes).
    """
    from scipy import stats as sps

    regular = stats[stats["kind"] == "pyramids"].set_index(SURFACE_KEYS + ["statistic"])["value"]
    pooled_values = (pooled.set_index(["kind"] + SURFACE_KEYS + ["statistic"])["value"]
                     if pooled is not None and len(pooled) else pd.Series(dtype=float))
    rows = []
    random = stats[stats["kind"] != "pyramids"]
    for (kind, t, a, i, name), group in random.groupby(["kind"] + SURFACE_KEYS + ["statistic"], sort=True):
        values = group["value"].dropna().to_numpy(float)
        n = len(values)
        mean = float(values.mean()) if n else np.nan
        sd = float(values.std(ddof=1)) if n > 1 else np.nan
        half = float(sps.t.ppf(0.5 + level / 2, n - 1) * sd / math.sqrt(n)) if n > 1 else np.nan
        reg = float(regular.get((t, a, i, name), np.nan))
        if n > 1 and sd > 0 and np.isfinite(reg):
            test = sps.ttest_1samp(values, reg)
            t_value, p_value = float(test.statistic), float(test.pvalue)
        else:
            t_value = p_value = np.nan
        boot_low, boot_high = bootstrap_interval(values, level)
        rows.append({"kind": kind, "truncation": t, "aspect": a, "incidence": i, "statistic": name,
                     "unit": STATISTICS.get(name, ""), "rendered": len(group), "seeds": n, "mean": mean, "sd": sd,
                     "ci_low": mean - half, "ci_high": mean + half, "regular": reg, "difference": mean - reg,
                     "t": t_value, "p_value": p_value,
                     "pooled": float(pooled_values.get((kind, t, a, i, name), np.nan)),
                     "boot_low": boot_low, "boot_high": boot_high})
    return pd.DataFrame(rows)


#: Bootstrap resamples of each ensemble's mean, and the generator's seed (fixed: the same interval every run).
BOOTSTRAP_RESAMPLES = 4000
BOOTSTRAP_SEED = 20011


def bootstrap_interval(values, level: float = 0.95) -> tuple[float, float]:
    """Percentile bootstrap interval of the mean of ``values`` (one per seed): the ``level`` central range of the
    means of :data:`BOOTSTRAP_RESAMPLES` resamples with replacement. Every resampled mean lies within the values'
    range, so a ratio's interval stays within [0, 1] where a Student-t interval can leave it. NaN with fewer
    than 2 values."""
    values = np.asarray(values, float)
    values = values[np.isfinite(values)]
    if len(values) < 2:
        return np.nan, np.nan
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    means = values[rng.integers(0, len(values), (BOOTSTRAP_RESAMPLES, len(values)))].mean(axis=1)
    tail = 50.0 * (1.0 - level)
    low, high = np.percentile(means, [tail, 100.0 - tail])
    return float(low), float(high)


def seeds_needed(summary: pd.DataFrame, relative_widths=(0.1, 0.05, 0.02), level: float = 0.95,
                 max_seeds: int = 10_000) -> pd.DataFrame:
    """How many seeds give a 95% interval of the mean no wider (half-width) than a fraction of the mean.

    Uses each ensemble's seed-to-seed SD as the population's: ``n`` is the
    smallest n >= 2 with ``t(n - 1) sd / sqrt(n) <= w |mean|``.

    Returns
    -------
    DataFrame: ``kind``, surface keys, ``statistic``, ``sd``, ``mean`` and one
    column ``seeds_for_{w}`` per relative half-width ``w`` (integers; capped
    at ``max_seeds``).
    """
    from scipy import stats as sps

    out = summary[["kind"] + SURFACE_KEYS + ["statistic", "mean", "sd"]].copy()
    n_all = np.arange(2, max_seeds + 1)
    quantile = sps.t.ppf(0.5 + level / 2, n_all - 1) / np.sqrt(n_all)
    for w in relative_widths:
        needed = []
        for mean, sd in zip(out["mean"], out["sd"]):
            if not (np.isfinite(mean) and np.isfinite(sd)) or mean == 0:
                needed.append(pd.NA)
                continue
            ok = np.flatnonzero(quantile * sd <= w * abs(mean))
            needed.append(int(n_all[ok[0]]) if len(ok) else max_seeds)
        out[f"seeds_for_{w:g}"] = pd.array(needed, dtype="Int64")
    return out


def ensemble_model_fits(study: pd.DataFrame, lighting: dict | None = None, hapke_max_phase: float = 60.0
                        ) -> pd.DataFrame:
    """The analytic models refitted on each random tile, beside the regular surface.

    For every kind and seed at the random grid points:
    :func:`roughlight.analysis.surface_models.analytic_model_fits` (Lambert, Oren-Nayar,
    the V-cavity facets, Hapke), plus ``rmse_regular_*``: the error of
    predicting the tile by the regular surface at its grid point (what the
    implicit shader's exact form, which reproduces the regular surface
    within 0.02 levels, would predict), diffuse and specular, over the tile's
    rendered views, each once (the zenith once, not once per azimuth:
    :func:`roughlight.render.views.distinct_views`).

    Returns
    -------
    DataFrame: :data:`ENSEMBLE_KEYS` and the fits' columns.
    """
    from .surface_models import analytic_model_fits

    data = random_points(study)
    keys = SURFACE_KEYS + ["azimuth", "elevation", "component"]
    regular = data[data["kind"].astype(str) == "pyramids"].set_index(keys)["rough"]
    frames = []
    for kind, seed, group in _per_sweep(data):
        fits = analytic_model_fits(group, lighting=lighting, hapke_max_phase=hapke_max_phase)
        fits.insert(0, "kind", kind)
        fits.insert(1, "seed", seed)
        joined = group.join(regular.rename("regular"), on=keys)
        seen = distinct_views(joined["azimuth"], joined["elevation"], joined["coverage"],
                              joined.groupby(SURFACE_KEYS + ["component"], observed=True).ngroup())
        for component in ("diffuse", "specular"):
            part = joined[seen & (joined["component"].astype(str) == component).to_numpy()]
            err = (part["rough"] - part["regular"]) ** 2
            rmse = err.groupby([part[k] for k in SURFACE_KEYS]).mean() ** 0.5
            fits[f"rmse_regular_{component}"] = [float(rmse.get(tuple(k), np.nan))
                                                 for k in fits[SURFACE_KEYS].itertuples(index=False)]
        frames.append(fits)
    return pd.concat(frames, ignore_index=True)
