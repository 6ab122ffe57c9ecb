"""The regressions' part of "Where methods fail", after the stability scans: the GLMs' status and the Tables 1-2 rows
with a note (``templates/regressions.html``)."""

from __future__ import annotations

import pandas as pd

from ..page_templates import frame_or_none
from ..registry import Section


def regressions_section(glm_summary: pd.DataFrame | None = None, glm_messages: list | None = None,
                        thesis_tables: pd.DataFrame | None = None,
                        thesis_tables_bootstrap: pd.DataFrame | None = None) -> dict:
    """The regressions' part of "Where methods fail": the GLMs' status, the Tables 1-2 rows with a note."""
    summary = glm_summary
    if summary is not None and len(summary):
        summary = summary[[c for c in ("response", "n", "cut_by_horizon", "terms", "dropped", "converged",
                                     "condition_scaled", "status")
                           if c in summary.columns]]
    else:
        summary = None
    noted = None
    thesis = thesis_tables
    if thesis is not None and len(thesis) and "note" in thesis:
        noted = thesis[(thesis["source"] != "thesis 2001") & (thesis["note"].fillna("") != "")]
        noted = noted[[c for c in ("table", "aspect_label", "model", "source", "n", "converged", "note") if c in noted]]
    return {"summary": summary, "messages": glm_messages or [], "noted": noted,
            "bootstrap": frame_or_none(thesis_tables_bootstrap) is not None}


SECTION = Section("regressions", regressions_section, "regressions.html",
                  inputs={"glm_summary": "results/analysis/glm_summary.csv",
                          "glm_messages": "results/analysis/glm_messages.json",
                          "thesis_tables": "results/analysis/thesis_tables.csv",
                          "thesis_tables_bootstrap": "results/analysis/thesis_tables_bootstrap.csv"})
