"""The default renderer against the exact reference at every view: worst view, p99 and MAE per surface, and how
far the figures' arc curves (Figs. 21 and 28) stray from the exact ones.

The thesis's complaint about its own data (Ch. IV.A) was "jagged peaks" from pixelation. A mean error hides
them; these functions report the worst view of every sweep and the largest deviation of every plotted curve,
against :func:`roughlight.render.exact.reference.reference_sweep` on the same views.
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd

from ..analysis.thesis import SQRT3_2, TABLE_ASPECTS, THESIS_INCIDENCE
from ..render import methods, shading
from ..render import views as sweeps
from ..study.tables import regular
from ..surfaces.surface import Surface
from . import comparison

#: Surfaces and view steps (elevation, azimuth; degrees) of each plan. ``full``: the grid's corners, edges' middles
#: and centre, the table aspect sqrt(3)/2 and two surfaces off the grid's lines, on every view of a sweep.
PLANS = {
    "quick": {"surfaces": ((0.1, 1.0), (1.0, 1.0), (0.5, 0.5)), "steps": (5.0, 20.0)},
    "smoke": {"surfaces": ((1.0, 1.0),), "steps": (20.0, 60.0)},  # a check that the report builds, in seconds
    "full": {
        "surfaces": ((0.1, 0.1), (0.1, 0.5), (0.1, 1.0), (0.5, 0.1), (0.5, 0.5), (0.5, 1.0), (1.0, 0.1),
                     (1.0, 0.5), (1.0, 1.0), (1.0, SQRT3_2), (0.3, 0.8), (0.8, 0.3)),
        "steps": (1.0, 5.0),
    },
}

#: Views within this many degrees of the horizon (e < 10 or e > 170) are the thesis's grazing views.
GRAZING = 10.0

#: The fast renderer's settings the validation compares besides the configured one: the default before issue 11
#: (lattice sampling at 24 pixels a period), whose speed the default (adaptive at 28) is held to.
FORMER_DEFAULT = {"sampling": "lattice", "pixels_per_period": 24}


def view_errors(rendered: dict, exact: dict, azimuth, elevation) -> list[dict]:
    """Error statistics of one sweep against the exact values, per component.

    Parameters
    ----------
    rendered, exact : dict
        ``diffuse``, ``specular``, ``total``: (n_views,) values, 0-255.
    azimuth, elevation : (n_views,) arrays
        The views, degrees. Views without surface (e = 0, 180) are left out, and each view counts once (the
        zenith once, not once per azimuth: :func:`roughlight.render.views.distinct_views`).

    Returns
    -------
    list of dicts: ``component``, ``n_views`` (the views compared), ``mae``, ``p99``, ``worst`` (0-255), ``worst_elevation``,
    ``worst_azimuth`` (degrees) and ``grazing_worst`` (the worst of the views within :data:`GRAZING` of the
    horizon).
    """
    azimuth, elevation = np.asarray(azimuth, float), np.asarray(elevation, float)
    seen = sweeps.distinct_views(azimuth, elevation)
    grazing = seen & ((elevation < GRAZING) | (elevation > 180.0 - GRAZING))
    rows = []
    for component, err in comparison.absolute_errors(rendered, exact).items():
        k = int(np.flatnonzero(seen)[np.argmax(err[seen])])
        rows.append({"component": component, "n_views": int(seen.sum()), **comparison.error_statistics(err[seen]),
                     "worst_elevation": float(elevation[k]), "worst_azimuth": float(azimuth[k]),
                     "grazing_worst": comparison.error_statistics(err[grazing], ("worst",))["worst"]
                     if grazing.any() else np.nan})
    return rows


def validate_renderer(plan: str = "full", incidence: float = THESIS_INCIDENCE, lighting=None, settings=None,
                      log=None) -> pd.DataFrame:
    """The fast renderer at ``settings`` (default: the default renderer) and at :data:`FORMER_DEFAULT` against the
    exact reference on every view of each surface of the plan.

    Returns
    -------
    DataFrame, one row per setting x surface x component: ``setting`` ('configured' | 'lattice 24'),
    ``sampling``, ``pixels_per_period``, ``truncation``, ``aspect``, ``incidence`` (degrees), the columns of
    :func:`view_errors`, and ``fast_views_per_second``, ``reference_views_per_second``.
    """
    from dataclasses import replace


    settings = methods.settings("fast", settings)
    former = replace(settings, **FORMER_DEFAULT)
    runs = [("configured", settings)]
    if former != settings:
        runs.append((f"{former.sampling} {former.pixels_per_period}", former))
    size = comparison.plan_size(PLANS, plan, "renderer validation")
    lighting = lighting or shading.Lighting()
    log = log or (lambda message: None)
    azimuth, elevation = sweeps.view_grid(*size["steps"])
    n_seen = int((~np.asarray(sweeps.is_grazing(elevation))).sum())
    rows = []
    for truncation, aspect in size["surfaces"]:
        surface = Surface(float(truncation), float(aspect))
        start = time.perf_counter()
        exact = methods.sweep("reference", surface, incidence, azimuth, elevation, lighting)
        reference_seconds = time.perf_counter() - start
        for name, run in runs:
            rendered = methods.sweep("fast", surface, incidence, azimuth, elevation, lighting, run)
            for row in view_errors(rendered, exact, azimuth, elevation):
                rows.append({"setting": name, "sampling": run.sampling, "pixels_per_period": int(run.pixels_per_period),
                             "truncation": surface.truncation, "aspect": surface.aspect, "incidence": float(incidence),
                             **row, "fast_views_per_second": n_seen / rendered["seconds"],
                             "reference_views_per_second": n_seen / reference_seconds})
            worst = max(r["worst"] for r in rows[-3:])
            log(f"t={surface.truncation:g} aspect={surface.aspect:g} {name}: worst view {worst:.2f}")
    return pd.DataFrame(rows)


def study_accuracy(study: pd.DataFrame, lighting=None, shard: tuple[int, int] = (0, 1), log=None) -> pd.DataFrame:
    """Every view of a study's regular surfaces against the exact reference: the study's own numbers, as its
    analyses read them.

    Parameters
    ----------
    study : DataFrame
        A study table (``results/study.parquet``); its regular rows are checked.
    lighting : Lighting
        The study's lighting (:func:`roughlight.study.config.lighting_from_config`).
    shard : (k, n)
        Check only the surfaces ``k, k + n, k + 2n, ...`` of the study's (incidence, truncation, aspect) order,
        to spread the work over ``n`` processes.

    Returns
    -------
    DataFrame, one row per surface x component: ``truncation``, ``aspect``, ``incidence`` and the columns of
    :func:`view_errors`.
    """
    lighting = lighting or shading.Lighting()
    log = log or (lambda message: None)
    rows = regular(study)
    wide = rows.pivot_table(index=["incidence", "truncation", "aspect", "azimuth", "elevation"], columns="component",
                            values="rough", aggfunc="first").reset_index()
    out = []
    for i, ((incidence, truncation, aspect), sweep) in enumerate(wide.groupby(["incidence", "truncation", "aspect"])):
        if i % int(shard[1]) != int(shard[0]):
            continue
        azimuth, elevation = sweep["azimuth"].to_numpy(float), sweep["elevation"].to_numpy(float)
        exact = methods.sweep("reference", Surface(float(truncation), float(aspect)), float(incidence), azimuth,
                              elevation, lighting)
        errors = view_errors({c: sweep[c].to_numpy(float) for c in shading.COMPONENTS}, exact, azimuth, elevation)
        out += [{"truncation": float(truncation), "aspect": float(aspect), "incidence": float(incidence), **row}
                for row in errors]
        log(f"t={truncation:g} aspect={aspect:g} i={incidence:g}: worst view {max(r['worst'] for r in errors):.2f}")
    return pd.DataFrame(out)


def arc_smoothness(study: pd.DataFrame, aspects=TABLE_ASPECTS, incidence: float = THESIS_INCIDENCE,
                   lighting=None) -> pd.DataFrame:
    """How far each curve of Figs. 21 (specular) and 28 (diffuse) lies from the exact curve.

    The curves are the study's light-plane arcs (azimuth 0, every elevation) of each truncation at the table
    aspects and the thesis's incidence; the exact reference is computed on the same views with ``lighting``
    (the study's).

    Returns
    -------
    DataFrame, one row per curve: ``figure`` ('Fig. 21' | 'Fig. 28'), ``component``, ``truncation``,
    ``aspect``, ``incidence``, ``n_views``, ``largest_deviation`` (0-255), ``at_elevation`` (degrees) and
    ``mae``; empty when the study has none of the aspects.
    """
    from ..study.selection import arc

    lighting = lighting or shading.Lighting()
    rows = []
    figures = (("Fig. 21", "specular"), ("Fig. 28", "diffuse"))
    curves = {component: arc(regular(study), component) for _, component in figures}
    keys = curves["diffuse"][["truncation", "aspect", "incidence"]].drop_duplicates()
    keys = keys[np.isclose(keys["incidence"], incidence)]
    keys = keys[np.any(np.abs(keys["aspect"].to_numpy(float)[:, None] - np.asarray(aspects, float)) < 1e-6, axis=1)]
    for t, a, i in keys.itertuples(index=False):
        elevation = np.asarray(sorted(curves["diffuse"].loc[
            (curves["diffuse"]["truncation"] == t) & (curves["diffuse"]["aspect"] == a)
            & (curves["diffuse"]["incidence"] == i), "elevation"]), float)
        exact = methods.sweep("reference", Surface(float(t), float(a)), float(i), np.zeros_like(elevation), elevation,
                              lighting)
        seen = ~np.asarray(sweeps.is_grazing(elevation))
        if not seen.any():  # every view of the arc grazes the surface (sweep.elevation_step 180): nothing to compare
            continue
        for figure, component in figures:
            c = curves[component]
            curve = c[(c["truncation"] == t) & (c["aspect"] == a) & (c["incidence"] == i)].sort_values("elevation")
            err = comparison.absolute_errors({component: curve["rough"].to_numpy(float)}, exact, seen, (component,))
            statistics = comparison.error_statistics(err[component], ("mae", "worst"))
            k = int(np.argmax(err[component]))
            rows.append({"figure": figure, "component": component, "truncation": float(t), "aspect": float(a),
                         "incidence": float(i), "n_views": int(seen.sum()), "largest_deviation": statistics["worst"],
                         "at_elevation": float(elevation[seen][k]), "mae": statistics["mae"]})
    columns = ["figure", "component", "truncation", "aspect", "incidence", "n_views", "largest_deviation",
               "at_elevation", "mae"]
    return pd.DataFrame(rows, columns=columns)


#: The study table's columns :func:`arc_smoothness` reads.
ARC_COLUMNS = ("kind", "truncation", "aspect", "incidence", "azimuth", "elevation", "phase", "component", "rough",
               "control", "coverage")


def read_arcs(path) -> pd.DataFrame:
    """The rows of a study table (``results/study.parquet``) that :func:`arc_smoothness` reads: the regular
    surface's views on the light's plane (azimuth 0, as :func:`roughlight.study.selection.arc` takes them), only
    the columns it reads (:data:`ARC_COLUMNS`). The default study's regular rows whole are a 0.42 GB frame
    (:func:`roughlight.study.tables.read_study`); its arcs are 1/36 of them."""
    import pyarrow.dataset as ds

    study = ds.dataset(path, format="parquet")
    names = set(study.schema.names)
    on_plane = (ds.field("azimuth") >= -1e-8) & (ds.field("azimuth") <= 1e-8)  # np.isclose(azimuth, 0.0)
    if "kind" in names:
        on_plane &= ds.field("kind") == "pyramids"
    # scanned a batch at a time, one read ahead: only the rows kept are ever held whole
    scan = study.scanner(columns=[c for c in ARC_COLUMNS if c in names], filter=on_plane, use_threads=False,
                         batch_readahead=1, fragment_readahead=1)
    return scan.to_table().to_pandas()


def validation_summary(validation: pd.DataFrame) -> pd.DataFrame:
    """Per setting and component, over the surfaces: the worst view, the largest p99, the largest and median MAE,
    the worst grazing view (0-255) and the median views per second of a sweep."""
    keys = [k for k in ("setting", "component") if k in validation.columns]
    grouped = validation.groupby(keys, sort=False)
    return pd.DataFrame({"worst": grouped["worst"].max(), "p99": grouped["p99"].max(),
                         "largest_mae": grouped["mae"].max(), "median_mae": grouped["mae"].median(),
                         "grazing_worst": grouped["grazing_worst"].max(),
                         "views_per_second": grouped["fast_views_per_second"].median()}).reset_index()


def main(argv=None) -> int:
    """``python -m roughlight.measurements.renderer_validation STUDY.parquet OUT.csv [--config CONFIG] [--shard K/N]``: every
    view of a study's regular surfaces against the exact reference (:func:`study_accuracy`), one row per surface
    and component; the summary (worst view, largest MAE) is printed."""
    import argparse

    import yaml

    from ..atomic import write_frame
    from ..study.config import lighting_from_config, validate_config

    parser = argparse.ArgumentParser(prog="python -m roughlight.measurements.renderer_validation", description=main.__doc__)
    parser.add_argument("study")
    parser.add_argument("out")
    parser.add_argument("--config", default="config/config.yaml", help="the study's config (its lighting)")
    parser.add_argument("--shard", default="0/1",
                        help="K/N: only every N-th surface from the K-th, K counted from 0 (0 <= K < N)")
    args = parser.parse_args(argv)
    try:
        k, n = (int(x) for x in args.shard.split("/"))
    except ValueError:
        parser.error(f"--shard must be K/N with integers K and N, got {args.shard!r}")
    if not 0 <= k < n:
        parser.error(f"--shard K/N needs 0 <= K < N (shards count from 0), got {args.shard!r}")
    with open(args.config) as f:
        lighting = lighting_from_config(validate_config(yaml.safe_load(f)))
    table = study_accuracy(pd.read_parquet(args.study), lighting, (k, n), log=print)
    write_frame(table, args.out)
    if len(table):
        summary = table.groupby("component").agg(surfaces=("worst", "size"), worst=("worst", "max"),
                                                 largest_mae=("mae", "max"), n_views=("n_views", "sum"))
        print(summary.to_string())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
