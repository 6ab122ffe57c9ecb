"""The regular surfaces' clipper in C (render.exact.pyramid): the exact reference's shares, to rounding, on views
and lights drawn at random, shadows on and off, the plate and the full pyramid among the surfaces."""

import numpy as np
import pytest

from roughlight.render import native
from roughlight.render.exact import LitScene, PyramidScene, pyramid, pyramid_shares
from roughlight.surfaces.geometry import FACET_NAMES
from roughlight.surfaces.roughness import make_surface
from roughlight.surfaces.surface import PLATE, Surface


def reference_shares(surface, incidence, elevation, azimuth, shadows, light_azimuth):
    """The exact reference's (GEOS's) shares of one view, in FACET_NAMES order."""
    scene = LitScene(surface, incidence, shadows, light_azimuth)
    lit, shadowed = scene.areas(elevation, azimuth)
    out = np.zeros((2, len(FACET_NAMES)))
    order = [FACET_NAMES.index(name) for name in scene.surf.names]
    out[0, order], out[1, order] = lit, shadowed
    return out / out.sum()


@pytest.mark.parametrize("surface", [Surface(1.0, 1.0), Surface(0.5, 0.5), Surface(0.3, 2.0), Surface(0.65, 0.8),
                                     Surface(1.0, 0.2), PLATE])
def test_the_clipper_gives_the_exact_references_shares(surface):
    rng = np.random.default_rng(7)
    for k in range(3):
        incidence, light_azimuth, shadows = rng.uniform(5, 85), rng.uniform(0, 360), k != 2
        elevation, azimuth = rng.uniform(1, 179, 12), rng.uniform(0, 360, 12)
        lit, shadowed = pyramid_shares(surface, incidence, elevation, azimuth, shadows, light_azimuth)
        assert lit.shape == shadowed.shape == (12, 5)
        assert np.allclose(lit.sum(axis=1) + shadowed.sum(axis=1), 1.0, atol=1e-12, rtol=0)
        assert (lit >= 0).all() and (shadowed >= -1e-12).all()
        for v in range(12):
            exact = reference_shares(surface, incidence, elevation[v], azimuth[v], shadows, light_azimuth)
            assert np.abs(np.stack([lit[v], shadowed[v]]) - exact).max() < 1e-9, (incidence, elevation[v], azimuth[v])


def test_a_piece_is_not_cut_by_an_edge_of_no_length():
    """An occluder's overlap can close on a corner a rounding away from its first: that edge has no direction, and
    taking one cut the piece it should have removed (t 1, a 1: east 0.669 of the image where 0.554 is)."""
    surface, incidence, light_azimuth, elevation, azimuth = Surface(1.0, 1.0), 55.02, 249.7, 24.461240823308252, \
        337.95065825275844
    lit, shadowed = pyramid_shares(surface, incidence, elevation, azimuth, False, light_azimuth)
    exact = reference_shares(surface, incidence, elevation, azimuth, False, light_azimuth)
    assert lit[FACET_NAMES.index("east")] == pytest.approx(0.5541755742779146, abs=1e-9)
    assert np.abs(np.stack([lit, shadowed]) - exact).max() < 1e-9


def test_one_view_is_a_sweeps_view_and_bad_input_is_refused(tmp_path):
    scene = PyramidScene(Surface(0.5, 1.0), 30.0, True, 20.0)
    elevation, azimuth = np.array([10.0, 60.0, 150.0]), np.array([0.0, 95.0, 300.0])
    lit, shadowed = scene.shares(elevation, azimuth)
    for v in range(3):
        one = scene.shares(float(elevation[v]), float(azimuth[v]))
        assert np.abs(one[0] - lit[v]).max() < 1e-12 and np.abs(one[1] - shadowed[v]).max() < 1e-12
    assert 0 < scene.nbytes < 1000
    with pytest.raises(ValueError, match="grazing"):
        scene.shares(180.0, 0.0)
    with pytest.raises(ValueError, match="grazing"):
        scene.shares(np.array([30.0, 0.0]), 0.0)
    with pytest.raises(TypeError, match="random tile"):
        PyramidScene(make_surface("random_pyramids", 0.5, 0.5, seed=1, cells=2), 30.0)
    with pytest.raises(ValueError):
        PyramidScene(Surface(0.5, 1.0), 95.0)
    built = native.build(pyramid.SOURCE, "the clipper", tmp_path)
    assert built.parent == tmp_path and built.name.startswith("pyramid-") and built.suffix == ".so"


def test_a_row_of_views_under_many_lights_is_the_references_under_each():
    """shares_under_lights (a share table's nodes: each view clipped once for all the lights) against the exact
    reference's shares_under, on symmetric nodes too (azimuths 0, 45, 90; the light in the plane, at the zenith and
    where a side facet turns edge-on to it, atan(2 a) = 58.0 degrees for a 0.8)."""
    from roughlight.render.exact import shares_under
    from roughlight.render.exact.pyramid import shares_under_lights

    surface = Surface(0.65, 0.8)
    lights = [(i, p) for i in (0.0, 10.0, 57.994616, 90.0) for p in (0.0, 15.0, 45.0)]
    scenes = [LitScene(surface, i, True, p) for i, p in lights]
    elevation, azimuth = np.array([1.0, 12.0, 45.0, 57.994616, 90.0]), np.array([0.0, 45.0, 90.0, 200.0, 317.5])
    lit, shadowed = shares_under_lights(surface, lights, elevation, azimuth)
    assert lit.shape == shadowed.shape == (len(lights), 5, 5)
    order = [FACET_NAMES.index(name) for name in scenes[0].surf.names]
    for v in range(5):
        exact_lit, exact_shadowed = shares_under(scenes, elevation[v], azimuth[v])
        assert np.abs(lit[:, v][:, order] - exact_lit).max() < 1e-9
        assert np.abs(shadowed[:, v][:, order] - exact_shadowed).max() < 1e-9


def test_a_view_the_clipper_refuses_goes_to_geos_and_a_random_tile_never_reaches_it(monkeypatch):
    """view_areas (the exact reference's sweeps): where the C clipper raises (more pieces or corners than it keeps),
    GEOS's areas stand in, view for view; a random tile is clipped by GEOS alone."""
    from roughlight.render.exact import view_areas
    from roughlight.render.exact.reference import lit_scene

    surface = Surface(0.5, 1.0)
    scene = lit_scene(surface, 30.0, True, 40.0)
    elevation, azimuth = np.array([15.0, 70.0, 130.0]), np.array([10.0, 100.0, 250.0])
    clipped = view_areas(scene, surface, elevation, azimuth)
    geos = [scene.areas(e, a) for e, a in zip(elevation, azimuth)]

    def refuse(self, elevation, azimuth):
        raise RuntimeError("pyramid_shares: more convex pieces than it keeps")

    monkeypatch.setattr(PyramidScene, "shares", refuse)
    fallen = view_areas(scene, surface, elevation, azimuth)
    for k in range(3):
        assert np.array_equal(fallen[0][k], geos[k][0]) and np.array_equal(fallen[1][k], geos[k][1])
        assert np.abs(clipped[0][k] - geos[k][0]).max() < 1e-9
    tile = make_surface("random_pyramids", 0.5, 0.5, seed=1, cells=2)
    tile_scene = lit_scene(tile, 30.0, True, 0.0)
    lit, shadowed = view_areas(tile_scene, tile, elevation[:1], azimuth[:1])  # the C clipper would refuse it
    assert lit.shape == (1, len(tile_scene.surf.names)) and abs(lit.sum() + shadowed.sum() - 1.0) < 1e-9
