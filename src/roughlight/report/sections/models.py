"""The page's "Analytic models": Hapke against its background, Oren–Nayar's σ on a bound, the model that fits best a
band (``templates/models.html``)."""

from __future__ import annotations

import pandas as pd

from ..page_templates import frame_or_none, section_figures
from ..registry import Section, figures


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


SECTION = Section("models", models_section, "models.html", title="Analytic models",
                  inputs={"model_fits": "results/analysis/model_fits.parquet",
                          "model_fits_summary": "results/analysis/model_fits_summary.csv",
                          "figures": tuple(f.path for f in figures(section="models"))})
