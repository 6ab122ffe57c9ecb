"""Rendered pictures and plate sweeps for the report's figures (the thesis's Figs. 9, 10, 13, 17, 20).

These render (the naive scene for pictures of finite patches, the fast method
for the plate's sweeps); :mod:`roughlight.report.figures` only draws what they return.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..surfaces.surface import PLATE, Surface


def plate_sweeps(incidences, lights, elevation_step: float = 1.0, lighting=None, settings=None) -> pd.DataFrame:
    """Render the flat plate on the phi = 0 arc for several incidences and light levels.

    Parameters
    ----------
    incidences : iterable of degrees; lights : iterable of J (0-255)
    elevation_step : degrees
    lighting : dict of :class:`roughlight.render.shading.Lighting` fields (the
        light level is replaced by each of ``lights``); settings : dict of
        :class:`roughlight.render.fast.settings.FastSettings` fields.

    Returns
    -------
    long DataFrame: ``incidence``, ``light``, ``elevation``, ``component``, ``value`` (0-255), ``seconds``.
    """
    from . import methods
    from .shading import Lighting
    from .views import elevations

    base = dict(lighting or {})
    base["shadows"] = False  # the plate casts none
    el = elevations(elevation_step)
    az = np.zeros_like(el)
    rs = methods.settings("fast", settings)
    rows = []
    for inc in incidences:
        for J in lights:
            lit = Lighting(**{**base, "light": float(J)})
            out = methods.sweep("fast", PLATE, float(inc), az, el, lit, rs)
            for comp in ("diffuse", "specular", "total"):
                rows.append(pd.DataFrame({"incidence": float(inc), "light": float(J), "elevation": el,
                                          "component": comp, "value": np.asarray(out[comp], float),
                                          "seconds": float(out["seconds"])}))
    return pd.concat(rows, ignore_index=True)



#: stem -> (title, list of (truncation, aspect, incidence, elevation, azimuth, label))
PICTURE_SETS = {
    "fig09_shadows": (
        "Shadows at several incidences (full pyramids, aspect 1, seen from elevation 20, azimuth 60)",
        [(1.0, 1.0, i, 20.0, 60.0, f"incidence {i:g}") for i in (15.0, 30.0, 45.0, 70.0)]
        + [(0.5, 1.0, 30.0, 20.0, 60.0, "truncation 0.5, incidence 30")],
    ),
    "fig10_grazing": (
        "Views near grazing (truncation 1, aspect 1, incidence 30, azimuth 0 from the light's side)",
        [(1.0, 1.0, 30.0, e, 0.0, f"elevation {e:g}") for e in (2.0, 10.0, 30.0, 90.0)],
    ),
    "fig13_tops": (
        "Truncated tops at low incidence (aspect 1, incidence 10, seen from the mirror direction, elevation 170)",
        [(t, 1.0, 10.0, 170.0, 0.0, f"truncation {t:g}") for t in (0.3, 0.6, 0.9, 1.0)],
    ),
}


def surface_pictures(views, lighting=None, size=(400, 300), periods=6):
    """Render pictures of finite patches (as the thesis's screenshots).

    Parameters
    ----------
    views : list of (truncation, aspect, incidence, elevation, azimuth, label)
    lighting : :class:`roughlight.render.shading.Lighting` or None

    Returns
    -------
    list of (label, (H, W, 3) uint8 image), from :func:`roughlight.render.naive.procedure.render_picture`
    """
    from .naive.procedure import render_picture

    return [(label, np.asarray(render_picture(Surface(t, a), i, e, phi, lighting=lighting, size=size,
                                              periods=periods)))
            for t, a, i, e, phi, label in views]


