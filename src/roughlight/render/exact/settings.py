"""The exact reference's settings (:class:`ReferenceSettings`). Pure Python."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["ReferenceSettings"]


@dataclass(frozen=True)
class ReferenceSettings:
    """Knobs of the ``reference`` method (exact polygon clipping).

    Attributes
    ----------
    quantized : bool
        True (the study's): each facet's lit and shadowed values are rounded to 8-bit levels before they are
        weighted by area, as a framebuffer stores them; False: the unrounded mean.
    """

    quantized: bool = True

    def __post_init__(self):
        if not isinstance(self.quantized, bool):
            raise TypeError(f"reference quantized must be True or False, got {self.quantized!r}")

    def recorded(self, surface=None) -> dict:
        """How the surface was sampled: exactly, with no pixels and no shadow map."""
        return {"pixels_per_period": 0, "sampling": "exact", "shadow_map_size": 0}
