"""Issue 58's held-out trial of the implicit models, as a user calls them: three surfaces off the study's grid, three
random lights each (incidence 10-80, any azimuth) and 40 random views a light (elevation 1-179, any azimuth), each
model through ``methods.sweep(model, surface, incidence, azimuth, elevation, light_azimuth=psi)`` with no settings,
against the exact reference under the same light. Prints each model's MAE and worst view by component.

Run: ``PYTHONPATH=src python tests/implicit_held_out.py`` (the table model measures each surface's table once, kept
in ``ROUGHLIGHT_TABLE_CACHE`` or ``~/.cache/roughlight/share_tables``).
"""

from __future__ import annotations

import os
import time

os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.render import methods, shading  # noqa: E402
from roughlight.surfaces.surface import Surface  # noqa: E402

SURFACES = (Surface(0.35, 0.55), Surface(0.75, 0.9), Surface(1.0, 0.7))
MODELS = ("implicit_exact", "implicit_correction", "implicit_table")


def trial(seed: int = 58) -> pd.DataFrame:
    """One row a model, surface, light, view and component: the model's value and the reference's."""
    rng = np.random.default_rng(seed)
    rows = []
    for surface in SURFACES:
        for _ in range(3):
            incidence, psi = float(rng.uniform(10, 80)), float(rng.uniform(0, 360))
            azimuth, elevation = rng.uniform(0, 360, 40), rng.uniform(1, 179, 40)
            exact = methods.sweep("reference", surface, incidence, azimuth, elevation, light_azimuth=psi)
            for model in MODELS:
                start = time.perf_counter()
                out = methods.sweep(model, surface, incidence, azimuth, elevation, light_azimuth=psi)
                seconds = time.perf_counter() - start
                for c in shading.COMPONENTS:
                    rows.append(pd.DataFrame({"model": model, "truncation": surface.truncation,
                                              "aspect": surface.aspect, "incidence": incidence, "light_azimuth": psi,
                                              "azimuth": azimuth, "elevation": elevation, "component": c,
                                              "value": out[c], "exact": exact[c], "seconds": seconds}))
    frame = pd.concat(rows, ignore_index=True)
    frame["error"] = (frame["value"] - frame["exact"]).abs()
    return frame


if __name__ == "__main__":
    frame = trial()
    summary = frame.groupby(["model", "component"])["error"].agg(mae="mean", worst="max", views="size")
    print(summary.round(3).to_string())
    worst = frame.loc[frame.groupby("model")["error"].idxmax()]
    print(worst[["model", "component", "truncation", "aspect", "incidence", "light_azimuth", "elevation", "azimuth",
                 "value", "exact"]].round(2).to_string(index=False))
