"""The clipped scene's facet shares: each facet's lit and shadowed share of one view's image, clipped exactly on the
CPU in C (:class:`roughlight.render.exact.pyramid.PyramidScene`, the exact reference's construction with convex
pieces), for one quad to draw as the correction draws its own (:func:`roughlight.render.implicit.shader.render_field`
with ``"clipped"``, :func:`roughlight.render.implicit.shader.clipped_sweep`)."""

from __future__ import annotations

import functools

import numpy as np

from ...surfaces.surface import Surface
from ..exact.pyramid import PyramidScene

__all__ = ["clipped_shares", "clipped_scene", "clipped_state_bytes"]


@functools.lru_cache(maxsize=16)
def clipped_scene(surface: Surface, incidence: float, shadows: bool, light_azimuth: float) -> PyramidScene:
    """The light's scene (:class:`~roughlight.render.exact.pyramid.PyramidScene`), kept for the process's last 16
    lights."""
    return PyramidScene(surface, incidence, shadows, light_azimuth)


def clipped_shares(surface: Surface, incidence, elevation, azimuth, shadows: bool = True,
                   light_azimuth: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """The clipped scene's shares: each facet's visible-lit and visible-shadowed share of each view's image, clipped
    exactly in C (:meth:`PyramidScene.shares <roughlight.render.exact.pyramid.PyramidScene.shares>`; the exact
    reference's :meth:`LitScene.areas <roughlight.render.exact.reference.LitScene.areas>` to about 1e-12) under the
    light at ``incidence`` and ``light_azimuth`` (degrees).

    Returns
    -------
    lit, shadowed : (5,) float arrays for one view (``elevation``, ``azimuth`` floats, degrees), (V, 5) for (V,)
    arrays of them: fractions of the view's image in :data:`~roughlight.surfaces.geometry.FACET_NAMES` order (a
    facet the surface does not have: 0); each view's ten sum to 1. No elevation may be grazing (0 or 180 degrees:
    no image).
    """
    return clipped_scene(surface, float(incidence), bool(shadows), float(light_azimuth)).shares(elevation, azimuth)


def clipped_state_bytes(surface: Surface, incidence, shadows: bool = True, light_azimuth: float = 0.0) -> int:
    """Bytes the clipped scene holds for one surface and light: its facets' corners and planes, and the light
    (:attr:`PyramidScene.nbytes <roughlight.render.exact.pyramid.PyramidScene.nbytes>`)."""
    return clipped_scene(surface, float(incidence), bool(shadows), float(light_azimuth)).nbytes
