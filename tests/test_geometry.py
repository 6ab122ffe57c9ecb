import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from roughlight.surfaces import geometry
from roughlight.surfaces.surface import Surface

truncations = st.floats(0.0, 1.0, allow_nan=False)
aspects = st.floats(0.0, 5.0, allow_nan=False)


def test_face_normals_are_true_facet_normals():
    tris, normals, names = geometry.period_triangles(Surface(0.5, 1.0))
    expected = {
        "top": (0, 0, 1),
        "east": (2, 0, 1),
        "west": (-2, 0, 1),
        "north": (0, 2, 1),
        "south": (0, -2, 1),
    }
    for normal, name in zip(normals, names):
        want = np.array(expected[name], float)
        np.testing.assert_allclose(normal, want / np.linalg.norm(want), atol=1e-12)
    # the mesh carries the same normals on its faces and on every (unshared) vertex
    mesh = geometry.period_mesh(Surface(0.5, 1.0))
    np.testing.assert_allclose(mesh.face_normals, normals, atol=1e-12)
    np.testing.assert_allclose(mesh.vertex_normals, np.repeat(normals, 3, axis=0), atol=1e-12)
    assert len(mesh.vertices) == 3 * len(mesh.faces)


@pytest.mark.parametrize("t", [0.1, 0.3, 0.5, 0.9])
def test_top_area_fraction(t):
    areas = geometry.facet_areas(Surface(t, 1.0))
    assert areas["top"] == pytest.approx((1 - t) ** 2, abs=1e-12)


def test_triangle_counts():
    assert len(geometry.period_mesh(Surface(0.5, 1.0)).faces) == 10  # four trapezoids and the top square
    assert len(geometry.period_mesh(Surface(1.0, 1.0)).faces) == 4  # full pyramid: four triangles
    assert len(geometry.period_mesh(Surface(0.0, 1.0)).faces) == 2  # plate


@pytest.mark.parametrize("t,a", [(0.0, 1.0), (0.7, 0.0), (0.0, 0.0)])
def test_zero_truncation_or_aspect_is_the_plate(t, a):
    plate = geometry.control_mesh()
    mesh = geometry.period_mesh(Surface(t, a))
    np.testing.assert_allclose(mesh.vertices, plate.vertices)
    np.testing.assert_array_equal(mesh.faces, plate.faces)
    assert np.all(mesh.vertices[:, 2] == 0)
    assert Surface(t, a).is_plate


def test_side_slope_for_thirty_degree_facets():
    # aspect sqrt(3)/2: side facets tilt 60 deg, their normals 30 deg above the horizon
    assert geometry.side_slope_deg(math.sqrt(3) / 2) == pytest.approx(60.0)
    _, normals, names = geometry.period_triangles(Surface(0.5, math.sqrt(3) / 2))
    east = normals[names.index("east")]
    assert math.degrees(math.asin(east[2])) == pytest.approx(30.0)


@pytest.mark.parametrize("t,a", [(-0.1, 1), (1.5, 1), (0.5, -1), (float("nan"), 1), ("abc", 1)])
def test_invalid_surfaces_are_refused(t, a):
    with pytest.raises(ValueError, match="truncation|aspect"):
        geometry.period_mesh(Surface(t, a))


@settings(max_examples=60, deadline=None)
@given(truncations, aspects)
def test_any_valid_surface_is_a_valid_heightfield(t, a):
    tris, normals, names = geometry.period_triangles(Surface(t, a))
    cross = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    area = 0.5 * np.linalg.norm(cross, axis=1)
    assert np.all(area > 1e-12), "degenerate triangle"
    assert np.all(normals[:, 2] > 0), "every facet faces up"
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0)
    # plan projection covers the period exactly once
    assert np.sum(area * normals[:, 2]) == pytest.approx(1.0, abs=1e-9)
    # true areas: top (1-t)^2 and each side a quarter of the remaining plan area / cos(slope)
    areas = geometry.facet_areas(Surface(t, a))
    if Surface(t, a).is_plate:
        assert areas == pytest.approx({"top": 1.0})
    else:
        cos_slope = 1.0 / math.sqrt(1.0 + 4.0 * a * a)
        side = (1.0 - (1.0 - t) ** 2) / 4.0 / cos_slope
        assert areas.get("top", 0.0) == pytest.approx((1 - t) ** 2, abs=1e-9)
        for name in ("east", "west", "north", "south"):
            assert areas[name] == pytest.approx(side, rel=1e-9)
    assert np.all(tris[..., 2] >= 0) and np.all(tris[..., 2] <= t * a + 1e-12)
