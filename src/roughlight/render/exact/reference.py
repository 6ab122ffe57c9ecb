"""Exact reference values of a sweep, by polygon clipping (no sampling, no GPU).

What is measured
----------------
For one surface (``truncation``, ``aspect``; see :mod:`roughlight.surfaces.geometry`),
one directional light and many views, the value of a view is the mean, over
the projected image of the *infinite* periodic surface seen by an
orthographic detector looking along ``-V``, of the per-pixel value of each
component (diffuse, specular, total) of the lighting equation
(:mod:`roughlight.render.shading`). The light is directional and the detector
orthographic, so every flat facet has one value where it is lit and the
ambient-only value where it is shadowed, and

    value = sum over facets f of  q(f, lit) * A_lit(f) + q(f, shadow) * A_shadow(f)

with ``A_lit`` / ``A_shadow`` the visible-and-lit / visible-and-shadowed
areas of facet ``f`` in the view's oblique base-plane coordinates (below)
and ``q`` the 8-bit value ``quantize(component)`` (``quantized=True``, what
an 8-bit framebuffer stores) or the raw float.

Oblique coordinates
-------------------
Every view ray (direction ``-V``, ``0 < e < 180``) crosses ``z = 0`` once;
the world point ``p`` maps to ``(s, u) = (p.x - p.z Vx/Vz, p.y - p.z Vy/Vz)``.
Up to a constant area factor the projected image *is* the ``(s, u)`` plane,
periodic with the unit lattice, so the image mean is the mean over one unit
cell: the visible parts of the facets of one period (all lattice copies
counted mod 1) tile it and their areas sum to exactly 1 (checked to 1e-9 on
every view: a clipping bug raises). Along a view ray the surface point seen
is the one with the largest ``z``. The projections of two facets overlap in a
convex region on which one of them is in front throughout (facets meet only
at edges), so the visible region of a facet is its projection minus the
union of the projections, on that overlap, of the facet copies in front of it
(depth compared at the overlap's centroid). Only facets facing the detector
(``N.V > 0``) can be seen or need to be considered as occluders: any ray
that meets a back-facing facet has entered the solid through a front-facing
facet higher up.

On a regular surface the square's symmetries join views eight at a time: a view's visible regions are clipped
at the view whose azimuth they take into [0, 45] degrees and turned back (:mod:`.square_views`). A sweep of a
regular surface clips its views in C instead (:func:`view_areas`, :mod:`.pyramid`: the same construction with
convex pieces, GEOS's areas to 1e-9 of the image); GEOS clips random tiles, and any view the C clipper refuses.

Shadows are the same construction along the light, in light-oblique
coordinates ``(a, b) = (p.x - p.z Lx/Lz, p.y)``: the lit part of a facet is
the part seen "by the light". It depends only on the light, so it is computed
once per sweep and stored as a region of the facet's plan footprint (its
``(x, y)`` projection); each view maps it through the facet's plane into
``(s, u)`` (an affine map) and intersects it with the facet's visible region.

Conventions shared with the renderer (:mod:`roughlight.render.fast.periodic`)
------------------------------------------------------------------
* Grazing views, ``e`` = 0 or 180 (:func:`roughlight.render.views.is_grazing`, the one grazing rule of
  :mod:`roughlight.render.sweep`): the detector sees no area; every component and the coverage are 0.
* ``lighting.shadows`` true and the light in the plane (``Lz < 1e-9``, i.e.
  incidence 0) on a non-flat surface: every point is shadowed (ambient only).
  The plate casts no shadow; its ``N.L`` is then 0 and it is ambient-only
  anyway.
* ``lighting.shadows`` false: every point is lit; ``facet_components``
  applies ``N.L > 0``.
* A facet with ``N.L <= 0`` is wholly shadowed; so is a facet edge-on to the
  light to floating point (``|N.L| * |n| / (|n_z| L_z) < 1e-12``, the
  area ratio of its light projection): no light reaches it.
* The plate (``t = 0`` or ``aspect = 0``) is one facet, visible everywhere.

Accuracy
--------
Exact up to floating point: areas come from GEOS's overlay in double
precision; overlaps smaller than 1e-13 (in units of the period squared;
floating-point slivers along shared edges) are ignored. The resulting error
of a component is below :data:`REFERENCE_ERROR` (0-255 scale), far below one
8-bit step. Note that a renderer computing the same equation in single
precision may round a facet's value to the other 8-bit integer when the
exact value lies within ~1e-5 of a half-integer; that is a property of the
renderer, not an error of the reference.
"""

from __future__ import annotations

import functools

import numpy as np
import shapely
import shapely.errors
from shapely import affinity

from ...surfaces.surface import Surface
from .. import sweep
from ..shading import EXTRAS, Lighting, check_incidence, check_light_azimuth, facet_sums, light_direction, view_direction
from ..sweep import sweep_views
from ..views import is_grazing
from .clipping import (
    EDGE_ON,
    MIN_OVERLAP,
    Facets,
    affine_each,
    area_parts,
    from_oblique,
    overlay,
    period_facets,
    projection_ratios,
    to_oblique,
    visible_regions,
)
from .pyramid import view_areas
from .settings import ReferenceSettings
from .square_views import square_visible_regions

__all__ = [
    "REFERENCE_ERROR",
    "AREA_TOLERANCE",
    "reference_sweep",
    "reference_views",
    "visible_lit_areas",
    "lit_footprints",
    "lit_scene",
    "shares_under",
]

#: Bound on |reference - exact value| of each component, on the 0-255 scale,
#: from floating-point area arithmetic (the method itself is exact). Per view
#: the visible areas sum to 1 within :data:`AREA_TOLERANCE`; values are at
#: most 255 per unit area; 255 * 1e-9 < 1e-6.
REFERENCE_ERROR = 1e-6

#: The visible areas of a view must sum to 1 within this (else RuntimeError).
AREA_TOLERANCE = 1e-9

#: Snap-rounding grids (periods) of the robust fallbacks, finest first: when an overlay in double precision
#: fails (GEOS's topology errors, or areas not summing to 1, seen on random tiles whose thin facets project to
#: near-collinear slivers), the view is recomputed with every overlay snap-rounded to the first grid (GEOS
#: OverlayNG in fixed precision, robust by construction), and if its checks still fail, to the next (a lit
#: footprint is first redone alone: :func:`_lit_footprint`). Moving
#: vertices by at most a grid step changes an area by about its perimeter times it: at most
#: :func:`snapped_tolerance` (1e-5 for the coarsest, 0.003 of an 8-bit level).
SNAP_GRIDS = (1e-10, 1e-9, 1e-8)
#: The finest snap-rounding grid (the first fallback).
SNAP_GRID = SNAP_GRIDS[0]

#: Snap-rounding grid (periods) of the one overlay that splits a facet's visible region into its lit and shadowed
#: parts, in every view. No check can catch that overlay going wrong in double precision: a lit part whose edge runs
#: along the visible region's edge (a thin sliver at a grazing view) came out with no area, and the whole visible
#: region was counted as shadowed (random pyramids, seed 1, t 0.5, a 0.5, i 30, e 3, phi 5: 1.70 levels off, where
#: the fast renderer and a ray cast agree), while areas still summed as they should. Snap-rounded, the overlay is
#: robust by construction. Moving vertices by 1e-12 changes an area by about its perimeter times that (oblique
#: perimeters reach tens of periods at grazing views): under 1e-7 of a level, within :data:`REFERENCE_ERROR`.
LIT_SPLIT_GRID = 1e-12


def snapped_tolerance(grid_size: float) -> float:
    """How far from 1 the visible areas of a view snap-rounded to ``grid_size`` may sum (1000 grid steps)."""
    return 1e3 * float(grid_size)


#: Light grazing the plane (matches the renderer's ``light_dir[2] < 1e-9``).
_GRAZING_LIGHT = 1e-9



def _check_sum(total: float, what: str, grid_size=None) -> None:
    tolerance = AREA_TOLERANCE if grid_size is None else snapped_tolerance(grid_size)
    if not abs(total - 1.0) <= tolerance:
        raise RuntimeError(
            f"reference clipping failed: the visible areas of the {what} sum to {total!r}, not 1"
        )


def _check_overlap(both: float, a: float, b: float, whole: float, what: str, grid_size=None) -> None:
    """Inclusion-exclusion bounds of an intersection of two parts of one facet's projection (area ``whole``):
    ``a + b - whole <= |A & B| <= min(a, b)``. GEOS can return an empty intersection of two valid polygons whose
    edges nearly coincide (seen: a lit region and a visible region of 0.34 and 0.45 of a 0.45 facet meeting in
    nothing), which these bounds catch; the caller then recomputes snap-rounded."""
    tolerance = AREA_TOLERANCE if grid_size is None else snapped_tolerance(grid_size)
    if both < a + b - whole - tolerance or both > min(a, b) + tolerance:
        raise RuntimeError(f"reference clipping failed: the lit and visible parts of {what} meet in {both!r}, "
                           f"outside [{a + b - whole!r}, {min(a, b)!r}]")


def with_fallback(compute, *args):
    """``compute(*args, grid_size=None)`` in double precision; if GEOS fails or the checks do not hold, again
    snap-rounded to each of :data:`SNAP_GRIDS` in turn (OverlayNG's fixed precision); the last one's error is
    raised if every grid fails."""
    try:
        return compute(*args, grid_size=None)
    except (shapely.errors.GEOSException, RuntimeError) as exc:
        error = exc
    for grid_size in SNAP_GRIDS:
        try:
            return compute(*args, grid_size=grid_size)
        except (shapely.errors.GEOSException, RuntimeError) as exc:
            error = exc
    raise error


def _lit_regions(surf: Facets, incidence: float, shadows: bool, light_azimuth: float = 0.0) -> list:
    """Lit part of each facet's plan footprint (shapely geometries)."""
    return with_fallback(_lit_regions_at, surf, incidence, shadows, light_azimuth)


def _lit_regions_at(surf: Facets, incidence: float, shadows: bool, light_azimuth: float = 0.0, grid_size=None) -> list:
    L = light_direction(incidence, light_azimuth)
    ndotl = surf.normals @ L
    if not shadows or surf.plate:
        # every point with N.L > 0 is lit (nothing casts a shadow on the
        # plate; its N.L is 0 at incidence 0)
        return [fp if nl > 0 else shapely.Polygon() for fp, nl in zip(surf.footprints, ndotl)]
    if L[2] < _GRAZING_LIGHT:
        return [shapely.Polygon() for _ in surf.footprints]
    d = np.array([L[0] / L[2], L[1] / L[2]])
    regions, det = visible_regions(surf, d, grid_size)
    regions = np.array(regions, dtype=object)
    _check_sum(float(sum(shapely.area(regions))), f"light view (incidence {incidence})", grid_size)
    out = np.array([shapely.Polygon() for _ in regions], dtype=object)
    lit = np.flatnonzero((det > EDGE_ON) & (ndotl > 0) & ~shapely.is_empty(regions))
    out[lit] = _lit_footprints(surf, lit, regions[lit], det[lit], d, grid_size)
    # mapped back onto their facets, the lit parts still fill the light's view (areas scale by det)
    front = det > EDGE_ON
    _check_sum(float(sum(shapely.area(out[front]) * det[front])), f"lit footprints (incidence {incidence})",
               grid_size)
    return list(out)


def _lit_footprints(surf: Facets, facets, regions, det, d, grid_size=None) -> np.ndarray:
    """:func:`_lit_footprint` of each of ``facets`` ((n,), their visible ``regions`` and area ratios ``det``), in
    double precision in whole-array GEOS calls; a facet whose footprint does not pass there (or all of them, if
    GEOS raises) goes through :func:`_lit_footprint` alone."""
    done = np.zeros(len(facets), bool)
    lit = np.empty(len(facets), dtype=object)
    if grid_size is None:
        plan = affine_each(regions, from_oblique(surf, facets, d))
        try:
            lit = area_parts(shapely.intersection(plan, np.array(surf.footprints, dtype=object)[facets]))
            done = np.abs(shapely.area(lit) * det - shapely.area(regions)) <= AREA_TOLERANCE
        except shapely.errors.GEOSException:  # which facet raised is not known: each one alone
            pass
    for i in np.flatnonzero(~done):
        lit[i] = _lit_footprint(surf, facets[i], regions[i], det[i], d, grid_size)
    return lit


def _lit_footprint(surf: Facets, f: int, region, det: float, d, grid_size=None):
    """Facet ``f``'s lit footprint: its visible ``region`` in the light's view (plan shift ``d``, area ratio
    ``det``) mapped back onto its plan footprint, the floating-point overhang trimmed (the lit part lies on the
    facet). In double precision GEOS can return most of the footprint as the intersection of a sliver with it (random
    pyramids t 0.2, a 0.4, seed 1, incidence 30, facet c3_0_east_w00: 0.003054 of the light's view mapped back from
    0.000098 visible), which the sum over facets then catches; where the area mapped back is not the visible area
    to :data:`AREA_TOLERANCE`, or GEOS raises a topology error, this one overlay is snap-rounded to
    :data:`SNAP_GRID` instead of clipping the whole light's view again snap-rounded (most random tiles' light views
    came out of double precision wrong this way, and snap-rounding all of it took eight times as long)."""
    plan = affinity.affine_transform(region, from_oblique(surf, f, d))
    if grid_size is None:
        try:
            lit = area_parts(shapely.intersection(plan, surf.footprints[f]))
            if abs(lit.area * det - region.area) <= AREA_TOLERANCE:
                return lit
        except shapely.errors.GEOSException:  # a topology error (random pyramids t 1, a 1, seed 1, incidence 30)
            pass
        grid_size = SNAP_GRID
    return area_parts(overlay(shapely.intersection, plan, surf.footprints[f], grid_size=grid_size))


def _without_slivers(region):
    """``region`` without its parts of no area (zero-width spikes and bow-ties that polygon clipping of random
    tiles leaves; mapped into a view they can turn invalid and count twice, as in random pyramids, seed 2,
    t 1, a 1, i 30, e 45, phi 15)."""
    every = shapely.get_parts(region)
    parts = [p for p in every if p.area > MIN_OVERLAP]
    if len(parts) == len(every):
        return region
    return area_parts(shapely.union_all(parts)) if parts else shapely.Polygon()


def _without_slivers_each(regions) -> list:
    """:func:`_without_slivers` of each of a list of regions: those with a part of no area alone, the others
    found in one GEOS call and kept as they are."""
    regions = list(regions)
    parts, owner = shapely.get_parts(np.array(regions, dtype=object), return_index=True)
    for f in np.unique(owner[shapely.area(parts) <= MIN_OVERLAP]):
        regions[f] = _without_slivers(regions[f])
    return regions


class LitScene:
    """Everything of a sweep that does not depend on the view."""

    def __init__(self, surface: Surface, incidence, shadows, light_azimuth=0.0):
        self.surf = period_facets(surface)
        self.incidence = check_incidence(incidence)
        self.light_azimuth = check_light_azimuth(light_azimuth)
        self.shadows = bool(shadows)
        #: unit vector toward the light
        self.light = light_direction(self.incidence, self.light_azimuth)
        self.lit = _without_slivers_each(_lit_regions(self.surf, self.incidence, bool(shadows), self.light_azimuth))
        fp_area = shapely.area(np.array(self.surf.footprints, dtype=object))
        self.fp_area = fp_area
        lit_area = shapely.area(np.array(self.lit, dtype=object))
        self.all_lit = np.abs(lit_area - fp_area) <= 1e-15 * np.maximum(fp_area, 1.0)
        self.none_lit = lit_area <= 0.0

    def areas(self, elevation: float, azimuth: float) -> tuple[np.ndarray, np.ndarray]:
        """Visible-lit and visible-shadowed area of each facet, one view (0 if grazing)."""
        n = len(self.surf.names)
        if is_grazing(elevation):
            return np.zeros(n), np.zeros(n)
        return with_fallback(self._areas_at, elevation, azimuth)

    def _areas_at(self, elevation: float, azimuth: float, grid_size=None) -> tuple[np.ndarray, np.ndarray]:
        return self.split(*_visible_at(self.surf, elevation, azimuth, grid_size), grid_size)

    def split(self, view, regions, vis, det, d, grid_size=None) -> tuple[np.ndarray, np.ndarray]:
        """The view's visible ``regions`` (areas ``vis``, projection ratios ``det``, plan shift ``d``;
        :func:`_visible_at`) split into each facet's lit and shadowed area under this scene's light."""
        lit = np.zeros(len(self.surf.names))
        for f, region in enumerate(regions):
            if vis[f] <= 0.0 or self.none_lit[f]:
                continue
            if self.all_lit[f]:
                lit[f] = vis[f]
                continue
            lit_view = affinity.affine_transform(self.lit[f], to_oblique(self.surf, f, d))
            if not lit_view.is_valid:
                # parts that touched in plan can overlap after the map, by rounding: their area would count twice
                lit_view = area_parts(lit_view)
            if vis[f] >= self.fp_area[f] * det[f] - AREA_TOLERANCE:
                # wholly visible: no overlay (GEOS can misjudge a lit part with sliver spikes)
                lit[f] = min(lit_view.area, vis[f])
                continue
            both = overlay(shapely.intersection, region, lit_view,
                           grid_size=LIT_SPLIT_GRID if grid_size is None else grid_size).area
            _check_overlap(both, vis[f], lit_view.area, self.fp_area[f] * det[f],
                           f"facet {self.surf.names[f]}, view {view}", grid_size)
            lit[f] = min(both, vis[f])
        return lit, vis - lit


def _visible_at(surf: Facets, elevation: float, azimuth: float, grid_size=None):
    """One view's visible region of each facet, checked to fill the image: ``(view, regions, vis, det, d)``
    with ``view`` its name for messages, ``vis`` the regions' areas, ``det`` the facets' projection ratios and
    ``d`` the view's plan shift."""
    V = view_direction(elevation, azimuth)
    d = np.array([V[0] / V[2], V[1] / V[2]])
    if surf.symmetry == "square" and grid_size is None:
        # clipped once for the views the square's symmetry joins, turned for the others (square_views); a view
        # whose checks fail is clipped again here, snap-rounded (with_fallback)
        regions, det = square_visible_regions(surf, d), projection_ratios(surf, d)
    else:
        regions, det = visible_regions(surf, d, grid_size)
    vis = np.array([r.area for r in regions])
    view = f"(e={elevation}, phi={azimuth})"
    _check_sum(float(vis.sum()), f"view {view}", grid_size)
    return view, regions, vis, det, d


def shares_under(scenes, elevation: float, azimuth: float) -> tuple[np.ndarray, np.ndarray]:
    """Each facet's visible-lit and visible-shadowed share of one view under each of several lights of one
    surface, the view's visibility clipped once (what a table of light directions needs).

    Parameters
    ----------
    scenes : sequence of LitScene
        One surface (:func:`lit_scene`) under each light.
    elevation, azimuth : float
        The view, degrees (not grazing).

    Returns
    -------
    lit, shadow : (len(scenes), F) arrays, fractions of the view's image (each row's sum is 1)
    """
    if is_grazing(elevation):
        raise ValueError(f"shares_under: elevation {elevation!r} is grazing (no image)")
    return with_fallback(_shares_under_at, tuple(scenes), float(elevation), float(azimuth))


def _shares_under_at(scenes, elevation: float, azimuth: float, grid_size=None):
    """:func:`shares_under` at one precision: :meth:`LitScene.split`'s steps, each facet's lit parts of all the
    lights mapped into the view and clipped as one array (GEOS's vectorised calls)."""
    view, regions, vis, det, d = _visible_at(scenes[0].surf, elevation, azimuth, grid_size)
    surf = scenes[0].surf
    lit = np.zeros((len(scenes), len(vis)))
    all_lit = np.array([scene.all_lit for scene in scenes])
    clipped = ~all_lit & ~np.array([scene.none_lit for scene in scenes])
    for f, region in enumerate(regions):
        if vis[f] <= 0.0:
            continue
        lit[all_lit[:, f], f] = vis[f]
        todo = np.flatnonzero(clipped[:, f])
        if todo.size == 0:
            continue
        a, b, c, e, xo, yo = to_oblique(surf, f, d)
        matrix, offset = np.array([[a, b], [c, e]]), np.array([xo, yo])
        lit_view = shapely.transform(np.array([scenes[k].lit[f] for k in todo], object),
                                     lambda xy, m=matrix, o=offset: xy @ m.T + o)
        invalid = np.flatnonzero(~shapely.is_valid(lit_view))
        for k in invalid:  # parts that touched in plan can overlap after the map, by rounding (LitScene.split)
            lit_view[k] = area_parts(lit_view[k])
        if vis[f] >= scenes[0].fp_area[f] * det[f] - AREA_TOLERANCE:
            lit[todo, f] = np.minimum(shapely.area(lit_view), vis[f])
            continue
        both = _lit_parts(region, lit_view, grid_size)
        for k, area in zip(todo, both):
            _check_overlap(area, vis[f], scenes[k].lit[f].area * det[f], scenes[0].fp_area[f] * det[f],
                           f"facet {surf.names[f]}, view {view}", grid_size)
        lit[todo, f] = np.minimum(both, vis[f])
    return lit, vis - lit


def _lit_parts(region, lit_views, grid_size=None) -> np.ndarray:
    """(n,) areas of one visible ``region`` meeting each of ``lit_views`` ((n,) geometries: one facet's lit parts
    under n lights, mapped into the view).

    In double precision first, then snap-rounded to :data:`LIT_SPLIT_GRID` (:meth:`LitScene.split`'s overlay)
    wherever that found no overlap although the two regions' boxes overlap. There GEOS in double precision returned
    no area for a lit part wholly inside the visible region (t 1, a 1, the light at incidence 10 and azimuth 15,
    the view at e 22 and phi 307.5: 0.217 of the image lit counted as shadowed), which no check on the areas can
    catch; of the default share table's 123,000 overlays, about 15 to 350 are clipped again. A fallback's
    ``grid_size`` snap-rounds them all."""
    if grid_size is not None:
        return _snapped_overlaps(region, lit_views, grid_size)
    both = shapely.area(shapely.intersection(region, lit_views))
    box, boxes = np.asarray(shapely.bounds(region)), shapely.bounds(lit_views)
    meet = ((np.minimum(boxes[:, 2], box[2]) > np.maximum(boxes[:, 0], box[0]))
            & (np.minimum(boxes[:, 3], box[3]) > np.maximum(boxes[:, 1], box[1])))
    again = np.flatnonzero((both <= MIN_OVERLAP) & meet)
    if len(again):
        both[again] = _snapped_overlaps(region, lit_views[again], LIT_SPLIT_GRID)
    return both


def _snapped_overlaps(region, geometries, grid_size) -> np.ndarray:
    """(n,) areas of ``region`` meeting each of ``geometries``, :func:`overlay`'s snap-rounding over the array:
    each part snapped to ``grid_size``, then clipped on it (lines and points an overlay leaves carry no area)."""
    return shapely.area(shapely.intersection(shapely.set_precision(area_parts(region), grid_size),
                                             shapely.set_precision(geometries, grid_size), grid_size=grid_size))


# ---------------------------------------------------------------------------
# public API


@functools.lru_cache(maxsize=16)
def lit_scene(surface: Surface, incidence: float, shadows: bool, light_azimuth: float = 0.0) -> LitScene:
    """:class:`LitScene` of ``surface`` under the light at ``incidence`` (and ``light_azimuth``, degrees), kept
    for the process's last 16: a random tile's takes about a second, and the fast method's regions, the exact
    reference and the measurements ask for one tile under one light many times. A scene is never changed once
    made."""
    return LitScene(surface, float(incidence), bool(shadows), float(light_azimuth))


def lit_footprints(surface: Surface, incidence, shadows=True) -> dict:
    """Lit part of each facet of one period, as a region of its plan footprint.

    Parameters
    ----------
    surface : Surface
        The surface (:mod:`roughlight.surfaces.surface`).
    incidence : float
        Light elevation above the plane, degrees in [0, 90]; the light is at
        azimuth 0, ``L = (cos i, 0, sin i)``.
    shadows : bool
        Whether the surface casts shadows (``Lighting.shadows``). Without
        shadows the whole footprint of every facet with ``N.L > 0`` is lit.

    Returns
    -------
    dict name -> shapely geometry
        In plan coordinates ``(x, y)`` of the cell ``[0, 1]^2``; empty where
        the facet is wholly shadowed. The facet's true lit area is the plan
        area divided by its normal's ``z``.
    """
    scene = lit_scene(surface, incidence, shadows)
    return dict(zip(scene.surf.names, scene.lit))


def visible_lit_areas(surface: Surface, incidence, azimuth, elevation, shadows=True) -> dict:
    """Visible-and-lit and visible-and-shadowed area of each facet, one view.

    Parameters
    ----------
    surface : Surface
        The surface (:mod:`roughlight.surfaces.surface`).
    incidence : float
        Light elevation, degrees in [0, 90] (light at azimuth 0).
    azimuth, elevation : float
        The view, degrees: ``V = (cos e cos phi, cos e sin phi, sin e)``,
        ``e`` in [0, 180].
    shadows : bool
        Whether shadows are cast.

    Returns
    -------
    dict name -> (lit, shadowed)
        Areas in the view's oblique base-plane coordinates, i.e. fractions of
        the projected image (they sum to 1 for ``0 < e < 180``; all 0 for
        grazing views). Facets are named as in
        :data:`roughlight.surfaces.geometry.FACET_NAMES`; facets that do not exist (the
        top of the full pyramid, the sides of the plate) are absent. "Lit"
        means reached by the light with ``N.L > 0``.
    """
    scene = lit_scene(surface, incidence, shadows)
    views = sweep_views(azimuth, elevation)
    if len(views) != 1:
        raise ValueError("visible_lit_areas takes one view; use reference_sweep for many")
    lit, shadow = scene.areas(float(views.elevation[0]), float(views.azimuth[0]))
    return {name: (float(a), float(b)) for name, a, b in zip(scene.surf.names, lit, shadow)}


def reference_sweep(surface: Surface, incidence, azimuth, elevation, lighting=None, settings=None,
                    light_azimuth=0.0) -> dict:
    """Exact mean image value of each component for many views of one surface.

    Parameters
    ----------
    surface : Surface
        Truncation (fraction of the pyramid height kept, 0 = flat plate,
        1 = full pyramid) and aspect (full pyramid height over the period).
    incidence : float
        Light elevation above the surface plane ``i``, degrees in [0, 90].
    azimuth, elevation : array_like, degrees
        The views (one shape, flattened to ``n_views``; :func:`roughlight.render.sweep.sweep_views`): view
        azimuth ``phi`` (the study uses [0, 180)) and elevation ``e`` in
        [0, 180]; ``V = (cos e cos phi, cos e sin phi, sin e)``, so ``e > 90``
        looks from the far side of the zenith.
    lighting : Lighting, optional
        Light and material (default ``Lighting()``); ``lighting.shadows``
        switches cast and self shadows.
    settings : ReferenceSettings, optional
        ``quantized`` True (default): each facet's value is the 8-bit framebuffer value
        ``quantize(component)`` (clamped to [0, 255], rounded to nearest),
        as the renderer stores per pixel; False: the raw float.

    Returns
    -------
    dict
        ``'diffuse'``, ``'specular'``, ``'total'``: (n_views,) float64 arrays,
        the mean over the projected image on the 0-255 scale (the area
        weighted sum of the facets' values); ``'coverage'``: (n_views,), the
        fraction of the image showing the surface: 1 (to 1e-9) for
        ``0 < e < 180``, 0 for grazing views (where all components are 0); ``'{component}_unrounded'``,
        ``'{component}_unshadowed'``: :func:`roughlight.render.shading.facet_sums`'.

    light_azimuth : float, optional
        The light's azimuth psi, degrees: ``L = (cos i cos psi, cos i sin psi, sin i)`` (0, the study's).

    Notes
    -----
    Exact up to floating point (see :data:`REFERENCE_ERROR`). Raises
    RuntimeError if a view's visible areas do not sum to 1 (a clipping bug)
    and ValueError for views so close to grazing that they need more than
    200,000 lattice copies.
    """
    lighting = Lighting() if lighting is None else lighting
    quantized = (settings or ReferenceSettings()).quantized
    scene = lit_scene(surface, incidence, lighting.shadows, check_light_azimuth(light_azimuth))

    def step(out, views, incidence, lighting):
        measured = views.measured
        lit, shadow = view_areas(scene, surface, views.elevation[measured], views.azimuth[measured])
        values = facet_sums(scene.surf.normals, scene.light, views.directions(), lit, shadow, lighting, quantized)
        for name, value in values.items():
            out[name][measured] = value
        out["coverage"][measured] = (lit + shadow).sum(axis=1)

    return sweep.measure(step, incidence, azimuth, elevation, lighting, gives=EXTRAS)


def reference_views(surface: Surface, incidence, azimuth, elevation, lighting=None, light_azimuth=0.0):
    """The exact reference on many views, leaving out the views it refuses instead of failing all of them.

    :func:`reference_sweep` raises ``RuntimeError`` when a view's clipping fails its own checks (seen on random
    tiles: GEOS areas off even after snap-rounding). A measurement that compares against the reference keeps the
    other views: the sweep is computed whole and, only when it raises, again one view at a time.

    Returns
    -------
    values : dict, ``diffuse``, ``specular``, ``total``: (n_views,) arrays, NaN at refused views
    refused : (n_views,) bool array
    """
    from ..shading import COMPONENTS

    azimuth = np.atleast_1d(np.asarray(azimuth, float))
    elevation = np.atleast_1d(np.asarray(elevation, float))
    try:
        exact = reference_sweep(surface, incidence, azimuth, elevation, lighting, light_azimuth=light_azimuth)
        return {c: np.asarray(exact[c], float) for c in COMPONENTS}, np.zeros(azimuth.size, bool)
    except RuntimeError:
        pass
    values = {c: np.full(azimuth.size, np.nan) for c in COMPONENTS}
    refused = np.zeros(azimuth.size, bool)
    for k in range(azimuth.size):
        try:
            one = reference_sweep(surface, incidence, azimuth[k:k + 1], elevation[k:k + 1], lighting,
                                  light_azimuth=light_azimuth)
        except RuntimeError:
            refused[k] = True
            continue
        for c in COMPONENTS:
            values[c][k] = one[c][0]
    return values, refused
