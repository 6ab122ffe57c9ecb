"""read_study's columns: only the study columns a job reads (roughlight.analysis.inputs), the same frame."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from roughlight.analysis.inputs import STUDY_COLUMNS
from roughlight.study import tables
from roughlight.study.tables import read_study


def study_file(tmp_path, with_kind=True):
    """A small study table: the regular surface and a random tile, every column of results/study.parquet."""
    rng = np.random.default_rng(0)
    n = 60
    frame = pd.DataFrame({
        "kind": np.repeat(["pyramids", "random_pyramids"], n // 2), "seed": np.repeat([0, 1], n // 2),
        "truncation": 0.5, "aspect": 1.0, "incidence": 30.0, "azimuth": np.tile([0.0, 5.0], n // 2),
        "elevation": np.arange(n, dtype=float), "phase": rng.uniform(0, 180, n),
        "component": np.tile(["diffuse", "specular", "total"], n // 3), "rough": rng.uniform(0, 255, n),
        "control": rng.uniform(0, 255, n), "coverage": 1.0, "rough_unrounded": rng.uniform(0, 255, n),
        "control_unrounded": rng.uniform(0, 255, n), "rough_unshadowed": rng.uniform(0, 255, n), "light": 255.0,
        "ambient": 0.0, "shininess": 64.0,
        "specular_model": pd.Categorical(["phong"] * n), "shadows": True, "specular_shadows": False,
        "method": pd.Categorical(["fast"] * n), "pixels_per_period": 16, "sampling": pd.Categorical(["lattice"] * n),
        "shadow_map_size": 1024, "render_seconds": rng.uniform(0, 1, n)})
    assert list(frame.columns) == tables.STUDY_COLUMNS  # every column, in the table's order
    if not with_kind:
        frame = frame.drop(columns=["kind", "seed"])
    path = tmp_path / "study.parquet"
    frame.to_parquet(path)
    return str(path)


@pytest.mark.parametrize("with_kind", [True, False])
def test_reading_a_jobs_columns_is_reading_all_and_selecting_them(tmp_path, with_kind):
    path = study_file(tmp_path, with_kind)
    for rows in ("regular", "random_points", "regular_points", "all"):
        for columns in STUDY_COLUMNS.values():
            if not with_kind and "kind" in columns:  # a table from before random tiles: analysis_random never runs
                continue
            pd.testing.assert_frame_equal(read_study(path, rows=rows, columns=columns),
                                          read_study(path, rows=rows)[columns], check_exact=True)


def test_a_missing_column_is_named(tmp_path):
    with pytest.raises(KeyError, match="glossiness"):
        read_study(study_file(tmp_path), rows="regular", columns=["rough", "glossiness"])
