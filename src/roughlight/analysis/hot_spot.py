"""The hot spot: the shadow-hiding function around the direction back to the light, and the halo it draws.

The thesis's Fig. 18 is a halo around the shadow of an airplane on grass: the backward reflection around V = L,
where every visible point is lit and the shadows hide (Hapke's opposition effect, Ch. II). In the diffuse and the
total it is a kink, not a local maximum (the diffuse is flat or still rising below the light's elevation), so its
shape is read from the **shadow-hiding function**

    H(V) = diffuse with inner shadows / diffuse with them off

(the study table's ``rough_unrounded`` over ``rough_unshadowed``, the diffuse component): the lit share of what
is seen, each point weighted by its N . L. H = 1 at V = L, and, on any heightfield, on every view below the light
on its azimuth: a ray from a visible point toward such a view escapes the surface, so the steeper ray toward the
light does too. The halo is therefore open below the light, down to the horizon, on the regular surface and on the
random tiles alike; its shape is in its upper edge, which is what :func:`hot_spot_reading` reads:

* **background**: the mean of H over the upper half of the circle of ``radius`` around L (the views above the
  light's level, where the shadows show);
* **contrast**: H at L less the background, and the same in 8-bit levels of the diffuse (times the diffuse at L);
* **width**: how far above L, along the light's plane, H falls to its half-contrast level (degrees);
* **flatness**: the height of the halo's edge (the half-contrast level's upper crossing) at ``width`` to either
  side, over ``width``. A halo circular around L has its edge meet the light's level there (flatness 0); a
  flat-topped one, as a rectangle's edge, keeps its height (1). It is the hot spot's equivalent of the back
  lobe's squareness and phase shift: how the halo's edge moves as the view leaves the light's azimuth.

Directions are read between the measured views only (:mod:`roughlight.analysis.lobe_shape`'s field: each view
once, nothing mirrored, views that were not rendered NaN); the two sides are averaged, so a tile and its mirror
image in the light's plane give the same numbers. Angles are degrees of the plane tangent at L (``X`` toward the
zenith along the light's plane, ``Y`` across it).
"""

from __future__ import annotations

import math

import numpy as np

from .lobe_shape import RESOLUTION, field_values, tangent_basis, tangent_patch

__all__ = ["shadow_hiding", "hot_spot_reading", "HOT_SPOT_KEYS"]

#: What :func:`hot_spot_reading` returns (with ``measurable`` and ``why``).
HOT_SPOT_KEYS = ("contrast", "contrast_levels", "background", "top", "width", "flatness", "edge_plus", "edge_minus")

#: Step along the tangent plane at which an edge is looked for, degrees.
EDGE_STEP = 0.05


def shadow_hiding(diffuse, unshadowed) -> np.ndarray:
    """H = ``diffuse`` / ``unshadowed`` (the diffuse with inner shadows over the diffuse without them, arrays of
    one shape, 0-255 unrounded); NaN where the unshadowed diffuse is 0 or NaN (nothing lit to hide)."""
    d, u = np.asarray(diffuse, float), np.asarray(unshadowed, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(u > 0, d / u, np.nan)


def _line(light, y: float, xs) -> np.ndarray:
    """(n, 3) unit directions at tangent-plane points (x, ``y``) for ``xs`` (degrees) around ``light``."""
    u1, u2 = tangent_basis(light)
    d = light[None, :] + np.radians(np.asarray(xs, float))[:, None] * u1[None, :] + math.radians(y) * u2[None, :]
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def _edge(field, light, y: float, level: float, low: float, high: float) -> tuple[float, str]:
    """The halo's edge on the tangent-plane line Y = ``y``: scanning down from X = ``high`` to ``low``, the first
    X (interpolated) where H is at or above ``level``. Returns (X, '') or (NaN, why)."""
    xs = np.arange(high, low - EDGE_STEP / 2, -EDGE_STEP)
    values = field_values(field, _line(light, y, xs))
    reached = np.flatnonzero(~(values < level))  # at or above the level, or NaN
    if not len(reached):
        return np.nan, f"its edge lies below {low:g} deg at {y:+.2g} deg to the side"
    k = int(reached[0])
    if not np.isfinite(values[k]):
        return np.nan, "cut by the horizon: a view it needs was not rendered"
    if k == 0:
        return np.nan, f"wider than the search disc: it reaches {high:g} deg above the light"
    return float(xs[k] + EDGE_STEP * (values[k] - level) / (values[k] - values[k - 1])), ""


def hot_spot_reading(hiding_field, diffuse_field, light, radius: float, resolution: float = RESOLUTION) -> dict:
    """The hot spot's contrast, width and flatness around the unit direction to the ``light``.

    Parameters
    ----------
    hiding_field : the shadow-hiding function as a measured field
        (:func:`roughlight.analysis.lobe_shape.measured_field` of :func:`shadow_hiding`'s (A, E) values)
    diffuse_field : the diffuse (0-255) as a measured field, for the contrast in levels
    light : (3,) unit direction to the light (the study's: ``light_direction(incidence)``)
    radius : degrees of tangent plane: the background's circle, and how far an edge is looked for
    resolution : the background circle's sampling, degrees

    Returns
    -------
    dict: :data:`HOT_SPOT_KEYS` (H's units but ``contrast_levels``, 0-255, and the widths and edges, degrees),
    ``measurable`` and ``why`` ('' or why not).
    """
    light = np.asarray(light, float)
    out = {key: np.nan for key in HOT_SPOT_KEYS}
    out.update(measurable=False, why="")
    X, Y, values, _ = tangent_patch(hiding_field, light, radius, resolution)
    r = np.hypot(X, Y)
    ring = (r <= radius) & (r > radius - 2 * resolution) & (X >= 0)
    top = float(field_values(hiding_field, light[None, :])[0])
    if not (np.isfinite(values[ring]).all() and np.isfinite(top)):
        out["why"] = "cut by the horizon: the halo's background circle reaches views that were not rendered"
        return out
    background = float(values[ring].mean())
    diffuse_at_light = float(field_values(diffuse_field, light[None, :])[0])
    out.update(top=top, background=background, contrast=top - background,
               contrast_levels=(top - background) * diffuse_at_light)
    if not top > background:
        out["why"] = "no hot spot: H at the light is no higher than its background"
        return out
    level = top - (top - background) / 2.0
    width, why = _edge(hiding_field, light, 0.0, level, 0.0, radius)
    out["width"] = width
    if why or not width > 0:
        out["why"] = why or "no width: H falls to half its contrast at the light itself"
        return out
    edges = [_edge(hiding_field, light, side * width, level, -radius, radius) for side in (1.0, -1.0)]
    out["edge_plus"], out["edge_minus"] = edges[0][0], edges[1][0]
    whys = [w for _, w in edges if w]
    if whys:
        out["why"] = whys[0]
        return out
    out.update(flatness=0.5 * (edges[0][0] + edges[1][0]) / width, measurable=True)
    return out
