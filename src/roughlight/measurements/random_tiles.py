"""Random tiles measured for the benchmark stage: the tile-size convergence, the fast renderer's accuracy against
the exact reference and its speed beside the regular surface's, and pictures of each kind as rendered.

Plans (``measurements.plan``, the folder ``results/benchmarks/{plan}/``):

* ``quick``: random pyramids in tiles of 1, 2 and 4 cells, 3 seeds, views every 3 x 10 degrees at t = 1,
  a = 1, i = 30 (a random heightfield's sweep costs three times a random pyramids' one: 4-cell tiles 2.5-3.7 s
  where the whole convergence of random pyramids takes about 10 s); accuracy on one 4-cell tile (the study's) of
  each kind at coarse views (30 x 45 degrees).
* ``full`` (``make bench``): both kinds in tiles of 1, 2, 3, 4 and 6 cells, 6 seeds; accuracy on 2 seeds of
  4-cell tiles (the study's default) of each kind at the corners of the default random grid (t 0.5 and 1 x
  a 0.5 and 1: 16 tiles) at 5 x 15 degrees (444 views).
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd

from ..render import methods
from ..render.views import distinct_views
from ..surfaces.roughness import RANDOM_KINDS, make_surface
from . import comparison

__all__ = ["PLANS", "tile_convergence", "convergence_summary", "random_accuracy", "random_pictures",
           "tile_pixel_scan", "TILE_SAMPLINGS", "every_view_errors", "every_view_summary"]

PLANS = {
    "quick": {"point": (1.0, 1.0, 30.0), "kinds": ("random_pyramids",), "cells": (1, 2, 4), "seeds": 3,
              "views": (3.0, 10.0),
              "accuracy_cells": 4, "accuracy_seeds": 1, "accuracy_views": (30.0, 45.0),
              "accuracy_points": ((1.0, 1.0),)},
    # a check that a config builds the whole report, in seconds (its numbers are not for reading)
    "smoke": {"point": (1.0, 1.0, 30.0), "kinds": ("random_pyramids",), "cells": (1, 2), "seeds": 2,
              "views": (10.0, 30.0),
              "accuracy_cells": 2, "accuracy_seeds": 1, "accuracy_views": (45.0, 90.0),
              "accuracy_points": ((1.0, 1.0),)},
    "full": {"point": (1.0, 1.0, 30.0), "kinds": RANDOM_KINDS, "cells": (1, 2, 3, 4, 6), "seeds": 6,
             "views": (1.0, 5.0),
             "accuracy_cells": 4, "accuracy_seeds": 2, "accuracy_views": (5.0, 15.0),
             "accuracy_points": ((0.5, 0.5), (0.5, 1.0), (1.0, 0.5), (1.0, 1.0))},
}
#: The statistics followed against tile size.
CONVERGENCE_STATISTICS = ("back_peak", "back_width", "back_squareness", "diffuse_level", "diffuse_level3")


def _sweep_frame(surface, incidence, azimuth, elevation, lighting, settings, method="fast"):
    from ..study.tables import sweep_table

    result = methods.sweep(method, surface, incidence, azimuth, elevation, lighting, settings)
    frame = sweep_table(result, surface, incidence, azimuth, elevation, lighting, method,
                        methods.recorded(method, settings, surface)).to_pandas()
    return frame, result


def tile_convergence(plan: str = "quick", lighting=None, settings=None, log=None) -> pd.DataFrame:
    """Ensemble statistics of each random kind of the plan against tile size (cells a side), with the regular
    surface.

    Returns
    -------
    DataFrame: ``kind``, ``cells`` (0 for the regular surface), ``seed``, ``statistic``, ``value``,
    ``seconds`` (the sweep's wall time), ``views``, ``views_per_second``.
    """
    from ..analysis.ensembles import seed_statistics
    from ..render.shading import Lighting
    from ..render.views import view_grid
    from ..study.tables import join_controls

    p = comparison.plan_size(PLANS, plan, "random tiles")
    log = log or (lambda message: None)
    lighting = lighting or Lighting()
    settings = methods.settings("fast", settings)
    t, a, i = p["point"]
    azimuth, elevation = view_grid(*p["views"])
    control, _ = _sweep_frame(make_surface(), i, azimuth, elevation, Lighting(**{**lighting.as_dict(), "shadows": False}),
                              settings)
    runs = [("pyramids", 0, 0)] + [(kind, cells, seed) for kind in p.get("kinds", RANDOM_KINDS)
                                   for cells in p["cells"]
                                   for seed in range(1, p["seeds"] + 1)]
    rows = []
    for kind, cells, seed in runs:
        surface = make_surface(kind, t, a, seed, cells=max(cells, 1))
        frame, result = _sweep_frame(surface, i, azimuth, elevation, lighting, settings)
        stats = seed_statistics(join_controls(frame, control))
        views = int(np.count_nonzero((elevation > 0) & (elevation < 180)))  # rendered: not the grazing e = 0, 180
        for _, row in stats.iterrows():
            rows.append({"kind": kind, "cells": cells, "seed": seed, "statistic": row["statistic"],
                         "value": row["value"], "seconds": result["seconds"], "views": views,
                         "views_per_second": views / result["seconds"]})
        log(f"{kind} cells={cells} seed={seed}: {views} views in {result['seconds']:.2f} s")
    return pd.DataFrame(rows)


def convergence_summary(convergence: pd.DataFrame) -> pd.DataFrame:
    """Mean, SD and 95% interval over seeds of each followed statistic (:data:`CONVERGENCE_STATISTICS`) per kind
    and tile size, beside the regular value, and the fast renderer's views per second (random and regular)."""
    from scipy import stats as sps

    regular_rows = convergence[convergence["kind"] == "pyramids"]
    regular = regular_rows.set_index("statistic")["value"]
    regular_speed = float(regular_rows["views_per_second"].mean()) if len(regular_rows) else np.nan
    convergence = convergence[convergence["statistic"].isin(CONVERGENCE_STATISTICS)]
    rows = []
    for (kind, cells, name), g in convergence[convergence["kind"] != "pyramids"].groupby(["kind", "cells", "statistic"]):
        v = g["value"].dropna().to_numpy(float)
        n = len(v)
        half = float(sps.t.ppf(0.975, n - 1) * v.std(ddof=1) / np.sqrt(n)) if n > 1 else np.nan
        rows.append({"kind": kind, "cells": int(cells), "statistic": name, "seeds": n,
                     "mean": float(v.mean()) if n else np.nan, "sd": float(v.std(ddof=1)) if n > 1 else np.nan,
                     "ci_half_width": half, "regular": float(regular.get(name, np.nan)),
                     "views_per_second": float(g["views_per_second"].mean()),
                     "regular_views_per_second": regular_speed})
    return pd.DataFrame(rows)


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
