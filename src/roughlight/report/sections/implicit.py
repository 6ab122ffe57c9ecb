"""The page's "An implicit rough surface: the thesis's goal": the implicit shader against the exact reference and its
frame times (``templates/implicit.html``); switched by ``report.implicit``."""

from __future__ import annotations

import pandas as pd

from ..page_templates import caption_text, existing
from ..registry import Section


def implicit_data(implicit_validation: pd.DataFrame | None = None, implicit_frames: pd.DataFrame | None = None,
                  implicit_png=None, implicit_maps_png=None, plan: str = "full") -> dict | None:
    """"An implicit rough surface: the thesis's goal": the validation against the exact reference and the frame
    times (rule ``implicit_surface``), with their charts; None: switched off."""
    from ...measurements.implicit_surface import GOAL, goal, held_out_counts, summary

    validation, frames = implicit_validation, implicit_frames
    if validation is None or frames is None:
        return None
    f = frames.groupby(["field", "method"], as_index=False).agg(
        triangles=("triangles", "first"), frame_ms=("frame_ms", "mean"), error=("error", "max"))
    explicit = f[f["method"] == "explicit"].set_index("field")["frame_ms"]
    f["speedup_vs_explicit"] = f["frame_ms"].rdiv(f["field"].map(explicit))
    png, maps_png = existing(implicit_png), existing(implicit_maps_png)
    drawn = held_out_counts(validation)
    return {"plan": plan, "n_surfaces": drawn["surfaces"], "n_views": drawn["views"], "held_out": drawn,
            "summary": summary(validation),
            "png": png, "caption": caption_text("implicit") if png else None,
            "maps_png": maps_png, "maps_caption": caption_text("implicit_maps") if maps_png else None, "frames": f,
            "goal": goal(validation, frames), "targets": GOAL}


SECTION = Section("implicit", implicit_data, "implicit.html", title="An implicit rough surface", switch="report.implicit",
                  inputs={"implicit_validation": "results/benchmarks/{plan}/implicit_validation.parquet",
                          "implicit_frames": "results/benchmarks/{plan}/implicit_frames.parquet",
                          "implicit_png": "results/benchmarks/{plan}/implicit.png",
                          "implicit_maps_png": "results/benchmarks/{plan}/implicit_maps.png"})
