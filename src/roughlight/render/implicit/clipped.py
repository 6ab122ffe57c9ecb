"""The clipped scene's facet shares: each facet's lit and shadowed share of one view's image, clipped exactly on the
CPU by the exact reference's polygons (:class:`roughlight.render.exact.reference.LitScene`), for one quad to draw
as the correction draws its own (:func:`roughlight.render.implicit.shader.render_field` with ``"clipped"``,
:func:`roughlight.render.implicit.shader.clipped_sweep`)."""

from __future__ import annotations

import numpy as np
import shapely

from ...surfaces.geometry import FACET_NAMES
from ...surfaces.surface import Surface
from ..exact.reference import lit_scene
from ..views import is_grazing

__all__ = ["clipped_shares", "forget_views", "clipped_state_bytes"]


def clipped_shares(surface: Surface, incidence, elevation, azimuth, shadows: bool = True,
                   light_azimuth: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """The clipped scene's shares: each facet's visible-lit and visible-shadowed share of one view's image, clipped
    exactly (the exact reference's polygons, as its sweep clips them: :meth:`LitScene.areas
    <roughlight.render.exact.reference.LitScene.areas>`) under the light at
    ``incidence`` and ``light_azimuth`` (degrees), whose scene (:func:`roughlight.render.exact.reference.lit_scene`)
    is kept for the process's last 16 lights.

    Returns
    -------
    lit, shadowed : (5,) float arrays, fractions of the view's image in
    :data:`~roughlight.surfaces.geometry.FACET_NAMES` order (a facet the surface does not have: 0); they sum to 1.
    ``elevation`` must not be grazing (0 or 180 degrees: no image).
    """
    if is_grazing(elevation):
        raise ValueError(f"clipped_shares: elevation {elevation!r} is grazing (no image)")
    scene = lit_scene(surface, float(incidence), bool(shadows), float(light_azimuth))
    lit, shadow = scene.areas(float(elevation), float(azimuth))
    order = [FACET_NAMES.index(name) for name in scene.surf.names]
    out = np.zeros((2, len(FACET_NAMES)))
    out[0, order], out[1, order] = lit, shadow
    return out[0] / out.sum(), out[1] / out.sum()


def forget_views(surface: Surface, incidence, shadows: bool, light_azimuth: float) -> None:
    """Forget the visible regions the light's scene keeps of the views it clipped
    (:func:`roughlight.render.exact.square_views.square_visible_regions`), so that a frame's shares clip its view
    whole: a frame benchmark draws one view again and again, which a moving camera never does."""
    lit_scene(surface, float(incidence), bool(shadows), float(light_azimuth)).surf.views.clear()


def clipped_state_bytes(surface: Surface, incidence, shadows: bool = True, light_azimuth: float = 0.0) -> int:
    """Bytes the clipped scene holds for one surface and light: its facets' footprints and their lit regions under
    the light, as well-known binary (the light's scene, :func:`clipped_shares`)."""
    scene = lit_scene(surface, float(incidence), bool(shadows), float(light_azimuth))
    polygons = list(scene.surf.footprints) + list(scene.lit)
    return int(sum(len(shapely.to_wkb(p)) for p in polygons))
