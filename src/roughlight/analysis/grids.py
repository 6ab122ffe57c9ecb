"""Each surface's views as azimuth x elevation grids, every surface in one pass, and the arcs of views.

:func:`roughlight.study.selection.surface_grids` groups the study by surface and pivots each group with pandas
(``pivot_table``: about 0.02 s a surface, for every surface of every component asked for). Here one sort orders a
component's rows by surface, azimuth and elevation, and each surface's grid is its block of values laid out: the
same grids, value for value (``pivot_table``'s mean of a view measured once is its value). A view measured more
than once, or a NaN among the keys, views or values, is left to ``surface_grids`` itself. :func:`arc` is
:func:`roughlight.study.selection.arc` without copying every column of the component's rows first.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..study import selection
from ..study.selection import SURFACE_KEYS

__all__ = ["arc", "surface_grids", "surface_value_grids"]


def surface_grids(study: pd.DataFrame, component: str, value: str = "rough"):
    """:func:`roughlight.study.selection.surface_grids`, the same grids in the same order, faster.

    Yields
    ------
    key : (truncation, aspect, incidence) floats
    azimuth : (A,) float array, degrees, ascending
    elevation : (E,) float array, degrees, ascending
    values : (A, E) float array of ``value`` (NaN where a view is missing)
    """
    for key, azimuth, elevation, grids in surface_value_grids(study, component, (value,)):
        yield key, azimuth, elevation, grids[value]


def surface_value_grids(study: pd.DataFrame, component: str, values=("rough",)):
    """Each surface's views of one component as grids of several columns at once (see :func:`surface_grids`).

    Parameters
    ----------
    study : DataFrame, the study table (at least the surface keys, ``azimuth``, ``elevation``, ``component`` and
        ``values``)
    component : ``'diffuse'``, ``'specular'`` or ``'total'``
    values : columns to grid (``'rough'``, ``'control'``, ``'coverage'``, ...)

    Yields
    ------
    key, azimuth, elevation : as :func:`surface_grids`
    grids : dict, column -> (A, E) float array
    """
    rows = np.flatnonzero((study["component"].astype(str) == component).to_numpy(bool))
    if not len(rows):
        raise ValueError(f"the study table has no {component!r} rows")
    keys = [study[name].to_numpy(float)[rows] for name in SURFACE_KEYS]
    azimuth, elevation = (study[name].to_numpy(float)[rows] for name in ("azimuth", "elevation"))
    columns = {name: study[name].to_numpy(float)[rows] for name in values}
    if any(np.isnan(a).any() for a in [*keys, azimuth, elevation, *columns.values()]):
        yield from _pivoted(study, component, values)
        return
    order = np.lexsort([elevation, azimuth] + keys[::-1])
    keys = [k[order] for k in keys]
    azimuth, elevation = azimuth[order], elevation[order]
    columns = {name: column[order] for name, column in columns.items()}
    for start, stop in _surface_blocks(keys):
        az, el = azimuth[start:stop], elevation[start:stop]
        if np.any((az[1:] == az[:-1]) & (el[1:] == el[:-1])):  # a view measured twice: pandas' mean
            yield from _pivoted(study.iloc[rows[np.sort(order[start:stop])]], component, values)
            continue
        key = tuple(float(k[start]) for k in keys)
        az_grid, el_grid = np.unique(az), np.unique(el)
        yield key, az_grid, el_grid, {name: _laid_out(column[start:stop], az, el, az_grid, el_grid)
                                      for name, column in columns.items()}


def _surface_blocks(keys: list) -> list[tuple[int, int]]:
    """The (start, stop) of each run of equal surface ``keys`` (arrays, sorted), in order."""
    changes = np.zeros(len(keys[0]) - 1, bool)
    for k in keys:
        changes |= k[1:] != k[:-1]
    edges = np.concatenate([[0], np.flatnonzero(changes) + 1, [len(keys[0])]])
    return list(zip(edges[:-1].tolist(), edges[1:].tolist()))


def _laid_out(values, az, el, az_grid, el_grid) -> np.ndarray:
    """One surface's ``values`` at the views (``az``, ``el``; sorted by azimuth, then elevation, each view once) as
    the (A, E) grid over ``az_grid`` x ``el_grid``, NaN where a view is missing."""
    if len(values) == len(az_grid) * len(el_grid):  # every view: the block is the grid, row by row
        return values.reshape(len(az_grid), len(el_grid)).copy()
    grid = np.full((len(az_grid), len(el_grid)), np.nan)
    grid[np.searchsorted(az_grid, az), np.searchsorted(el_grid, el)] = values
    return grid


def _pivoted(study: pd.DataFrame, component: str, values):
    """:func:`surface_value_grids` through :func:`roughlight.study.selection.surface_grids`, a column at a time."""
    grids = {name: list(selection.surface_grids(study, component, name)) for name in values}
    first = grids[values[0]]
    for n, (key, az, el, _) in enumerate(first):
        yield key, az, el, {name: grids[name][n][3] for name in values}


def arc(study: pd.DataFrame, component: str, azimuth: float = 0.0) -> pd.DataFrame:
    """The views of one half great circle (default the light's plane, phi = 0): the frame
    :func:`roughlight.study.selection.arc` returns (the same rows, columns and order), from the arc's rows alone.

    Returns
    -------
    DataFrame with the surface keys, ``elevation``, ``phase``, ``rough``, ``control`` and ``coverage``, sorted by
    surface and elevation.
    """
    of_component = (study["component"].astype(str) == component).to_numpy(bool)
    if not of_component.any():
        raise ValueError(f"the study table has no {component!r} rows")
    rows = np.flatnonzero(of_component & np.isclose(study["azimuth"].to_numpy(float), azimuth))
    if not len(rows):
        raise ValueError(f"the study table has no views at azimuth {azimuth}")
    cols = SURFACE_KEYS + ["elevation", "phase", "rough", "control", "coverage"]
    return study.iloc[rows][cols].sort_values(SURFACE_KEYS + ["elevation"]).reset_index(drop=True)
