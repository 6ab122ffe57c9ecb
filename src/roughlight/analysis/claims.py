"""The thesis's random-roughness claim as a design stated before the test, and its verdict.

The claim (Ch. IV.C, VI): regular pyramids reflect in "rectangular" patterns whose peak shifts off the light's
plane, where surfaces with random facets reflect in circular lobes. Two statistics of the back lobe (the
light-facing facets' mirror direction) put it into numbers, both read from the measured views of the whole lobe
(:mod:`roughlight.analysis.lobe_shape`):

* ``back_squareness``: how much closer the lobe's half-maximum region lies to its rectangle than to its ellipse
  (each with the region's own second moments): > 0 rectangular, < 0 elliptical (a circle is an ellipse). On
  synthetic lobes a rectangle gives +0.10 to +0.15 and an ellipse -0.17 to -0.19. The claim: a random surface's
  lobe is less square than the regular surface's.
* ``back_phase_shift``: the mean distance (degrees) of each measured arc's peak from where a circular lobe around
  the region's centre would put it (Fig. 19's "phase shift"). The claim: a random surface's is smaller.

The design, fixed before any tested seed is read (:func:`claim_design`):

* **What can be measured.** A lobe is measurable when its half-maximum region closes inside the measured views
  (the horizon cuts none of it) and its peak is at least ``min_peak`` 8-bit levels (:func:`floor_effect` measures
  what rounding each view to whole levels does to the statistics of synthetic lobes of a given peak).
* **Margins.** A difference counts, and "no difference" can be concluded, relative to a margin a statistic:
  the largest of the regular surface's own rendering noise (the same statistic from the two halves of the
  hemisphere of a mirror-symmetric surface, each measured separately, :func:`rendering_noise`) and the 8-bit
  floor's effect on a lobe at least ``min_peak`` high. Smaller differences are within what rendering and 8 bits
  alone produce.
* **Family.** Every planned test (random kind x grid point x statistic) is one of a family whose error is
  controlled together: each interval is a Student-t interval at the Bonferroni level ``1 - alpha / m``.
* **Seeds.** Each ensemble has pilot seeds (numbered from :data:`PILOT_SEED_BASE` + 1) that are never tested: their
  spread and effect give the test seeds each test needs (:func:`planned_seeds`); the test seeds are those the config
  names (1 ... n), counted beside what the pilot asks for.
* **Decision** (:func:`decide`): "difference" when the interval lies wholly outside the margin around the regular
  value, "no difference" when wholly inside it, "undecided" otherwise (with the seeds the pilot's spread says would
  decide it), and "not measurable" when the regular lobe is not, or fewer than half of the tested seeds (or
  fewer than 2) have a measurable lobe: a statistic of a minority of tiles says nothing of the kind.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..study.config import PILOT_SEED_BASE
from ..study.selection import SURFACE_KEYS

__all__ = [
    "PILOT_SEED_BASE",
    "CLAIMS",
    "is_pilot",
    "floor_effect",
    "rendering_noise",
    "margins",
    "planned_seeds",
    "fewest_seeds",
    "claim_design",
    "decide",
    "claim_table",
]

#: The claim's tests, a statistic each: what the thesis says of a random surface against the regular one, which
#: way, what the statistic shows, and the range it takes.
CLAIMS = {
    "back_squareness": {
        "claim": "random lobes are rounder (less rectangular) than the regular surface's",
        "expected": "below",
        "shows": "the half-maximum region's misfit to its ellipse less its misfit to its rectangle (> 0 nearer a "
                 "rectangle, < 0 nearer an ellipse)",
        "unit": "",
        "range": (-1.0, 1.0),
    },
    "back_phase_shift": {
        "claim": "random lobes peak where a circular lobe would: less phase shift off the light's plane",
        "expected": "below",
        "shows": "mean distance of the measured arcs' peaks from a circular lobe's, both sides of the light's plane",
        "unit": "deg",
        "range": (0.0, math.inf),
    },
}


def is_pilot(seed) -> np.ndarray | bool:
    """Whether ``seed`` (an int or an array) is a claim design's pilot seed (above :data:`PILOT_SEED_BASE`)."""
    return np.asarray(seed) > PILOT_SEED_BASE if np.ndim(seed) else int(seed) > PILOT_SEED_BASE


# ---------------------------------------------------------------------------------------------------------------
# the design's measurements


#: The synthetic lobes :func:`floor_effect` rounds: Gaussian ellipses and soft-edged rectangles of several sizes
#: and orientations, (half-widths in degrees of tangent plane, edge softness or None, rotation in degrees).
SYNTHETIC_LOBES = (
    (10.0, 10.0, None, 0.0), (12.0, 5.0, None, 30.0), (6.0, 4.0, None, 0.0),
    (8.0, 8.0, 0.5, 0.0), (12.0, 6.0, 0.5, 30.0), (5.0, 3.0, 0.5, 0.0),
)


def synthetic_lobe(azimuth, elevation, centre, half_widths, soft=None, rotation=0.0, peak=100.0) -> np.ndarray:
    """(A, E) values of a synthetic lobe around the unit direction ``centre`` on the view grid: a Gaussian
    ``peak exp(-(x/wx)^2 - (y/wy)^2)`` or, with ``soft`` (degrees), a rectangle of half-widths (wx, wy) with
    logistic edges, in gnomonic tangent-plane coordinates (degrees) rotated by ``rotation``; 0 where the view
    faces away from ``centre``."""
    from ..render.shading import view_direction
    from .lobe_shape import tangent_basis

    A, El = np.meshgrid(np.asarray(azimuth, float), np.asarray(elevation, float), indexing="ij")
    V = view_direction(El, A)
    D = np.asarray(centre, float)
    u1, u2 = tangent_basis(D)
    cos_d = V @ D
    with np.errstate(divide="ignore", invalid="ignore"):
        x0, y0 = np.degrees((V @ u1) / cos_d), np.degrees((V @ u2) / cos_d)
    c, s = math.cos(math.radians(rotation)), math.sin(math.radians(rotation))
    x, y = c * x0 + s * y0, -s * x0 + c * y0
    wx, wy = half_widths
    if soft is None:
        values = peak * np.exp(-((x / wx) ** 2 + (y / wy) ** 2))
    else:
        edge = np.clip(np.maximum(np.abs(x) - wx, np.abs(y) - wy) / soft, -50, 50)
        values = peak / (1 + np.exp(edge))
    return np.where(cos_d > 0, values, 0.0)


def floor_effect(peaks, centre_elevation: float, azimuth, elevation) -> pd.DataFrame:
    """What rounding every view to whole 8-bit levels does to the claim's statistics, lobe by lobe.

    Each of :data:`SYNTHETIC_LOBES`, centred at ``centre_elevation`` on the light's plane and scaled to each of
    ``peaks`` (0-255), is measured on the view grid (``azimuth`` x ``elevation``, degrees) as it is and rounded to
    whole levels (the worst case: a view's capture window all one value; a real view averages many pixels).

    Returns
    -------
    DataFrame, one row a peak: ``peak`` and, per claim statistic, the largest change over the synthetic lobes.
    """
    from .lobe_shape import SHAPE_STATISTICS, direction, lobe_statistics, measured_field

    az, el = np.asarray(azimuth, float), np.asarray(elevation, float)
    coverage = np.ones((len(az), len(el)))
    coverage[:, (el <= 0) | (el >= 180)] = 0.0
    centre = direction(0.0, centre_elevation)
    rows = []
    for peak in peaks:
        worst = dict.fromkeys(CLAIMS, 0.0)
        for wx, wy, soft, rotation in SYNTHETIC_LOBES:
            values = synthetic_lobe(az, el, centre, (wx, wy), soft, rotation, float(peak))
            exact, rounded = (lobe_statistics(measured_field(az, el, v, coverage), centre)
                              for v in (values, np.floor(values + 0.5)))
            for name in CLAIMS:
                change = abs(exact[SHAPE_STATISTICS[name]] - rounded[SHAPE_STATISTICS[name]])
                worst[name] = max(worst[name], float(change) if np.isfinite(change) else np.inf)
        rows.append({"peak": float(peak), **worst})
    return pd.DataFrame(rows)


def mirrored_half(values, side: int) -> np.ndarray:
    """An (A, E) grid (azimuths 0, step, ... < 180; elevations symmetric about 90) whose views on one side of the
    light's plane are replaced by their mirror images' ((180 - phi, 180 - e)) from the other: ``side`` +1 keeps
    the views at y >= 0 (e <= 90), -1 those at y <= 0. Only for a surface that is itself mirror-symmetric in the
    light's plane (the regular pyramids): its two halves are then two separate measurements of one lobe."""
    vals = np.asarray(values, float)
    out = vals.copy()
    n_az, n_el = vals.shape
    half = (n_el - 1) // 2
    replace = np.arange(n_el) > half if side > 0 else np.arange(n_el) < half
    for k in range(1, n_az):
        out[k, replace] = vals[n_az - k, ::-1][replace]
    return out


def rendering_noise(grids: dict, min_peak: float) -> pd.DataFrame:
    """The regular surface's rendering noise in each claim statistic: the statistic from each half of the
    hemisphere (:func:`mirrored_half`), measured separately, one against the other.

    Parameters
    ----------
    grids : dict, surface key (truncation, aspect, incidence) -> (azimuth, elevation, specular, coverage, peak
        direction) of a regular surface's back lobe
    min_peak : the 8-bit floor (0-255)

    Returns
    -------
    DataFrame: surface keys and, per claim statistic, ``{statistic}_half_a``, ``{statistic}_half_b`` and
    ``{statistic}_noise`` (their absolute difference).
    """
    from .lobe_shape import SHAPE_STATISTICS, lobe_statistics, measured_field

    rows = []
    for key, (az, el, values, coverage, peak_direction) in grids.items():
        row = dict(zip(SURFACE_KEYS, key))
        halves = [lobe_statistics(measured_field(az, el, mirrored_half(values, side), coverage), peak_direction,
                                  min_peak) for side in (1, -1)]
        for name in CLAIMS:
            a, b = (h[SHAPE_STATISTICS[name]] if h["measurable"] else np.nan for h in halves)
            row.update({f"{name}_half_a": a, f"{name}_half_b": b, f"{name}_noise": abs(a - b)})
        rows.append(row)
    return pd.DataFrame(rows)


def margins(noise: pd.DataFrame, floor: pd.DataFrame, min_peak: float) -> pd.DataFrame:
    """Each claim statistic's margin: the larger of the regular surface's largest rendering noise
    (:func:`rendering_noise`) and the 8-bit floor's largest effect on lobes at least ``min_peak`` high
    (:func:`floor_effect`).

    Returns
    -------
    DataFrame, one row a statistic: ``statistic``, ``rendering_noise``, ``floor_effect``, ``margin``, ``from``
    (which of the two sets it).
    """
    rows = []
    for name in CLAIMS:
        rendered = float(np.nanmax(noise[f"{name}_noise"])) if len(noise) and noise[f"{name}_noise"].notna().any() \
            else 0.0
        above = floor.loc[floor["peak"] >= min_peak, name]
        rounded = float(above.max()) if len(above) else 0.0
        rows.append({"statistic": name, "rendering_noise": rendered, "floor_effect": rounded,
                     "margin": max(rendered, rounded),
                     "from": "rendering noise" if rendered > rounded else "8-bit floor"})
    return pd.DataFrame(rows)


def _t_quantile(level: float, n):
    from scipy import stats as sps

    return sps.t.ppf(0.5 + level / 2.0, np.asarray(n) - 1)


def fewest_seeds(sd: float, room: float, level: float, max_seeds: int) -> int | None:
    """The fewest seeds n (2 ... ``max_seeds``) whose ``level`` Student-t half-width ``t(n - 1) sd / sqrt(n)`` is
    at most ``room``; None when no such n (or no room)."""
    if room <= 0:
        return None
    n = np.arange(2, max_seeds + 1)
    ok = np.flatnonzero(_t_quantile(level, n) * sd / np.sqrt(n) <= room)
    return int(n[ok[0]]) if len(ok) else None


def planned_seeds(pilot_values, regular: float, margin: float, level: float, max_seeds: int = 1000,
                 sd_confidence: float = 0.8) -> tuple[int | None, str]:
    """Test seeds a claim test needs, from its pilot seeds (never tested).

    The pilot's mean difference from the regular value ``d`` and its SD (taken at its one-sided
    ``sd_confidence`` upper confidence limit, as pilot-based plans do: a pilot of 3 seeds estimates an SD
    poorly) give the fewest seeds ``n`` whose ``level`` Student-t interval, centred on ``d``, lies wholly outside
    the margin (``|d| - h(n) >= margin``, a difference) or wholly inside it (``|d| + h(n) <= margin``, no
    difference), ``h(n) = t(n - 1) sd / sqrt(n)``.

    Returns
    -------
    (n, why): n is None when the pilot cannot say (fewer than 2 measurable pilot seeds, no regular value) or
    when no n up to ``max_seeds`` decides (``|d|`` is within ``h`` of the margin); why says which.
    """
    from scipy import stats as sps

    values = np.asarray(pilot_values, float)
    values = values[np.isfinite(values)]
    if not np.isfinite(regular):
        return None, "the regular lobe is not measurable"
    if len(values) < 2:
        return None, f"{len(values)} measurable pilot seed(s): a spread needs 2"
    d = abs(float(values.mean()) - regular)
    sd = float(values.std(ddof=1))
    df = len(values) - 1
    sd_upper = sd * math.sqrt(df / sps.chi2.ppf(1.0 - sd_confidence, df))
    room = d - margin if d > margin else margin - d
    if sd_upper == 0:
        return 2, "the pilot seeds agree exactly"
    n = fewest_seeds(sd_upper, room, level, max_seeds)
    if n is None:
        return None, (f"the pilot's difference {d:.3g} lies within its spread of the margin {margin:.3g}: more than "
                      f"{max_seeds} seeds")
    return n, ("a difference" if d > margin else "no difference") + " expected from the pilot"


def claim_design(statistics: pd.DataFrame, design: dict, margin_table: pd.DataFrame, configured: dict
                 ) -> pd.DataFrame:
    """The claim's design, a test a row: what each test needs, from the pilot seeds alone.

    Parameters
    ----------
    statistics : per-seed statistics (:func:`roughlight.analysis.ensembles.seed_statistics`): kind, seed, surface
        keys, ``statistic``, ``value``; pilot seeds are those :func:`is_pilot` names, the regular surface's rows
        are kind ``pyramids``
    design : ``alpha`` (family-wise error), ``max_seeds`` (the most test seeds an ensemble may take)
    margin_table : from :func:`margins`
    configured : (kind, truncation, aspect) -> the number of test seeds the config gives the ensemble

    Returns
    -------
    DataFrame: kind, surface keys, ``test``, ``family`` (tests in the family), ``level`` (each interval's),
    ``margin``, ``regular``, ``pilot_seeds``, ``pilot_measurable``, ``pilot_mean``, ``pilot_sd``, ``seeds_needed``
    (Int64), ``plan`` (why), ``seeds_configured``.
    """
    tests = _planned_tests(statistics)
    family = len(tests)
    level = 1.0 - float(design["alpha"]) / max(family, 1)
    margin_of = margin_table.set_index("statistic")["margin"]
    regular = _regular_values(statistics)
    pilots = statistics[(statistics["kind"] != "pyramids") & is_pilot(statistics["seed"].to_numpy())]
    rows = []
    for kind, t, a, i, name in tests:
        values = pilots.loc[(pilots["kind"] == kind) & (pilots["truncation"] == t) & (pilots["aspect"] == a)
                            & (pilots["incidence"] == i) & (pilots["statistic"] == name), "value"].to_numpy(float)
        reg = float(regular.get((t, a, i, name), np.nan))
        need, why = planned_seeds(values, reg, float(margin_of[name]), level, int(design["max_seeds"]))
        finite = values[np.isfinite(values)]
        rows.append({"kind": kind, "truncation": t, "aspect": a, "incidence": i, "test": name, "family": family,
                     "level": level, "margin": float(margin_of[name]), "regular": reg, "pilot_seeds": len(values),
                     "pilot_measurable": len(finite), "pilot_mean": float(finite.mean()) if len(finite) else np.nan,
                     "pilot_sd": float(finite.std(ddof=1)) if len(finite) > 1 else np.nan,
                     "seeds_needed": need, "plan": why,
                     "seeds_configured": int(configured.get((kind, t, a), 0))})
    out = pd.DataFrame(rows, columns=["kind"] + SURFACE_KEYS + [
        "test", "family", "level", "margin", "regular", "pilot_seeds", "pilot_measurable", "pilot_mean", "pilot_sd",
        "seeds_needed", "plan", "seeds_configured"])
    out["seeds_needed"] = pd.array(out["seeds_needed"], dtype="Int64")
    return out


def _planned_tests(statistics: pd.DataFrame) -> list[tuple]:
    """Every planned test: (kind, truncation, aspect, incidence, statistic) for each random ensemble (the
    grid points with random tiles) and claim statistic, in order; fixed by the design, not by any outcome."""
    random = statistics[statistics["kind"] != "pyramids"]
    ensembles = random[["kind"] + SURFACE_KEYS].drop_duplicates().sort_values(["kind"] + SURFACE_KEYS)
    return [(str(r.kind), float(r.truncation), float(r.aspect), float(r.incidence), name)
            for r in ensembles.itertuples(index=False) for name in CLAIMS]


def _regular_values(statistics: pd.DataFrame) -> pd.Series:
    regular = statistics[statistics["kind"] == "pyramids"]
    return regular.set_index(SURFACE_KEYS + ["statistic"])["value"]


def decide(mean: float, low: float, high: float, regular: float, margin: float, expected: str) -> tuple[str, str]:
    """One test's verdict from its interval [low, high] against the regular value and the margin: "difference"
    (the interval wholly beyond ``regular +- margin``; ``expected`` "below" or "above" says whether it goes the
    way the thesis claims), "no difference" (wholly within), or "undecided". Returns (verdict, why)."""
    if low > regular + margin or high < regular - margin:
        side = "above" if low > regular + margin else "below"
        agrees = "as the thesis claims" if side == expected else "against the thesis's claim"
        return "difference", f"the interval lies {side} the regular value by more than the margin ({agrees})"
    if regular - margin <= low and high <= regular + margin:
        return "no difference", f"the interval lies within ±{margin:.3g} of the regular value"
    return "undecided", "the interval reaches across the margin's edge"


def claim_table(statistics: pd.DataFrame, design_table: pd.DataFrame) -> pd.DataFrame:
    """The claim's verdict, a test a row, from the tested seeds only (the pilots never enter).

    Every tested seed is accounted for: ``seeds`` (rendered and tested), ``measurable`` (with a measurable lobe)
    and ``left_out`` (how many were not, and why, grouped). The interval is Student-t at the design's level,
    cut to the statistic's range.

    Returns
    -------
    DataFrame: kind, surface keys, ``test``, ``claim``, ``regular``, ``margin``, ``level``, ``seeds``,
    ``measurable``, ``left_out``, ``mean``, ``sd``, ``low``, ``high``, ``verdict`` ("difference", "no difference",
    "undecided" or "not measurable"), ``why``, ``agrees`` (True where a difference goes the way the thesis
    claims, False against it, <NA> otherwise), ``seeds_needed`` (the pilot's plan), ``seeds_to_decide`` (from the
    tested seeds' spread, where undecided: how many would narrow the interval enough; Int64).
    """
    tested = statistics[(statistics["kind"] != "pyramids") & ~is_pilot(statistics["seed"].to_numpy())]
    rows = []
    for d in design_table.itertuples(index=False):
        part = tested[(tested["kind"] == d.kind) & (tested["truncation"] == d.truncation)
                      & (tested["aspect"] == d.aspect) & (tested["incidence"] == d.incidence)
                      & (tested["statistic"] == d.test)]
        rows.append(_claim_row(d, part))
    out = pd.DataFrame(rows)
    if len(out):
        for column in ("seeds_needed", "seeds_to_decide"):
            out[column] = pd.array(out[column], dtype="Int64")
        out["agrees"] = pd.array(out["agrees"], dtype="boolean")
    return out


def _left_out(part: pd.DataFrame) -> str:
    """The tested seeds without a value, grouped by why: ``"2 cut by the horizon (seeds 3, 7)"``."""
    missing = part[part["value"].isna()]
    if missing.empty:
        return ""
    groups = []
    for why, g in missing.groupby(missing["note"].fillna("").str.split(":").str[0], sort=True):
        groups.append(f"{len(g)} {why or 'without a value'} (seed{'s' if len(g) > 1 else ''} "
                      f"{', '.join(str(int(s)) for s in sorted(g['seed']))})")
    return "; ".join(groups)


def _claim_row(d, part: pd.DataFrame) -> dict:
    """One test's row of :func:`claim_table` from its design row ``d`` and its tested seeds' rows ``part``."""
    rule = CLAIMS[d.test]
    values = part["value"].to_numpy(float)
    finite = values[np.isfinite(values)]
    n, k = len(values), len(finite)
    row = {"kind": d.kind, "truncation": d.truncation, "aspect": d.aspect, "incidence": d.incidence, "test": d.test,
           "claim": rule["claim"], "regular": d.regular, "margin": d.margin, "level": d.level, "seeds": n,
           "measurable": k, "left_out": _left_out(part), "mean": float(finite.mean()) if k else np.nan,
           "sd": float(finite.std(ddof=1)) if k > 1 else np.nan, "low": np.nan, "high": np.nan,
           "verdict": "not measurable", "why": "", "agrees": pd.NA, "seeds_needed": d.seeds_needed,
           "seeds_to_decide": pd.NA}
    if not np.isfinite(d.regular):
        row["why"] = "the regular surface's lobe is not measurable here"
        return row
    if k < 2 or 2 * k < n:
        row["why"] = f"{k} of {n} tested seeds have a measurable lobe: the test needs at least half of them and 2"
        return row
    half = float(_t_quantile(d.level, k) * row["sd"] / math.sqrt(k))
    lo, hi = rule["range"]
    row["low"], row["high"] = max(lo, row["mean"] - half), min(hi, row["mean"] + half)
    row["verdict"], row["why"] = decide(row["mean"], row["low"], row["high"], d.regular, d.margin, rule["expected"])
    if row["verdict"] == "difference":
        row["agrees"] = (row["low"] > d.regular) == (rule["expected"] == "above")
    if row["verdict"] == "undecided" and row["sd"] > 0:
        need = fewest_seeds(row["sd"], abs(abs(row["mean"] - d.regular) - d.margin), d.level, 10_000)
        row["seeds_to_decide"] = pd.NA if need is None else need
        row["why"] += (f"; about {need} measurable seeds at this spread would decide it" if need is not None
                       else "; its mean sits on the margin's edge: no number of seeds decides it")
    return row


#: The peaks (0-255) at which :func:`floor_effect` rounds its synthetic lobes.
FLOOR_PEAKS = (4.0, 6.0, 8.0, 10.0, 12.0, 16.0, 24.0, 32.0)


def regular_back_lobes(study: pd.DataFrame) -> dict:
    """The regular surface's back lobes at the random grid points: surface key -> (azimuth, elevation, specular,
    coverage, peak direction), for :func:`rendering_noise`; a surface without a back lobe to look at is left out."""
    from .grids import surface_value_grids
    from .lobe_shape import back_lobe_peak

    regular = study[study["kind"].astype(str) == "pyramids"] if "kind" in study else study
    out = {}
    if regular.empty:
        return out
    for key, az, el, grids in surface_value_grids(regular, "specular", ("rough", "coverage")):
        peak_direction, _ = back_lobe_peak(key, az, el, grids["rough"], grids["coverage"])
        if peak_direction is not None:
            out[key] = (az, el, grids["rough"], grids["coverage"], peak_direction)
    return out


def design_tables(study: pd.DataFrame, statistics: pd.DataFrame, claims: dict) -> dict:
    """The claim's design and verdict as the tables rule ``analysis_random`` writes.

    Parameters
    ----------
    study : the study's rows at the random grid points (the regular surface's among them)
    statistics : per-seed statistics (:func:`roughlight.analysis.ensembles.seed_statistics`, pilot seeds included)
    claims : :func:`roughlight.study.config.claim_settings`

    Returns
    -------
    dict of DataFrames: ``random_claim_floor`` (:func:`floor_effect` at each distinct back-lobe elevation of the
    regular surface, the largest change kept), ``random_claim_noise`` (:func:`rendering_noise`),
    ``random_claim_margins`` (:func:`margins`), ``random_claim_design`` (:func:`claim_design`) and
    ``random_claims`` (:func:`claim_table`).
    """
    min_peak = float(claims["min_peak"])
    lobes = regular_back_lobes(study)
    noise = rendering_noise(lobes, min_peak)
    if lobes:
        az, el = next(iter(lobes.values()))[:2]
        elevations = sorted({round(float(np.degrees(np.arcsin(v[4][2])))) for v in lobes.values()})
        floors = [floor_effect(FLOOR_PEAKS, e, az, el) for e in elevations]
        floor = pd.concat(floors).groupby("peak", as_index=False).max()
    else:
        floor = pd.DataFrame({"peak": list(FLOOR_PEAKS), **{name: np.nan for name in CLAIMS}})
    margin_table = margins(noise, floor, min_peak)
    configured = {(kind, float(t), float(a)): int(n) for kind, t, a, n in claims.get("tested", [])}
    design = claim_design(statistics, claims, margin_table, configured)
    if int(claims.get("pilot_seeds", 0)) == 0:
        design["plan"] = "no pilot seeds (claims.pilot_seeds 0): no plan"
    return {"random_claim_floor": floor, "random_claim_noise": noise, "random_claim_margins": margin_table,
            "random_claim_design": design, "random_claims": claim_table(statistics, design)}
