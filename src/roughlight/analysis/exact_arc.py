"""The exact reference on a surface's phi = 0 arc, each view clipped once: the exact lobe peaks' and widths'
sweeps (:func:`roughlight.analysis.thesis.exact_lobe_peaks`)."""

from __future__ import annotations

import numpy as np

from ..surfaces.surface import Surface

__all__ = ["ExactArc", "arc_elevations", "exact_widths"]


def arc_elevations(centre: float, halfwidth: float, step: float) -> np.ndarray:
    """The study's elevations (every ``step`` degrees) within ``halfwidth`` of ``centre``, strictly inside (0, 180)."""
    el = np.arange(np.ceil((centre - halfwidth) / step) * step, centre + halfwidth + 1e-9, step)
    return el[(el > 0) & (el < 180)]


class ExactArc:
    """The exact reference on one surface's phi = 0 arc, each view's facet areas clipped once.

    :func:`roughlight.render.exact.reference.reference_sweep` clips every view afresh. A lobe's exact peak and
    widths (:func:`exact_lobe_peaks`) ask for the same views up to three times, with and without specular
    shadows, which share the areas: the lit scene depends on ``shadows`` only. :meth:`sweep` gives
    ``reference_sweep``'s values, view for view (the same areas and the same :func:`~roughlight.render.shading.
    facet_sum`).

    Parameters
    ----------
    surface : Surface
    incidence : float, degrees
    shadows : bool, whether the surface casts shadows (``Lighting.shadows`` of every sweep asked for)
    """

    def __init__(self, surface: Surface, incidence: float, shadows: bool):
        from ..render.exact import LitScene

        self.surface, self.shadows = surface, bool(shadows)
        self.scene = LitScene(surface, incidence, self.shadows)
        self.areas = {}  # elevation -> (lit, shadowed) area of each facet

    def sweep(self, elevation, lighting) -> dict:
        """``reference_sweep(surface, incidence, 0, elevation, lighting)``'s ``diffuse``, ``specular`` and ``total``
        ((n,) arrays, 0-255, quantized) at elevations in (0, 180) degrees on the phi = 0 arc."""
        from ..render.shading import facet_sum, light_direction, view_direction

        if bool(lighting.shadows) != self.shadows:
            raise ValueError(f"this arc's areas are for shadows={self.shadows}, not {lighting.shadows}")
        from ..render.exact import view_areas

        el = np.asarray(elevation, float)
        missing = np.unique(el[[float(e) not in self.areas for e in el]])
        if missing.size:
            lit, shadow = view_areas(self.scene, self.surface, missing, np.zeros_like(missing))
            self.areas.update((float(e), (lit[k], shadow[k])) for k, e in enumerate(missing))
        lit = np.array([self.areas[float(e)][0] for e in el])
        shadow = np.array([self.areas[float(e)][1] for e in el])
        azimuth = np.zeros_like(el)
        return facet_sum(self.scene.surf.normals, light_direction(self.scene.incidence), view_direction(el, azimuth),
                         lit, shadow, lighting)


def exact_widths(surface, incidence, centre, lighting, halfwidth, step, exact: ExactArc | None = None) -> dict:
    """The exact lobe's FWHM on the phi = 0 arc with the study's specular shadows and without (the thesis's).

    ``exact``: the surface's :class:`ExactArc` under ``lighting.shadows``, if one is at hand (its areas are
    reused); else one is made.
    """
    from dataclasses import replace

    from .lobes import profile_lobe

    el = arc_elevations(centre, halfwidth, step)
    out = {"exact_fwhm": np.nan, "exact_peak_no_specular_shadows": np.nan, "exact_fwhm_no_specular_shadows": np.nan}
    if len(el) < 3:
        return out
    exact = exact or ExactArc(surface, incidence, lighting.shadows)
    window = (float(el[0]), float(el[-1]))
    for suffix, light in (("", lighting), ("_no_specular_shadows", replace(lighting, specular_shadows=False))):
        values = exact.sweep(el, light)["specular"]
        lobe = profile_lobe(el, values, centre, window)
        out[f"exact_fwhm{suffix}"] = float(lobe["fwhm"])
        if suffix:
            out[f"exact_peak{suffix}"] = float(lobe["peak"])
    return out
