"""The page's "Random roughness": the random ensembles against the regular surface, the rectangular-lobe claim's
design and verdict, the analytic models refitted, the seeds needed and the random tiles' benchmark
(``templates/random.html``); on when ``surface.kind`` lists a random kind."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...analysis.direction_rounds import ROUNDS
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


def claim_test_label(test: str) -> str:
    """A claim test's name as the page shows it: ``back_phase_shift`` -> ``back lobe: phase shift``."""
    lobe, _, statistic = test.partition("_") if test.startswith("back_") else ("hot spot", "", test[9:])
    return f"{'back lobe' if lobe == 'back' else lobe}: {statistic.replace('_', ' ')}"


def random_claim_rows(claims: pd.DataFrame) -> pd.DataFrame:
    """The thesis's random-roughness claim as the page shows it: one row per random kind, grid point and test of
    rule ``analysis_random``'s verdict (:func:`roughlight.analysis.claims.claim_table`), its two readings side by
    side: the regular value and the margin, the tested seeds' mean with its interval at the family's level and
    the verdict, unrounded and at 8 bits, the seeds and why (unrounded)."""
    keys = ["kind", "truncation", "aspect", "incidence", "test"]
    rows = []
    for _, group in claims.groupby(keys, sort=False):
        by = {r["reading"]: r for _, r in group.iterrows()}
        first = by.get("unrounded", group.iloc[0])
        row = {"kind": first["kind"].replace("_", " "), "truncation": first["truncation"],
               "aspect": first["aspect"], "test": claim_test_label(first["test"]), "seeds": int(first["seeds"])}
        for reading, r in by.items():
            row[f"{reading}: regular"] = r["regular"]
            row[f"{reading}: margin"] = r["margin"]
            row[f"{reading}: random [interval]"] = _interval(r["mean"], r["low"], r["high"])
            row[f"{reading}: verdict"] = r["verdict"]
        row["why (unrounded)"] = first["why"]
        rows.append(row)
    return pd.DataFrame(rows)


def _claim_tests(margins: pd.DataFrame | None) -> list[dict]:
    """Each test of the claim: its lobe, what it asks and what its statistic shows, and its margins over the
    grid points (unrounded reading) with what set them most often (rule ``analysis_random``'s margins)."""
    from ...analysis.claims import TESTS

    out = []
    for name, rule in TESTS.items():
        part = None if margins is None else margins[(margins["test"] == name) & (margins["reading"] == "unrounded")]
        found = part is not None and len(part) and part["margin"].notna().any()
        out.append({"test": claim_test_label(name), "role": rule["role"], "claim": rule["claim"],
                    "shows": rule["shows"], "unit": rule["unit"],
                    "low": float(part["margin"].min()) if found else None,
                    "high": float(part["margin"].max()) if found else None,
                    "from": str(part["from"].mode().iloc[0]) if found else None})
    return out


def claim_design_rows(design: pd.DataFrame) -> pd.DataFrame:
    """The claim's design as the page shows it: a test a row, the pilot ensemble's mean and jackknife error, the
    seeds they plan and why, the ensemble's plan and the seeds the config tests (rule ``analysis_random``,
    :func:`roughlight.analysis.claims.claim_design`)."""
    rows = []
    for _, r in design.iterrows():
        rows.append({"kind": r["kind"].replace("_", " "), "truncation": r["truncation"], "aspect": r["aspect"],
                     "test": claim_test_label(r["test"]), "margin": r["margin"], "regular": r["regular"],
                     "pilot seeds": int(r["pilot_seeds"]), "pilot width": r["pilot_width"],
                     "pilot mean": r["pilot_mean"], "pilot SE": r["pilot_se"],
                     "seeds planned": r["seeds_needed"], "plan": r["plan"], "ensemble plan": int(r["ensemble_seeds"]),
                     "seeds tested": int(r["seeds_configured"])})
    return pd.DataFrame(rows)


def claim_geometry_rows(geometry: pd.DataFrame) -> pd.DataFrame:
    """Which lobes enter the claim (rule ``claim_discs``): each grid point's lobe, where its regular lobe lies,
    its width, its search disc, the room the horizon leaves, and whether it is in the claim (or why not)."""
    rows = []
    for _, g in geometry.iterrows():
        rows.append({"truncation": g["truncation"], "aspect": g["aspect"], "incidence": g["incidence"],
                     "lobe": "back lobe" if g["lobe"] == "back" else "hot spot",
                     "centre elevation": g["centre_elevation"], "regular width": g["width"], "disc": g["radius"],
                     "room": g["cap"], "in the claim": "yes" if g["in_claim"] else f"no: {g['why']}"})
    return pd.DataFrame(rows)


def claim_grid_rows(grid: pd.DataFrame) -> pd.DataFrame:
    """The regular lobes' statistics at each azimuth step (rule ``analysis_random``'s grid table), a statistic and
    method a row, the steps side by side."""
    if grid.empty:
        return grid
    wide = grid.pivot_table(index=["truncation", "aspect", "incidence", "statistic", "method"], columns="step",
                            values="value", aggfunc="first", sort=False)
    wide.columns = [f"{step:g}°" for step in wide.columns]
    wide = wide.reset_index()
    wide["statistic"] = wide["statistic"].map(claim_test_label)
    return wide


def _claim_family(design: pd.DataFrame | None) -> dict | None:
    """The family's size and each interval's level (from the design table), None when not given."""
    if design is None or design.empty:
        return None
    return {"tests": int(design["family"].iloc[0]), "level": float(design["level"].iloc[0]),
            "alpha": round(float((1 - design["level"].iloc[0]) * design["family"].iloc[0]), 6)}


def _claim_counts(claims: pd.DataFrame | None) -> dict:
    """How many tests reach each verdict, by reading."""
    if claims is None or claims.empty:
        return {}
    return {reading: part["verdict"].value_counts().to_dict() for reading, part in claims.groupby("reading")}


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


def _estimate(value: float, se: float, low: float, high: float) -> str:
    """``value ± se [low, high]`` to 3 significant figures; less where there is no error or interval, "–" where
    there is no value."""
    if not np.isfinite(value):
        return "–"
    if not np.isfinite(se):
        return f"{value:.3g}"
    interval = f" [{low:.3g}, {high:.3g}]" if np.isfinite(low) else ""
    return f"{value:.3g} ± {se:.2g}{interval}"


def convergence_rows(summary: pd.DataFrame) -> pd.DataFrame:
    """The tile-size convergence as the page shows it (rule ``random_tiles``,
    :func:`roughlight.measurements.random_tiles.convergence_summary`): a row per kind and statistic, the regular
    surface's value in the same discs, then at each tile size the mean surface's value ± its jackknife error over
    seeds [its 95% Student-t interval], and why a statistic could not be read where it could not; each kind's last
    row its views per second (the regular surface's beside it)."""
    cells = sorted(summary["cells"].unique())
    label = {c: f"{c} cell{'s' if c != 1 else ''}" for c in cells}
    rows = []
    for kind, part in summary.groupby("kind", sort=False):
        for name, g in part.groupby("statistic", sort=False):
            by = g.set_index("cells")
            row = {"kind": kind.replace("_", " "), "statistic": name.replace("_", " "), "unit": g["unit"].iloc[0],
                   "seeds": int(g["seeds"].max()), "regular": g["regular"].iloc[0]}
            for c in cells:
                r = by.loc[c] if c in by.index else None
                row[label[c]] = "" if r is None else _estimate(r["value"], r["se"], r["low"], r["high"])
            unread = g[g["why"] != ""]
            row["not read"] = "; ".join(f"{', '.join(str(c) for c in w['cells'])} cells: {why}"
                                        for why, w in unread.groupby("why", sort=False))
            rows.append(row)
        speed = part.drop_duplicates("cells").set_index("cells")
        rows.append({"kind": kind.replace("_", " "), "statistic": "views per second", "unit": "",
                     "seeds": int(part["seeds"].max()), "regular": speed["regular_views_per_second"].iloc[0],
                     **{label[c]: f"{speed.loc[c, 'views_per_second']:.0f}" if c in speed.index else ""
                        for c in cells}, "not read": ""})
    return pd.DataFrame(rows)


def convergence_shown(convergence: pd.DataFrame | None) -> tuple[pd.DataFrame | None, dict | None]:
    """Rule ``random_tiles``' ``tile_convergence.parquet`` as the page shows it: :func:`convergence_rows` of its
    summary and its point (truncation, aspect, incidence and each kind's discs); (None, None) without one, or for a
    table of the old design (per-seed statistics, before the claim's readings), which is not read."""
    from ...measurements.random_tiles import CONVERGENCE_COLUMNS, convergence_summary

    if convergence is None or not set(CONVERGENCE_COLUMNS) <= set(convergence.columns) or not len(convergence):
        return None, None
    first = convergence.iloc[0]
    discs = convergence[np.isfinite(convergence["radius"])].drop_duplicates(["discs", "lobe"])
    lobe = {"back": "back lobe", "hot_spot": "hot spot"}
    point = {"truncation": first["truncation"], "aspect": first["aspect"], "incidence": first["incidence"],
             "discs": [f"{kind.replace('_', ' ')}: " + ", ".join(f"{lobe.get(r['lobe'], r['lobe'])} {r['radius']:.1f}°"
                                                                  for _, r in d.iterrows())
                       for kind, d in discs.groupby("discs", sort=False)]}
    summary = convergence_summary(convergence)
    return (convergence_rows(summary) if len(summary) else None), point


def _random_tiles(accuracy, convergence, tiles_png) -> dict:
    """The random tiles' benchmark: the fast renderer against the exact reference, tile-size convergence (the
    claim's statistics of each kind's mean surface by tile size: :func:`convergence_shown`)."""
    tiles_png = existing(tiles_png)
    table, point = convergence_shown(frame_or_none(convergence))
    return {"accuracy": frame_or_none(accuracy), "convergence": table, "convergence_point": point,
            "tiles_png": tiles_png, "tiles_caption": caption_text("random_tiles") if tiles_png else None}


#: The later rounds' names, as the page says them: the third, and the rounds of the claim's direction.
ROUND_NAMES = {3: "third", **{number: spec["name"] for number, spec in ROUNDS.items()}}


def untaken_rounds(untaken: pd.DataFrame | None) -> list[dict]:
    """The registered rounds a verdict did not take (rule ``analysis_random``'s ``random_claims_untaken.csv``), as
    the page names them: the round, the ensemble and why."""
    rows = frame_or_none(untaken)
    return [] if rows is None else [
        {"round": ROUND_NAMES.get(int(r.round), str(r.round)),
         "ensemble": f"{str(r.kind).replace('_', ' ')} t {r.truncation:g}, a {r.aspect:g}", "why": str(r.why)}
        for r in rows.itertuples(index=False)]


def random_data(random_ensembles: pd.DataFrame | None = None, random_seeds_needed: pd.DataFrame | None = None,
                random_model_fits: pd.DataFrame | None = None, random_ensembles_png=None, random_maps_png=None,
                surface_settings: dict | None = None, random_accuracy: pd.DataFrame | None = None,
                tile_convergence: pd.DataFrame | None = None, random_tiles_png=None, plan: str = "full",
                random_claims: pd.DataFrame | None = None, random_claim_design: pd.DataFrame | None = None,
                random_claim_margins: pd.DataFrame | None = None, random_claim_geometry: pd.DataFrame | None = None,
                random_claim_grid: pd.DataFrame | None = None,
                random_claims_untaken: pd.DataFrame | None = None) -> dict | None:
    """"Random roughness" (ensembles against the regular surface, the claim's design and verdict, the analytic
    models refitted, seeds needed, the random tiles' benchmark), from rules ``claim_discs``, ``claim_design``,
    ``analysis_random`` and ``random_tiles``; None: no random kind measured."""
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
    claims, design = frame_or_none(random_claims), frame_or_none(random_claim_design)
    geometry, grid = frame_or_none(random_claim_geometry), frame_or_none(random_claim_grid)
    return {
        "settings": surface_settings or {}, "tests": _claim_tests(frame_or_none(random_claim_margins)),
        "claim": random_claim_rows(claims) if claims is not None else None, "counts": _claim_counts(claims),
        "untaken": untaken_rounds(random_claims_untaken),
        "design": claim_design_rows(design) if design is not None else None,
        "geometry": claim_geometry_rows(geometry) if geometry is not None else None,
        "grid": claim_grid_rows(grid) if grid is not None else None,
        "family": _claim_family(design), "charts": charts, "shown": shown, "best": _best_models(fits),
        "fits": fits[keys + [c for c in rmse if c in modelled]],
        "opposition": fits[keys + opposition] if opposition else None,
        "seeds": seeds_needed[keys + ["statistic", "mean", "sd"] + needed],
        "plan": plan, **_random_tiles(random_accuracy, tile_convergence, random_tiles_png)}


SECTION = Section("random", random_data, "random.html", title="Random roughness", switch=random_surfaces,
                  inputs={"random_ensembles": "results/analysis/random_ensembles.csv",
                          "random_claims": "results/analysis/random_claims.csv",
                          "random_claims_untaken": "results/analysis/random_claims_untaken.csv",
                          "random_claim_design": "results/analysis/random_claim_design.csv",
                          "random_claim_margins": "results/analysis/random_claim_margins.csv",
                          "random_claim_geometry": "results/analysis/random_claim_geometry.csv",
                          "random_claim_grid": "results/analysis/random_claim_grid.csv",
                          "random_seeds_needed": "results/analysis/random_seeds_needed.csv",
                          "random_model_fits": "results/analysis/random_model_fits.parquet",
                          "random_ensembles_png": "results/figures/random_ensembles.png",
                          "random_maps_png": "results/figures/random_maps.png",
                          "random_accuracy": "results/benchmarks/{plan}/random_accuracy.parquet",
                          "tile_convergence": "results/benchmarks/{plan}/tile_convergence.parquet",
                          "random_tiles_png": "results/benchmarks/{plan}/random_tiles.png"})
