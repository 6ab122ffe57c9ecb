"""Which light directions a surface cannot tell apart: measure one and turn the views.

A surface's symmetries act on azimuths (degrees, the study's: 0 along the lattice's x axis). Lit from azimuth
``psi`` and seen from views at azimuths ``phi``, a surface gives the same image as lit from ``g(psi)`` and seen from
``g(phi)`` for every symmetry ``g`` of it. So a light direction needs measuring once per class:

* the plate (the control) is the same turned by any angle: every light azimuth is the study's, 0;
* square pyramids repeat every 90 degrees and mirror about the lattice's axes and diagonals (the square's eight
  symmetries): every light azimuth is one in [0, 45];
* a random tile repeats nothing: every light azimuth is its own.

:func:`canonical_light` names the light to measure and the map that takes the views along.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .roughness import kind_and_seed

__all__ = ["SYMMETRIES", "AzimuthMap", "symmetry", "canonical_light", "canonical_directions", "square_fold"]

#: What each sort of surface repeats, by :func:`symmetry`'s name: ``isotropic``, ``square``, ``none``.
SYMMETRIES = ("isotropic", "square", "none")


@dataclass(frozen=True)
class AzimuthMap:
    """``phi -> sign * phi + offset`` (degrees, modulo 360): a rotation (``sign`` 1) or a mirror (``sign`` -1)."""

    sign: int = 1
    offset: float = 0.0

    def __call__(self, azimuth):
        """The map applied to azimuths (degrees; an array or a number), in [0, 360)."""
        return np.mod(self.sign * np.asarray(azimuth, float) + self.offset, 360.0)


def symmetry(surface) -> str:
    """The symmetry of ``surface`` that acts on light directions: ``isotropic`` (the plate), ``square`` (regular
    truncated pyramids) or ``none`` (a random tile, ``surface.kind`` random_*)."""
    if kind_and_seed(surface)[0] != "pyramids":
        return "none"
    return "isotropic" if surface.is_plate else "square"


def canonical_light(surface, light_azimuth: float) -> tuple[float, AzimuthMap]:
    """The light azimuth to measure in place of ``light_azimuth``, and the map that takes a view azimuth with it.

    Returns
    -------
    (float, AzimuthMap)
        ``psi0`` (degrees: 0 for the plate, in [0, 45] for square pyramids, ``light_azimuth`` mod 360 for a random
        tile) and ``g`` with ``g(light_azimuth) == psi0``: the view at azimuth ``phi`` under the light at
        ``light_azimuth`` sees what the view at ``g(phi)`` (same elevation) sees under the light at ``psi0``.
    """
    psi0, sign, offset = _folds(symmetry(surface), np.array([float(light_azimuth)]))
    return float(psi0[0]), AzimuthMap(int(sign[0]), float(offset[0]))


def _folds(kind: str, light_azimuth):
    """The canonical light azimuths of many lights and the maps that take them there, arrays (n,): ``psi0``
    (degrees), ``sign`` (1 a rotation, -1 a mirror) and ``offset`` (degrees) of :class:`AzimuthMap`, for a surface
    of symmetry ``kind`` (:func:`symmetry`)."""
    psi = np.mod(np.asarray(light_azimuth, float), 360.0)
    ones = np.ones(psi.shape, int)
    if kind == "none":
        return psi, ones, np.zeros(psi.shape)
    if kind == "isotropic":
        return np.zeros(psi.shape), ones, -psi
    quarter = 90.0 * np.floor(psi / 90.0)  # turn into [0, 90) by a multiple of 90 degrees
    rest = psi - quarter
    mirrored = rest > 45.0  # then mirror about the diagonal at 45 degrees
    return (np.where(mirrored, 90.0 - rest, rest), np.where(mirrored, -1, 1),
            np.where(mirrored, 90.0 + quarter, -quarter))


def _turned(directions, degrees, mirrored):
    """(n, 3) ``directions`` turned about the z axis by ``degrees`` (n,), after mirroring those ``mirrored`` (n,)
    about the x axis (y -> -y): the :class:`AzimuthMap` ``phi -> sign phi + offset`` applied to vectors."""
    d = np.array(directions, float, copy=True)
    d[mirrored, 1] *= -1.0
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    x, y = d[:, 0].copy(), d[:, 1].copy()
    d[:, 0], d[:, 1] = c * x - s * y, s * x + c * y
    return d


def canonical_directions(surface, light, view):
    """Light and view directions turned together to the light :func:`canonical_light` measures, many at once.

    Parameters
    ----------
    surface : Surface or RandomSurface
    light, view : (n, 3) arrays
        Unit vectors toward the light and toward the detector, one pair a row.

    Returns
    -------
    light, view : (n, 3) arrays
        The same pairs moved by the surface's symmetry that takes each light's azimuth to its canonical one
        (:func:`canonical_light`, the same map applied to both vectors: rotations and mirrors keep every angle
        between them, so each facet's lighting equation is unchanged).
    """
    light, view = np.atleast_2d(np.asarray(light, float)), np.atleast_2d(np.asarray(view, float))
    _, sign, offset = _folds(symmetry(surface), np.degrees(np.arctan2(light[:, 1], light[:, 0])))
    return _turned(light, offset, sign < 0), _turned(view, offset, sign < 0)


def square_fold(direction) -> np.ndarray:
    """The symmetry of the square's eight that takes a direction's azimuth into [0, 45] degrees, as its matrix on
    plan vectors.

    Parameters
    ----------
    direction : (2,) or (3,) array
        A direction's plan part ``(x, y)`` (a ``z`` is ignored); not vertical.

    Returns
    -------
    (2, 2) float array
        ``M`` with entries in {-1, 0, 1} (a rotation by a multiple of 90 degrees after a mirror ``y -> -y`` or
        not, :class:`AzimuthMap`'s), such that ``M @ direction[:2]`` has its azimuth in [0, 45]; about the lattice
        cell's centre it maps square pyramids onto themselves. Exact: a plan point moves without rounding.
    """
    direction = np.asarray(direction, float)
    _, sign, offset = _folds("square", np.degrees(np.arctan2(direction[1:2], direction[0:1])))
    turn = np.radians(offset[0])
    c, s = round(float(np.cos(turn))), round(float(np.sin(turn)))
    return np.array([[c, -s * sign[0]], [s, c * sign[0]]], float)
