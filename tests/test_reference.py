"""Tests of the exact polygon-clipping reference (roughlight.render.exact.reference)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughlight.render.exact import reference
from roughlight.render.exact.reference import reference_sweep, visible_lit_areas
from roughlight.render.exact.settings import ReferenceSettings
from roughlight.render.shading import Lighting, facet_components, light_direction, quantize, view_direction
from roughlight.render.views import view_grid
from roughlight.surfaces.surface import Surface

J = 127.0


def _views(az_step=30.0, el_step=10.0):
    az = np.arange(0.0, 180.0, az_step)
    el = np.arange(0.0, 180.0 + 1e-9, el_step)
    a, e = np.meshgrid(az, el, indexing="ij")
    return a.ravel(), e.ravel()


# ---------------------------------------------------------------------------
# 1. the plate: closed forms


@pytest.mark.parametrize("incidence", [0.0, 10.0, 30.0, 55.0, 90.0])
@pytest.mark.parametrize("shadows", [True, False])
def test_plate_closed_forms(incidence, shadows):
    az, el = _views(20.0, 5.0)
    inner = (el > 0) & (el < 180)
    for lighting in (Lighting(shadows=shadows), Lighting(shadows=shadows, ambient=0.2, shininess=10)):
        out = reference_sweep(Surface(0.0, 1.0), incidence, az, el, lighting)
        i = math.radians(incidence)
        diffuse = quantize(J * (0.2 * (lighting.ambient > 0) + max(math.sin(i), 0.0)))
        np.testing.assert_array_equal(out["diffuse"][inner], diffuse)
        e, p = np.radians(el), np.radians(az)
        # R = mirror of L about +z = (-cos i, 0, sin i)
        rdotv = -math.cos(i) * np.cos(e) * np.cos(p) + math.sin(i) * np.sin(e)
        spec = J * np.maximum(rdotv, 0.0) ** lighting.shininess
        if math.sin(i) <= 0:  # N.L = 0 at incidence 0: no specular
            spec = np.zeros_like(spec)
        np.testing.assert_array_equal(out["specular"][inner], quantize(spec[inner]))
        total = quantize(J * (0.2 * (lighting.ambient > 0) + math.sin(i)) + spec)
        np.testing.assert_array_equal(out["total"][inner], total[inner])
        # grazing views see nothing
        assert np.all(out["diffuse"][~inner] == 0) and np.all(out["coverage"][~inner] == 0)
        np.testing.assert_allclose(out["coverage"][inner], 1.0, atol=1e-12)


@pytest.mark.parametrize("incidence", [15.0, 30.0, 60.0])
def test_plate_specular_peak_in_mirror_direction(incidence):
    out = reference_sweep(Surface(0.0, 0.0), incidence, [0.0, 0.0, 5.0], [180.0 - incidence, 90.0, 180.0 - incidence])
    assert out["specular"][0] == 127.0  # m_s = 1, R.V = 1
    assert out["specular"][0] > out["specular"][2] >= out["specular"][1]


def test_plate_quantized_false_is_raw():
    out = reference_sweep(Surface(0.0, 1.0), 30.0, [0.0], [45.0], settings=ReferenceSettings(quantized=False))
    assert out["diffuse"][0] == pytest.approx(J * 0.5, abs=1e-9)
    raw = J * math.sin(math.radians(30.0))  # 63.49999999999999 in float64
    assert out["diffuse"][0] == raw
    assert reference_sweep(Surface(0.0, 1.0), 30.0, [0.0], [45.0])["diffuse"][0] == quantize(raw)


# ---------------------------------------------------------------------------
# 2. top view: visible areas are the plan footprints


@pytest.mark.parametrize("t", [0.25, 0.5, 0.8, 1.0])
def test_top_view_areas_and_values(t):
    aspect, incidence = 0.9, 40.0
    areas = visible_lit_areas(Surface(t, aspect), incidence, 0.0, 90.0, shadows=False)
    side = (1.0 - (1.0 - t) ** 2) / 4.0
    expected = {"top": (1.0 - t) ** 2, "east": side, "west": side, "north": side, "south": side}
    if t == 1.0:
        expected.pop("top")
    assert set(areas) == set(expected)
    for name, (lit, shadowed) in areas.items():
        assert lit + shadowed == pytest.approx(expected[name], abs=1e-12)
    # shadows off: lit is exactly N.L > 0 (the west facet faces away at this incidence)
    assert areas["west"] == (0.0, pytest.approx(side, abs=1e-12))
    assert areas["east"][1] == 0.0

    lighting = Lighting(shadows=False, ambient=0.1)
    out = reference_sweep(Surface(t, aspect), incidence, [0.0], [90.0], lighting)
    normals = {
        "top": (0.0, 0.0, 1.0),
        "east": (2 * aspect, 0.0, 1.0),
        "west": (-2 * aspect, 0.0, 1.0),
        "north": (0.0, 2 * aspect, 1.0),
        "south": (0.0, -2 * aspect, 1.0),
    }
    names = list(expected)
    n = np.array([normals[k] for k in names])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    comps = facet_components(n, light_direction(incidence), view_direction(90.0, 0.0), lighting)
    w = np.array([expected[k] for k in names])
    for key, c in zip(("diffuse", "specular", "total"), comps):
        assert out[key][0] == pytest.approx(float(np.sum(quantize(c) * w)), abs=1e-9)


# ---------------------------------------------------------------------------
# 3. shadows derived by hand (full pyramid, light in the x-z plane)
#
# Full pyramid (t = 1), aspect a, c = cot i. In light-oblique coordinates
# (x - z c, y) the east facet of the pyramid at the origin is the triangle
# (1, 0), (1, 1), (0.5 - a c, 0.5); the next pyramid (at x + 1) projects onto
# the hull of its base [1, 2] x [0, 1] and its apex (1.5 - a c, 0.5), so for
# 0.5 <= a c <= 1.5 it overlaps that triangle (and is in front of it, being
# closer to the light) in the triangle (1, 0), (1, 1), (1.5 - a c, 0.5). Both
# triangles share the base x = 1, so the shadowed fraction of the east facet
# is the ratio of their heights, (a c - 0.5) / (a c + 0.5). Seen from the
# zenith, every facet is wholly visible and its projected area is 1/4, so
# the east facet shows 1/4 (1 - f) lit and 1/4 f shadowed. The west facet
# faces away (self-shadowed) iff tan i <= 2 a, i.e. a c >= 0.5: the cast
# shadow appears exactly when the west facet turns away.


@pytest.mark.parametrize("aspect, incidence", [(1.0, 45.0), (0.5, 30.0), (1.2, 50.0), (0.8, 40.0)])
def test_cast_shadow_full_pyramid_by_hand(aspect, incidence):
    ac = aspect / math.tan(math.radians(incidence))
    assert 0.5 <= ac <= 1.5
    frac = (ac - 0.5) / (ac + 0.5)
    areas = visible_lit_areas(Surface(1.0, aspect), incidence, 0.0, 90.0)
    assert areas["east"][0] == pytest.approx(0.25 * (1 - frac), abs=1e-12)
    assert areas["east"][1] == pytest.approx(0.25 * frac, abs=1e-12)
    assert areas["west"] == (0.0, pytest.approx(0.25, abs=1e-12))
    for name in ("north", "south"):
        assert areas[name] == (pytest.approx(0.25, abs=1e-12), 0.0)
    if (aspect, incidence) == (1.0, 45.0):
        assert areas["east"][0] == pytest.approx(1 / 6, abs=1e-12)
        # in plan: the east facet is z = 2 (1 - x), light coordinate
        # x - z = 3 x - 2; the shadow triangle's apex (0.5, 0.5) maps back to
        # x = 5/6, so the shadow is the plan triangle (1, 0), (1, 1), (5/6, 1/2)
        lit = reference.lit_footprints(Surface(1.0, 1.0), 45.0)["east"]
        assert lit.area == pytest.approx(0.25 - 0.5 * (1 - 5 / 6), abs=1e-12)


@pytest.mark.parametrize("aspect", [0.3, 1.0])
def test_west_self_shadow_threshold(aspect):
    threshold = math.degrees(math.atan(2 * aspect))
    below = visible_lit_areas(Surface(1.0, aspect), threshold - 0.5, 0.0, 90.0)
    above = visible_lit_areas(Surface(1.0, aspect), threshold + 0.5, 0.0, 90.0)
    assert below["west"][0] == 0.0 and below["west"][1] == pytest.approx(0.25)
    # just above the threshold nothing casts a shadow (a cot i < 0.5)
    assert above["west"] == (pytest.approx(0.25, abs=1e-12), 0.0)
    assert above["east"] == (pytest.approx(0.25, abs=1e-12), 0.0)
    # just below it the east facet is barely shadowed
    assert 0.0 < below["east"][1] < 0.01


def test_incidence_zero_all_shadowed():
    az, el = _views(45.0, 15.0)
    inner = (el > 0) & (el < 180)
    lighting = Lighting(ambient=0.3)
    out = reference_sweep(Surface(0.5, 1.0), 0.0, az, el, lighting)
    np.testing.assert_allclose(out["diffuse"][inner], quantize(J * 0.3), atol=1e-9)
    assert np.all(out["specular"] == 0.0)
    for lit, _ in visible_lit_areas(Surface(0.5, 1.0), 0.0, 10.0, 60.0).values():
        assert lit == 0.0
    # without shadows the east facet (N.L > 0) is lit at incidence 0
    areas = visible_lit_areas(Surface(0.5, 1.0), 0.0, 0.0, 90.0, shadows=False)
    assert areas["east"][0] > 0 and areas["top"][0] == 0.0


def test_shadows_only_darken():
    az, el = _views(30.0, 10.0)
    on = reference_sweep(Surface(0.6, 1.1), 25.0, az, el, Lighting(shadows=True))
    off = reference_sweep(Surface(0.6, 1.1), 25.0, az, el, Lighting(shadows=False))
    assert np.all(on["diffuse"] <= off["diffuse"] + 1e-9)
    assert np.all(on["specular"] <= off["specular"] + 1e-9)
    assert np.any(on["diffuse"] < off["diffuse"] - 1.0)


# ---------------------------------------------------------------------------
# 4. an independent brute-force check: ray marching the heightfield


def _height(x, y, t, a):
    xf, yf = x - np.floor(x), y - np.floor(y)
    r = np.maximum(np.abs(xf - 0.5), np.abs(yf - 0.5))
    return np.minimum(t * a, a * (1.0 - 2.0 * r))


def _classify(x, y, t, a):
    """Facet index (0 top, 1 east, 2 west, 3 north, 4 south) and unit normal at plan (x, y)."""
    xf, yf = x - np.floor(x), y - np.floor(y)
    ax, ay = np.abs(xf - 0.5), np.abs(yf - 0.5)
    r = np.maximum(ax, ay)
    side = a * (1.0 - 2.0 * r) < t * a
    cls = np.zeros(x.shape, int)
    xdom = side & (ax >= ay)
    ydom = side & (ax < ay)
    cls[xdom & (xf > 0.5)] = 1
    cls[xdom & (xf <= 0.5)] = 2
    cls[ydom & (yf > 0.5)] = 3
    cls[ydom & (yf <= 0.5)] = 4
    table = np.array([[0, 0, 1], [2 * a, 0, 1], [-2 * a, 0, 1], [0, 2 * a, 1], [0, -2 * a, 1]], float)
    table /= np.linalg.norm(table, axis=1, keepdims=True)
    return cls, table[cls]


def _view_hits(s, u, d, t, a):
    """Largest z where the ray (s + z dx, u + z dy, z) meets the heightfield (bisection-refined)."""
    H = t * a
    lip = 2.0 * a * max(abs(d[0]), abs(d[1])) + 1.0
    min_step = 1e-4 / max(1.0, float(np.hypot(*d)))
    z = np.full(s.shape, H + 1e-9)
    z_hi = z.copy()  # last height known to be above the surface
    z_lo = np.zeros_like(z)  # first height found at or below the surface
    active = np.ones(s.shape, bool)
    while active.any():
        k = np.flatnonzero(active)
        zk = z[k]
        g = _height(s[k] + zk * d[0], u[k] + zk * d[1], t, a) - zk
        found = (g >= 0.0) | (zk <= 0.0)
        z_lo[k[found]] = zk[found]
        active[k[found]] = False
        go = k[~found]
        z_hi[go] = z[go]
        z[go] = np.maximum(z[go] - np.maximum(-g[~found] / lip, min_step), 0.0)
    for _ in range(60):  # bisection: g(z_lo) >= 0 > g(z_hi)
        mid = 0.5 * (z_lo + z_hi)
        g = _height(s + mid * d[0], u + mid * d[1], t, a) - mid
        inside = g >= 0.0
        z_lo = np.where(inside, mid, z_lo)
        z_hi = np.where(inside, z_hi, mid)
    return 0.5 * (z_lo + z_hi)


def _in_shadow(x, y, z, cot_i, t, a):
    """True where the ray from (x, y, z) toward the light (x + w cot i, y, z + w) meets the solid."""
    H = t * a
    lip = 2.0 * a * cot_i + 1.0
    min_step = 1e-4 / max(1.0, cot_i)
    w = np.full(x.shape, 1e-7)
    shadow = np.zeros(x.shape, bool)
    active = z + w < H
    while active.any():
        k = np.flatnonzero(active)
        wk = w[k]
        h = _height(x[k] + wk * cot_i, y[k], t, a) - (z[k] + wk)
        hit = h >= 0.0
        shadow[k[hit]] = True
        go = k[~hit]
        w[go] = wk[~hit] + np.maximum(-h[~hit] / lip, min_step)
        active[:] = False
        active[go] = z[go] + w[go] < H
    return shadow


def _brute_force(t, a, incidence, azimuth, elevation, lighting, n_side, rng):
    """Stratified-jittered ray-traced mean of each component over one cell of (s, u)."""
    V = view_direction(elevation, azimuth)
    d = np.array([V[0] / V[2], V[1] / V[2]])
    i_grid = (np.arange(n_side)[:, None] + rng.random((n_side, n_side))) / n_side
    j_grid = (np.arange(n_side)[None, :] + rng.random((n_side, n_side))) / n_side
    s, u = i_grid.ravel(), j_grid.ravel()
    z = _view_hits(s, u, d, t, a)
    x, y = s + z * d[0], u + z * d[1]
    cls, normals = _classify(x, y, t, a)
    L = light_direction(incidence)
    lit = np.ones(s.shape)
    if lighting.shadows:
        front = normals @ L > 0
        cot_i = L[0] / L[2]
        lit[front] = ~_in_shadow(x[front], y[front], z[front], cot_i, t, a)
    comps = facet_components(normals, L, V, lighting, lit=lit)
    per_ray = {k: quantize(c) for k, c in zip(("diffuse", "specular", "total"), comps)}
    lit_eff = (lit > 0) & (normals @ L > 0)
    for c, name in enumerate(("top", "east", "west", "north", "south")):
        per_ray[(name, "lit")] = ((cls == c) & lit_eff).astype(float)
        per_ray[(name, "shadowed")] = ((cls == c) & ~lit_eff).astype(float)
    return per_ray


def _stratified_se(y, n_side):
    """Conservative standard error of a stratified (one sample per stratum) mean.

    Collapsed strata: neighbouring strata are paired; E[(y_a - y_b)^2] =
    var_a + var_b + (mu_a - mu_b)^2 >= var_a + var_b, so
    sqrt(sum (y_a - y_b)^2) / N over-estimates the standard error.
    """
    y = y.reshape(n_side, n_side)
    return math.sqrt(float(np.sum((y[:, 0::2] - y[:, 1::2]) ** 2))) / y.size


def _brute_cases():
    rng = np.random.default_rng(20240607)
    cases = [(1.0, 1.0, 30.0, 25.0, 40.0)]  # full pyramid, low-ish light
    while len(cases) < 10:
        t = float(rng.choice([rng.uniform(0.2, 0.95), 1.0], p=[0.8, 0.2]))
        a = float(rng.uniform(0.3, 1.5))
        i = float(rng.uniform(10.0, 80.0))
        phi = float(rng.uniform(0.0, 180.0))
        e = float(rng.uniform(15.0, 165.0))
        cases.append((round(t, 3), round(a, 3), round(i, 2), round(phi, 2), round(e, 2)))
    return cases


@pytest.mark.parametrize("case", _brute_cases())
def test_against_brute_force_ray_marcher(case):
    # N = 256^2 rays, one per stratum (jittered) of the unit cell of (s, u).
    # Tolerance per quantity: 4 standard errors of the stratified mean,
    # estimated conservatively by collapsed strata (_stratified_se), plus an
    # allowance for the marcher's own discretisation: its minimum step
    # (1e-4 period) can miss a solid sliver thinner than that, which affects a
    # fraction of rays of order 1e-4 -- 0.02 on the 0-255 scale, 2e-4 for an
    # area fraction. (Measured: |reference - brute force| <= ~1.5 SE.) Plain
    # Monte-Carlo standard errors (sd / sqrt(N)) are ~5x larger.
    t, a, incidence, phi, e = case
    lighting = Lighting(ambient=0.15, specular_model="blinn" if int(phi) % 2 else "phong", shininess=20)
    n_side = 256
    rng = np.random.default_rng([int(round(v * 100)) for v in case])
    per_ray = _brute_force(t, a, incidence, phi, e, lighting, n_side, rng)
    ref = reference_sweep(Surface(t, a), incidence, [phi], [e], lighting)
    areas = visible_lit_areas(Surface(t, a), incidence, phi, e)
    for key, y in per_ray.items():
        if isinstance(key, tuple):
            name, state = key
            expected = areas.get(name, (0.0, 0.0))[0 if state == "lit" else 1]
            allowance = 2e-4
        else:
            expected = ref[key][0]
            allowance = 0.02
        tol = 4.0 * _stratified_se(y, n_side) + allowance
        assert abs(expected - y.mean()) <= tol, (key, expected, y.mean(), tol)


# ---------------------------------------------------------------------------
# 5. mirror symmetry about the light's plane (x-z)
#
# The mirror y -> -y maps V(e, phi) = (cos e cos phi, cos e sin phi, sin e)
# to (cos e cos phi, -cos e sin phi, sin e) = V(180 - e, 180 - phi): with
# e' = 180 - e, cos e' = -cos e, so cos phi' = -cos phi and sin phi' = sin phi.
# The surface and the light are symmetric under it (north <-> south), so the
# values must agree. (phi = 0 views lie in the mirror plane: their own mirror.)


@pytest.mark.parametrize("surface", [(0.5, 1.0), (1.0, 0.7), (0.3, 1.6)])
def test_mirror_symmetry(surface):
    t, a = surface
    phi = np.array([5.0, 30.0, 45.0, 60.0, 95.0, 120.0, 170.0])
    e = np.array([20.0, 45.0, 80.0, 90.0, 100.0, 140.0, 163.0])
    az, el = np.meshgrid(phi, e, indexing="ij")
    az, el = az.ravel(), el.ravel()
    lighting = Lighting(ambient=0.1, shininess=16)
    out = reference_sweep(Surface(t, a), 35.0, az, el, lighting)
    mirrored = reference_sweep(Surface(t, a), 35.0, 180.0 - az, 180.0 - el, lighting)
    for key in ("diffuse", "specular", "total", "coverage"):
        np.testing.assert_allclose(out[key], mirrored[key], atol=1e-9)
    # the per-facet areas swap north and south
    m = visible_lit_areas(Surface(t, a), 35.0, 60.0, 140.0)
    mm = visible_lit_areas(Surface(t, a), 35.0, 120.0, 40.0)
    for name, other in (("north", "south"), ("south", "north"), ("east", "east"), ("west", "west")):
        np.testing.assert_allclose(m[name], mm[other], atol=1e-12)
    # and phi -> 180 - phi alone is not a symmetry (the test can fail)
    not_mirror = reference_sweep(Surface(t, a), 35.0, 180.0 - az, el, lighting)
    assert np.max(np.abs(not_mirror["total"] - out["total"])) > 1.0


def test_mirror_symmetry_phi_90():
    # V(e, 90) = (0, cos e, sin e) mirrors to (0, -cos e, sin e) = V(180 - e, 90).
    e = np.array([10.0, 35.0, 70.0])
    out = reference_sweep(Surface(0.4, 1.2), 50.0, np.full(3, 90.0), e)
    mirrored = reference_sweep(Surface(0.4, 1.2), 50.0, np.full(3, 90.0), 180.0 - e)
    np.testing.assert_allclose(out["total"], mirrored["total"], atol=1e-9)


# ---------------------------------------------------------------------------
# 6. coverage


@pytest.mark.parametrize("surface", [(0.0, 0.0), (0.5, 1.0), (1.0, 2.0), (0.9, 0.4)])
def test_coverage(surface):
    az, el = _views(15.0, 7.5)
    el = np.concatenate([el, [0.0, 180.0, 1.0, 179.0]])
    az = np.concatenate([az, [0.0, 90.0, 45.0, 135.0]])
    out = reference_sweep(Surface(*surface), 20.0, az, el)
    grazing = (el == 0) | (el == 180)
    np.testing.assert_allclose(out["coverage"][~grazing], 1.0, atol=reference.AREA_TOLERANCE)
    assert np.all(out["coverage"][grazing] == 0.0)
    for key in ("diffuse", "specular", "total"):
        assert np.all(out[key][grazing] == 0.0)
        assert out[key].shape == az.shape and out[key].dtype == np.float64
    for lit, shadowed in visible_lit_areas(Surface(*surface), 20.0, 45.0, 1.0).values():
        assert lit >= 0 and shadowed >= -1e-15
    assert sum(sum(v) for v in visible_lit_areas(Surface(*surface), 20.0, 45.0, 1.0).values()) == pytest.approx(1.0, abs=1e-9)


def test_input_validation():
    with pytest.raises(ValueError):
        reference_sweep(Surface(0.5, 1.0), 95.0, [0.0], [45.0])
    with pytest.raises(ValueError):
        reference_sweep(Surface(0.5, 1.0), 30.0, [0.0], [181.0])
    with pytest.raises(ValueError):
        reference_sweep(Surface(1.5, 1.0), 30.0, [0.0], [45.0])
    assert reference.REFERENCE_ERROR < 0.5


def test_specular_without_inner_shadows_is_the_theses_protocol():
    """render.specular_shadows: false shadows the diffuse only; the back lobe widens (15.6 to 16.8 deg, t 1, sqrt3/2)."""
    from dataclasses import replace

    from roughlight.analysis.thesis import exact_widths
    from roughlight.render.shading import Lighting
    from roughlight.surfaces.surface import SQRT3_2, Surface

    surface = Surface(1.0, SQRT3_2)
    el = np.arange(5.0, 180.0, 7.0)
    az = np.zeros_like(el)
    shadowed = reference_sweep(surface, 30, az, el, Lighting())
    thesis = reference_sweep(surface, 30, az, el, Lighting(specular_shadows=False))
    unshadowed = reference_sweep(surface, 30, az, el, Lighting(shadows=False))
    np.testing.assert_allclose(thesis["diffuse"], shadowed["diffuse"])
    np.testing.assert_allclose(thesis["specular"], unshadowed["specular"])
    assert (thesis["specular"] >= shadowed["specular"] - 1e-9).all()
    assert (thesis["specular"] > shadowed["specular"] + 0.5).any()
    widths = exact_widths(surface, 30, 30.0, Lighting(), 25, 1.0)
    assert widths["exact_fwhm"] == pytest.approx(15.57, abs=0.05)
    assert widths["exact_fwhm_no_specular_shadows"] == pytest.approx(16.82, abs=0.05)
    assert replace(Lighting(), specular_shadows=False).specular_shadows is False


def test_a_silently_empty_geos_intersection_is_caught_and_redone():
    """GEOS once returned an empty intersection of a facet's lit and visible parts (0.34 and 0.45 of a 0.45 facet,
    edges nearly coinciding): the inclusion-exclusion check catches it and the view is recomputed snap-rounded."""
    areas = visible_lit_areas(Surface(0.8927, 0.3784), 24.13, 0.0, 42.0)
    lit, shadowed = areas["east"]
    assert lit == pytest.approx(0.33823, abs=1e-4)
    assert lit + shadowed == pytest.approx(0.45483, abs=1e-4)
    assert sum(a + b for a, b in areas.values()) == pytest.approx(1.0, abs=1e-9)


def test_a_lit_sliver_along_the_visible_edge_is_counted_lit():
    """Random pyramids, 4 cells, seed 1, t 0.5, a 0.5, incidence 30, view e 3, phi 5: facet c0_2_east shows a thin
    sliver of its lit part (a brute-force ray cast from its lit and shadowed parts finds 23 of 400 lit points and
    none of 400 shadowed ones visible), whose edge runs along the lit part's. GEOS's double-precision intersection
    gave the sliver no lit area, so the whole of it counted as shadowed and the view came out 1.70 levels below
    the fast renderer, with every check passing. The lit split is now snap-rounded (reference.LIT_SPLIT_GRID)."""
    from roughlight.render.fast.periodic import fast_sweep
    from roughlight.render.fast.settings import FastSettings, TileSettings
    from roughlight.surfaces.roughness import make_surface

    spread = {"truncation": 0.2, "aspect": 0.3, "apex": 0.5, "corner": 0.3}
    tile = make_surface("random_pyramids", 0.5, 0.5, 1, cells=4, spread=spread)
    lit, shadowed = visible_lit_areas(tile, 30.0, 5.0, 3.0)["c0_2_east"]
    assert lit == pytest.approx(0.01001, abs=2e-5) and shadowed < 1e-9
    exact = reference_sweep(tile, 30.0, np.array([5.0]), np.array([3.0]))
    fast = fast_sweep(tile, 30.0, np.array([5.0]), np.array([3.0]), Lighting(),
                      FastSettings(tile=TileSettings(pixels_per_period=16, shadow_map_size=128)))
    assert abs(fast["total"][0] - exact["total"][0]) < 1.0


def test_the_share_table_split_is_the_sweeps_where_double_precision_sees_no_overlap():
    """The share table's split of a view under many lights (shares_under) gives each light what one sweep's split
    gives (LitScene.areas, snap-rounded). At this node GEOS in double precision found no overlap of the east facet's
    lit part (0.217 of the image) with its visible region, which holds it: the table counted it shadowed, with every
    check passing, at 2,022 of the default table's nodes. The views are clipped straight (no symmetry), as then."""
    from roughlight.render.exact.reference import LitScene, shares_under

    scenes = [LitScene(Surface(1.0, 1.0), 10.0, True, 15.0), LitScene(Surface(1.0, 1.0), 40.0, True, 30.0)]
    for scene in scenes:
        scene.surf.symmetry = "none"
    for elevation, azimuth in ((22.0, 307.5), (22.0, 300.0), (5.0, 135.0), (60.0, 10.0)):
        lit, shadow = shares_under(scenes, elevation, azimuth)
        for k, scene in enumerate(scenes):
            one_lit, one_shadow = scene.areas(elevation, azimuth)
            np.testing.assert_allclose(lit[k], one_lit, atol=1e-9)
            np.testing.assert_allclose(shadow[k], one_shadow, atol=1e-9)
    lit, _ = shares_under(scenes, 22.0, 307.5)
    assert lit[0, scenes[0].surf.names.index("east")] == pytest.approx(0.21721, abs=1e-5)


@pytest.mark.parametrize("surface", [(1.0, 1.0), (0.5, 0.5), (0.3, 1.6)])
def test_views_the_squares_symmetry_joins_are_clipped_once_and_turned(surface):
    """square_views: each facet's visible region of a view is the region clipped at the view of the wedge [0, 45]
    the square's symmetry takes it to, turned back; the eight views of an orbit (and their e -> 180 - e twins) are
    clipped once."""
    from shapely import area, symmetric_difference

    from roughlight.render.exact.clipping import period_facets, visible_regions
    from roughlight.render.exact.square_views import square_visible_regions

    surf = period_facets(Surface(*surface))
    assert surf.symmetry == "square"
    base = 17.5
    orbit = [base, 90 - base, 90 + base, 180 - base, 180 + base, 270 - base, 270 + base, 360 - base]
    for elevation in (1.5, 24.0, 71.0):
        for azimuth in orbit:
            for e, phi in ((elevation, azimuth), (180.0 - elevation, azimuth + 180.0)):
                V = view_direction(e, phi)
                d = np.array([V[0] / V[2], V[1] / V[2]])
                straight, turned = visible_regions(surf, d)[0], square_visible_regions(surf, d)
                assert max(float(area(symmetric_difference(a, b))) for a, b in zip(straight, turned)) < 1e-10
                assert sum(float(area(r)) for r in turned) == pytest.approx(1.0, abs=reference.AREA_TOLERANCE)
    assert len(surf.views) == 3  # one clipped view an elevation
    # the regions differ from view to view (the test can fail): the orbit's first two show different facets
    V0, V1 = view_direction(24.0, orbit[0]), view_direction(24.0, orbit[1])
    a0 = area(np.array(square_visible_regions(surf, np.array([V0[0], V0[1]]) / V0[2]), dtype=object))
    a1 = area(np.array(square_visible_regions(surf, np.array([V1[0], V1[1]]) / V1[2]), dtype=object))
    assert np.max(np.abs(a0 - a1)) > 0.01


def test_a_view_turned_from_a_kept_one_is_valid_and_splits_as_clipped_afresh():
    """After GEOS has filled the light's scene with a sweep's views (a regular surface's sweep clips in C now), a
    view turned from a kept one can come out self-intersecting by rounding (t 0.65, a 0.8, the west facet at e 12,
    phi 120). It is made valid, its area kept, so the share table's double-precision split (shares_under) gives
    what the sweep's snapped split gives: before, it read 0.119 of the view as the west facet lit where 0.343 is."""
    import shapely

    from roughlight.render.exact.reference import lit_scene, shares_under
    from roughlight.render.exact.square_views import square_visible_regions

    surface, incidence, psi = Surface(0.65, 0.8), 22.0, 200.0
    azimuth, elevation = view_grid(6.0, 30.0)
    scene = lit_scene(surface, incidence, True, psi)
    for e, phi in zip(elevation, azimuth):  # GEOS's clipping of a sweep's views fills the scene's kept views
        if 0.0 < e < 180.0:
            scene.areas(float(e), float(phi))
    assert len(scene.surf.views) > 1
    V = view_direction(12.0, 120.0)
    regions = square_visible_regions(scene.surf, np.array([V[0], V[1]]) / V[2])
    assert shapely.is_valid(np.array(regions, dtype=object)).all()
    lit, shadow = shares_under([scene], 12.0, 120.0)
    one_lit, one_shadow = scene.areas(12.0, 120.0)
    np.testing.assert_allclose(lit[0], one_lit, atol=1e-9)
    np.testing.assert_allclose(shadow[0], one_shadow, atol=1e-9)
    assert lit[0, scene.surf.names.index("west")] == pytest.approx(0.3426, abs=1e-4)


def test_only_square_surfaces_are_turned():
    """A random tile and the plate are clipped view by view: their symmetry is not the square's."""
    from roughlight.render.exact.clipping import period_facets
    from roughlight.render.exact.square_views import square_visible_regions
    from roughlight.surfaces.roughness import make_surface

    tile = make_surface("random_pyramids", 0.5, 0.5, 1, cells=2)
    for surf in (period_facets(tile), period_facets(Surface(0.0, 1.0))):
        assert surf.symmetry != "square"
        with pytest.raises(ValueError, match="not square"):
            square_visible_regions(surf, np.array([0.3, 0.1]))
    out = reference_sweep(tile, 30.0, np.array([10.0, 100.0]), np.array([40.0, 40.0]))
    assert np.all(np.isfinite(out["total"])) and reference.lit_scene(tile, 30.0, True).surf.views == {}
