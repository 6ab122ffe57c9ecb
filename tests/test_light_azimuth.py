"""A light from any azimuth (issue 45): the exact reference lit from azimuth psi, L = (cos i cos psi, cos i sin psi,
sin i), held to the symmetries the surfaces have: square pyramids repeat every 90 degrees and mirror about the
diagonals, the plate only moves its mirror, random tiles repeat nothing. The study's light (psi = 0) is the same
bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from roughlight.render import methods, shading
from roughlight.render.exact.reference import REFERENCE_ERROR
from roughlight.surfaces.roughness import make_surface
from roughlight.surfaces.surface import Surface

INCIDENCE = 30.0
#: a few views on and off the light's plane, both sides of the zenith
AZ = np.array([0.0, 20.0, 45.0, 70.0, 110.0, 160.0, 200.0, 300.0])
EL = np.array([40.0, 65.0, 90.0, 120.0, 35.0, 150.0, 80.0, 55.0])


def reference(surface, light_azimuth, az=AZ, el=EL, lighting=None):
    return methods.sweep("reference", surface, INCIDENCE, az, el, lighting, light_azimuth=light_azimuth)


def same(a: dict, b: dict, tol: float = REFERENCE_ERROR):
    """Equal within the exact reference's floating point (its polygon clipping differs by about 1e-8 between two
    equivalent lights)."""
    for component in shading.COMPONENTS:
        np.testing.assert_allclose(a[component], b[component], atol=tol, rtol=0, err_msg=component)


def test_the_studys_light_is_unchanged_bit_for_bit():
    i = np.array([0.0, 12.5, 30.0, 89.0, 90.0])
    r = np.radians(i)
    assert np.array_equal(shading.light_direction(i), np.stack([np.cos(r), np.zeros_like(r), np.sin(r)], axis=-1))
    assert np.array_equal(shading.light_direction(i, 0.0), shading.light_direction(i))
    surface = Surface(0.5, 1.0)
    plain = methods.sweep("reference", surface, INCIDENCE, AZ, EL)
    for component in shading.COMPONENTS:
        assert np.array_equal(plain[component], reference(surface, 0.0)[component])


def test_the_light_direction_turns_with_its_azimuth():
    L = shading.light_direction(30.0, 90.0)
    np.testing.assert_allclose(L, [0.0, np.cos(np.radians(30.0)), 0.5], atol=1e-15)
    assert np.isclose(np.linalg.norm(shading.light_direction(40.0, 123.0)), 1.0)
    for bad in (float("nan"), "north", float("inf")):
        with pytest.raises(ValueError, match="light_azimuth"):
            shading.check_light_azimuth(bad)


@pytest.mark.parametrize("surface", [Surface(1.0, 1.0), Surface(0.5, 0.5)], ids=str)
def test_square_pyramids_repeat_every_quarter_turn(surface):
    """Turning light and detector together by 90 degrees turns the lattice onto itself."""
    same(reference(surface, 90.0, AZ + 90.0), reference(surface, 0.0))
    same(reference(surface, 200.0, AZ + 200.0), reference(surface, 20.0, AZ + 20.0))


def test_square_pyramids_mirror_about_their_diagonals():
    """Reflecting light and detector in the diagonal x = y maps azimuth theta to 90 - theta."""
    surface = Surface(1.0, 1.0)
    same(reference(surface, 60.0, 90.0 - AZ), reference(surface, 30.0))


def test_a_light_off_the_axes_is_not_the_studys_light():
    surface = Surface(1.0, 1.0)
    turned, study = reference(surface, 30.0), reference(surface, 0.0)
    assert np.abs(turned["specular"] - study["specular"]).max() > 1.0
    assert np.abs(turned["diffuse"] - study["diffuse"]).max() > 1.0


def test_the_plate_only_moves_its_mirror():
    """On the plate the diffuse does not depend on the light's azimuth; the specular peak follows the mirror view,
    at azimuth psi + 180 (the far side of the zenith: elevation 180 - i at azimuth psi)."""
    plate, psi = Surface(0.0, 0.0), 40.0
    turned = reference(plate, psi, np.array([psi, 0.0]), np.array([180.0 - INCIDENCE] * 2))
    study = reference(plate, 0.0, np.array([0.0, 0.0]), np.array([180.0 - INCIDENCE] * 2))
    np.testing.assert_array_equal(turned["diffuse"], study["diffuse"])
    assert turned["specular"][0] == study["specular"][0] > 100.0 and turned["specular"][1] < study["specular"][0]


def test_random_tiles_repeat_nothing():
    tile = make_surface("random_pyramids", 1.0, 1.0, seed=1)
    az, el = AZ[:4], EL[:4]
    turned, study = reference(tile, 90.0, az + 90.0, el), reference(tile, 0.0, az, el)
    assert np.abs(turned["total"] - study["total"]).max() > 0.5


def test_a_method_that_lights_from_azimuth_0_only_refuses_another():
    with pytest.raises(ValueError, match="lights from azimuth 0 only.*measured by fast, reference, implicit_exact, "
                       "implicit_correction, implicit_table, implicit_clipped, mitsuba"):
        methods.sweep("naive", Surface(0.5, 0.5), INCIDENCE, AZ, EL, light_azimuth=45.0)


#: light azimuths off the study's: off the lattice's axes, on a diagonal, across the far side
LIGHT_AZIMUTHS = (30.0, 45.0, 135.0)


@pytest.mark.parametrize("surface, lights, steps", [
    (Surface(1.0, 1.0), LIGHT_AZIMUTHS, (15.0, 16.0)), (Surface(0.5, 0.3), LIGHT_AZIMUTHS, (15.0, 16.0)),
    (Surface(0.0, 0.0), LIGHT_AZIMUTHS, (15.0, 16.0)),
    # the exact reference takes tens of seconds a light for a random tile on the fine grid: one light, coarser views
    (make_surface("random_pyramids", 1.0, 1.0, seed=1), (30.0,), (30.0, 32.0))], ids=str)
def test_the_fast_method_is_within_a_level_of_the_reference_under_any_light(surface, lights, steps):
    """Every view of a coarse hemisphere (both sides of the zenith, every azimuth the study measures), each
    component within one 8-bit level of the exact reference, at light azimuths other than 0."""
    az, el = np.meshgrid(np.arange(0.0, 180.0, steps[0]), np.arange(10.0, 171.0, steps[1]), indexing="ij")
    az, el = az.ravel(), el.ravel()
    for psi in lights:
        fast = methods.sweep("fast", surface, INCIDENCE, az, el, light_azimuth=psi)
        exact = reference(surface, psi, az, el)
        for component in shading.COMPONENTS:
            worst = np.abs(fast[component] - exact[component]).max()
            assert worst < 1.0, (psi, component, worst)


def test_mitsuba_lights_from_the_same_azimuth():
    surface = Surface(1.0, 1.0)
    az, el = AZ[:5], EL[:5]
    rendered = methods.sweep("mitsuba", surface, INCIDENCE, az, el, None,
                             {"pixels_per_period": 24, "samples_per_pixel": 8}, light_azimuth=45.0)
    exact = reference(surface, 45.0, az, el)
    for component in shading.COMPONENTS:
        assert np.abs(rendered[component] - exact[component]).max() < 1.0, component


@pytest.mark.parametrize("psi", [10.0, 60.0, 100.0, 170.0, 200.0, 250.0, 300.0, 350.0, -30.0])
def test_one_light_of_each_class_is_measured_and_the_views_turned(psi):
    """Square pyramids under any light are one of the lights in [0, 45] seen from views the same symmetry takes
    along (surfaces.symmetry.canonical_light), held against the exact reference."""
    from roughlight.surfaces.symmetry import canonical_light

    surface = Surface(1.0, 0.8)
    psi0, g = canonical_light(surface, psi)
    assert 0.0 <= psi0 <= 45.0 and np.isclose(g(psi), psi0)
    same(reference(surface, psi0, g(AZ)), reference(surface, psi))


def test_the_plate_is_the_studys_light_turned_and_a_random_tile_its_own():
    from roughlight.surfaces.symmetry import canonical_light, symmetry

    plate, tile = Surface(0.0, 0.0), make_surface("random_heightfield", 0.5, 0.5, seed=2)
    assert (symmetry(plate), symmetry(Surface(0.5, 0.5)), symmetry(tile)) == ("isotropic", "square", "none")
    psi0, g = canonical_light(plate, 123.0)
    assert psi0 == 0.0
    same(reference(plate, 0.0, g(AZ)), reference(plate, 123.0))
    psi0, g = canonical_light(tile, 400.0)
    assert psi0 == 40.0 and np.allclose(g(AZ), np.mod(AZ, 360.0))
