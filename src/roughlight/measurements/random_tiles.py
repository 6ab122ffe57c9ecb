"""Random tiles measured for the benchmark stage: the tile-size convergence, the fast renderer's accuracy against
the exact reference and its speed beside the regular surface's, and pictures of each kind as rendered.

The tile-size convergence (:func:`tile_convergence`, :func:`convergence_summary`) follows the random-roughness
claim's own statistics (:mod:`roughlight.analysis.claim_readings`): each kind's mean surface over its seeds, read
on the back lobe and the hot spot before rounding, with its delete-one jackknife error over seeds, in the same
discs at every tile size (the claim's, :func:`roughlight.analysis.claims.discs`: three of the regular lobe's
widths), beside the regular surface in those discs, at t 1, a 0.5, i 30: a point where both
lobes enter the claim at the default light (at a 1 the back lobe does not clear the horizon by three widths).

Plans (``measurements.plan``, the folder ``results/benchmarks/{plan}/``):

* ``quick``: random pyramids in tiles of 1, 2 and 4 cells, 3 seeds, on the study's views (1 x 5 degrees: the
  claim's discs are 17-45 degrees wide); accuracy on one 4-cell tile (the study's) of each kind at coarse views
  (30 x 45 degrees). About 15 s a job, as before (rule ``random_tiles``' benchmark file): a random heightfield's
  sweep costs two to three times a random pyramids' one, so the quick plan leaves it out.
* ``smoke``: a check that a config builds the whole report: 1- and 2-cell tiles, 2 seeds, views every
  10 x 30 degrees; its numbers are not for reading.
* ``full`` (``make bench``): both kinds in tiles of 1, 2, 3, 4 and 6 cells, 6 seeds, on the study's views;
  accuracy on 2 seeds of 4-cell tiles (the study's default) of each kind at the corners of the default random
  grid (t 0.5 and 1 x a 0.5 and 1: 16 tiles) at 5 x 15 degrees (444 views).
"""

from __future__ import annotations

import math
import time

import numpy as np
import pandas as pd

from ..analysis.claim_readings import STATISTICS
from ..analysis.claims import TESTS
from ..render import methods
from ..render.views import distinct_views
from ..surfaces.roughness import DEFAULT_CELLS, RANDOM_KINDS, make_surface
from . import comparison

__all__ = ["PLANS", "tile_convergence", "convergence_summary", "random_accuracy", "random_pictures",
           "tile_pixel_scan", "TILE_SAMPLINGS", "every_view_errors", "every_view_summary"]

PLANS = {
    "quick": {"point": (1.0, 0.5, 30.0), "kinds": ("random_pyramids",), "cells": (1, 2, 4), "seeds": 3,
              "views": (1.0, 5.0),
              "accuracy_cells": 4, "accuracy_seeds": 1, "accuracy_views": (30.0, 45.0),
              "accuracy_points": ((1.0, 1.0),)},
    # a check that a config builds the whole report, in seconds (its numbers are not for reading: its views are
    # too coarse for the claim's discs, which it takes from its own largest tile)
    "smoke": {"point": (1.0, 0.5, 30.0), "kinds": ("random_pyramids",), "cells": (1, 2), "seeds": 2,
              "views": (10.0, 30.0),
              "accuracy_cells": 2, "accuracy_seeds": 1, "accuracy_views": (45.0, 90.0),
              "accuracy_points": ((1.0, 1.0),)},
    "full": {"point": (1.0, 0.5, 30.0), "kinds": RANDOM_KINDS, "cells": (1, 2, 3, 4, 6), "seeds": 6,
             "views": (1.0, 5.0),
             "accuracy_cells": 4, "accuracy_seeds": 2, "accuracy_views": (5.0, 15.0),
             "accuracy_points": ((0.5, 0.5), (0.5, 1.0), (1.0, 0.5), (1.0, 1.0))},
}
#: The statistics followed against tile size: the random-roughness claim's readings of the mean surface
#: (:data:`roughlight.analysis.claim_readings.STATISTICS`) and the diffuse's hemisphere level.
CONVERGENCE_STATISTICS = tuple(STATISTICS) + ("diffuse_level",)
#: The range each followed statistic takes (its interval is cut to it): the claim's tests' where they give one.
STATISTIC_RANGES = {**{name: (0.0, math.inf) for name in ("back_width", "hot_spot_width")},
                    **{name: test["range"] for name, test in TESTS.items()}, "diffuse_level": (0.0, 255.0)}
#: :func:`tile_convergence`'s columns: ``kind`` (``pyramids`` for the regular surface), ``discs`` (the kind whose
#: discs it is read in: the regular surface is read once in each kind's), ``truncation``, ``aspect``, ``incidence``
#: (the point), ``cells`` (0 for the regular surface), ``seeds``, ``statistic``, ``lobe``, ``unit``, ``value`` (the
#: mean surface's), ``se`` (its jackknife standard error over seeds, NaN for fewer than 2 or where a resample
#: cannot be read), ``why`` ('' or why the lobe could not be read), ``radius`` (the lobe's search disc, degrees;
#: NaN outside the claim), ``seconds`` (a tile's mean sweep
#: time), ``views`` (rendered: not e = 0, 180), ``views_per_second`` (the mean over tiles of a sweep's).
CONVERGENCE_COLUMNS = ["kind", "discs", "truncation", "aspect", "incidence", "cells", "seeds", "statistic", "lobe",
                       "unit", "value", "se", "why", "radius", "seconds", "views", "views_per_second"]
#: Each followed statistic's lobe and unit.
STATISTIC_UNITS = {**{name: (lobe, unit) for name, (lobe, _, unit) in STATISTICS.items()},
                   "diffuse_level": ("diffuse", "0-255")}


def _sweep_frame(surface, incidence, azimuth, elevation, lighting, settings, method="fast"):
    from ..study.tables import sweep_table

    result = methods.sweep(method, surface, incidence, azimuth, elevation, lighting, settings)
    frame = sweep_table(result, surface, incidence, azimuth, elevation, lighting, method,
                        methods.recorded(method, settings, surface)).to_pandas()
    return frame, result


#: A sweep frame's columns as the study table names them (what :func:`claim_readings.seed_stacks` reads).
_STUDY_NAMES = {"value": "rough", "value_unrounded": "rough_unrounded", "value_unshadowed": "rough_unshadowed"}
_STACK_COLUMNS = ["kind", "seed", "truncation", "aspect", "incidence", "azimuth", "elevation", "component", "coverage",
                  *_STUDY_NAMES.values()]


def _stack(frames: list[pd.DataFrame]):
    """One surface's sweeps (a tile a frame, every tile on the same views) as a
    :class:`~roughlight.analysis.claim_readings.SeedStack`."""
    from ..analysis.claim_readings import seed_stacks

    rows = pd.concat([f.rename(columns=_STUDY_NAMES)[_STACK_COLUMNS] for f in frames], ignore_index=True)
    (stack,) = seed_stacks(rows)
    return stack


def diffuse_level(stack, reading: str = "unrounded") -> float:
    """The solid-angle-weighted hemisphere mean of the diffuse of the mean of ``stack``'s tiles over the rendered
    views (coverage > 0), 0-255: :func:`roughlight.analysis.diffuse.diffuse_levels`' level of the mean surface."""
    from ..study.selection import solid_angle_weights

    values = stack.diffuse[reading].mean(axis=0)
    weights = solid_angle_weights(stack.azimuth, stack.elevation)
    seen = (stack.coverage > 0) & np.isfinite(values)
    return float(np.sum(weights[seen] * values[seen]) / np.sum(weights[seen])) if seen.any() else np.nan


def _readings(stack, centres: dict, radii: dict) -> dict:
    """:func:`claim_readings.pooled_readings` of the mean of ``stack``'s tiles (unrounded) with its diffuse level
    and that level's jackknife standard error over seeds."""
    from ..analysis.claim_readings import jackknife, pooled_readings

    out = pooled_readings(stack, centres, radii, "unrounded")
    out["diffuse_level"] = diffuse_level(stack)
    n = len(stack)
    out["diffuse_level_se"] = (jackknife([diffuse_level(stack.subset(np.arange(n) != k)) for k in range(n)])
                               if n >= 2 else np.nan)
    out["diffuse_why"] = ""
    return out


def tile_convergence(plan: str = "quick", lighting=None, settings=None, log=None, surface=None) -> pd.DataFrame:
    """The random-roughness claim's statistics of each random kind's mean surface against tile size (cells a
    side), and of the regular surface in the same discs, at the plan's grid point (``point``: t 1, a 0.5, i 30,
    where both the back lobe and the hot spot enter the claim at the default light).

    For each kind and tile size, the plan's seeds are swept on the plan's views (the study's grid, 1 x 5 degrees,
    but at the smoke plan) and their mean surface is read as the claim reads a tested ensemble
    (:func:`roughlight.analysis.claim_readings.pooled_readings`, the unrounded reading, with the delete-one
    jackknife standard error over seeds), with the diffuse's hemisphere level. Every tile size is read in the same
    discs, the claim's (:func:`roughlight.analysis.claims.discs`, on the regular surface's geometry from
    :func:`roughlight.analysis.claims.claim_geometry`). A lobe outside the claim is not read (NaN, ``why`` says
    why).

    Parameters
    ----------
    plan : a name of :data:`PLANS`
    lighting : Lighting (default: the default light)
    settings : the fast method's settings (its knobs for random tiles among them)
    log : callable taking a line, optional
    surface : how the study builds tiles (``surface.cells``, ``surface.spread``:
        :func:`roughlight.study.config.random_surface_settings`; default 4 cells, the default spread)

    Returns
    -------
    DataFrame, a row per kind, tile size and statistic (:data:`CONVERGENCE_STATISTICS`): :data:`CONVERGENCE_COLUMNS`.
    """
    from ..analysis.claim_readings import lobe_centres
    from ..analysis.claims import claim_geometry, discs
    from ..render.shading import Lighting
    from ..render.views import view_grid

    p = comparison.plan_size(PLANS, plan, "random tiles")
    log, lighting, settings = log or (lambda message: None), lighting or Lighting(), methods.settings("fast", settings)
    surface = {"cells": DEFAULT_CELLS, "spread": None, **(surface or {})}
    azimuth, elevation = view_grid(*p["views"])
    kinds, sizes = tuple(p.get("kinds", RANDOM_KINDS)), sorted(set(p["cells"]))

    def measure(kind, cells, seeds):
        return _swept_stack(kind, cells, seeds, p["point"], surface["spread"], (azimuth, elevation), lighting,
                            settings, log)

    regular = measure("pyramids", 0, [0])
    ensembles = {(kind, cells): measure(kind, cells, range(1, int(p["seeds"]) + 1)) for kind in kinds
                 for cells in sizes}
    geometry = claim_geometry([regular[0]], lighting.as_dict())
    disc = discs(geometry, regular[0].key)
    out = dict(geometry=geometry, centres=lobe_centres(regular[0].key),
               views=int(np.count_nonzero((elevation > 0) & (elevation < 180))))  # rendered: not e = 0, 180
    rows = []
    for kind in kinds:
        for name, cells, (stack, seconds) in [("pyramids", 0, regular)] + [(kind, c, ensembles[kind, c])
                                                                           for c in sizes]:
            rows += _convergence_rows(name, kind, cells, stack, seconds, disc, **out)
        log(f"{kind}: discs {', '.join(f'{k} {v:.1f} deg' for k, v in disc.items())}")
    return pd.DataFrame(rows, columns=CONVERGENCE_COLUMNS)


def _swept_stack(kind, cells, seeds, point, spread, views, lighting, settings, log):
    """One kind's tiles of ``cells`` a side (the regular surface: ``pyramids``, seed 0) at ``point`` swept on
    ``views`` (azimuth, elevation): their :class:`~roughlight.analysis.claim_readings.SeedStack` and each sweep's
    seconds."""
    t, a, i = point
    frames, seconds = [], []
    for seed in seeds:
        tile = make_surface(kind, t, a, seed, cells=max(cells, 1), spread=spread)
        frame, result = _sweep_frame(tile, i, *views, lighting, settings)
        frames.append(frame)
        seconds.append(float(result["seconds"]))
        rendered = int(np.count_nonzero((views[1] > 0) & (views[1] < 180)))  # not the grazing e = 0, 180
        log(f"{kind} cells={cells} seed={seed}: {rendered} views in {result['seconds']:.2f} s")
    return _stack(frames), np.asarray(seconds)


def _convergence_rows(kind, discs, cells, stack, seconds, disc, geometry, centres, views) -> list:
    """:func:`tile_convergence`'s rows of one surface (``kind``; ``cells`` 0: the regular one) read in ``discs``'
    discs (``disc``: lobe -> radius, degrees; a lobe without one is outside the claim, ``geometry`` says why)."""
    t, a, i = stack.key
    reading = _readings(stack, centres, disc)
    out_of_claim = dict(zip(geometry["lobe"], geometry["why"]))
    rows = []
    for statistic in CONVERGENCE_STATISTICS:
        lobe, unit = STATISTIC_UNITS[statistic]
        why = reading.get(f"{lobe}_why", "")
        if lobe != "diffuse" and lobe not in disc:
            why = f"not in the claim at t {t:g}, a {a:g}, i {i:g}: {out_of_claim.get(lobe, '')}"
        rows.append({"kind": kind, "discs": discs, "truncation": t, "aspect": a, "incidence": i, "cells": cells,
                     "seeds": len(stack), "statistic": statistic, "lobe": lobe, "unit": unit,
                     "value": float(reading[statistic]), "se": float(reading.get(f"{statistic}_se", np.nan)),
                     "why": why or "", "radius": disc.get(lobe, np.nan),
                     "seconds": float(seconds.mean()), "views": views,
                     "views_per_second": float(np.mean(views / seconds))})
    return rows


def convergence_summary(convergence: pd.DataFrame, level: float = 0.95) -> pd.DataFrame:
    """Each followed statistic (:data:`CONVERGENCE_STATISTICS`) of each kind's mean surface by tile size, with its
    jackknife standard error over seeds and the Student-t interval at ``level`` on it (``n - 1`` degrees of
    freedom, cut to the statistic's range), beside the regular surface's value in the same discs, and the fast
    renderer's views per second (random and regular).

    Parameters
    ----------
    convergence : :func:`tile_convergence`

    Returns
    -------
    DataFrame, a row per kind, tile size and statistic: ``kind``, ``cells``, ``statistic``, ``unit``, ``seeds``,
    ``value``, ``se``, ``low``, ``high`` (NaN without an SE), ``regular``, ``why`` ('' or why there is no value or
    no error), ``radius``,
    ``views_per_second``, ``regular_views_per_second``.
    """
    from scipy import stats as sps

    regular = convergence[convergence["kind"] == "pyramids"].set_index(["discs", "statistic"])
    rows = []
    random = convergence[(convergence["kind"] != "pyramids")
                         & convergence["statistic"].isin(CONVERGENCE_STATISTICS)]
    for r in random.itertuples(index=False):
        n, value, se = int(r.seeds), float(r.value), float(r.se)
        low = high = np.nan
        if n >= 2 and np.isfinite(value) and np.isfinite(se):
            half = float(sps.t.ppf(0.5 + level / 2, n - 1) * se)
            lo, hi = STATISTIC_RANGES.get(r.statistic, (-math.inf, math.inf))
            low, high = max(lo, value - half), min(hi, value + half)
        key = (r.kind, r.statistic)
        why = r.why if not np.isfinite(value) else ""
        if np.isfinite(value) and n >= 2 and not np.isfinite(se):
            why = "no error: with a seed left out, the lobe could not be read"
        rows.append({"kind": r.kind, "cells": int(r.cells), "statistic": r.statistic, "unit": r.unit, "seeds": n,
                     "value": value, "se": se, "low": low, "high": high,
                     "regular": float(regular["value"].get(key, np.nan)), "why": why, "radius": float(r.radius),
                     "views_per_second": float(r.views_per_second),
                     "regular_views_per_second": float(regular["views_per_second"].get(key, np.nan))})
    columns = ["kind", "cells", "statistic", "unit", "seeds", "value", "se", "low", "high", "regular", "why", "radius",
               "views_per_second", "regular_views_per_second"]
    return pd.DataFrame(rows, columns=columns)


def random_accuracy(plan: str = "quick", lighting=None, settings=None, log=None) -> pd.DataFrame:
    """The fast renderer against the exact reference on random tiles (and the regular surface at the same point).

    Returns
    -------
    DataFrame, one row per surface x component: ``kind``, ``truncation``, ``aspect``, ``cells``, ``seed``,
    ``component``, ``views``
    (compared: rendered, each once, the zenith once and not once per azimuth), ``reference_refused`` (views the
    reference's own checks refused, left out), ``mae``, ``p99``,
    ``worst`` (0-255), ``fast_views_per_second``, ``reference_seconds``.
    """
    from ..render.exact import reference_views
    from ..render.shading import Lighting
    from ..render.views import view_grid

    p = comparison.plan_size(PLANS, plan, "random tiles")
    log = log or (lambda message: None)
    lighting = lighting or Lighting()
    settings = methods.settings("fast", settings)
    i = p["point"][2]
    azimuth, elevation = view_grid(*p["accuracy_views"])
    rendered = np.sin(np.radians(elevation)) > 1e-9
    seen = distinct_views(azimuth, elevation)
    runs = [("pyramids", t, a, 1, 0) for t, a in p["accuracy_points"]]
    runs += [(kind, t, a, p["accuracy_cells"], seed) for kind in RANDOM_KINDS for t, a in p["accuracy_points"]
             for seed in range(1, p["accuracy_seeds"] + 1)]
    rows = []
    for kind, t, a, cells, seed in runs:
        surface = make_surface(kind, t, a, seed, cells=cells)
        start = time.perf_counter()
        # a view the reference's own checks refuse is left out and counted
        exact, refused = reference_views(surface, i, azimuth, elevation, lighting)
        reference_seconds = time.perf_counter() - start
        fast = methods.sweep("fast", surface, i, azimuth, elevation, lighting, settings)
        compared = seen & ~refused
        for component, error in comparison.absolute_errors(fast, exact, compared).items():
            rows.append({"kind": kind, "truncation": t, "aspect": a, "cells": cells if kind != "pyramids" else 0,
                         "seed": seed,
                         "component": component, "views": int(compared.sum()),
                         "reference_refused": int((seen & refused).sum()), **comparison.error_statistics(error),
                         "fast_views_per_second": int(rendered.sum()) / fast["seconds"],  # the rendered views
                         "reference_seconds": reference_seconds})
        log(f"accuracy {kind} t={t} a={a} cells={cells} seed={seed}: total MAE {rows[-1]['mae']:.3f}, "
            f"worst {rows[-1]['worst']:.2f}; reference {reference_seconds:.1f} s")
    return pd.DataFrame(rows)


def every_view_errors(sweep: pd.DataFrame, surface, incidence: float, lighting=None) -> pd.DataFrame:
    """A study sweep (rule ``random_sweeps``'s long frame) against the exact reference at every one of its views.

    Parameters
    ----------
    sweep : DataFrame
        ``azimuth``, ``elevation`` (degrees), ``component``, ``value`` (0-255) and the surface's ``kind``,
        ``truncation``, ``aspect``, ``seed``.
    surface : RandomSurface or Surface
        The surface the sweep measured.
    incidence : float
        Light elevation, degrees.
    lighting : Lighting

    Returns
    -------
    DataFrame, one row a view and component: ``kind``, ``truncation``, ``aspect``, ``seed``, ``azimuth``,
    ``elevation``, ``component``, ``fast``, ``exact`` (0-255; NaN where the reference refused the view), ``error``
    (absolute, 8-bit levels), ``reference_seconds`` (the reference's wall time for the whole sweep).
    """
    from ..render.exact import reference_views
    from ..render.shading import COMPONENTS, Lighting

    views = sweep.drop_duplicates(["azimuth", "elevation"])[["azimuth", "elevation"]].reset_index(drop=True)
    start = time.perf_counter()
    exact, _ = reference_views(surface, incidence, views["azimuth"].to_numpy(), views["elevation"].to_numpy(),
                               lighting or Lighting())
    seconds = time.perf_counter() - start
    reference = pd.concat([views.assign(component=c, exact=np.asarray(exact[c], float)) for c in COMPONENTS])
    keys = ["azimuth", "elevation", "component"]
    fast = sweep.assign(component=sweep["component"].astype(str))[["kind", "truncation", "aspect", "seed", *keys,
                                                                    "value"]]
    out = fast.rename(columns={"value": "fast"}).merge(reference, on=keys, how="left", validate="one_to_one")
    out["kind"] = out["kind"].astype(str)
    out["error"] = (out["fast"] - out["exact"]).abs()
    out["reference_seconds"] = seconds
    return out.reset_index(drop=True)


def every_view_summary(errors: pd.DataFrame) -> pd.DataFrame:
    """Per tile and component: views compared (the rendered ones: elevations strictly between 0 and 180, each once:
    the zenith once, not once per azimuth), views the reference refused, mean and worst error (8-bit levels),
    where the worst is, views over one level, and the reference's seconds. Component ``all`` takes each view's
    largest error over the three components.

    Parameters
    ----------
    errors : DataFrame
        :func:`every_view_errors` of one or more tiles, concatenated.
    """
    tile = ["kind", "truncation", "aspect", "seed"]
    rows = []
    for key, group in pd.concat([errors, errors.assign(component="all")]).groupby([*tile, "component"]):
        # the views that were rendered only: at elevation 0 and 180 (coverage 0) both sides hold 0, no view at all
        rendered = group[(group["elevation"] > 0) & (group["elevation"] < 180)]
        view = rendered.groupby(["elevation", "azimuth"]).agg(error=("error", "max"),
                                                               refused=("exact", lambda x: bool(x.isna().any())))
        view = view[distinct_views(view.index.get_level_values("azimuth"), view.index.get_level_values("elevation"))]
        seen = view.loc[~view["refused"], "error"]
        worst = seen.idxmax() if len(seen) else (np.nan, np.nan)
        statistics = comparison.error_statistics(seen.to_numpy(float), ("mae", "worst")) if len(seen) \
            else {"mae": np.nan, "worst": np.nan}
        rows.append({**dict(zip([*tile, "component"], key)), "views": int(seen.size),
                     "refused": int(view["refused"].sum()), **statistics,
                     "worst_elevation": float(worst[0]), "worst_azimuth": float(worst[1]),
                     "views_over_one_level": int((seen > 1.0).sum()),
                     "reference_seconds": float(group["reference_seconds"].iloc[0])})
    return pd.DataFrame(rows)


#: The thesis's telling views for the pictures: (incidence, elevation, azimuth, label).
PICTURE_VIEWS = ((30.0, 20.0, 60.0, "Fig. 9's view: e 20, phi 60"),
                 (30.0, 150.0, 0.0, "forward mirror: e 150, phi 0"),
                 (30.0, 60.0, 30.0, "off the light's plane: e 60, phi 30"))


def random_pictures(plan: str = "quick", lighting=None, cells: int = 4) -> list:
    """Pictures of each kind as rendered (finite patches,
    :func:`roughlight.render.naive.procedure.render_picture`) at the thesis's telling views, the same width of
    surface for every kind (8 cells across).

    Returns
    -------
    list of (label, (H, W, 3) uint8 image), kinds by rows and views by columns.
    """
    from ..render.naive import render_picture

    t, a, _ = comparison.plan_size(PLANS, plan, "random tiles")["point"]
    out = []
    for kind in ("pyramids",) + RANDOM_KINDS:
        surface = make_surface(kind, t, a, 0 if kind == "pyramids" else 1, cells=cells)
        periods = 8 if kind == "pyramids" else max(1, 8 // cells)
        for i, e, phi, label in PICTURE_VIEWS:
            image = render_picture(surface, i, e, phi, lighting=lighting, size=(240, 180), periods=periods)
            out.append((f"{kind.replace('_', ' ')}: {label}", np.asarray(image)))
    return out


#: The samplings the tile scan compares: the default (adaptive: regions counted on the CPU) and the shader's
#: tile mean (lattice), each at its own densities a cell.
TILE_SAMPLINGS = ("adaptive", "lattice")


def tile_method(kind: str, sampling: str) -> str:
    """The ``method`` label of a tile scan's rows, e.g. ``fast tiles (random pyramids, adaptive)``."""
    return f"fast tiles ({kind.replace('_', ' ')}, {sampling})"


def tile_pixel_scan(kinds=RANDOM_KINDS, pixels=(4, 8, 12, 16, 24), samplings=TILE_SAMPLINGS, point=(1.0, 1.0, 30.0),
                    seed: int = 1, cells: int = 4, views=(15.0, 30.0), lighting=None) -> pd.DataFrame:
    """Where the random tiles' sampling fails: the error against the exact reference against pixels a cell, for
    each random kind and sampling (a row set of ``roughlight.measurements.stability``'s long frame, experiment
    ``tile_pixels``, ``method`` :func:`tile_method`).

    Parameters
    ----------
    kinds : random kinds measured, one tile each (``seed``, ``cells`` cells a side, at the grid point ``point``
        (truncation, aspect, incidence))
    pixels : pixels a cell (``render.random_tiles.pixels_per_period``)
    views : (elevation step, azimuth step), degrees
    """
    from ..render.shading import Lighting
    from ..render.views import view_grid

    lighting = lighting or Lighting()
    t, a, i = point
    azimuth, elevation = view_grid(*views)
    seen = distinct_views(azimuth, elevation)  # rendered, each once: the zenith once, not once per azimuth
    rows = []
    for kind in kinds:
        tile = make_surface(kind, t, a, seed, cells=cells)
        exact = comparison.reference(tile, i, azimuth, elevation, lighting)
        for sampling in samplings:
            for p in pixels:
                settings = methods.settings("fast", {"tile_sampling": sampling, "tile_pixels_per_period": int(p)})
                fast = methods.sweep("fast", tile, i, azimuth, elevation, lighting, settings)
                for component, error in comparison.absolute_errors(fast, exact, seen).items():
                    statistics = comparison.error_statistics(error, ("mae", "worst"))
                    for metric, value in (("mae", statistics["mae"]), ("max_error", statistics["worst"])):
                        rows.append({"experiment": "tile_pixels", "method": tile_method(kind, sampling),
                                     "variable": "pixels_per_cell", "x": float(p), "setting": "",
                                     "component": component, "metric": metric, "value": float(value)})
    return pd.DataFrame(rows)
