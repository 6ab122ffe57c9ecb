"""The workflow's analysis steps as functions over tables: what each analysis rule computes, without its files.

Each function takes the tables a rule reads and its settings, and returns the tables it writes, keyed by the
rule's output names (``workflow/rules/report.smk``), which are the stems of the files they are written to; the
rule's script only reads, calls and writes. Tests chain them in memory to build the whole report for any grid.
"""

from __future__ import annotations

import pandas as pd

from ..render.shading import Lighting
from ..study import config as rl_config
from ..study.selection import SURFACE_KEYS, find_aspect
from ..study.tables import study_summary
from . import claims as C
from .areas import reflecting_areas
from .claim_instrument import grid_table, instrument_errors, reference_stacks
from .claim_readings import READINGS, lobe_centres, pooled_readings
from .diffuse import diffuse_levels, diffuse_three_part
from .glm import grid_glms
from .lobes import arc_lobes, hemisphere_lobes
from .share_laws import share_law_fits
from .surface_models import analytic_model_fits, model_fit_summary
from .thesis import (
    bootstrap_tables,
    exact_lobe_peaks,
    implied_scales,
    sine_refits,
    tables_at_implied_scale,
    thesis_tables,
)
from .timings import render_timings

__all__ = ["analysis_tables", "analysis_glm", "analysis_models", "analysis_random", "claim_discs", "claim_tables"]


def analysis_tables(study: pd.DataFrame, settings: dict, lighting: dict, log=print) -> tuple[dict, dict]:
    """The regular surface's study -> lobes, diffuse parts and levels, Tables 1-2 and their refits, timings.

    Parameters
    ----------
    study : the regular surface's rows of ``results/study.parquet``
    settings : the ``report:`` section (:func:`roughlight.study.config.report_settings`)
    lighting : :class:`roughlight.render.shading.Lighting` fields

    Returns
    -------
    (tables, study_summary): DataFrames keyed by the rule's output names; the JSON summary (study, timings,
    messages).
    """
    light = Lighting(**lighting)
    aspects, incidence = settings["table_aspects"], float(settings["table_incidence"])
    m = light.light * light.specular_reflectance
    halfwidth = float(settings["lobe_halfwidth"])
    out, messages = {}, []
    lobes = out["lobes_arc"] = arc_lobes(study, max_halfwidth=halfwidth)
    out["lobes_hemisphere"] = hemisphere_lobes(study, max_angle=halfwidth)
    log(f"lobes: {len(lobes)} arc lobes")
    out["diffuse_three_part"] = diffuse_three_part(study)
    out["diffuse_levels"] = diffuse_levels(study)
    if settings["exact_check"]:
        exact = exact_lobe_peaks(lobes, aspects, incidence, light)
        if len(exact):
            log(f"exact peaks: {len(exact)}; max |measured - exact| = {exact['error'].abs().max():.3f}")
    else:
        exact = pd.DataFrame(columns=SURFACE_KEYS + ["lobe", "peak", "exact_peak", "exact_peak_elevation", "error"])
        messages.append("the exact-reference check of the lobe peaks is switched off (report.exact_check)")
    out["exact_peaks"] = exact
    tables, table_messages = thesis_tables(lobes, aspects, incidence, m=m, k=None, exact=exact if len(exact) else None)
    messages += table_messages
    out["thesis_tables"] = tables
    out["thesis_tables_bootstrap"] = bootstrap_tables(lobes, aspects, incidence, m=m)
    out["sine_refits"] = sine_refits(lobes, aspects, incidence, m=m)
    out["implied_scales"] = implied_scales()
    out["tables_at_implied_scale"] = tables_at_implied_scale(lobes, aspects, incidence)
    out["reflecting_areas"] = _reflecting_areas(study, aspects, incidence)
    per_sweep, timing_summary = render_timings(study)
    out["render_timings"] = per_sweep
    for msg in table_messages:
        log(msg)
    return out, {"study": study_summary(study), "timings": timing_summary, "messages": messages}


def _reflecting_areas(study: pd.DataFrame, aspects, incidence: float) -> pd.DataFrame:
    """Fig. 24's reflecting areas at each table aspect the study has."""
    areas = []
    for wanted in aspects:
        found = find_aspect(study["aspect"], wanted)
        if found is not None:
            frame = reflecting_areas(found, incidence)
            frame.insert(0, "aspect", found)
            areas.append(frame)
    return pd.concat(areas, ignore_index=True) if areas else pd.DataFrame()


def analysis_glm(lobes: pd.DataFrame, levels: pd.DataFrame, settings: dict, lighting: dict) -> tuple[dict, list]:
    """Lobe peaks and diffuse levels -> the grid GLMs, their diagnostics and the share laws.

    Returns
    -------
    (tables, messages): DataFrames keyed by the rule's output names; what could not be fitted and why.
    """
    summary, coefficients, diagnostics, messages = grid_glms(
        lobes, levels, collinearity_limit=float(settings["collinearity_limit"]))
    light = Lighting(**lighting)
    laws = share_law_fits(lobes, m=light.light * light.specular_reflectance)
    return {"glm_summary": summary, "glm_coefficients": coefficients, "glm_diagnostics": diagnostics,
            "share_laws": laws}, messages


def analysis_models(study: pd.DataFrame, settings: dict, lighting: dict) -> dict:
    """The regular surface's study -> each analytic model fitted to each surface, and the best by band."""
    fits = analytic_model_fits(study, lighting=lighting, hapke_max_phase=float(settings["hapke_max_phase"]))
    return {"model_fits": fits, "model_fits_summary": model_fit_summary(fits)}


def analysis_random(study: pd.DataFrame, settings: dict, lighting: dict, claims: dict | None = None,
                    discs: dict | None = None, elevation_step: float = 1.0) -> dict:
    """The whole study (random tiles and the regular surface) -> per-tile statistics, the ensembles against the
    regular surface, the seeds each comparison needs, the models refitted to every tile, and the random-roughness
    claim's design and verdict.

    Parameters
    ----------
    claims : :func:`roughlight.study.config.claim_settings` (its defaults when None)
    discs : rule ``claim_discs``' ``geometry`` and ``radii`` and rule ``claim_grid``'s ``grid`` (None: computed
        here from the study, with no claim grid)
    """
    from . import ensembles as E

    claims = {"tested": [], **rl_config.claims({"claims": claims or {}})}
    halfwidth, min_peak = float(settings["lobe_halfwidth"]), float(claims["min_peak"])
    stats = E.seed_statistics(study, lobe_halfwidth=halfwidth, min_peak=min_peak)
    summary = E.ensemble_summary(stats, pooled=E.pooled_statistics(study, halfwidth, min_peak))
    fits = E.ensemble_model_fits(study, lighting=lighting, hapke_max_phase=float(settings["hapke_max_phase"]))
    if discs is None:
        found = claim_discs(study, lighting)
        discs = {"geometry": found["random_claim_geometry"], "radii": found["random_claim_radii"], "grid": None}
    design = claim_tables(study, discs["radii"], discs["geometry"], discs.get("grid"), claims, elevation_step)
    return {"random_statistics": stats, "random_ensembles": summary, "random_seeds_needed": E.seeds_needed(summary),
            "random_model_fits": fits, **design}


def claim_discs(study: pd.DataFrame, lighting: dict) -> dict:
    """Which lobes enter the claim and how far each kind's are looked for, from geometry, the regular surfaces and
    the pilot seeds (rule ``claim_discs``; no tested seed is read).

    Returns
    -------
    dict of DataFrames: ``random_claim_geometry`` (:func:`roughlight.analysis.claims.claim_geometry`),
    ``random_claim_radii`` (:func:`roughlight.analysis.claims.search_radii`).
    """
    kinds = study["kind"].astype(str)
    ensembles = {(str(k), float(t), float(a), float(i))
                 for k, t, a, i in study.loc[kinds != "pyramids", ["kind"] + SURFACE_KEYS].drop_duplicates()
                 .itertuples(index=False)}
    regular, pilots, _ = C.split_stacks(study[C.is_pilot(study["seed"].to_numpy()) | (kinds == "pyramids")])
    geometry = C.claim_geometry(list(regular.values()), lighting)
    return {"random_claim_geometry": geometry, "random_claim_radii": C.search_radii(geometry, pilots, ensembles)}


def claim_tables(study: pd.DataFrame, radii: pd.DataFrame, geometry: pd.DataFrame, reference: pd.DataFrame | None,
                 claims: dict, elevation_step: float = 1.0) -> dict:
    """The claim's design and verdict as the tables rule ``analysis_random`` writes.

    Parameters
    ----------
    study : the study's rows at the random grid points (the regular surface's among them, pilot seeds included)
    radii, geometry : rule ``claim_discs``' tables
    reference : rule ``claim_grid``'s measurements (None: none; the margins go without the sampling error and the
        grid's effect)
    claims : :func:`roughlight.study.config.claim_settings` (``alpha``, ``max_seeds``, ``tested``)

    Returns
    -------
    dict of DataFrames: ``random_claim_margins``, ``random_claim_design`` and ``random_claims``
    (:mod:`roughlight.analysis.claims`' margins, design and verdict), ``random_claim_grid`` and ``random_claim_errors``
    (:mod:`roughlight.analysis.claim_instrument`).
    """
    regular, pilots, tested = C.split_stacks(study)
    ref = reference_stacks(reference, elevation_step) if reference is not None and len(reference) else {}
    errors = instrument_errors(ref, geometry)
    margin_table = C.margins(regular, radii, errors)
    pilot_readings = {key: pooled_readings(stack, lobe_centres(key[1:]), C.disc_of(radii, key[0], key[1:]))
                      for key, stack in pilots.items()}
    configured = {(kind, float(t), float(a)): int(n) for kind, t, a, n in claims.get("tested", [])}
    design = C.claim_design(margin_table, pilot_readings, claims, configured)
    if int(claims.get("pilot_seeds", 0)) == 0:
        design["plan"] = "no pilot seeds (claims.pilot_seeds 0): no plan"
    readings = {key + (reading,): pooled_readings(stack, lobe_centres(key[1:]), C.disc_of(radii, key[0], key[1:]),
                                                  reading)
                for key, stack in tested.items() for reading in READINGS}
    return {"random_claim_margins": margin_table, "random_claim_design": design, "random_claim_errors": errors,
            "random_claims": C.claim_table(readings, design, margin_table), "random_claim_grid": grid_table(ref, geometry)}
