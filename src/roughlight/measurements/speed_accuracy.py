"""Speed against accuracy: every method and setting on one fixed set of views.

The benchmark measures, in one process, each method's views per second and
its error against the exact reference on the same surfaces and views, and
charts error against time per view (log scales) with the Pareto front.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from functools import partial

import numpy as np

from ..render import methods, shading
from ..render.shading import COMPONENTS
from ..render.views import distinct_views
from ..surfaces.roughness import RANDOM_KINDS, make_surface
from ..surfaces.surface import SQRT3_2, Surface
from . import comparison

__all__ = [
    "BENCH_SURFACES",
    "bench_views",
    "Config",
    "default_configs",
    "quick_configs",
    "PLANS",
    "tile_configs",
    "tile_surfaces",
    "run_benchmark",
    "pareto_front",
]

#: Surfaces under a light (Surface, incidence) spread over the grid: low and tall,
#: truncated and full, the thesis's aspect 1 and the 30-degree facets of sqrt(3)/2.
BENCH_SURFACES = (
    (Surface(0.2, 0.3), 30.0),
    (Surface(0.5, 1.0), 30.0),
    (Surface(0.8, SQRT3_2), 30.0),
    (Surface(1.0, 1.0), 30.0),
    (Surface(1.0, 0.5), 60.0),
    (Surface(0.3, 0.7), 15.0),
)


def bench_views(elevation_step: float = 5.0, azimuth_step: float = 20.0):
    """The fixed views: elevation 10..170 deg, azimuth 0..<180 deg (degrees)."""
    el = np.arange(10.0, 170.0 + 1e-9, elevation_step)
    az = np.arange(0.0, 180.0 - 1e-9, azimuth_step)
    a, e = np.meshgrid(az, el, indexing="ij")
    return a.ravel(), e.ravel()


@dataclass(frozen=True)
class Config:
    """One method with its settings."""

    method: str
    settings: dict = field(default_factory=dict)

    @property
    def tiles(self) -> bool:
        """True for a random tiles' config (its settings are the tile ones: ``tile_sampling``, ...)."""
        return self.method == "fast" and "tile_sampling" in self.settings

    @property
    def label(self) -> str:
        if self.tiles:
            return f"fast tiles {self.settings['tile_sampling']} P={self.settings.get('tile_pixels_per_period')}/cell"
        if self.method == "fast":
            s = self.settings
            return f"fast {s.get('sampling', 'lattice')} P={s.get('pixels_per_period')} S={s.get('shadow_map_size')}" + (
                f" bias={s['shadow_bias']:g}" if "shadow_bias" in s else ""
            )
        if self.method == "naive":
            return "naive (thesis: 400x300, central 40x40)"
        if self.method == "implicit_exact":
            return "implicit quad: exact form (ray cast)"
        if self.method == "implicit_correction":
            return "implicit quad: first-order correction"
        if self.method == "implicit_clipped":
            return "implicit quad: clipped scene (shares in C)"
        return self.method


def default_configs() -> list[Config]:
    """The naive baseline, the reference, and the fast method's knobs."""
    configs = [Config("naive"), Config("reference"), Config("implicit_exact"), Config("implicit_correction"),
               Config("implicit_clipped")]
    for sampling in ("lattice", "grid"):
        for pixels in (8, 12, 16, 24, 32, 48, 64):
            configs.append(Config("fast", {"sampling": sampling, "pixels_per_period": pixels, "shadow_map_size": 512}))
    for pixels in (16, 20, 24, 28, 32):
        configs.append(Config("fast", {"sampling": "adaptive", "pixels_per_period": pixels, "shadow_map_size": 512}))
    for size in (32, 128, 2048):
        configs.append(Config("fast", {"sampling": "lattice", "pixels_per_period": 24, "shadow_map_size": size}))
    for bias in (0.0, 1e-2):
        configs.append(Config("fast", {"sampling": "lattice", "pixels_per_period": 24, "shadow_map_size": 512,
                                       "shadow_bias": bias}))
    return configs


def quick_configs() -> list[Config]:
    """A few of :func:`default_configs`: the naive baseline, the reference and the fast method's
    pixels per period around the default, lattice and grid (the default workflow's chart)."""
    configs = [Config("naive"), Config("reference"), Config("implicit_exact"), Config("implicit_correction"),
               Config("implicit_clipped")]
    for pixels in (8, 16, 24, 32):
        configs.append(Config("fast", {"sampling": "lattice", "pixels_per_period": pixels, "shadow_map_size": 512}))
    configs.append(Config("fast", {"sampling": "grid", "pixels_per_period": 24, "shadow_map_size": 512}))
    for pixels in (24, 28):
        configs.append(Config("fast", {"sampling": "adaptive", "pixels_per_period": pixels, "shadow_map_size": 512}))
    return configs


def tile_configs(adaptive=(8, 16, 24), lattice=(16, 24)) -> list[Config]:
    """The random tiles' fast configs: adaptive sampling (counted on the CPU, the default) and lattice sampling
    (the shader's tile mean) at these pixels a cell."""
    return ([Config("fast", {"tile_sampling": "adaptive", "tile_pixels_per_period": p}) for p in adaptive]
            + [Config("fast", {"tile_sampling": "lattice", "tile_pixels_per_period": p}) for p in lattice])


def tile_surfaces(kinds=RANDOM_KINDS, point=(1.0, 1.0, 30.0), seed: int = 1) -> tuple:
    """One random tile of each kind (the study's 4 cells) at ``point`` (truncation, aspect, incidence)."""
    t, a, i = point
    return tuple((make_surface(kind, t, a, seed), i) for kind in kinds)


#: Sizes of the benchmark, by name (``measurements.plan`` in the config): ``full`` is
#: ``make bench``'s measurement; ``quick`` the same code on fewer configs, surfaces and views,
#: sized for the default workflow's chart; ``smoke`` quick's configs on one surface and a few views (a check that a
#: config builds the whole report, in seconds; its numbers are not for reading).
PLANS = {
    "full": {"configs": default_configs, "surfaces": BENCH_SURFACES, "views": (5.0, 20.0), "repeats": 3,
             "tiles": {"configs": partial(tile_configs, (8, 12, 16, 24, 32), (8, 16, 24, 32)), "kinds": RANDOM_KINDS}},
    "quick": {"configs": quick_configs, "surfaces": BENCH_SURFACES[1:4:2], "views": (20.0, 45.0), "repeats": 1,
              "tiles": {"configs": partial(tile_configs, (8, 16), (16,)), "kinds": ("random_pyramids",)}},
    "smoke": {"configs": quick_configs, "surfaces": BENCH_SURFACES[1:2], "views": (40.0, 90.0), "repeats": 1,
              "tiles": {"configs": partial(tile_configs, (8, 16), (16,)), "kinds": ("random_pyramids",)}},
}


def _settings(config: Config):
    """The settings of a config's method (:func:`roughlight.render.methods.settings`)."""
    return methods.settings(config.method, config.settings)


def _measure(config: Config, lit_surface, azimuth, elevation, lighting):
    surface, incidence = lit_surface
    return methods.sweep(config.method, surface, incidence, azimuth, elevation, lighting, _settings(config))


def run_plan(plan: str = "full", lighting=None, log=None):
    """The benchmark at one of the sizes of :data:`PLANS`."""
    import pandas as pd

    size = comparison.plan_size(PLANS, plan, "benchmark")
    views = bench_views(*size["views"])
    table = _measured(size["configs"](), size["surfaces"], views, lighting, log, size["repeats"])
    tiles = size.get("tiles")
    if tiles:  # the random tiles' samplings, on tiles of their own (their Pareto front apart)
        tile_table = _measured(tiles["configs"](), tile_surfaces(tiles["kinds"]), views, lighting, log,
                               size["repeats"])
        table = pd.concat([table, tile_table], ignore_index=True)
    return _with_comparisons(table)


def run_benchmark(configs=None, surfaces=BENCH_SURFACES, views=None, lighting=None, log=None, repeats=3):
    """Run every config on every surface and view; errors against the reference.

    Parameters
    ----------
    configs : list of Config (default :func:`default_configs`)
    surfaces : sequence of (Surface, incidence)
    views : (azimuth, elevation) arrays, degrees (default :func:`bench_views`)
    lighting : shading.Lighting
    log : callable, optional
    repeats : int
        Timed runs of each fast config (the fastest counts: the machine's other
        load only ever slows a run down); the slow methods run once.

    Returns
    -------
    pandas.DataFrame, one row per config x component: method ("fast tiles" for a random tiles' config), label,
    settings columns (sampling, pixels_per_period, shadow_map_size, shadow_bias; a tile's per cell), n_views
    (the views rendered, whose time is measured), seconds, views_per_second, ms_per_view, mae, max_error (over
    the views, each once: the zenith once, not once per azimuth), component, surfaces ("regular surfaces" or "random
    tiles"), speedup_vs_naive (views per second over the naive method's, same run and surfaces), default (the
    fast method's default settings), pareto (on the front of error against time per view for that component,
    among the same surfaces).
    """
    return _with_comparisons(_measured(configs, surfaces, views, lighting, log, repeats))


def _measured(configs, surfaces, views, lighting, log, repeats):
    """:func:`run_benchmark`'s rows before the comparisons, each with ``surfaces``: "random tiles" when the
    surfaces are random tiles, else "regular surfaces"."""
    import pandas as pd

    configs = list(configs or default_configs())
    lighting = lighting or shading.Lighting()
    log = log or (lambda message: None)
    azimuth, elevation = views if views is not None else bench_views()
    exact = [comparison.reference(surface, i, azimuth, elevation, lighting) for (surface, i) in surfaces]
    n_views = len(surfaces) * azimuth.size
    rows = []
    for config in configs:
        seconds, errors = _timed_errors(config, surfaces, exact, azimuth, elevation, lighting, repeats)
        log(f"{config.label}: {n_views / seconds:.0f} views/s")
        rows += _config_rows(config, seconds, errors, n_views)
    table = pd.DataFrame(rows)
    table["surfaces"] = "random tiles" if hasattr(surfaces[0][0], "cells") else "regular surfaces"
    return table


def _timed_errors(config: Config, surfaces, exact, azimuth, elevation, lighting, repeats: int):
    """Time ``config`` on every surface (after a warm-up run: context, layout, shaders; the naive method's on one
    view), ``repeats`` times for the fast method and once for the others.

    Returns
    -------
    seconds : float, the fastest run's wall time over all surfaces
    errors : dict component -> array, ``|value - exact|`` (0-255) over every surface's views, each view once (the
        zenith once, not once per azimuth: :func:`roughlight.render.views.distinct_views`;
        :func:`roughlight.measurements.comparison.pooled_errors`), of the last run
    """
    # warm up: context, layout, shaders. The naive method draws a view at a time (its warm-up is its first view:
    # a whole sweep took 2 s of the quick plan's 20); the others lay out the whole sweep at once.
    views = slice(0, 1) if config.method == "naive" else slice(None)
    _measure(config, surfaces[0], azimuth[views], elevation[views], lighting)
    runs = []
    for _ in range(repeats if config.method == "fast" else 1):
        seconds = 0.0
        outputs = []
        for surface in surfaces:
            start = time.perf_counter()
            outputs.append(_measure(config, surface, azimuth, elevation, lighting))
            seconds += time.perf_counter() - start
        runs.append(seconds)
    return min(runs), comparison.pooled_errors(zip(outputs, exact), distinct_views(azimuth, elevation))


def _config_rows(config: Config, seconds: float, errors: dict, n_views: int) -> list[dict]:
    """:func:`run_benchmark`'s rows of one config, one a component: its recorded settings, speed and errors."""
    settings = _settings(config)
    recorded = methods.recorded(config.method, settings.tile_settings() if config.tiles else settings)
    rows = []
    for c in COMPONENTS:
        statistics = comparison.error_statistics(errors[c], ("mae", "worst"))
        rows.append(
            {
                "method": "fast tiles" if config.tiles else config.method,
                "label": config.label,
                **recorded,
                "shadow_bias": config.settings.get(
                    "shadow_bias", methods.settings("fast").shadow_bias if config.method == "fast" else np.nan),
                "component": c,
                "n_views": n_views,
                "seconds": seconds,
                "views_per_second": n_views / seconds,
                "ms_per_view": 1000.0 * seconds / n_views,
                "mae": statistics["mae"],
                "max_error": statistics["worst"],
            }
        )
    return rows


def _with_comparisons(table):
    """Add to the benchmark's table ``speedup_vs_naive``, ``default`` (the fast method's default settings) and
    ``pareto`` (on each component's front of error against time per view)."""
    defaults = methods.settings("fast")
    default = Config("fast", {"sampling": defaults.sampling, "pixels_per_period": defaults.pixels_per_period,
                              "shadow_map_size": defaults.shadow_map_size}).label
    if "surfaces" not in table:
        table["surfaces"] = "regular surfaces"
    naive = table.loc[table["method"] == "naive", "views_per_second"]
    regular = table["surfaces"] == "regular surfaces"
    table["speedup_vs_naive"] = np.where(regular, table["views_per_second"] / naive.iloc[0], np.nan) if len(naive) \
        else np.nan
    table["default"] = table["label"] == default
    table["pareto"] = False
    for _, group in table.groupby(["component", "surfaces"]):
        table.loc[group.index, "pareto"] = pareto_front(group["ms_per_view"].to_numpy(), group["mae"].to_numpy())
    return table


def pareto_front(cost, error) -> np.ndarray:
    """True for points no other point beats on both cost and error (lower is better)."""
    cost = np.asarray(cost, float)
    error = np.asarray(error, float)
    front = np.ones(len(cost), bool)
    for k in range(len(cost)):
        better_or_equal = (cost <= cost[k]) & (error <= error[k])
        strictly = (cost < cost[k]) | (error < error[k])
        front[k] = not np.any(better_or_equal & strictly)
    return front
