"""The page's "Tables 1 and 2": the data ``templates/tables.html`` and ``templates/thesis_table.html`` show.

Each function here picks and computes numbers from the analysis tables (:mod:`roughlight.analysis.thesis`); the
sentences around them are the templates'.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...analysis.thesis import TABLE_METRICS, THESIS_INCIDENCE, THESIS_TABLES, sd_bound
from ...study.selection import ASPECT_TOL
from ...surfaces.surface import aspect_label
from ..page_templates import frame_or_none
from ..registry import Section

#: The columns of a printed table (both readings of the thesis's SD) and their decimals.
PRINTED_METRICS = TABLE_METRICS[:2] + ["SD of |error|"] + TABLE_METRICS[2:]
DIGITS = {"Mean Abs Error": 2, "Standard Deviation": 2, "SD of |error|": 2, "b0": 3, "b1": 3, "RSS": 3}
#: The sources of a model's rows, in table order, and each row's class.
SOURCES = {"ours": "ours", "exact geometry": "exact", "thesis 2001": "thesis"}


def thesis_table(tables: pd.DataFrame, table: int, aspect: float, incidence: float = THESIS_INCIDENCE) -> dict:
    """One printed table's data: the thesis's models, for each a row per source ('ours', 'exact geometry' when
    present, 'thesis 2001')."""
    spec = THESIS_TABLES[table]
    sel = tables[(tables["table"] == table) & (np.abs(tables["aspect"] - aspect) <= ASPECT_TOL)]
    label = aspect_label(aspect)
    order = {source: k for k, source in enumerate(SOURCES)}
    blocks = []
    for model in spec["rows"]:
        block = sel[sel["model"] == model].sort_values("source", key=lambda s: s.map(order))
        rows = [{"cls": SOURCES[r["source"]], "source": r["source"], "cells": [r.get(m) for m in PRINTED_METRICS]}
                for _, r in block.iterrows()]
        blocks.append({"model": model, "rows": rows})
    return {"table": table, "id": f"table{table}-aspect-{label.replace('√3/2', 'sqrt3-2')}", "label": label,
            "title": spec["title"], "incidence": incidence, "metrics": PRINTED_METRICS, "digits": DIGITS,
            "blocks": blocks}


def table_statistic(tables, table, aspect, model, source, metric):
    sel = tables[(tables["table"] == table) & (np.abs(tables["aspect"] - aspect) <= ASPECT_TOL)
                 & (tables["model"] == model) & (tables["source"] == source)]
    return float(sel[metric].iloc[0]) if len(sel) else float("nan")


def lobe_maes(tables: pd.DataFrame) -> list[dict]:
    """Per aspect (largest first): the area function's and the regressed model's MAE of each lobe, ours."""
    out = []
    for aspect in sorted(tables["aspect"].unique(), reverse=True):
        out.append({
            "label": aspect_label(aspect),
            "forward_area": table_statistic(tables, 1, aspect, "Square Area Function", "ours", "Mean Abs Error"),
            "forward_regressed": table_statistic(tables, 1, aspect, "Regressed Model", "ours", "Mean Abs Error"),
            "back_area": table_statistic(tables, 2, aspect, "Triangle Area Function", "ours", "Mean Abs Error"),
            "back_regressed": table_statistic(tables, 2, aspect, "Regressed Model", "ours", "Mean Abs Error"),
        })
    return out


def exact_error(tables: pd.DataFrame, exact: pd.DataFrame | None) -> dict | None:
    """How far the fast renderer's peaks are from the exact ones (largest, mean) and the area functions' largest
    MAE on the exact peaks (None: not computed); None without exact peaks."""
    err = exact["error"].abs().dropna() if exact is not None and len(exact) else pd.Series(dtype=float)
    if not len(err):
        return None
    ex_area = tables[(tables["source"] == "exact geometry") & tables["model"].str.contains("Area")]
    worst = float(ex_area["Mean Abs Error"].max()) if ex_area["Mean Abs Error"].notna().any() else None
    return {"max": err.max(), "mean": err.mean(), "worst": worst}


def sd_reading(n: int = 11) -> dict:
    """What the thesis's SD column can be: a least-squares line leaves RSS <= (n - 1) SD^2 when SD is of the
    raw errors; the rows that break it at the thesis's 11 truncations cannot have that SD."""
    broken = []
    for table, spec in THESIS_TABLES.items():
        for model, values in spec["rows"].items():
            stats = dict(zip(TABLE_METRICS, values))
            bound = sd_bound(stats["Standard Deviation"], n)
            if stats["RSS"] > bound:
                broken.append({"table": table, "model": model, "rss": stats["RSS"], "bound": bound})
    return {"n": n, "broken": broken}


def implied(scales, at_scale) -> dict | None:
    """Which scale of its area functions the thesis's own numbers allow, and our rows at that scale."""
    if scales is None or not len(scales):
        return None
    shown = None
    if at_scale is not None and len(at_scale) and (at_scale["scale"] == "implied").any():
        cols = [c for c in ("scale", "m", "table", "aspect_label", "model", "Mean Abs Error", "Standard Deviation",
                            "b0", "b1", "RSS") if c in at_scale]
        shown = at_scale[cols]
    return {"scales": scales, "at_scale": shown, "area_wins": shown is not None and area_still_wins(at_scale)}


def area_still_wins(at_scale) -> bool:
    implied_rows = at_scale[at_scale["scale"] == "implied"]
    area = implied_rows[implied_rows["model"].str.contains("Area")]["Mean Abs Error"]
    regressed = implied_rows[implied_rows["model"] == "Regressed Model"]["Mean Abs Error"]
    return bool(len(area) and len(regressed) and area.max() < regressed.min())


def _interval_text(lo, hi) -> str:
    return f"[{lo:.3g}, {hi:.3g}]" if np.isfinite(lo) and np.isfinite(hi) else "–"


def bootstrap(boot) -> dict | None:
    """The bootstrap ranges of Tables 1-2, one row per table, aspect and model, a column per statistic."""
    if boot is None or not len(boot):
        return None
    b = boot.copy()
    b["interval"] = [_interval_text(lo, hi) for lo, hi in zip(b["low"], b["high"])]
    wide = b.pivot_table(index=["table", "aspect_label", "model"], columns="metric", values="interval",
                         aggfunc="first")
    wide = wide[[m for m in TABLE_METRICS if m in wide.columns]].reset_index()
    return {"wide": wide.rename(columns={"aspect_label": "aspect"}), "n_boot": int(b["n_boot"].iloc[0]),
            "n_trunc": "/".join(str(int(n)) for n in sorted(b["n"].unique())),
            "unresampled": bool((b["interval"] == "–").any())}


def _k_values(thesis) -> list | None:
    """The back lobe's k from geometry per aspect label (NaN: no side facets); None when the tables have no k."""
    if thesis is None or not len(thesis) or "k" not in thesis:
        return None
    return list(thesis[thesis["source"] == "ours"].groupby("aspect_label")["k"].first().items())


def _sine(sine) -> pd.DataFrame | None:
    if sine is None or not len(sine):
        return None
    s = sine.copy()
    s["aspect"] = s["aspect_label"]
    return s.drop(columns=["aspect_label"])


def tables_section(thesis_tables: pd.DataFrame | None = None, exact_peaks: pd.DataFrame | None = None,
                   implied_scales: pd.DataFrame | None = None, tables_at_implied_scale: pd.DataFrame | None = None,
                   thesis_tables_bootstrap: pd.DataFrame | None = None, sine_refits: pd.DataFrame | None = None,
                   table_incidence: float = THESIS_INCIDENCE) -> dict:
    """The data of ``templates/tables.html``, from the analysis outputs of rule ``analysis_tables`` by name."""
    thesis, exact = thesis_tables, exact_peaks
    has = thesis is not None and len(thesis)
    printed = [thesis_table(thesis, table, aspect, table_incidence)
               for aspect in sorted(thesis["aspect"].unique(), reverse=True) for table in (1, 2)] if has else []
    return {
        "incidence": table_incidence, "k": _k_values(thesis), "printed": printed,
        "maes": lobe_maes(thesis) if has else [], "exact_error": exact_error(thesis, exact) if has else None,
        "sd": sd_reading(),
        "implied": implied(implied_scales, tables_at_implied_scale) if has else None,
        "bootstrap": bootstrap(thesis_tables_bootstrap), "sine": _sine(sine_refits),
        "exact": frame_or_none(exact),
    }


SECTION = Section("tables", tables_section, "tables.html", title="Tables 1 and 2",
                  inputs={"thesis_tables": "results/analysis/thesis_tables.csv",
                          "exact_peaks": "results/analysis/exact_peaks.csv",
                          "implied_scales": "results/analysis/implied_scales.csv",
                          "tables_at_implied_scale": "results/analysis/tables_at_implied_scale.csv",
                          "thesis_tables_bootstrap": "results/analysis/thesis_tables_bootstrap.csv",
                          "sine_refits": "results/analysis/sine_refits.csv"})
