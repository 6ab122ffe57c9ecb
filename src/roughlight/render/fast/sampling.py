"""How the fast renderer samples one period of the surface: the lattices, which views are drawn on which, the
lattice copies and the tile layout.

Each view's tile in the framebuffer shows exactly one period of the projected
image of the infinite periodic surface (see :mod:`roughlight.render.fast.periodic`). The
integer sampling matrix maps cell coordinates to window pixels; ``lattice``
sampling rotates it so that no row of pixel centres runs along the facets'
axis-aligned or diagonal edges. Every lattice the renderer draws on is made here: the configured one
(:func:`sampling_matrix`), the adaptive sampling's candidates (:func:`candidate_lattices`, scored by
:func:`roughlight.render.fast.shares.choose_lattices`) and the random tiles' lattices turned to each view's
azimuth (:func:`oriented_lattices`, :func:`counting_passes`). What is drawn on one lattice is a
:class:`LatticePass`, with its tile layout. Pure numpy: no OpenGL is loaded here. The knobs are
:class:`roughlight.render.fast.settings.FastSettings`.
"""

from __future__ import annotations

import functools
import math
from dataclasses import replace
from typing import NamedTuple

import numpy as np

#: Pixel sampling patterns of the fast renderer (``render.sampling``).
SAMPLINGS = ("lattice", "grid", "adaptive")

#: Views within this many degrees of the horizon are counted at ``TileSettings.grazing_scale`` times the
#: pixels (:func:`counting_passes`).
GRAZING_BAND = 10.0

#: Views within this many degrees of the horizon are each drawn on their own rotated lattice
#: (:func:`counting_passes`).
ORIENTED_BAND = 30.0


class LatticePass(NamedTuple):
    """Views drawn on one lattice: a pass of the GL side (:mod:`roughlight.render.fast.periodic`), as many
    framebuffers as its layout needs, or a random tile's views counted on one lattice
    (:mod:`roughlight.render.fast.counting`)."""

    #: (2, 2) int array, cell coordinates to window pixels
    matrix: np.ndarray
    #: (2,) the surface's shift in periods (:func:`surface_shift`)
    shift: np.ndarray
    #: (n,) int array, the views drawn (indices into the caller's views)
    members: np.ndarray
    #: (n,) float array, each view's weight in its value (1, or 1 / K for a view drawn on K lattices)
    weights: np.ndarray
    #: :func:`cached_layout` of the lattice for ``n`` views: width, height, slots, pixel_order (None: counted, not
    #: drawn)
    layout: tuple | None
    #: counting only: count every fragment (False: the visible pixels alone)
    totals: bool = True


def lattice_copies(shifts, margin: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Lattice offsets of the period copies whose projection reaches the unit cell.

    A copy at offset ``(k, l)`` occupies ``[k, k+1] x [l, l+1]`` in plan; the
    oblique projection moves a point at height ``z`` by ``-z * shear``, so the
    copy's projection is the unit square swept along the segment from
    ``(k, l)`` to ``(k, l) - d`` with ``d = H * shear``. It reaches the open
    unit cell iff that segment meets the open square ``(-1, 1)^2``.

    Parameters
    ----------
    shifts : (n, 2) array
        ``d`` for each of ``n`` views: the plan shift of the surface's top
        (height ``H``) relative to its base, in periods.
    margin : float
        Widen the cell by this much on every side (periods), for a sampling
        grid shifted by less than ``margin``.

    Returns
    -------
    view : (m,) int array
        Which view each copy belongs to (non-decreasing).
    offsets : (m, 2) int array
        ``(k, l)`` of each copy.
    """
    d = np.atleast_2d(np.asarray(shifts, float))
    eps = -float(margin) if margin else 1e-9
    # x: candidate columns k per view; the slab (-1, 1) in x bounds lambda
    pad = 1 + int(math.ceil(max(float(margin), 0.0)))
    k_lo = np.floor(np.minimum(0.0, d[:, 0])).astype(int) - pad
    k_hi = np.ceil(np.maximum(0.0, d[:, 0])).astype(int) + pad
    counts = k_hi - k_lo + 1
    view = np.repeat(np.arange(len(d)), counts)
    k = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts) + np.repeat(k_lo, counts)
    dx, dy = d[view, 0], d[view, 1]
    lam_lo = np.zeros(len(view))
    lam_hi = np.ones(len(view))
    moving = np.abs(dx) > 1e-15
    with np.errstate(divide="ignore", invalid="ignore"):
        a = (k - (1.0 - eps)) / dx
        b = (k + (1.0 - eps)) / dx
    lam_lo = np.where(moving, np.maximum(lam_lo, np.minimum(a, b)), lam_lo)
    lam_hi = np.where(moving, np.minimum(lam_hi, np.maximum(a, b)), lam_hi)
    lam_hi = np.where(~moving & (np.abs(k) >= 1.0 - eps), -1.0, lam_hi)
    keep = lam_lo <= lam_hi
    view, k, dy, lam_lo, lam_hi = view[keep], k[keep], dy[keep], lam_lo[keep], lam_hi[keep]
    # y: l - lam * dy must fall in (-1, 1) for some lam in [lam_lo, lam_hi]
    y_lo = np.minimum(lam_lo * dy, lam_hi * dy) - (1.0 - eps)
    y_hi = np.maximum(lam_lo * dy, lam_hi * dy) + (1.0 - eps)
    l_lo = np.ceil(y_lo).astype(int)
    l_hi = np.floor(y_hi).astype(int)
    counts = np.maximum(l_hi - l_lo + 1, 0)
    view_out = np.repeat(view, counts)
    l_out = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts) + np.repeat(l_lo, counts)
    k_out = np.repeat(k, counts)
    return view_out, np.stack([k_out, l_out], axis=1)


def sampling_matrix(pixels_per_period: int, sampling: str = "lattice") -> np.ndarray:
    """Integer matrix ``S`` mapping cell coordinates to window pixels.

    ``grid``: ``P * I``. ``lattice``: ``[[p, q], [-q, p]]`` with ``p^2 + q^2``
    within 10% of ``P^2`` (closest when none is), ``q / p`` closest to the golden ratio's conjugate
    0.618 (a slope far from every ratio of small integers), ``p + q`` odd (so
    that no pixel centre falls on a tile's edge) and ``gcd(p, q) = 1`` (so that
    every line along a lattice axis or diagonal meets one sample per period).
    """
    P = int(pixels_per_period)
    if sampling == "grid":
        return np.array([[P, 0], [0, P]])
    if sampling not in ("lattice", "adaptive"):  # adaptive: this lattice and others chosen per view (shares.py)
        raise ValueError(f"render.sampling must be one of {SAMPLINGS}, got {sampling!r}")
    best = None
    for p in range(1, P + 2):
        for q in range(0, p + 1):
            if (p + q) % 2 == 0 or math.gcd(p, q) != 1:
                continue
            size_error = abs(p * p + q * q - P * P) / max(P * P, 1)
            # within 10% of the asked density, the slope matters most
            score = (max(size_error, 0.1), abs(q / p - 0.6180339887498949), size_error)
            if best is None or score < best[0]:
                best = (score, p, q)
    _, p, q = best
    return np.array([[p, q], [-q, p]])


#: The golden slope's angle, degrees: ``atan(0.618...)``, the slope worst approximated by ratios of small integers.
GOLDEN_ANGLE = math.degrees(math.atan(0.6180339887498949))


def lattice_pairs(pixels_per_period: int):
    """Each ``(p, q)`` (``p > 0``, ``q >= 0``, ``p`` then ``q`` ascending) of a rotated-square sampling matrix
    ``[[p, q], [-q, p]]`` with ``p^2 + q^2`` within 10% of ``pixels_per_period^2``, ``p + q`` odd and
    ``gcd(p, q) = 1`` (as :func:`sampling_matrix`)."""
    size = int(pixels_per_period) ** 2
    for p in range(1, int(pixels_per_period) + 3):
        for q in range(0, int(pixels_per_period) + 3):
            if (p + q) % 2 == 1 and math.gcd(p, q) == 1 and abs(p * p + q * q - size) <= 0.1 * size:
                yield p, q


@functools.lru_cache(maxsize=16)
def rotated_lattices(pixels_per_period: int) -> tuple[np.ndarray, ...]:
    """Every rotated-square sampling matrix of :func:`lattice_pairs` (rotations by ``atan(q / p)`` in [0, 90)
    degrees), by angle."""
    found = [(math.atan2(q, p), p, q) for p, q in lattice_pairs(pixels_per_period)]
    if not found:  # very low densities: the lattice sampling_matrix picks
        return (sampling_matrix(int(pixels_per_period), "lattice"),)
    return tuple(np.array([[p, q], [-q, p]]) for _, p, q in sorted(found))


def oriented_lattices(pixels_per_period: int, azimuth) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
    """For each view, the rotated lattice across whose pixel rows the view's azimuth runs at the golden slope.

    Near the horizon a view stretches every facet along its azimuth: the long edges in its image all run along
    ``(cos phi, sin phi)``, which the matrix ``[[p, q], [-q, p]]`` turns by ``-atan(q / p)``. An edge along a short
    lattice vector (a pixel row, a diagonal: a slope of a ratio of small integers) collects its count error over
    its whole length; at the golden slope, the slope worst approximated by such ratios, the error stays bounded.

    Parameters
    ----------
    pixels_per_period : int
        The density (:func:`rotated_lattices`).
    azimuth : (V,) array
        The views' azimuths of their image's stretch, degrees (any; only modulo 90 matters).

    Returns
    -------
    matrices : tuple of (2, 2) int arrays
        :func:`rotated_lattices`.
    choice : (V,) int array
        Each view's index into ``matrices``: the lattice whose angle to the azimuth, folded into [0, 45] degrees
        (the pixel grid's symmetries), is nearest :data:`GOLDEN_ANGLE`.
    """
    matrices = rotated_lattices(int(pixels_per_period))
    angle = np.array([math.degrees(math.atan2(m[0, 1], m[0, 0])) for m in matrices])
    relative = np.mod(np.asarray(azimuth, float)[:, None] - angle[None, :], 90.0)
    folded = np.minimum(relative, 90.0 - relative)
    return matrices, np.argmin(np.abs(folded - GOLDEN_ANGLE), axis=1)


def candidate_lattices(pixels_per_period: int, n: int = 6) -> list[np.ndarray]:
    """The adaptive sampling's candidate lattices.

    ``n`` rotated-square sampling matrices ``[[p, q], [-q, p]]`` of :func:`lattice_pairs` (``p^2 + q^2`` within
    10% of ``pixels_per_period^2``, ``gcd(p, q) = 1``, ``p + q`` odd), their angles ``atan(q / p)`` spread over
    [0, 45] degrees; the default lattice (:func:`sampling_matrix`) comes first. Fewer at very low densities.
    """
    size = int(pixels_per_period) ** 2
    found = {}
    for p, q in lattice_pairs(pixels_per_period):
        if 1 <= q < p:
            angle = math.degrees(math.atan2(q, p))
            key = round(angle)
            if key not in found or abs(p * p + q * q - size) < abs(sum(x * x for x in found[key][1:]) - size):
                found[key] = (angle, p, q)
    default = sampling_matrix(int(pixels_per_period), "lattice")
    out = [default]
    wanted = np.linspace(0.0, 45.0, n + 1)[1:] - 45.0 / (2 * n)
    options = sorted(found.values())
    for target in wanted if options else ():  # none at very low densities: the default lattice alone
        angle, p, q = min(options, key=lambda o: abs(o[0] - target))
        matrix = np.array([[p, q], [-q, p]])
        if not any(np.array_equal(matrix, m) for m in out) and len(out) < n:
            out.append(matrix)
    return out


def surface_shift(matrix: np.ndarray, jitter) -> np.ndarray:
    """(2,) the surface's shift in periods that a camera shift by ``jitter`` pixels is, drawn with ``matrix``."""
    return -np.linalg.solve(np.asarray(matrix, float), np.asarray(jitter, float))


def lattice_passes(matrices, shifts, order, many, max_framebuffer: int) -> list[LatticePass]:
    """Adaptive sampling: each lattice's pass, given each view's best lattices.

    Parameters
    ----------
    matrices, shifts : lists of (2, 2) int and (2,) float arrays
        The candidates (:func:`candidate_lattices`) and the surface shift each is drawn with.
    order : (K, V) int array
        Each view's best lattices, best first (indices into ``matrices``).
    many : (V,) bool array
        The views drawn on all K, each with weight 1 / K; the others are drawn on their best alone, weight 1.
    max_framebuffer : int
        Largest framebuffer side, pixels.

    Returns
    -------
    list of LatticePass
        One a lattice that draws any view, in the order of ``matrices``.
    """
    out = []
    for k, (matrix, shift) in enumerate(zip(matrices, shifts)):
        members = np.flatnonzero((order[0] == k) | (many & np.any(order[1:] == k, axis=0)))
        if members.size:
            weights = np.where(many[members], 1.0 / len(order), 1.0)
            out.append(LatticePass(matrix, shift, members, weights,
                                   cached_layout(matrix, members.size, int(max_framebuffer))))
    return out


def one_lattice(n_views: int, settings) -> list[LatticePass]:
    """Lattice and grid sampling: every one of ``n_views`` views drawn on ``settings.sampling_matrix()``, shifted
    by ``settings.jitter`` (none when ``n_views`` is 0)."""
    matrix = settings.sampling_matrix()
    order, many = np.zeros((1, int(n_views)), int), np.zeros(int(n_views), bool)
    return lattice_passes([matrix], [surface_shift(matrix, settings.jitter)], order, many,
                          int(settings.max_framebuffer))


def counting_passes(views, hidden, settings) -> list[LatticePass]:
    """How a random tile's views ``hidden`` (indices into the (V, 3) unit ``views``) are counted: one pass a
    lattice and density, unshifted, each view with weight 1 (:func:`tile_pass`).

    Views more than :data:`ORIENTED_BAND` degrees above the horizon are drawn on the tile's lattice
    (``settings.sampling_matrix()``). Nearer the horizon each view is drawn on the rotated lattice across whose
    rows its azimuth runs at the golden slope (:func:`oriented_lattices`): there the image is stretched along the
    azimuth, and on a fixed lattice the views whose azimuth ran near a row (as azimuth 30 on the tile's lattice,
    turned 31.7 degrees) were off by more than a level. Within :data:`GRAZING_BAND` of the horizon they are also
    drawn at ``settings.tile.grazing_scale`` times the pixels (:func:`grazing_settings`), and only their visible
    pixels are counted (``totals`` False): there a region's visible part is the top of a projection stretched over
    many periods, whose own edges the total no longer cancels, and its fragments were most of a sweep's (more
    than ten for each visible one).
    """
    sin_e = np.abs(views[hidden, 2])
    oriented = sin_e < np.sin(np.radians(ORIENTED_BAND))
    grazing = sin_e < np.sin(np.radians(GRAZING_BAND))
    parts = [(hidden[~oriented], settings.sampling_matrix(), True)]
    for part, part_settings, totals in ((hidden[oriented & ~grazing], settings, True),
                                        (hidden[grazing], grazing_settings(settings), False)):
        azimuth = np.degrees(np.arctan2(views[part, 1], views[part, 0]))
        matrices, choice = oriented_lattices(int(part_settings.pixels_per_period), azimuth)
        parts += [(part[choice == k], matrix, totals) for k, matrix in enumerate(matrices)]
    return [tile_pass(part, matrix, totals) for part, matrix, totals in parts if part.size]


def tile_pass(members, matrix, totals: bool = True) -> LatticePass:
    """A random tile's counting pass of the views ``members`` on ``matrix``: unshifted, each view with weight 1,
    no framebuffer layout (the views are counted on the CPU, :mod:`roughlight.render.fast.raster`)."""
    members = np.asarray(members)
    return LatticePass(matrix, np.zeros(2), members, np.ones(members.size), None, totals)


def grazing_settings(settings):
    """The settings of a random tile's views within :data:`GRAZING_BAND` of the horizon:
    ``settings.tile.grazing_scale`` times the pixels."""
    scale = float(settings.tile.grazing_scale)
    return settings if scale == 1.0 else replace(
        settings, pixels_per_period=int(round(int(settings.pixels_per_period) * scale)))


_LAYOUTS: dict = {}


def cached_layout(matrix: np.ndarray, n_views: int, max_framebuffer: int):
    """:func:`tile_layout` for at least ``n_views``: the count is rounded up to a step of 2^(1/4) (at most 19%
    spare slots), so that sweeps drawing slightly different numbers of views with one lattice (adaptive sampling)
    share a layout; the caller uses the first slots."""
    n_views = int(math.ceil(2.0 ** (math.ceil(4.0 * math.log2(max(int(n_views), 1))) / 4.0)))
    key = (tuple(np.asarray(matrix).ravel()), n_views, max_framebuffer)
    if key not in _LAYOUTS:
        if len(_LAYOUTS) >= 64:
            _LAYOUTS.clear()
        _LAYOUTS[key] = tile_layout(matrix, n_views, max_framebuffer)
    return _LAYOUTS[key]


def tile_layout(matrix: np.ndarray, n_views: int, max_framebuffer: int):
    """Slots for view tiles in one framebuffer, and which slot each pixel samples.

    Parameters
    ----------
    matrix : (2, 2) int array
        Cell coordinates to window pixels (:func:`sampling_matrix`).
    n_views : int
        Views wanted in one pass (fewer slots are returned if the largest
        framebuffer cannot hold them all).
    max_framebuffer : int
        Largest framebuffer side, pixels.

    Returns
    -------
    width, height : int
        Framebuffer size.
    slots : (m, 2) int array
        Integer cell offset ``K`` of each tile; tile ``k`` covers the window
        region ``matrix @ (K_k + [0, 1)^2)``, wholly inside the framebuffer.
    pixel_order : (m * N,) int array
        Flat pixel indices (row-major, bottom row first as OpenGL reads them)
        grouped by slot: ``pixel_order.reshape(m, N)`` lists slot ``k``'s
        ``N = |det matrix|`` pixels.
    """
    matrix = np.asarray(matrix, float)
    per_tile = int(round(abs(np.linalg.det(matrix))))
    reach = int(np.abs(matrix).sum(axis=0).max()) + 1
    inverse = np.linalg.inv(matrix)
    side, slots = _square_framebuffer(matrix, inverse, n_views, per_tile, reach, max_framebuffer)
    width = height = side
    # keep the slots nearest the origin first (row-major in the window)
    centre = (slots + 0.5) @ matrix.T
    slots = slots[np.lexsort((centre[:, 0], np.floor(centre[:, 1] / reach)))][: max(n_views, 1)]
    base = _home_pixels(matrix, inverse, per_tile)
    shift = np.rint(slots @ matrix.T).astype(np.int64)
    # flat indices (< 4096^2, so 32 bits): each slot's offset plus the home slot's pixels
    offset = (shift[:, 1] * width + shift[:, 0]).astype(np.int32)
    pixel_order = (offset[:, None] + (base[:, 1] * width + base[:, 0]).astype(np.int32)[None, :]).ravel()
    return width, height, slots, pixel_order


def _square_framebuffer(matrix, inverse, n_views: int, per_tile: int, reach: int, max_framebuffer: int):
    """The smallest square framebuffer side (pixels, growing by 5% from an estimate) whose whole tiles number
    at least ``n_views``, or ``max_framebuffer``; returns the side and those tiles' (m, 2) cell offsets.

    ``per_tile`` is a tile's pixel count ``|det matrix|``, ``reach`` one more than a tile's widest extent in
    pixels, ``inverse`` the inverse of ``matrix``."""
    side = int(math.ceil(math.sqrt(n_views * per_tile * 1.03))) + 2 * reach
    side = min(max(side, reach + 1), max_framebuffer)
    while True:
        slots = _whole_tiles(matrix, inverse, side, side)
        if len(slots) >= n_views or side >= max_framebuffer:
            return side, slots
        side = min(max_framebuffer, int(side * 1.05) + 1)


def _whole_tiles(matrix, inverse, width: int, height: int) -> np.ndarray:
    """(m, 2) int cell offsets ``K`` of the tiles ``matrix @ (K + [0, 1]^2)`` lying wholly inside the
    ``width`` x ``height`` pixel window, in the order of a scan of a box of candidates (x major)."""
    corners = np.array([[0, 0], [width, 0], [0, height], [width, height]], float)
    pre = corners @ inverse.T
    lo = np.floor(pre.min(axis=0)).astype(int) - 1
    hi = np.ceil(pre.max(axis=0)).astype(int) + 1
    kx, ky = np.meshgrid(np.arange(lo[0], hi[0] + 1), np.arange(lo[1], hi[1] + 1), indexing="ij")
    cand = np.stack([kx.ravel(), ky.ravel()], axis=1)
    unit = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], float)
    pts = (cand[:, None, :] + unit[None]) @ matrix.T
    x, y = pts[..., 0], pts[..., 1]
    inside = np.all((x >= 0) & (x <= width) & (y >= 0) & (y <= height), axis=1)
    return cand[inside]


def _home_pixels(matrix, inverse, per_tile: int) -> np.ndarray:
    """(per_tile, 2) int (x, y) of the pixels whose centres fall in the slot at ``K = 0``, row-major bottom row
    first; every slot's are these moved by ``matrix @ K``. Raises if they are not exactly ``per_tile``."""
    box = np.abs(matrix).sum(axis=1).astype(int) + 1
    lo_px = np.minimum(0, matrix.sum(axis=1).clip(max=0)).astype(int) - 1
    ys, xs = np.mgrid[lo_px[1] - box[1]:box[1] + 1, lo_px[0] - box[0]:box[0] + 1]
    centres = np.stack([xs.ravel() + 0.5, ys.ravel() + 0.5], axis=1)
    home = np.all(np.floor(centres @ inverse.T) == 0, axis=1)
    base = np.stack([xs.ravel()[home], ys.ravel()[home]], axis=1)
    if len(base) != per_tile:
        raise RuntimeError("tile layout: a tile does not hold exactly |det S| pixel centres")
    return base
