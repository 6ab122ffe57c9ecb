"""The three-part diffuse model's fits at the table aspects, after the diffuse figures
(``templates/diffuse_parts.html``)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...analysis.thesis import TABLE_ASPECTS
from ...study.selection import find_aspect
from ...surfaces.surface import aspect_label
from ..registry import Section


def diffuse_parts_section(diffuse_three_part: pd.DataFrame | None = None, table_aspects=TABLE_ASPECTS) -> dict:
    """The three-part diffuse model's fits at the table aspects."""
    dp = diffuse_three_part
    if dp is None or not len(dp):
        return {"table": None}
    want = [a for a in table_aspects if find_aspect(dp["aspect"], a) is not None]
    sel = dp[np.isin(dp["aspect"].round(12), [round(find_aspect(dp["aspect"], a), 12) for a in want])] \
        if want else dp.head(0)
    cols = ["truncation", "aspect", "e1", "e2", "level1", "level3", "rate", "decay_length", "rmse", "jump_at_e2",
            "rate_continuous", "rmse_continuous", "note"]
    sel = sel[[c for c in cols if c in sel]].copy()
    sel["aspect"] = sel["aspect"].map(aspect_label)
    return {"table": sel}


SECTION = Section("diffuse_parts", diffuse_parts_section, "diffuse_parts.html",
                  inputs={"diffuse_three_part": "results/analysis/diffuse_three_part.csv"})
