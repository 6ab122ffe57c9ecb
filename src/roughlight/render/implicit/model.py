"""An implicit rough surface: one flat polygon that reflects like the explicit pyramids (numpy form).

The thesis's goal (Ch. I.A) was a shader with which a surface of few polygons
"reflects light as if it were rough". This module is the numpy form of the two
implicit models whose GLSL lives in ``shaders/implicit.frag`` (run by
:mod:`roughlight.render.implicit.shader`); tests compare the two.

Exact form (``implicit_exact``)
-------------------------------
Every pixel of the flat polygon is one point ``(s, u)`` of the base plane in
the view's oblique coordinates (see :mod:`roughlight.render.exact.reference`). The pixel
casts the view ray through the *analytic* periodic heightfield

    h(x, y) = min(2 a c(x, y), t a),   c = min(fx, 1 - fx, fy, 1 - fy),  fx = frac(x),

(``a`` the aspect, ``t`` the truncation; within one cell the solid under ``h``
is convex: five half-spaces), takes the first facet it meets, casts a second
ray from there toward the light to decide lit or shadowed, and stores that
facet's 8-bit value. No mesh, no table: the surface is the two uniforms ``t``
and ``a``, so the model holds for every surface, between grid values too.
The image mean is then ``sum_f q(f, lit) A_lit(f) + q(f, shadow) A_shadow(f)``,
the reference's facet sum, with the areas estimated by the pixels: each
view's pixels are the points of a Fibonacci lattice over one period
(:func:`fibonacci_lattice`), whose low discrepancy keeps the area error of
every facet edge near ``1 / M`` for ``M`` pixels.

Angles in degrees; the light at azimuth 0, ``L = (cos i, 0, sin i)``; views
``V = (cos e cos phi, cos e sin phi, sin e)`` (:mod:`roughlight.render.shading`).
"""

from __future__ import annotations

import numpy as np

from ...surfaces.roughness import kind_and_seed
from ...surfaces.surface import Surface
from .. import shading
from .. import views as sweeps
from ..sweep import measure

__all__ = [
    "MODELS",
    "check_uniforms",
    "model_samples",
    "FIBONACCI",
    "DEFAULT_SAMPLES",
    "fibonacci_lattice",
    "facet_normals",
    "cast_rays",
    "exact_shares",
    "exact_sweep",
    "shader_uniforms",
]

#: Fibonacci numbers usable as lattice sizes ``M`` (the generator is the one before).
FIBONACCI = (233, 377, 610, 987, 1597, 2584, 4181, 6765, 10946, 17711, 28657, 46368)

#: Samples a view (pixels) of the exact form's sweep: see docs/implicit-surface.md.
DEFAULT_SAMPLES = 28657

#: The implicit models: the exact form (ray casting), the first-order correction (closed form) and the table
#: (the shares read from a table of them, :mod:`roughlight.render.implicit.table`).
MODELS = ("exact", "correction", "table")

#: Pixels a view of each model's sweep. The correction's pixels only dither
#: its closed-form shares into 8-bit facet values, so fewer are enough.
SAMPLES = {"exact": DEFAULT_SAMPLES, "correction": 4181, "table": 4181}


def model_samples(model: str) -> int:
    """Pixels a view of the named model's sweep (:data:`SAMPLES`)."""
    if model not in MODELS:
        raise ValueError(f"implicit model must be one of {MODELS}, got {model!r}")
    return SAMPLES[model]


def check_uniforms(truncation, aspect) -> Surface:
    """The shader's surface uniforms as a :class:`Surface`, or ValueError naming the bad one.

    Parameters
    ----------
    truncation : float in [0, 1]
    aspect : float >= 0, finite

    Raises
    ------
    ValueError
        ``"implicit shader: truncation must be within [0, 1], got 1.5"`` and the like.
    """
    try:
        return Surface(truncation, aspect)
    except ValueError as exc:
        raise ValueError(f"implicit shader: {exc}") from exc


def fibonacci_lattice(samples: int) -> np.ndarray:
    """The Fibonacci lattice of ``samples`` points over the unit cell.

    Point ``k`` is ``((k + 1/2) / M, frac((k g + 1/2) / M))`` with ``M`` the
    Fibonacci number ``samples`` and ``g`` the one before it: a rank-1 lattice
    of the lowest discrepancy known in two dimensions.

    Returns
    -------
    (M, 2) float array in [0, 1)^2.
    """
    m = int(samples)
    if m not in FIBONACCI:
        raise ValueError(f"samples must be one of the Fibonacci numbers {FIBONACCI}, got {samples!r}")
    g = FIBONACCI[FIBONACCI.index(m) - 1] if m != FIBONACCI[0] else 144
    k = np.arange(m, dtype=np.int64)
    return np.stack([(k + 0.5) / m, ((k * g) % m + 0.5) / m], axis=1)


def facet_normals(surface: Surface) -> np.ndarray:
    """Unit normals of the five facets, in :data:`~roughlight.surfaces.geometry.FACET_NAMES` order.

    Returns
    -------
    (5, 3) float array: top ``(0, 0, 1)``; east, west ``(+-2a, 0, 1)`` and
    north, south ``(0, +-2a, 1)``, normalised (``a`` the aspect).
    """
    grad = _half_spaces(surface)[0]
    return grad / np.linalg.norm(grad, axis=1, keepdims=True)


def _half_spaces(surface: Surface):
    """The solid in cell (i, j) is ``grad_k . p <= off_k + s (w_i i + w_j j)`` for the five facets."""
    s = 2.0 * surface.aspect
    grad = np.array([[0, 0, 1], [s, 0, 1], [-s, 0, 1], [0, s, 1], [0, -s, 1]], float)
    # offsets: top H; east s (i + 1); west -s i; north s (j + 1); south -s j
    const = np.array([surface.height, s, 0.0, s, 0.0])
    w_i = np.array([0.0, s, -s, 0.0, 0.0])
    w_j = np.array([0.0, 0.0, 0.0, s, -s])
    return grad, const, w_i, w_j


def cast_rays(surface: Surface, origins, directions, tau_end, cells=None, min_length=0.0):
    """First meeting of rays with the periodic heightfield, cell by cell.

    Parameters
    ----------
    surface : Surface
        Not the plate (its heightfield is the plane ``z = 0``).
    origins, directions : (n, 3) arrays
        Ray starts (inside or above the surface's slab ``0 <= z <= t a``) and
        directions (not normalised necessarily).
    tau_end : (n,) array
        Ray parameter at which to stop looking.
    cells : (n, 2) int array, optional
        The cell each ray starts in (default ``floor(origin.xy)``).
    min_length : float
        A cell counts as met only where the ray runs inside the solid for more
        than this (in ray parameter): 0 for view rays; a small positive value
        for shadow rays starting on the surface, so that a facet does not
        shadow itself.

    Returns
    -------
    hit : (n,) bool
    tau : (n,) float, ray parameter of the first point in the solid
    facet : (n,) int, index in :data:`FACET_NAMES` of the facet met there
    cell : (n, 2) int, the cell met
    """
    p0 = np.asarray(origins, float)
    d = np.asarray(directions, float)
    tau_end = np.broadcast_to(np.asarray(tau_end, float), (len(p0),))
    grad, const, w_i, w_j = _half_spaces(surface)
    cell = np.floor(p0[:, :2]).astype(np.int64) if cells is None else np.array(cells, np.int64)
    walk = _cell_walk(p0, d, cell)
    # plane k along the ray: grad_k . (p0 + tau d) = gp0 + tau gd, offset by cell (i, j)'s const + w_i i + w_j j
    planes = (p0 @ grad.T, d @ grad.T, const, w_i, w_j)
    return _first_solid(planes, cell, walk, tau_end, min_length)


def _cell_walk(p0, d, cell):
    """The start of each ray's walk through the cells (one wall crossing a step).

    Parameters
    ----------
    p0, d : (n, 3) arrays
        Ray starts and directions.
    cell : (n, 2) int array
        The cell each ray starts in.

    Returns
    -------
    step : (n, 2) int array
        +1 or -1: the way each ray crosses the x and y cell walls.
    t_wall : (n, 2) float array
        Ray parameter of the next x and y wall (inf where the ray runs along it).
    dt : (n, 2) float array
        Ray parameter between two x walls and between two y walls.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.where(d[:, :2] != 0, 1.0 / d[:, :2], np.inf)
    step = np.where(d[:, :2] > 0, 1, -1)
    # parameter of the next cell wall in x and y, and between walls
    nxt = np.where(d[:, :2] > 0, cell + 1, cell) - p0[:, :2]
    t_wall = np.where(np.isfinite(inv), nxt * inv, np.inf)
    dt = np.abs(inv)
    return step, t_wall, dt


def _first_solid(planes, cell, walk, tau_end, min_length):
    """Walk every ray cell by cell until it meets the solid of a cell or passes ``tau_end``.

    ``planes`` is ``(gp0, gd, const, w_i, w_j)``: the five facet planes' values at the ray starts and rates
    along the rays, (n, 5) each, and their offsets (:func:`_half_spaces`); ``cell`` (n, 2) and ``walk``
    (:func:`_cell_walk`) are updated in place as the rays step on. Returns :func:`cast_rays`'s four arrays.
    """
    gp0, gd, const, w_i, w_j = planes
    step, t_wall, dt = walk
    n = len(gp0)
    tau_in = np.zeros(n)
    hit = np.zeros(n, bool)
    tau = np.full(n, np.inf)
    facet = np.zeros(n, np.int64)
    met = np.zeros((n, 2), np.int64)
    active = np.ones(n, bool)
    while active.any():
        a = np.flatnonzero(active)
        g0 = gp0[a] - (const + np.outer(cell[a, 0], w_i) + np.outer(cell[a, 1], w_j))  # g(p0) per plane
        found, enter, entering = _enter_cell(g0, gd[a], tau_in[a], t_wall[a], tau_end[a], min_length)
        f = a[found]
        hit[f] = True
        tau[f] = enter[found]
        facet[f] = np.argmax(entering[found], axis=1)
        met[f] = cell[f]
        active[f] = False
        rest = a[~found]
        _next_cell(rest, cell, t_wall, tau_in, step, dt)
        active[rest] = tau_in[rest] < tau_end[rest]
    return hit, tau, facet, met


def _enter_cell(g0, gd, tau_in, t_wall, tau_end, min_length):
    """Where rays meet the solid of their current cell (the intersection of the five half-spaces ``g <= 0``).

    Parameters
    ----------
    g0, gd : (m, 5) arrays
        Each plane's ``g`` at the ray start and its rate along the ray.
    tau_in, t_wall, tau_end : (m,), (m, 2), (m,) arrays
        Ray parameters: entry into the cell, the next x and y walls, the end of the search.
    min_length : float
        Least run inside the solid that counts as meeting it (see :func:`cast_rays`).

    Returns
    -------
    found : (m,) bool
    enter : (m,) float, ray parameter of entry into the solid (meaningful where found)
    entering : (m, 5) float, each plane's entry parameter (-inf for planes the ray leaves); the largest
        names the facet met
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        cross = -g0 / gd
    entering = np.where(gd < 0, cross, -np.inf)
    leaving = np.where(gd > 0, cross, np.inf)
    never = (gd == 0) & (g0 > 0)
    enter = np.maximum(entering.max(axis=1), tau_in)
    tau_out = np.minimum(t_wall.min(axis=1), tau_end)
    leave = np.minimum(leaving.min(axis=1), tau_out)
    found = (enter <= leave - min_length) & ~never.any(axis=1) & (enter <= tau_end)
    if min_length > 0:
        found &= leave > min_length
    return found, enter, entering


def _next_cell(rest, cell, t_wall, tau_in, step, dt) -> None:
    """Step the rays ``rest`` into their next cell across the nearer wall, in place: ``cell``, ``t_wall``
    and ``tau_in`` (see :func:`_cell_walk`)."""
    x_first = t_wall[rest, 0] <= t_wall[rest, 1]
    tau_in[rest] = np.where(x_first, t_wall[rest, 0], t_wall[rest, 1])
    axis = np.where(x_first, 0, 1)
    cell[rest, axis] += step[rest, axis]
    t_wall[rest, axis] += dt[rest, axis]


def _light(incidence, light_azimuth=0.0) -> np.ndarray:
    """(3,) unit vector toward the light at ``incidence`` and ``light_azimuth`` (degrees), each checked
    (:func:`roughlight.render.shading.check_incidence`, :func:`~roughlight.render.shading.check_light_azimuth`)."""
    return shading.light_direction(shading.check_incidence(incidence), shading.check_light_azimuth(light_azimuth))


def exact_shares(surface: Surface, incidence, azimuth, elevation, samples: int = DEFAULT_SAMPLES,
                 shadows: bool = True, light_azimuth: float = 0.0):
    """Visible-lit and visible-shadowed share of each facet, by the exact form's pixels.

    Parameters
    ----------
    surface : Surface
    incidence : float
        Light elevation, degrees in [0, 90].
    azimuth, elevation : (n_views,) arrays, degrees
    samples : int
        Pixels a view (a Fibonacci number, :data:`FIBONACCI`).
    shadows : bool
        Whether the surface casts shadows.
    light_azimuth : float
        The light's azimuth, degrees.

    Returns
    -------
    lit, shadowed : (n_views, 5) float arrays
        Fractions of the view's pixels showing each facet lit and shadowed
        (facets in :data:`FACET_NAMES` order); rows sum to 1, or 0 for
        grazing views (``e`` = 0 or 180).
    """
    incidence = shading.check_incidence(incidence)
    az = np.atleast_1d(np.asarray(azimuth, float))
    el = np.atleast_1d(np.asarray(elevation, float))
    points = fibonacci_lattice(samples)
    m = len(points)
    L = _light(incidence, light_azimuth)
    lit = np.zeros((az.size, 5))
    shadow = np.zeros((az.size, 5))
    normals = facet_normals(surface)
    facing_light = normals @ L > 0
    for k in np.flatnonzero(~sweeps.is_grazing(el)):
        if surface.is_plate:
            (lit if facing_light[0] else shadow)[k, 0] = 1.0
            continue
        facet, is_lit = _pixel_facets(surface, L, el[k], az[k], points, shadows, facing_light)
        lit[k] = np.bincount(facet[is_lit], minlength=5) / m
        shadow[k] = np.bincount(facet[~is_lit], minlength=5) / m
    return lit, shadow


def _pixel_facets(surface: Surface, L, elevation, azimuth, points, shadows, facing_light):
    """Facet seen and whether it is lit, at each pixel ``points`` (oblique cell coordinates) of one view."""
    V = shading.view_direction(elevation, azimuth)
    H = surface.height
    m = len(points)
    origins = np.column_stack([points + H * V[:2] / V[2], np.full(m, H)])
    d = np.broadcast_to(-V, (m, 3))
    _, tau, facet, cell = cast_rays(surface, origins, d, np.full(m, H / V[2] * (1 + 1e-12) + 1e-12))
    is_lit = facing_light[facet]
    if shadows:
        if L[2] < 1e-9:
            is_lit[:] = False
        else:
            todo = np.flatnonzero(is_lit)
            p = origins[todo] + tau[todo, None] * d[todo]
            blocked, *_ = cast_rays(surface, p, np.broadcast_to(L, (todo.size, 3)),
                                    np.maximum(H - p[:, 2], 0.0) / L[2], cells=cell[todo], min_length=1e-9)
            is_lit[todo[blocked]] = False
    return facet, is_lit


def exact_sweep(surface: Surface, incidence, azimuth, elevation, lighting=None,
                samples: int = DEFAULT_SAMPLES, light_azimuth: float = 0.0) -> dict:
    """Mean 8-bit value of each component for many views, by the exact form (numpy), under the light at
    ``incidence`` and ``light_azimuth`` (degrees).

    Returns the dict of :func:`roughlight.render.exact.reference.reference_sweep` plus
    ``seconds``: each pixel stores ``quantize(component)`` of its facet.
    """
    def step(out, views, incidence, lighting):
        az, el = views.azimuth[views.measured], views.elevation[views.measured]
        lit, shadow = exact_shares(surface, incidence, az, el, samples, lighting.shadows, light_azimuth)
        _store(out, views.measured, facet_sum(surface, incidence, az, el, lit, shadow, lighting, light_azimuth))

    return measure(step, incidence, azimuth, elevation, lighting, gives=shading.EXTRAS)


def _store(out: dict, measured, values: dict) -> None:
    """``values`` (:func:`facet_sum`'s, one a measured view) into the sweep's ``out`` at ``measured``."""
    for key, value in values.items():
        out[key][measured] = value


def facet_sum(surface: Surface, incidence, azimuth, elevation, lit, shadow, lighting, light_azimuth=0.0) -> dict:
    """The facet sum: 8-bit facet values weighted by their lit and shadowed shares, under the light at
    ``incidence`` and ``light_azimuth`` (degrees).

    ``lit`` and ``shadow`` are (n_views, 5) shares; returns ``diffuse``,
    ``specular``, ``total`` and ``coverage`` as (n_views,) arrays, and each component's sum before rounding and
    with inner shadows off (:func:`roughlight.render.shading.facet_sums`).
    """
    light = _light(incidence, light_azimuth)
    out = shading.facet_sums(facet_normals(surface), light,
                            shading.view_direction(elevation, azimuth), lit, shadow, lighting)
    out["coverage"] = (lit + shadow).sum(axis=1)
    return out


# ---------------------------------------------------------------------------
# the first-order correction

#: Horizontal outward directions of the side facets east, west, north, south.
_SIDE_DIRECTIONS = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]])

#: The correction's fitted constant: how fast the shares of two masked
#: facets move from the V-groove split to the split of their unmasked
#: projections, against the second-largest view shear (fitted on the exact
#: reference, 10 surfaces x 1,080 views; docs/implicit-surface.md).
BLEND_SCALE = 3.0


def correction_shares(surface: Surface, incidence, azimuth, elevation, shadows: bool = True,
                      light_azimuth: float = 0.0):
    """Lit and shadowed share of each facet by the first-order correction (closed form).

    With ``s = 2a``, top plan area ``P_t = (1 - t)^2`` and side plan area
    ``P_s = (1 - P_t) / 4``, a side facet with horizontal outward direction
    ``h`` has view shear ``x = s (V.h) / V_z`` and light shear
    ``x_L = s (L.h) / L_z``; its unmasked share of the image is
    ``P_s (1 + x)`` (0 when ``1 + x <= 0``: it faces away). The V-groove
    (Torrance-Sparrow) masking ``G(x) = min(1, 2 / (1 + x))`` gives share
    ``a = P_s (1 + x) G(x)``; when two facets face the view and are both
    masked, the image splits between them more like their unmasked
    projections, ``b = 4 P_s (1 + x) / sum(1 + x)``, the more so the deeper
    the pits between four pyramids (truncation ``t``): the share is
    ``a + w (b - a)``, ``w = t clip((x_2 - 1) / c, 0, 1)`` with ``x_2`` the
    second-largest view shear of the four sides and ``c`` =
    :data:`BLEND_SCALE`. The lit part is ``share * min(1, G(x_L) / G_eff)``
    (V-groove shadowing, correlated with masking: the lit and the seen
    parts of a facet are both its upper parts), 0 when the facet faces away
    from the light. The top is seen and lit whole: ``P_t``. The light is at ``incidence`` and ``light_azimuth``
    (degrees): ``L = (cos i cos psi, cos i sin psi, sin i)``.

    Returns
    -------
    lit, shadowed : (n_views, 5) arrays, facets in
    :data:`~roughlight.surfaces.geometry.FACET_NAMES` order; rows sum to 1 (0 for
    grazing views).
    """
    incidence = shading.check_incidence(incidence)
    az = np.atleast_1d(np.asarray(azimuth, float))
    el = np.atleast_1d(np.asarray(elevation, float))
    n = az.size
    L = _light(incidence, light_azimuth)
    lit = np.zeros((n, 5))
    shadow = np.zeros((n, 5))
    seen = ~np.asarray(sweeps.is_grazing(el))
    light_up = L[2] > 1e-9 or not shadows
    if surface.is_plate:
        (lit if L[2] > 0 else shadow)[seen, 0] = 1.0
        return lit, shadow
    top = (1.0 - surface.truncation) ** 2
    side = (1.0 - top) / 4.0
    V = shading.view_direction(el[seen], az[seen])
    seen_share, lit_side = _side_shares(surface, side, V, L, shadows, light_up)
    lit[seen, 0] = top if light_up else 0.0
    shadow[seen, 0] = top - lit[seen, 0]
    lit[seen, 1:] = lit_side
    shadow[seen, 1:] = seen_share - lit_side
    return lit, shadow


def _side_shares(surface: Surface, side: float, V, L, shadows: bool, light_up: bool):
    """The four side facets' seen and lit shares by the first-order correction (see :func:`correction_shares`).

    Parameters
    ----------
    surface : Surface
        Not the plate.
    side : float
        A side facet's plan area ``P_s`` (periods^2).
    V : (n, 3) array
        Unit view directions (no grazing view).
    L : (3,) array
        Unit direction towards the light.
    shadows : bool
        Whether the surface casts shadows.
    light_up : bool
        Whether the light is above the surface plane (or shadows are off).

    Returns
    -------
    seen_share, lit_side : (n, 4) arrays
        Share of the image each side facet (east, west, north, south) fills, and its lit part.
    """
    s = 2.0 * surface.aspect
    x = s * (V[:, :2] @ _SIDE_DIRECTIONS.T) / V[:, 2:3]
    x_light = s * (_SIDE_DIRECTIONS @ L[:2]) / max(L[2], 1e-12)
    unmasked = np.maximum(1.0 + x, 0.0)
    g_view = np.where(x > 1.0, 2.0 / (1.0 + x), 1.0)
    g_light = np.where(x_light > 1.0, 2.0 / (1.0 + x_light), 1.0)
    v_groove = side * unmasked * g_view
    projected = 4.0 * side * unmasked / unmasked.sum(axis=1, keepdims=True)
    w = surface.truncation * np.clip((np.sort(x, axis=1)[:, -2] - 1.0) / BLEND_SCALE, 0.0, 1.0)[:, None]
    seen_share = v_groove + w * (projected - v_groove)
    g_eff = seen_share / np.maximum(side * unmasked, 1e-300)
    faces_light = (1.0 + x_light > 0.0) & light_up
    if shadows:
        lit_side = np.where(faces_light, seen_share * np.minimum(1.0, g_light / np.maximum(g_eff, 1e-300)), 0.0)
    else:
        lit_side = np.where(faces_light, seen_share, 0.0)
    return seen_share, np.minimum(lit_side, seen_share)


def correction_sweep(surface: Surface, incidence, azimuth, elevation, lighting=None, light_azimuth=0.0) -> dict:
    """Mean value of each component for many views by the first-order correction (numpy), under the light at
    ``incidence`` and ``light_azimuth`` (degrees).

    The facet sum of :func:`correction_shares` with each facet's 8-bit value
    (what the shader's dithered pixels average to, within ``1 / M``).
    """
    def step(out, views, incidence, lighting):
        az, el = views.azimuth[views.measured], views.elevation[views.measured]
        lit, shadow = correction_shares(surface, incidence, az, el, lighting.shadows, light_azimuth)
        _store(out, views.measured, facet_sum(surface, incidence, az, el, lit, shadow, lighting, light_azimuth))

    return measure(step, incidence, azimuth, elevation, lighting, gives=shading.EXTRAS)


def shader_uniforms(model: str, surface: Surface, incidence, lighting=None, samples: int | None = None,
                    light_azimuth: float = 0.0) -> dict:
    """The implicit shader's uniforms for one surface, light and material: what a program using
    ``shaders/implicit.vert`` and ``implicit.frag`` sets before drawing its quad.

    Parameters
    ----------
    model : str
        ``"exact"``, ``"correction"`` or ``"table"`` (:data:`MODELS`; the table's own uniforms are
        :func:`roughlight.render.implicit.shader.table_uniforms`').
    surface : Surface
        Truncation in [0, 1], aspect >= 0 (checked by :func:`check_uniforms`).
    incidence : float
        Light elevation, degrees in [0, 90].
    lighting : Lighting, optional
    samples : int, optional
        Pixels a view (sweep) or the dither period (scene), a Fibonacci number (default
        :func:`model_samples`).
    light_azimuth : float, optional
        The light's azimuth, degrees (``light_dir`` is ``(cos i cos psi, cos i sin psi, sin i)``).

    Returns
    -------
    dict, uniform name -> value: ``model``, ``truncation``, ``aspect``, ``shadows``, ``blend_scale``,
    ``samples``, ``generator`` and the material (:func:`roughlight.render.shading.material_uniforms`). A scene adds
    ``camera``, ``field_size``, ``scene_view`` and ``fb_width`` (:func:`roughlight.render.implicit.shader.render_field`).
    """
    default = model_samples(model)  # refuses an unknown model
    lighting = lighting or shading.Lighting()
    if kind_and_seed(surface)[0] != "pyramids":
        raise ValueError(f"the implicit models draw regular surfaces (truncated square pyramids: two uniforms, "
                         f"truncation and aspect), not {surface!r}; measure a random tile with render.method fast")
    check_uniforms(surface.truncation, surface.aspect)
    samples = default if samples is None else int(samples)
    fibonacci_lattice(samples)  # refuses a size that is not a Fibonacci number
    return {
        "model": MODELS.index(model),
        "truncation": float(surface.truncation),
        "aspect": float(surface.aspect),
        **shading.material_uniforms(lighting, _light(incidence, light_azimuth)),
        "shadows": int(bool(lighting.shadows)),
        "blend_scale": float(BLEND_SCALE),
        "samples": samples,
        "generator": int(FIBONACCI[FIBONACCI.index(samples) - 1]),
    }
