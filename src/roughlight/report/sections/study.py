"""The page's "The study": the grid measured, the settings that followed it, the table aspects it lacks, the notes
(``templates/study.html``)."""

from __future__ import annotations

from ...analysis.thesis import TABLE_ASPECTS
from ...study.selection import find_aspect
from ..registry import Section


def study_section(study_summary: dict | None = None, table_aspects=TABLE_ASPECTS, followed=()) -> dict:
    """"The study": the summary, the table aspects the study lacks, the notes (``study_summary``: what rule
    ``analysis_tables`` writes, ``study``, ``timings`` and ``messages``)."""
    study = (study_summary or {}).get("study") or {}
    messages = list((study_summary or {}).get("messages") or [])
    missing = [a for a in table_aspects if find_aspect(study.get("aspects", []), a) is None] if study else []
    return {"study": study, "followed": list(followed), "missing": missing, "messages": messages}


SECTION = Section("study", study_section, "study.html", title="The study",
                  inputs={"study_summary": "results/analysis/study_summary.json"})
