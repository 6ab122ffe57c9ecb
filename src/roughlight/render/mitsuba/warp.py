"""The Mitsuba file's warp: where its half-vector nodes go (the ``vndf`` field of Dupuy and Jakob's format).

The ``measured`` plugin takes a direction pair's half vector ``u`` back to a sample space through the warp the
``vndf`` field defines (a continuous 2-D marginal distribution over the ``u`` square, one a ``wi`` node and
interpolated between them) and reads ``rgb`` bilinearly there. A density that is high where the values curve puts
more of the grid's nodes there. :func:`warp_density` builds it from a table on the regular grid;
:func:`node_half_vectors` gives the half vectors a slice's nodes take, which
:func:`roughlight.render.mitsuba.measured.tabulate` measures. docs/export-mitsuba.md ("The warp") says how the
density was chosen and what it buys.
"""

from __future__ import annotations

import numpy as np

__all__ = ["WARP_FLOOR", "WARP_POWER", "WARP_OWN", "WARP_SIDE", "half_vector", "warp_density", "node_half_vectors"]

#: The warp's share of nodes spread evenly (:func:`warp_density`): the rest follow the values' curvature.
WARP_FLOOR = 0.3
#: The power of the curvature that places the rest (0.75 between the 1/2 and 1 tried; docs/export-mitsuba.md).
WARP_POWER = 0.75
#: How much of each slice's own density the warp keeps (the rest is the mean over the slices): neighbouring slices
#: with one warp put a feature at one sample point, and the plugin interpolates between slices there.
WARP_OWN = 0.5
#: The warp's own grid, nodes a side: as good as the values' 32 at the design pairs, a quarter of the bytes.
WARP_SIDE = 16


def warp_density(rgb, floor: float = WARP_FLOOR, power: float = WARP_POWER, own: float = WARP_OWN,
                 side: int | None = WARP_SIDE) -> np.ndarray:
    """The file's ``vndf`` field from a table on the regular grid (``tabulate`` without a warp): where the plugin's
    bilinear lookup needs nodes.

    Each slice's need is its total's (channel 2: the total in either layout) curvature on the ``u`` grid,
    ``(|f_00| + |f_11| + 2 |f_01|) ** power`` (second differences), over its mean; the density is ``floor`` of even
    spread plus ``1 - floor`` of that need, and each slice keeps ``own`` of its density and takes the rest from
    the mean over all slices. With ``side`` it is read at ``side x side`` nodes of the ``u`` square (bilinearly):
    the plugin's warp has a grid of its own, and a coarser one is a smaller file.

    Returns
    -------
    (n_phi, n_theta, side, side) float32 (``side`` None: ``n_u``), positive: the density over the ``u`` square
    (``[u_1, u_0]``, as ``rgb``)
    """
    total = np.asarray(rgb, float)[:, :, 2]
    d00 = np.abs(np.gradient(np.gradient(total, axis=3), axis=3))
    d11 = np.abs(np.gradient(np.gradient(total, axis=2), axis=2))
    d01 = np.abs(np.gradient(np.gradient(total, axis=2), axis=3))
    need = (d00 + d11 + 2.0 * d01) ** float(power)
    mean = need.mean(axis=(2, 3), keepdims=True)
    need = np.where(mean > 0, need / np.where(mean > 0, mean, 1.0), 1.0)
    density = (1.0 - float(floor)) * need + float(floor)
    density = float(own) * density + (1.0 - float(own)) * density.mean(axis=(0, 1))
    n_u = density.shape[-1]
    if side is not None and int(side) != n_u:
        if int(side) < 2:
            raise ValueError(f"side must be at least 2, got {side!r}")
        at = np.linspace(0.0, n_u - 1.0, int(side))
        low = np.minimum(np.floor(at).astype(int), n_u - 2)
        w = at - low
        density = density[..., low, :] * (1 - w)[:, None] + density[..., low + 1, :] * w[:, None]
        density = density[..., low] * (1 - w) + density[..., low + 1] * w
    return density.astype(np.float32)


def half_vector(u) -> np.ndarray:
    """The half vector of points of the plugin's ``u`` square, ``(..., 2)`` as ``(u_0, u_1)``: ``theta_m = u_0^2 pi /
    2`` from the normal, ``phi_m = (2 u_1 - 1) pi``; ``(..., 3)`` unit vectors."""
    u = np.asarray(u, float)
    theta_m, phi_m = u[..., 0] ** 2 * (np.pi / 2.0), (2.0 * u[..., 1] - 1.0) * np.pi
    return np.stack([np.sin(theta_m) * np.cos(phi_m), np.sin(theta_m) * np.sin(phi_m), np.cos(theta_m)], axis=-1)


def node_half_vectors(vndf, theta, phi, n_u: int):
    """Where the plugin's warp takes the regular grid of its sample space, slice by slice.

    Parameters
    ----------
    vndf : (n_phi, n_theta, k, k) positive array (any ``k`` >= 2), the warp's density (:func:`warp_density`)
    theta, phi : the file's ``theta_i`` and ``phi_i`` nodes, radians
    n_u : int, the grid's side

    Returns
    -------
    callable ``nodes(a, b)``: slice ``(phi[a], theta[b])``'s half vectors, ``(n_u * n_u, 3)`` unit vectors in the
    file's order (sample ``[s_1, s_0]``, ``s = k / (n_u - 1)``), through Mitsuba's ``MarginalContinuous2D2`` (the
    class ``measured.cpp`` builds from the field) at that slice's node
    """
    density = np.ascontiguousarray(vndf, np.float32)
    if (density.ndim != 4 or density.shape[:2] != (len(phi), len(theta)) or density.shape[2] != density.shape[3]
            or density.shape[2] < 2 or not np.all(density > 0)):
        raise ValueError(f"vndf must be a positive (n_phi, n_theta, k, k) = {(len(phi), len(theta))} + (k, k) array, "
                         f"got {density.shape}")
    from . import runtime

    mi, _ = runtime.load("scalar_rgb")
    warp = mi.MarginalContinuous2D2(density, [np.asarray(phi, float).tolist(), np.asarray(theta, float).tolist()])
    grid = np.linspace(0.0, 1.0, n_u)

    def nodes(a, b):
        param = mi.ScalarPoint2f(float(phi[a]), float(theta[b]))
        u = np.array([[list(warp.sample(mi.ScalarPoint2f(float(s0), float(s1)), param)[0]) for s0 in grid]
                      for s1 in grid]).reshape(-1, 2)
        return half_vector(u)

    return nodes

