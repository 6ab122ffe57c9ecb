"""The measurements' one comparison against the exact reference.

Every measurement of the methods (:mod:`.stability`, :mod:`.speed_accuracy`, :mod:`.renderer_validation`,
:mod:`.random_tiles`, :mod:`.implicit_surface`) holds a method's sweep against the exact reference on the same
views. This module is what they share:

- :func:`reference`: the reference sweep of a surface under a light, computed once per (surface, incidence,
  views, lighting, settings) in a process, through the registry (:func:`roughlight.render.methods.sweep`);
- :func:`absolute_errors` and :func:`pooled_errors`: ``|rendered - exact|`` of each component (0-255), of one
  sweep or of several sweeps end to end;
- :func:`error_statistics`: the statistics of those errors the tables report (:data:`STATISTICS`), over the views
  that were rendered, each once (the zenith once, not once per azimuth: the ``seen`` views, from
  :func:`roughlight.render.views.distinct_views`);
- :func:`plan_size`: the size of a measurement named by its plan (``measurements.plan``), refused with the
  choices for any other name.
"""

from __future__ import annotations

import numpy as np

from ..render import methods
from ..render.shading import COMPONENTS

__all__ = ["STATISTICS", "REFERENCE_CACHE_SIZE", "reference", "clear_references", "absolute_errors",
           "pooled_errors", "error_statistics", "plan_size"]

#: The error statistics, 0-255: ``mae`` (mean absolute error), ``p99`` (99th percentile, numpy's linear
#: interpolation) and ``worst`` (the largest; the stability frame's ``max_error``, the benchmark's ``max_error``).
STATISTICS = ("mae", "p99", "worst")

#: Reference sweeps kept in a process; past this many the cache starts again empty.
REFERENCE_CACHE_SIZE = 512

_REFERENCES: dict = {}


def reference(surface, incidence, azimuth, elevation, lighting=None, settings=None, light_azimuth=0.0) -> dict:
    """The exact reference's sweep of a surface under a light, computed once per views and lighting in a process.

    Parameters
    ----------
    surface : Surface or RandomSurface
    incidence : float
        Light elevation above the surface plane, degrees in [0, 90].
    azimuth, elevation : (n_views,) arrays
        The views, degrees (:func:`roughlight.render.sweep.sweep_views`).
    lighting : Lighting, optional
    settings : ReferenceSettings, optional
        Default: the reference's defaults (quantized to 8-bit levels, as the study's).
    light_azimuth : float
        The light's azimuth, degrees (0: the light in the plane of the sweep's azimuth 0).

    Returns
    -------
    dict
        The sweep's result (:data:`roughlight.render.sweep.RESULT` and ``seconds``, the wall time of the one
        computation). Shared between callers: read it, do not change it.
    """
    azimuth, elevation = np.asarray(azimuth, float), np.asarray(elevation, float)
    key = (surface, float(incidence), azimuth.shape, azimuth.tobytes(), elevation.tobytes(), lighting, settings,
           float(light_azimuth))
    if key not in _REFERENCES:
        if len(_REFERENCES) > REFERENCE_CACHE_SIZE:
            _REFERENCES.clear()
        _REFERENCES[key] = methods.sweep("reference", surface, incidence, azimuth, elevation, lighting, settings,
                                         light_azimuth=light_azimuth)
    return _REFERENCES[key]


def clear_references() -> None:
    """Forget every reference sweep :func:`reference` kept (after the reference itself changed, e.g. in a test)."""
    _REFERENCES.clear()


def absolute_errors(rendered: dict, exact: dict, seen=None, components=COMPONENTS) -> dict:
    """``|rendered - exact|`` of each component of one sweep.

    Parameters
    ----------
    rendered, exact : dict
        Component -> (n_views,) values, 0-255 (a sweep's result: ``diffuse``, ``specular``, ``total``).
    seen : (n_views,) bool array, optional
        The views compared (default: every view).
    components : sequence of str
        The components compared (default all three).

    Returns
    -------
    dict
        Component -> float64 array of the absolute errors at the ``seen`` views, 0-255, in view order.
    """
    errors = {}
    for component in components:
        error = np.abs(np.asarray(rendered[component], float) - np.asarray(exact[component], float))
        errors[component] = error if seen is None else error[seen]
    return errors


def pooled_errors(pairs, seen=None) -> dict:
    """:func:`absolute_errors` of several sweeps end to end: the errors over every surface's views.

    Parameters
    ----------
    pairs : iterable of (rendered, exact)
        One pair of sweep results a surface, in the order the errors are joined.
    seen : (n_views,) bool array, optional
        The views compared in every sweep (default: every view; the sweeps share their views).

    Returns
    -------
    dict
        Component -> float64 array, the sweeps' absolute errors concatenated (0-255).
    """
    parts = {component: [] for component in COMPONENTS}
    for rendered, exact in pairs:
        for component, error in absolute_errors(rendered, exact, seen).items():
            parts[component].append(error)
    return {component: np.concatenate(errors) for component, errors in parts.items()}


def error_statistics(error, statistics=STATISTICS) -> dict:
    """The statistics of a sweep's absolute errors.

    Parameters
    ----------
    error : array_like
        Absolute errors, 0-255 (:func:`absolute_errors`), at least one.
    statistics : sequence of str
        Which of :data:`STATISTICS` to compute.

    Returns
    -------
    dict
        Statistic -> float: ``mae`` (the mean), ``p99`` (``np.percentile(error, 99)``) and ``worst`` (the
        largest error).
    """
    error = np.asarray(error, float)
    unknown = sorted(set(statistics) - set(STATISTICS))
    if unknown:
        raise ValueError(f"error statistics must be among {STATISTICS}, got {unknown}")
    if error.size == 0:
        raise ValueError("no error to summarize: every view was left out")
    compute = {"mae": error.mean, "p99": lambda: np.percentile(error, 99), "worst": error.max}
    return {name: float(compute[name]()) for name in statistics}


def plan_size(plans: dict, plan: str, measurement: str) -> dict:
    """The size of a measurement at a plan.

    Parameters
    ----------
    plans : dict
        The measurement's plans, by name (its ``PLANS``).
    plan : str
        The plan asked for (``measurements.plan`` in the config).
    measurement : str
        The measurement's name in the error message (``stability``, ``benchmark``, ...).

    Returns
    -------
    ``plans[plan]``; ``ValueError`` naming the measurement's plans for any other name.
    """
    if plan not in plans:
        raise ValueError(f"no {measurement} plan {plan!r}: one of {', '.join(plans)}")
    return plans[plan]
