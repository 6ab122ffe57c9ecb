"""Selecting surfaces, arcs and view grids out of the study table.

The study table (:mod:`roughlight.study.tables`) has one row per surface x view x
component, values on the 0-255 scale. The analysis reads it through these
helpers: one surface's views as an azimuth x elevation grid, one half great
circle of views (an arc), the lighting the study recorded, and the solid
angle each view stands for.

Angles are degrees. Elevation ``e`` runs 0..180 along half great circles at
azimuth ``phi`` in [0, 180); the light is at azimuth 0 and elevation ``i``
(the incidence).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

#: One row per surface (and light) in the per-surface tables.
SURFACE_KEYS = ["truncation", "aspect", "incidence"]


#: Aspects are matched to a wanted value within this.
ASPECT_TOL = 1e-9


def find_aspect(values, wanted: float, tol: float = ASPECT_TOL):
    """The value in ``values`` equal to ``wanted`` within ``tol``, or None."""
    vals = np.unique(np.asarray(values, float))
    hit = vals[np.abs(vals - float(wanted)) <= tol]
    return float(hit[0]) if len(hit) else None


def component_rows(study: pd.DataFrame, component: str) -> pd.DataFrame:
    comp = study["component"].astype(str)
    out = study.loc[comp == component]
    if out.empty:
        raise ValueError(f"the study table has no {component!r} rows")
    return out


def surface_grids(study: pd.DataFrame, component: str, value: str = "rough"):
    """Each surface's views as a regular azimuth x elevation grid.

    Parameters
    ----------
    study : DataFrame
        The study table.
    component : str
        ``'diffuse'``, ``'specular'`` or ``'total'``.
    value : str
        Column to grid (``'rough'`` or ``'control'``).

    Yields
    ------
    key : (truncation, aspect, incidence) floats
    azimuth : (A,) float array, degrees, ascending
    elevation : (E,) float array, degrees, ascending
    values : (A, E) float array (NaN where a view is missing)
    """
    frame = component_rows(study, component)
    for key, group in frame.groupby(SURFACE_KEYS, sort=True):
        grid = group.pivot_table(index="azimuth", columns="elevation", values=value, aggfunc="mean")
        yield (
            tuple(float(k) for k in key),
            grid.index.to_numpy(float),
            grid.columns.to_numpy(float),
            grid.to_numpy(float),
        )


def arc(study: pd.DataFrame, component: str, azimuth: float = 0.0) -> pd.DataFrame:
    """The views of one half great circle (default the light's plane, phi = 0).

    Returns
    -------
    DataFrame with the surface keys, ``elevation``, ``phase``, ``rough``,
    ``control`` and ``coverage``, sorted by surface and elevation.
    """
    frame = component_rows(study, component)
    out = frame.loc[np.isclose(frame["azimuth"].to_numpy(float), azimuth)]
    if out.empty:
        raise ValueError(f"the study table has no views at azimuth {azimuth}")
    cols = SURFACE_KEYS + ["elevation", "phase", "rough", "control", "coverage"]
    return out[cols].sort_values(SURFACE_KEYS + ["elevation"]).reset_index(drop=True)


def recorded_lighting(study: pd.DataFrame) -> dict:
    """Light settings recorded in the study (first row; they are constant per study)."""
    row = study.iloc[0]
    return {
        "light": float(row["light"]),
        "ambient": float(row.get("ambient", 0.0)),
        "shininess": float(row.get("shininess", 64.0)),
        "specular_model": str(row.get("specular_model", "phong")),
        "shadows": bool(row.get("shadows", True)),
        "specular_shadows": bool(row.get("specular_shadows", True)),
    }


def solid_angle_weights(azimuth, elevation) -> np.ndarray:
    """(A, E) solid angle (sr) each view stands for; they sum to 2 pi over the half great circles.

    A view at elevation ``e`` (degrees, ascending over [0, 180]) on one of the ``A`` half great circles
    stands for the cell between the midpoints to its neighbours (clipped to [0, 180]) and ``pi / A`` of
    azimuth: the exact integral of ``|cos e| de dphi`` over it.
    """
    az = np.asarray(azimuth, float)
    el = np.radians(np.asarray(elevation, float))
    dphi = math.pi / len(az) if len(az) else 0.0
    edges = np.concatenate([[max(el[0] - (el[1] - el[0]) / 2, 0.0) if len(el) > 1 else 0.0],
                            (el[1:] + el[:-1]) / 2,
                            [min(el[-1] + (el[-1] - el[-2]) / 2, math.pi) if len(el) > 1 else math.pi]])
    edges = np.clip(edges, 0.0, math.pi)

    def primitive(x):  # an antiderivative of |cos x| on [0, pi]
        return np.where(x <= math.pi / 2, np.sin(x), 2.0 - np.sin(x))

    cells = primitive(edges[1:]) - primitive(edges[:-1])
    return cells[None, :] * dphi * np.ones((len(az), 1))
