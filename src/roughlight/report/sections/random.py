"""The page's "Random roughness": the random ensembles against the regular surface, the rectangular-lobe claim's
design and verdict, the analytic models refitted, the seeds needed and the random tiles' benchmark
(``templates/random.html``); on when ``surface.kind`` lists a random kind."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...study.config import random_surfaces
from ..page_templates import caption_text, existing, frame_or_none
from ..registry import Section

# ---------------------------------------------------------------------------
# random roughness

#: The analytic models compared on random tiles, by component: (column, name in the text).
RANDOM_MODELS = {
    "diffuse": (("rmse_lambert", "Lambert (the plate)"), ("rmse_oren_nayar", "Oren–Nayar, geometric σ"),
                ("rmse_oren_nayar_fitted", "Oren–Nayar, fitted σ"), ("rmse_facet_vcavity_diffuse", "V-cavity facets"),
                ("rmse_regular_diffuse", "the regular surface (implicit exact form)")),
    "specular": (("rmse_phong_plate", "Phong on the plate"), ("rmse_facet_nomask_specular", "facets, no masking"),
                 ("rmse_facet_vcavity_specular", "V-cavity facets"),
                 ("rmse_regular_specular", "the regular surface (implicit exact form)")),
}


def _interval(mean: float, low: float, high: float) -> str:
    """``mean [low, high]`` to 3 significant figures; the mean alone, or "–", where there is no interval."""
    if np.isfinite(low):
        return f"{mean:.3g} [{low:.3g}, {high:.3g}]"
    return f"{mean:.3g}" if np.isfinite(mean) else "–"


def random_claim_rows(claims: pd.DataFrame) -> pd.DataFrame:
    """The thesis's random-roughness claim as the page shows it: one row per random kind, grid point and test of
    rule ``analysis_random``'s verdict (:func:`roughlight.analysis.claims.claim_table`): the regular value and the
    margin, the tested seeds' mean with its interval at the family's level, how many seeds were tested and had a
    measurable lobe, what became of the rest, the verdict and why, and the seeds the pilot planned."""
    rows = []
    for _, r in claims.iterrows():
        rows.append({"kind": r["kind"].replace("_", " "), "truncation": r["truncation"], "aspect": r["aspect"],
                     "incidence": r["incidence"], "test": claim_test_label(r["test"]), "regular": r["regular"],
                     "margin": r["margin"], "random mean [interval]": _interval(r["mean"], r["low"], r["high"]),
                     "tested": int(r["seeds"]), "measurable": int(r["measurable"]),
                     "left out": r["left_out"] if isinstance(r["left_out"], str) else "",
                     "verdict": r["verdict"], "why": r["why"], "pilot plan": r["seeds_needed"]})
    return pd.DataFrame(rows)


def claim_test_label(statistic: str) -> str:
    """A claim test's name as the page shows it: ``back_phase_shift`` -> ``phase shift``."""
    return statistic.replace("back_", "").replace("_", " ")


def _claim_tests(margins: pd.DataFrame | None) -> list[dict]:
    """Each test of the claim: its name, the claim it puts, what its statistic shows, its margin and where the
    margin comes from (rule ``analysis_random``'s margins table; None: not given)."""
    from ...analysis.claims import CLAIMS

    margin = margins.set_index("statistic") if margins is not None else None
    out = []
    for name, rule in CLAIMS.items():
        row = margin.loc[name] if margin is not None and name in margin.index else None
        out.append({"test": claim_test_label(name), "claim": rule["claim"], "shows": rule["shows"],
                    "unit": rule["unit"], "margin": None if row is None else float(row["margin"]),
                    "from": None if row is None else str(row["from"]),
                    "noise": None if row is None else float(row["rendering_noise"]),
                    "floor": None if row is None else float(row["floor_effect"])})
    return out


def claim_design_rows(design: pd.DataFrame) -> pd.DataFrame:
    """The claim's design as the page shows it: a test a row, the pilot seeds' numbers and the seeds they plan,
    beside the seeds the config tests (rule ``analysis_random``, :func:`roughlight.analysis.claims.claim_design`)."""
    rows = []
    for _, r in design.iterrows():
        rows.append({"kind": r["kind"].replace("_", " "), "truncation": r["truncation"], "aspect": r["aspect"],
                     "test": claim_test_label(r["test"]), "pilot seeds": int(r["pilot_seeds"]),
                     "measurable": int(r["pilot_measurable"]), "pilot mean": r["pilot_mean"], "pilot SD": r["pilot_sd"],
                     "seeds planned": r["seeds_needed"], "plan": r["plan"], "seeds tested": int(r["seeds_configured"])})
    return pd.DataFrame(rows)


def _claim_family(design: pd.DataFrame | None) -> dict | None:
    """The family's size and each interval's level (from the design table), None when not given."""
    if design is None or design.empty:
        return None
    return {"tests": int(design["family"].iloc[0]), "level": float(design["level"].iloc[0]),
            "alpha": round(float((1 - design["level"].iloc[0]) * design["family"].iloc[0]), 6)}


def _best_models(fits: pd.DataFrame) -> list[dict]:
    """Per kind and component: the analytic model with the lowest mean RMSE over its grid points, and every one's."""
    items = []
    for kind, g in fits.groupby("kind", sort=False):
        for component, models in RANDOM_MODELS.items():
            present = [(c, name) for c, name in models if c in g and not (kind == "pyramids" and "regular" in c)]
            if not present:
                continue
            means = {name: float(g[c].mean()) for c, name in present}
            items.append({"kind": kind, "component": component, "model": min(means, key=means.get),
                          "means": sorted(means.items(), key=lambda kv: kv[1])})
    return items


def _random_tiles(accuracy, convergence, tiles_png) -> dict:
    """The random tiles' benchmark: the fast renderer against the exact reference, tile-size convergence."""
    from ...measurements.random_tiles import convergence_summary

    convergence = frame_or_none(convergence)
    tiles_png = existing(tiles_png)
    return {"accuracy": frame_or_none(accuracy),
            "convergence": convergence_summary(convergence) if convergence is not None else None,
            "tiles_png": tiles_png, "tiles_caption": caption_text("random_tiles") if tiles_png else None}


def random_data(random_ensembles: pd.DataFrame | None = None, random_seeds_needed: pd.DataFrame | None = None,
                random_model_fits: pd.DataFrame | None = None, random_ensembles_png=None, random_maps_png=None,
                surface_settings: dict | None = None, random_accuracy: pd.DataFrame | None = None,
                tile_convergence: pd.DataFrame | None = None, random_tiles_png=None, plan: str = "full",
                random_claims: pd.DataFrame | None = None, random_claim_design: pd.DataFrame | None = None,
                random_claim_margins: pd.DataFrame | None = None, random_claim_floor: pd.DataFrame | None = None
                ) -> dict | None:
    """"Random roughness" (ensembles against the regular surface, the claim's design and verdict, the analytic
    models refitted, seeds needed, the random tiles' benchmark), from rule ``analysis_random``'s outputs and rule
    ``random_tiles``'; None: no random kind measured."""
    ensembles, seeds_needed, model_fits = random_ensembles, random_seeds_needed, random_model_fits
    if ensembles is None:
        return None
    charts = [(f"fig-{stem.replace('_', '-')}", png, alt, caption_text(stem))
              for png, stem, alt in ((random_ensembles_png, "random_ensembles", "ensembles"),
                                     (random_maps_png, "random_maps", "maps"))
              if existing(png)]
    shown = ensembles[[c for c in ("kind", "truncation", "aspect", "incidence", "statistic", "unit", "seeds", "mean",
                                   "boot_low", "boot_high", "regular", "difference", "pooled") if c in ensembles]]
    keys = ["kind", "truncation", "aspect", "incidence"]
    rmse = [c for c in model_fits.columns if c.startswith("rmse_")]
    fits = model_fits.groupby(keys, as_index=False)[rmse].mean()
    # two tables, to fit the page's width: the diffuse and specular models, then Hapke's surge near opposition
    modelled = {c for models in RANDOM_MODELS.values() for c, _ in models}
    opposition = [c for c in rmse if c not in modelled]
    needed = [c for c in seeds_needed.columns if c.startswith("seeds_for_")]
    return {
        "settings": surface_settings or {}, "tests": _claim_tests(frame_or_none(random_claim_margins)),
        "claim": random_claim_rows(random_claims) if frame_or_none(random_claims) is not None else None,
        "design": (claim_design_rows(random_claim_design) if frame_or_none(random_claim_design) is not None
                   else None),
        "family": _claim_family(frame_or_none(random_claim_design)),
        "floor": frame_or_none(random_claim_floor), "charts": charts, "shown": shown, "best": _best_models(fits),
        "fits": fits[keys + [c for c in rmse if c in modelled]],
        "opposition": fits[keys + opposition] if opposition else None,
        "seeds": seeds_needed[keys + ["statistic", "mean", "sd"] + needed],
        "plan": plan, **_random_tiles(random_accuracy, tile_convergence, random_tiles_png)}


SECTION = Section("random", random_data, "random.html", title="Random roughness", switch=random_surfaces,
                  inputs={"random_ensembles": "results/analysis/random_ensembles.csv",
                          "random_claims": "results/analysis/random_claims.csv",
                          "random_claim_design": "results/analysis/random_claim_design.csv",
                          "random_claim_margins": "results/analysis/random_claim_margins.csv",
                          "random_claim_floor": "results/analysis/random_claim_floor.csv",
                          "random_seeds_needed": "results/analysis/random_seeds_needed.csv",
                          "random_model_fits": "results/analysis/random_model_fits.parquet",
                          "random_ensembles_png": "results/figures/random_ensembles.png",
                          "random_maps_png": "results/figures/random_maps.png",
                          "random_accuracy": "results/benchmarks/{plan}/random_accuracy.parquet",
                          "tile_convergence": "results/benchmarks/{plan}/tile_convergence.parquet",
                          "random_tiles_png": "results/benchmarks/{plan}/random_tiles.png"})
