"""The regular lobes of the random-roughness claim, measured around each lobe at the study's azimuth step and finer.

Rule ``claim_grid`` measures the regular surface at each grid point whose lobes enter the claim
(:func:`roughlight.analysis.claims.claim_geometry`), on the views around each lobe
(:func:`roughlight.analysis.claim_instrument.reference_views`), unrounded and with inner shadows off as well:

* the fast method (the study's) at every azimuth step of
  :func:`roughlight.analysis.claim_instrument.reference_steps` (the study's, half of it, 1 degree);
* the same geometry drawn as the random tiles are (a one-cell ``random_pyramids`` tile with no spread, at the
  tiles' own sampling, ``render.random_tiles``) at the study's step: the tested tiles' sampling on the regular lobe;
* the exact reference at the study's step, and, in the ``full`` plan, at every step.

Two of the claim's margins come from them (:func:`roughlight.analysis.claim_instrument.instrument_errors`): the
sampling error of the fast method and of the tiles' sampling against the exact reference on the study's view grid,
and the view grid's own effect (the study's azimuth step against 1 degree); the report shows each regular lobe's
statistics at each step.
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd

from ..render import methods
from ..study.selection import SURFACE_KEYS
from ..surfaces.roughness import make_surface
from ..surfaces.surface import Surface

__all__ = ["PLANS", "claim_grid"]

#: Which azimuth steps the exact reference measures, by plan: "study" (the study's alone) or "all"; the smoke
#: plan measures the study's step alone with either method.
PLANS = {"smoke": {"reference": "study", "fast": "study", "tile": "study"},
         "quick": {"reference": "study", "fast": "all", "tile": "study"},
         "full": {"reference": "all", "fast": "all", "tile": "study"}}
#: The regular surface drawn as a random tile: one cell, nothing varied (method "tile").
REGULAR_TILE = {"kind": "random_pyramids", "seed": 1, "cells": 1,
                "spread": {"truncation": 0.0, "aspect": 0.0, "apex": 0.0, "corner": 0.0}}

COLUMNS = SURFACE_KEYS + ["method", "step", "azimuth", "elevation", "component", "rough_unrounded",
                          "rough_unshadowed", "seconds"]


def claim_grid(geometry: pd.DataFrame, plan: str, sweep: dict, lighting, render: dict, log=print) -> pd.DataFrame:
    """Every claimed regular lobe measured around it by the fast method and the exact reference.

    Parameters
    ----------
    geometry : :func:`roughlight.analysis.claims.claim_geometry` (rule ``claim_discs``)
    plan : a key of :data:`PLANS`
    sweep : the study's view steps (``elevation_step``, ``azimuth_step``, degrees)
    lighting : :class:`roughlight.render.shading.Lighting`
    render : the fast method's knobs (the study's ``render:`` keys, with the random tiles' ``tile_*``)

    Returns
    -------
    DataFrame (:data:`COLUMNS`), a view x component a row: the view's ``rough_unrounded`` and ``rough_unshadowed``
    (0-255), by ``method`` ("fast", "tile", "reference") and azimuth ``step``; ``seconds`` the sweep's wall time.
    """
    from ..analysis.claim_instrument import reference_steps, reference_views

    if plan not in PLANS:
        raise ValueError(f"measurements.plan must be one of {sorted(PLANS)}, got {plan!r}")
    steps = reference_steps(float(sweep["azimuth_step"]))
    study_step = steps[0]
    views = reference_views(geometry, steps, float(sweep["elevation_step"]))
    chosen = {m: steps if which == "all" else [study_step] for m, which in PLANS[plan].items()}
    knobs = {"fast": methods.settings("fast", render), "tile": methods.settings("fast", render),
             "reference": methods.settings("reference", {})}
    frames = []
    for (t, a, i, step), part in views.groupby(SURFACE_KEYS + ["step"], sort=True):
        for method in ("fast", "tile", "reference"):
            if step not in chosen[method]:
                continue
            start = time.perf_counter()
            az, el = part["azimuth"].to_numpy(float), part["elevation"].to_numpy(float)
            surface = make_surface(truncation=t, aspect=a, **REGULAR_TILE) if method == "tile" else Surface(t, a)
            result = methods.sweep("reference" if method == "reference" else "fast", surface, i, az, el, lighting,
                                   knobs[method])
            seconds = time.perf_counter() - start
            log(f"claim grid: {method} t {t:g} a {a:g} i {i:g}, azimuth step {step:g}: {len(az)} views in "
                f"{seconds:.1f} s")
            frames.append(_rows((t, a, i), method, step, az, el, result, seconds))
    return pd.concat(frames, ignore_index=True)[COLUMNS] if frames else pd.DataFrame(columns=COLUMNS)


def _rows(key, method: str, step: float, az, el, result: dict, seconds: float) -> pd.DataFrame:
    """A sweep's rows: each view's unrounded and unshadowed means, a component at a time."""
    parts = []
    for component in ("diffuse", "specular", "total"):
        parts.append(pd.DataFrame({
            **dict(zip(SURFACE_KEYS, key)), "method": method, "step": float(step), "azimuth": az, "elevation": el,
            "component": component, "rough_unrounded": np.asarray(result[f"{component}_unrounded"], float),
            "rough_unshadowed": np.asarray(result[f"{component}_unshadowed"], float), "seconds": seconds}))
    return pd.concat(parts, ignore_index=True)
