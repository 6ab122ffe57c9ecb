"""Random roughness measured as ensembles: per-seed statistics, means with intervals, and the thesis's
"rectangular lobes" as numbers (Ch. IV.C, Fig. 19), random against regular.

Every statistic is computed per surface and seed with the same functions the
regular surface's analysis uses (:mod:`roughlight.analysis.lobes`,
:mod:`roughlight.analysis.diffuse`), and two more that put the thesis's claim into
numbers, both of the back lobe (the light-facing facets' mirror direction):

* ``rectangularity`` (:func:`lobe_shape`): the area of the half-maximum region
  of the specular lobe over the area of its bounding rectangle along the
  region's principal axes, in the tangent plane at the lobe's peak: 1 for a
  rectangle, pi/4 = 0.785 for an ellipse (a circle included), whatever its
  elongation;
* ``phase_shift`` (:func:`phase_shift`): on each half great circle off the
  light's plane, how far (degrees) the lobe's peak elevation lies from where a
  circular lobe around the same peak direction would put it, averaged over
  the arcs where the lobe stands above half its maximum (Fig. 19's shift).

The regular surface is one surface (its values have no seed-to-seed spread);
each random kind is a sample of seeds, so its mean gets a Student-t 95%
interval and a one-sample t-test against the regular value.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..render.shading import view_direction
from ..study.selection import SURFACE_KEYS
from .grids import surface_grids

__all__ = [
    "ENSEMBLE_KEYS",
    "STATISTICS",
    "lobe_shape",
    "phase_shift",
    "seed_statistics",
    "pooled_study",
    "pooled_statistics",
    "ensemble_summary",
    "seeds_needed",
    "bootstrap_interval",
    "claim_table",
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
    "back_rectangularity": "ratio",
    "back_phase_shift": "deg",
    "diffuse_level": "0-255",
    "diffuse_level1": "0-255",
    "diffuse_level3": "0-255",
    "diffuse_rate": "1/deg",
}

#: An ellipse fills pi/4 of its bounding rectangle.
ELLIPSE_FILL = math.pi / 4.0


def _tangent_basis(direction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    up = np.array([0.0, 0.0, 1.0])
    u1 = up - (up @ direction) * direction
    if np.linalg.norm(u1) < 1e-6:
        u1 = np.array([1.0, 0.0, 0.0]) - direction[0] * direction
    u1 /= np.linalg.norm(u1)
    return u1, np.cross(direction, u1)


def lobe_shape(azimuth, elevation, values, centre_elevation: float, max_angle: float = 30.0,
               resolution: float = 0.25) -> dict:
    """Shape of one specular lobe's half-maximum region on the hemisphere.

    Parameters
    ----------
    azimuth : (A,) degrees, ascending in [0, 180); elevation : (E,) degrees in [0, 180]
    values : (A, E) specular values, 0-255
    centre_elevation : float
        The lobe's peak on the light's plane (phi = 0), degrees; the region is
        searched within ``max_angle`` degrees of that direction.
    max_angle, resolution : float
        Search radius and the interpolation step in the tangent plane, degrees.

    Returns
    -------
    dict: ``peak`` (0-255), ``area`` (deg^2 of tangent plane above half
    maximum), ``rectangularity`` (area over the bounding rectangle along the
    principal axes; 1 rectangle, 0.785 ellipse), ``elongation`` (long over
    short side, >= 1); NaN when the lobe has no value above one 8-bit step.
    """
    nan = {"peak": np.nan, "area": np.nan, "rectangularity": np.nan, "elongation": np.nan}
    samples = _tangent_samples(azimuth, elevation, values, centre_elevation, max_angle)
    if samples is None:
        return nan
    gridded = _tangent_grid(*samples, max_angle, resolution)
    if gridded is None:
        return nan
    X, Y, grid = gridded
    inside = np.isfinite(grid) & (np.hypot(X, Y) <= max_angle)
    if not inside.any():
        return nan
    peak = float(np.nanmax(np.where(inside, grid, -np.inf)))
    if peak < 1.0:
        return nan
    region = _peak_region(grid, inside, peak)
    return {"peak": peak, **_region_shape(X, Y, region, resolution)}


def _tangent_samples(azimuth, elevation, values, centre_elevation: float, max_angle: float):
    """The views within 1.5 ``max_angle`` of the lobe's direction (elevation ``centre_elevation`` on the plane
    phi = 0) in its tangent plane: (x, y) in degrees and their values, mirrored across the plane. None when no
    view there has a value of at least 1 (0-255)."""
    az, el = np.asarray(azimuth, float), np.asarray(elevation, float)
    A, E = np.meshgrid(az, el, indexing="ij")
    V = view_direction(E, A).reshape(-1, 3)
    v = np.asarray(values, float).reshape(-1)
    D = view_direction(float(centre_elevation), 0.0)
    cos_d = V @ D
    near = np.isfinite(v) & (cos_d > math.cos(math.radians(max_angle * 1.5)))
    if not near.any() or np.nanmax(v[near]) < 1.0:
        return None
    u1, u2 = _tangent_basis(D)
    x = np.degrees((V[near] @ u1) / cos_d[near])
    y = np.degrees((V[near] @ u2) / cos_d[near])
    # the plane phi = 0 folds at azimuth 0: mirror the half hemisphere (the surface and the light are symmetric in y)
    return np.concatenate([x, x]), np.concatenate([y, -y]), np.concatenate([v[near], v[near]])


def _tangent_grid(x, y, w, max_angle: float, resolution: float):
    """The values ``w`` at the tangent-plane points (``x``, ``y``) interpolated linearly onto a square grid of
    step ``resolution`` over [-max_angle, max_angle]^2 (degrees): X, Y and the values (NaN outside the points'
    hull), each (G, G); None when the points are too few to triangulate."""
    from scipy.interpolate import griddata

    axis = np.arange(-max_angle, max_angle + resolution / 2, resolution)
    X, Y = np.meshgrid(axis, axis, indexing="ij")
    try:
        grid = griddata((x, y), w, (X, Y), method="linear")
    except (ValueError, RuntimeError):  # too few views near the lobe to triangulate (a coarse sweep: QhullError)
        return None
    return X, Y, grid


def _peak_region(grid, inside, peak: float) -> np.ndarray:
    """(G, G) bool: the connected part of the grid at or above half of ``peak`` that holds the peak."""
    from scipy import ndimage

    above = inside & (grid >= peak / 2.0)
    labels, _ = ndimage.label(above)
    ip, jp = np.unravel_index(int(np.argmax(np.where(inside, grid, -np.inf))), grid.shape)
    return labels == labels[ip, jp]


def _region_shape(X, Y, region, resolution: float) -> dict:
    """``area`` (deg^2), ``rectangularity`` and ``elongation`` of the grid ``region`` (see :func:`lobe_shape`):
    the bounding rectangle is along the region's principal axes, each side one grid step wider than its points."""
    pts = np.stack([X[region], Y[region]], axis=1)
    area = float(region.sum()) * resolution**2
    if len(pts) < 3:
        return {"area": area, "rectangularity": np.nan, "elongation": np.nan}
    centred = pts - pts.mean(axis=0)
    _, vectors = np.linalg.eigh(np.cov(centred.T))
    along = centred @ vectors
    extent = along.max(axis=0) - along.min(axis=0) + resolution
    return {"area": area, "rectangularity": float(area / (extent[0] * extent[1])),
            "elongation": float(extent.max() / extent.min())}


def phase_shift(azimuth, elevation, values, centre_elevation: float, halfwidth: float = 30.0,
                max_azimuth: float = 60.0) -> float:
    """Mean distance (degrees) of each arc's lobe peak from where a circular lobe would peak (Fig. 19).

    A lobe circular around the direction ``D`` (its peak on the light's plane)
    peaks on the half great circle at azimuth ``phi`` at the elevation nearest
    ``D``: ``e*(phi) = atan2(Dz, Dx cos phi)``. The shift is the mean of
    ``|e_peak(phi) - e*(phi)|`` over the arcs ``0 < phi <= max_azimuth``
    where the lobe's arc maximum is at least half its maximum on ``phi = 0``.
    NaN when no such arc exists.
    """
    from .lobes import lobe_track

    track = lobe_track(azimuth, elevation, values, centre_elevation, halfwidth)
    on_plane = track.loc[np.isclose(track["azimuth"], 0.0), "value"]
    if on_plane.empty or float(on_plane.iloc[0]) < 1.0:
        return np.nan
    D = view_direction(float(centre_elevation), 0.0)
    phi = np.radians(track["azimuth"].to_numpy(float))
    expected = np.degrees(np.arctan2(D[2], D[0] * np.cos(phi)))
    keep = ((track["azimuth"] > 0) & (track["azimuth"] <= max_azimuth)
            & (track["value"] >= float(on_plane.iloc[0]) / 2.0) & track["elevation"].notna()).to_numpy()
    if not keep.any():
        return np.nan
    return float(np.mean(np.abs(track["elevation"].to_numpy(float)[keep] - expected[keep])))


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


def seed_statistics(study: pd.DataFrame, lobe_halfwidth: float = 40.0) -> pd.DataFrame:
    """Every statistic of :data:`STATISTICS` per kind, seed and grid point (random points only).

    Returns
    -------
    DataFrame: :data:`ENSEMBLE_KEYS`, ``statistic``, ``value``.
    """
    from .diffuse import diffuse_levels, diffuse_three_part
    from .lobes import arc_lobes

    rows = []
    for kind, seed, group in _per_sweep(random_points(study)):
        lobes = arc_lobes(group, max_halfwidth=lobe_halfwidth)
        levels = diffuse_levels(group).set_index(SURFACE_KEYS)
        parts = diffuse_three_part(group).set_index(SURFACE_KEYS)
        grids = {key: (az, el, vals) for key, az, el, vals in surface_grids(group, "specular")}
        for key, (az, el, vals) in grids.items():
            stats = {}
            for lobe in ("forward", "back"):
                row = lobes[(lobes[SURFACE_KEYS].to_numpy(float) == np.array(key)).all(axis=1) & (lobes["lobe"] == lobe)]
                # a flagged maximum (below one 8-bit step, on the window's edge) is not a lobe: no statistics
                found = not row.empty and np.isfinite(row["peak"].iloc[0]) and row["note"].iloc[0] == ""
                stats[f"{lobe}_peak"] = float(row["peak"].iloc[0]) if found else np.nan
                stats[f"{lobe}_centre"] = float(row["peak_elevation"].iloc[0]) if found else np.nan
                stats[f"{lobe}_width"] = float(row["fwhm"].iloc[0]) if found else np.nan
            centre = stats["back_centre"]
            shape = lobe_shape(az, el, vals, centre) if np.isfinite(centre) else {"rectangularity": np.nan}
            stats["back_rectangularity"] = shape["rectangularity"]
            stats["back_phase_shift"] = phase_shift(az, el, vals, centre) if np.isfinite(centre) else np.nan
            stats["diffuse_level"] = float(levels.loc[key, "diffuse_level"])
            stats["diffuse_level1"] = float(parts.loc[key, "level1"])
            stats["diffuse_level3"] = float(parts.loc[key, "level3"])
            stats["diffuse_rate"] = float(parts.loc[key, "rate_continuous"])
            for name, value in stats.items():
                rows.append({"kind": kind, "seed": seed, "truncation": key[0], "aspect": key[1], "incidence": key[2],
                             "statistic": name, "value": value})
    return pd.DataFrame(rows, columns=ENSEMBLE_KEYS + ["statistic", "value"])


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


def pooled_statistics(study: pd.DataFrame, lobe_halfwidth: float = 40.0) -> pd.DataFrame:
    """:func:`seed_statistics` of each random kind's seed-averaged views (:func:`pooled_study`)."""
    pooled = pooled_study(study)
    if pooled.empty:
        return pd.DataFrame(columns=ENSEMBLE_KEYS + ["statistic", "value"])
    return seed_statistics(pooled, lobe_halfwidth)


def ensemble_summary(stats: pd.DataFrame, level: float = 0.95, pooled: pd.DataFrame | None = None) -> pd.DataFrame:
    """Ensemble means with Student-t intervals over seeds, beside the regular surface, and a t-test.

    Parameters
    ----------
    stats : DataFrame from :func:`seed_statistics`.

    Returns
    -------
    DataFrame, one row per random kind x grid point x statistic: ``kind``,
    surface keys, ``statistic``, ``unit``, ``seeds`` (n with a value),
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
                     "unit": STATISTICS.get(name, ""), "seeds": n, "mean": mean, "sd": sd,
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


#: The thesis's claim, one test a statistic: what a random surface should show against the regular one, and how
#: close an interval must be to decide "no difference" (relative to the regular value, or absolute).
CLAIMS = {
    "back_rectangularity": {"claim": "random lobes are less rectangular than the regular surface's",
                            "shows": "fill of the back lobe's half-maximum region in its bounding rectangle "
                                     "(1 rectangle, π/4 ellipse)", "relative": 0.10, "absolute": None,
                            "range": (0.0, 1.0)},
    "back_phase_shift": {"claim": "random lobes peak where a circular lobe would: less phase shift off the "
                                  "light's plane", "shows": "mean distance of the off-plane arcs' peaks from a "
                                                            "circular lobe's (deg)", "relative": None,
                         "absolute": 2.0, "range": (0.0, math.inf)},
}


def claim_interval(row, rule) -> tuple[float, float]:
    """The interval a claim is decided on: the wider of the Student-t and the bootstrap 95% intervals of the mean,
    cut to the statistic's range (``rule["range"]``). With a handful of seeds the bootstrap alone is far too
    narrow (with 2 seeds its resampled means take 3 values), and Student-t alone can leave the range."""
    low, high = rule["range"]
    lows = [v for v in (row.get("ci_low", np.nan), row["boot_low"]) if np.isfinite(v)]
    highs = [v for v in (row.get("ci_high", np.nan), row["boot_high"]) if np.isfinite(v)]
    if not lows or not highs:
        return np.nan, np.nan
    return max(low, min(lows)), min(high, max(highs))


def _tolerance(row, rule) -> float:
    """How close to the regular value a claim row's interval must lie to decide "no difference" (``rule``:
    absolute, or relative to the regular value)."""
    return rule["absolute"] if rule["absolute"] is not None else rule["relative"] * abs(row["regular"])


def _decision(row, rule) -> tuple[str, str]:
    """(decided, why) for one claim row: decided when its interval (:func:`claim_interval`, in ``row["low"]``,
    ``row["high"]``) excludes the regular value, or lies within the tolerance of it (``rule``: relative to the
    regular value or absolute)."""
    if not np.isfinite(row["regular"]):
        return "–", "the regular surface has no back lobe here (its maximum is below one 8-bit step or on the " \
                    "window's edge), so there is nothing to compare"
    if row["seeds"] < 2 or not np.isfinite(row["low"]):
        return "–", f"{int(row['seeds'])} seed(s) with a back lobe: an interval needs 2 or more (surface.seeds)"
    tolerance = _tolerance(row, rule)
    if row["low"] > row["regular"] or row["high"] < row["regular"]:
        side = "above" if row["low"] > row["regular"] else "below"
        return "yes", f"the interval lies {side} the regular value"
    if row["regular"] - tolerance <= row["low"] and row["high"] <= row["regular"] + tolerance:
        return "yes", f"no difference: the interval lies within ±{tolerance:.3g} of the regular value"
    return "no", "the interval holds the regular value and is wider than the tolerance: more seeds"


def claim_table(summary: pd.DataFrame, level: float = 0.95) -> pd.DataFrame:
    """The thesis's rectangular-lobe claim as one table: per random kind, grid point and test (:data:`CLAIMS`),
    the regular value, the ensemble's mean with its interval (:func:`claim_interval`), whether the test is decided
    and why, and the seeds that would decide it (from the seed-to-seed SD: the fewest whose t-interval excludes the regular
    value or fits the tolerance).

    Parameters
    ----------
    summary : DataFrame from :func:`ensemble_summary`.

    Returns
    -------
    DataFrame: ``kind``, surface keys, ``test``, ``claim``, ``shows``, ``regular``, ``mean``, ``low``, ``high``
    (the interval), ``seeds``, ``decided`` ("yes", "no" or "–"), ``why``, ``seeds_to_decide`` (Int64, <NA>
    where it cannot be estimated).
    """
    from scipy import stats as sps

    rows = []
    part = summary[summary["statistic"].isin(list(CLAIMS))]
    for _, r in part.iterrows():
        rule = CLAIMS[r["statistic"]]
        r = r.copy()
        r["low"], r["high"] = claim_interval(r, rule)
        decided, why = _decision(r, rule)
        need = pd.NA
        if np.isfinite(r["sd"]) and r["sd"] > 0 and np.isfinite(r["regular"]):
            target = max(abs(r["mean"] - r["regular"]), _tolerance(r, rule) / 2.0)
            n = np.arange(2, 10_001)
            ok = np.flatnonzero(sps.t.ppf(0.5 + level / 2, n - 1) * r["sd"] / np.sqrt(n) <= target)
            need = int(n[ok[0]]) if len(ok) else 10_000
        rows.append({"kind": r["kind"], "truncation": r["truncation"], "aspect": r["aspect"],
                     "incidence": r["incidence"], "test": r["statistic"], "claim": rule["claim"],
                     "shows": rule["shows"], "regular": r["regular"], "mean": r["mean"], "low": r["low"],
                     "high": r["high"], "seeds": int(r["seeds"]), "decided": decided, "why": why,
                     "seeds_to_decide": need})
    out = pd.DataFrame(rows)
    if len(out):
        out["seeds_to_decide"] = pd.array(out["seeds_to_decide"], dtype="Int64")
    return out


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
    within 0.02 levels, would predict), diffuse and specular.

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
        seen = joined["coverage"] > 0
        for component in ("diffuse", "specular"):
            part = joined[seen & (joined["component"].astype(str) == component)]
            err = (part["rough"] - part["regular"]) ** 2
            rmse = err.groupby([part[k] for k in SURFACE_KEYS]).mean() ** 0.5
            fits[f"rmse_regular_{component}"] = [float(rmse.get(tuple(k), np.nan))
                                                 for k in fits[SURFACE_KEYS].itertuples(index=False)]
        frames.append(fits)
    return pd.concat(frames, ignore_index=True)
