"""The measurements' one comparison against the exact reference (roughlight.measurements.comparison): the shared
reference sweeps, the error statistics every table reports, and the plan check."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

from roughlight.measurements import comparison
from roughlight.render import methods
from roughlight.render.shading import COMPONENTS, Lighting
from roughlight.surfaces.surface import Surface

MEASUREMENTS = Path(comparison.__file__).parent


def test_error_statistics_are_the_mean_the_99th_percentile_and_the_largest():
    error = np.arange(101.0)  # 0..100: mean 50, 99th percentile 99, largest 100
    assert comparison.error_statistics(error) == {"mae": 50.0, "p99": 99.0, "worst": 100.0}
    assert comparison.error_statistics(error, ("worst", "mae")) == {"worst": 100.0, "mae": 50.0}
    assert comparison.error_statistics([3, 1, 2], ("mae",)) == {"mae": 2.0}  # integers are read as floats


def test_error_statistics_are_bit_identical_to_the_formulas_the_tables_used():
    """The tables' values must not move by a bit: the mean, np.percentile(99) (and np.quantile(0.99), which the
    random tiles' accuracy used) and the largest, on float64, in view order."""
    error = np.abs(np.random.default_rng(3).normal(0.0, 1.7, 1234))
    stats = comparison.error_statistics(error)
    assert stats["mae"] == float(error.mean()) == float(np.mean(error))
    assert stats["p99"] == float(np.percentile(error, 99)) == float(np.quantile(error, 0.99))
    assert stats["worst"] == float(error.max())


def test_error_statistics_refuse_no_errors_and_unknown_statistics():
    with pytest.raises(ValueError, match="every view was left out"):
        comparison.error_statistics(np.array([]))
    with pytest.raises(ValueError, match="among"):
        comparison.error_statistics([1.0], ("median",))


def test_absolute_errors_of_a_sweep_at_its_seen_views():
    rendered = {"diffuse": np.array([1, 5, 9]), "specular": np.array([0.0, 0.0, 2.0]), "total": np.array([3.0, 2, 1])}
    exact = {"diffuse": np.array([2.0, 5.0, 6.5]), "specular": np.zeros(3), "total": np.array([1.0, 1.0, 1.0])}
    seen = np.array([True, False, True])
    errors = comparison.absolute_errors(rendered, exact, seen)
    assert list(errors) == list(COMPONENTS)
    np.testing.assert_array_equal(errors["diffuse"], [1.0, 2.5])
    np.testing.assert_array_equal(errors["total"], [2.0, 0.0])
    assert all(e.dtype == np.float64 for e in errors.values())
    assert list(comparison.absolute_errors(rendered, exact, components=("total",))) == ["total"]
    np.testing.assert_array_equal(comparison.absolute_errors(rendered, exact)["diffuse"], [1.0, 0.0, 2.5])


def test_pooled_errors_join_the_surfaces_in_order():
    first = ({c: np.array([1.0, 2.0]) for c in COMPONENTS}, {c: np.zeros(2) for c in COMPONENTS})
    second = ({c: np.zeros(1) for c in COMPONENTS}, {c: np.array([4.0]) for c in COMPONENTS})
    pooled = comparison.pooled_errors([first, second])
    for c in COMPONENTS:
        np.testing.assert_array_equal(pooled[c], [1.0, 2.0, 4.0])


def test_the_reference_is_computed_once_and_through_the_registry(monkeypatch):
    """The registry loads the reference's sweep by attribute at call time: a stand-in for it is what the cache
    calls, once per surface, views and lighting; other lighting is another sweep; clear_references forgets."""
    from roughlight.render.exact import reference

    calls = []
    real = reference.reference_sweep

    def counted(*args):
        calls.append(args[0])
        return real(*args)

    monkeypatch.setattr(reference, "reference_sweep", counted)
    comparison.clear_references()
    azimuth, elevation = np.array([0.0, 90.0]), np.array([60.0, 120.0])
    surface = Surface(0.5, 1.0)
    first = comparison.reference(surface, 30.0, azimuth, elevation, Lighting())
    again = comparison.reference(surface, 30, azimuth.copy(), elevation.copy(), Lighting())
    assert again is first and calls == [surface]
    exact = methods.sweep("reference", surface, 30.0, azimuth, elevation, Lighting())
    for c in COMPONENTS:
        np.testing.assert_array_equal(first[c], exact[c])
    comparison.reference(surface, 30.0, azimuth, elevation, Lighting(shininess=8.0))
    assert len(calls) == 3  # the registry's own sweep above, and the other lighting
    comparison.clear_references()
    comparison.reference(surface, 30.0, azimuth, elevation, Lighting())
    assert len(calls) == 4
    comparison.clear_references()


def test_a_plan_is_looked_up_and_an_unknown_one_refused_naming_the_choices():
    plans = {"full": {"n": 2}, "quick": {"n": 1}}
    assert comparison.plan_size(plans, "quick", "stability") == {"n": 1}
    with pytest.raises(ValueError, match="no stability plan 'huge': one of full, quick"):
        comparison.plan_size(plans, "huge", "stability")


@pytest.mark.parametrize("call", [
    "roughlight.measurements.stability:run_measurement('pixels', plan='huge')",
    "roughlight.measurements.speed_accuracy:run_plan('huge')",
    "roughlight.measurements.renderer_validation:validate_renderer('huge')",
    "roughlight.measurements.random_tiles:tile_convergence('huge')",
    "roughlight.measurements.random_tiles:random_accuracy('huge')",
    "roughlight.measurements.implicit_surface:validation('huge')",
])
def test_every_measurement_refuses_an_unknown_plan_before_it_renders(call):
    import importlib

    module, expression = call.split(":")
    with pytest.raises(ValueError, match="plan 'huge': one of"):
        eval(expression, vars(importlib.import_module(module)))


def test_the_measurements_reach_every_method_through_the_registry():
    """No measurement imports a method's sweep function itself (reference_views, which leaves out the views the
    reference refuses, is another function)."""
    sweeps = {"fast_sweep", "naive_sweep", "reference_sweep", "implicit_sweep", "correction_sweep"}
    reaches = []
    for path in sorted(MEASUREMENTS.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            names = [a.name for a in node.names] if isinstance(node, ast.ImportFrom) else []
            if isinstance(node, ast.Attribute):
                names = [node.attr]
            reaches += [f"{path.name}:{node.lineno}: {n}" for n in names if n in sweeps]
    assert not reaches, "direct sweep calls:\n" + "\n".join(reaches)
