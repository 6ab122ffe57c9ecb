"""The instrument's own error on the claim's regular lobes: the fast method against the exact reference, and the
study's azimuth step against finer ones (rule ``claim_grid``'s measurements, read as rule ``analysis_random`` reads
them).

Two of the claim's margins (:func:`roughlight.analysis.claims.margins`) come from here: the fast method's sampling
error against the exact reference on the study's view grid, and the view grid's own effect (the study's azimuth
step against 1 degree), each on the regular lobe in its own disc (:data:`roughlight.analysis.claims.CLEARANCE` of
its widths). :func:`grid_table` is the page's table of each regular lobe's statistics by azimuth step.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..render.shading import view_direction
from ..study.selection import SURFACE_KEYS
from .claim_readings import READINGS, SeedStack, lobe_centres, surface_readings
from .claims import TESTS
from .lobe_shape import tangent_basis

__all__ = ["reference_steps", "claim_views", "reference_views", "reference_stacks", "instrument_errors", "grid_table"]


def reference_steps(azimuth_step: float) -> list[float]:
    """The azimuth steps (degrees, coarsest first) the regular lobes are measured at by the exact reference: the
    study's, half of it, and 1 degree."""
    return sorted({float(azimuth_step), float(azimuth_step) / 2.0, 1.0}, reverse=True)


def claim_views(geometry: pd.DataFrame, key, step: float, elevation_step: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """The views the claim reads at the grid point ``key`` (truncation, aspect, incidence), on the view grid of
    azimuth ``step`` and ``elevation_step``: every view within each claimed lobe's disc (its ``radius``), and a
    step's reach beyond (the interpolation between views at the rim); the hot spot's also its width beyond, where
    its edge is looked for to either side, but no lower than its width below the light's level (its reading looks
    no lower: below the light every view hides every shadow). Returns (azimuth, elevation) arrays, degrees, in the
    grid's order."""
    from ..render.views import view_grid

    part = geometry[(geometry["truncation"] == key[0]) & (geometry["aspect"] == key[1])
                    & (geometry["incidence"] == key[2]) & geometry["in_claim"]]
    centres = lobe_centres(tuple(float(k) for k in key))
    az, el = view_grid(elevation_step, step)
    V = view_direction(el, az)
    near = np.zeros(len(az), bool)
    beyond = 1.5 * max(step, elevation_step)
    for g in part.itertuples(index=False):
        centre, spot = centres[g.lobe], g.lobe == "hot_spot"
        within = np.degrees(np.arccos(np.clip(V @ centre, -1.0, 1.0))) <= g.radius + (g.width if spot else 0) + beyond
        if spot:  # its edge's reach to either side, and nothing far below the light's level
            with np.errstate(divide="ignore", invalid="ignore"):
                height = np.degrees((V @ tangent_basis(centre)[0]) / (V @ centre))
            within &= height >= -(g.width + beyond)
        near |= within
    return az[near], el[near]


def reference_views(geometry: pd.DataFrame, steps, elevation_step: float = 1.0) -> pd.DataFrame:
    """The views rule ``claim_grid`` measures of each regular surface in the claim, at each azimuth step:
    :func:`claim_views`.

    Returns
    -------
    DataFrame: surface keys, ``step``, ``azimuth``, ``elevation`` (degrees), a view a row.
    """
    frames = []
    claimed = geometry[geometry["in_claim"]]
    for key in claimed[SURFACE_KEYS].drop_duplicates().itertuples(index=False):
        for step in steps:
            az, el = claim_views(geometry, tuple(key), step, elevation_step)
            frames.append(pd.DataFrame({**dict(zip(SURFACE_KEYS, key)), "step": float(step), "azimuth": az,
                                        "elevation": el}))
    columns = SURFACE_KEYS + ["step", "azimuth", "elevation"]
    return pd.concat(frames, ignore_index=True)[columns] if frames else pd.DataFrame(columns=columns)


def reference_stacks(grid: pd.DataFrame, elevation_step: float = 1.0) -> dict:
    """Rule ``claim_grid``'s measurements (surface keys, ``method``, ``step``, ``azimuth``, ``elevation``,
    ``component``, ``rough_unrounded``, ``rough_unshadowed``) as a :class:`SeedStack` for each regular surface,
    method and azimuth step, on the full view grid of that step: NaN (coverage 0) where nothing was measured.
    Returns {surface key: {(method, step): SeedStack}}; both readings hold the unrounded values."""
    out = {}
    for (t, a, i, method, step), part in grid.groupby(SURFACE_KEYS + ["method", "step"], sort=True):
        az = np.arange(0.0, 180.0 - step / 2, step)
        el = np.arange(0.0, 180.0 + elevation_step / 2, elevation_step)
        grids = {}
        for component in ("specular", "diffuse"):
            rows = part[part["component"].astype(str) == component]
            ia = np.rint(rows["azimuth"].to_numpy(float) / step).astype(int)
            ie = np.rint(rows["elevation"].to_numpy(float) / elevation_step).astype(int)
            for column in ("rough_unrounded", "rough_unshadowed"):
                values = np.full((1, len(az), len(el)), np.nan)
                values[0, ia, ie] = rows[column].to_numpy(float)
                grids[component, column] = values
        coverage = np.where(np.isfinite(grids["diffuse", "rough_unrounded"][0]), 1.0, 0.0)
        coverage[:, (el <= 0) | (el >= 180)] = 0.0
        both = lambda g: {reading: g for reading in READINGS}  # noqa: E731
        out.setdefault((float(t), float(a), float(i)), {})[str(method), float(step)] = SeedStack(
            (t, a, i), "pyramids", [0], az, el, coverage, both(grids["specular", "rough_unrounded"]),
            both(grids["diffuse", "rough_unrounded"]), grids["diffuse", "rough_unshadowed"])
    return out


def grid_table(reference: dict, geometry: pd.DataFrame) -> pd.DataFrame:
    """The regular lobes' statistics at each azimuth step rule ``claim_grid`` measured (unrounded), by each
    method, each lobe in its disc (:func:`roughlight.analysis.claims.discs`): whether the study's azimuth step is
    fine enough for each statistic.

    Returns
    -------
    DataFrame: surface keys, ``lobe``, ``statistic``, ``method``, ``step``, ``value``, ``change`` (against the same
    method's finest step).
    """
    rows = []
    for g in geometry[geometry["in_claim"]].itertuples(index=False):
        key = (g.truncation, g.aspect, g.incidence)
        read = {ms: surface_readings(s, lobe_centres(key), {g.lobe: g.radius})
                for ms, s in reference.get(key, {}).items()}
        for test, spec in TESTS.items():
            if spec["lobe"] != g.lobe:
                continue
            for method in sorted({m for m, _ in read}, reverse=True):
                steps = sorted((s for m, s in read if m == method), reverse=True)
                for step in steps:
                    value = read[method, step][test]
                    rows.append({**dict(zip(SURFACE_KEYS, key)), "lobe": g.lobe, "statistic": test,
                                 "method": method, "step": step, "value": value,
                                 "change": value - read[method, steps[-1]][test]})
    return pd.DataFrame(rows, columns=SURFACE_KEYS + ["lobe", "statistic", "method", "step", "value", "change"])


def instrument_errors(reference: dict, geometry: pd.DataFrame) -> pd.DataFrame:
    """What the instrument's method and view grid alone do to each regular lobe's statistics, in the lobe's disc:
    on the study's view grid, the fast method (the regular surface's sampling: ``fast_error``) and the same geometry
    drawn as the random tiles are (their sampling: ``tile_error``) against the exact reference, the larger the
    ``sampling_error``; and the study's azimuth step against 1 degree (``grid_effect``: the exact reference's where
    it measured 1 degree, else the fast method's).

    Parameters
    ----------
    reference : :func:`reference_stacks` of rule ``claim_grid``'s measurements
    geometry : :func:`claim_geometry`

    Returns
    -------
    DataFrame: surface keys, ``test``, ``fast_error``, ``tile_error``, ``sampling_error``, ``grid_effect``,
    ``grid_method``.
    """
    rows = []
    for g in geometry[geometry["in_claim"]].itertuples(index=False):
        key = (g.truncation, g.aspect, g.incidence)
        stacks = reference.get(key, {})
        if not stacks:
            continue
        disc = {g.lobe: g.radius}
        read = {ms: surface_readings(s, lobe_centres(key), disc) for ms, s in stacks.items()}
        coarse = max(step for _, step in read)
        fine_method = "reference" if ("reference", min(step for _, step in read)) in read else "fast"
        finest = min(step for method, step in read if method == fine_method)
        for test, spec in TESTS.items():
            if spec["lobe"] != g.lobe:
                continue
            exact = read[("reference", coarse)][test] if ("reference", coarse) in read else np.nan
            errors = [abs(read[method, coarse][test] - exact) if (method, coarse) in read else np.nan
                      for method in ("fast", "tile")]
            grid = abs(read[fine_method, coarse][test] - read[fine_method, finest][test])
            rows.append({**dict(zip(SURFACE_KEYS, key)), "test": test, "fast_error": errors[0],
                         "tile_error": errors[1], "sampling_error": max((e for e in errors if np.isfinite(e)),
                                                                         default=np.nan),
                         "grid_effect": grid, "grid_method": fine_method})
    return pd.DataFrame(rows, columns=SURFACE_KEYS + ["test", "fast_error", "tile_error", "sampling_error",
                                                      "grid_effect", "grid_method"])
