"""A regular surface's facet shares clipped exactly in C (``pyramid.c`` beside this module): each facet's
visible-lit and visible-shadowed share of a view's image, for many views under one light or many, the exact
reference's construction (:mod:`roughlight.render.exact.reference`, "Oblique coordinates") with convex pieces in
place of GEOS's overlays.

A regular surface's facets are convex, so what hides a facet along a direction (toward the viewer or the light) is
a set of convex polygons, the overlaps of its projection with the copies in front of it. Both sets are mapped back
onto the facet's plan footprint and subtracted from it, the footprint kept as disjoint convex pieces; the pieces'
areas, times the facet's projection ratio, are its visible and its visible-lit area of one period of the image
(area 1). It agrees with :meth:`LitScene.areas <roughlight.render.exact.reference.LitScene.areas>` to about
1e-11 of the image (``tests/test_pyramid_clipper.py``) and takes tens of microseconds a view, where the GEOS overlays take
one to two milliseconds: the clipped scene's per-frame shares (:mod:`roughlight.render.implicit.clipped`).
A random tile's facets are not a regular surface's: :func:`pyramid_shares` refuses one.
"""

from __future__ import annotations

import ctypes
import functools
import math
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ...surfaces.geometry import FACET_NAMES
from ...surfaces.surface import Surface
from .. import native
from ..shading import check_incidence, check_light_azimuth, light_direction, view_direction
from ..views import is_grazing
from .clipping import period_facets

__all__ = ["PyramidScene", "pyramid_shares", "shares_under_lights", "view_areas", "SOURCE", "build_kernel"]

#: The clipper's C source.
SOURCE = Path(__file__).with_name("pyramid.c")
#: The C function's error codes.
_ERRORS = {-1: "more convex pieces than it keeps (20,000 a facet)", -2: "a piece with more than 64 corners",
           -3: "no memory", -4: "more than 200,000 lattice copies (a view too close to grazing)",
           -5: "a facet of fewer than 3 or more than 4 corners, or a view below the horizon"}


def build_kernel(cache=None) -> Path:
    """The clipper's shared library (:func:`roughlight.render.native.build`: ``__pycache__/pyramid-<digest>.so``
    beside this module); ``make setup`` builds it."""
    return native.build(SOURCE, "the regular surfaces' clipper", cache)


@functools.cache
def _library():
    library = ctypes.CDLL(str(build_kernel()))
    p, n = ctypes.c_void_p, ctypes.c_int64
    library.roughlight_pyramid_shares.argtypes = [p, p, n, p, p, p, p, p, n, ctypes.c_int, p, n, p, p]
    library.roughlight_pyramid_shares.restype = ctypes.c_int
    return library


class _Facets(NamedTuple):
    """A regular surface's facets as the C function takes them."""

    #: corners (F, 4, 3), sides (F,), alpha, beta, gamma (F,) and normals (F, 3), C-contiguous
    arrays: tuple
    #: the arrays' addresses (ints: ctypes passes them at a fraction of ``data_as``'s cost)
    addresses: list
    #: (F,) int, each facet's column in FACET_NAMES order
    columns: np.ndarray
    #: whether the surface is the plate (it casts no shadow)
    plate: bool


@functools.lru_cache(maxsize=64)
def _facets(surface: Surface) -> _Facets:
    """``surface``'s facets (:func:`roughlight.render.exact.clipping.period_facets`) as the C function takes them,
    kept for the process's last 64 surfaces; a random tile is refused."""
    if not isinstance(surface, Surface):
        raise TypeError(f"pyramid_shares clips a regular surface's facets, not a {type(surface).__name__} "
                        "(a random tile: use the exact reference, roughlight.render.exact.LitScene)")
    surf = period_facets(surface)
    corners = np.zeros((len(surf.names), 4, 3))
    for f, verts in enumerate(surf.verts):
        corners[f, :len(verts)] = verts
    arrays = tuple(np.ascontiguousarray(a, dtype=np.int64 if a.dtype.kind == "i" else float)
                   for a in (corners, surf.sides, surf.alpha, surf.beta, surf.gamma, surf.normals))
    return _Facets(arrays, [a.ctypes.data for a in arrays], np.array([FACET_NAMES.index(n) for n in surf.names]),
                   bool(surf.plate))


def _clip(facets: _Facets, shadows: bool, lights: np.ndarray, views: np.ndarray, what: str):
    """The C function's shares of ``views`` ((V, 3) unit vectors toward the detector) under ``lights`` ((L, 3) unit
    vectors toward each light), both C-contiguous: (L, V, 5) arrays in FACET_NAMES order, each view's ten summing
    to 1. ``what`` names the surface and lights in an error."""
    n_lights, n_views, n_facets, a = len(lights), len(views), len(facets.columns), facets.addresses
    lit, shadowed = np.empty((n_lights, n_views, n_facets)), np.empty((n_lights, n_views, n_facets))
    err = _library().roughlight_pyramid_shares(a[0], a[1], n_facets, *a[2:], lights.ctypes.data, n_lights,
                                               int(bool(shadows) and not facets.plate), views.ctypes.data, n_views,
                                               lit.ctypes.data, shadowed.ctypes.data)
    if err:
        raise RuntimeError(f"pyramid_shares: {_ERRORS.get(err, err)} ({what})")
    total = lit.sum(axis=2, keepdims=True) + shadowed.sum(axis=2, keepdims=True)
    out = np.zeros((2, n_lights, n_views, len(FACET_NAMES)))
    out[0][..., facets.columns], out[1][..., facets.columns] = lit / total, shadowed / total
    return out[0], out[1]


class PyramidScene:
    """One regular surface under one light, ready to clip views' shares in C (:meth:`shares`): its facets as the C
    function takes them, and the light.

    Parameters
    ----------
    surface : Surface
        A regular surface (truncated pyramids or the plate); a random tile is refused.
    incidence, light_azimuth : float, degrees
        The light (:func:`roughlight.render.shading.light_direction`).
    shadows : bool
        Whether facets cast shadows (the plate casts none).
    """

    def __init__(self, surface: Surface, incidence, shadows: bool = True, light_azimuth: float = 0.0):
        self.facets = _facets(surface)
        #: (1, 3) unit vector toward the light
        self.light = np.ascontiguousarray(
            light_direction(check_incidence(incidence), check_light_azimuth(light_azimuth)), dtype=float).reshape(1, 3)
        self.shadows = bool(shadows)
        self.description = f"{surface}, incidence {incidence}, light azimuth {light_azimuth}"
        _library()  # built and loaded now, not inside a frame's time

    @property
    def nbytes(self) -> int:
        """Bytes the scene holds: its facets' corners and planes, and the light."""
        return int(sum(a.nbytes for a in self.facets.arrays) + self.light.nbytes)

    def shares(self, elevation, azimuth) -> tuple[np.ndarray, np.ndarray]:
        """:func:`pyramid_shares` of this scene: (V, 5) arrays, or (5,) for one view."""
        one = np.ndim(elevation) == 0 and np.ndim(azimuth) == 0
        if one:  # one view, as a frame asks for it: no array arithmetic around the C call
            if is_grazing(float(elevation)):
                raise ValueError(f"pyramid_shares: elevation {elevation!r} is grazing (no image)")
            e, p = math.radians(float(elevation)), math.radians(float(azimuth))
            views = np.array([[math.cos(e) * math.cos(p), math.cos(e) * math.sin(p), math.sin(e)]])
        else:
            views = _view_vectors(elevation, azimuth)
        lit, shadowed = _clip(self.facets, self.shadows, self.light, views, self.description)
        return (lit[0, 0], shadowed[0, 0]) if one else (lit[0], shadowed[0])


def _view_vectors(elevation, azimuth) -> np.ndarray:
    """(V, 3) unit vectors toward the detector of the views (arrays, broadcast), none grazing."""
    elevation, azimuth = np.broadcast_arrays(np.atleast_1d(np.asarray(elevation, float)),
                                             np.atleast_1d(np.asarray(azimuth, float)))
    grazing = is_grazing(elevation)
    if np.any(grazing):
        raise ValueError(f"pyramid_shares: elevation {elevation[grazing][0]!r} is grazing (no image)")
    return np.ascontiguousarray(view_direction(elevation, azimuth).reshape(-1, 3))


def shares_under_lights(surface: Surface, lights, elevation, azimuth, shadows: bool = True) -> tuple[np.ndarray,
                                                                                                     np.ndarray]:
    """Each facet's visible-lit and visible-shadowed share of each view under each of several lights, each view's
    visibility clipped once for all of them (what a table of light directions needs; the exact reference's
    :func:`~roughlight.render.exact.reference.shares_under`, in C).

    Parameters
    ----------
    surface : Surface
        A regular surface.
    lights : sequence of (incidence, light_azimuth)
        The lights, degrees.
    elevation, azimuth : (V,) arrays, degrees
        The views, none grazing.
    shadows : bool

    Returns
    -------
    lit, shadowed : (L, V, 5) float arrays in :data:`~roughlight.surfaces.geometry.FACET_NAMES` order; each view's
    ten sum to 1 under each light.
    """
    vectors = np.ascontiguousarray([light_direction(check_incidence(i), check_light_azimuth(p)) for i, p in lights],
                                   dtype=float).reshape(-1, 3)
    return _clip(_facets(surface), shadows, vectors, _view_vectors(elevation, azimuth),
                 f"{surface}, {len(vectors)} lights")


def pyramid_shares(surface: Surface, incidence, elevation, azimuth, shadows: bool = True,
                   light_azimuth: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Each facet's visible-lit and visible-shadowed share of each view's image, clipped exactly in C
    (:class:`PyramidScene`).

    Parameters
    ----------
    surface : Surface
        A regular surface (truncated pyramids or the plate); a random tile is refused.
    incidence, light_azimuth : float, degrees
        The light (:func:`roughlight.render.shading.light_direction`).
    elevation, azimuth : float or (V,) arrays, degrees
        The views (:func:`roughlight.render.shading.view_direction`); none may be grazing (0 or 180: no image).
    shadows : bool
        Whether facets cast shadows (the plate casts none).

    Returns
    -------
    lit, shadowed : (V, 5) float arrays (or (5,) for one view), fractions of each view's image in
    :data:`~roughlight.surfaces.geometry.FACET_NAMES` order (a facet the surface does not have: 0); each view's
    ten sum to 1.
    """
    return PyramidScene(surface, incidence, shadows, light_azimuth).shares(elevation, azimuth)


def view_areas(scene, surface: Surface, elevation, azimuth) -> tuple[np.ndarray, np.ndarray]:
    """Each facet's visible-lit and visible-shadowed area of each view (none grazing) under ``scene``'s light
    (a :class:`~roughlight.render.exact.reference.LitScene`):
    ``(V, F)`` arrays in ``scene.surf.names``' order, each row summing to 1. A regular surface's are clipped in C
    (:class:`PyramidScene`, the same construction with convex pieces: GEOS's to about
    1e-11, a view in tens of microseconds against one to two milliseconds); a random tile's, or a regular surface's
    the C clipper refuses, by GEOS (:meth:`LitScene.areas
    <roughlight.render.exact.reference.LitScene.areas>`)."""
    elevation, azimuth = np.asarray(elevation, float), np.asarray(azimuth, float)
    if isinstance(surface, Surface) and elevation.size:
        try:
            lit, shadow = PyramidScene(surface, scene.incidence, scene.shadows, scene.light_azimuth).shares(
                elevation, azimuth)
            order = [FACET_NAMES.index(name) for name in scene.surf.names]
            return lit[:, order], shadow[:, order]
        except RuntimeError:  # more pieces or corners than the C clipper keeps: GEOS's overlays have no such limit
            pass
    lit = np.zeros((elevation.size, len(scene.surf.names)))
    shadow = np.zeros_like(lit)
    for row in range(elevation.size):
        lit[row], shadow[row] = scene.areas(float(elevation[row]), float(azimuth[row]))
    return lit, shadow
