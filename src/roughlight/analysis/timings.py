"""How long each sweep took to render, from the study table's ``render_seconds``.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..study.selection import SURFACE_KEYS
from ..surfaces.surface import aspect_label


def render_timings(study: pd.DataFrame) -> tuple[pd.DataFrame, dict]:
    """Per-sweep render timings recorded in the study (``render_seconds``).

    Returns
    -------
    per_sweep : DataFrame, one row per sweep: keys, ``method``, ``views`` (rendered: coverage above 0),
        ``seconds``, ``views_per_second``.
    summary : dict: sweeps, views, total/median/max seconds, slowest sweep,
        overall views per second, methods.
    """
    comp = study["component"].astype(str)
    first = study.loc[comp == comp.iloc[0]]
    g = first.groupby(SURFACE_KEYS, sort=True)
    # the views rendered: coverage 0 (e = 0, 180) is a view the renderer never drew
    per = g.agg(views=("coverage", lambda c: int((c > 0).sum())), seconds=("render_seconds", "first"),
                method=("method", lambda s: str(s.iloc[0]))).reset_index()
    per["views_per_second"] = per["views"] / per["seconds"].where(per["seconds"] > 0)
    slow = per.loc[per["seconds"].idxmax()] if len(per) else None
    summary = {
        "sweeps": int(len(per)),
        "views": int(per["views"].sum()),
        "total_seconds": float(per["seconds"].sum()),
        "median_seconds": float(per["seconds"].median()) if len(per) else np.nan,
        "max_seconds": float(per["seconds"].max()) if len(per) else np.nan,
        "slowest": (f"truncation {slow['truncation']:g}, aspect {aspect_label(slow['aspect'])}, "
                    f"incidence {slow['incidence']:g}") if slow is not None else "",
        "views_per_second": float(per["views"].sum() / per["seconds"].sum()) if per["seconds"].sum() > 0 else np.nan,
        "methods": ", ".join(sorted(per["method"].unique())),
    }
    return per, summary
