"""The study table's aggregate (roughlight.study.tables.aggregate) and its Parquet writing (roughlight.atomic)."""

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from roughlight import atomic
from roughlight.render import views as sweeps
from roughlight.render.shading import COMPONENTS, Lighting
from roughlight.render.sweep import EXTRA_KEYS
from roughlight.study.tables import STUDY_COLUMNS, aggregate, write_study
from roughlight.study.tables import sweep_table as make_sweep_table
from roughlight.surfaces.roughness import make_surface

SETTINGS = {"pixels_per_period": 16, "sampling": "adaptive", "shadow_map_size": 128}


def _sweep(surface, incidence, seed):
    azimuth, elevation = sweeps.view_grid(30, 45)
    rng = np.random.default_rng(seed)
    result = {key: rng.uniform(0, 255, azimuth.size) for key in ("diffuse", "specular", "total") + EXTRA_KEYS}
    result.update(coverage=np.ones(azimuth.size), seconds=0.5)
    return make_sweep_table(result, surface, incidence, azimuth, elevation, Lighting(), "fast", SETTINGS)


def _sweep_files(tmp_path):
    """Rough sweeps of three kinds at two incidences, listed in no particular order, and the two controls."""
    surfaces = [make_surface("pyramids", t, a) for t, a in ((1.0, 0.5), (0.5, 1.0), (0.0, 0.2))]
    surfaces += [make_surface(kind, 1.0, 1.0, seed, cells=2) for kind in ("random_heightfield", "random_pyramids")
                 for seed in (2, 1)]
    rough = []
    for n, (surface, incidence) in enumerate([(s, i) for i in (45.0, 30.0) for s in surfaces]):
        rough.append(tmp_path / f"rough{n}.parquet")
        pq.write_table(_sweep(surface, incidence, n), rough[-1])
    control = []
    for incidence in (30.0, 45.0):
        control.append(tmp_path / f"control{incidence}.parquet")
        pq.write_table(_sweep(make_surface("pyramids", 0.0, 0.0), incidence, 100 + int(incidence)), control[-1])
    return rough, control


def _merged_and_sorted(rough_paths, control_paths):
    """The study table as a pandas merge and sort computes it (what ``aggregate`` did before it was built a
    column at a time)."""
    rough = pd.concat([pd.read_parquet(p) for p in rough_paths], ignore_index=True)
    control = pd.concat([pd.read_parquet(p) for p in control_paths], ignore_index=True)
    join = ["incidence", "azimuth", "elevation", "component"]
    control = control[join + ["value", "value_unrounded"]].rename(columns={"value": "control",
                                                                         "value_unrounded": "control_unrounded"})
    for frame in (rough, control):
        frame["component"] = frame["component"].astype(str)
    rough["kind"] = rough["kind"].astype(str)
    rough = rough.rename(columns={"value": "rough", "value_unrounded": "rough_unrounded",
                                  "value_unshadowed": "rough_unshadowed"})
    study = rough.merge(control, on=join, how="left", validate="many_to_one")
    study["component"] = pd.Categorical(study["component"], categories=list(COMPONENTS))
    kind = pd.Categorical(study["kind"], categories=["pyramids", "random_pyramids", "random_heightfield"])
    study = study.assign(_kind=kind).sort_values(
        ["_kind", "seed", "truncation", "aspect", "incidence", "azimuth", "elevation", "component"])
    study = study[STUDY_COLUMNS].reset_index(drop=True)
    study["component"] = study["component"].astype(str)
    return study


def test_the_aggregate_is_the_merged_and_sorted_sweeps(tmp_path):
    rough, control = _sweep_files(tmp_path)
    study = aggregate(rough, control)
    pd.testing.assert_frame_equal(study, _merged_and_sorted(rough, control))
    assert list(study["kind"].unique()) == ["pyramids", "random_pyramids", "random_heightfield"]
    assert study["control"].notna().all() and (study["rough"] != study["control"]).any()
    # written, it is the file a whole-table write gives
    atomic.write_frame(study, tmp_path / "study.parquet")
    pq.write_table(pa.Table.from_pandas(study, preserve_index=False), tmp_path / "whole.parquet", compression="zstd")
    assert (tmp_path / "study.parquet").read_bytes() == (tmp_path / "whole.parquet").read_bytes()


def test_a_view_the_control_lacks_stops_the_aggregate(tmp_path):
    rough, control = _sweep_files(tmp_path)
    with pytest.raises(ValueError, match="no control measurement for .* views"):
        aggregate(rough, control[:1])


def test_frames_are_written_a_row_group_at_a_time(tmp_path, monkeypatch):
    monkeypatch.setattr(atomic, "ROW_GROUP_ROWS", 7)
    frame = pd.DataFrame({"x": np.arange(30.0), "name": [f"v{i % 4}" for i in range(30)],
                          "level": pd.Categorical(["a", "b", "c"] * 10)})
    atomic.write_frame(frame, tmp_path / "frame.parquet")
    assert pq.ParquetFile(tmp_path / "frame.parquet").metadata.num_row_groups == 5
    pd.testing.assert_frame_equal(pd.read_parquet(tmp_path / "frame.parquet"), frame)
    atomic.write_frame(frame.iloc[:0], tmp_path / "empty.parquet")
    assert len(pd.read_parquet(tmp_path / "empty.parquet")) == 0


@pytest.mark.parametrize("group_rows", [7_000, 1_000_000])
def test_the_study_is_written_a_sweep_at_a_time_as_the_whole_table_would_be(tmp_path, monkeypatch, group_rows):
    """write_study never holds the table (issue 35: the study job at 1,063 MB), yet writes the aggregate's file byte
    for byte, row groups cut across sweeps included (7,000 rows: a group ends inside the third of the sweeps)."""
    monkeypatch.setattr(atomic, "ROW_GROUP_ROWS", group_rows)
    rough, control = _sweep_files(tmp_path)
    meta = {"roughlight.renderers": "[]"}
    rows = write_study(rough, control, tmp_path / "streamed.parquet", metadata=meta)
    atomic.write_frame(aggregate(rough, control), tmp_path / "whole.parquet", metadata=meta)
    assert rows == len(pd.read_parquet(tmp_path / "whole.parquet"))
    assert pq.ParquetFile(tmp_path / "streamed.parquet").metadata.num_row_groups == -(-rows // group_rows)
    assert (tmp_path / "streamed.parquet").read_bytes() == (tmp_path / "whole.parquet").read_bytes()


def test_sweeps_of_other_settings_concatenate_as_pandas_does(tmp_path):
    """A sweep drawn with other settings (here lattice sampling) has labels of its own: the column becomes what
    pandas.concat makes of the sweeps, in every row."""
    rough, control = _sweep_files(tmp_path)
    other = _sweep(make_surface("pyramids", 0.2, 0.2), 30.0, 7)
    other = other.set_column(other.schema.get_field_index("sampling"), "sampling",
                             pa.array(["lattice"] * other.num_rows).dictionary_encode())
    pq.write_table(other, tmp_path / "lattice.parquet")
    study = aggregate(rough + [tmp_path / "lattice.parquet"], control)
    expected = pd.concat([pd.read_parquet(p)["sampling"] for p in rough + [tmp_path / "lattice.parquet"]])
    assert study["sampling"].dtype == expected.dtype
    assert sorted(set(study["sampling"].astype(str))) == ["adaptive", "lattice"]


def test_two_sweeps_of_one_surface_and_light_stop_the_study(tmp_path):
    rough, control = _sweep_files(tmp_path)
    with pytest.raises(ValueError, match="measure the same surface under the same light"):
        aggregate(rough + rough[:1], control)


def test_the_means_before_rounding_and_without_shadows_are_joined_as_the_values_are(tmp_path):
    """rough_unrounded and rough_unshadowed are the rough sweep's, control_unrounded its control's at the same view;
    NaN where a sweep holds NaN (a method that cannot give them) and nowhere else."""
    rough, control = _sweep_files(tmp_path)
    lattice = _sweep(make_surface("pyramids", 0.2, 0.2), 30.0, 7)
    for name in ("value_unrounded", "value_unshadowed"):  # as a method averaging 8-bit pixels writes them
        lattice = lattice.set_column(lattice.schema.get_field_index(name), name,
                                     pa.array(np.full(lattice.num_rows, np.nan)))
    pq.write_table(lattice, tmp_path / "lattice.parquet")
    study = aggregate(rough + [tmp_path / "lattice.parquet"], control)
    assert [c for c in STUDY_COLUMNS if c.endswith(("_unrounded", "_unshadowed"))] == [
        "rough_unrounded", "control_unrounded", "rough_unshadowed"]
    nan = (study["truncation"] == 0.2) & (study["aspect"] == 0.2)
    for name in ("rough_unrounded", "rough_unshadowed"):
        assert study[name].dtype == np.float64 and study[name].isna().equals(nan)
    assert study["control_unrounded"].notna().all()
    controls = pd.concat([pd.read_parquet(p) for p in control]).set_index(["incidence", "azimuth", "elevation",
                                                                          "component"])
    at = pd.MultiIndex.from_frame(study[["incidence", "azimuth", "elevation", "component"]])
    np.testing.assert_array_equal(study["control_unrounded"], controls["value_unrounded"].reindex(at))


def test_a_sweep_file_of_an_earlier_format_is_named(tmp_path):
    """A sweep written before the means before rounding existed lacks them: the aggregate says which file and
    what to do, rather than fill a column the method could give (the sweep rules rerun it: SWEEP_FORMAT)."""
    rough, control = _sweep_files(tmp_path)
    old = pq.read_table(rough[0]).drop_columns(["value_unrounded", "value_unshadowed"])
    pq.write_table(old, rough[0])
    with pytest.raises(ValueError, match=r"lacks columns \['value_unrounded', 'value_unshadowed'\]; delete it"):
        aggregate(rough, control)
