"""The thesis's area functions from exact geometry: the reflecting facets' visible-and-lit shares of the image
seen from the lobes' mirror directions (its Fig. 24), and the back-lobe factor ``k``."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..render.exact import visible_lit_areas
from ..surfaces.geometry import lobe_centres
from ..surfaces.surface import Surface

__all__ = ["front_facet_share", "reflecting_areas"]


def front_facet_share(aspect: float, incidence: float) -> float:
    """The back-lobe area factor ``k`` from geometry.

    The share of the image that the full pyramid's light-facing facet fills,
    visible and lit, seen from its mirror direction (exact polygon clipping):
    0.5 at aspects 1 and sqrt(3)/2 with incidence 30. NaN when that mirror
    direction is below the horizon (no back lobe).
    """
    back = lobe_centres(incidence, aspect)["back"]
    if back is None:
        return float("nan")
    return float(visible_lit_areas(Surface(1.0, aspect), incidence, 0.0, back).get("east", (0.0, 0.0))[0])


def reflecting_areas(aspect: float, incidence: float, truncations=None):
    """Visible-and-lit areas of the reflecting facets against truncation (the thesis's Fig. 24).

    For each truncation, the top's share of the image seen from the forward
    mirror direction and the light-facing facet's share seen from the back
    mirror direction (exact polygon clipping,
    :func:`roughlight.render.exact.reference.visible_lit_areas`), beside the normalised
    square and triangle area functions ``(1 - t)^2`` and
    ``k (1 - (1 - t)^2)`` with ``k`` the full pyramid's value.

    Returns
    -------
    DataFrame: ``truncation``, ``top`` and ``front`` (fractions of the image,
    0-1), ``square_area`` and ``triangle_area`` (same scale), ``k``.
    """
    t_values = np.linspace(0, 1, 21) if truncations is None else np.asarray(truncations, float)
    centres = lobe_centres(incidence, aspect)
    rows = []
    for t in t_values:
        top = visible_lit_areas(Surface(t, aspect), incidence, 0.0, centres["forward"]).get("top", (0.0, 0.0))[0]
        front = np.nan
        if centres["back"] is not None:
            front = visible_lit_areas(Surface(t, aspect), incidence, 0.0, centres["back"]).get("east", (0.0, 0.0))[0]
        rows.append({"truncation": float(t), "top": float(top), "front": float(front)})
    out = pd.DataFrame(rows)
    k = front_facet_share(aspect, incidence)
    out["square_area"] = (1 - out["truncation"]) ** 2
    out["triangle_area"] = k * (1 - (1 - out["truncation"]) ** 2)
    out["k"] = k
    return out
