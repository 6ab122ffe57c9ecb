"""Each facet's share of a view's image, from pixel counts corrected by exact projected areas.

The fast renderer's tile holds one period of the projected image; a view's value is the sum over facets of each
facet's 8-bit value times the share of the image it fills, lit and in shadow. Counting pixels estimates the shares
with an error along every edge in the image, which at single views reaches several 8-bit levels (issue 11, and the
thesis's "jagged peaks", Ch. IV.A). Two corrections, both exact geometry and no rendering:

- **Ratio to the exact area.** Each *region* (the lit or the shadowed part of a facet, :mod:`roughlight.render.fast.regions`, from
  :func:`roughlight.render.exact.reference.lit_footprints`) projects along the view to a polygon whose area is known exactly and
  whose lattice points (the tile's pixel centres) can be counted exactly. The rendered count of the region's visible
  part over that count is its visible fraction, and times the exact area its share: the pixel errors along the
  region's own edges cancel, those along the edges of whatever hides it remain.
- **A lattice chosen per view, and three where the choice is not good enough.** Pixel centres are a
  lattice; an edge running along a short lattice vector collects its error over its whole length. Among a few
  rotated lattices of the same density the view is drawn with the one whose edges have the smallest *value
  discrepancy*: the sum over the edges in view of the step in 8-bit value across the edge times its *star
  discrepancy* (the largest count error of any part of it, which is what a partly hidden edge contributes),
  over the lattice's pixels a period. It is close to a bound on the view's error, in 8-bit levels: drawn on
  its best lattice, a view's error was above the score on 0.003% of 72,900 views of 22 surfaces, and at most
  1.11 times it (issue 11). Where even the best lattice scores at or above a threshold the view is drawn on
  its three best lattices and the values averaged: their errors are nearly independent.

Which views are exact: where every facet faces the view nothing is hidden and each region's share is its exact
projected area, unrendered (:func:`exact_views`). A facet faces the view where its area ratio (:func:`area_ratio`,
the one formula) exceeds :data:`FACING`. :func:`adaptive_plan` puts it together for the regular surface: the exact
views' shares and, for the others, the lattices they are drawn on (:mod:`roughlight.render.fast.sampling`).

Coordinates: plan ``(x, y, z)`` of one period; a view's plan shift ``d = (V_x / V_z, V_y / V_z)``; the oblique
("cell") coordinates ``(x, y) - z d`` in periods, and pixel coordinates ``matrix @ (cell + shift)`` whose integer
points plus one half are the tile's pixel centres (:mod:`roughlight.render.fast.sampling`). Pure numpy (and
shapely): no OpenGL is loaded here.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...surfaces.geometry import twice_signed_area
from .regions import Regions, facet_edges, unique_edges
from .sampling import LatticePass, candidate_lattices, lattice_passes, surface_shift

__all__ = ["area_ratio", "front_facing", "exact_views",
           "area_shares", "region_plan_areas", "projected_areas", "counts_and_areas", "normalised_shares",
           "ratio_shares", "region_values", "edge_steps", "value_discrepancy", "star_discrepancy",
           "star_discrepancy_numpy", "choose_lattices", "AdaptivePlan", "adaptive_plan", "candidate_lattices",
           "AVERAGED", "FACING"]

#: A view whose best lattice scores at or above ``render.average_lattices_above`` is drawn on this many best
#: lattices and their values averaged. Two were not enough: where the second best is much worse than the best,
#: the mean of the two is worse than the best alone (1.29 against 0.61 at t 0.8, a sqrt(3)/2, e 2, the one view
#: of the default study past 1.0 with two, issue 11).
AVERAGED = 3

#: The lattice choice scores at most this many periods' worth of pixel rows of each edge, from its top: at views
#: near the horizon an edge spans tens of periods of the image, of which only the top can be seen past the rows
#: in front (scoring the rest costs most of the choice's time and changes no view's worst error, issue 11).
SCORED_PERIODS = 4.0

#: A facet faces a view where its area ratio (:func:`area_ratio`) exceeds this: the one facing test of the fast
#: renderer (which views are exact, which edges and regions count, which projected areas are not 0). The exact
#: reference's own test (:data:`roughlight.render.exact.clipping.EDGE_ON`, 1e-12) is smaller; the two disagree only
#: on a facet whose projection is within 1e-9 of edge-on, whose area (below 1e-9 of a period) no 8-bit value sees.
FACING = 1e-9


def area_ratio(regions: Regions, shear) -> np.ndarray:
    """(V, F) each facet's area ratio along each view: ``det = 1 - alpha d_x - beta d_y``, its projected area over
    its plan area (the projection along the view is affine on a facet; negative where the facet faces away).

    Parameters
    ----------
    regions : Regions
        Its ``alpha``, ``beta`` (F,): the facets' planes ``z = alpha x + beta y + gamma``.
    shear : (V, 2) array
        Each view's plan shift ``d = (V_x / V_z, V_y / V_z)``.
    """
    return 1.0 - regions.alpha[None, :] * shear[:, 0:1] - regions.beta[None, :] * shear[:, 1:2]


def front_facing(regions: Regions, owner, shear) -> np.ndarray:
    """(V, E) True where the facet of the region ``owner`` (E,) faces the view: its area ratio exceeds
    :data:`FACING` (its projection has positive area)."""
    return area_ratio(regions, shear)[:, regions.facet[owner]] > FACING


def all_facing(regions: Regions, shear) -> np.ndarray:
    """(V,) True where every facet faces the view: nothing is hidden.

    The surface is a continuous periodic height field, so when every facet's projection keeps its orientation the
    projection of one period covers the unit cell once: every region is seen whole and its share of the image is
    its exact projected area (:func:`area_shares`, :func:`projected_areas`), with no rendering.
    """
    shear = np.atleast_2d(np.asarray(shear, float))
    _, first = np.unique(regions.facet, return_index=True)  # a region of each facet (a random tile has two)
    return np.all(front_facing(regions, first, shear), axis=1)


def exact_views(regions: Regions, shear, batch: int = 1024) -> np.ndarray:
    """(V,) bool :func:`all_facing`, ``batch`` views at a time (a (views, regions) array whole takes gigabytes on
    large random tiles): the views whose shares are their exact projected areas, unrendered."""
    shear = np.atleast_2d(np.asarray(shear, float))
    return np.concatenate([all_facing(regions, shear[i:i + batch]) for i in range(0, len(shear), batch)]
                          or [np.zeros(0, bool)])


def area_shares(regions: Regions, shear):
    """Each facet's lit and shadowed share of the image when nothing is hidden (see :func:`all_facing`).

    Parameters
    ----------
    regions : Regions
    shear : (V, 2) array
        Each view's plan shift ``d``.

    Returns
    -------
    lit, shadow : (V, F) arrays
        The exact projected areas of each facet's lit and shadowed parts, in periods (summing to 1 a view).
    """
    return _facet_shares(_areas(regions, np.atleast_2d(np.asarray(shear, float))), regions)


def _areas(regions: Regions, shear) -> np.ndarray:
    """(V, R) each region's projected area in periods, 0 where its facet faces away (shoelace over the edges)."""
    start, end, owner = facet_edges(regions)
    n_views, n_regions = len(shear), len(regions.rings)
    if len(owner) == 0:
        return np.zeros((n_views, n_regions))
    identity = np.eye(2)
    a, b = _project(start, shear, identity, (0.0, 0.0)), _project(end, shear, identity, (0.0, 0.0))
    cross = (a[..., 0] * b[..., 1] - b[..., 0] * a[..., 1]) * front_facing(regions, owner, shear)
    key = np.arange(n_views)[:, None] * n_regions + owner[None, :]
    areas = np.bincount(key.ravel(), weights=0.5 * cross.ravel(), minlength=n_views * n_regions)
    return areas.reshape(n_views, n_regions)


def region_plan_areas(regions: Regions) -> np.ndarray:
    """(R,) each region's plan area (periods^2): its rings' shoelace sums, holes (clockwise) subtracted."""
    out = np.zeros(len(regions.rings))
    for r, rings in enumerate(regions.rings):
        for ring in rings:
            out[r] += 0.5 * twice_signed_area(ring[:, 0], ring[:, 1])
    return out


def projected_areas(regions: Regions, plan_areas, shears) -> np.ndarray:
    """(V, R) each region's projected area along each view: its plan area times its facet's :func:`area_ratio`,
    0 where the facet does not face the view (periods^2; a view's areas sum to 1 where nothing is hidden).

    The random tiles' exact areas; the regular surface's (:func:`area_shares`, :func:`counts_and_areas`) are the
    shoelace of the projected rings, the polygon whose pixel centres are counted. The two agree to 1e-12.

    Parameters
    ----------
    regions : Regions
    plan_areas : (R,) array
        :func:`region_plan_areas`.
    shears : (V, 2) array
        Each view's plan shift ``d = (V_x / V_z, V_y / V_z)``.
    """
    det = area_ratio(regions, shears)
    det[~(det > FACING)] = 0.0  # where the facet does not face the view
    out = np.take(det, regions.facet, axis=1)
    out *= plan_areas[None, :]
    return out


def _facet_shares(share, regions: Regions):
    """(V, F) lit and (V, F) shadowed shares from (V, R) region shares."""
    n_facets = len(regions.normals)
    lit = np.zeros((len(share), n_facets))
    shadow = np.zeros((len(share), n_facets))
    np.add.at(lit.T, regions.facet[regions.lit], share[:, regions.lit].T)
    np.add.at(shadow.T, regions.facet[~regions.lit], share[:, ~regions.lit].T)
    return lit, shadow


def _project(points, shear, matrix, shift) -> np.ndarray:
    """(V, E, 2) pixel coordinates of plan points (E, 3) seen along each of V shears."""
    m = np.asarray(matrix, float)
    shift = np.asarray(shift, float)
    cx = points[None, :, 0] - points[None, :, 2] * shear[:, 0:1] + shift[0]
    cy = points[None, :, 1] - points[None, :, 2] * shear[:, 1:2] + shift[1]
    # written out: a matrix product over a last axis of 2 is several times slower
    return np.stack([m[0, 0] * cx + m[0, 1] * cy, m[1, 0] * cx + m[1, 1] * cy], axis=-1)


def counts_and_areas(regions: Regions, shear, matrix, shift=(0.0, 0.0)):
    """Exact pixel-centre counts and areas of every region's projection, per view.

    Parameters
    ----------
    regions : Regions
    shear : (V, 2) array
        Each view's plan shift ``d``.
    matrix : (2, 2) int array
        Cell coordinates to pixels (:func:`roughlight.render.fast.sampling.sampling_matrix`).
    shift : (2,) array
        Translation of the surface in cell units (the renderer's jitter).

    Returns
    -------
    counts, areas : (V, R) float arrays
        Pixel centres inside each region's projected polygon (with multiplicity over periods, as the tile counts
        them) and the polygon's area in periods (0 where the facet faces away).
    """
    shear = np.atleast_2d(np.asarray(shear, float))
    start, end, owner = facet_edges(regions)
    n_views, n_regions = len(shear), len(regions.rings)
    if len(owner) == 0:
        return np.zeros((n_views, n_regions)), np.zeros((n_views, n_regions))
    front = front_facing(regions, owner, shear)
    a, b = _project(start, shear, matrix, shift), _project(end, shear, matrix, shift)
    key = np.arange(n_views)[:, None] * n_regions + owner[None, :]
    # crossing sums: each edge adds, on every pixel-centre row it spans, the pixel centres left of it (+ going up,
    # - going down); over a closed ring these sum to the centres inside
    x0, y0, x1, y1 = a[..., 0].ravel(), a[..., 1].ravel(), b[..., 0].ravel(), b[..., 1].ravel()
    has, start, _, x = _row_crossings(x0, y0, x1, y1, front.ravel())
    left = np.add.reduceat(np.floor(x) + 1.0, start) if has.size else np.zeros(0)
    sign = np.where(y1[has] > y0[has], 1.0, -1.0)
    counts = np.bincount(key.ravel()[has], weights=sign * left, minlength=n_views * n_regions)
    return counts.reshape(n_views, n_regions), _areas(regions, shear)


def region_values(regions: Regions, light_dir, views, lighting) -> np.ndarray:
    """(3, V, R) each region's 8-bit diffuse, specular and total value in each view (its facet's value, lit or in
    shadow as the region is; :func:`roughlight.render.shading.facet_values`)."""
    from ..shading import facet_values

    on, off = facet_values(regions.normals, light_dir, views, lighting)
    return np.stack([np.where(regions.lit[None, :], v_on[:, regions.facet], v_off[:, regions.facet])
                     for v_on, v_off in zip(on, off)])


def edge_steps(regions: Regions, sides, shear, values) -> np.ndarray:
    """(V, E) the largest step in 8-bit value (over the components) across each edge, 0 where neither side faces
    the view.

    Parameters
    ----------
    regions : Regions
    sides : (E, 2) int array
        The regions on each edge's two sides (:func:`unique_edges`), -1 for none.
    shear : (V, 2) array
        Each view's plan shift ``d``.
    values : (3, V, R) array
        :func:`region_values`.

    An edge with both sides facing the view separates them wherever it is seen. An edge with one side facing
    (a silhouette, whose other facet faces away, or an unpaired cell border) can have any region in view behind
    it: its step is the largest from its region to any region facing the view.
    """
    facing = front_facing(regions, np.arange(len(regions.facet)), shear)
    first, second = sides[:, 0], np.maximum(sides[:, 1], 0)
    f0, f1 = facing[:, first], facing[:, second] & (sides[:, 1] >= 0)[None, :]
    q0, q1 = values[:, :, first], values[:, :, second]
    # the range of values in view (views with nothing in view have no step: where() below never picks them)
    high = np.where(facing[None], values, 0.0).max(axis=2, keepdims=True)
    low = np.where(facing[None], values, 255.0).min(axis=2, keepdims=True)

    def behind(q):  # largest step from q to anything in view
        return np.maximum(np.abs(q - high), np.abs(q - low)).max(axis=0)

    both = np.abs(q0 - q1).max(axis=0)
    return np.where(f0 & f1, both, np.where(f0, behind(q0), np.where(f1, behind(q1), 0.0)))


def value_discrepancy(start, end, steps, shear, matrix, shift=(0.0, 0.0)) -> np.ndarray:
    """(V,) the sum over the edges of step times star discrepancy under the lattice ``matrix``, over its pixels a
    period: close to a bound on the view's error from this lattice, in 8-bit levels.

    Parameters
    ----------
    start, end : (E, 3) arrays
        The edges (:func:`unique_edges`).
    steps : (V, E) array
        :func:`edge_steps`; edges with no step are not walked.
    shear, matrix, shift
        As :func:`counts_and_areas`.

    An edge's star discrepancy is the largest count error, in pixels, of any part of it cut at a pixel row (or
    column, for edges nearer the horizontal): the error a partly hidden edge can bring to a view.
    """
    shear = np.atleast_2d(np.asarray(shear, float))
    n_pixels = abs(round(np.linalg.det(np.asarray(matrix, float))))
    if len(start) == 0:
        return np.zeros(len(shear))
    walked = steps > 0
    a, b = _project(start, shear, matrix, shift), _project(end, shear, matrix, shift)
    # keep each edge's top SCORED_PERIODS periods of rows
    run = np.maximum(np.abs(b - a).max(axis=-1), 1e-12)[..., None]
    keep = np.minimum(1.0, SCORED_PERIODS * math.sqrt(n_pixels) / run)
    top_first = (start[:, 2] >= end[:, 2])[None, :, None]
    a, b = np.where(top_first, a, b + (a - b) * keep), np.where(top_first, a + (b - a) * keep, b)
    steep = np.abs(b[..., 1] - a[..., 1]) >= np.abs(b[..., 0] - a[..., 0])
    # run along rows for steep edges, along columns for flat ones
    x0, y0 = np.where(steep, a[..., 0], a[..., 1]).ravel(), np.where(steep, a[..., 1], a[..., 0]).ravel()
    x1, y1 = np.where(steep, b[..., 0], b[..., 1]).ravel(), np.where(steep, b[..., 1], b[..., 0]).ravel()
    star = star_discrepancy(x0, y0, x1, y1, walked.ravel())
    return (star.reshape(walked.shape) * steps).sum(axis=1) / n_pixels


def _row_crossings(x0, y0, x1, y1, valid):
    """Where each segment crosses the pixel-centre rows ``r + 1/2`` it spans (``[min(y0, y1), max(y0, y1))``).

    Returns
    -------
    has : (S',) int array
        The segments (indices into ``x0``...) that are valid and cross at least one row.
    start, count : (S',) int arrays
        Where each one's rows begin in ``x`` and how many there are.
    x : (sum count,) float array
        x - 1/2 where each segment crosses each of its rows, a segment's rows contiguous.
    """
    lo, hi = np.minimum(y0, y1), np.maximum(y0, y1)
    first = np.ceil(lo - 0.5)
    count = np.where(valid, np.maximum(np.ceil(hi - 0.5) - first, 0), 0).astype(np.int64)
    has = np.flatnonzero(count > 0)
    count, first = count[has], first[has]
    slope = (x1[has] - x0[has]) / (y1[has] - y0[has])
    start = np.cumsum(count) - count
    row = np.arange(count.sum(), dtype=float) - np.repeat(start, count)  # the row's number in its segment
    x = np.repeat(x0[has] - 0.5 + (first + 0.5 - y0[has]) * slope, count) + row * np.repeat(slope, count)
    return has, start, count, x


def star_discrepancy(x0, y0, x1, y1, valid) -> np.ndarray:
    """(S,) each segment's star discrepancy against the pixel centres: walking the rows ``r + 1/2`` it spans, the
    largest absolute running sum, from either end, of (pixel centres left of it) - (its x); 0 where not valid.

    Computed by the counting kernel (:func:`roughlight.render.fast.raster.star_discrepancy`, 13 times as fast on
    200,000 segments) where the machine can build it, else by :func:`star_discrepancy_numpy`: the same to the bit.
    """
    global STAR_KERNEL
    if STAR_KERNEL:
        from . import raster

        try:
            return raster.star_discrepancy(x0, y0, x1, y1, valid)
        except RuntimeError:  # no C compiler: the random tiles say so; the regular surfaces need none
            STAR_KERNEL = False
    return star_discrepancy_numpy(x0, y0, x1, y1, valid)


#: Whether :func:`star_discrepancy` still tries the counting kernel (False once it could not be built).
STAR_KERNEL = True


def star_discrepancy_numpy(x0, y0, x1, y1, valid) -> np.ndarray:
    """:func:`star_discrepancy` in numpy: the running sum over every segment's rows in one ``cumsum``."""
    star = np.zeros(len(x0))
    has, start, count, x = _row_crossings(x0, y0, x1, y1, valid)
    if has.size == 0:
        return star
    running = np.cumsum(0.5 - (x - np.floor(x)))  # pixel centres left of x, minus x: mean 0
    before = np.concatenate([[0.0], running])[start]
    high = np.maximum(np.maximum.reduceat(running, start) - before, 0.0)
    low = np.minimum(np.minimum.reduceat(running, start) - before, 0.0)
    total = running[start + count - 1] - before
    star[has] = np.max(np.abs([high, low, total - high, total - low]), axis=0)
    return star


def choose_lattices(regions: Regions, shear, matrices, shifts, values):
    """The lattices with the smallest :func:`value_discrepancy` for each view, best first.

    Parameters
    ----------
    regions : Regions
    shear : (V, 2) array
        Each view's plan shift ``d``.
    matrices : list of (2, 2) int arrays
        The candidates (:func:`candidate_lattices`).
    shifts : list of (2,) arrays
        Each lattice's surface shift in periods, as it will be drawn.
    values : (3, V, R) array
        :func:`region_values`.

    Returns
    -------
    order : (K, V) int array
        Index into ``matrices`` of each view's :data:`AVERAGED` best lattices, best first (K = :data:`AVERAGED`,
        or the number of candidates if there are fewer).
    score : (V,) array
        The best lattice's value discrepancy, 8-bit levels.
    """
    shear = np.atleast_2d(np.asarray(shear, float))
    start, end, sides = unique_edges(regions)
    steps = edge_steps(regions, sides, shear, values)
    scores = np.array([value_discrepancy(start, end, steps, shear, m, s) for m, s in zip(matrices, shifts)])
    order = np.argsort(scores, axis=0, kind="stable")[:AVERAGED]
    return order, scores[order[0], np.arange(len(shear))]


def ratio_shares(pixel_counts, regions: Regions, shear, matrix, shift=(0.0, 0.0)):
    """Each facet's lit and shadowed share of the image, from the rendered pixel counts.

    Parameters
    ----------
    pixel_counts : (V, R) array
        Pixels of each view's tile showing each region's visible part.
    regions, shear, matrix, shift
        As :func:`counts_and_areas` (the lattice the views were drawn with).

    Returns
    -------
    lit, shadow : (V, F) arrays
        Shares, normalised to sum to 1 over the facets of each view that shows any surface.
    """
    pixel_counts = np.asarray(pixel_counts, float)
    counts, areas = counts_and_areas(regions, shear, matrix, shift)
    n_pixels = abs(round(np.linalg.det(np.asarray(matrix, float))))
    return _facet_shares(normalised_shares(pixel_counts, n_pixels, counts, areas), regions)


def normalised_shares(visible, per_tile: int, total=None, areas=None) -> np.ndarray:
    """(V, R) each region's share of each view's image from its pixel counts, summing to 1 a view (0 where a view
    shows nothing).

    Parameters
    ----------
    visible : (V, R) float array
        Pixels of each view's tile showing each region's visible part.
    per_tile : int
        A tile's pixels.
    total, areas : (V, R) float arrays, optional
        Pixel centres in each region's whole projection and its exact projected area (periods^2). Where the
        total is at least one, the share is ``areas * visible / total`` (a region seen whole has as many pixels
        as its projection holds: the ratio then gives its exact area); elsewhere, or without them, it is
        ``visible / per_tile``.
    """
    if total is None:
        share = visible / per_tile
    else:  # np.where(total > 0.5, areas * visible / np.maximum(total, 1.0), visible / per_tile), in one array
        share = areas * visible
        share /= np.maximum(total, 1.0)
        np.divide(visible, per_tile, out=share, where=~(total > 0.5))
    sums = share.sum(axis=1, keepdims=True)
    share /= np.where(sums > 0, sums, 1.0)
    share[~(sums[:, 0] > 0)] = 0.0
    return share


class AdaptivePlan(NamedTuple):
    """Adaptive sampling's plan of one sweep of the regular surface (:func:`adaptive_plan`)."""

    #: (V,) bool, the views where nothing is hidden
    exact: np.ndarray
    #: (n_exact, F) each facet's lit and shadowed share in those views, their exact projected areas
    lit: np.ndarray
    shadow: np.ndarray
    #: the other views' lattice passes; their ``members`` index the views where ``exact`` is False
    passes: list[LatticePass]


def adaptive_plan(regions: Regions, views, light_dir, lighting, settings) -> AdaptivePlan:
    """Which views are exact and on which lattices the others are drawn, for adaptive sampling.

    Where every facet faces the view nothing is hidden: each region's share is its exact area
    (:func:`area_shares`). Each of the others is drawn on its best lattice of
    :func:`roughlight.render.fast.sampling.candidate_lattices` (:func:`choose_lattices`), and on the next best too,
    averaged, where even the best may be off by ``settings.average_lattices_above`` levels.

    Parameters
    ----------
    regions : Regions
        :func:`adaptive_regions` of the surface under this light.
    views : (V, 3) array
        Unit vectors toward the detector, none grazing.
    light_dir : (3,) array
        Unit vector toward the light.
    lighting : Lighting
    settings : FastSettings
    """
    shears = views[:, :2] / views[:, 2:3]
    whole = all_facing(regions, shears)
    lit, shadow = area_shares(regions, shears[whole])
    views, shears = views[~whole], shears[~whole]
    if len(views) == 0:
        return AdaptivePlan(whole, lit, shadow, [])
    matrices = candidate_lattices(int(settings.pixels_per_period))
    shifts = [surface_shift(m, settings.jitter) for m in matrices]
    values = region_values(regions, light_dir, views, lighting)
    order, score = choose_lattices(regions, shears, matrices, shifts, values)
    many = score >= float(settings.average_lattices_above)
    return AdaptivePlan(whole, lit, shadow, lattice_passes(matrices, shifts, order, many, settings.max_framebuffer))
