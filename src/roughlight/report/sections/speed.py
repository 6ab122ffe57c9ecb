"""The page's "Speed and accuracy": the speed/accuracy benchmark at ``measurements.plan`` with its chart, and
"Accuracy at every view", the default renderer held to the exact reference (``templates/speed.html``,
``templates/renderer_validation.html``); switched by ``report.speed_accuracy``."""

from __future__ import annotations

import pandas as pd

from ..page_templates import existing, frame_or_none, plain_text, render_macro
from ..registry import Section


def validation_line(validation: pd.DataFrame) -> dict:
    """The data of ``macros.html``'s ``validation_line``: per sampling setting, each component's worst view."""
    from ...measurements.renderer_validation import validation_summary

    summary = validation_summary(validation)
    if "setting" not in summary.columns:
        summary["setting"] = "configured"
    settings = []
    for setting, rows in summary.groupby("setting", sort=False):
        settings.append({"setting": setting, "views_per_second": rows["views_per_second"].iloc[0],
                         "rows": [{"component": r.component, "worst": r.worst, "p99": r.p99,
                                   "largest_mae": r.largest_mae} for r in rows.itertuples()]})
    return {"n_surfaces": len(validation[["truncation", "aspect", "incidence"]].drop_duplicates()),
            "views": int(validation["n_views"].max()), "settings": settings}


def renderer_validation_line(validation: pd.DataFrame) -> str:
    """One sentence (plain text): the default renderer's worst view, p99 and MAE against the exact reference."""
    return plain_text(render_macro("macros.html", "validation_line", validation_line(validation)))


def renderer_validation_data(validation: pd.DataFrame, smoothness: pd.DataFrame | None, png_path=None,
                             tiles: pd.DataFrame | None = None) -> dict:
    """The data of ``templates/renderer_validation.html``; ``tiles``: the random tiles against the exact reference
    (rule ``random_tiles``'s ``random_accuracy``), or None when no random kind is measured."""
    smoothness = frame_or_none(smoothness)
    worst = smoothness.sort_values("largest_deviation", ascending=False).iloc[0] if smoothness is not None else None
    return {"line": validation_line(validation), "png": existing(png_path), "validation": validation,
            "smoothness": smoothness, "worst": worst, "tiles": tile_accuracy(frame_or_none(tiles))}


def tile_accuracy(accuracy: pd.DataFrame | None) -> dict | None:
    """Per random kind: the tiles compared, their views, the worst view and the largest MAE over components."""
    if accuracy is None or "kind" not in accuracy:
        return None
    tiles = accuracy[accuracy["kind"] != "pyramids"]
    if tiles.empty:
        return None
    keys = [c for c in ("truncation", "aspect", "cells", "seed") if c in tiles]
    table = tiles.groupby("kind", sort=True).agg(
        tiles=("seed", lambda s: len(tiles.loc[s.index, keys].drop_duplicates())), views=("views", "sum"),
        refused=("reference_refused", "sum"), worst=("worst", "max"), largest_mae=("mae", "max")).reset_index()
    table["views"] = table["views"] // 3  # one row a component
    table["refused"] = table["refused"] // 3
    return {"table": table, "worst": float(tiles["worst"].max()), "largest_mae": float(tiles["mae"].max())}


def speed_section(speed_accuracy: pd.DataFrame | None = None, speed_accuracy_png=None,
                    renderer_validation: pd.DataFrame | None = None, arc_smoothness: pd.DataFrame | None = None,
                    renderer_validation_png=None, random_accuracy: pd.DataFrame | None = None) -> dict | None:
    """The speed/accuracy part of the provenance, with "Accuracy at every view" (None: switched off): the
    benchmark's table and chart, the renderer's validation, its arc curves and chart, the random tiles'."""
    if not (speed_accuracy_png or speed_accuracy is not None):
        return None
    return {"png": existing(speed_accuracy_png), "table": speed_accuracy,
            "validation": None if renderer_validation is None else renderer_validation_data(
                renderer_validation, arc_smoothness, renderer_validation_png, random_accuracy)}


SECTION = Section("speed", speed_section, "speed.html", title="Speed and accuracy", switch="report.speed_accuracy",
                  inputs={"speed_accuracy": "results/benchmarks/{plan}/speed_accuracy.parquet",
                          "speed_accuracy_png": "results/benchmarks/{plan}/speed_accuracy.png",
                          "renderer_validation": "results/benchmarks/{plan}/renderer_validation.parquet",
                          "arc_smoothness": "results/benchmarks/{plan}/arc_smoothness.parquet",
                          "renderer_validation_png": "results/benchmarks/{plan}/renderer_validation.png"})
