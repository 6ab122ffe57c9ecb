"""The implicit shader's settings (:class:`ImplicitSettings`): which model, and how many pixels a view."""

from __future__ import annotations

from dataclasses import dataclass

from .model import FIBONACCI, model_samples

__all__ = ["ImplicitSettings"]


@dataclass(frozen=True)
class ImplicitSettings:
    """Knobs of the ``implicit_exact`` and ``implicit_correction`` methods (one quad through the implicit shader).

    Attributes
    ----------
    model : str
        ``"exact"`` (ray casting) or ``"correction"`` (the first-order correction), :data:`MODELS`.
    samples : int or None
        Pixels a view, a Fibonacci number (:data:`FIBONACCI`); None: the model's own
        (:func:`roughlight.render.implicit.model.model_samples`).
    """

    model: str = "exact"
    samples: int | None = None

    def __post_init__(self):
        model_samples(self.model)  # refuses an unknown model
        if self.samples is not None and int(self.samples) not in FIBONACCI:
            raise ValueError(f"samples must be one of the Fibonacci numbers {FIBONACCI}, got {self.samples!r}")

    @property
    def pixels(self) -> int:
        """Pixels a view."""
        return model_samples(self.model) if self.samples is None else int(self.samples)

    def recorded(self, surface=None) -> dict:
        """How the surface was sampled: ``pixels`` on one period, sqrt(pixels) a period along each direction."""
        return {"pixels_per_period": int(round(self.pixels**0.5)), "sampling": "fibonacci", "shadow_map_size": 0}
