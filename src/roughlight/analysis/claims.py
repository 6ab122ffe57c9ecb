"""The thesis's random-roughness claim as a design fixed before the test, and its verdict.

The claim (Ch. IV.C, VI): regular pyramids reflect in "rectangular" patterns whose peak shifts off the light's
plane, where natural rough surfaces, whose facets are random, reflect in circular lobes (Fig. 18: the halo
around an airplane's shadow on grass). The surface the thesis means is a large random surface: an ensemble's
mean over its tiles (:mod:`roughlight.analysis.claim_readings`), compared with the regular surface at the same
grid point and light, on two lobes:

* the **back lobe** (the light-facing facet's mirror direction, Tables 1-2 and Fig. 19): does it exist (its
  contrast over its background), and is a random one less square and less phase-shifted than the regular one;
* the **hot spot** (V = L, Fig. 18): does its halo exist, and is a random one's edge rounder (less flat) than the
  regular one's.

The design (:func:`roughlight.analysis.steps.claim_tables`), fixed from geometry, the regular surfaces, the
exact reference and the pilot seeds, before any tested seed is read:

* **Which lobes, where** (:func:`claim_geometry`): each random grid point's lobe enters the claim when its regular
  lobe clears the horizon by :data:`CLEARANCE` of its own widths (the back mirror direction lies at elevation
  180 - (i + 2 alpha) for a facet tilted alpha toward a light at incidence i; the hot spot at i), and, for the hot
  spot, when the regular surface has shadows there to hide.
* **Search discs** (:func:`discs`): :data:`CLEARANCE` of the regular lobe's widths, for every kind: the back
  lobe's follows the material's shininess, the halo's its own width; the random lobes, 1.5-2 times the regular
  ones' width on the pilot seeds, fill two of theirs (the design table reports the pilot's width).
* **Margins** (:func:`margins`): what counts as a difference, for each test: the largest of the regular surface's
  rendering noise (each half of the hemisphere of a mirror-symmetric surface, read on its own), the fast method's
  sampling error against the exact reference on the study's view grid, and the view grid's own effect (the
  study's azimuth step against 1 deg); the 8-bit reading adds what rounding does to the regular lobe. No 8-bit
  floor: the unrounded values read lobes a few levels high. A shape statistic with a scale of its own (squareness:
  ellipse to rectangle; flatness: circle to flat edge) also has the smallest difference that matters to the
  thesis's question, a sixth of that scale: "no difference" needs an interval inside it, which the instrument's
  noise alone would put out of reach of any number of seeds.
* **Family** (:func:`claim_design`): every planned test (ensemble x lobe x statistic) is one of a family whose
  error is controlled together: each interval is a Student-t interval at the Bonferroni level ``1 - alpha / m``
  on the jackknife standard error over seeds.
* **Seeds** (:func:`planned_seeds`): the pilots, the claim's own pilot tiles of each ensemble (``claims.pilots``
  at ``claims.cells``, never tested), give by their mean and standard error the tested seeds each test needs; an
  ensemble tests as many as its most demanding test that ``claims.max_seeds`` seeds can decide (``claims.seeds``,
  fresh tiles).

The verdict (:func:`claim_table`), from the tested seeds only, in both readings (unrounded and 8-bit):

* a lobe's **contrast**: *lobe* when its interval lies wholly above the margin, *no lobe* when wholly below it
  (its contrast is within what the instrument cannot tell from none: random roughness removes it), *undecided*
  otherwise;
* a lobe's **shape**, where it has one: *difference* (the interval wholly beyond the margin around the regular
  value; the table says whether the way the thesis claims), *no difference* (wholly within it), *undecided*
  otherwise (with the seeds that would decide it); *no lobe* where the contrast test found none.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..render.shading import view_direction
from ..study.selection import SURFACE_KEYS
from .claim_readings import READINGS, SeedStack, lobe_centres, mirrored_halves, surface_readings

__all__ = [
    "CLEARANCE",
    "TESTS",
    "lobe_width",
    "claim_geometry",
    "discs",
    "margins",
    "t_quantile",
    "fewest_seeds",
    "planned_seeds",
    "claim_design",
    "decide",
    "claim_table",
    "regular_stacks",
    "seed_stacks_of",
]

#: How many of its own half-widths a regular lobe must clear the horizon by, and its search disc reaches.
CLEARANCE = 3.0

#: The claim's tests: what the thesis says of a random surface against the regular one, which way, and the range
#: the statistic takes. ``role`` "lobe": does the lobe exist; "shape": its shape, where it does. ``matters``: the
#: smallest difference that matters to the thesis's question (rectangular or circular), fixed from the
#: statistic's own scale before any seed is read: without it "no difference" would need an interval within the
#: instrument's noise, which no number of seeds reaches; 0 where the noise alone sets the margin.
TESTS = {
    "back_contrast": {
        "lobe": "back", "role": "lobe", "unit": "levels", "range": (-math.inf, math.inf),
        "matters": 1.0,
        "why_matters": "one 8-bit level: no framebuffer, the thesis's instrument, shows a lobe lower than that above its "
                       "background",
        "claim": "the back lobe stands above its background (a lobe to compare)",
        "shows": "the specular's mean over a 3-degree cap at the mirror direction less its mean on the search "
                 "disc's rim",
    },
    "back_squareness": {
        "lobe": "back", "role": "shape", "expected": "below", "unit": "", "range": (-1.0, 1.0), "matters": 0.05,
        "why_matters": "a sixth of the distance between an ellipse's squareness (-0.18) and a rectangle's (+0.12)",
        "claim": "random lobes are rounder (less rectangular) than the regular surface's",
        "shows": "the half-contrast region's misfit to its ellipse less its misfit to its rectangle (> 0 nearer "
                 "a rectangle, < 0 nearer an ellipse)",
    },
    "back_phase_shift": {
        "lobe": "back", "role": "shape", "expected": "below", "unit": "deg", "range": (0.0, math.inf),
        "matters": 0.0, "why_matters": "",
        "claim": "random lobes peak where a circular lobe would: less phase shift off the light's plane",
        "shows": "mean distance of the measured arcs' peaks from a circular lobe's, both sides of the light's plane",
    },
    "hot_spot_contrast": {
        "lobe": "hot_spot", "role": "lobe", "unit": "levels", "range": (-math.inf, math.inf),
        "matters": 1.0,
        "why_matters": "one 8-bit level: no framebuffer, the thesis's instrument, shows a lobe lower than that above its "
                       "background",
        "claim": "the hot spot stands above its background (a halo to compare)",
        "shows": "the shadow-hiding function at V = L less its mean above the light on the search circle, times "
                 "the diffuse at V = L",
    },
    "hot_spot_flatness": {
        "lobe": "hot_spot", "role": "shape", "expected": "below", "unit": "", "range": (-math.inf, math.inf),
        "matters": 1.0 / 6.0, "why_matters": "a sixth of the distance between a circle's flatness (0) and a flat edge's (1)",
        "claim": "a random surface's halo is round (its edge falls away beside the light) where the regular one's "
                 "is flat",
        "shows": "the halo's edge one width to either side of the light over its width above it (0 a circle "
                 "around L, 1 a flat edge)",
    },
}


# ---------------------------------------------------------------------------------------------------------------
# which lobes, where, and how far to look


def lobe_width(shininess: float, specular_model: str = "phong") -> float:
    """Half-width at half maximum (degrees) of a flat facet's specular lobe over view directions: Phong's
    ``(R.V)^zeta`` halves at ``acos(2^(-1/zeta))``; Blinn-Phong's ``(N.H)^zeta`` at twice that (H turns half as
    fast as V)."""
    half = math.degrees(math.acos(0.5 ** (1.0 / float(shininess))))
    return half if specular_model == "phong" else 2.0 * half


#: The search circle the regular halo's own width is read in, degrees (its design radius is then
#: :data:`CLEARANCE` of those widths).
HOT_SPOT_PROBE = 30.0


def _elevation(d) -> float:
    return math.degrees(math.asin(max(-1.0, min(1.0, float(d[2])))))


def claim_geometry(regular: list[SeedStack], lighting: dict) -> pd.DataFrame:
    """Which lobes of which grid points enter the claim, from geometry and the regular surfaces alone.

    Parameters
    ----------
    regular : the regular surface at each random grid point (:func:`roughlight.analysis.claim_readings.seed_stacks`
        of its rows: one tile, seed 0)
    lighting : the study's lighting (``shininess``, ``specular_model``)

    Returns
    -------
    DataFrame, a row a grid point and lobe: surface keys, ``lobe``, ``centre_azimuth``, ``centre_elevation``
    (degrees), ``width`` (the regular lobe's half-width, degrees: the Phong lobe's for the back lobe, the halo's
    width above the light for the hot spot), ``radius`` (its search disc, :data:`CLEARANCE` of its widths, for
    every kind), ``clearance`` (degrees between the lobe's centre and the nearer of the horizon and the other
    side's horizon), ``cap`` (the widest search disc the horizon allows, degrees), ``in_claim`` and ``why``.
    """
    phong = lobe_width(float(lighting.get("shininess", 64.0)), str(lighting.get("specular_model", "phong")))
    rows = []
    for stack in regular:
        centres = lobe_centres(stack.key)
        for lobe in ("back", "hot_spot"):
            row = dict(zip(SURFACE_KEYS, stack.key), lobe=lobe, centre_azimuth=0.0, centre_elevation=np.nan,
                       width=np.nan, radius=np.nan, clearance=np.nan, cap=np.nan, in_claim=False, why="")
            if lobe not in centres:
                rows.append({**row, "why": "its mirror direction lies below the horizon"})
                continue
            e = _elevation(centres[lobe])
            row.update(centre_elevation=e, clearance=min(e, 180.0 - e) - 1.0)
            if lobe == "back":
                apart = math.degrees(math.acos(float(np.clip(centres["back"] @ _forward(stack.key[2]), -1, 1))))
                row.update(width=phong, cap=min(row["clearance"], apart / 2.0))
            else:
                spot = surface_readings(stack, centres, {"hot_spot": HOT_SPOT_PROBE})
                row.update(width=spot["hot_spot_width"], cap=min(60.0, 179.0 - e))
                if not spot["hot_spot_contrast"] > 0 or not np.isfinite(spot["hot_spot_width"]):
                    rows.append({**row, "why": "the regular surface hides no shadow here: "
                                               + (spot["hot_spot_why"] or "no contrast")})
                    continue
            need = row["radius"] = CLEARANCE * row["width"]
            if need > row["cap"]:
                row["why"] = (f"its regular lobe does not clear the horizon by {CLEARANCE:g} widths "
                              f"({need:.1f} deg needed, {row['cap']:.1f} deg free)")
            else:
                row["in_claim"] = True
            rows.append(row)
    return pd.DataFrame(rows, columns=SURFACE_KEYS + ["lobe", "centre_azimuth", "centre_elevation", "width",
                                                      "radius", "clearance", "cap", "in_claim", "why"])


def _forward(incidence: float) -> np.ndarray:
    """The plate's mirror direction under a light at ``incidence`` (the forward lobe's centre)."""
    return np.asarray(view_direction(180.0 - float(incidence), 0.0), float)


def discs(geometry: pd.DataFrame, key) -> dict:
    """The search discs of the lobes in the claim at the grid point ``key`` (truncation, aspect, incidence):
    lobe -> radius, degrees (:func:`claim_geometry`'s ``radius``, the same for every kind)."""
    part = geometry[(geometry["truncation"] == key[0]) & (geometry["aspect"] == key[1])
                    & (geometry["incidence"] == key[2]) & geometry["in_claim"]]
    return dict(zip(part["lobe"], part["radius"].astype(float)))


# ---------------------------------------------------------------------------------------------------------------
# margins


#: The margin table's columns.
MARGIN_COLUMNS = ["kind"] + SURFACE_KEYS + ["test", "reading", "regular", "rendering_noise", "sampling_error",
                                            "grid_effect", "rounding", "matters", "margin", "from"]
#: What set a margin, as its table says it.
MARGIN_SOURCES = {"rendering_noise": "rendering noise", "sampling_error": "sampling error", "grid_effect": "view grid",
                  "rounding": "8-bit rounding", "matters": "difference that matters"}


def margins(regular: dict, geometry: pd.DataFrame, kinds, errors: pd.DataFrame | None = None) -> pd.DataFrame:
    """Every test's margin, in each reading, from what the instrument alone can make of the regular surface.

    Parameters
    ----------
    regular : surface key -> the regular surface's :class:`SeedStack` (the fast method, the study's views)
    geometry : :func:`claim_geometry` (each lobe in the claim, with its disc)
    kinds : the random kinds tested (each takes every lobe in the claim)
    errors : :func:`roughlight.analysis.claim_instrument.instrument_errors` (None: not measured; the margins go
        without them)

    Returns
    -------
    DataFrame, a row a kind x grid point x test x reading: ``regular`` (the regular surface's value in the
    lobe's disc, the fast method on the study's views, as the random tiles are measured), ``rendering_noise``
    (its two halves read apart), ``sampling_error``, ``grid_effect`` (from ``errors``), ``rounding`` (the 8-bit
    reading's only: what rounding does to the regular lobe), ``matters`` (:data:`TESTS`' smallest difference that
    matters), ``margin`` (their largest) and ``from``.
    """
    errors = errors if errors is not None else pd.DataFrame(columns=SURFACE_KEYS + ["test"])
    measured = errors.set_index(SURFACE_KEYS + ["test"]) if len(errors) else None
    rows = []
    for g in geometry[geometry["in_claim"]].itertuples(index=False):
        key = (g.truncation, g.aspect, g.incidence)
        if key not in regular:
            continue
        centres, disc = lobe_centres(key), {g.lobe: g.radius}
        read = {reading: surface_readings(regular[key], centres, disc, reading) for reading in READINGS}
        halves = [surface_readings(h, centres, disc) for h in mirrored_halves(regular[key])]
        for test, spec in TESTS.items():
            if spec["lobe"] != g.lobe:
                continue
            found = measured is not None and key + (test,) in measured.index
            parts = {"rendering_noise": abs(halves[0][test] - halves[1][test]),
                     "sampling_error": float(measured.loc[key + (test,), "sampling_error"]) if found else np.nan,
                     "grid_effect": float(measured.loc[key + (test,), "grid_effect"]) if found else np.nan}
            for reading in READINGS:
                extra = {"rounding": abs(read["8-bit"][test] - read["unrounded"][test])} if reading == "8-bit" else {}
                known = {k: v for k, v in {**parts, **extra, "matters": spec["matters"]}.items() if np.isfinite(v)}
                source = max(known, key=known.get) if known else ""
                for kind in sorted(kinds):
                    rows.append({"kind": kind, **dict(zip(SURFACE_KEYS, key)), "test": test, "reading": reading,
                                 "regular": read[reading][test], **parts, "rounding": extra.get("rounding", np.nan),
                                 "matters": spec["matters"], "margin": known[source] if known else np.nan,
                                 "from": MARGIN_SOURCES[source] if source else ""})
    out = pd.DataFrame(rows, columns=MARGIN_COLUMNS)
    return out.sort_values(["kind"] + SURFACE_KEYS, kind="stable").reset_index(drop=True)


# ---------------------------------------------------------------------------------------------------------------
# the family and the seeds


def t_quantile(level: float, n):
    """The two-sided ``level`` quantile of Student's t with ``n - 1`` degrees of freedom (``n`` seeds)."""
    from scipy import stats as sps

    return sps.t.ppf(0.5 + level / 2.0, np.asarray(n) - 1)


def fewest_seeds(sd: float, room: float, level: float, max_seeds: int) -> int | None:
    """The fewest seeds n (2 ... ``max_seeds``) whose ``level`` Student-t half-width ``t(n - 1) sd / sqrt(n)`` is
    at most ``room``; None when no such n (or no room)."""
    if not room > 0 or not np.isfinite(sd):
        return None
    n = np.arange(2, max_seeds + 1)
    ok = np.flatnonzero(t_quantile(level, n) * sd / np.sqrt(n) <= room)
    return int(n[ok[0]]) if len(ok) else None


def planned_seeds(pilot: float, pilot_se: float, pilot_seeds: int, regular: float, margin: float, level: float,
                  role: str, max_seeds: int = 1000, sd_confidence: float = 0.8) -> tuple[int | None, str]:
    """Test seeds a claim test needs, from the pilot ensemble (never tested).

    The pilot's per-seed spread is its jackknife standard error times sqrt(pilot seeds), taken at its one-sided
    ``sd_confidence`` upper confidence limit (a few pilot seeds estimate a spread poorly). A lobe test
    (``role`` "lobe") needs the seeds whose interval, centred on the pilot's contrast, lies wholly above the
    margin (a lobe) or wholly below it (no lobe); a shape test needs those whose interval, centred on the pilot's
    difference from the regular value, lies wholly beyond or wholly within the margin; a test of the claim's
    direction (``role`` "direction", ``margin`` the threshold beyond the regular value the claim's way:
    :mod:`roughlight.analysis.direction_rounds`) needs those whose interval lies wholly on one side of the threshold;
    ``role`` "decisive" (``margin`` a half-width) those whose interval is no wider, wherever the pilot's mean lies.

    Returns
    -------
    (n, why): n is None when the pilot cannot say, or when no n up to ``max_seeds`` decides.
    """
    from scipy import stats as sps

    if not (np.isfinite(pilot) and np.isfinite(pilot_se) and pilot_seeds >= 2):
        return None, "the pilot's lobe cannot be read on every resample: no spread to plan from"
    df = pilot_seeds - 1
    sd = pilot_se * math.sqrt(pilot_seeds) * math.sqrt(df / sps.chi2.ppf(1.0 - sd_confidence, df))
    if role == "lobe":
        room, expect = (pilot - margin, "a lobe") if pilot > margin else (margin - pilot, "no lobe")
    elif role == "decisive":  # margin: the interval's half-width at which every mean decides
        room, expect = margin, "a verdict whatever the mean"
    elif role == "direction":
        claimed = (pilot - margin) * (margin - regular) > 0  # beyond the threshold, away from the regular value
        room, expect = abs(pilot - margin), ("a difference as claimed" if claimed else "not as claimed")
    else:
        if not np.isfinite(regular):
            return None, "the regular lobe cannot be read"
        d = abs(pilot - regular)
        room, expect = (d - margin, "a difference") if d > margin else (margin - d, "no difference")
    if sd == 0:
        return 2, "the pilot seeds agree exactly"
    n = fewest_seeds(sd, room, level, max_seeds)
    if n is None:
        return None, (f"the pilot's {'contrast' if role == 'lobe' else 'difference'} lies within its spread of the "
                      f"margin {margin:.3g}: more than {max_seeds} seeds")
    return n, f"{expect} expected from the pilot"


def claim_design(margin_table: pd.DataFrame, pilot_readings: dict, design: dict, configured: dict) -> pd.DataFrame:
    """The claim's design, a test a row (the unrounded reading's margins plan the seeds).

    Parameters
    ----------
    margin_table : :func:`margins`
    pilot_readings : (kind, truncation, aspect, incidence) -> the pilot ensemble's
        :func:`roughlight.analysis.claim_readings.pooled_readings` (unrounded) at its search radii
    design : ``alpha`` (family-wise error), ``max_seeds`` (the most tested seeds an ensemble may take)
    configured : (kind, truncation, aspect) -> the tested seeds the config gives the ensemble

    Returns
    -------
    DataFrame: kind, surface keys, ``test``, ``lobe``, ``role``, ``family``, ``level``, ``margin``, ``regular``,
    ``pilot_seeds``, ``pilot_width`` (the pilot mean's lobe width, degrees: two of them should fit its disc),
    ``pilot_mean``, ``pilot_se``, ``seeds_needed`` (Int64; NA where no count up to ``max_seeds``
    decides the test, or the pilot cannot say), ``plan`` (why), ``ensemble_seeds`` (the ensemble's plan: its most
    demanding test that ``max_seeds`` seeds can decide; seeds beyond would not decide the others), ``seeds_configured``.
    """
    plan = margin_table[margin_table["reading"] == "unrounded"].reset_index(drop=True)
    family = len(plan)
    level = 1.0 - float(design["alpha"]) / max(family, 1)
    lobe_margin = {(m.kind, m.truncation, m.aspect, m.incidence, TESTS[m.test]["lobe"]): m.margin
                   for m in plan.itertuples(index=False) if TESTS[m.test]["role"] == "lobe"}
    rows = []
    for m in plan.itertuples(index=False):
        key = (m.kind, m.truncation, m.aspect, m.incidence)
        pilot = pilot_readings.get(key, {})
        spec = TESTS[m.test]
        mean, se = float(pilot.get(m.test, np.nan)), float(pilot.get(f"{m.test}_se", np.nan))
        if spec["role"] == "shape" and not (pilot.get(f"{spec['lobe']}_contrast", np.nan)
                                            > lobe_margin.get(key + (spec["lobe"],), 0.0)):
            need, why = 2, "no lobe expected from the pilot: no shape to test"
        else:
            need, why = planned_seeds(mean, se, int(pilot.get("seeds", 0)), m.regular, m.margin, level, spec["role"],
                                      int(design["max_seeds"]))
        rows.append({"kind": m.kind, "truncation": m.truncation, "aspect": m.aspect, "incidence": m.incidence,
                     "test": m.test, "lobe": spec["lobe"], "role": spec["role"], "family": family, "level": level,
                     "margin": m.margin, "regular": m.regular, "pilot_seeds": int(pilot.get("seeds", 0)),
                     "pilot_width": float(pilot.get(f"{spec['lobe']}_width", np.nan)),
                     "pilot_mean": mean, "pilot_se": se, "seeds_needed": need, "plan": why,
                     "seeds_configured": int(configured.get((m.kind, m.truncation, m.aspect), 0))})
    out = pd.DataFrame(rows, columns=["kind"] + SURFACE_KEYS + [
        "test", "lobe", "role", "family", "level", "margin", "regular", "pilot_seeds", "pilot_width", "pilot_mean",
        "pilot_se", "seeds_needed", "plan", "seeds_configured"])
    out["seeds_needed"] = pd.array(out["seeds_needed"], dtype="Int64")
    out["ensemble_seeds"] = (out.groupby(["kind"] + SURFACE_KEYS)["seeds_needed"].transform(
        lambda s: int(s.dropna().max()) if s.notna().any() else 2).astype(int) if len(out) else pd.Series(dtype=int))
    return out


# ---------------------------------------------------------------------------------------------------------------
# the verdict


def decide(low: float, high: float, regular: float, margin: float, expected: str) -> tuple[str, str]:
    """A shape test's verdict from its interval [low, high] against the regular value and the margin:
    "difference" (the interval wholly beyond ``regular +- margin``; ``expected`` "below" or "above" says whether it
    goes the way the thesis claims), "no difference" (wholly within), or "undecided". Returns (verdict, why)."""
    if low > regular + margin or high < regular - margin:
        side = "above" if low > regular + margin else "below"
        agrees = "as the thesis claims" if side == expected else "against the thesis's claim"
        return "difference", f"the interval lies {side} the regular value by more than the margin ({agrees})"
    if regular - margin <= low and high <= regular + margin:
        return "no difference", f"the interval lies within ±{margin:.3g} of the regular value"
    return "undecided", "the interval reaches across the margin's edge"


#: The verdict table's columns.
VERDICT_COLUMNS = ["kind"] + SURFACE_KEYS + ["test", "reading", "claim", "regular", "margin", "level", "seeds", "mean",
                                            "se", "low", "high", "verdict", "why", "agrees", "seeds_to_decide"]


def claim_table(tested: dict, design_table: pd.DataFrame, margin_table: pd.DataFrame) -> pd.DataFrame:
    """The claim's verdict, a test and reading a row, from the tested seeds only (the pilots never enter).

    Parameters
    ----------
    tested : (kind, truncation, aspect, incidence, reading) -> the tested ensemble's
        :func:`roughlight.analysis.claim_readings.pooled_readings` at its search radii
    design_table : :func:`claim_design`
    margin_table : :func:`margins` (each reading's margin)

    Returns
    -------
    DataFrame: kind, surface keys, ``test``, ``reading``, ``claim``, ``regular``, ``margin``, ``level``, ``seeds``,
    ``mean``, ``se``, ``low``, ``high``, ``verdict`` ("lobe", "no lobe", "difference", "no difference",
    "undecided", "not measurable"), ``why``, ``agrees`` (True where a difference goes the way the thesis claims,
    False against it), ``seeds_to_decide`` (Int64, where undecided). A shape test whose lobe test found no lobe (in
    the same reading) is "no lobe".
    """
    margin_of = margin_table.set_index(["kind"] + SURFACE_KEYS + ["test", "reading"])
    rows, lobes = [], {}
    order = sorted(design_table.itertuples(index=False), key=lambda d: TESTS[d.test]["role"] != "lobe")
    for d in order:
        for reading in READINGS:
            key = (d.kind, d.truncation, d.aspect, d.incidence)
            m = margin_of.loc[key + (d.test, reading)]
            spec = TESTS[d.test]
            row = _verdict_row(d, reading, tested.get(key + (reading,), {}), float(m["regular"]), float(m["margin"]),
                               lobes.get(key + (spec["lobe"], reading)))
            if spec["role"] == "lobe":
                lobes[key + (spec["lobe"], reading)] = row["verdict"]
            rows.append(row)
    out = pd.DataFrame(rows, columns=VERDICT_COLUMNS)
    if len(out):
        tests = list(TESTS)
        out = out.sort_values(["kind"] + SURFACE_KEYS + ["test", "reading"],
                              key=lambda c: c.map(tests.index) if c.name == "test" else c).reset_index(drop=True)
        out["seeds_to_decide"] = pd.array(out["seeds_to_decide"], dtype="Int64")
        out["agrees"] = pd.array(out["agrees"], dtype="boolean")
    return out


def _verdict_row(d, reading: str, pooled: dict, regular: float, margin: float, lobe: str | None) -> dict:
    """One test's row of :func:`claim_table` in one reading (``lobe``: its lobe test's verdict, for a shape
    test)."""
    spec = TESTS[d.test]
    mean, se, n = (float(pooled.get(d.test, np.nan)), float(pooled.get(f"{d.test}_se", np.nan)),
                   int(pooled.get("seeds", 0)))
    row = {"kind": d.kind, "truncation": d.truncation, "aspect": d.aspect, "incidence": d.incidence, "test": d.test,
           "reading": reading, "claim": spec["claim"], "regular": regular, "margin": margin, "level": d.level,
           "seeds": n, "mean": mean, "se": se, "low": np.nan, "high": np.nan, "verdict": "not measurable",
           "why": "", "agrees": pd.NA, "seeds_to_decide": pd.NA}
    if spec["role"] == "shape" and lobe != "lobe":
        row.update(verdict="no lobe" if lobe == "no lobe" else "undecided",
                   why="its lobe test found none: no shape to compare" if lobe == "no lobe"
                   else "its lobe test is not decided: no shape to compare yet")
        return row
    if not (np.isfinite(mean) and np.isfinite(se)) or n < 2:
        row["why"] = (pooled.get(f"{spec['lobe']}_why") or "a resample of the seeds could not read it"
                      if n >= 2 else f"{n} tested seed(s): an interval needs 2")
        return row
    half = float(t_quantile(d.level, n) * se)
    lo, hi = spec["range"]
    row["low"], row["high"] = max(lo, mean - half), min(hi, mean + half)
    if spec["role"] == "lobe":
        if row["low"] > margin or row["high"] < margin:
            found = row["low"] > margin
            row.update(verdict="lobe" if found else "no lobe",
                       why=f"its contrast's interval lies wholly {'above' if found else 'below'} the margin {margin:.3g}"
                           + ("" if found else ": within what the instrument cannot tell from no lobe"))
            return row
        row.update(verdict="undecided", why=f"its contrast's interval reaches across the margin {margin:.3g}")
        need = fewest_seeds(se * math.sqrt(n), abs(mean - margin), d.level, 10_000)
        row["seeds_to_decide"] = pd.NA if need is None else need
        row["why"] += f"; about {need} seeds at this spread would decide it" if need is not None else ""
        return row
    row["verdict"], row["why"] = decide(row["low"], row["high"], regular, margin, spec["expected"])
    if row["verdict"] == "difference":
        row["agrees"] = (row["low"] > regular) == (spec["expected"] == "above")
    if row["verdict"] == "undecided":
        need = fewest_seeds(se * math.sqrt(n), abs(abs(mean - regular) - margin), d.level, 10_000)
        row["seeds_to_decide"] = pd.NA if need is None else need
        row["why"] += (f"; about {need} seeds at this spread would decide it" if need is not None
                       else "; its mean sits on the margin's edge: no number of seeds decides it")
    return row


# ---------------------------------------------------------------------------------------------------------------
# the whole design and verdict from the study's tables


def regular_stacks(study: pd.DataFrame) -> dict:
    """The regular surface's rows in ``study`` (its other kinds' are left out) as :class:`SeedStack` s, by surface
    key: one tile, seed 0, at each random grid point."""
    from .claim_readings import seed_stacks

    regular = study[study["kind"].astype(str) == "pyramids"] if "kind" in study else study
    return {stack.key: stack for stack in seed_stacks(regular)}


def seed_stacks_of(rows: pd.DataFrame, steps: tuple[float, float]) -> dict:
    """The claim's tiles (rule ``claim_sweeps``' rows, at the claim's views) as :class:`SeedStack` s on the study's
    whole view grid (azimuth and elevation ``steps``, degrees), by (kind, truncation, aspect, incidence)."""
    from .claim_readings import seed_stacks

    if rows is None or not len(rows):
        return {}
    return {(stack.kind,) + stack.key: stack for stack in seed_stacks(rows, steps)}
