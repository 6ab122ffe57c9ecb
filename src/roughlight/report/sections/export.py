"""The page's "Lit from any direction: the measured BRDF exported": each exported surface's share table (drawn by
``implicit_table``) and Mitsuba file, their sizes and their errors against the exact reference off their nodes
(``templates/export.html``); on when ``export.surfaces`` names a surface."""

from __future__ import annotations

import pandas as pd

from ..page_templates import caption_text, existing, frame_or_none
from ..registry import Section

#: What the page shows of an export's summary (rule export_summary's table).
SHOWN = ["truncation", "aspect", "method", "component", "views", "mae", "p99", "worst", "worst_incidence",
         "worst_light_azimuth", "worst_azimuth", "worst_elevation", "within_level", "megabytes", "file_megabytes"]


def exported(config) -> bool:
    """Whether ``export.surfaces`` names a surface (the section's switch)."""
    from ...study.config import export_surfaces

    return bool(export_surfaces(config))


def export_section(export_summary: pd.DataFrame | None = None, export_png=None) -> dict | None:
    """The data of ``templates/export.html``: per exported surface and method, the total's error off the nodes,
    the files' sizes and the seconds each step took; None: nothing exported."""
    summary = frame_or_none(export_summary)
    if summary is None:
        return None
    total = summary[summary["component"] == "total"]
    parts = summary[summary["component"].isin(["diffuse", "specular"])]
    # each method's component with the worst view of its own (the one that sets the total's worst)
    worst_part = {(r.truncation, r.aspect, r.method): r.component
                  for r in parts.sort_values("worst").itertuples()}
    surfaces = []
    for (t, a), rows in total.groupby(["truncation", "aspect"], sort=False):
        methods = {r.method: {"mae": float(r.mae), "p99": float(r.p99), "worst": float(r.worst),
                              "within": bool(r.within_level), "megabytes": float(r.megabytes),
                              "file_megabytes": float(r.file_megabytes), "views": int(r.views),
                              "worst_above": min(float(r.worst_elevation), 180.0 - float(r.worst_elevation)),
                              "worst_incidence": float(r.worst_incidence),
                              "worst_component": worst_part.get((t, a, r.method))}
                   for r in rows.itertuples()}
        first = rows.iloc[0]
        surfaces.append({"truncation": float(t), "aspect": float(a), "methods": methods,
                         "seconds": float(first["table_seconds"] + first["mitsuba_seconds"] + first["check_seconds"]),
                         "table_seconds": float(first["table_seconds"])})
    png = existing(export_png)
    return {"surfaces": surfaces, "summary": summary[[c for c in SHOWN if c in summary.columns]],
            "png": png, "caption": caption_text("export") if png else None}


SECTION = Section("export", export_section, "export.html", title="Lit from any direction: the BRDF exported",
                  anchor="export", switch=exported,
                  inputs={"export_summary": "results/export/summary.csv", "export_png": "results/export/export.png"})
