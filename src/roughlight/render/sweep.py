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
surface, 0-1), each component's mean before rounding and with inner shadows off (:data:`EXTRA_KEYS`, NaN where
the method cannot give them) and ``seconds`` (the sweep's wall time).

Beside its 8-bit mean ``c``, each component ``c`` has (:data:`roughlight.render.shading.EXTRAS`):

- ``{c}_unrounded``: the mean of each pixel's value clamped to [0, 255] but not rounded, so within 0.5 of ``c``
  at every measured view (and the rounding's tie slack: :func:`roughlight.render.shading.quantize`'s 1e-6,
  Mitsuba's 2e-3);
- ``{c}_unshadowed``: the same unrounded mean with inner (cast) shadows off: every seen point lit, the view's
  visible shares unchanged (what the shadow-hiding function ``diffuse_on / diffuse_off`` is made of).

A method gives them only where its values come from each facet's value before it is rounded: the exact reference,
the fast method's adaptive sampling (regular surfaces and random tiles, from the facets' shares) and the implicit
models' numpy sweeps give both; Mitsuba (a float film, but its light always casts shadows) gives ``_unrounded``
only; the naive method, the fast method's lattice and grid sampling and the implicit shader average 8-bit
framebuffer pixels and give neither (docs/conventions.md, "Before rounding and without shadows", says why). A
method's step says which it fills (:func:`measure`'s ``gives``); the others are NaN at every measured view.
Grazing views are 0 in every array, as they are in the 8-bit ones.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from . import shading
from .views import is_grazing

__all__ = ["RESULT", "EXTRA_KEYS", "extra_keys", "SweepViews", "sweep_views", "measure"]


def extra_keys(extras=shading.EXTRAS) -> tuple:
    """The result's keys of ``extras`` (some of :data:`roughlight.render.shading.EXTRAS`), a component at a time:
    ``diffuse_unrounded``, ``specular_unrounded``, ..."""
    return tuple(f"{component}_{extra}" for extra in extras for component in shading.COMPONENTS)


#: Each component's mean before rounding and with inner shadows off (NaN where a method cannot give them).
EXTRA_KEYS = extra_keys()
#: The arrays of a sweep's result, one value a view (and ``seconds``, its wall time).
RESULT = ("diffuse", "specular", "total", "coverage") + EXTRA_KEYS


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


def measure(step: Callable, incidence, azimuth, elevation, lighting=None, gives=()) -> dict:
    """Run one sweep: check the light and the views, call ``step(out, views, incidence, lighting)`` when some
    view is not grazing, and return :data:`RESULT` with the sweep's ``seconds``.

    Parameters
    ----------
    step : the method's own step; it fills ``out``'s arrays at ``views.measured`` and returns nothing (every array
        starts at 0).
    incidence : float, light elevation above the surface plane, degrees in [0, 90] (light at azimuth 0).
    azimuth, elevation : the views (:func:`sweep_views`).
    lighting : Lighting, optional (``Lighting()``).
    gives : some of :data:`roughlight.render.shading.EXTRAS`: what the step fills beside the 8-bit means
        (:data:`EXTRA_KEYS`); the others are NaN at the measured views, whatever the step left there.
    """
    start = time.perf_counter()
    incidence = shading.check_incidence(incidence)
    views = sweep_views(azimuth, elevation)
    lighting = lighting or shading.Lighting()
    unknown = set(gives) - set(shading.EXTRAS)
    if unknown:
        raise ValueError(f"a method gives some of {shading.EXTRAS}, not {sorted(unknown)}")
    out = {key: np.zeros(len(views)) for key in RESULT}
    if views.measured.size:
        step(out, views, incidence, lighting)
        for key in extra_keys(e for e in shading.EXTRAS if e not in gives):
            out[key][views.measured] = np.nan
    out["seconds"] = time.perf_counter() - start
    return out
