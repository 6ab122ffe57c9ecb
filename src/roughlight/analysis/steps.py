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
from .claim_readings import READINGS, lobe_centres, pooled_readings, readings_table, table_readings
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

__all__ = ["analysis_tables", "analysis_glm", "analysis_models", "analysis_random", "claim_discs", "claim_design",
           "pilot_readings", "claim_verdict", "claim_tables"]


def analysis_tables(study: pd.DataFrame, settings: dict, lighting: dict, log=print) -> tuple[dict, dict]:
    """The regular surface's study -> lobes, diffuse parts and levels, Tables 1-2 and their refits, timings.

    Parameters
    ----------
    study : the regular surface's rows of ``results/study.parquet``
    settings : the ``report:`` section's ``table_aspects``, ``table_incidence``, ``lobe_halfwidth`` and
        ``exact_check`` (:func:`roughlight.study.config.report_settings`)
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
                    claim: dict | None = None) -> dict:
    """The study's random tiles and the regular surface -> per-tile statistics, the ensembles against the regular
    surface, the seeds each comparison needs, the models refitted to every tile, and, given ``claim``, the
    random-roughness claim's verdict.

    Parameters
    ----------
    claims : :func:`roughlight.study.config.claim_settings` (its defaults when None)
    claim : the claim's design and tested tiles (:func:`claim_verdict`'s ``rows``, ``geometry``, ``margins``,
        ``design`` and ``steps``), and optionally its registered later rounds (``third_round``:
        :func:`roughlight.analysis.third_round.read_registered`'s table; ``direction_rounds``: round number -> such
        a table, :func:`roughlight.analysis.direction_rounds.registered_rounds`; ``measured``: the run's
        :func:`roughlight.study.plan.claim_measurement`); None: no verdict. ``random_claims_round2`` is the second
        round's verdict, ``random_claims`` with the later rounds where they apply
        (:func:`roughlight.analysis.third_round.with_third_round`, then
        :func:`roughlight.analysis.direction_rounds.with_direction_rounds`), ``random_claims_untaken`` the
        registered rounds' ensembles it does not take, and why (both from
        :func:`roughlight.analysis.direction_rounds.later_rounds`)
    """
    from . import ensembles as E

    claims = {"tested": [], **rl_config.claims({"claims": claims or {}})}
    halfwidth, min_peak = float(settings["lobe_halfwidth"]), float(claims["min_peak"])
    stats = E.seed_statistics(study, lobe_halfwidth=halfwidth, min_peak=min_peak)
    summary = E.ensemble_summary(stats, pooled=E.pooled_statistics(study, halfwidth, min_peak))
    fits = E.ensemble_model_fits(study, lighting=lighting, hapke_max_phase=float(settings["hapke_max_phase"]))
    out = {"random_statistics": stats, "random_ensembles": summary, "random_seeds_needed": E.seeds_needed(summary),
           "random_model_fits": fits}
    if claim is not None:
        from .direction_rounds import later_rounds
        from .third_round import read_registered

        claim = dict(claim)
        third, later = claim.pop("third_round", None), claim.pop("direction_rounds", None) or {}
        third = third if third is not None else read_registered(None)
        measured = claim.pop("measured", None) or {}
        out["random_claims_round2"] = claim_verdict(**claim)
        out["random_claims"], out["random_claims_untaken"] = later_rounds(
            out["random_claims_round2"], third, later, claim["design"], claim["margins"], measured)
    return out


def claim_discs(study: pd.DataFrame, lighting: dict) -> dict:
    """Which lobes enter the claim and their search discs, from geometry and the regular surfaces alone (rule
    ``claim_discs``): ``random_claim_geometry`` (:func:`roughlight.analysis.claims.claim_geometry`)."""
    return {"random_claim_geometry": C.claim_geometry(list(C.regular_stacks(study).values()), lighting)}


def pilot_readings(pilots: pd.DataFrame, geometry: pd.DataFrame, steps: tuple[float, float] = (5.0, 1.0),
                   keys: dict | None = None) -> pd.DataFrame:
    """What the claim's design reads of its pilots (rule ``claim_pilots``): each pilot ensemble's
    :func:`roughlight.analysis.claim_readings.pooled_readings` (unrounded) at its search discs, as
    :func:`roughlight.analysis.claim_readings.readings_table` lays them out.

    Parameters
    ----------
    pilots : the pilot tiles' rows (rule ``claim_sweeps``' pilots, ``claims.pilots`` at ``claims.cells``, as
        :func:`roughlight.study.tables.claim_rows` gives them)
    geometry : rule ``claim_discs``' table
    steps : the study's azimuth and elevation steps, degrees
    keys : (kind, truncation, aspect, incidence) -> the ensemble's :func:`roughlight.study.pilots.pilot_key`
    """
    stacks = C.seed_stacks_of(pilots, steps)
    readings = {key: pooled_readings(stack, lobe_centres(key[1:]), C.discs(geometry, key[1:]))
                for key, stack in stacks.items()}
    return readings_table(readings, keys)


def claim_design(study: pd.DataFrame, geometry: pd.DataFrame, grid: pd.DataFrame | None, claims: dict,
                 steps: tuple[float, float] = (5.0, 1.0), *, pilots: pd.DataFrame) -> dict:
    """The claim's design (rule ``claim_design``), from the regular surfaces, the exact reference and the pilots'
    readings: no tested seed (``claims.seeds``) is read.

    Parameters
    ----------
    study : the regular surfaces' rows at the random grid points (the fast method, every view; other kinds' rows
        are left out)
    geometry : rule ``claim_discs``' table
    grid : rule ``claim_grid``'s measurements (None: none; the margins go without the sampling error and the
        view grid's effect)
    claims : :func:`roughlight.study.config.claim_settings` (``alpha``, ``max_seeds``, ``tested``)
    steps : the study's azimuth and elevation steps, degrees
    pilots : the pilots' readings (rule ``claim_pilots``' table, :func:`pilot_readings`; registered or rendered)

    Returns
    -------
    dict of DataFrames: ``random_claim_margins``, ``random_claim_design`` (:mod:`roughlight.analysis.claims`),
    ``random_claim_grid``, ``random_claim_errors`` (:mod:`roughlight.analysis.claim_instrument`).
    """
    regular = C.regular_stacks(study)
    readings = table_readings(pilots)
    ref = reference_stacks(grid, steps[1]) if grid is not None and len(grid) else {}
    errors = instrument_errors(ref, geometry)
    kinds = sorted({kind for kind, *_ in claims.get("tested", [])} | {k[0] for k in readings})
    margin_table = C.margins(regular, geometry, kinds, errors)
    configured = {(kind, float(t), float(a)): int(n) for kind, t, a, n in claims.get("tested", [])}
    design = C.claim_design(margin_table, readings, claims, configured)
    return {"random_claim_margins": margin_table, "random_claim_design": design, "random_claim_errors": errors,
            "random_claim_grid": grid_table(ref, geometry)}


def claim_verdict(rows: pd.DataFrame, geometry: pd.DataFrame, margins: pd.DataFrame, design: pd.DataFrame,
                  steps: tuple[float, float] = (5.0, 1.0)) -> pd.DataFrame:
    """The claim's verdict (rule ``analysis_random``) from the tested tiles alone (rule ``claim_sweeps``' tested
    files), in both readings: :func:`roughlight.analysis.claims.claim_table`."""
    tested = C.seed_stacks_of(rows, steps)
    readings = {key + (reading,): pooled_readings(stack, lobe_centres(key[1:]), C.discs(geometry, key[1:]), reading)
                for key, stack in tested.items() for reading in READINGS}
    return C.claim_table(readings, design, margins)


def claim_tables(study: pd.DataFrame, claim_rows: pd.DataFrame, grid: pd.DataFrame | None, claims: dict,
                 lighting: dict, steps: tuple[float, float] = (5.0, 1.0), *, pilots: pd.DataFrame) -> dict:
    """Every table of the claim at once, in the workflow's order (rules ``claim_discs``, ``claim_design`` and the
    verdict of ``analysis_random``): the ``pilots``' rows plan, the claim's tested tiles (``claim_rows``) decide."""
    geometry = claim_discs(study, lighting)["random_claim_geometry"]
    design = claim_design(study, geometry, grid, claims, steps, pilots=pilot_readings(pilots, geometry, steps))
    verdict = claim_verdict(claim_rows, geometry, design["random_claim_margins"], design["random_claim_design"],
                            steps)
    return {"random_claim_geometry": geometry, **design, "random_claims": verdict}
