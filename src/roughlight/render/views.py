"""The detector's orbit: which views a sweep measures.

A sweep is one surface under one light. The detector orbits the hemisphere
along half great circles: for each azimuth ``phi`` in ``[0, 180)`` (step
``azimuth_step``) the elevation ``e`` runs over ``[0, 180]`` (step
``elevation_step``), so ``e > 90`` looks from the far side of the zenith.
With the thesis's 1 deg x 5 deg steps that is 181 x 36 = 6,516 views.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["elevations", "azimuths", "view_grid", "is_grazing", "is_zenith", "distinct_views"]

#: Views whose elevation is within this many degrees of 0 or 180 look along
#: the surface plane: the projected surface has no area there.
GRAZING_TOLERANCE_DEG = 1e-9


def _check_step(step, name: str, span: float) -> float:
    try:
        value = float(step)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a number of degrees, got {step!r}") from exc
    if not (math.isfinite(value) and 0.0 < value <= span):
        raise ValueError(f"{name} must be > 0 and <= {span:g} degrees, got {step!r}")
    return value


def elevations(step: float = 1.0) -> np.ndarray:
    """Elevations ``0, step, ...`` up to and including 180 when it falls on the grid (degrees)."""
    step = _check_step(step, "sweep.elevation_step", 180.0)
    n = int(math.floor(180.0 / step + 1e-9))
    return np.round(np.arange(n + 1) * step, 9)


def azimuths(step: float = 5.0) -> np.ndarray:
    """Azimuths ``0, step, ...`` strictly below 180 (degrees)."""
    step = _check_step(step, "sweep.azimuth_step", 180.0)
    n = int(math.ceil(180.0 / step - 1e-9))
    return np.round(np.arange(n) * step, 9)


def view_grid(elevation_step: float = 1.0, azimuth_step: float = 5.0) -> tuple[np.ndarray, np.ndarray]:
    """All views of a sweep, azimuth-major (the thesis's orbit order).

    Returns
    -------
    azimuth, elevation : (n_views,) float arrays, degrees.
    """
    az = azimuths(azimuth_step)
    el = elevations(elevation_step)
    azimuth, elevation = np.meshgrid(az, el, indexing="ij")
    return azimuth.ravel(), elevation.ravel()


#: ... or whose sine is below this (within about 6e-8 degrees of 0 or 180).
GRAZING_SIN = 1e-9


def is_grazing(elevation) -> np.ndarray:
    """True where the view lies in the surface plane (``e`` = 0 or 180): the one grazing rule of every method
    (:mod:`roughlight.render.sweep` leaves these views at zero)."""
    e = np.asarray(elevation, float)
    return ((np.abs(e) <= GRAZING_TOLERANCE_DEG) | (np.abs(e - 180.0) <= GRAZING_TOLERANCE_DEG)
            | (np.abs(np.sin(np.radians(e))) < GRAZING_SIN))


#: Views whose elevation is within this many degrees of 90 look straight down: the zenith.
ZENITH_TOLERANCE_DEG = 1e-9


def is_zenith(elevation) -> np.ndarray:
    """True where the view is the zenith (``e`` = 90): one direction, on every half great circle of a sweep."""
    return np.abs(np.asarray(elevation, float) - 90.0) <= ZENITH_TOLERANCE_DEG


def distinct_views(azimuth, elevation, coverage=None, sweep=None) -> np.ndarray:
    """Which rows a statistic over a sweep's views counts: every view that was rendered, each direction once.

    A sweep's half great circles all pass through the zenith (e = 90): the one view appears once per azimuth
    (36 times in the default sweep), and an unweighted mean over the rows would count it 36 times. Of the rows
    that show one direction (the zenith at any azimuth, or an (azimuth, elevation) given twice) the one at the
    smallest azimuth, the first on a tie, is kept. Views that were not rendered (grazing, e = 0 and 180; and
    coverage 0 where ``coverage`` is given) are left out: no measurement, never a dark view. The default
    sweep's 6,516 rows hold 6,409 distinct rendered views.

    Parameters
    ----------
    azimuth, elevation : (n,) array_like, degrees
    coverage : (n,) array_like, optional
        The fraction of the capture window showing the surface (the study's ``coverage``); 0 leaves a row out.
    sweep : (n,) array_like, optional
        Which sweep (surface, component, ...) each row belongs to, when the rows hold several: each sweep keeps
        its own zenith. Default: the rows are one sweep.

    Returns
    -------
    (n,) bool array: True at the rows counted.
    """
    az, el = np.asarray(azimuth, float).ravel(), np.asarray(elevation, float).ravel()
    keep = ~is_grazing(el)
    if coverage is not None:
        keep &= np.asarray(coverage, float).ravel() > 0
    label = np.zeros(az.size, int) if sweep is None else np.unique(np.asarray(sweep).ravel(), return_inverse=True)[1]
    zenith = is_zenith(el)
    direction = (label, np.where(zenith, 0.0, az), np.where(zenith, 90.0, el))  # the zenith: one direction
    rows = np.flatnonzero(keep)
    order = rows[np.lexsort((rows, az[rows]) + tuple(d[rows] for d in direction[::-1]))]
    repeated = np.ones(order.size - 1 if order.size else 0, bool)
    for d in direction:
        repeated &= d[order][1:] == d[order][:-1]
    keep[order[1:][repeated]] = False
    return keep
