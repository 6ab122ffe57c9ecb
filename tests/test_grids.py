"""roughlight.analysis.grids: the surface grids and arcs of roughlight.study.selection, value for value."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from roughlight.analysis import grids
from roughlight.study import selection


def synthetic_study(seed: int = 0) -> pd.DataFrame:
    """Three surfaces x 4 azimuths x 7 elevations x 3 components of random values, rows shuffled."""
    rng = np.random.default_rng(seed)
    t, a, az, el, comp = np.meshgrid([0.0, 0.5, 1.0], [1.0], [0.0, 5.0, 45.0, 90.0], np.linspace(0, 180, 7),
                                     np.arange(3), indexing="ij")
    n = t.size
    study = pd.DataFrame({"truncation": t.ravel(), "aspect": a.ravel(), "incidence": 30.0, "azimuth": az.ravel(),
                          "elevation": el.ravel(), "phase": rng.uniform(0, 180, n),
                          "component": np.array(["diffuse", "specular", "total"])[comp.ravel()],
                          "rough": rng.uniform(0, 255, n), "control": rng.uniform(0, 255, n),
                          "coverage": rng.uniform(0, 1, n)})
    return study.iloc[rng.permutation(n)].reset_index(drop=True)


def assert_same_grids(study, component, value):
    old = list(selection.surface_grids(study, component, value))
    new = list(grids.surface_grids(study, component, value))
    assert [g[0] for g in new] == [g[0] for g in old]
    for o, n in zip(old, new):
        for x, y in zip(o[1:], n[1:]):
            assert x.shape == y.shape and x.dtype == y.dtype
            assert np.array_equal(x, y, equal_nan=True) and x.tobytes() == y.tobytes()


@pytest.mark.parametrize("value", ["rough", "control", "coverage"])
def test_surface_grids_equal_the_pivoted_ones(value):
    study = synthetic_study()
    for component in ("diffuse", "specular", "total"):
        assert_same_grids(study, component, value)


def test_surface_grids_with_missing_twice_measured_and_nan_views():
    study = synthetic_study(1)
    assert_same_grids(study.drop(index=[3, 11, 40]), "diffuse", "rough")  # views missing: NaN in the grid
    twice = study.iloc[:30].copy()
    twice["rough"] += 1.0
    assert_same_grids(pd.concat([study, twice], ignore_index=True), "diffuse", "rough")  # pandas' mean
    with_nan = study.copy()
    with_nan.loc[with_nan.index[:5], "rough"] = np.nan
    assert_same_grids(with_nan, "specular", "rough")


def test_surface_value_grids_give_every_column_on_one_grid():
    study = synthetic_study(2)
    out = list(grids.surface_value_grids(study, "total", ("rough", "coverage")))
    for (key, az, el, both), (k2, az2, el2, rough) in zip(out, selection.surface_grids(study, "total", "rough")):
        assert key == k2 and np.array_equal(az, az2) and np.array_equal(el, el2)
        assert np.array_equal(both["rough"], rough)
    with pytest.raises(ValueError, match="no 'glossy' rows"):
        list(grids.surface_value_grids(study, "glossy"))


@pytest.mark.parametrize("azimuth", [0.0, 45.0])
def test_arc_equals_the_selection_arc(azimuth):
    study = synthetic_study(3)
    for component in ("diffuse", "specular"):
        pd.testing.assert_frame_equal(grids.arc(study, component, azimuth),
                                      selection.arc(study, component, azimuth), check_exact=True)
    with pytest.raises(ValueError, match="no views at azimuth"):
        grids.arc(study, "diffuse", 7.0)
