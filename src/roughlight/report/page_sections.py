"""The data of the page's sections from the analysis tables: the study, the figure sections, the lobes, the GLMs,
the analytic models, the regressions' failures and the provenance (``templates/<section>.html`` each).

A function here picks rows and columns and counts; what the page says about them is in its template.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..study.selection import SURFACE_KEYS, find_aspect
from ..surfaces.surface import aspect_label
from .page_measurements import renderer_validation_data
from .page_templates import existing, frame_or_none, render, section_figures

#: The columns of the exact lobe peaks shown beside the measured lobes: the two specular-shadow protocols.
PROTOCOLS = ["exact_fwhm", "exact_peak_no_specular_shadows", "exact_fwhm_no_specular_shadows"]


def study_section(study: dict, messages: list, table_aspects, followed=()) -> dict:
    """"The study": the summary, the table aspects the study lacks, the notes."""
    missing = [a for a in table_aspects if find_aspect(study.get("aspects", []), a) is None] if study else []
    return {"study": study, "followed": list(followed), "missing": missing, "messages": messages}


def figure_section(section: str, figures: dict) -> dict:
    """A figure section of the page (specular, diffuse, pictures): its registry figures."""
    return {"section": section, "figures": section_figures(section, figures)}


def diffuse_parts_section(tables: dict, table_aspects) -> dict:
    """The three-part diffuse model's fits at the table aspects."""
    dp = tables.get("diffuse_parts")
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


def _at_table_aspects(frame: pd.DataFrame, table_aspects) -> pd.DataFrame:
    want = [find_aspect(frame["aspect"], a) for a in table_aspects]
    return frame[frame["aspect"].isin([a for a in want if a is not None])]


def lobes_section(tables: dict, figures: dict, table_aspects) -> dict:
    """"Lobes": the arc lobes at the table aspects (with the exact widths of both protocols), the hemisphere's."""
    out = {"figures": section_figures("lobes", figures), "arc": None, "protocols": False, "hemisphere": None}
    lobes = tables.get("lobes")
    if lobes is not None and len(lobes):
        sel = _at_table_aspects(lobes, table_aspects)
        sel = sel[sel["lobe"].isin(["forward", "back"])].copy()
        sel["aspect"] = sel["aspect"].map(aspect_label)
        cols = ["truncation", "aspect", "incidence", "lobe", "predicted", "peak", "peak_elevation", "centroid",
                "fwhm", "phase_at_peak", "note"]
        exact = tables.get("exact_peaks")
        if exact is not None and len(exact) and all(c in exact for c in PROTOCOLS):
            ex = exact[SURFACE_KEYS + ["lobe"] + PROTOCOLS].copy()
            ex["aspect"] = ex["aspect"].map(aspect_label)
            sel = sel.merge(ex, on=SURFACE_KEYS + ["lobe"], how="left")
            cols = cols[:-1] + PROTOCOLS + ["note"]
            out["protocols"] = True
        out["arc"] = sel[cols]
    hemi = tables.get("lobes_hemisphere")
    if hemi is not None and len(hemi):
        sel = _at_table_aspects(hemi, table_aspects).copy()
        sel["aspect"] = sel["aspect"].map(aspect_label)
        out["hemisphere"] = sel
    return out


def glm_section(tables: dict, figures: dict) -> dict:
    """"GLMs over the grid": the GLMs' summary and coefficients, the share laws and their best model held out."""
    laws = frame_or_none(tables.get("share_laws"))
    best = laws.loc[laws.groupby(["lobe", "incidence"])["rmse_held_out"].idxmin()] if laws is not None else None
    return {"messages": tables.get("glm_messages") or [], "summary": tables.get("glm_summary"),
            "coefficients": tables.get("glm_coefficients"), "laws": laws, "best_laws": best,
            "figures": section_figures("glm", figures)}


def _model_findings(summary: pd.DataFrame) -> list[dict]:
    """Per component, per band: the model that fits best on most surfaces and its median RMSE."""
    out = []
    for comp, g in summary[summary["band"] != "all"].groupby("component", sort=False):
        bands = []
        for band, gb in g.groupby("band", sort=True):
            best = gb.sort_values(["best_in", "median_rmse"], ascending=[False, True]).iloc[0]
            bands.append({"band": band, "model": best["model"], "rmse": best["median_rmse"]})
        out.append({"component": comp, "bands": bands})
    return out


def models_section(tables: dict, figures: dict, provenance: dict) -> dict:
    """"Analytic rough-surface models": Hapke against its background, Oren–Nayar's σ on a bound, the best models."""
    out = {"hapke_max_phase": (provenance.get("settings") or {}).get("hapke_max_phase", 60), "hapke": None,
           "sigma_bound": None, "findings": [], "summary_all": None, "summary_bands": None,
           "figures": section_figures("models", figures)}
    fits = tables.get("model_fits")
    if fits is not None and "hapke_aic" in fits:
        rough = fits[fits["truncation"] * fits["aspect"] > 0]
        ok = rough[["hapke_aic", "hapke_aic_constant", "rmse_hapke_heldout", "rmse_constant_heldout"]].dropna()
        if len(ok):
            out["hapke"] = {"n": len(ok), "by_aic": int((ok["hapke_aic"] < ok["hapke_aic_constant"]).sum()),
                            "held": int((ok["rmse_hapke_heldout"] < ok["rmse_constant_heldout"]).sum())}
    if fits is not None and "sigma_fitted_at_bound" in fits:
        rough = fits[fits["truncation"] * fits["aspect"] > 0]
        n_bound = int(rough["sigma_fitted_at_bound"].sum())
        if n_bound:
            out["sigma_bound"] = {"n_bound": n_bound, "n_rough": len(rough)}
    msum = frame_or_none(tables.get("model_fits_summary"))
    if msum is not None:
        out.update(findings=_model_findings(msum), summary_all=msum[msum["band"] == "all"],
                   summary_bands=msum[msum["band"] != "all"])
    return out


def models_section_html(tables: dict, figures: dict, provenance: dict) -> str:
    """The report's section: analytic models (its HTML)."""
    return render("models.html", s=models_section(tables, figures, provenance))


def regressions_section(tables: dict) -> dict:
    """The regressions' part of "Where methods fail": the GLMs' status, the Tables 1-2 rows with a note."""
    summary = tables.get("glm_summary")
    if summary is not None and len(summary):
        summary = summary[[c for c in ("response", "n", "terms", "dropped", "converged", "condition_scaled", "status")
                           if c in summary.columns]]
    else:
        summary = None
    noted = None
    thesis = tables.get("thesis_tables")
    if thesis is not None and len(thesis) and "note" in thesis:
        noted = thesis[(thesis["source"] != "thesis 2001") & (thesis["note"].fillna("") != "")]
        noted = noted[[c for c in ("table", "aspect_label", "model", "source", "n", "converged", "note") if c in noted]]
    return {"summary": summary, "messages": tables.get("glm_messages") or [], "noted": noted,
            "bootstrap": frame_or_none(tables.get("bootstrap_tables")) is not None}


def regression_failures_html(tables: dict) -> str:
    """The regressions' part of "Where methods fail": every fit that could not be made as asked.

    Lists the grid GLMs' status with what was kept out (zero-variance terms,
    near-collinear terms, the plate surfaces) and the reason, the Tables 1-2
    rows (ours and on exact peaks) whose regression line was not fitted or is
    exact, and points to the bootstrap intervals. ``tables`` as
    :func:`roughlight.report.page.build_report` (``glm_summary``, ``glm_messages``, ``thesis_tables``,
    ``bootstrap_tables``); missing ones are said to be missing.
    """
    return render("regressions.html", s=regressions_section(tables))


def _plain(obj):
    """Config values as plain YAML-safe types (Snakemake's Namedlist/dict subclasses)."""
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    return obj


def benchmarks_data(benchmarks: dict | None) -> dict | None:
    """The speed/accuracy part of the provenance (None: switched off)."""
    if not (benchmarks and (benchmarks.get("png") or benchmarks.get("table") is not None)):
        return None
    validation = benchmarks.get("validation")
    return {"png": existing(benchmarks.get("png")), "table": benchmarks.get("table"),
            "validation": None if validation is None else renderer_validation_data(
                validation, benchmarks.get("smoothness"), benchmarks.get("validation_png"), benchmarks.get("tiles"))}


def provenance_section(tables: dict, figures: dict, config, provenance: dict, benchmarks, versions: dict) -> dict:
    """"Settings and provenance": timings, the speed/accuracy benchmark with its "Accuracy at every view",
    settings and configuration as YAML, package versions (``versions``), inputs."""
    import yaml

    timings = frame_or_none(tables.get("timings"))
    if timings is not None:
        timings = timings.copy()
        timings["aspect"] = timings["aspect"].map(aspect_label)
    settings, inputs = provenance.get("settings"), provenance.get("inputs")
    return {
        "timings_summary": tables.get("timings_summary") or {}, "timings": timings,
        "figures": section_figures("provenance", figures), "benchmarks": benchmarks_data(benchmarks),
        "settings": yaml.safe_dump(settings, sort_keys=False) if settings else None,
        "config": yaml.safe_dump(_plain(config), sort_keys=False) if config else None,
        "versions": pd.DataFrame(sorted(versions.items()), columns=["package", "version"]),
        "inputs": pd.DataFrame(inputs) if inputs else None,
    }
