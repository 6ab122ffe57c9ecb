"""Share tables whose incidence rows have light azimuth nodes of their own (``export.table.light_azimuth_steps``):
measured, read in numpy and in the shader, written and read back, and the old files of one list still read."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from roughlight.render import methods, shading
from roughlight.render.implicit import tabulate
from roughlight.render.implicit.table import (
    SCALE,
    ShareTable,
    light_slices,
    load_table,
    save_table,
    table_shares,
    table_values,
)
from roughlight.study import config as rl_config
from roughlight.surfaces.surface import Surface

from .conftest import REPO

SURFACE = Surface(0.5, 0.8)
INCIDENCE = [0.0, 20.0, 50.0, 90.0]
#: Each row's own light azimuth nodes: the low rows closer.
ROWS = [[0.0, 45.0], [0.0, 15.0, 30.0, 45.0], [0.0, 22.5, 45.0], [0.0, 45.0]]
ELEVATION = [2.0, 10.0, 35.0, 70.0, 90.0]


@pytest.fixture(scope="module")
def rows_table():
    return tabulate.measure_table(SURFACE, INCIDENCE, ROWS, ELEVATION, 15.0)


def _pairs(incidence, light_azimuth, azimuth, elevation):
    view = shading.view_direction(np.asarray(elevation, float), np.asarray(azimuth, float))
    return np.tile(shading.light_direction(incidence, light_azimuth), (len(view), 1)), view


def test_each_row_holds_its_own_nodes_and_gives_the_reference_there(rows_table):
    """The slices run row by row; a light on a row's own node (incidence 20, azimuth 15: not a node of the other
    rows) and views on the view nodes read the exact reference."""
    assert rows_table.lights == 11 and rows_table.shares.shape == (11, 5, 24, 10)
    assert [row.tolist() for row in rows_table.rows] == ROWS
    assert rows_table.light_azimuth.tolist() == [0.0, 15.0, 22.5, 30.0, 45.0]
    assert rows_table.slice_incidence.tolist() == [0, 0, 20, 20, 20, 20, 50, 50, 50, 90, 90]
    azimuth = np.arange(0.0, 180.0, 15.0)
    for elevation in (10.0, 35.0, 145.0):
        exact = methods.sweep("reference", SURFACE, 20.0, azimuth, np.full(azimuth.size, elevation),
                              light_azimuth=15.0)
        got = table_values(rows_table, *_pairs(20.0, 15.0, azimuth, np.full(azimuth.size, elevation)))
        for component in shading.COMPONENTS:
            assert np.abs(got[component] - exact[component]).max() < 0.02, (elevation, component)


def test_a_light_is_read_between_its_rows_own_azimuth_nodes():
    """Shares that are a curve of the light's azimuth, read at a light on a row (incidence 30) between that row's
    nodes 9 and 18: linear between those two, not between the other row's 0 and 45."""
    rows = [[0.0, 45.0], [0.0, 9.0, 18.0, 27.0, 36.0, 45.0]]
    curve = lambda psi: (np.asarray(psi) / 45.0) ** 2  # noqa: E731
    shares = np.zeros((8, 1, 4, 10), np.uint16)
    shares[:, 0, :, 0] = np.round(curve(np.concatenate(rows)) * SCALE)[:, None]
    table = ShareTable(0.5, 0.8, True, [0.0, 30.0], rows, [90.0], 4, shares)
    light, view = _pairs(30.0, 13.0, [0.0], [90.0])
    lit, *_ = table_shares(table, light, view, hot_spot_blend=0.0)
    expected = curve(9.0) + (13.0 - 9.0) / 9.0 * (curve(18.0) - curve(9.0))
    assert lit[0, 0] == pytest.approx(expected, abs=2.0 / SCALE)
    # halfway between the rows: half of each row's reading
    light, view = _pairs(15.0, 13.0, [0.0], [90.0])
    lit, *_ = table_shares(table, light, view, hot_spot_blend=0.0)
    assert lit[0, 0] == pytest.approx(0.5 * expected + 0.5 * 13.0 / 45.0 * curve(45.0), abs=2.0 / SCALE)
    slices, weights = light_slices(table, [15.0, 30.0, 0.0], [13.0, 13.0, 45.0])
    assert np.allclose(weights.sum(axis=1), 1.0)
    assert slices[1, 2:].tolist() == [3, 4] and slices[0, :2].tolist() == [0, 1] and slices[2, 1] == 1


def test_rows_of_one_list_read_as_the_table_of_that_list(rows_table):
    """A table of each row's own nodes, all the same, is the table of one list: the same slices, read the same."""
    one = tabulate.measure_table(SURFACE, INCIDENCE, [0.0, 22.5, 45.0], ELEVATION, 15.0)
    same = ShareTable(one.truncation, one.aspect, True, INCIDENCE, [[0.0, 22.5, 45.0]] * 4, ELEVATION, 24, one.shares)
    rng = np.random.default_rng(4)
    light = np.array([shading.light_direction(i, p) for i, p in zip(rng.uniform(0, 90, 100), rng.uniform(0, 360, 100))])
    view = shading.view_direction(rng.uniform(1, 179, 100), rng.uniform(0, 180, 100))
    for a, b in zip(table_shares(one, light, view), table_shares(same, light, view)):
        assert np.array_equal(a, b)


def test_the_shader_reads_a_table_of_rows_as_numpy_does(rows_table):
    """The implicit_table sweep with rows of their own: the CPU hands the shader each light's four slices (two a
    row), read within the dither of a view's pixels as table_values reads them."""
    azimuth = np.arange(2.5, 180.0, 20.0)
    elevation = np.array([5.0, 15.0, 40.0, 75.0, 110.0, 160.0])
    az, el = (a.ravel() for a in np.meshgrid(azimuth, elevation))
    for incidence, psi in ((33.0, 203.0), (12.0, 71.0)):
        drawn = methods.sweep("implicit_table", SURFACE, incidence, az, el, settings={"table": rows_table},
                              light_azimuth=psi)
        expected = table_values(rows_table, *_pairs(incidence, psi, az, el))
        for component in shading.COMPONENTS:
            assert np.abs(drawn[component] - expected[component]).max() < 0.35, (incidence, component)


def test_a_table_of_rows_round_trips_and_a_file_of_one_list_still_reads(rows_table, tmp_path):
    save_table(tmp_path / "rows.npz", rows_table)
    back = load_table(tmp_path / "rows.npz")
    assert [r.tolist() for r in back.rows] == ROWS and np.array_equal(back.shares, rows_table.shares)
    # a file written before the rows had nodes of their own: one list, shares (I, P, E, A, 10)
    one = tabulate.measure_table(SURFACE, INCIDENCE, [0.0, 45.0], ELEVATION, 15.0)
    np.savez_compressed(tmp_path / "old.npz", truncation=0.5, aspect=0.8, shadows=True, incidence=INCIDENCE,
                        light_azimuth=[0.0, 45.0], elevation=ELEVATION, azimuth_nodes=24,
                        shares=one.shares.reshape(4, 2, 5, 24, 10))
    old = load_table(tmp_path / "old.npz")
    assert old.lights == 8 and np.array_equal(old.shares, one.shares) and len(old.rows) == 4


def test_the_rows_nodes_follow_the_steps_and_bad_ones_are_refused():
    rows = tabulate.row_azimuths([0.0, 20.0, 25.0, 40.0, 60.0], [0.0, 15.0, 30.0, 45.0], [[25.0, 1.5], [50.0, 5.0]])
    assert [r.size for r in rows] == [31, 31, 31, 10, 4] and rows[0][1] == 1.5 and rows[3][-1] == 45.0
    with pytest.raises(ValueError, match="divide 45"):
        tabulate.row_azimuths([10.0], [0.0, 45.0], [[20.0, 2.0]])
    with pytest.raises(ValueError, match="one for each of the 2 incidence"):
        ShareTable(0.5, 0.8, True, [0.0, 90.0], [[0.0, 45.0]], [90.0], 4, np.zeros((2, 1, 4, 10), np.uint16))
    with pytest.raises(ValueError, match="shape"):
        ShareTable(0.5, 0.8, True, [0.0, 90.0], [[0.0, 45.0], [0.0]], [90.0], 4, np.zeros((4, 1, 4, 10), np.uint16))


def test_the_schemas_defaults_are_the_tables():
    """export.table's defaults in the schema are the nodes a model without a config builds (tabulate.TABLE): the
    share table a renderer asks for is the one the workflow exports."""
    config = rl_config.validate_config(yaml.safe_load((REPO / "config" / "config.yaml").read_text()),
                                       REPO / "workflow" / "schemas" / "config.schema.yaml")
    assert rl_config.export_settings(config)["table"] == tabulate.TABLE


def test_a_context_keeps_the_textures_of_its_last_two_tables(rows_table):
    """Each table's textures stay resident for the frames that follow, but only the last two tables' (a validation
    draws one a surface: all of them kept would hold tens of MB each); a table drawn again is uploaded again and
    draws the same picture."""
    from roughlight.render.gl.context import context
    from roughlight.render.implicit import render_field
    from roughlight.render.implicit.shader import KEPT_TABLES

    others = [ShareTable(rows_table.truncation, rows_table.aspect, True, INCIDENCE, ROWS, ELEVATION, 24,
                         rows_table.shares.copy()) for _ in range(2)]
    first, _ = render_field("table", SURFACE, 35.0, 60.0, 20.0, 4, size=32, table=rows_table)
    for other in others:
        render_field("table", SURFACE, 35.0, 60.0, 20.0, 4, size=32, table=other)
    kept = context(32, 32, 1)._share_tables
    assert KEPT_TABLES == 2 and list(kept) == [id(t) for t in others]
    again, _ = render_field("table", SURFACE, 35.0, 60.0, 20.0, 4, size=32, table=rows_table)
    assert np.array_equal(again, first) and list(kept) == [id(others[1]), id(rows_table)]


def test_the_validation_drops_a_measured_table_after_its_surfaces_held_out_lights(monkeypatch):
    """The full plan measures a share table for each surface it is not given (22 MB at the default nodes) and holds
    it only through that surface's last light and its held-out lights, unless the frames or maps read it later: the
    tables given stay, the held-out rows keep held_out_lights' order, and every surface's held-out rows are read
    with its table."""
    from roughlight.measurements import implicit_surface as bench

    plan = {**bench.PLANS["quick"], "grid": ((1.0, 1.0), (0.5, 0.5)), "incidences": (30.0, 60.0), "random": 2,
            "steps": (30.0, 90.0),
            "held_out": {"lights": 1, "views": 3}}
    monkeypatch.setitem(bench.PLANS, "full", plan)
    measured = []

    def small(surface, lighting=None, log=None):
        measured.append((surface.truncation, surface.aspect))
        return tabulate.measure_table(surface, [0.0, 45.0, 90.0], [0.0, 45.0], [10.0, 90.0], 45.0)

    monkeypatch.setattr(bench, "share_table", small)
    given = tabulate.measure_table(Surface(1.0, 1.0), [0.0, 45.0, 90.0], [0.0, 45.0], [10.0, 90.0], 45.0)
    tables = bench.load_tables({(1.0, 1.0): given})
    rows = bench.validation("full", tables=tables)
    assert len(measured) == 3 and list(tables) == [(1.0, 1.0)] and tables[(1.0, 1.0)] is given
    held = rows[(rows["kind"] == bench.HELD_OUT) & (rows["method"] == "implicit_table") & (rows["component"] == "total")]
    order = [(s.truncation, s.aspect) for s, *_ in bench.held_out_lights("full")]
    assert list(zip(held["truncation"], held["aspect"])) == order and held["n_views"].gt(0).all()
