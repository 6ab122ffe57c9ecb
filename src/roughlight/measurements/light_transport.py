"""Beyond the OpenGL equation: the study's surfaces in Mitsuba 3, with direct light alone and with light that bounces.

Two questions, one plan of surfaces and views (:data:`PLANS`):

* **Does a renderer nobody here wrote agree with our exact reference?** :func:`agreement` renders each surface of
  the plan's check (regular surfaces, the control plate, one tile of each random kind) with the ``mitsuba`` method at its default,
  direct light alone, and holds each component to the exact reference (``reference``) at every view, as
  :func:`roughlight.measurements.renderer_validation.view_errors` holds the fast renderer.
* **What does the OpenGL equation miss?** :func:`interreflection` renders the grid's surfaces again with light that
  bounces between facets, the diffuse alone, at two albedos: the study's diffuse reflectance (1: a white surface,
  the extreme) and a physical one below it (``report.light_transport.albedo``). Direct light stays on the study's
  scale at either albedo (the mitsuba method's ``albedo``), so the gain is what bouncing adds to the study's
  diffuse, in 8-bit levels and in percent of direct light. :func:`interreflection_summary` gives each surface's mean and worst
  gain over the views of Tables 1-2 (the azimuth-0 arc) and over the hemisphere.

Angles in degrees; values on the study's 0-255 scale.
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd

from ..analysis.thesis import SQRT3_2, THESIS_INCIDENCE
from ..render import methods, shading
from ..render.views import distinct_views
from ..surfaces.roughness import kind_and_seed, make_surface
from ..surfaces.surface import Surface
from .renderer_validation import view_errors

__all__ = ["LEVEL", "PLANS", "plan_views", "agreement", "interreflection", "interreflection_summary"]

#: One 8-bit level: where the OpenGL equation stops being within a level of what it is held to.
LEVEL = 1.0

#: Each plan: the grid's surfaces (truncation, aspect) light bounces on, the surfaces checked against the exact
#: reference (``check``, with the control plate and the random ``tiles``: kind, truncation, aspect, seed), the views
#: (the arc's elevation step; the hemisphere's elevation and azimuth steps), Mitsuba's sampling (pixels a period,
#: samples a pixel) of the check, of the check's random tiles (``tile_sampling``: pixels a cell, and a tile is
#: ``cells`` periods a side, so at the regular surfaces' 32 its film held 16 times their pixels; at 16 the quick
#: plan's two tiles took 1.2 s each against 3.0-4.4 s, their worst view 0.10 of a level off against 0.05, beside
#: the regular surfaces' 0.08-0.20: docs/mitsuba.md) and where light bounces, and the variant light bounces in.
#: ``quick`` is the default run's (a report section's worth): its small films the scalar variant renders in
#: milliseconds, where the llvm variant spends about a second compiling its kernels for each new scene (measured: 28
#: views of one surface, 0.1 s scalar against 1.6 s llvm with its compile); the check stays in the configured variant,
#: whose specular plugin the scalar variant runs in Python, a sample at a time. ``full`` is ``make bench``'s, all in
#: the configured variant (``variant`` None).
PLANS = {
    "quick": {"grid": tuple((t, a) for t in (0.25, 0.5, 1.0) for a in (0.1, 0.3, 1.0)),
              "check": ((0.5, 0.3), (1.0, 1.0)),
              "tiles": (("random_pyramids", 1.0, 1.0, 1), ("random_heightfield", 1.0, 1.0, 1)),
              "arc_step": 20.0, "hemisphere": (30.0, 45.0), "check_sampling": (32, 16), "tile_sampling": (16, 16),
              "sampling": (16, 4), "variant": "scalar_rgb"},
    # a check that a config builds the whole report, in seconds (its numbers are not for reading)
    "smoke": {"grid": ((0.5, 0.3), (1.0, 1.0)), "check": ((1.0, 1.0),),
              "tiles": (("random_pyramids", 1.0, 1.0, 1), ("random_heightfield", 1.0, 1.0, 1)),
              "arc_step": 45.0, "hemisphere": (45.0, 90.0), "check_sampling": (16, 4), "tile_sampling": (8, 4),
              "sampling": (8, 2), "variant": "scalar_rgb"},
    "full": {"grid": tuple((t, a) for t in (0.25, 0.5, 0.75, 1.0) for a in (0.1, 0.25, 0.5, 0.75, SQRT3_2, 1.0)),
             "check": tuple((t, a) for t in (0.25, 0.5, 0.75, 1.0) for a in (0.1, 0.25, 0.5, 0.75, SQRT3_2, 1.0)),
             "tiles": tuple((kind, t, a, seed) for kind in ("random_pyramids", "random_heightfield")
                            for t, a in ((0.5, 0.5), (1.0, 1.0)) for seed in (1, 2)),
             "arc_step": 5.0, "hemisphere": (10.0, 15.0), "check_sampling": (32, 16), "tile_sampling": (32, 16),
             "sampling": (32, 16), "variant": None},
}

def plan_views(plan: str) -> dict:
    """The plan's two sets of views, ``{"arc": (azimuth, elevation), "hemisphere": (azimuth, elevation)}``: the
    azimuth-0 arc of Tables 1-2 (elevations ``arc_step`` to 180 - ``arc_step``) and the hemisphere (azimuths 0 to
    180 by the hemisphere's azimuth step, elevations from its elevation step to 180 less it), each a pair of
    (n,) arrays, degrees."""
    p = PLANS[plan]
    arc = np.arange(p["arc_step"], 180.0 - p["arc_step"] / 2, p["arc_step"])
    el_step, az_step = p["hemisphere"]
    az, el = np.meshgrid(np.arange(0.0, 180.0, az_step), np.arange(el_step, 180.0 - el_step / 2, el_step),
                         indexing="ij")
    return {"arc": (np.zeros_like(arc), arc), "hemisphere": (az.ravel(), el.ravel())}


def _all_views(plan: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Both sets of :func:`plan_views` in one sweep's views: each view's set's name, azimuth and elevation, (n,)."""
    views = plan_views(plan)
    names = np.concatenate([np.full(len(az), name) for name, (az, _) in views.items()])
    return (names, np.concatenate([az for az, _ in views.values()]),
            np.concatenate([el for _, el in views.values()]))


def _mitsuba(plan: str, settings, bounce: bool = True, tile: bool = False, **knobs) -> dict:
    """The mitsuba method's knobs: the plan's sampling (the check's, without ``bounce``; its random tiles', with
    ``tile``), the variant (the plan's where light bounces and it names one, else the configured one, ``settings``:
    ``render.mitsuba``), and ``knobs``."""
    p = PLANS[plan]
    configured = {"variant": settings["variant"]} if settings and "variant" in settings else {}
    variant = {"variant": p["variant"]} if bounce and p["variant"] else configured
    pixels, samples = p["sampling"] if bounce else p["tile_sampling"] if tile else p["check_sampling"]
    return {"pixels_per_period": pixels, "samples_per_pixel": samples, **variant, **knobs}


def _surfaces(plan: str, check: bool = False) -> list:
    """The plan's surfaces light bounces on (its grid), or (``check``) those checked against the exact reference:
    the check's, the control plate and the random tiles."""
    p = PLANS[plan]
    if not check:
        return [Surface(t, a) for t, a in p["grid"]]
    return [Surface(t, a) for t, a in p["check"]] + [Surface(0.0, 0.0)] + [
        make_surface(kind, t, a, seed=seed) for kind, t, a, seed in p["tiles"]]


def _describe(surface) -> dict:
    kind, seed = kind_and_seed(surface)
    return {"kind": "control" if surface.is_plate and kind == "pyramids" else kind,
            "truncation": float(surface.truncation), "aspect": float(surface.aspect), "seed": int(seed)}


def agreement(plan: str = "quick", incidence: float = THESIS_INCIDENCE, lighting=None, settings=None,
              log=None) -> pd.DataFrame:
    """The ``mitsuba`` method (direct light alone, its default) against the exact reference at every view of the
    plan, per surface and component.

    Parameters
    ----------
    settings : dict, optional
        The method's config keys (``render.mitsuba``): its ``variant`` is used; the plan fixes the sampling.

    Returns
    -------
    DataFrame, one row a surface and component: ``kind``, ``truncation``, ``aspect``, ``seed``, ``incidence``,
    :func:`~roughlight.measurements.renderer_validation.view_errors`' columns, ``variant`` (what Mitsuba ran on) and
    ``mitsuba_views_per_second``.
    """
    lighting = lighting or shading.Lighting()
    _, az, el = _all_views(plan)
    rows = []
    for surface in _surfaces(plan, check=True):
        tile = kind_and_seed(surface)[0] != "pyramids"
        knobs = methods.settings("mitsuba", _mitsuba(plan, settings, bounce=False, tile=tile, bounces=1))
        exact = methods.sweep("reference", surface, incidence, az, el, lighting)
        start = time.perf_counter()
        rendered = methods.sweep("mitsuba", surface, incidence, az, el, lighting, knobs)
        seconds = time.perf_counter() - start
        measured = {c: rendered[c] for c in shading.COMPONENTS if np.all(np.isfinite(rendered[c]))}
        for row in view_errors(measured, exact, az, el):
            rows.append({**_describe(surface), "incidence": float(incidence), **row, "variant": rendered["renderer"],
                         "mitsuba_views_per_second": len(az) / seconds})
        if log:
            log(f"mitsuba against the reference: {surface}: worst "
                + ", ".join(f"{r['component']} {r['worst']:.3f}" for r in rows[-len(measured):]))
    return pd.DataFrame(rows)


def interreflection(plan: str = "quick", incidence: float = THESIS_INCIDENCE, lighting=None, bounces: int = 8,
                    albedo: float = 0.5, settings=None, log=None) -> pd.DataFrame:
    """The diffuse with light that bounces ``bounces`` times against direct light alone, on the plan's grid, at two
    albedos: the study's diffuse reflectance and ``albedo``, a physical one below it.

    Returns
    -------
    DataFrame, one row a surface, albedo and view: ``truncation``, ``aspect``, ``incidence``, ``albedo``, ``views``
    (``arc`` | ``hemisphere``), ``azimuth``, ``elevation``, ``direct`` and ``bounced`` (the diffuse, 0-255),
    ``gain`` (levels) and ``gain_percent`` (of direct; NaN where direct is below one level), ``bounces``.
    """
    lighting = lighting or shading.Lighting()
    names, az, el = _all_views(plan)
    albedos = sorted({float(lighting.diffuse_reflectance), float(albedo)}, reverse=True)
    frames = []
    for surface in _surfaces(plan):
        # direct light is on the study's scale at any albedo: rendered once a surface, all views in one sweep
        direct = methods.sweep("mitsuba", surface, incidence, az, el, lighting,
                               _mitsuba(plan, settings, specular=False, bounces=1))["diffuse"]
        for rho in albedos:
            bounced = methods.sweep("mitsuba", surface, incidence, az, el, lighting,
                                    _mitsuba(plan, settings, specular=False, bounces=int(bounces), albedo=rho))["diffuse"]
            gain = bounced - direct
            frames.append(pd.DataFrame({
                "truncation": float(surface.truncation), "aspect": float(surface.aspect), "incidence": float(incidence),
                "albedo": rho, "views": names, "azimuth": az, "elevation": el, "direct": direct, "bounced": bounced,
                "gain": gain, "gain_percent": np.where(direct >= 1.0, 100.0 * gain / np.maximum(direct, 1.0), np.nan),
                "bounces": int(bounces)}))
            if log:
                log(f"interreflection: {surface} albedo {rho:g}: gain mean {gain.mean():.2f}, worst {gain.max():.2f} "
                    "levels")
    return pd.concat(frames, ignore_index=True)


def interreflection_summary(frame: pd.DataFrame, level: float = LEVEL) -> pd.DataFrame:
    """Each surface's gain from light that bounces, per albedo and set of views (with its ``bounces``), over the
    set's views each once (``n_views``; the zenith once, not once per azimuth:
    :func:`roughlight.render.views.distinct_views`): ``mean_gain`` and ``worst_gain`` (levels), ``mean_percent``
    and ``worst_percent`` (of direct light, over views with at least one level of it), ``worst_elevation`` and
    ``worst_azimuth`` (the view of the worst gain), and ``within_level`` (the worst gain is below ``level``: the
    OpenGL equation's diffuse is within a level of light transport at every view)."""
    keys = ["truncation", "aspect", "incidence", "albedo", "views", "bounces"]
    rows = []
    for key, g in frame.groupby(keys, sort=True):
        g = g[distinct_views(g["azimuth"], g["elevation"])]
        k = g["gain"].to_numpy().argmax()
        rows.append({**dict(zip(keys, key)), "n_views": len(g), "mean_gain": float(g["gain"].mean()),
                     "worst_gain": float(g["gain"].max()), "mean_percent": float(g["gain_percent"].mean()),
                     "worst_percent": float(g["gain_percent"].max()),
                     "worst_elevation": float(g["elevation"].iloc[k]), "worst_azimuth": float(g["azimuth"].iloc[k]),
                     "within_level": bool(g["gain"].max() < level)})
    return pd.DataFrame(rows)
