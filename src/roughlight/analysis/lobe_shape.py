"""A specular lobe's shape over the hemisphere, from the views that were measured, each once.

The thesis (Ch. IV.C, Fig. 19) says its regular pyramids reflect in "rectangular" patterns whose peak shifts off
the light's plane as the view's azimuth moves ("phase shift"), where natural rough surfaces reflect in circular
lobes. This module reads that shape directly, for one lobe of one surface:

* :func:`measured_field` turns a sweep's (A, E) grid into values a direction can be looked up in: a view that was
  not rendered (coverage 0: elevation 0 and 180) is NaN, never a dark view; the zenith, which every azimuth's arc
  passes through, is the view measured at azimuth 0, once; nothing is mirrored or filled in, since azimuths
  0-175 by elevations 0-180 already cover the whole hemisphere, both sides of the light's plane.
* :func:`tangent_patch` lays the field out around a direction on the lobe's tangent plane (gnomonic coordinates in
  degrees: great circles, the horizon among them, are straight lines), bilinear between the measured views in
  (azimuth, elevation); where a neighbouring view was not rendered, or the direction lies below the horizon, the
  patch is NaN.
* :func:`lobe_shape` finds the lobe's half-maximum region there and compares it with the ellipse and the rectangle
  that have the region's own centre and second moments: ``ellipse_misfit`` and ``rectangle_misfit`` are the area
  each shape gets wrong (the symmetric difference) over the region's area, and ``squareness`` is their difference
  (positive: closer to a rectangle than to an ellipse). It says whether the lobe can be measured at all: a region
  that the horizon or the search disc cuts, or a peak too few 8-bit levels high, is not measurable, and why.
* :func:`phase_shift`: on every measured half great circle that crosses the lobe's half-maximum region, on both
  sides of the light's plane, how far (degrees) the arc's peak lies from where a circular lobe around the region's
  centre would put it; the peak is located between views (a parabola through the highest view and its two
  neighbours), so that the 1-degree view grid alone does not lift the statistic.

Angles are degrees: azimuth phi in [0, 180), elevation e in [0, 180] (a view's direction is
:func:`roughlight.render.shading.view_direction`); values are 0-255.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..render.shading import view_direction

__all__ = [
    "SEARCH_RADIUS",
    "RESOLUTION",
    "measured_field",
    "field_values",
    "tangent_basis",
    "tangent_patch",
    "lobe_shape",
    "phase_shift",
    "lobe_statistics",
    "lobe_reading",
    "CAP_RADIUS",
    "synthetic_lobe",
    "SHAPE_STATISTICS",
    "shape_misfits",
    "back_lobe_peak",
    "BACK_SEARCH",
]

#: How far from the lobe's peak its half-maximum region is looked for, degrees of tangent plane.
SEARCH_RADIUS = 30.0
#: The tangent-plane grid's step, degrees.
RESOLUTION = 0.25


def measured_field(azimuth, elevation, values, coverage=None):
    """A sweep's grid as a field over directions: the measured views only, each once.

    Parameters
    ----------
    azimuth : (A,) degrees, ascending in [0, 180), evenly spaced from 0
    elevation : (E,) degrees, ascending in [0, 180]
    values : (A, E) 0-255
    coverage : (A, E) fraction of the capture window showing the surface, optional. Views with coverage 0 were
        not rendered (they see no surface): NaN in the field, whatever the table holds there.

    Returns
    -------
    (azimuth, elevation, values): the azimuths with 180 appended (the azimuth-0 arc read backwards: the same
    views, named once more so that interpolation wraps), the elevations, and (A + 1, E) values, NaN where no view
    was measured; every arc's zenith is the azimuth-0 arc's zenith view.
    """
    az = np.asarray(azimuth, float)
    el = np.asarray(elevation, float)
    vals = np.array(values, float)
    if vals.shape != (len(az), len(el)):
        raise ValueError(f"values {vals.shape} for {len(az)} azimuths x {len(el)} elevations")
    if coverage is not None:
        vals[~(np.asarray(coverage, float) > 0)] = np.nan
    zenith = np.flatnonzero(np.isclose(el, 90.0))
    if len(zenith):
        vals[:, zenith] = vals[0, zenith]
    if not np.allclose(el + el[::-1], 180.0):
        raise ValueError("the elevations must be symmetric about 90 degrees (as 0..180 by a step)")
    return np.append(az, 180.0), el, np.vstack([vals, vals[0, ::-1]])


def _view_coordinates(directions):
    """(..., 3) unit directions above the plane -> (azimuth, elevation) of the study's views, degrees, NaN below
    the horizon."""
    d = np.asarray(directions, float)
    alpha = np.degrees(np.arctan2(d[..., 1], d[..., 0]))
    height = np.degrees(np.arctan2(d[..., 2], np.hypot(d[..., 0], d[..., 1])))
    back = alpha < 0  # the far half of an arc (e > 90); alpha = 180 is azimuth 180, the azimuth-0 arc read back
    phi = np.where(back, alpha + 180.0, alpha)
    e = np.where(back, 180.0 - height, height)
    e = np.where(phi >= 180.0, 180.0 - e, e)  # azimuth 180 is the azimuth-0 arc read backwards: named as that
    phi = np.where(phi >= 180.0, 0.0, phi)
    below = d[..., 2] < 0
    return np.where(below, np.nan, phi), np.where(below, np.nan, e)


def _bilinear(axis, x):
    """Indices i and weights w of x between axis[i] and axis[i + 1] (x outside the axis: i = -1)."""
    i = np.searchsorted(axis, x, side="right") - 1
    i = np.where(x == axis[-1], len(axis) - 2, i)
    ok = (i >= 0) & (i < len(axis) - 1) & np.isfinite(x)
    i = np.clip(i, 0, len(axis) - 2)
    w = (x - axis[i]) / (axis[i + 1] - axis[i])
    return np.where(ok, i, -1), np.where(ok, w, np.nan)


def field_values(field, directions) -> np.ndarray:
    """The field (:func:`measured_field`) at unit ``directions`` (..., 3): bilinear in (azimuth, elevation)
    between the four measured views around each; NaN below the horizon or where one of the four was not
    measured."""
    az, el, vals = field
    return _interpolated(vals, _lookup(az, el, directions))


def _lookup(az, el, directions) -> tuple:
    """Where unit ``directions`` (..., 3) fall between a field's views: the (azimuth, elevation) indices of the
    corner below each, the four corners' weights and whether all four exist."""
    phi, e = _view_coordinates(directions)
    ia, wa = _bilinear(az, phi)
    ie, we = _bilinear(el, e)
    ok = (ia >= 0) & (ie >= 0)
    ia, ie = np.where(ok, ia, 0), np.where(ok, ie, 0)
    weights = ((1 - wa) * (1 - we), wa * (1 - we), (1 - wa) * we, wa * we)
    return ia, ie, weights, ok


def _interpolated(vals, lookup) -> np.ndarray:
    """A field's (A + 1, E) ``vals`` at the places of a :func:`_lookup`; NaN where a corner is missing."""
    ia, ie, (w00, w10, w01, w11), ok = lookup
    out = w00 * vals[ia, ie] + w10 * vals[ia + 1, ie] + w01 * vals[ia, ie + 1] + w11 * vals[ia + 1, ie + 1]
    return np.where(ok, out, np.nan)


def tangent_basis(direction) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors spanning the plane tangent to the unit ``direction``: ``u1`` towards the zenith (the
    zenith's projection; +x at the zenith itself) and ``u2 = direction x u1``."""
    d = np.asarray(direction, float)
    up = np.array([0.0, 0.0, 1.0])
    u1 = up - (up @ d) * d
    if np.linalg.norm(u1) < 1e-9:
        u1 = np.array([1.0, 0.0, 0.0]) - d[0] * d
    u1 = u1 / np.linalg.norm(u1)
    return u1, np.cross(d, u1)


def tangent_patch(field, centre, radius: float = SEARCH_RADIUS, resolution: float = RESOLUTION):
    """The field on a square of the plane tangent at the unit direction ``centre``.

    Returns
    -------
    X, Y : (G, G) gnomonic coordinates, degrees (``radians(X)`` along ``u1``, towards the zenith; ``Y`` along
        ``u2``, :func:`tangent_basis`), over [-radius, radius] by ``resolution``
    values : (G, G) the field there (:func:`field_values`), NaN below the horizon or next to an unmeasured view
    directions : (G, G, 3) the unit directions of the grid's points
    """
    az, el, vals = field
    c = np.asarray(centre, float)
    X, Y, d, lookup = _patch(c.tobytes(), float(radius), float(resolution), np.asarray(az, float).tobytes(),
                             np.asarray(el, float).tobytes())
    return X, Y, _interpolated(vals, lookup), d


@functools.lru_cache(maxsize=4)  # 5.2 MB each at the default radius and resolution
def _patch(centre: bytes, radius: float, resolution: float, az: bytes, el: bytes) -> tuple:
    """A tangent patch's grid, directions and :func:`_lookup` in a field's view axes, read-only: the same for
    every field on the same views around the same direction (the claim design's synthetic lobes, at every peak),
    so made once. The arguments are the float64 arrays' bytes."""
    axis = np.arange(-radius, radius + resolution / 2, resolution)
    X, Y = np.meshgrid(axis, axis, indexing="ij")
    c = np.frombuffer(centre)
    u1, u2 = tangent_basis(c)
    d = c + np.radians(X)[..., None] * u1 + np.radians(Y)[..., None] * u2
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    ia, ie, weights, ok = _lookup(np.frombuffer(az), np.frombuffer(el), d)
    for array in (X, Y, d, ia, ie, ok, *weights):
        array.flags.writeable = False
    return X, Y, d, (ia, ie, weights, ok)


def _peak_region(values, inside, peak: float) -> np.ndarray:
    """(G, G) bool: the connected part of ``values`` (within ``inside``) at or above half of ``peak`` that holds
    the highest point."""
    from scipy import ndimage

    above = inside & (values >= peak / 2.0)
    labels, _ = ndimage.label(above)
    top = np.where(inside, values, -np.inf)
    ip, jp = np.unravel_index(int(np.argmax(top)), values.shape)
    return labels == labels[ip, jp]


def shape_misfits(X, Y, region, resolution: float = RESOLUTION) -> dict:
    """How far a grid region lies from its ellipse and its rectangle of the same centre and second moments.

    The ellipse has semi-axes ``2 sqrt(l)`` and the rectangle sides ``sqrt(12 l)`` along the region's principal
    axes (``l`` the eigenvalues of its covariance): each has the region's own moments. A shape's misfit is the
    area of the symmetric difference between it and the region, over the region's area (0: the region is that
    shape; an ellipse's rectangle and a rectangle's ellipse both give about 0.2).

    Returns
    -------
    dict: ``area`` (deg^2), ``centre_x``, ``centre_y`` (degrees), ``ellipse_misfit``, ``rectangle_misfit``,
    ``squareness`` (ellipse misfit less rectangle misfit: > 0 closer to a rectangle, < 0 closer to an ellipse),
    ``elongation`` (long over short axis, >= 1) and ``rectangularity`` (area over the bounding rectangle along
    the principal axes: 1 rectangle, pi/4 ellipse).
    """
    pts = np.stack([X[region], Y[region]], axis=1)
    area = float(region.sum()) * resolution**2
    nan = dict(area=area, centre_x=np.nan, centre_y=np.nan, ellipse_misfit=np.nan, rectangle_misfit=np.nan,
               squareness=np.nan, elongation=np.nan, rectangularity=np.nan)
    if len(pts) < 8:
        return nan
    centre = pts.mean(axis=0)
    lam, vectors = np.linalg.eigh(np.cov((pts - centre).T) + np.eye(2) * resolution**2 / 12.0)
    if lam.min() <= 0:
        return nan
    P = np.stack([X - centre[0], Y - centre[1]], axis=-1) @ vectors  # every grid point along the axes
    ellipse = (P[..., 0] ** 2 / (4 * lam[0]) + P[..., 1] ** 2 / (4 * lam[1])) <= 1.0
    rectangle = (np.abs(P[..., 0]) <= math.sqrt(3 * lam[0])) & (np.abs(P[..., 1]) <= math.sqrt(3 * lam[1]))
    n = float(region.sum())
    along = (pts - centre) @ vectors
    extent = along.max(axis=0) - along.min(axis=0) + resolution
    e_mis = float(np.sum(region ^ ellipse)) / n
    r_mis = float(np.sum(region ^ rectangle)) / n
    return dict(area=area, centre_x=float(centre[0]), centre_y=float(centre[1]), ellipse_misfit=e_mis,
                rectangle_misfit=r_mis, squareness=e_mis - r_mis, elongation=float(math.sqrt(lam[1] / lam[0])),
                rectangularity=float(area / (extent[0] * extent[1])))


#: What :func:`lobe_shape` returns where the lobe cannot be measured (with its ``why``).
SHAPE_KEYS = ("peak", "peak_azimuth", "peak_elevation", "centre_azimuth", "centre_elevation", "area",
              "ellipse_misfit", "rectangle_misfit", "squareness", "elongation", "rectangularity")


def lobe_shape(field, peak_direction, min_peak: float = 0.5, radius: float = SEARCH_RADIUS,
               resolution: float = RESOLUTION) -> dict:
    """The half-maximum region of the lobe whose highest measured view is ``peak_direction``, and its shape.

    Parameters
    ----------
    field : from :func:`measured_field`
    peak_direction : (3,) unit direction of the lobe's highest measured view
    min_peak : float
        The lowest peak (0-255) whose half-maximum contour is resolved by the 8-bit values: below it the lobe is
        not measurable (the claim design's floor, :mod:`roughlight.analysis.claims`).
    radius, resolution : degrees of tangent plane searched around the peak, and the grid's step

    Returns
    -------
    dict: :data:`SHAPE_KEYS` (peak 0-255; directions as view azimuth and elevation, degrees; the region's centre
    is its centroid on the tangent plane; the rest as :func:`shape_misfits`), ``measurable`` (bool) and ``why``
    ('' when measurable; else why not, its kind before a colon: "below the 8-bit floor: ...", "cut by the
    horizon: ...", "wider than the search disc: ...").
    """
    out = {key: np.nan for key in SHAPE_KEYS}
    out.update(measurable=False, why="")
    X, Y, values, directions = tangent_patch(field, peak_direction, radius, resolution)
    disc = np.hypot(X, Y) <= radius
    inside = disc & np.isfinite(values)
    if not inside.any():
        out["why"] = "no measured view near the lobe"
        return out
    peak = float(np.nanmax(np.where(inside, values, -np.inf)))
    ip = np.unravel_index(int(np.argmax(np.where(inside, values, -np.inf))), values.shape)
    out["peak"] = peak
    out["peak_azimuth"], out["peak_elevation"] = (float(c) for c in _view_coordinates(directions[ip]))
    if peak < min_peak:
        out["why"] = f"below the 8-bit floor: peak {peak:.2f} levels, the floor {min_peak:.3g}"
        return out
    region = _peak_region(values, inside, peak)
    from scipy import ndimage

    rim = ndimage.binary_dilation(region) & ~region
    out.update(shape_misfits(X, Y, region, resolution))
    centre = _tangent_direction(peak_direction, out["centre_x"], out["centre_y"])
    if centre is not None:
        out["centre_azimuth"], out["centre_elevation"] = (float(c) for c in _view_coordinates(centre))
    if (rim & ~np.isfinite(values)).any():
        out["why"] = "cut by the horizon: its half-maximum region reaches views that were not rendered"
    elif (rim & ~disc).any() or (region & (np.hypot(X, Y) > radius - resolution)).any():
        out["why"] = f"wider than the search disc: its half-maximum region reaches {radius:g} deg from the peak"
    elif not np.isfinite(out["squareness"]):
        out["why"] = "half-maximum region too small to have a shape"
    else:
        out["measurable"] = True
    return out


def _tangent_direction(centre, x: float, y: float):
    """The unit direction at gnomonic coordinates (x, y), degrees, on the plane tangent at ``centre``; None when
    they are not finite."""
    if not (np.isfinite(x) and np.isfinite(y)):
        return None
    u1, u2 = tangent_basis(centre)
    d = np.asarray(centre, float) + math.radians(x) * u1 + math.radians(y) * u2
    return d / np.linalg.norm(d)


def _arc_peak(elevation, values, j: int) -> float:
    """The elevation (degrees) of an arc's peak at or around view ``j`` (the first of its highest views): the middle
    of a run of equal highest views, else the vertex of the parabola through the view and its two neighbours
    (within half a step of it)."""
    run = j
    while run + 1 < len(values) and values[run + 1] == values[j]:
        run += 1
    if run > j:
        return float(0.5 * (elevation[j] + elevation[run]))
    if j == 0 or j == len(values) - 1 or not (np.isfinite(values[j - 1]) and np.isfinite(values[j + 1])):
        return float(elevation[j])
    v0, v1, v2 = values[j - 1], values[j], values[j + 1]
    curvature = v0 - 2 * v1 + v2
    if curvature >= 0:
        return float(elevation[j])
    shift = float(np.clip(0.5 * (v0 - v2) / curvature, -0.5, 0.5))
    return float(elevation[j] + shift * (elevation[j + 1] - elevation[j]))


def phase_shift(field, centre_direction, peak: float, halfwidth: float = SEARCH_RADIUS) -> dict:
    """How far each measured arc's peak lies from where a circular lobe around ``centre_direction`` would put it.

    A lobe circular around the unit direction ``D`` peaks on the half great circle of azimuth ``phi`` where that
    arc comes nearest ``D``: ``e*(phi) = atan2(Dz, Dx cos phi + Dy sin phi)`` (in (0, 180): arcs on both sides of
    the light's plane). An arc counts when its highest measured view within ``halfwidth`` of ``e*`` is at least
    half the lobe's ``peak``; its peak is located between views (:func:`_arc_peak`).

    Returns
    -------
    dict: ``phase_shift`` (mean of ``|e_peak - e*|`` over the arcs that count, degrees; NaN when none),
    ``signed_shift`` (mean of ``e_peak - e*`` with the sign taken towards the zenith on both sides of the plane,
    degrees), ``arcs`` (how many counted).
    """
    az, el, vals = field
    D = np.asarray(centre_direction, float)
    offsets, signed = [], []
    for k, phi in enumerate(az[:-1]):  # the appended azimuth 180 is the azimuth-0 arc again
        p = math.radians(phi)
        expected = math.degrees(math.atan2(D[2], D[0] * math.cos(p) + D[1] * math.sin(p)))
        near = (np.abs(el - expected) <= halfwidth) & np.isfinite(vals[k])
        if not near.any():
            continue
        idx = np.flatnonzero(near)
        arc_values = vals[k, idx]
        top = int(np.argmax(arc_values))
        if arc_values[top] < peak / 2.0:
            continue
        offset = _arc_peak(el[idx], arc_values, top) - expected
        offsets.append(abs(offset))
        signed.append(-offset if expected > 90.0 else offset)
    if not offsets:
        return {"phase_shift": np.nan, "signed_shift": np.nan, "arcs": 0}
    return {"phase_shift": float(np.mean(offsets)), "signed_shift": float(np.mean(signed)), "arcs": len(offsets)}


#: A back lobe's shape statistics: the study's name (:data:`roughlight.analysis.ensembles.STATISTICS`) -> the key of
#: :func:`lobe_statistics`.
SHAPE_STATISTICS = {"back_squareness": "squareness", "back_phase_shift": "phase_shift",
                    "back_ellipse_misfit": "ellipse_misfit", "back_rectangle_misfit": "rectangle_misfit",
                    "back_rectangularity": "rectangularity", "back_elongation": "elongation"}


def lobe_statistics(field, peak_direction, min_peak: float = 0.5) -> dict:
    """The shape of the lobe whose highest measured view is ``peak_direction`` in ``field``
    (:func:`measured_field`): the dict of :func:`lobe_shape` with :func:`phase_shift`'s ``phase_shift``,
    ``signed_shift`` and ``arcs`` around the region's centre."""
    shape = lobe_shape(field, peak_direction, min_peak=min_peak)
    arcs = {"phase_shift": np.nan, "signed_shift": np.nan, "arcs": 0}
    if np.isfinite(shape["centre_azimuth"]):
        arcs = phase_shift(field, direction(shape["centre_azimuth"], shape["centre_elevation"]), shape["peak"])
    return {**shape, **arcs}


#: The cap around a lobe's expected direction whose mean is its height in :func:`lobe_reading`, degrees.
CAP_RADIUS = 3.0


def lobe_reading(field, centre, radius: float, cap: float = CAP_RADIUS, resolution: float = RESOLUTION) -> dict:
    """A lobe read against its own background, in a disc around the direction it is expected in.

    The lobe is looked for in the disc of ``radius`` degrees of tangent plane around the unit direction ``centre``
    (a facet's mirror direction: geometry, not the data). Its **contrast** is the mean of the field over the cap
    of ``cap`` degrees around ``centre`` less its **background**, the mean over the disc's rim: a lobe stands
    above the rim by its contrast, a plane or a slope through the disc has none (the mean of a linear field over a
    circle is its value at the centre), a dip has a negative one. Its shape is that of the region above half its
    contrast: the connected part of the disc at or above ``background + (peak - background) / 2`` that holds the
    disc's highest point, with :func:`shape_misfits`' statistics and :func:`phase_shift`'s around the region's
    centre (the field less its background; each arc's peak looked for within the region's own reach of where the
    circular lobe's would be).

    Parameters
    ----------
    field : from :func:`measured_field`: the measured views only, each once
    centre : (3,) unit direction
    radius, cap, resolution : degrees of tangent plane

    Returns
    -------
    dict: ``contrast``, ``background``, ``peak`` (the field's units), the :func:`shape_misfits` keys, ``phase_shift``,
    ``signed_shift``, ``arcs``, ``measurable`` (whether the shape could be read) and ``why`` ('' or why not:
    "cut by the horizon: ...", "no lobe: ...", "half-contrast region too small ..."). The contrast is given wherever the
    whole disc was measured, the shape only where the region closes inside it.
    """
    out = {key: np.nan for key in ("contrast", "background", "peak", *SHAPE_KEYS[5:], "centre_x", "centre_y",
                                   "phase_shift", "signed_shift")}
    out.update(arcs=0, measurable=False, why="")
    X, Y, values, directions = tangent_patch(field, centre, radius, resolution)
    r = np.hypot(X, Y)
    disc = r <= radius
    if not np.isfinite(values[disc]).all():
        out["why"] = f"cut by the horizon: the {radius:g} deg disc reaches views that were not rendered"
        return out
    rim = disc & (r > radius - 2 * resolution)
    background = float(values[rim].mean())
    top = np.where(disc, values, -np.inf)
    ip = np.unravel_index(int(np.argmax(top)), top.shape)
    peak = float(top[ip])
    out.update(contrast=float(values[r <= cap].mean()) - background, background=background, peak=peak)
    if not peak > float(values[rim].max()):
        out["why"] = "no lobe: the disc's highest view lies on its rim"
        return out
    region = _island(values, disc, rim, ip, background, peak)
    out.update(shape_misfits(X, Y, region, resolution))
    region_centre = _tangent_direction(centre, out["centre_x"], out["centre_y"])
    if region_centre is None or not np.isfinite(out["squareness"]):
        out["why"] = "half-contrast region too small to have a shape"
        return out
    # each arc looks for its peak within the region's own reach from its centre: the lobe's, not the disc's
    reach = float(np.max(np.hypot(X[region] - out["centre_x"], Y[region] - out["centre_y"]))) + resolution
    az, el, vals = field
    out.update(phase_shift((az, el, vals - background), region_centre, peak - background, reach))
    out["measurable"] = True
    return out


def _island(values, disc, rim, ip, background: float, peak: float) -> np.ndarray:
    """The lobe's region in its disc: the connected part at or above half its contrast that holds the highest point
    ``ip``, the level raised above the rim's highest value where a tail of the lobe reaches the rim."""
    from scipy import ndimage

    level = max(background + (peak - background) / 2.0, np.nextafter(float(values[rim].max()), np.inf))
    labels, _ = ndimage.label(disc & (values >= level))
    return labels == labels[ip]


def synthetic_lobe(azimuth, elevation, centre, half_widths, soft=None, rotation=0.0, peak=100.0) -> np.ndarray:
    """(A, E) values of a synthetic lobe around the unit direction ``centre`` on the view grid: a Gaussian
    ``peak exp(-(x/wx)^2 - (y/wy)^2)`` or, with ``soft`` (degrees), a rectangle of half-widths (wx, wy) with
    logistic edges, in gnomonic tangent-plane coordinates (degrees) rotated by ``rotation``; 0 where the view
    faces away from ``centre``. For tests and for checking what a statistic reads."""
    A, El = np.meshgrid(np.asarray(azimuth, float), np.asarray(elevation, float), indexing="ij")
    V = view_direction(El, A)
    D = np.asarray(centre, float)
    u1, u2 = tangent_basis(D)
    cos_d = V @ D
    with np.errstate(divide="ignore", invalid="ignore"):
        x0, y0 = np.degrees((V @ u1) / cos_d), np.degrees((V @ u2) / cos_d)
    c, s = math.cos(math.radians(rotation)), math.sin(math.radians(rotation))
    x, y = c * x0 + s * y0, -s * x0 + c * y0
    wx, wy = half_widths
    if soft is None:
        values = peak * np.exp(-((x / wx) ** 2 + (y / wy) ** 2))
    else:
        edge = np.clip(np.maximum(np.abs(x) - wx, np.abs(y) - wy) / soft, -50, 50)
        values = peak / (1 + np.exp(edge))
    return np.where(cos_d > 0, values, 0.0)


def direction(azimuth: float, elevation: float) -> np.ndarray:
    """The unit direction of the view (``azimuth``, ``elevation``), degrees."""
    return np.asarray(view_direction(float(elevation), float(azimuth)), float)


#: How far (degrees) from the back lobe's predicted mirror direction its peak is looked for (and nearer it than
#: to any other facet's mirror direction).
BACK_SEARCH = 40.0


def back_lobe_peak(key, azimuth, elevation, values, coverage) -> tuple[np.ndarray | None, str]:
    """The unit direction of the back lobe's highest measured view, or (None, why) where there is none to look at.

    The back lobe's views are those nearer the grid point's back mirror direction
    (:func:`roughlight.analysis.lobes.lobe_directions`: the light-facing side facet's) than any other facet's,
    within :data:`BACK_SEARCH` degrees of it, with coverage above 0: on both sides of the light's plane, since a
    random tile's lobe need not peak on it.
    """
    from .lobes import lobe_directions

    t, a, i = key
    dirs = lobe_directions(t, a, i)
    if "back" not in dirs:
        return None, "no back mirror direction above the horizon"
    if "forward" in dirs and float(dirs["back"] @ dirs["forward"]) > math.cos(math.radians(1e-6)):
        return None, "the back lobe coincides with the forward lobe"
    A, E = np.meshgrid(np.asarray(azimuth, float), np.asarray(elevation, float), indexing="ij")
    V = view_direction(E, A)
    names = list(dirs)
    cosines = np.stack([V @ dirs[n] for n in names], axis=-1)
    own = ((np.argmax(cosines, axis=-1) == names.index("back"))
           & (cosines[..., names.index("back")] >= math.cos(math.radians(BACK_SEARCH)))
           & (np.asarray(coverage, float) > 0) & np.isfinite(values))
    if not own.any():
        return None, "no measured view near the back mirror direction"
    ia, ie = np.unravel_index(int(np.argmax(np.where(own, values, -np.inf))), own.shape)
    return V[ia, ie], ""
