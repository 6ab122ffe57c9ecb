"""Measuring a sweep (one surface seen from every view) with the method the config names.

``render.method`` is one of :data:`METHODS`: ``fast`` (the periodic renderer,
:mod:`roughlight.render.fast.periodic`), ``naive`` (the thesis's procedure,
:mod:`roughlight.render.naive.procedure`) or ``reference`` (exact polygon clipping,
:mod:`roughlight.render.exact.reference`), ``implicit_exact`` or ``implicit_correction``
(one flat quad through the implicit rough-surface shader,
:mod:`roughlight.render.implicit.shader`). :func:`measure_sweep` imports a renderer, and so
OpenGL, only when the method needs it. :func:`recorded_settings` says how each
method sampled the surface, as the study table and the benchmark record it.
"""

from __future__ import annotations

import time

import numpy as np

from ..surfaces.surface import Surface
from . import shading
from .fast.sampling import RenderSettings

#: Renderers selectable with ``render.method``.
METHODS = ("fast", "naive", "reference", "implicit_exact", "implicit_correction")


def recorded_settings(method: str, settings=None) -> dict:
    """How a method sampled the surface, as the study table and the benchmark record it.

    Returns
    -------
    dict: ``pixels_per_period`` (int), ``sampling`` (``lattice`` | ``grid`` for
    fast, ``window`` for naive, ``exact`` for the reference) and
    ``shadow_map_size`` (texels a side; 0 for the reference, which needs none).
    """
    if method == "fast":
        settings = settings or RenderSettings()
        return {"pixels_per_period": int(settings.pixels_per_period), "sampling": settings.sampling,
                "shadow_map_size": int(settings.shadow_map_size)}
    if method == "naive":
        from .naive.procedure import NAIVE_SHADOW_MAP, NAIVE_VIEW_PERIODS, NAIVE_WINDOW

        return {"pixels_per_period": int(round(NAIVE_WINDOW[0] / NAIVE_VIEW_PERIODS)), "sampling": "window",
                "shadow_map_size": NAIVE_SHADOW_MAP}
    if method == "reference":
        return {"pixels_per_period": 0, "sampling": "exact", "shadow_map_size": 0}
    if method.startswith("implicit_") and method in METHODS:
        from .implicit.model import model_samples

        # M pixels a view, all on one period: sqrt(M) a period along each direction
        samples = model_samples(method.removeprefix("implicit_"))
        return {"pixels_per_period": int(round(samples**0.5)), "sampling": "fibonacci", "shadow_map_size": 0}
    raise ValueError(f"render.method must be one of {METHODS}, got {method!r}")


def measure_sweep(method: str, surface: Surface, incidence, azimuth, elevation, lighting=None,
                  settings=None) -> dict:
    """Measure a sweep with the named method (``render.method``).

    Parameters
    ----------
    method : str
        One of :data:`METHODS`.
    surface : Surface
    incidence : float
        Light elevation above the surface plane, degrees in [0, 90].
    azimuth, elevation : (n_views,) arrays
        Views, degrees.
    lighting : Lighting, optional
    settings : RenderSettings, optional
        The fast method's; the others ignore it.

    Returns
    -------
    dict
        ``diffuse``, ``specular``, ``total`` and ``coverage``: (n_views,)
        arrays (0-255; coverage 0-1); ``seconds``: wall time of the sweep.
        ``fast`` renders with :func:`roughlight.render.fast.periodic.fast_sweep`, ``naive``
        with :func:`roughlight.render.naive.procedure.naive_sweep` (one render per view),
        ``reference`` computes the same quantity exactly
        (:func:`roughlight.render.exact.reference.reference_sweep`) without loading OpenGL;
        ``implicit_exact`` and ``implicit_correction`` render one quad through
        :func:`roughlight.render.implicit.shader.implicit_sweep`.
    """
    if method == "fast":
        from .fast.periodic import fast_sweep

        return fast_sweep(surface, incidence, azimuth, elevation, lighting, settings)
    if method == "naive":
        from .naive.procedure import naive_sweep

        return naive_sweep(surface, incidence, azimuth, elevation, lighting)
    if method == "reference":
        from .exact.reference import reference_sweep

        start = time.perf_counter()
        out = reference_sweep(surface, incidence, azimuth, elevation, lighting or shading.Lighting())
        out = {key: np.asarray(value, float) for key, value in out.items()}
        out["seconds"] = time.perf_counter() - start
        return out
    if method.startswith("implicit_") and method in METHODS:
        from .implicit.shader import implicit_sweep

        return implicit_sweep(method.removeprefix("implicit_"), surface, incidence, azimuth, elevation, lighting)
    raise ValueError(f"render.method must be one of {METHODS}, got {method!r}")
