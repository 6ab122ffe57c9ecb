import numpy as np
import pandas as pd

from roughlight.measurements import speed_accuracy as benchmark
from roughlight.report import figures
from roughlight.surfaces.surface import Surface


def test_pareto_front():
    cost = np.array([1.0, 2.0, 3.0, 2.0, 0.5])
    error = np.array([1.0, 0.5, 0.1, 0.8, 5.0])
    assert benchmark.pareto_front(cost, error).tolist() == [True, True, True, False, True]


def test_benchmark_runs_every_method_against_the_reference(tmp_path):
    views = benchmark.bench_views(40.0, 60.0)
    configs = [
        benchmark.Config("naive"),
        benchmark.Config("reference"),
        benchmark.Config("fast", {"sampling": "adaptive", "pixels_per_period": 28, "shadow_map_size": 512}),
        benchmark.Config("fast", {"sampling": "grid", "pixels_per_period": 8, "shadow_map_size": 64}),
    ]
    table = benchmark.run_benchmark(configs, surfaces=[(Surface(0.5, 1.0), 30.0)], views=views, repeats=1)
    assert len(table) == len(configs) * 3
    assert set(table["component"]) == {"diffuse", "specular", "total"}
    ref = table[table["method"] == "reference"]
    assert (ref["mae"] < 1e-6).all()
    fast = table[table["default"]]
    coarse = table[(table["method"] == "fast") & (table["pixels_per_period"] == 8)]
    # finer sampling is more accurate
    assert fast.set_index("component")["mae"]["diffuse"] < coarse.set_index("component")["mae"]["diffuse"]
    assert (table.loc[table["method"] == "fast", "speedup_vs_naive"] > 1).all()
    figures.make("speed_accuracy", tmp_path / "chart.png", table=table)
    assert (tmp_path / "chart.png").stat().st_size > 10_000
    assert isinstance(table, pd.DataFrame)


def test_plans_name_their_sizes():
    assert set(benchmark.PLANS) == {"full", "quick", "smoke"}
    full, quick, smoke = benchmark.PLANS["full"], benchmark.PLANS["quick"], benchmark.PLANS["smoke"]
    assert [c.label for c in full["configs"]()] == [c.label for c in benchmark.default_configs()]
    assert full["surfaces"] == benchmark.BENCH_SURFACES
    assert len(quick["configs"]()) < len(full["configs"]()) and len(quick["surfaces"]) < len(full["surfaces"])
    assert {c.method for c in quick["configs"]()} == {"naive", "reference", "fast", "implicit_exact",
                                                     "implicit_correction", "implicit_clipped"}
    # smoke: every config of quick (the report's section shows each method), on fewer surfaces and views
    assert [c.label for c in smoke["configs"]()] == [c.label for c in quick["configs"]()]
    assert len(smoke["surfaces"]) < len(quick["surfaces"])
    assert len(benchmark.bench_views(*smoke["views"])[0]) < len(benchmark.bench_views(*quick["views"])[0])


def test_random_tiles_samplings_are_charted_on_tiles_of_their_own(tmp_path):
    """The random tiles' configs run on a tile (their own surfaces: their Pareto front apart, no speed-up against a
    naive method measured on other surfaces); the default adaptive sampling beats lattice sampling at the same
    pixels a cell, and both improve with pixels."""
    views = benchmark.bench_views(40.0, 60.0)
    configs = benchmark.tile_configs(adaptive=(8, 16), lattice=(8, 16))
    table = benchmark.run_benchmark(configs, surfaces=benchmark.tile_surfaces(("random_pyramids",)), views=views,
                                    repeats=1)
    assert set(table["method"]) == {"fast tiles"} and set(table["surfaces"]) == {"random tiles"}
    assert table["speedup_vs_naive"].isna().all()
    total = table[table["component"] == "total"].set_index(["sampling", "pixels_per_period"])["mae"]
    assert total[("adaptive", 16)] < total[("adaptive", 8)] and total[("lattice", 16)] < total[("lattice", 8)]
    assert total[("adaptive", 16)] < total[("lattice", 16)]
    assert [c.label for c in configs][:2] == ["fast tiles adaptive P=8/cell", "fast tiles adaptive P=16/cell"]
    quick = benchmark.PLANS["quick"]["tiles"]
    assert {c.settings["tile_sampling"] for c in quick["configs"]()} == {"adaptive", "lattice"}
    figures.make("speed_accuracy", tmp_path / "chart.png", table=table)
    assert (tmp_path / "chart.png").stat().st_size > 10_000
