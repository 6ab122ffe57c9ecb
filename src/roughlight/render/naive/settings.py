"""The naive method's settings: the thesis's window, capture and patch, as :class:`NaiveSettings`.

Pure Python: no OpenGL is loaded here, so the settings can be built, checked and recorded by code that never
renders.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..shading import SHADINGS

__all__ = ["NaiveSettings", "NAIVE_SHADOW_MAP"]

#: pyrender's directional shadow map, texels a side (``pyrender.constants.SHADOW_TEX_SZ``, which
#: tests/test_rendering.py checks this equals).
NAIVE_SHADOW_MAP = 2048


@dataclass(frozen=True)
class NaiveSettings:
    """Knobs of the ``naive`` method (the thesis's procedure, one render per view).

    Attributes
    ----------
    window : (int, int)
        Framebuffer width and height, pixels (the thesis's 400 x 300).
    capture : int
        Side of the central capture window whose mean is the view's value, pixels (the thesis's 40).
    view_periods : float
        Periods across the window (40: 10 pixels a period).
    lowest_elevation : float
        Degrees: the patch has enough periods to fill the capture window down to this elevation.
    jitter : (float, float)
        Shift of the camera in its image plane, pixels (x, y).
    shading_model : str
        One of :data:`roughlight.render.shading.SHADINGS`: ``flat`` is the study's (true face normals);
        ``phong`` and ``gouraud`` use averaged vertex normals, to measure how wrong they make each component.
    """

    window: tuple = (400, 300)
    capture: int = 40
    view_periods: float = 40.0
    lowest_elevation: float = 10.0
    jitter: tuple = (0.0, 0.0)
    shading_model: str = "flat"

    def __post_init__(self):
        if len(self.window) != 2 or min(int(w) for w in self.window) < 1:
            raise ValueError(f"naive window must be two sizes >= 1 pixel, got {self.window!r}")
        if not 1 <= int(self.capture) <= min(int(w) for w in self.window):
            raise ValueError(f"naive capture must be within 1 and the window's side, got {self.capture!r}")
        if not float(self.view_periods) > 0:
            raise ValueError(f"naive view_periods must be > 0, got {self.view_periods!r}")
        if not 0 < float(self.lowest_elevation) <= 90:
            raise ValueError(f"naive lowest_elevation must be within (0, 90] degrees, got {self.lowest_elevation!r}")
        if self.shading_model not in SHADINGS:
            raise ValueError(f"shading_model must be one of {SHADINGS}, got {self.shading_model!r}")

    def recorded(self, surface=None) -> dict:
        """How the surface was sampled, as the study table and the benchmark record it: pixels a period,
        ``window`` sampling and pyrender's shadow map."""
        return {"pixels_per_period": int(round(self.window[0] / self.view_periods)), "sampling": "window",
                "shadow_map_size": NAIVE_SHADOW_MAP}
