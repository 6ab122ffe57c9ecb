"""The page's sections on the measurements (:mod:`roughlight.measurements`): "Where methods fail" (the stability
scans), "Accuracy at every view" (the renderer's validation), "An implicit rough surface" and "Random roughness".

Each section is a function from its inputs, named as the analysis outputs and the measurements' files are
(:data:`roughlight.report.registry.SECTIONS`: :func:`stability_data`, :func:`implicit_data`, :func:`random_data`), to
the data its template says (``templates/stability.html``, ``renderer_validation.html``, ``implicit.html`` and
``random.html``); it returns None when its inputs were not given (the section is switched off).
One section alone is rendered through the page's own path, :func:`roughlight.report.page.render_section`.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from .page_templates import caption_text, existing, frame_or_none, plain_text, render_macro

# ---------------------------------------------------------------------------
# the renderer at every view


def validation_line(validation: pd.DataFrame) -> dict:
    """The data of ``macros.html``'s ``validation_line``: per sampling setting, each component's worst view."""
    from ..measurements.renderer_validation import validation_summary

    summary = validation_summary(validation)
    if "setting" not in summary.columns:
        summary["setting"] = "configured"
    settings = []
    for setting, rows in summary.groupby("setting", sort=False):
        settings.append({"setting": setting, "views_per_second": rows["views_per_second"].iloc[0],
                         "rows": [{"component": r.component, "worst": r.worst, "p99": r.p99,
                                   "largest_mae": r.largest_mae} for r in rows.itertuples()]})
    return {"n_surfaces": len(validation[["truncation", "aspect", "incidence"]].drop_duplicates()),
            "views": int(validation["n_views"].max()), "settings": settings}


def renderer_validation_line(validation: pd.DataFrame) -> str:
    """One sentence (plain text): the default renderer's worst view, p99 and MAE against the exact reference."""
    return plain_text(render_macro("macros.html", "validation_line", validation_line(validation)))


def renderer_validation_data(validation: pd.DataFrame, smoothness: pd.DataFrame | None, png_path=None,
                             tiles: pd.DataFrame | None = None) -> dict:
    """The data of ``templates/renderer_validation.html``; ``tiles``: the random tiles against the exact reference
    (rule ``random_tiles``'s ``random_accuracy``), or None when no random kind is measured."""
    smoothness = frame_or_none(smoothness)
    worst = smoothness.sort_values("largest_deviation", ascending=False).iloc[0] if smoothness is not None else None
    return {"line": validation_line(validation), "png": existing(png_path), "validation": validation,
            "smoothness": smoothness, "worst": worst, "tiles": tile_accuracy(frame_or_none(tiles))}


def tile_accuracy(accuracy: pd.DataFrame | None) -> dict | None:
    """Per random kind: the tiles compared, their views, the worst view and the largest MAE over components."""
    if accuracy is None or "kind" not in accuracy:
        return None
    tiles = accuracy[accuracy["kind"] != "pyramids"]
    if tiles.empty:
        return None
    keys = [c for c in ("truncation", "aspect", "cells", "seed") if c in tiles]
    table = tiles.groupby("kind", sort=True).agg(
        tiles=("seed", lambda s: len(tiles.loc[s.index, keys].drop_duplicates())), views=("views", "sum"),
        refused=("reference_refused", "sum"), worst=("worst", "max"), largest_mae=("mae", "max")).reset_index()
    table["views"] = table["views"] // 3  # one row a component
    table["refused"] = table["refused"] // 3
    return {"table": table, "worst": float(tiles["worst"].max()), "largest_mae": float(tiles["mae"].max())}


# ---------------------------------------------------------------------------
# where methods fail


def stability_data(safe_domain: pd.DataFrame | None = None, stability: pd.DataFrame | None = None,
                   stability_png=None, plan: str = "full", renderer_validation: pd.DataFrame | None = None) -> dict | None:
    """"Where methods fail": the safe-domain table, the chart, what fails where (with the default renderer's worst
    view at every view when ``renderer_validation``, the frame of
    :func:`roughlight.measurements.renderer_validation.validate_renderer`, is given); None: switched off.

    Parameters
    ----------
    safe_domain : the frame of :func:`roughlight.measurements.stability.safe_domain`.
    stability : the long frame of the scans (for the clipping numbers and the normals), or None.
    stability_png : path of the PNG from :func:`roughlight.report.figures.plot_stability`.
    plan : the size the measurements ran at (:data:`roughlight.measurements.stability.PLANS`).
    """
    from ..measurements.stability import TOLERANCE, normals_table, plan_surfaces

    if safe_domain is None:
        return None
    surfaces_of = plan_surfaces(plan)
    safe = safe_domain if isinstance(safe_domain, pd.DataFrame) else pd.DataFrame(safe_domain)
    long = stability
    clipped = None
    if long is not None:
        cf = long[(long["experiment"] == "clipping") & (long["metric"] == "clipped_fraction")]
        clipped = list(zip(cf["setting"], cf["x"], cf["value"]))
    nt = normals_table(long) if long is not None else pd.DataFrame()
    normals = {"table": nt, "surfaces": [(s.truncation, s.aspect) for s, _ in surfaces_of["normals"]]} \
        if len(nt) else None
    line = validation_line(renderer_validation) \
        if renderer_validation is not None and len(renderer_validation) else None
    return {"plan": plan, "n_fast": len(surfaces_of["fast"]), "n_naive": len(surfaces_of["naive"]),
            "tolerance": TOLERANCE, "safe": safe, "png": stability_png, "clipped": clipped, "line": line,
            "normals": normals}


# ---------------------------------------------------------------------------
# an implicit rough surface


def implicit_data(implicit_validation: pd.DataFrame | None = None, implicit_frames: pd.DataFrame | None = None,
                  implicit_png=None, implicit_maps_png=None, plan: str = "full") -> dict | None:
    """"An implicit rough surface: the thesis's goal": the validation against the exact reference and the frame
    times (rule ``implicit_surface``), with their charts; None: switched off."""
    from ..measurements.implicit_surface import summary

    validation, frames = implicit_validation, implicit_frames
    if validation is None or frames is None:
        return None
    f = frames.groupby(["field", "method"], as_index=False).agg(
        triangles=("triangles", "first"), frame_ms=("frame_ms", "mean"), error=("error", "max"))
    explicit = f[f["method"] == "explicit"].set_index("field")["frame_ms"]
    f["speedup_vs_explicit"] = f["frame_ms"].rdiv(f["field"].map(explicit))
    png, maps_png = existing(implicit_png), existing(implicit_maps_png)
    return {"plan": plan, "n_surfaces": validation.groupby(["truncation", "aspect", "incidence"]).ngroups,
            "n_views": int(validation["n_views"].iloc[0]), "summary": summary(validation),
            "png": png, "caption": caption_text("implicit") if png else None,
            "maps_png": maps_png, "maps_caption": caption_text("implicit_maps") if maps_png else None, "frames": f}


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
    from ..analysis.claims import CLAIMS

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
    from ..measurements.random_tiles import convergence_summary

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
