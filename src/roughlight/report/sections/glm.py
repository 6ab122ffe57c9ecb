"""The page's "Grid GLMs": the GLMs over the grid, their coefficients, the share laws and the best of them held out
(``templates/glm.html``)."""

from __future__ import annotations

import pandas as pd

from ..page_templates import frame_or_none, section_figures
from ..registry import Section, figures


def best_laws(share_laws: pd.DataFrame | None) -> pd.DataFrame | None:
    """Per lobe and incidence, the share-law model best held out (None: no share laws)."""
    laws = frame_or_none(share_laws)
    return laws.loc[laws.groupby(["lobe", "incidence"])["rmse_held_out"].idxmin()] if laws is not None else None


def glm_section(glm_summary: pd.DataFrame | None = None, glm_coefficients: pd.DataFrame | None = None,
                glm_messages: list | None = None, share_laws: pd.DataFrame | None = None,
                figures: dict | None = None) -> dict:
    """"GLMs over the grid": the GLMs' summary and coefficients, the share laws and their best model held out."""
    return {"messages": glm_messages or [], "summary": glm_summary, "coefficients": glm_coefficients,
            "laws": frame_or_none(share_laws), "best_laws": best_laws(share_laws),
            "figures": section_figures("glm", figures or {})}


SECTION = Section("glm", glm_section, "glm.html", title="Grid GLMs",
                  inputs={"glm_summary": "results/analysis/glm_summary.csv",
                          "glm_coefficients": "results/analysis/glm_coefficients.csv",
                          "glm_messages": "results/analysis/glm_messages.json",
                          "share_laws": "results/analysis/share_laws.csv",
                          "figures": tuple(f.path for f in figures(section="glm"))})
