"""The OpenGL lighting equation, as the study uses it, in numpy.

This module is the written-down form of what the renderer's GLSL computes
per fragment (``shaders/periodic.frag``) and what the reference computes per
facet; tests compare all three.

Directions
----------
* Light: directional, from azimuth 0. The unit vector toward the light is
  ``L = (cos i, 0, sin i)``, ``i`` the incidence: the light's elevation above
  the surface plane, degrees. From another azimuth ``psi`` (the fast method,
  the exact reference and Mitsuba: ``light_azimuth``),
  ``L = (cos i cos psi, cos i sin psi, sin i)``.
* Detector: the unit vector toward it is
  ``V = (cos e cos phi, cos e sin phi, sin e)``, ``e`` the view elevation in
  [0, 180] and ``phi`` the view azimuth in [0, 180), degrees. At ``phi = 0``,
  ``e = i`` is zero phase (back/retro lobe) and ``e = 180 - i`` the mirror
  direction (forward lobe).
* Phase angle ``g = arccos(L . V)``, degrees.

Equation
--------
``I = J * (m_a * A + m_d * max(N.L, 0) + m_s * S)`` on the 0-255 scale, with
``S = max(R.V, 0) ** shininess`` (Phong; ``R = 2 (N.L) N - L``) or
``S = max(N.H, 0) ** shininess`` (Blinn-Phong, ``H = normalize(L + V)``),
and ``S = 0`` where ``N.L <= 0``. Shadowed points keep the ambient term only.
The ``diffuse`` component is ``J (m_a A + lit m_d max(N.L, 0))``, the
``specular`` component ``J lit m_s S``, and ``total`` their sum; each is
clamped to [0, 255] and rounded to an 8-bit value per pixel, as the
framebuffer stores it.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

__all__ = [
    "COMPONENTS",
    "EXTRAS",
    "SPECULAR_MODELS",
    "Lighting",
    "check_incidence",
    "light_direction",
    "check_light_azimuth",
    "view_direction",
    "phase_angle",
    "facet_components",
    "facet_values",
    "facet_sum",
    "facet_sums",
    "quantize",
    "material_uniforms",
]

#: Components written to the study table, in this order.
COMPONENTS = ("diffuse", "specular", "total")
#: What :func:`facet_sums` gives beside each component's 8-bit mean, each under ``{component}_{extra}``:
#: ``unrounded``, the mean of each value clamped to [0, 255] but not rounded; ``unshadowed``, the same with inner
#: shadows off (every seen point lit).
EXTRAS = ("unrounded", "unshadowed")
#: Specular models the renderer and the reference both implement.
SPECULAR_MODELS = ("phong", "blinn")

#: Shading of a faceted mesh (the naive method's): ``flat`` (true face normals, the
#: study's), ``phong`` (averaged vertex normals interpolated per fragment),
#: ``gouraud`` (the equation at the vertices with averaged normals, interpolated).
SHADINGS = ("flat", "phong", "gouraud")


@dataclass(frozen=True)
class Lighting:
    """Light and material settings of a sweep.

    Attributes
    ----------
    light : float
        Light intensity ``J`` on the 0-255 scale (the thesis used 127).
    ambient : float
        Ambient light level ``A`` as a fraction of ``J`` (0 = none).
    ambient_reflectance, diffuse_reflectance, specular_reflectance : float
        Material coefficients ``m_a``, ``m_d``, ``m_s`` (0-1).
    shininess : float
        Specular exponent ``zeta`` (0-128, OpenGL's range).
    specular_model : str
        ``"phong"`` (R.V, the default) or ``"blinn"`` (N.H).
    shadows : bool
        Whether inner shadows are cast.
    specular_shadows : bool
        With ``shadows``, whether they take the specular component too (the
        default). False is the thesis's protocol for its specular runs, which
        had no inner shadows (Ch. V.D): the specular is lit wherever
        ``N.L > 0``, shadowed or not, and the diffuse keeps its shadows.
    """

    light: float = 127.0
    ambient: float = 0.0
    ambient_reflectance: float = 1.0
    diffuse_reflectance: float = 1.0
    specular_reflectance: float = 1.0
    shininess: float = 64.0
    specular_model: str = "phong"
    shadows: bool = True
    specular_shadows: bool = True

    def __post_init__(self):
        if self.specular_model not in SPECULAR_MODELS:
            raise ValueError(
                f"specular_model must be one of {SPECULAR_MODELS}, got {self.specular_model!r}"
            )

    def as_dict(self) -> dict:
        return asdict(self)


def check_incidence(incidence) -> float:
    """The incidence as a float, or ValueError unless it is a number of degrees in [0, 90]."""
    try:
        value = float(incidence)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"incidence must be a number of degrees, got {incidence!r}") from exc
    if not (math.isfinite(value) and 0.0 <= value <= 90.0):
        raise ValueError(f"incidence must be within [0, 90] degrees, got {incidence!r}")
    return value


def light_direction(incidence, light_azimuth=0.0) -> np.ndarray:
    """Unit vector toward the light, ``(cos i cos psi, cos i sin psi, sin i)``: ``(cos i, 0, sin i)`` at the
    study's light azimuth ``psi = 0``, bit for bit (no rotation is applied there).

    Parameters
    ----------
    incidence : float or array, degrees above the surface plane.
    light_azimuth : float, degrees: the light's azimuth, as a view's (0: the study's light).

    Returns
    -------
    (..., 3) float array
    """
    i = np.radians(np.asarray(incidence, float))
    if light_azimuth == 0:
        return np.stack([np.cos(i), np.zeros_like(i), np.sin(i)], axis=-1)
    psi = np.radians(float(light_azimuth))
    return np.stack([np.cos(i) * np.cos(psi), np.cos(i) * np.sin(psi), np.sin(i)], axis=-1)


def check_light_azimuth(light_azimuth) -> float:
    """The light's azimuth as a float, or ValueError unless it is a finite number of degrees."""
    try:
        value = float(light_azimuth)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"light_azimuth must be a number of degrees, got {light_azimuth!r}") from exc
    if not math.isfinite(value):
        raise ValueError(f"light_azimuth must be finite (degrees), got {light_azimuth!r}")
    return value


def view_direction(elevation, azimuth) -> np.ndarray:
    """Unit vector toward the detector, ``(cos e cos phi, cos e sin phi, sin e)``.

    Parameters
    ----------
    elevation, azimuth : float or arrays (broadcast), degrees.

    Returns
    -------
    (..., 3) float array
    """
    e = np.radians(np.asarray(elevation, float))
    p = np.radians(np.asarray(azimuth, float))
    e, p = np.broadcast_arrays(e, p)
    return np.stack([np.cos(e) * np.cos(p), np.cos(e) * np.sin(p), np.sin(e)], axis=-1)


def phase_angle(incidence, elevation, azimuth) -> np.ndarray:
    """Phase angle ``arccos(L . V)`` in degrees (broadcast over the inputs)."""
    cosg = np.sum(light_direction(incidence) * view_direction(elevation, azimuth), axis=-1)
    return np.degrees(np.arccos(np.clip(cosg, -1.0, 1.0)))


def facet_components(normals, light_dir, view_dirs, lighting: Lighting, lit=1.0):
    """Unquantized diffuse, specular and total of flat facets.

    Parameters
    ----------
    normals : (..., 3) array
        Unit facet normals.
    light_dir : (3,) array
        Unit vector toward the light.
    view_dirs : (..., 3) array
        Unit vectors toward the detector (broadcast against ``normals``).
    lighting : Lighting
    lit : float or array (broadcast)
        1 where the facet point is lit, 0 where it is in shadow.

    Returns
    -------
    diffuse, specular, total : arrays on the 0-255 scale, not clamped.
    """
    return _components(_facet_terms(normals, light_dir, view_dirs, lighting), lighting, lit)


def _facet_terms(normals, light_dir, view_dirs, lighting: Lighting):
    """N.L, whether it is positive, and the specular factor of :func:`facet_components`, which do not depend on
    whether the point is lit (computed once for both)."""
    n = np.asarray(normals, float)
    v = np.asarray(view_dirs, float)
    lvec = np.asarray(light_dir, float)
    ndotl = np.sum(n * lvec, axis=-1)
    if lighting.specular_model == "phong":
        r = 2.0 * ndotl[..., None] * n - lvec
        base = _dot(r, v)
    else:
        h = lvec + v
        h = h / np.maximum(np.linalg.norm(h, axis=-1, keepdims=True), 1e-12)
        base = _dot(n, h)
    facing = ndotl > 0
    return ndotl, facing, np.where(facing, np.maximum(base, 0.0) ** lighting.shininess, 0.0)


def _dot(a, b) -> np.ndarray:
    """The dot products of (..., 3) arrays broadcast against each other, summed left to right as ``np.sum(a * b,
    axis=-1)`` sums them (the same value to the bit), without the (..., 3) array of products: a random tile's
    views x facets made it 0.1 s a sweep."""
    return (a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]) + a[..., 2] * b[..., 2]


def _components(terms, lighting: Lighting, lit):
    """:func:`facet_components` from :func:`_facet_terms`."""
    ndotl, facing, spec_factor = terms
    lit = np.asarray(lit, float) * facing
    # the thesis's specular protocol: no inner shadows on the specular (N.L > 0 still gates it)
    spec_lit = lit if lighting.specular_shadows else facing.astype(float)
    j = lighting.light
    diffuse = j * (
        lighting.ambient_reflectance * lighting.ambient
        + lit * lighting.diffuse_reflectance * np.maximum(ndotl, 0.0)
    )
    specular = j * spec_lit * lighting.specular_reflectance * spec_factor
    return diffuse, specular, diffuse + specular


def facet_values(normals, light_dir, view_dirs, lighting: Lighting, quantized: bool = True):
    """Every facet's value lit and in shadow, for each view.

    Parameters
    ----------
    normals : (F, 3) array
        Unit facet normals.
    light_dir : (3,) array
        Unit vector toward the light.
    view_dirs : (n_views, 3) array
        Unit vectors toward the detector.
    lighting : Lighting
    quantized : bool
        True: each value is its 8-bit framebuffer value (:func:`quantize`); False: the raw float.

    Returns
    -------
    on, off : tuples of three (n_views, F) arrays
        Diffuse, specular and total of each facet where it is lit (``on``) and in shadow (``off``), 0-255.
    """
    normals = np.asarray(normals, float)[None, :, :]
    views = np.asarray(view_dirs, float)[:, None, :]
    shape = (views.shape[0], normals.shape[1])
    out = []
    terms = _facet_terms(normals, light_dir, views, lighting)
    for lit in (1.0, 0.0):
        values = _components(terms, lighting, lit)
        out.append(tuple(np.broadcast_to(quantize(v) if quantized else v, shape) for v in values))
    return out[0], out[1]


def facet_sum(normals, light_dir, view_dirs, lit, shadow, lighting: Lighting, quantized: bool = True) -> dict:
    """Image mean of each component: every facet's value weighted by its lit and its shadowed share.

    Parameters
    ----------
    normals, light_dir, view_dirs, lighting, quantized
        As :func:`facet_values`.
    lit, shadow : (n_views, F) arrays
        Share of the image each facet fills, lit and in shadow.

    Returns
    -------
    dict: ``diffuse``, ``specular``, ``total`` as (n_views,) arrays (0-255).
    """
    on, off = facet_values(normals, light_dir, view_dirs, lighting, quantized)
    return {name: (v_on * lit).sum(axis=1) + (v_off * shadow).sum(axis=1)
            for name, v_on, v_off in zip(COMPONENTS, on, off)}


def facet_sums(normals, light_dir, view_dirs, lit, shadow, lighting: Lighting, quantized: bool = True) -> dict:
    """:func:`facet_sum` and, from the same evaluation of the facets' terms, each component's mean before rounding
    and with inner shadows off.

    Parameters
    ----------
    normals, light_dir, view_dirs, lit, shadow, lighting, quantized
        As :func:`facet_sum`.

    Returns
    -------
    dict of (n_views,) arrays (0-255):

    - ``diffuse``, ``specular``, ``total``: :func:`facet_sum`'s, bit for bit;
    - ``{component}_unrounded``: every facet's value clamped to [0, 255] but not rounded, weighted by its lit and its
      shadowed share (with ``quantized`` at every view within ``0.5 + tie slack`` of the 8-bit mean, the slack
      :func:`quantize`'s 1e-6: each value is);
    - ``{component}_unshadowed``: the same with each facet's shadowed share counted lit (inner shadows off: the
      same visible shares, every seen point lit; a facet turned from the light, ``N.L <= 0``, keeps its ambient
      only, lit or not, as :func:`facet_components` has it).
    """
    normals = np.asarray(normals, float)[None, :, :]
    views = np.asarray(view_dirs, float)[:, None, :]
    lit, shadow = np.asarray(lit), np.asarray(shadow)
    terms = _facet_terms(normals, light_dir, views, lighting)
    out = {}
    # the lit values first, then the shadowed: three arrays of values held at a time, as facet_values holds them
    for is_lit, shares in ((True, lit), (False, shadow)):
        values = list(_components(terms, lighting, 1.0 if is_lit else 0.0))
        for name in COMPONENTS:
            value = values.pop(0)
            if quantized:  # clamped in place (the array is this call's own), then rounded as quantize rounds
                clamped = _clamped(value, out=value)
                value = _rounded(clamped, out=np.empty_like(clamped))
            else:
                clamped = _clamped(value)
            # facet_sum's sum, bit for bit: (8-bit lit values * lit).sum(axis=1) + (shadowed * shadow).sum(axis=1)
            part = (value * shares).sum(axis=1)
            del value
            if is_lit:
                out[name] = part
                lit_part = out[f"{name}_unrounded"] = _row_dots(clamped, lit)
                out[f"{name}_unshadowed"] = lit_part + _row_dots(clamped, shadow)
            else:
                out[name] = out[name] + part
                out[f"{name}_unrounded"] = out[f"{name}_unrounded"] + _row_dots(clamped, shadow)
    return out


def _row_dots(values, shares) -> np.ndarray:
    """Each view's sum over facets of ``values * shares``, (V, F) shares with (V, F) values or a (1, F) row of them
    for every view, without a (V, F) array of products (``einsum``: a third of the product and its sum's time)."""
    return np.einsum("vf,vf->v", np.broadcast_to(values, shares.shape), shares)


#: Values within this of a half step round up, as the framebuffer's float to
#: 8-bit conversion does for exact ties such as 127 sin(30 deg) = 63.5 (which
#: double precision computes as 63.49999999999999).
_TIE_SLACK = 1e-6


def quantize(values, tie_slack: float = _TIE_SLACK) -> np.ndarray:
    """8-bit framebuffer value of an intensity: clamp to [0, 255], round to nearest, ties (values within
    ``tie_slack`` of a half step) up."""
    values = np.asarray(values, float)
    # np.floor(np.clip(values, 0, 255) + 0.5 + tie_slack), the same operations in one new array (a random tile's
    # views x facets took four): clip is maximum then minimum
    out = _rounded(_clamped(values), tie_slack)
    return out if out.ndim else out[()]


def _clamped(values: np.ndarray, out=None) -> np.ndarray:
    """``np.clip(values, 0, 255)``, the value before :func:`quantize` rounds it: in a new array, or in ``out``
    (``out=values``: in place)."""
    out = np.maximum(values, 0.0, out=np.empty_like(values) if out is None else out)
    np.minimum(out, 255.0, out=out)
    return out


def _rounded(clamped: np.ndarray, tie_slack: float = _TIE_SLACK, out=None) -> np.ndarray:
    """:func:`quantize`'s rounding of :func:`_clamped` values (``floor(clamped + 0.5 + tie_slack)``), in place
    unless ``out`` is given (``out=np.empty_like(clamped)``: ``clamped`` kept)."""
    if out is None:
        out = clamped
    np.add(clamped, 0.5, out=out)
    out += tie_slack
    np.floor(out, out=out)
    return out


def material_uniforms(lighting: Lighting, light_dir) -> dict:
    """The lighting equation's shader uniforms, as ``periodic.frag`` and ``implicit_model.glsl`` name them.

    Parameters
    ----------
    lighting : Lighting
    light_dir : (3,) array, unit vector toward the light

    Returns
    -------
    dict, uniform name -> value: ``light_dir`` (float32 (3,)), ``light`` (``J / 255``), ``ambient_term``
    (``m_a A``), ``diffuse_reflectance``, ``specular_reflectance``, ``shininess``, ``specular_model``
    (index in :data:`SPECULAR_MODELS`), ``specular_shadows`` (0 or 1).
    """
    return {
        "light_dir": np.asarray(light_dir, np.float32),
        "light": float(lighting.light) / 255.0,
        "ambient_term": float(lighting.ambient_reflectance * lighting.ambient),
        "diffuse_reflectance": float(lighting.diffuse_reflectance),
        "specular_reflectance": float(lighting.specular_reflectance),
        "shininess": float(lighting.shininess),
        "specular_model": int(SPECULAR_MODELS.index(lighting.specular_model)),
        "specular_shadows": int(bool(lighting.specular_shadows)),
    }
