"""A rough surface as one value: truncation and aspect, validated once where it enters.

See :mod:`roughlight.geometry` for what the two numbers mean: truncation ``t``
in [0, 1] is the fraction of the pyramid's height kept, aspect >= 0 the full
pyramid's height over its base width; ``t = 0`` or ``aspect = 0`` is the flat
plate, the control.
"""

from __future__ import annotations

import math

#: Aspect whose side facets face a light at incidence 30 (tilt 60 deg).
SQRT3_2 = math.sqrt(3.0) / 2.0


def aspect_label(aspect: float) -> str:
    """Readable label of an aspect: ``'√3/2'`` for sqrt(3)/2, else ``'%g'``."""
    return "√3/2" if abs(float(aspect) - SQRT3_2) < 1e-6 else f"{float(aspect):g}"
