"""The page's "Beyond the OpenGL equation": the study's surfaces in Mitsuba 3. Direct light alone against the exact
reference (a check of our reference by a renderer nobody here wrote), then what light that bounces between facets
adds to the diffuse (``templates/light_transport.html``); switched by ``report.light_transport.enabled``."""

from __future__ import annotations

import pandas as pd

from ...measurements.light_transport import LEVEL
from ..page_templates import caption_text, existing, frame_or_none
from ..registry import Section


def agreement_summary(agreement: pd.DataFrame) -> dict:
    """Per component: the surfaces and views checked, the worst view over them and the largest MAE."""
    rows = []
    for component, g in agreement.groupby("component", sort=False):
        k = g["worst"].to_numpy().argmax()
        rows.append({"component": component, "surfaces": len(g), "views": int(g["n_views"].sum()),
                     "worst": float(g["worst"].max()), "worst_surface": f"{g['kind'].iloc[k]} t {g['truncation'].iloc[k]:g}, "
                     f"a {g['aspect'].iloc[k]:.3g}", "largest_mae": float(g["mae"].max())})
    return {"rows": rows, "within": all(r["worst"] < LEVEL for r in rows),
            "variant": str(agreement["variant"].iloc[0]), "table": agreement}


def gains(summary: pd.DataFrame) -> list[dict]:
    """Per albedo, over the hemisphere: where the worst view's gain stays below a level, and the largest gain."""
    out = []
    hemi = summary[summary["views"] == "hemisphere"]
    for albedo, g in hemi.groupby("albedo", sort=False):
        within = g[g["within_level"]]
        k = g["worst_gain"].to_numpy().argmax()
        out.append({"albedo": float(albedo), "surfaces": len(g), "within": len(within),
                    "within_surfaces": [(float(r.truncation), float(r.aspect)) for r in within.itertuples()],
                    "mean_low": float(g["mean_gain"].min()), "mean_high": float(g["mean_gain"].max()),
                    "percent_low": float(g["mean_percent"].min()), "percent_high": float(g["mean_percent"].max()),
                    "worst": float(g["worst_gain"].iloc[k]), "worst_percent": float(g["worst_percent"].iloc[k]),
                    "worst_surface": (float(g["truncation"].iloc[k]), float(g["aspect"].iloc[k]))})
    return sorted(out, key=lambda r: -r["albedo"])


def light_transport_section(mitsuba_agreement: pd.DataFrame | None = None,
                            interreflection_summary: pd.DataFrame | None = None, light_transport_png=None,
                            plan: str = "full") -> dict | None:
    """The data of ``templates/light_transport.html``: the agreement of Mitsuba's direct light with the exact
    reference, and the gain of light that bounces (rule ``light_transport``'s tables and chart); None: switched
    off."""
    agreement, summary = frame_or_none(mitsuba_agreement), frame_or_none(interreflection_summary)
    if agreement is None or summary is None:
        return None
    png = existing(light_transport_png)
    shown = summary[["truncation", "aspect", "albedo", "views", "n_views", "mean_gain", "worst_gain", "mean_percent",
                     "worst_percent", "worst_elevation", "worst_azimuth", "within_level"]]
    return {"plan": plan, "level": LEVEL, "agreement": agreement_summary(agreement), "gains": gains(summary),
            "bounces": int(summary["bounces"].iloc[0]), "summary": shown,
            "png": png, "caption": caption_text("light_transport") if png else None}


SECTION = Section("light_transport", light_transport_section, "light_transport.html",
                  title="Beyond the OpenGL equation", anchor="light-transport",
                  switch="report.light_transport.enabled",
                  inputs={"mitsuba_agreement": "results/benchmarks/{plan}/mitsuba_agreement.parquet",
                          "interreflection_summary": "results/benchmarks/{plan}/interreflection_summary.csv",
                          "light_transport_png": "results/benchmarks/{plan}/light_transport.png"})
