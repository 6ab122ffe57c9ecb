"""Every hemisphere map (Fig. 19, random roughness, the implicit surface's error maps) is drawn from the views that
were measured and none from a mirror image (issue 33).

The sweeps here are made up so that a view and its mirror image in the light's plane, (180 - phi, 180 - e),
always differ: the value at azimuth phi and elevation e is phi + e / 1000 (plus an offset per sweep), far from
symmetric, as a random tile is. Each figure is drawn with its real function; what it drew is read back twice:
the nodes and values of the triangulation handed to ``tricontourf`` (every node must be a measured view, at its
top-down position, with its measured value), and the drawn filled contours (at several views, the band there
must hold the value measured there).
"""
from __future__ import annotations

from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.path import Path  # noqa: E402
from matplotlib.tri import Triangulation  # noqa: E402
from scipy.spatial import cKDTree  # noqa: E402

from roughlight.render import views as sweeps  # noqa: E402
from roughlight.report.figures import implicit, random_roughness, specular  # noqa: E402
from roughlight.report.figures.common import hemisphere_triangulation  # noqa: E402

#: Two points of the top-down disc closer than this are one position.
SAME = 1e-9

#: (azimuth step, elevation step): the default sweep, and one whose azimuths (0, 7, ..., 175) do not hold the
#: mirror image 180 - phi of most azimuths, so that a mirrored node would sit where no view was measured.
GRIDS = {"default 5x1": (5.0, 1.0), "7x2": (7.0, 2.0)}

#: Views checked one by one, on both grids: far side (e > 90), azimuth 175 next to the closing wedge, azimuth 0.
CHECKED_VIEWS = ((0.0, 120.0), (35.0, 150.0), (70.0, 30.0), (105.0, 100.0), (140.0, 60.0), (175.0, 100.0),
                 (175.0, 30.0), (175.0, 170.0))


def topdown(azimuth, elevation):
    """Top-down position of views (degrees): x = cos e cos phi (toward the light), y = cos e sin phi."""
    phi, e = np.radians(np.asarray(azimuth, float)), np.radians(np.asarray(elevation, float))
    return np.cos(e) * np.cos(phi), np.cos(e) * np.sin(phi)


def asymmetric(azimuth, elevation, offset=0.0):
    """A made-up measurement that differs from its own mirror image (180 - phi, 180 - e) at every view but the
    zenith of azimuth 90."""
    return np.asarray(azimuth, float) + np.asarray(elevation, float) / 1000.0 + offset


def views(grid):
    """Every view of a sweep on ``grid`` (GRIDS' key), azimuth-major: azimuth, elevation (n,) degrees."""
    azimuth_step, elevation_step = GRIDS[grid]
    return sweeps.view_grid(elevation_step, azimuth_step)


def rendered(sweep):
    """A sweep's rows at the views that were rendered (0 < e < 180): what a map may draw."""
    return sweep[~sweeps.is_grazing(sweep["elevation"].to_numpy(float))]


def not_rendered_rows(study, value, coverage=True):
    """``study`` with ``value`` in every row of a view not rendered (e = 0 and 180), and (``coverage``) the
    sweeps' coverage column: 0 there, 1 elsewhere."""
    out = study.copy()
    grazing = sweeps.is_grazing(out["elevation"].to_numpy(float))
    out.loc[grazing, "rough"] = value
    if coverage:
        out["coverage"] = np.where(grazing, 0.0, 1.0)
    return out


def drawn_triangles(map_):
    """A map's drawn triangles as their corners' positions (each triangle's corners in order, the triangles
    sorted): the same drawing whatever the nodes' numbering (a grid with or without its e = 0, 180 rows)."""
    tri = map_.triangulation
    corners = np.stack([tri.x[tri.get_masked_triangles()], tri.y[tri.get_masked_triangles()]], axis=-1)
    corners = corners.reshape(len(corners), -1)
    return corners[np.lexsort(corners.T[::-1])]


def assert_same_maps(first, other):
    """Two lists of drawn maps (:class:`Drawn`) show the same nodes, values, triangles and bands."""
    assert len(first) == len(other) > 0
    for a, b in zip(first, other):
        np.testing.assert_array_equal(a.x, b.x)
        np.testing.assert_array_equal(a.z, b.z)
        np.testing.assert_array_equal(drawn_triangles(a), drawn_triangles(b))
        np.testing.assert_array_equal(a.contours.levels, b.contours.levels)
    # no node on the horizon (e = 0, 180: the disc's rim)
    assert all(np.hypot(map_.x, map_.y).max() < 1.0 - 1e-6 for map_ in first + other)


@dataclass
class Drawn:
    """One ``tricontourf`` call: the axes, the triangulation's nodes in a triangle and their values, its
    triangles, and the contour set it drew."""

    ax: Axes
    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    triangulation: Triangulation
    contours: object


@pytest.fixture
def drawn(monkeypatch):
    """Every filled-contour map drawn while the test runs, in order (see :class:`Drawn`)."""
    calls = []
    original = Axes.tricontourf

    def spy(self, *args, **kwargs):
        triangulation, rest, _ = Triangulation.get_from_args_and_kwargs(*args, **dict(kwargs))
        z = np.asarray(rest[0], float)
        contours = original(self, *args, **kwargs)
        used = np.unique(triangulation.get_masked_triangles())
        calls.append(Drawn(self, triangulation.x[used], triangulation.y[used], z[used], triangulation, contours))
        return contours

    monkeypatch.setattr(Axes, "tricontourf", spy)
    return calls


def band_holds(path, point) -> bool:
    """Whether one band's filled contour (its polygons, islands and holes alike) covers ``point``: inside an odd
    number of its polygons."""
    return sum(Path(p).contains_point(point) for p in path.to_polygons(closed_only=True)) % 2 == 1


def assert_drawn_from_measured(map_, azimuth, elevation, value):
    """The map's every node is a measured view at its position with its measured value; every measured view is a
    node; at :data:`CHECKED_VIEWS` the drawn band holds the measured value; the nodes cover the disc."""
    azimuth, elevation, value = (np.asarray(a, float) for a in (azimuth, elevation, value))
    X, Y = topdown(azimuth, elevation)
    measured = cKDTree(np.column_stack([X, Y]))
    # no node where no view was measured, and none with a value not measured there (a mirrored one); the views
    # within SAME of a node (several only at the zenith), padded with index len(value) where there are fewer
    distance, at = measured.query(np.column_stack([map_.x, map_.y]), k=len(np.unique(azimuth)) + 1,
                                  distance_upper_bound=SAME)
    found = np.isfinite(distance)
    bad = ~found[:, 0]
    assert not bad.any(), f"{bad.sum()} node(s) where no view was measured, e.g. {map_.x[bad][0], map_.y[bad][0]}"
    measured_there = np.where(found, np.append(value, np.nan)[at], np.nan)
    same = (np.abs(measured_there - map_.z[:, None]) <= 1e-9).any(axis=1)
    assert same.all(), (f"{(~same).sum()} node(s) show a value not measured at their view, e.g. "
                        f"{map_.z[~same][0]:.3f} where {measured_there[~same][0][found[~same][0]]} was measured")
    # every measured view is drawn
    nodes = cKDTree(np.column_stack([map_.x, map_.y]))
    assert all(nodes.query_ball_point((x, y), SAME) for x, y in zip(X, Y)), "a measured view is not on the map"
    levels = np.asarray(map_.contours.levels, float)
    for phi, e in CHECKED_VIEWS:
        k = np.flatnonzero(np.isclose(azimuth, phi) & np.isclose(elevation, e))
        assert len(k) == 1, f"view ({phi:g}, {e:g}) is not in the sweep"
        v, (x, y) = value[k[0]], (X[k[0]], Y[k[0]])
        # the triangulation: the nodes at the view's position (one, away from the zenith) carry its value
        at = nodes.query_ball_point((x, y), SAME)
        assert at and np.allclose(map_.z[at], v, rtol=0, atol=1e-9), (
            f"at view ({phi:g}, {e:g}) the map has {map_.z[at]}, measured {v:.3f}")
        # the drawing: the filled band around the view's position holds the measured value
        bands = [b for b, path in enumerate(map_.contours.get_paths()) if band_holds(path, (x, y))]
        assert bands, f"nothing drawn at view ({phi:g}, {e:g})"
        for b in bands:
            assert levels[b] - 1e-9 <= v <= levels[b + 1] + 1e-9, (
                f"at view ({phi:g}, {e:g}) the map shows {levels[b]:.2f}-{levels[b + 1]:.2f}, measured {v:.3f}")
    # the triangles cover the disc from the outermost views (the horizon's, or the lowest rendered, e and 180 - e):
    # each wedge between neighbouring half great circles, the last one (up to azimuth 180) closed by azimuth 0's
    # views, twice (near and far side), r^2 sin(wedge) / 2 each, r the outermost views' distance from the centre
    wedges = np.diff(np.append(np.unique(azimuth), 180.0))
    r = np.abs(np.cos(np.radians(elevation))).max()
    assert triangle_areas(map_.triangulation).sum() == pytest.approx(r**2 * np.sin(np.radians(wedges)).sum(), rel=1e-9)


# ---------------------------------------------------------------------------
# random roughness


def random_study(grid):
    """A study table of one random grid point: the regular surface, two seeds of random pyramids and one of the
    random heightfield, each sweep's values made up (:func:`asymmetric`, an offset per sweep), specular and
    diffuse."""
    azimuth, elevation = views(grid)
    frames = []
    for kind, seed, offset in (("pyramids", 0, 0.0), ("random_pyramids", 1, 20.0), ("random_pyramids", 2, 40.0),
                               ("random_heightfield", 1, 10.0)):
        for component, extra in (("specular", 0.0), ("diffuse", 60.0)):
            frames.append(pd.DataFrame({
                "kind": kind, "seed": seed, "truncation": 0.5, "aspect": 1.0, "incidence": 30.0,
                "azimuth": azimuth, "elevation": elevation, "component": component,
                "rough": asymmetric(azimuth, elevation, offset + extra)}))
    study = pd.concat(frames, ignore_index=True)
    return study.sample(frac=1.0, random_state=3).reset_index(drop=True)  # no reliance on the rows' order


@pytest.mark.parametrize("grid", GRIDS)
def test_random_maps_show_each_tile_as_measured(grid, drawn, tmp_path):
    study = random_study(grid)
    random_roughness.fig_random_maps(study)
    # one map a kind, in the figure's order; the random kinds show their lowest seed
    expected = [("pyramids", 0), ("random_pyramids", 1), ("random_heightfield", 1)]
    assert len(drawn) == len(expected)
    for map_, (kind, seed) in zip(drawn, expected):
        sweep = rendered(study[(study.kind == kind) & (study.seed == seed) & (study.component == "specular")])
        assert_drawn_from_measured(map_, sweep["azimuth"], sweep["elevation"], sweep["rough"])
        assert kind.replace("_", " ") in map_.ax.get_title(loc="left")


@pytest.mark.parametrize("grid", GRIDS)
def test_random_maps_leave_out_the_views_not_rendered(grid, drawn):
    """The views not rendered (e = 0 and 180, coverage 0) are no measurement: whether their rows hold 0 (as a
    sweep stores them), 255 or NaN, with or without the coverage column, every map draws the same nodes, values,
    triangles and bands, and none on the horizon."""
    study = random_study(grid)
    for value, coverage in ((0.0, True), (255.0, True), (255.0, False), (np.nan, False)):
        random_roughness.fig_random_maps(not_rendered_rows(study, value, coverage))
        plt.close("all")
    assert len(drawn) == 12
    assert_same_maps(drawn[:3] * 3, drawn[3:])


def test_no_node_at_the_mirror_image_of_a_view(drawn):
    """On the 7x2 grid the mirror image (x, -y) of view (35, 60), view (145, 120), was not measured: nothing may
    be drawn there; view (175, 100)'s position holds only its own value, not that of its mirror (5, 80)."""
    azimuth, elevation = views("7x2")
    fig, ax = plt.subplots()
    sweep = pd.DataFrame({"azimuth": azimuth, "elevation": elevation, "seed": 1,
                          "rough": asymmetric(azimuth, elevation)})
    random_roughness.random_map(fig, ax, sweep, "random_pyramids", (0.5, 1.0, 30.0))
    plt.close(fig)
    (map_,) = drawn
    x, y = topdown(35.0, 60.0)
    assert np.hypot(map_.x - x, map_.y + y).min() > 1e-3
    x, y = topdown(175.0, 100.0)
    at = np.hypot(map_.x - x, map_.y - y) < SAME
    assert at.sum() == 1 and map_.z[at][0] == pytest.approx(175.1)


# ---------------------------------------------------------------------------
# Fig. 19


def regular_study(grid, surfaces):
    """A study table of regular surfaces whose specular values are made up (:func:`asymmetric`, an offset a
    surface)."""
    azimuth, elevation = views(grid)
    frames = [pd.DataFrame({"kind": "pyramids", "seed": 0, "truncation": t, "aspect": a, "incidence": i,
                            "azimuth": azimuth, "elevation": elevation, "component": "specular",
                            "rough": asymmetric(azimuth, elevation, 7.0 * n)})
              for n, (t, a, i) in enumerate(surfaces)]
    return pd.concat(frames, ignore_index=True)


@pytest.mark.parametrize("grid", GRIDS)
def test_fig19_maps_show_the_measured_views(grid, drawn):
    surfaces = [(0.0, 0.0, 30.0), (1.0, 1.0, 30.0)]
    study = regular_study(grid, surfaces)
    fig = specular.fig19_topdown(study, surfaces=surfaces)
    try:
        assert len(drawn) == len(surfaces)
        for map_, (t, a, _) in zip(drawn, surfaces):
            sweep = rendered(study[(study.truncation == t) & (study.aspect == a)])
            assert_drawn_from_measured(map_, sweep["azimuth"], sweep["elevation"], sweep["rough"])
            # the back lobe's dots mark measured views only (none mirrored)
            X, Y = topdown(sweep["azimuth"], sweep["elevation"])
            measured = cKDTree(np.column_stack([X, Y]))
            dots = [line for line in map_.ax.get_lines() if isinstance(line, Line2D) and line.get_marker() == "."]
            for line in dots:
                for x, y in zip(*line.get_data()):
                    assert measured.query_ball_point((x, y), SAME), f"a dot at ({x:.4f}, {y:.4f}), not a view"
        assert any(line.get_marker() == "." for line in drawn[1].ax.get_lines())  # t 1, a 1 has a back lobe
    finally:
        plt.close(fig)


@pytest.mark.parametrize("grid", GRIDS)
def test_fig19_maps_leave_out_the_views_not_rendered(grid, drawn):
    """Fig. 19's maps and the back lobe's dots are the same whether the views not rendered (e = 0 and 180,
    coverage 0) hold 0, 255 or NaN, with or without the coverage column: none is drawn, as dark or as bright."""
    surfaces = [(0.0, 0.0, 30.0), (1.0, 1.0, 30.0)]
    study = regular_study(grid, surfaces)
    dots = []
    for value, coverage in ((0.0, True), (255.0, True), (255.0, False), (np.nan, False)):
        fig = specular.fig19_topdown(not_rendered_rows(study, value, coverage), surfaces=surfaces)
        dots.append([line.get_data() for ax in fig.axes for line in ax.get_lines() if line.get_marker() == "."])
        plt.close(fig)
    assert len(drawn) == 8
    assert_same_maps(drawn[:2] * 3, drawn[2:])
    assert dots[0] and all(len(d) == len(dots[0]) for d in dots)
    for other in dots[1:]:
        for (x0, y0), (x1, y1) in zip(dots[0], other):
            np.testing.assert_array_equal(x0, x1)
            np.testing.assert_array_equal(y0, y1)


# ---------------------------------------------------------------------------
# the implicit surface's maps


def implicit_maps(grid, not_rendered=0.0):
    """Made-up hemisphere maps of one surface (:func:`roughlight.measurements.implicit_surface.hemisphere_maps`'
    columns, rows in any order): the exact values and each model's, by method ({method: (n,) total}), and the
    frame, whose views not rendered (e = 0, 180) hold ``not_rendered`` in every method and component."""
    azimuth, elevation = views(grid)
    reference = asymmetric(azimuth, elevation)
    phi, e = np.radians(azimuth), np.radians(elevation)
    models = {"reference": reference,
              "implicit_exact": reference + np.sin(phi) * np.cos(e),  # changes sign in the mirror image
              "implicit_correction": reference + 2.0 * np.cos(phi) + np.sin(2 * e)}
    grazing = sweeps.is_grazing(elevation)
    maps = pd.concat([pd.DataFrame({"truncation": 1.0, "aspect": 1.0, "incidence": 30.0, "azimuth": azimuth,
                                    "elevation": elevation, "method": method,
                                    "total": np.where(grazing, not_rendered, total),
                                    "diffuse": np.where(grazing, not_rendered, 0.0),
                                    "specular": np.where(grazing, not_rendered, 0.0)})
                      for method, total in models.items()], ignore_index=True)
    return models, maps.sample(frac=1.0, random_state=5).reset_index(drop=True)


@pytest.mark.parametrize("grid", GRIDS)
def test_implicit_maps_show_the_measured_differences(grid, drawn, tmp_path):
    """The exact map, and each model's difference from it taken view by view (rows in any order), at every view
    that was rendered (0 < e < 180)."""
    azimuth, elevation = views(grid)
    models, maps = implicit_maps(grid)
    implicit.fig_implicit_maps(maps)
    assert len(drawn) == 3
    rendered = ~sweeps.is_grazing(elevation)
    for map_, method in zip(drawn, models):
        value = models[method] - (0.0 if method == "reference" else models["reference"])
        assert_drawn_from_measured(map_, azimuth[rendered], elevation[rendered], value[rendered])


@pytest.mark.parametrize("grid", GRIDS)
def test_implicit_maps_leave_out_the_views_not_rendered(grid, drawn):
    """The views not rendered (e = 0 and 180, coverage 0) are no measurement: whatever their rows hold (0, as a
    sweep stores them, 255 or NaN), every map draws the same nodes, values, triangles and bands."""
    for not_rendered in (0.0, 255.0, np.nan):
        implicit.fig_implicit_maps(implicit_maps(grid, not_rendered)[1])
        plt.close("all")
    assert len(drawn) == 9
    for first, other in zip(drawn[:3] * 2, drawn[3:]):
        np.testing.assert_array_equal(first.z, other.z)
        np.testing.assert_array_equal(first.triangulation.get_masked_triangles(),
                                      other.triangulation.get_masked_triangles())
        np.testing.assert_array_equal(first.contours.levels, other.contours.levels)
    # no node on the horizon (e = 0, 180: the disc's rim)
    assert all(np.hypot(map_.x, map_.y).max() < 1.0 - 1e-6 for map_ in drawn)


def test_implicit_difference_needs_the_same_views():
    azimuth, elevation = views("7x2")
    frame = pd.DataFrame({"azimuth": azimuth, "elevation": elevation, "total": asymmetric(azimuth, elevation)})
    fig, ax = plt.subplots()
    with pytest.raises(ValueError, match="same views"):
        implicit.map_panel(fig, ax, frame.iloc[1:], frame, "implicit_exact", "total", (1.0, 1.0, 30.0))
    plt.close(fig)


# ---------------------------------------------------------------------------
# the triangulation itself


def triangle_areas(triangulation):
    """The triangulation's triangles' areas (all positive: the orientation left out)."""
    tri = triangulation.get_masked_triangles()
    tx, ty = triangulation.x[tri], triangulation.y[tri]
    return 0.5 * np.abs((tx[:, 1] - tx[:, 0]) * (ty[:, 2] - ty[:, 0]) - (tx[:, 2] - tx[:, 0]) * (ty[:, 1] - ty[:, 0]))


@pytest.mark.parametrize("elevation_step, azimuth_step", [(1.0, 5.0), (4.0, 5.0), (2.0, 7.0), (0.8, 1.0), (12.0, 45.0)])
def test_a_symmetric_sweep_covers_the_disc_once(elevation_step, azimuth_step):
    """Elevations e and 180 - e all measured, with or without the zenith (steps 4, 0.8 and 12 have none): the
    triangles fill the polygon of the horizon's views, wedge by wedge up to azimuth 180, once (no overlap: their
    areas add up to it exactly), and every view is a node of one."""
    azimuth, elevation = sweeps.view_grid(elevation_step, azimuth_step)
    triangulation, z = hemisphere_triangulation(azimuth, elevation, asymmetric(azimuth, elevation))
    wedges = np.diff(np.append(np.unique(azimuth), 180.0))
    assert triangle_areas(triangulation).sum() == pytest.approx(np.sin(np.radians(wedges)).sum(), rel=1e-9)
    assert len(np.unique(triangulation.get_masked_triangles())) == len(azimuth)
    assert np.array_equal(z, asymmetric(azimuth, elevation))  # the nodes are the views, in the sweep's order


def test_a_sweep_without_the_mirror_elevations_leaves_the_last_wedge_open():
    """Elevations 0, 7, ..., 175: the view at azimuth 180 and elevation e would be azimuth 0's at 180 - e, never
    measured, so the wedges between azimuth 175 and 180 (and 355 and 360) are not closed by made-up views; the
    centre (no view at 90: rows 84 and 91 on either side of it) is filled by the ring of those views."""
    azimuth, elevation = sweeps.view_grid(7.0, 35.0)  # azimuths 0, 35, ..., 175
    triangulation, _ = hemisphere_triangulation(azimuth, elevation, asymmetric(azimuth, elevation))
    tri = triangulation.get_masked_triangles()
    cx, cy = triangulation.x[tri].mean(axis=1), triangulation.y[tri].mean(axis=1)
    outer = np.hypot(cx, cy) > np.cos(np.radians(84.0))
    angle = np.degrees(np.arctan2(cy[outer], cx[outer])) % 180.0
    assert outer.any() and (angle <= 175.0 + 1e-9).all()
    # near side from the horizon to elevation 84, far side from 91 to 175, the ring of views at 84 and 91 between
    near = 5 * np.sin(np.radians(35.0)) / 2 * (1.0 - np.cos(np.radians(84.0)) ** 2)
    far = 5 * np.sin(np.radians(35.0)) / 2 * (np.cos(np.radians(175.0)) ** 2 - np.cos(np.radians(91.0)) ** 2)
    rx, ry = topdown(np.r_[np.arange(0.0, 176.0, 35.0), np.arange(0.0, 176.0, 35.0)], np.r_[[84.0] * 6, [91.0] * 6])
    ring = 0.5 * abs(np.sum(rx * np.roll(ry, -1) - np.roll(rx, -1) * ry))
    assert triangle_areas(triangulation).sum() == pytest.approx(near + far + ring, rel=1e-9)


def test_a_view_twice_is_refused():
    azimuth, elevation = sweeps.view_grid(30.0, 60.0)
    with pytest.raises(ValueError, match="twice"):
        hemisphere_triangulation(np.append(azimuth, 60.0), np.append(elevation, 30.0), np.zeros(len(azimuth) + 1))
