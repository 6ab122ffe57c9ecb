"""The page's "Findings": the study's main results as numbered statements, each with its numbers and a link to the
element of the page that shows the evidence (``templates/findings.html``).

Each function here gathers one statement's numbers from this run's frames, through the functions of the section
that shows the evidence (:mod:`~roughlight.report.sections.tables`, :mod:`~roughlight.report.sections.glm`,
:mod:`~roughlight.report.sections.speed`, :mod:`~roughlight.report.sections.random`, rule ``analysis_random``'s
claim table), so that a finding
says what its section says. Each returns a dict: the statement's numbers and ``target``, the id of the page element
it links to (on the page whenever the statement is made); or, where the statement cannot be made for this run,
``{"why": code}``, a code the template turns into the sentence that says why.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..page_templates import frame_or_none
from ..registry import Section
from . import light_transport as light_section
from . import tables
from .glm import best_laws
from .random import ROUND_NAMES, claim_test_label, untaken_rounds
from .speed import speed_section

#: The lobes of Tables 1-2: (lobe, table, its area function).
LOBES = (("forward", 1, "Square Area Function"), ("back", 2, "Triangle Area Function"))
#: The share laws' baseline model (:data:`roughlight.analysis.share_laws.MODELS`).
BASELINE = "linear GLM (baseline)"


def _span(values) -> tuple[float, float] | None:
    """The smallest and largest of the finite ``values`` (None: none is finite)."""
    v = np.asarray([x for x in values if x is not None and np.isfinite(x)], float)
    return (float(v.min()), float(v.max())) if len(v) else None


def _better(area: float, regressed: float) -> str | None:
    """Which of two MAEs is smaller: "area", "regressed", or None when either is not a number."""
    if not (np.isfinite(area) and np.isfinite(regressed)):
        return None
    return "area" if area < regressed else "regressed"


def _has_rows(frame) -> bool:
    """The frame is given and has rows."""
    return frame_or_none(frame) is not None


# ---------------------------------------------------------------------------
# Tables 1-2


def _lobe_ranking(thesis: pd.DataFrame, per_aspect: list[dict], lobe: str, table: int, area_model: str) -> dict:
    """One lobe's MAEs over the table aspects (ours, the area function and the regressed model) and the thesis's."""
    area = [f[f"{lobe}_area"] for f in per_aspect]
    regressed = [f[f"{lobe}_regressed"] for f in per_aspect]
    first = thesis["aspect"].max()
    t_area = tables.table_statistic(thesis, table, first, area_model, "thesis 2001", "Mean Abs Error")
    t_regressed = tables.table_statistic(thesis, table, first, "Regressed Model", "thesis 2001", "Mean Abs Error")
    ours = {_better(a, r) for a, r in zip(area, regressed)} - {None}
    return {"lobe": lobe, "table": table, "area": _span(area), "regressed": _span(regressed),
            "ours": ours.pop() if len(ours) == 1 else ("mixed" if ours else None),
            "thesis": _better(t_area, t_regressed), "thesis_area": t_area, "thesis_regressed": t_regressed}


def ranking(thesis: pd.DataFrame | None) -> dict:
    """Tables 1-2's ranking of the area functions against the regressed models, ours against the thesis's.

    Ours are :func:`roughlight.report.sections.tables.lobe_maes`' MAEs (what "Tables 1 and 2" says), per lobe the
    range over the table aspects; ``verdict``: "reversed" (every lobe ranks the other way round from the
    thesis), "same", or "mixed" (some lobe could not be compared, or ranks differently at different aspects).
    """
    if not _has_rows(thesis):
        return {"why": "no_table_aspect"}
    per_aspect = tables.lobe_maes(thesis)
    lobes = [_lobe_ranking(thesis, per_aspect, *lobe) for lobe in LOBES]
    ranked = [lb for lb in lobes if lb["ours"] in ("area", "regressed") and lb["thesis"]]
    verdict = "mixed"
    if len(ranked) == len(lobes):
        if all(lb["ours"] != lb["thesis"] for lb in ranked):
            verdict = "reversed"
        elif all(lb["ours"] == lb["thesis"] for lb in ranked):
            verdict = "same"
    return {"labels": [f["label"] for f in per_aspect], "lobes": lobes, "verdict": verdict, "target": "tables"}


def exact_law(thesis: pd.DataFrame | None, exact: pd.DataFrame | None) -> dict:
    """The area functions on the exact lobe peaks, and how far the fast renderer's peaks are from them
    (:func:`roughlight.report.sections.tables.exact_error`: max, mean, worst)."""
    if not _has_rows(thesis):
        return {"why": "no_table_aspect"}
    error = tables.exact_error(thesis, exact)
    if error is None:
        return {"why": "no_exact"}
    return {**error, "target": "exact-peaks"}


def _at_implied_scale(at_scale: pd.DataFrame, scales: pd.DataFrame) -> list[dict]:
    """Per table recomputed at the implied scale: the scale, our area function's and regressed model's MAEs over
    the table aspects, the thesis's MAE and whether the area function still wins."""
    out = []
    implied_rows = at_scale[at_scale["scale"] == "implied"]
    for table, rows in implied_rows.groupby("table", sort=True):
        scale = scales[scales["table"] == table].iloc[0]
        area = rows[rows["model"].str.contains("Area")]
        out.append({"table": int(table), "model": scale["model"], "scale": float(scale["s_min_mae"]),
                    "area": _span(area["Mean Abs Error"]), "thesis": float(scale["mae"]),
                    "regressed": _span(rows[rows["model"] == "Regressed Model"]["Mean Abs Error"]),
                    "area_wins": tables.area_still_wins(rows)})
    return out


def implied_scale(thesis: pd.DataFrame | None, implied_scales: pd.DataFrame | None,
                  tables_at_implied_scale: pd.DataFrame | None) -> dict:
    """The scales of its area functions the thesis's own numbers allow (:func:`tables.implied`), and our
    rows at the smallest allowed scale where the stated one is impossible."""
    if not _has_rows(thesis):
        return {"why": "no_table_aspect"}
    shown = tables.implied(implied_scales, tables_at_implied_scale)
    if shown is None:
        return {"why": "no_scales"}
    scales = shown["scales"]
    rows = [{"table": int(r["table"]), "model": r["model"], "mae": float(r["mae"]), "low": float(r["s_min_mae"]),
             "high": float(r["s_max_mae"]), "stated": float(r["stated_scale"]), "possible": bool(r["stated_possible"])}
            for _, r in scales.sort_values("stated_possible").iterrows()]
    at = _at_implied_scale(tables_at_implied_scale, scales) if shown["at_scale"] is not None else []
    return {"scales": rows, "at_scale": at, "target": "implied-scale" if at else "tables"}


# ---------------------------------------------------------------------------
# over the grid


def share_law_finding(laws: pd.DataFrame | None) -> dict:
    """Per lobe and incidence, the model best held out (the one "GLMs over the grid" names) against the linear
    GLM's held-out RMSE (NaN, with the frame's ``note`` saying why, where it was not fitted); ``all_laws``: every
    best model is a share law."""
    laws = frame_or_none(laws)
    if laws is None:
        return {"why": "no_laws"}
    best = best_laws(laws)
    items = []
    for _, r in best.sort_values(["lobe", "incidence"], ascending=[False, True]).iterrows():
        base = laws[(laws["lobe"] == r["lobe"]) & (laws["incidence"] == r["incidence"]) & (laws["model"] == BASELINE)]
        items.append({"lobe": r["lobe"], "incidence": float(r["incidence"]), "model": r["model"],
                      "rmse_held_out": float(r["rmse_held_out"]), "n": int(r["n"]),
                      "baseline": float(base["rmse_held_out"].iloc[0]) if len(base) else float("nan"),
                      "baseline_note": str(base["note"].iloc[0]) if len(base) and pd.notna(base["note"].iloc[0]) else ""})
    return {"best": items, "all_laws": all(i["model"].startswith("share law") for i in items),
            "target": "share-laws"}


# ---------------------------------------------------------------------------
# random roughness


#: The claim's verdicts, in the order a finding counts them.
VERDICTS = ("lobe", "no lobe", "difference", "no difference", "not as claimed", "undecided", "not measurable")


def _claim_test(name: str, rows: pd.DataFrame, unit: str) -> dict:
    """One test of the claim over its rows in one reading (rule ``analysis_random``'s verdict,
    :func:`roughlight.analysis.claims.claim_table`): how many rows reach each verdict (``verdicts``: (verdict,
    count) pairs; differences split into ``as claimed`` and ``against``), the random means where the lobe was
    there (their range), the regular values and the margins (their ranges) and the statistic's ``unit``."""
    verdicts = []
    for verdict in VERDICTS:
        k = int((rows["verdict"] == verdict).sum())
        if verdict == "difference" and k:
            agrees = rows.loc[rows["verdict"] == verdict, "agrees"].astype("boolean")
            verdicts += [(way, n) for way, n in (("difference as claimed", int((agrees == True).sum())),  # noqa: E712
                                                  ("difference against the claim", int((agrees == False).sum())))  # noqa: E712
                         if n]
        elif k:
            verdicts.append((verdict, k))
    made = rows.loc[~rows["verdict"].isin(["no lobe", "not measurable"]), "mean"]
    return {"name": name, "test": claim_test_label(name), "claim": rows["claim"].iloc[0], "unit": unit,
            "n": len(rows), "verdicts": verdicts, "mean": _span(made), "regular": _span(rows["regular"]),
            "margin": _span(rows["margin"]), "seeds": _span(rows["seeds"])}


def _regular_shapes(claims: pd.DataFrame) -> dict:
    """The regular surface's lobes in the claim (unrounded): the back lobe's squareness ("ellipse" when below 0 at
    every point, "rectangle" when above, else "between") and the halo's flatness ("flat" when above 0.5, the edge
    nearer a straight line than a circle, "round" below), with their ranges."""
    unrounded = claims[claims["reading"] == "unrounded"]
    out = {}
    for test, key, (low_name, high_name), cut in (("back_squareness", "back", ("ellipse", "rectangle"), 0.0),
                                                  ("hot_spot_flatness", "halo", ("round", "flat"), 0.5)):
        values = unrounded.loc[unrounded["test"] == test].drop_duplicates(["truncation", "aspect", "incidence"])
        span = _span(values["regular"])
        if span is None:
            continue
        low, high = span
        out[key] = {"span": span, "points": len(values),
                    "shape": low_name if high < cut else (high_name if low > cut else "between")}
    return out


def _claim_headline(claims: pd.DataFrame) -> str:
    """What one reading's verdicts add up to, over the shape tests: "supported" (every shape test a difference as
    claimed), "refuted" (every one decided, none as claimed), "unsupported" (some decided, none as claimed, the rest
    undecided), "no lobe" (no random surface has a lobe to compare), "undecided" (none decided), else "mixed"."""
    shape = claims[claims["test"].map(lambda t: not t.endswith("_contrast"))]
    verdicts = shape["verdict"]
    if (verdicts == "no lobe").all():
        return "no lobe"
    compared = verdicts[verdicts != "no lobe"]
    decided = compared.isin(["difference", "no difference", "not as claimed"])
    if not decided.any():
        return "undecided"
    agrees = shape.loc[compared.index, "agrees"].astype("boolean")
    claimed = (compared == "difference") & (agrees == True)  # noqa: E712
    if claimed.all():
        return "supported"
    if not claimed.any():
        return "refuted" if decided.all() else "unsupported"
    return "mixed"




def random_claim_finding(random_claims: pd.DataFrame | None, shown: bool,
                         untaken: pd.DataFrame | None = None) -> dict:
    """The thesis's claim on random roughness, per test of :data:`roughlight.analysis.claims.TESTS` (in its
    order), in both readings: the regular surface's lobes and the verdicts over the random grid points and kinds
    (rule ``analysis_random``'s ``random_claims.csv``).

    ``shown``: the "Random roughness" section is on the page (a random kind was measured). ``untaken``: the
    registered rounds the verdict did not take (rule ``analysis_random``'s ``random_claims_untaken.csv``): the
    finding names each (``untaken``: round, ensemble and why), so that a round a change has made stale is seen.
    """
    from ...analysis.claims import TESTS
    from ...analysis.direction_rounds import ALPHA as D_ALPHA
    from ...analysis.third_round import ALPHA as T_ALPHA

    if not shown:
        return {"why": "no_kind"}
    if random_claims is None:
        return {"why": "not_given"}
    claims = frame_or_none(random_claims)
    if claims is None:
        return {"why": "no_claim"}
    readings = {}
    for reading, part in claims.groupby("reading", sort=False):
        readings[reading] = {
            "tests": [_claim_test(name, part[part["test"] == name], TESTS[name]["unit"])
                      for name in TESTS if (part["test"] == name).any()],
            "headline": _claim_headline(part), "n_tests": len(part)}
    rounds = claims["round"] if "round" in claims else pd.Series(2, index=claims.index)
    first = claims[rounds == 2].iloc[0] if (rounds == 2).any() else claims.iloc[0]
    unrounded = claims["reading"] == "unrounded"
    third, direction = claims[(rounds == 3) & unrounded], claims[(rounds >= 4) & unrounded]
    # a round of the claim's direction is planned from the verdict every round before it left, so its rows stand
    # only where those rounds were taken too: the last one names them all
    last = int(direction["round"].max()) if len(direction) else 3
    return {"readings": readings, "regular": _regular_shapes(claims), "kinds": claims["kind"].nunique(),
            "points": len(claims[["truncation", "aspect", "incidence"]].drop_duplicates()),
            "level": float(first["level"]), "target": "random-claim",
            "untaken": untaken_rounds(untaken),
            "third": {"n": int((third["verdict"] != "undecided").sum()), "level": float(third["level"].iloc[0])}
            if len(third) else None,
            "direction": {"tests": len(direction), "decided": int((direction["verdict"] != "undecided").sum()),
                          "rounds": [ROUND_NAMES[n] for n in range(4, last + 1)], "level": float(direction["level"].iloc[0])}
            if len(direction) else None,
            # Bonferroni over the rounds: the second's family error (its level's complement times its tests) and
            # each later round's own (third_round.ALPHA, direction_rounds.ALPHA)
            "together": 1.0 - (1.0 - float(first["level"])) * int(unrounded.sum())
            - (T_ALPHA if len(third) or len(direction) else 0.0) - D_ALPHA * (last - 3)}


# ---------------------------------------------------------------------------
# the renderers


def renderer_accuracy(shown: dict | None) -> dict:
    """The fast renderer against the exact reference at every view (the configured setting of
    :func:`roughlight.report.sections.speed.validation_line`: its worst view and largest MAE over the
    components) and on random tiles, as "Accuracy at every view" says them (``shown``: its data,
    :func:`roughlight.report.sections.speed.speed_section`)."""
    if shown is None:
        return {"why": "switched_off"}
    if shown["validation"] is None:
        return {"why": "no_validation"}
    line = shown["validation"]["line"]
    setting = next((s for s in line["settings"] if s["setting"] == "configured"), line["settings"][0])
    worst = max(setting["rows"], key=lambda r: r["worst"])
    return {"n_surfaces": line["n_surfaces"], "views": line["views"], "setting": setting["setting"],
            "worst": worst["worst"], "component": worst["component"],
            "mae": max(r["largest_mae"] for r in setting["rows"]), "tiles": shown["validation"]["tiles"],
            "target": "renderer-validation"}


def speed(shown: dict | None) -> dict:
    """The fast renderer at its default settings against the naive method, from the speed/accuracy benchmark
    (:func:`roughlight.measurements.speed_accuracy.run_benchmark`): views per second and the total's worst
    error and MAE against the exact reference (``shown``: :func:`roughlight.report.sections.speed.speed_section`)."""
    if shown is None:
        return {"why": "switched_off"}
    table = frame_or_none(shown["table"])
    if table is None or not {"default", "speedup_vs_naive"} <= set(table.columns):
        return {"why": "no_table"}
    total = table[table["component"] == "total"]
    fast, naive = total[total["default"].astype(bool)], total[total["method"] == "naive"]
    if fast.empty or naive.empty:
        return {"why": "no_default" if fast.empty else "no_naive"}
    f, n = fast.iloc[0], naive.iloc[0]
    return {"label": f["label"], "views": int(f["n_views"]), "fast_vps": float(f["views_per_second"]),
            "naive_vps": float(n["views_per_second"]), "speedup": float(f["speedup_vs_naive"]),
            "fast_worst": float(f["max_error"]), "naive_worst": float(n["max_error"]), "fast_mae": float(f["mae"]),
            "naive_mae": float(n["mae"]), "target": "speed-accuracy"}


def implicit(validation: pd.DataFrame | None, shown: bool, frames: pd.DataFrame | None = None) -> dict:
    """The implicit shader's two forms against the exact reference (the "all" band of
    :func:`roughlight.measurements.implicit_surface.summary`, the total): worst view, largest and median MAE.

    ``shown``: the "An implicit rough surface" section is on the page (``report.implicit``).
    """
    from ...measurements.implicit_surface import summary

    if not shown:
        return {"why": "switched_off"}
    if not _has_rows(validation):
        return {"why": "not_given"}
    s = summary(validation)
    s = s[(s["band"] == "all") & (s["component"] == "total")].set_index("method")
    forms = {m: {"worst": float(s.loc[m, "worst"]), "max_mae": float(s.loc[m, "max_mae"]),
                 "median_mae": float(s.loc[m, "median_mae"])} if m in s.index else None
             for m in ("implicit_exact", "implicit_correction")}
    from ...measurements.implicit_surface import goal

    met = goal(validation, frames) if _has_rows(frames) else []
    from ...measurements.implicit_surface import held_out_counts

    drawn = held_out_counts(validation)
    return {"n_surfaces": drawn["surfaces"], "n_views": drawn["views"], "held_out": drawn,
            "exact": forms["implicit_exact"],
            "correction": forms["implicit_correction"], "target": "implicit-validation", "goal": met,
            "meets": [g["method"] for g in met if g["meets"]]}


def light_transport(agreement: pd.DataFrame | None, summary: pd.DataFrame | None, shown: bool) -> dict:
    """Mitsuba 3 against the exact reference under direct light (each component's worst view), and where light that
    bounces adds less than one level at every view of the hemisphere, per albedo (rule ``light_transport``), as
    the section says them (:mod:`roughlight.report.sections.light_transport`).

    ``shown``: the "Beyond the OpenGL equation" section is on the page (``report.light_transport.enabled``).
    """
    if not shown:
        return {"why": "switched_off"}
    if not (_has_rows(agreement) and _has_rows(summary)):
        return {"why": "not_given"}
    checked = light_section.agreement_summary(agreement)
    albedos = [{"albedo": g["albedo"], "within": g["within"], "surfaces": g["surfaces"], "worst": g["worst"],
                "mean": _span([g["mean_low"], g["mean_high"]]), "percent": _span([g["percent_low"], g["percent_high"]])}
               for g in light_section.gains(summary)]
    return {"agreement": [(r["component"], r["worst"]) for r in checked["rows"]], "agrees": checked["within"],
            "albedos": albedos, "target": "light-transport"}


# ---------------------------------------------------------------------------
# the section


def findings_section(thesis_tables: pd.DataFrame | None = None, exact_peaks: pd.DataFrame | None = None,
                     implied_scales: pd.DataFrame | None = None, tables_at_implied_scale: pd.DataFrame | None = None,
                     share_laws: pd.DataFrame | None = None, implicit_validation: pd.DataFrame | None = None,
                     implicit_frames: pd.DataFrame | None = None,
                     random_claims: pd.DataFrame | None = None, random_claims_untaken: pd.DataFrame | None = None,
                     speed_accuracy: pd.DataFrame | None = None,
                     speed_accuracy_png=None, renderer_validation: pd.DataFrame | None = None,
                     arc_smoothness: pd.DataFrame | None = None, renderer_validation_png=None,
                     random_accuracy: pd.DataFrame | None = None, mitsuba_agreement: pd.DataFrame | None = None,
                     interreflection_summary: pd.DataFrame | None = None, table_aspects=(),
                     table_incidence: float = 30.0, shown: dict | None = None) -> dict:
    """The data of ``templates/findings.html``: one entry a statement, in page order.

    Parameters
    ----------
    thesis_tables, exact_peaks, implied_scales, tables_at_implied_scale, share_laws : the analysis outputs.
    implicit_validation : rule ``implicit_surface``'s validation; random_claims : rule ``analysis_random``'s
        claim table; None: the statement says they were not given. random_claims_untaken : its registered rounds
        not taken (:func:`roughlight.analysis.direction_rounds.later_rounds`).
    speed_accuracy, speed_accuracy_png, renderer_validation, arc_smoothness, renderer_validation_png,
    random_accuracy : the speed/accuracy benchmark and "Accuracy at every view", as "Settings and provenance" shows
        them (:func:`roughlight.report.sections.speed.speed_section`); none given: switched off.
    table_aspects, table_incidence : the aspects and incidence of Tables 1-2.
    mitsuba_agreement, interreflection_summary : rule ``light_transport``'s tables; None: not given.
    shown : which sections are on the page (name -> bool): ``random``, ``implicit``, ``light_transport``.

    Returns
    -------
    dict: the aspects and incidence of Tables 1-2 and a dict per statement (:func:`ranking`, ...).
    """
    shown = shown or {}
    thesis = thesis_tables
    benchmarks = speed_section(speed_accuracy, speed_accuracy_png, renderer_validation, arc_smoothness,
                                          renderer_validation_png, random_accuracy)
    return {
        "table_aspects": list(table_aspects), "incidence": table_incidence,
        "ranking": ranking(thesis), "exact": exact_law(thesis, exact_peaks),
        "implied": implied_scale(thesis, implied_scales, tables_at_implied_scale), "laws": share_law_finding(share_laws),
        "implicit": implicit(implicit_validation, bool(shown.get("implicit")), implicit_frames),
        "random": random_claim_finding(random_claims, bool(shown.get("random")), random_claims_untaken),
        "accuracy": renderer_accuracy(benchmarks), "speed": speed(benchmarks),
        "light": light_transport(mitsuba_agreement, interreflection_summary, bool(shown.get("light_transport"))),
    }


#: The findings come first on the page, above the contents; gathered last, since they say which sections are on it.
SECTION = Section("findings", findings_section, "findings.html", title="Findings",
                  inputs={"thesis_tables": "results/analysis/thesis_tables.csv",
                          "exact_peaks": "results/analysis/exact_peaks.csv",
                          "implied_scales": "results/analysis/implied_scales.csv",
                          "tables_at_implied_scale": "results/analysis/tables_at_implied_scale.csv",
                          "share_laws": "results/analysis/share_laws.csv"})
