"""The one sweep contract: every method takes a sweep's views the same way and returns the same result.

A sweep is one surface under one light, seen from many views. :func:`measure` is the driver every method runs
through: it checks the incidence and the views once (:func:`sweep_views`), leaves the grazing views
(:func:`roughlight.render.views.is_grazing`, the one grazing rule) at zero, times the sweep, and hands the method's
own step only the views it must measure. A method writes only that step::

    def step(out, views, incidence, lighting):
        # fill out["diffuse"], out["specular"], out["total"], out["coverage"] at views.measured
        ...

The result (:data:`RESULT`) is a dict: ``diffuse``, ``specular``, ``total`` ((n_views,) float arrays, the mean
8-bit value of the view's image, 0-255), ``coverage`` ((n_views,), the fraction of the image showing the
surface, 0-1) and ``seconds`` (the sweep's wall time).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from . import shading
from .views import is_grazing

__all__ = ["RESULT", "SweepViews", "sweep_views", "measure"]

#: The arrays of a sweep's result, one value a view (and ``seconds``, its wall time).
RESULT = ("diffuse", "specular", "total", "coverage")


@dataclass(frozen=True)
class SweepViews:
    """A sweep's views, checked.

    Attributes
    ----------
    azimuth, elevation : (n_views,) float arrays, degrees: the direction to the detector is
        (cos e cos phi, cos e sin phi, sin e), e in [0, 180] (e > 90 looks from beyond the zenith).
    measured : (m,) int array, the views that are not grazing (the ones a method measures), ascending.
    """

    azimuth: np.ndarray
    elevation: np.ndarray
    measured: np.ndarray

    def __len__(self) -> int:
        return self.azimuth.size

    def directions(self) -> np.ndarray:
        """(m, 3) unit vectors toward the detector at the measured views."""
        return shading.view_direction(self.elevation[self.measured], self.azimuth[self.measured])


def sweep_views(azimuth, elevation) -> SweepViews:
    """The views of a sweep, checked as every method checks them.

    Parameters
    ----------
    azimuth, elevation : array_like of one shape, degrees, flattened: azimuths finite (the study's are in
        [0, 180)), elevations in [0, 180].
    """
    az = np.atleast_1d(np.asarray(azimuth, float))
    el = np.atleast_1d(np.asarray(elevation, float))
    if az.shape != el.shape:
        raise ValueError(f"azimuth and elevation must have the same shape, got {az.shape} and {el.shape}")
    az, el = az.ravel().copy(), el.ravel().copy()
    if not np.all(np.isfinite(az)):
        raise ValueError("azimuth must be finite (degrees)")
    if not np.all(np.isfinite(el) & (el >= 0.0) & (el <= 180.0)):
        raise ValueError("elevation must be within [0, 180] degrees")
    return SweepViews(az, el, np.flatnonzero(~is_grazing(el)))


def measure(step: Callable, incidence, azimuth, elevation, lighting=None) -> dict:
    """Run one sweep: check the light and the views, call ``step(out, views, incidence, lighting)`` when some
    view is not grazing, and return :data:`RESULT` with the sweep's ``seconds``.

    Parameters
    ----------
    step : the method's own step; it fills ``out``'s arrays at ``views.measured`` and returns nothing.
    incidence : float, light elevation above the surface plane, degrees in [0, 90] (light at azimuth 0).
    azimuth, elevation : the views (:func:`sweep_views`).
    lighting : Lighting, optional (``Lighting()``).
    """
    start = time.perf_counter()
    incidence = shading.check_incidence(incidence)
    views = sweep_views(azimuth, elevation)
    lighting = lighting or shading.Lighting()
    out = {key: np.zeros(len(views)) for key in RESULT}
    if views.measured.size:
        step(out, views, incidence, lighting)
    out["seconds"] = time.perf_counter() - start
    return out
