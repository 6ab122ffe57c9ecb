"""A surface's BRDF as a file Mitsuba 3's own ``measured`` BSDF loads, and a flat quad rendered with it.

Mitsuba's ``measured`` plugin (``src/bsdfs/measured.cpp``, Dupuy and Jakob 2018, "An Adaptive Parameterization
for Efficient Material Acquisition and Rendering") reads a *tensor file* (``mitsuba.tensor_io``'s format: the
header ``tensor_file\\0``, version 1.0, then named little-endian arrays) and, in the RGB variants, evaluates it so:

- ``wi`` is the direction toward the detector (Mitsuba's ``si.wi``), ``wo`` the one toward the light, both in the
  surface's local frame (normal +z). Neither below the horizon, else 0.
- ``wi`` picks the table's slice: its polar angle ``theta_i`` (from the normal, radians) and azimuth
  ``phi_i = atan2(wi_y, wi_x)`` (radians, in ``[-pi, pi]``) are interpolated linearly between the nodes of the
  fields ``theta_i`` and ``phi_i`` (clamped at their ends).
- Within a slice the half vector ``wm = normalize(wi + wo)``, polar angle ``theta_m``, azimuth ``phi_m``, gives the
  unit square point ``u = (sqrt(2 theta_m / pi), (phi_m + pi) / (2 pi))``; with the file's ``vndf`` constant the
  plugin's warp is the identity and ``u`` is looked up bilinearly on the ``n x n`` grid of the field ``rgb``
  (nodes at ``k / (n - 1)``; the *last* axis is ``u_0``, the polar one, the one before it ``u_1``, the azimuth).
- ``jacobian`` 0: the value returned is the stored number itself, and it is what Mitsuba's ``BSDF::eval`` returns,
  the BRDF **times the cosine of the light's angle**: ``f_r cos(theta_o) = f_r L_z``.
- Folding: when ``phi_i`` spans ``2 pi / r`` (``r`` = 2 or 4, :data:`REDUCTIONS`) the plugin maps ``wi`` (and
  ``wo`` with it) to ``wi_y <= 0`` (``r`` 2: a half turn) or to ``wi_x <= 0, wi_y <= 0`` (``r`` 4: the mirrors
  ``x -> -x`` and ``y -> -y``, not a quarter turn), so the ``phi_i`` nodes must run from ``-pi`` to
  ``-pi + 2 pi / r`` (:func:`table_nodes`); the plugin does not check it and clamps any other range.
  ``phi_i`` of one or two nodes is read as an isotropic material (``phi_m`` relative to ``phi_i``); this module
  writes anisotropic tables only (at least three ``phi_i`` nodes).

The study's scale
-----------------
The study's value of a component is on the 0-255 scale for a light of intensity ``J`` (``lighting.light``):
the plate's diffuse is ``J m_d L_z``. The Mitsuba method (:mod:`.scene`) lights the scene with a ``directional``
emitter of irradiance ``pi`` and reads ``J`` times the radiance; so a value ``I(L, V)`` is the BRDF

    f_r(L, V) = I(L, V) / (pi J L_z)        (1 / steradian)

and the number stored in the file is ``f_r L_z = I / (pi J)``: a Lambertian facet of albedo ``m_d`` stores
``m_d L_z / pi``. Rendered under irradiance ``pi`` it gives back ``I / J`` (:func:`render_flat` multiplies by
``J``). The ambient term ``J m_a A`` is no BRDF (it does not depend on the light) and is left out: the callables
here take the ambient as 0.

Channels: the file for users holds the total in all three RGB channels (``channels="total"``, a grey BRDF); for
checking, ``channels="components"`` puts the diffuse, the specular and the total in red, green and blue.
"""

from __future__ import annotations

import struct
import tempfile
from pathlib import Path

import numpy as np

from ...atomic import atomic_path
from ..shading import Lighting, check_incidence, facet_components, light_direction, view_direction
from .field import sensor_matrix
from .warp import half_vector, node_half_vectors

__all__ = ["REDUCTIONS", "CHANNELS", "table_nodes", "half_vectors", "reflect", "plate_values", "tabulate",
           "write_measured", "read_measured", "file_size", "evaluate", "render_flat"]

#: The folds the plugin knows: ``phi_i`` nodes spanning ``2 pi / r``.
REDUCTIONS = (1, 2, 4)
#: What the three RGB channels hold: the total in all three, or diffuse, specular, total.
CHANNELS = ("total", "components")
#: The components a ``values`` callable returns.
COMPONENTS = ("diffuse", "specular", "total")

_HEADER = b"tensor_file\x00"
# mitsuba.tensor_io's (Struct's) type codes
_DTYPES = {np.dtype(np.uint8): 1, np.dtype(np.int8): 2, np.dtype(np.uint16): 3, np.dtype(np.int16): 4,
           np.dtype(np.uint32): 5, np.dtype(np.int32): 6, np.dtype(np.uint64): 7, np.dtype(np.int64): 8,
           np.dtype(np.float16): 9, np.dtype(np.float32): 10, np.dtype(np.float64): 11}
_CODES = {code: dtype for dtype, code in _DTYPES.items()}
#: The luminance table (what the plugin samples ``wo`` by) is floored at this share of its slice's largest value,
#: so that every direction with a value can be sampled.
LUMINANCE_FLOOR = 1e-3


def table_nodes(n_theta: int, n_phi: int, reduction: int = 1, theta_max: float = 90.0) -> tuple[np.ndarray, np.ndarray]:
    """The ``theta_i`` and ``phi_i`` nodes of a table (the detector's direction ``wi``), float32 radians.

    Parameters
    ----------
    n_theta : int, >= 2: polar angles from the normal, evenly spaced over ``[0, theta_max]``
    n_phi : int, >= 3: azimuths evenly spaced over ``[-pi, -pi + 2 pi / reduction]``, both ends included (the
        domain the plugin folds ``wi`` into: the module's docstring)
    reduction : int, 1, 2 or 4 (:data:`REDUCTIONS`): 4 for a surface symmetric under ``x -> -x`` and
        ``y -> -y`` (square pyramids with edges along the axes), 2 under a half turn, 1 for none
    theta_max : float, degrees, the last polar node (90: grazing views)

    Returns
    -------
    theta_nodes, phi_nodes : float32 arrays, radians
    """
    if reduction not in REDUCTIONS:
        raise ValueError(f"reduction must be one of {REDUCTIONS}, got {reduction!r}")
    if int(n_theta) < 2 or int(n_phi) < 3:
        raise ValueError(f"a table needs at least 2 theta_i and 3 phi_i nodes, got {n_theta} and {n_phi}")
    if not 0.0 < float(theta_max) <= 90.0:
        raise ValueError(f"theta_max must be within (0, 90] degrees, got {theta_max!r}")
    theta = np.linspace(0.0, np.radians(float(theta_max)), int(n_theta))
    phi = np.linspace(-np.pi, -np.pi + 2.0 * np.pi / reduction, int(n_phi))
    return theta.astype(np.float32), phi.astype(np.float32)


def half_vectors(n_u: int) -> np.ndarray:
    """The half vectors ``wm`` of the ``n_u x n_u`` grid, ``(n_u, n_u, 3)`` indexed ``[u_1, u_0]`` (as the file's
    last two axes): ``theta_m = u_0^2 pi / 2``, ``phi_m = (2 u_1 - 1) pi``, ``u = k / (n_u - 1)``."""
    if int(n_u) < 2:
        raise ValueError(f"n_u must be at least 2, got {n_u!r}")
    u_1, u_0 = np.meshgrid(np.linspace(0.0, 1.0, int(n_u)), np.linspace(0.0, 1.0, int(n_u)), indexing="ij")
    return half_vector(np.stack([u_0, u_1], axis=-1))


def reflect(wi, wm) -> np.ndarray:
    """``wi`` mirrored about ``wm``: ``2 (wi . wm) wm - wi`` (broadcast; both unit vectors)."""
    wi, wm = np.asarray(wi, float), np.asarray(wm, float)
    return 2.0 * np.sum(wi * wm, axis=-1, keepdims=True) * wm - wi


def plate_values(lighting: Lighting | None = None):
    """The plate's closed form as a ``values(L, V)`` callable (:func:`tabulate`): the study's equation on the facet
    of normal +z (:func:`roughlight.render.shading.facet_components`), the ambient left out, unquantized."""
    lighting = Lighting() if lighting is None else lighting
    normal = np.array([0.0, 0.0, 1.0])

    def values(light, view):
        diffuse, specular, total = facet_components(normal, light, view, lighting)
        return {"diffuse": diffuse, "specular": specular, "total": total}

    return values


def _check_values(out, n: int, light_z) -> dict:
    if not isinstance(out, dict) or any(name not in out for name in COMPONENTS):
        raise ValueError(f"values(L, V) must return a dict with keys {COMPONENTS}, got "
                         f"{sorted(out) if isinstance(out, dict) else type(out).__name__}")
    result = {}
    for name in COMPONENTS:
        value = np.asarray(out[name], float)
        if value.shape != (n,):
            raise ValueError(f"values(L, V)[{name!r}] must have shape ({n},) (one value a direction pair), got "
                             f"{value.shape}")
        if not np.all(np.isfinite(value)):
            raise ValueError(f"values(L, V)[{name!r}] is not finite everywhere")
        below = (light_z <= 0.0) & (value != 0.0)
        if np.any(below):
            raise ValueError(f"values(L, V)[{name!r}] is {value[below][0]} for a light below the horizon (L_z "
                             f"{light_z[below][0]:.3g}): a light there must give 0")
        result[name] = value
    return result


def tabulate(values, theta_nodes, phi_nodes, n_u: int, lighting: Lighting | None = None,
             channels: str = "total", vndf=None) -> np.ndarray:
    """The file's ``rgb`` table: ``f_r L_z`` at every node.

    For every ``(phi_i, theta_i)`` node, the detector's direction ``wi = V``, and every half vector ``wm`` of the
    ``n_u x n_u`` grid (:func:`half_vectors`), the light's direction is ``L = wo = 2 (wi . wm) wm - wi``; the value
    stored is ``values(L, V) / (pi J)``, which is ``f_r L_z`` with ``f_r = I / (pi J L_z)`` (the module's docstring),
    and 0 where ``L`` is below the horizon.

    Parameters
    ----------
    values : callable ``values(L, V) -> dict``; ``L``, ``V``: ``(n, 3)`` unit vectors toward the light and the
        detector (float64, surface frame, normal +z); the dict's ``diffuse``, ``specular``, ``total``: ``(n,)``
        arrays on the study's 0-255 scale for a light of ``J`` = ``lighting.light``, unquantized, no ambient, and 0
        where ``L_z <= 0`` (else ValueError)
    theta_nodes, phi_nodes : 1-D arrays, radians (:func:`table_nodes`)
    n_u : int, the half-vector grid's side
    lighting : Lighting, its ``light`` is ``J`` (default: the study's 127)
    channels : ``"total"`` (the total in R, G and B: the file for users) or ``"components"`` (diffuse, specular,
        total in R, G, B)
    vndf : (n_phi, n_theta, n_u, n_u) array, optional: the plugin's warp (:func:`warp_density`). Without it the
        nodes are the half vectors of the regular ``u`` grid (the identity warp); with it, the half vectors the
        plugin's own warp (Mitsuba's ``MarginalContinuous2D2``, what ``measured.cpp`` builds from the field) takes
        the regular grid of its sample space to, slice by slice: where the plugin reads them back.

    Returns
    -------
    (n_phi, n_theta, 3, n_u, n_u) float32 array
    """
    lighting = Lighting() if lighting is None else lighting
    if channels not in CHANNELS:
        raise ValueError(f"channels must be one of {CHANNELS}, got {channels!r}")
    theta = np.asarray(theta_nodes, float)
    phi = np.asarray(phi_nodes, float)
    if theta.ndim != 1 or phi.ndim != 1:
        raise ValueError("theta_nodes and phi_nodes must be 1-D arrays of radians")
    if np.any(theta < 0) or np.any(theta > np.pi / 2 + 1e-6):
        raise ValueError("theta_nodes must lie within [0, pi/2] radians (polar angles from the normal)")
    j = float(lighting.light)
    if not j > 0:
        raise ValueError(f"lighting.light (J) must be positive, got {j}")
    if vndf is None:
        regular = half_vectors(int(n_u)).reshape(-1, 3)
        nodes = lambda a, b: regular  # noqa: E731
    else:
        nodes = node_half_vectors(vndf, theta, phi, int(n_u))
    out = np.zeros((len(phi), len(theta), 3, int(n_u), int(n_u)), np.float32)
    for a, p in enumerate(phi):
        for b, t in enumerate(theta):
            wi = np.array([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)])
            wm = nodes(a, b)
            light = reflect(wi, wm)
            light /= np.linalg.norm(light, axis=-1, keepdims=True)
            view = np.broadcast_to(wi, light.shape)
            got = _check_values(values(light, view), len(light), light[:, 2])
            names = ("total",) * 3 if channels == "total" else COMPONENTS
            for c, name in enumerate(names):
                out[a, b, c] = (got[name] / (np.pi * j)).reshape(int(n_u), int(n_u))
    return out


def _write_tensor_file(path: Path, fields: dict, align: int = 8) -> None:
    """``fields`` as a tensor file (``mitsuba.tensor_io.write``'s layout), to ``path`` atomically."""
    arrays = {name: np.ascontiguousarray(value) for name, value in fields.items()}
    header = bytearray(_HEADER + struct.pack("<BB", 1, 0) + struct.pack("<I", len(arrays)))
    slots = {}
    for name, value in arrays.items():
        label = name.encode("utf8")
        header += struct.pack("<H", len(label)) + label + struct.pack("<H", value.ndim)
        header += struct.pack("<B", _DTYPES[value.dtype])
        slots[name] = len(header)
        header += struct.pack("<Q", 0) + struct.pack("<" + "Q" * value.ndim, *value.shape)
    position, offsets = len(header), {}
    for name, value in arrays.items():
        position = (position + align - 1) // align * align
        offsets[name] = position
        position += value.nbytes
    for name, offset in offsets.items():
        header[slots[name]:slots[name] + 8] = struct.pack("<Q", offset)
    with atomic_path(path) as temporary, open(temporary, "wb") as stream:
        stream.write(header)
        for name, value in arrays.items():
            stream.write(b"\x00" * (offsets[name] - stream.tell()))
            stream.write(value.tobytes())


def _check_nodes(theta: np.ndarray, phi: np.ndarray) -> None:
    """:func:`write_measured`'s ``theta_i`` and ``phi_i`` nodes: 1-D, increasing, ``phi`` a fold the plugin knows."""
    if theta.ndim != 1 or phi.ndim != 1 or len(theta) < 2 or len(phi) < 3:
        raise ValueError(f"theta_nodes and phi_nodes must be 1-D with at least 2 and 3 nodes, got shapes "
                         f"{theta.shape} and {phi.shape}")
    if np.any(np.diff(theta) <= 0) or np.any(np.diff(phi) <= 0):
        raise ValueError("theta_nodes and phi_nodes must increase")
    span = float(phi[-1]) - float(phi[0])
    reduction = int(np.rint(2 * np.pi / span))
    if reduction not in REDUCTIONS or abs(span - 2 * np.pi / reduction) > 1e-4 or abs(float(phi[0]) + np.pi) > 1e-4:
        raise ValueError(f"phi_nodes must run from -pi to -pi + 2 pi / r, r in {REDUCTIONS} (the plugin folds wi "
                         f"there), got [{phi[0]:.6g}, {phi[-1]:.6g}]")


def write_measured(path, theta_nodes, phi_nodes, rgb, description: str, luminance=None, vndf=None) -> Path:
    """Write a table as a file Mitsuba's ``measured`` plugin loads (atomically: a temporary name in the same
    folder, then ``os.replace``).

    Parameters
    ----------
    path : str or Path
    theta_nodes, phi_nodes : 1-D arrays, radians (:func:`table_nodes`); ``phi_nodes`` at least 3, spanning
        ``2 pi / r`` for ``r`` in :data:`REDUCTIONS`
    rgb : (n_phi, n_theta, 3, n_u, n_u) array, ``f_r L_z`` (:func:`tabulate`), stored as float32
    description : str, the material's description (the plugin logs it)
    luminance : (n_phi, n_theta, n_u, n_u) array, optional: the density the plugin draws ``wo`` from when light
        bounces (its ``sample``; :mod:`.bounces` checks it). Default: the mean of ``rgb``'s channels floored at
        :data:`LUMINANCE_FLOOR` of each slice's peak, nowhere 0, so that every direction with a value can be drawn.
        One given is stored as it is (non-negative, finite): where it is 0 and ``rgb`` is not, bounced light is lost.
    vndf : (n_phi, n_theta, n_u, n_u) array, optional: the warp ``rgb`` was tabulated through (:func:`tabulate`'s;
        default the identity, ``n_phi x n_theta x 2 x 2`` ones)

    Returns
    -------
    Path written. Fields: ``theta_i``, ``phi_i`` (float32), ``ndf``, ``sigma`` (2 x 2 ones), ``vndf`` (the warp
    given, else ``n_phi x n_theta x 2 x 2`` ones: the identity), ``luminance`` (``n_phi x n_theta x n_u x n_u``, the mean
    of the channels floored at :data:`LUMINANCE_FLOOR` of each slice's peak: what the plugin samples ``wo`` by when
    light bounces), ``rgb``, ``description`` (uint8), ``jacobian`` (uint8 ``[0]``).
    """
    theta = np.asarray(theta_nodes, np.float32)
    phi = np.asarray(phi_nodes, np.float32)
    table = np.asarray(rgb, np.float32)
    _check_nodes(theta, phi)
    expected = (len(phi), len(theta), 3)
    if table.ndim != 5 or table.shape[:3] != expected or table.shape[3] != table.shape[4] or table.shape[3] < 2:
        raise ValueError(f"rgb must have shape (n_phi, n_theta, 3, n_u, n_u) = {expected} + (n_u, n_u), got "
                         f"{table.shape}")
    if not np.all(np.isfinite(table)) or np.any(table < 0):
        raise ValueError("rgb must be finite and non-negative")
    luminance = _luminance(table, luminance)
    if vndf is not None and (np.shape(vndf)[:2] != expected[:2] or np.ndim(vndf) != 4
                             or not np.all(np.asarray(vndf) > 0)):
        raise ValueError(f"vndf must be a positive (n_phi, n_theta, n, n) array, got shape {np.shape(vndf)}")
    ones = np.ones((2, 2), np.float32)
    fields = {
        "description": np.frombuffer(str(description).encode("utf8"), np.uint8),
        "jacobian": np.zeros(1, np.uint8),
        "theta_i": theta,
        "phi_i": phi,
        "ndf": ones,
        "sigma": ones,
        "vndf": np.ones((len(phi), len(theta), 2, 2), np.float32) if vndf is None else np.asarray(vndf, np.float32),
        "luminance": luminance,
        "rgb": table,
    }
    path = Path(path)
    _write_tensor_file(path, fields)
    return path


def _luminance(table: np.ndarray, luminance=None) -> np.ndarray:
    """:func:`write_measured`'s ``luminance`` field: the one given, checked, or the mean of ``table``'s channels
    floored at :data:`LUMINANCE_FLOOR` of each slice's peak."""
    if luminance is None:
        luminance = table.mean(axis=2)
        peak = luminance.max(axis=(2, 3), keepdims=True)
        luminance = np.maximum(luminance, np.where(peak > 0, LUMINANCE_FLOOR * peak, 1.0))
    luminance = np.asarray(luminance, np.float32)
    if luminance.shape != table.shape[:2] + table.shape[3:]:
        raise ValueError(f"luminance must have shape (n_phi, n_theta, n_u, n_u) = "
                         f"{table.shape[:2] + table.shape[3:]}, got {luminance.shape}")
    if not np.all(np.isfinite(luminance)) or np.any(luminance < 0) or np.any(luminance.sum(axis=(2, 3)) <= 0):
        raise ValueError("luminance must be finite, non-negative and positive somewhere in every slice")
    return luminance


def read_measured(path) -> dict:
    """Every field of a tensor file (a file :func:`write_measured` wrote, or any of RGL's), as numpy arrays, with
    ``description`` decoded to a str; ValueError when it is no tensor file."""
    data = Path(path).read_bytes()
    if len(data) < 18 or data[:12] != _HEADER:
        raise ValueError(f"{path}: not a tensor file (no 'tensor_file' header)")
    if data[12:14] != b"\x01\x00":
        raise ValueError(f"{path}: unknown tensor file version {tuple(data[12:14])}")
    (count,), position, fields = struct.unpack_from("<I", data, 14), 18, {}
    for _ in range(count):
        (length,) = struct.unpack_from("<H", data, position)
        name = data[position + 2:position + 2 + length].decode("utf8")
        position += 2 + length
        ndim, code, offset = struct.unpack_from("<HBQ", data, position)
        position += 11
        shape = struct.unpack_from("<" + "Q" * ndim, data, position)
        position += 8 * ndim
        if code not in _CODES:
            raise ValueError(f"{path}: field {name!r} has an unknown type code {code}")
        dtype = _CODES[code]
        count_items = int(np.prod(shape, dtype=np.int64))
        if offset + count_items * dtype.itemsize > len(data):
            raise ValueError(f"{path}: field {name!r} runs past the end of the file (truncated?)")
        fields[name] = np.frombuffer(data, dtype, count_items, offset).reshape(shape).copy()
    if "description" in fields:
        fields["description"] = fields["description"].tobytes().decode("utf8", "replace")
    return fields


def file_size(n_theta: int, n_phi: int, n_u: int) -> int:
    """Bytes of the file :func:`write_measured` writes for such a table (headers aside): ``rgb`` and ``luminance``,
    ``4 n_phi n_theta n_u^2`` floats, and a few small fields."""
    return 4 * n_phi * n_theta * (4 * n_u * n_u + 4) + 4 * (n_theta + n_phi + 8)


def _plugin(path, variant: str):
    from . import runtime

    mi, used = runtime.load(variant)
    return mi, used, mi.load_dict({"type": "measured", "filename": str(Path(path).resolve())})


def evaluate(path, light, view, variant: str = "llvm_ad_rgb") -> np.ndarray:
    """The plugin's ``eval`` (``f_r L_z``, three channels) for direction pairs, without rendering.

    Parameters
    ----------
    path : the file
    light, view : (n, 3) unit vectors toward the light (``wo``) and the detector (``wi``), surface frame
    variant : Mitsuba variant (:func:`roughlight.render.mitsuba.runtime.load`)

    Returns
    -------
    (n, 3) float64: multiply by ``pi J`` for the study's 0-255 scale.
    """
    mi, used, bsdf = _plugin(path, variant)
    light = np.atleast_2d(np.asarray(light, float))
    view = np.atleast_2d(np.asarray(view, float))
    if light.shape != view.shape or light.shape[1:] != (3,):
        raise ValueError(f"light and view must both be (n, 3), got {light.shape} and {view.shape}")
    if used.startswith("scalar"):
        out = []
        for lo, vi in zip(light, view):
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(*vi)
            out.append(list(bsdf.eval(mi.BSDFContext(), si, mi.Vector3f(*lo))))
        return np.asarray(out, float)
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(*(mi.Float(view[:, k].astype(np.float32)) for k in range(3)))
    wo = mi.Vector3f(*(mi.Float(light[:, k].astype(np.float32)) for k in range(3)))
    value = bsdf.eval(mi.BSDFContext(), si, wo)
    return np.stack([np.asarray(value[k], float) for k in range(3)], axis=-1)


#: The flat quad's half side, and the detector window's (both periods of the study's frame; any size would do).
QUAD_HALF_SIDE = 4.0
WINDOW = 2


def _flat_scene(mi, bsdf, light):
    """The flat quad ``z = 0`` with ``bsdf`` (two triangles with texture coordinates along x and y, so that
    Mitsuba's shading frame is the world's) under a ``directional`` emitter toward ``-light`` of irradiance ``pi``,
    rendered by the ``direct`` integrator."""
    h = QUAD_HALF_SIDE
    vertices = np.array([[-h, -h, 0.0], [h, -h, 0.0], [h, h, 0.0], [-h, h, 0.0]], np.float32)
    faces = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)
    props = mi.Properties()
    props["bsdf"] = bsdf
    mesh = mi.Mesh("quad", 4, 2, has_vertex_texcoords=True, props=props)
    params = mi.traverse(mesh)
    params["vertex_positions"] = type(params["vertex_positions"])(vertices.ravel())
    params["vertex_texcoords"] = type(params["vertex_texcoords"])(vertices[:, :2].ravel())
    params["faces"] = type(params["faces"])(faces.ravel())
    params.update()
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
        "light": {"type": "directional", "direction": (-light).tolist(),
                  "irradiance": {"type": "rgb", "value": float(np.pi)}},
        "quad": mesh,
    })


def quad_sensor(mi, view, side: int, spp: int):
    """The orthographic detector along ``-view`` whose ``side x side`` film sees the flat quad alone
    (:func:`roughlight.render.mitsuba.field.sensor_matrix`, :data:`WINDOW` periods), ``spp`` samples a pixel."""
    matrix, far = sensor_matrix(view, WINDOW, 0.0)
    return mi.load_dict({
        "type": "orthographic", "to_world": mi.ScalarTransform4f(matrix), "near_clip": 1e-3, "far_clip": far,
        "film": {"type": "hdrfilm", "width": int(side), "height": int(side), "rfilter": {"type": "box"},
                 "pixel_format": "rgb", "component_format": "float32"},
        "sampler": {"type": "independent", "sample_count": int(spp)},
    })


def render_flat(path, incidence: float, light_azimuth: float, azimuth, elevation, lighting: Lighting | None = None,
                variant: str = "llvm_ad_rgb", spp: int = 1, side: int = 4) -> np.ndarray:
    """Render a flat quad with the file's BRDF, as the Mitsuba method renders the plate, one view at a time.

    The quad ``z = 0`` (two triangles, normal +z, so Mitsuba's frame is the world's: x, y, z), Mitsuba's
    ``{"type": "measured", "filename": path}``, a ``directional`` emitter toward ``-L`` of irradiance ``pi``
    (:mod:`.scene`), the ``direct`` integrator, and for each view an orthographic detector along ``-V``
    (:func:`roughlight.render.mitsuba.field.sensor_matrix`) whose ``side x side`` film sees the quad alone. A flat
    quad has one value everywhere: a tiny film and one sample a pixel measure it.

    Parameters
    ----------
    path : the file (:func:`write_measured`)
    incidence : float, degrees in (0, 90]: the light's elevation (a light in or below the plane lights nothing a
        BRDF can say: ValueError)
    light_azimuth : float, degrees
    azimuth, elevation : array_like (broadcast), degrees, the views (:func:`roughlight.render.shading.view_direction`;
        elevation in (0, 180))
    lighting : Lighting, its ``light`` is ``J`` (default 127)
    variant, spp, side : Mitsuba variant, samples a pixel, film side (pixels)

    Returns
    -------
    (n_views, 3) float64: each channel's mean over the film times ``J``, on the study's 0-255 scale, **not** rounded
    to 8 bits (rounding would hide the interpolation error being measured).
    """
    lighting = Lighting() if lighting is None else lighting
    incidence = check_incidence(incidence)
    if incidence <= 0.0:
        raise ValueError(f"incidence must be above the plane, within (0, 90] degrees, got {incidence!r}: a light "
                         f"in or below the plane gives a BRDF no light to reflect")
    elevation, azimuth = np.broadcast_arrays(np.atleast_1d(np.asarray(elevation, float)),
                                             np.atleast_1d(np.asarray(azimuth, float)))
    if np.any(elevation <= 0.0) or np.any(elevation >= 180.0):
        raise ValueError("elevation must be within (0, 180) degrees (views above the plane)")
    views = view_direction(elevation.ravel(), azimuth.ravel())
    light = light_direction(incidence, float(light_azimuth))
    mi, _, bsdf = _plugin(path, variant)
    scene = _flat_scene(mi, bsdf, light)
    j = float(lighting.light)
    out = np.zeros((len(views), 3))
    for k, view in enumerate(views):
        image = np.asarray(mi.render(scene, sensor=quad_sensor(mi, view, side, spp), seed=k),
                           dtype=np.float64).reshape(-1, 3)
        out[k] = j * image.mean(axis=0)
    return out


#: The resolution study's cores: light and view within these many degrees of the normal (elevations of at least
#: 30 and 10 degrees).
CORES = (60.0, 80.0)


def study_directions(count: int = 4000, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Light and view pairs for :func:`resolution_study`, off any table's nodes: half at random (incidence in
    [5, 90], any light azimuth, views at elevations [5, 175] and azimuths [0, 180) degrees), half within 12 degrees
    of the mirror direction (where the specular lobe is).

    Returns
    -------
    light, view : (count, 3) unit vectors
    """
    rng = np.random.default_rng(seed)
    half = count // 2
    incidence = rng.uniform(5.0, 90.0, count)
    light = light_direction(incidence, 0.0)
    psi = rng.uniform(0.0, 2 * np.pi, count)
    light = np.column_stack([light[:, 0] * np.cos(psi), light[:, 0] * np.sin(psi), light[:, 2]])
    view = view_direction(rng.uniform(5.0, 175.0, half), rng.uniform(0.0, 180.0, half))
    mirror = light[half:] * np.array([-1.0, -1.0, 1.0])
    tilt = rng.normal(size=mirror.shape)
    tilt -= np.sum(tilt * mirror, axis=1, keepdims=True) * mirror
    tilt /= np.linalg.norm(tilt, axis=1, keepdims=True)
    angle = np.radians(rng.uniform(0.0, 12.0, len(mirror)))[:, None]
    near = np.cos(angle) * mirror + np.sin(angle) * tilt
    near[:, 2] = np.maximum(near[:, 2], np.sin(np.radians(2.0)))
    near /= np.linalg.norm(near, axis=1, keepdims=True)
    return light, np.vstack([view, near])


def resolution_study(choices, lighting: Lighting | None = None, folder=None, count: int = 4000,
                     variant: str = "llvm_ad_rgb") -> list[dict]:
    """The plate's table against its closed form, one row a ``(n_theta, n_phi, reduction, n_u)`` choice.

    Each choice is tabulated with ``channels="components"`` (:func:`plate_values`), written, and evaluated by
    Mitsuba's plugin (:func:`evaluate`) at :func:`study_directions`; the error is on the study's 0-255 scale
    (``J`` = ``lighting.light``), unrounded.

    Returns
    -------
    list of dict: ``n_theta``, ``n_phi``, ``reduction``, ``n_u``, ``megabytes`` (the file), and for ``diffuse``
    and ``specular`` the ``worst`` and ``mean`` absolute error, the worst signed ``bias`` and the worst where the
    light and the view are both within 60 and 80 degrees of the normal (``worst_60``, ``worst_80``; :data:`CORES`),
    levels.
    """
    lighting = Lighting() if lighting is None else lighting
    folder = Path(tempfile.mkdtemp(prefix="measured-study-")) if folder is None else Path(folder)
    light, view = study_directions(count)
    exact = plate_values(lighting)(light, view)
    rows = []
    for n_theta, n_phi, reduction, n_u in choices:
        theta, phi = table_nodes(n_theta, n_phi, reduction)
        table = tabulate(plate_values(lighting), theta, phi, n_u, lighting, channels="components")
        path = write_measured(folder / f"plate-{n_theta}-{n_phi}-{reduction}-{n_u}.bsdf", theta, phi, table,
                              f"plate {n_theta} x {n_phi} (r {reduction}) x {n_u}^2")
        got = evaluate(path, light, view, variant) * np.pi * float(lighting.light)
        row = {"n_theta": n_theta, "n_phi": n_phi, "reduction": reduction, "n_u": n_u,
               "megabytes": path.stat().st_size / 1e6}
        lowest = np.minimum(light[:, 2], view[:, 2])
        for c, name in enumerate(("diffuse", "specular")):
            error = got[:, c] - exact[name]
            row[f"{name}_worst"] = float(np.abs(error).max())
            row[f"{name}_mean"] = float(np.abs(error).mean())
            row[f"{name}_bias"] = float(error[np.argmax(np.abs(error))])
            for core in CORES:
                inside = lowest >= np.cos(np.radians(core))
                row[f"{name}_worst_{core:.0f}"] = float(np.abs(error[inside]).max())
        rows.append(row)
        path.unlink()
    return rows


def _main(argv=None) -> None:
    import argparse

    parser = argparse.ArgumentParser(description="The plate's measured-BRDF table against its closed form")
    parser.add_argument("choices", nargs="+", help="n_theta,n_phi,reduction,n_u (e.g. 17,10,4,64)")
    parser.add_argument("--count", type=int, default=4000)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    args = parser.parse_args(argv)
    choices = [tuple(int(x) for x in choice.split(",")) for choice in args.choices]
    print("| theta_i x phi_i (r) | n_u | MB | diffuse worst: 60 / 80 / all | diffuse mean | "
          "specular worst: 60 / 80 / all | specular mean |")
    print("|---|---|---|---|---|---|---|")
    for row in resolution_study(choices, count=args.count, variant=args.variant):
        print(f"| {row['n_theta']} x {row['n_phi']} ({row['reduction']}) | {row['n_u']} | {row['megabytes']:.1f} | "
              f"{row['diffuse_worst_60']:.2f} / {row['diffuse_worst_80']:.2f} / {row['diffuse_worst']:.2f} | "
              f"{row['diffuse_mean']:.3f} | {row['specular_worst_60']:.2f} / {row['specular_worst_80']:.2f} / "
              f"{row['specular_worst']:.2f} | {row['specular_mean']:.3f} |")


if __name__ == "__main__":
    _main()
