"""A rough surface as one value: truncation and aspect, validated once where it enters.

See :mod:`roughlight.surfaces.geometry` for what the two numbers mean: truncation ``t``
in [0, 1] is the fraction of the pyramid's height kept, aspect >= 0 the full
pyramid's height over its base width; ``t = 0`` or ``aspect = 0`` is the flat
plate, the control.

A :class:`Surface` is built where a surface enters the program (the config's
grid, a benchmark or stability plan, a test) and passed down as it is to the
geometry, the renderers and the exact reference, none of which checks its
numbers again.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: Aspect whose side facets face a light at incidence 30 (tilt 60 deg).
SQRT3_2 = math.sqrt(3.0) / 2.0


#: Lengths below this (in periods) are zero: a surface lower than this is the
#: plate, and a top face narrower than this is the apex of a full pyramid.
LENGTH_EPS = 1e-9


@dataclass(frozen=True)
class Surface:
    """One rough surface of the study: a periodic grid of truncated square pyramids.

    Attributes
    ----------
    truncation : float
        Fraction of the pyramid's height kept, in [0, 1].
    aspect : float
        Full pyramid's height over its base width, >= 0 (finite).

    Raises
    ------
    ValueError
        At construction, naming the parameter and the allowed range.
    """

    truncation: float
    aspect: float

    def __post_init__(self):
        try:
            t = float(self.truncation)
            a = float(self.aspect)
        except (TypeError, ValueError) as exc:
            raise ValueError(
                f"truncation and aspect must be numbers, got {self.truncation!r}, {self.aspect!r}"
            ) from exc
        if not (math.isfinite(t) and 0.0 <= t <= 1.0):
            raise ValueError(f"truncation must be within [0, 1], got {self.truncation!r}")
        if not (math.isfinite(a) and a >= 0.0):
            raise ValueError(f"aspect must be a finite number >= 0, got {self.aspect!r}")
        object.__setattr__(self, "truncation", t)
        object.__setattr__(self, "aspect", a)

    @property
    def is_plate(self) -> bool:
        """True for the flat plate: ``t = 0`` or ``aspect = 0``, or lower than :data:`LENGTH_EPS`."""
        return self.truncation * self.aspect < LENGTH_EPS

    @property
    def height(self) -> float:
        """Height of the truncated pyramid, ``t * aspect`` (periods); 0 for the plate."""
        return 0.0 if self.is_plate else self.truncation * self.aspect


#: The flat plate (the control surface).
PLATE = Surface(0.0, 0.0)


def is_plate(truncation: float, aspect: float) -> bool:
    """True when (truncation, aspect) is the flat plate (see :attr:`Surface.is_plate`)."""
    return Surface(truncation, aspect).is_plate


def aspect_label(aspect: float) -> str:
    """Readable label of an aspect: ``'√3/2'`` for sqrt(3)/2, else ``'%g'``."""
    return "√3/2" if abs(float(aspect) - SQRT3_2) < 1e-6 else f"{float(aspect):g}"


def label(value) -> str:
    """Exact, file-name-safe text of a grid value: 0.1 -> '0.1', 1.0 -> '1', 30 -> '30'."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text
