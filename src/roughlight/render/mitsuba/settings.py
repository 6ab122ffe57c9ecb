"""The Mitsuba method's settings (:class:`MitsubaSettings`). Pure Python: building, checking and recording them
loads neither Mitsuba nor Dr.Jit."""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

from .runtime import VARIANTS, variant_in_use

__all__ = ["MitsubaSettings", "VARIANTS", "MAX_RESOLUTION"]

#: The largest film side, pixels (``periods`` x ``pixels_per_period``, x a random tile's cells).
MAX_RESOLUTION = 4096


def _integer(name: str, value, low: int, high: int | None = None) -> int:
    if (isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value)
            or int(value) != value):
        raise ValueError(f"render.mitsuba.{name} must be an integer, got {value!r}")
    if value < low or (high is not None and value > high):
        span = f">= {low}" if high is None else f"within [{low}, {high}]"
        raise ValueError(f"render.mitsuba.{name} must be {span}, got {value!r}")
    return int(value)


@dataclass(frozen=True)
class MitsubaSettings:
    """Knobs of the ``mitsuba`` method (Mitsuba 3 renders the periodic field; docs/mitsuba.md).

    Attributes
    ----------
    bounces : int
        Light bounces: 1 (the default) is direct light alone, light and shadows, what the OpenGL equation and
        every other method measure (Mitsuba's ``direct`` integrator); more adds light passed between facets
        (``path`` with ``max_depth`` = bounces + 1).
    samples_per_pixel : int
        Mitsuba's samples a pixel (an ``independent`` sampler, seeded per view).
    pixels_per_period : int
        Pixels along each direction of one period of the regular surface (a random tile: of one cell).
    periods : int
        Side of the capture window in whole periods (a random tile: in whole tiles), so that its mean is the
        periodic surface's.
    variant : str
        Mitsuba variant (:data:`VARIANTS`); a missing backend falls back to the next one, with a line in the log
        and in what the sweep records.
    albedo : float or None
        The diffuse BSDF's reflectance, in (0, 1], how much light a facet passes on when light bounces; None:
        the study's diffuse reflectance ``m_d``. Direct light stays on the study's scale either way
        (``J m_d N.L``); with an albedo the specular and total are not measured (NaN).
    specular : bool
        Measure the study's specular (Phong or Blinn-Phong, a small BSDF plugin, docs/mitsuba.md) and the total;
        False measures the diffuse alone with Mitsuba's own ``diffuse`` BSDF (specular and total NaN).
    """

    bounces: int = 1
    samples_per_pixel: int = 16
    pixels_per_period: int = 32
    periods: int = 2
    variant: str = "llvm_ad_rgb"
    albedo: float | None = None
    specular: bool = True

    def __post_init__(self):
        object.__setattr__(self, "bounces", _integer("bounces", self.bounces, 1, 64))
        object.__setattr__(self, "samples_per_pixel", _integer("samples_per_pixel", self.samples_per_pixel, 1, 4096))
        object.__setattr__(self, "pixels_per_period", _integer("pixels_per_period", self.pixels_per_period, 1, 512))
        object.__setattr__(self, "periods", _integer("periods", self.periods, 1, 64))
        if self.variant not in VARIANTS:
            raise ValueError(f"render.mitsuba.variant must be one of {VARIANTS}, got {self.variant!r}")
        if self.albedo is not None:
            if isinstance(self.albedo, bool) or not isinstance(self.albedo, numbers.Real) \
                    or not (math.isfinite(self.albedo) and 0.0 < self.albedo <= 1.0):
                raise ValueError(f"render.mitsuba.albedo must be a number in (0, 1] or null, got {self.albedo!r}")
            object.__setattr__(self, "albedo", float(self.albedo))
        if not isinstance(self.specular, bool):
            raise TypeError(f"render.mitsuba.specular must be true or false, got {self.specular!r}")
        if self.periods * self.pixels_per_period > MAX_RESOLUTION:
            raise ValueError(f"render.mitsuba: periods x pixels_per_period is {self.periods * self.pixels_per_period}"
                             f" pixels a side, more than {MAX_RESOLUTION}")

    @classmethod
    def from_config(cls, knobs: dict | None = None) -> MitsubaSettings:
        """The settings from the config's ``render.mitsuba`` keys; an unknown key raises ``TypeError`` naming it."""
        return cls(**dict(knobs or {}))

    def config(self) -> dict:
        """The inverse of :meth:`from_config`: the settings as the config's ``render.mitsuba`` keys."""
        return {key: getattr(self, key) for key in self.__dataclass_fields__}

    def cells(self, surface=None) -> int:
        """Cells a side of a period of ``surface``: a random tile's ``cells``, 1 for the regular surface."""
        return int(getattr(surface, "cells", 1) or 1)

    def resolution(self, surface=None) -> int:
        """Film side, pixels: ``periods`` x ``pixels_per_period`` (x a random tile's cells)."""
        side = self.periods * self.pixels_per_period * self.cells(surface)
        if side > MAX_RESOLUTION:
            raise ValueError(f"render.mitsuba: a film of {side} pixels a side for this surface, more than "
                             f"{MAX_RESOLUTION}: lower pixels_per_period or periods")
        return side

    def integrator(self) -> dict:
        """Mitsuba's integrator: ``direct`` (one emitter sample, no BSDF sample: the light is a delta) for one
        bounce, ``path`` with ``max_depth`` = bounces + 1 (and no Russian roulette) for more."""
        if self.bounces == 1:
            return {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0}
        return {"type": "path", "max_depth": self.bounces + 1, "rr_depth": self.bounces + 1}

    def sampling(self, variant: str | None = None) -> str:
        """The study table's ``sampling`` label: the variant in use, the samples a pixel and the bounces."""
        used = variant or variant_in_use(self.variant)
        bounces = "direct light" if self.bounces == 1 else f"{self.bounces} bounces"
        return f"mitsuba {used}, {self.samples_per_pixel} spp, {bounces}"

    def recorded(self, surface=None) -> dict:
        """How the surface was sampled: ``pixels_per_period`` (a random tile's per cell), ``sampling`` naming
        the variant in use (after any fallback), the samples a pixel and the bounces, and no shadow map."""
        return {"pixels_per_period": int(self.pixels_per_period), "sampling": self.sampling(),
                "shadow_map_size": 0}
