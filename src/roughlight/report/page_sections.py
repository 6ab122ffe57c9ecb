"""The data of the page's sections from the analysis tables: the study, the figure sections, the lobes, the GLMs,
the analytic models, the regressions' failures and the provenance (``templates/<section>.html`` each).

A function here picks rows and columns and counts; what the page says about them is in its template. Each section's
function takes its inputs by their names (:data:`roughlight.report.registry.SECTIONS`): the analysis outputs by
their files' stems, ``figures`` (stem -> PNG path) and the settings.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import importlib.metadata
import platform
from pathlib import Path

import numpy as np
import pandas as pd

from ..analysis.thesis import TABLE_ASPECTS
from ..study.selection import SURFACE_KEYS, find_aspect
from ..surfaces.surface import aspect_label
from .page_measurements import renderer_validation_data
from .page_templates import existing, frame_or_none, section_figures

#: The columns of the exact lobe peaks shown beside the measured lobes: the two specular-shadow protocols.
PROTOCOLS = ["exact_fwhm", "exact_peak_no_specular_shadows", "exact_fwhm_no_specular_shadows"]


def study_section(study_summary: dict | None = None, table_aspects=TABLE_ASPECTS, followed=()) -> dict:
    """"The study": the summary, the table aspects the study lacks, the notes (``study_summary``: what rule
    ``analysis_tables`` writes, ``study``, ``timings`` and ``messages``)."""
    study = (study_summary or {}).get("study") or {}
    messages = list((study_summary or {}).get("messages") or [])
    missing = [a for a in table_aspects if find_aspect(study.get("aspects", []), a) is None] if study else []
    return {"study": study, "followed": list(followed), "missing": missing, "messages": messages}


def figure_section(section: str, figures: dict | None = None) -> dict:
    """A figure section of the page (specular, diffuse, pictures): its registry figures."""
    return {"section": section, "figures": section_figures(section, figures or {})}


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


def _at_table_aspects(frame: pd.DataFrame, table_aspects) -> pd.DataFrame:
    want = [find_aspect(frame["aspect"], a) for a in table_aspects]
    return frame[frame["aspect"].isin([a for a in want if a is not None])]


def lobes_section(lobes_arc: pd.DataFrame | None = None, lobes_hemisphere: pd.DataFrame | None = None,
                  exact_peaks: pd.DataFrame | None = None, figures: dict | None = None,
                  table_aspects=TABLE_ASPECTS) -> dict:
    """"Lobes": the arc lobes at the table aspects (with the exact widths of both protocols), the hemisphere's."""
    out = {"figures": section_figures("lobes", figures or {}), "arc": None, "protocols": False, "hemisphere": None}
    lobes, exact, hemi = lobes_arc, exact_peaks, lobes_hemisphere
    if lobes is not None and len(lobes):
        sel = _at_table_aspects(lobes, table_aspects)
        sel = sel[sel["lobe"].isin(["forward", "back"])].copy()
        sel["aspect"] = sel["aspect"].map(aspect_label)
        cols = ["truncation", "aspect", "incidence", "lobe", "predicted", "peak", "peak_elevation", "centroid",
                "fwhm", "phase_at_peak", "note"]
        if exact is not None and len(exact) and all(c in exact for c in PROTOCOLS):
            ex = exact[SURFACE_KEYS + ["lobe"] + PROTOCOLS].copy()
            ex["aspect"] = ex["aspect"].map(aspect_label)
            sel = sel.merge(ex, on=SURFACE_KEYS + ["lobe"], how="left")
            cols = cols[:-1] + PROTOCOLS + ["note"]
            out["protocols"] = True
        out["arc"] = sel[cols]
    if hemi is not None and len(hemi):
        sel = _at_table_aspects(hemi, table_aspects).copy()
        sel["aspect"] = sel["aspect"].map(aspect_label)
        out["hemisphere"] = sel
    return out


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


def models_section(model_fits: pd.DataFrame | None = None, model_fits_summary: pd.DataFrame | None = None,
                   figures: dict | None = None, provenance: dict | None = None) -> dict:
    """"Analytic rough-surface models": Hapke against its background, Oren–Nayar's σ on a bound, the best models."""
    out = {"hapke_max_phase": ((provenance or {}).get("settings") or {}).get("hapke_max_phase", 60), "hapke": None,
           "sigma_bound": None, "findings": [], "summary_all": None, "summary_bands": None,
           "figures": section_figures("models", figures or {})}
    fits = model_fits
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
    msum = frame_or_none(model_fits_summary)
    if msum is not None:
        out.update(findings=_model_findings(msum), summary_all=msum[msum["band"] == "all"],
                   summary_bands=msum[msum["band"] != "all"])
    return out


def regressions_section(glm_summary: pd.DataFrame | None = None, glm_messages: list | None = None,
                        thesis_tables: pd.DataFrame | None = None,
                        thesis_tables_bootstrap: pd.DataFrame | None = None) -> dict:
    """The regressions' part of "Where methods fail": the GLMs' status, the Tables 1-2 rows with a note."""
    summary = glm_summary
    if summary is not None and len(summary):
        summary = summary[[c for c in ("response", "n", "terms", "dropped", "converged", "condition_scaled", "status")
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


def _plain(obj):
    """Config values as plain YAML-safe types (Snakemake's Namedlist/dict subclasses)."""
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    return obj


def package_versions(names=("roughlight", "numpy", "pandas", "pyarrow", "scipy", "statsmodels", "matplotlib",
                            "seaborn", "shapely", "trimesh", "pyrender2", "PyOpenGL", "snakemake")) -> dict:
    """Installed versions of the packages the study uses (missing ones are 'not installed')."""
    out = {"python": platform.python_version()}
    for name in names:
        try:
            out[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def file_provenance(path) -> dict:
    """Size, modification time and SHA-256 of a file."""
    p = Path(path)
    h = hashlib.sha256()
    with open(p, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    st = p.stat()
    return {"path": str(path), "bytes": st.st_size,
            "modified": _dt.datetime.fromtimestamp(st.st_mtime, _dt.UTC).isoformat(timespec="seconds"),
            "sha256": h.hexdigest()}


def benchmarks_data(speed_accuracy: pd.DataFrame | None = None, speed_accuracy_png=None,
                    renderer_validation: pd.DataFrame | None = None, arc_smoothness: pd.DataFrame | None = None,
                    renderer_validation_png=None, random_accuracy: pd.DataFrame | None = None) -> dict | None:
    """The speed/accuracy part of the provenance, with "Accuracy at every view" (None: switched off): the
    benchmark's table and chart, the renderer's validation, its arc curves and chart, the random tiles'."""
    if not (speed_accuracy_png or speed_accuracy is not None):
        return None
    return {"png": existing(speed_accuracy_png), "table": speed_accuracy,
            "validation": None if renderer_validation is None else renderer_validation_data(
                renderer_validation, arc_smoothness, renderer_validation_png, random_accuracy)}


def provenance_section(render_timings: pd.DataFrame | None = None, study_summary: dict | None = None,
                       figures: dict | None = None, config=None, provenance: dict | None = None,
                       speed_accuracy: pd.DataFrame | None = None, speed_accuracy_png=None,
                       renderer_validation: pd.DataFrame | None = None, arc_smoothness: pd.DataFrame | None = None,
                       renderer_validation_png=None, random_accuracy: pd.DataFrame | None = None) -> dict:
    """"Settings and provenance": timings, the speed/accuracy benchmark with its "Accuracy at every view"
    (:func:`benchmarks_data`), settings and configuration as YAML, package versions (``provenance["versions"]``,
    else those installed), inputs, and what the sweeps were rendered on (``provenance["renderers"]``: the GL
    renderer, OpenGL version and platform of each, :func:`roughlight.study.tables.renderers`)."""
    import yaml

    provenance = provenance or {}
    timings = frame_or_none(render_timings)
    if timings is not None:
        timings = timings.copy()
        timings["aspect"] = timings["aspect"].map(aspect_label)
    settings, inputs = provenance.get("settings"), provenance.get("inputs")
    versions = provenance.get("versions") or package_versions()
    benchmarks = benchmarks_data(speed_accuracy, speed_accuracy_png, renderer_validation, arc_smoothness,
                                 renderer_validation_png, random_accuracy)
    return {
        "timings_summary": (study_summary or {}).get("timings") or {}, "timings": timings,
        "figures": section_figures("provenance", figures or {}), "benchmarks": benchmarks,
        "settings": yaml.safe_dump(settings, sort_keys=False) if settings else None,
        "config": yaml.safe_dump(_plain(config), sort_keys=False) if config else None,
        "versions": pd.DataFrame(sorted(versions.items()), columns=["package", "version"]),
        "inputs": pd.DataFrame(inputs) if inputs else None,
        "renderers": list(provenance.get("renderers") or []),
    }
