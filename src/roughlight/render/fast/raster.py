"""A random tile's region triangles counted on the CPU: each view's visible and total pixels of each region (and,
for every surface's adaptive plan, its edges' star discrepancies against the pixel rows: :func:`star_discrepancy`).

The fast renderer samples one period of a view's image at the pixel centres of a lattice
(:mod:`roughlight.render.fast.sampling`): pixel coordinates are ``matrix @ cell``, ``cell = (x, y) - z d`` the
oblique projection along the view (``d = (V_x / V_z, V_y / V_z)``), and the samples are the centres
``(i + 1/2, j + 1/2)`` taken modulo the lattice ``matrix @ Z^2``: a torus of ``|det matrix|`` pixels, one period.
On that torus every periodic copy of a triangle is the triangle itself, so each triangle is drawn once, whole:

* Its pixel centres are found row by row (a centre on an edge goes to the triangle on the edge's right, each edge
  walked the same way in both its triangles, so that neighbours share no centre and leave none out).
* Each centre adds one to the region's *total* (every centre of its projection, hidden or not: the count
  :func:`roughlight.render.fast.shares.counts_and_areas` makes from polygons) and keeps the region in its torus
  pixel if it is higher than what the pixel holds: along a ray coming down from the detector the first surface
  hit is the highest one (``shaders/periodic.vert`` draws with the same depth).
* Triangles whose projection turns clockwise face away from the view and are left out (back faces).

:func:`count_views` runs that for many views in C (``raster.c`` beside this module, built once by the machine's C
compiler and loaded with :mod:`ctypes`: :func:`build_kernel`); OpenGL on llvmpipe took three to six times as long
for the same counts, set up and rasterised triangle by triangle (docs/budgets.md). Coordinates are double precision,
so a centre is misplaced only within rounding of an edge, where llvmpipe snaps vertices to 1/256 of a pixel.
"""

from __future__ import annotations

import ctypes
from pathlib import Path

import numpy as np

from .. import native

__all__ = ["torus_basis", "count_views", "star_discrepancy", "identity", "build_kernel", "compile_kernel", "SOURCE"]

#: The kernel's C source.
SOURCE = Path(__file__).with_name("raster.c")


def torus_basis(matrix) -> tuple[int, int, int]:
    """The lattice ``matrix @ Z^2`` in Hermite normal form: ``(a, b, c)`` with ``a, c > 0``, ``0 <= b < a``, so that
    ``(a, 0)`` and ``(b, c)`` span it. Pixel ``(i, j)`` is then torus pixel ``j' a + i'``, with ``j' = j mod c`` and
    ``i' = (i - b floor(j / c)) mod a``; there are ``a c = |det matrix|`` of them.

    Parameters
    ----------
    matrix : (2, 2) int array
        Cell coordinates to pixels (:func:`roughlight.render.fast.sampling.sampling_matrix`), non-singular.
    """
    m = np.asarray(matrix)
    if not np.array_equal(m, np.round(m)) or round(abs(np.linalg.det(m))) == 0:
        raise ValueError(f"a torus needs a non-singular integer matrix, got {m.tolist()}")
    (u0, v0), (u1, v1) = [[int(x) for x in row] for row in m]
    g, s, t = _extended_gcd(u1, v1)  # s u1 + t v1 = g > 0 (not both 0: the matrix is non-singular)
    a = abs((v1 // g) * u0 - (u1 // g) * v0)  # the combination with no second component
    return a, (s * u0 + t * v0) % a, g


def _extended_gcd(x: int, y: int) -> tuple[int, int, int]:
    """``(g, s, t)``: ``g = gcd(x, y) >= 0`` and ``s x + t y = g``."""
    s0, s1, t0, t1 = 1, 0, 0, 1
    while y:
        q = x // y
        x, y = y, x - q * y
        s0, s1, t0, t1 = s1, s0 - q * s1, t1, t0 - q * t1
    return (x, s0, t0) if x >= 0 else (-x, -s0, -t0)


def count_views(triangles, region, n_regions: int, shears, matrix, totals: bool = True):
    """Each view's visible and total pixel centres of each region, on the torus of ``matrix``.

    Parameters
    ----------
    triangles : (T, 3, 3) float array
        The tile's region triangles (:func:`roughlight.render.fast.counting.region_triangles`): plan x, y and
        height of each corner, periods, counter-clockwise seen from above.
    region : (T,) int array
        The region each triangle belongs to, in ``[0, n_regions)``.
    n_regions : int
    shears : (V, 2) float array
        Each view's plan shift ``d = (V_x / V_z, V_y / V_z)``.
    matrix : (2, 2) int array
        Cell coordinates to pixels, ``det > 0`` (:func:`torus_basis`).
    totals : bool
        Count every centre of each region's projection too; False: the visible ones only (``total`` is None).

    Returns
    -------
    visible : (V, R) float array
        Centres showing each region (at most ``|det matrix|`` a view).
    total : (V, R) float array or None
    per_tile : int
        ``|det matrix|``, the torus's pixels.
    """
    a, b, c = torus_basis(matrix)
    if np.linalg.det(np.asarray(matrix, float)) < 0:
        raise ValueError("count_views needs a matrix that keeps orientation (det > 0): back faces are told by it")
    tris = np.ascontiguousarray(triangles, np.float64).reshape(-1, 3, 3)
    region = np.ascontiguousarray(region, np.int64)
    shears = np.ascontiguousarray(shears, np.float64).reshape(-1, 2)
    if region.shape != (len(tris),):
        raise ValueError(f"{len(tris)} triangles need as many regions, got shape {region.shape}")
    if region.size and (region.min() < 0 or region.max() >= n_regions or n_regions >= 2**31):
        raise ValueError(f"regions must lie in [0, {n_regions}), fewer than 2**31")
    matrix = np.ascontiguousarray(matrix, np.float64)
    visible, total = np.zeros((2, len(shears), int(n_regions)))
    zbuf, rbuf = np.empty(a * c), np.empty(a * c, np.int32)  # each torus pixel's highest surface and its region
    _library().roughlight_count_views(
        _pointer(tris), _pointer(region), len(tris), int(n_regions), _pointer(shears), len(shears), _pointer(matrix),
        a, b, c, bool(totals), _pointer(visible), _pointer(total), _pointer(zbuf), _pointer(rbuf))
    return visible, (total if totals else None), a * c


def star_discrepancy(x0, y0, x1, y1, valid) -> np.ndarray:
    """(S,) each segment's star discrepancy against the pixel-centre rows, in C: what
    :func:`roughlight.render.fast.shares.star_discrepancy_numpy` computes, to the bit (the same operations in the
    same order, the running sum carried from segment to segment as ``numpy.cumsum`` carries it), in a tenth of the
    time. ``x0`` ... ``y1`` (S,) floats, pixels; ``valid`` (S,) bools."""
    x0, y0, x1, y1 = (np.ascontiguousarray(v, np.float64) for v in (x0, y0, x1, y1))
    valid = np.ascontiguousarray(valid, np.uint8)
    if not (x0.shape == y0.shape == x1.shape == y1.shape == valid.shape) or x0.ndim != 1:
        raise ValueError("star_discrepancy: the segments' arrays must be (S,) alike")
    star = np.empty(x0.shape)
    _library().roughlight_star_discrepancy(_pointer(x0), _pointer(y0), _pointer(x1), _pointer(y1), _pointer(valid),
                                           len(x0), _pointer(star))
    return star


def identity() -> str:
    """What the counts run on, as a sweep records it in place of an OpenGL renderer: ``"counted on the CPU (C,
    gcc 12.2.0)"``, the compiler that built the kernel."""
    return f"counted on the CPU (C, {_library().roughlight_compiler().decode()})"


def build_kernel(cache=None) -> Path:
    """The kernel's shared library, built from :data:`SOURCE` if it is not yet there
    (:func:`roughlight.render.native.build`: ``__pycache__/raster-<digest>.so`` beside this module, or in
    ``$XDG_CACHE_HOME/roughlight``; ``cache``, a folder, instead). ``make setup`` builds it.

    Raises
    ------
    RuntimeError
        No C compiler, or the compiler failed (its message is included).
    """
    return native.build(SOURCE, "the random tiles' counting kernel", cache)


def compile_kernel() -> None:
    """Build the counting kernel now (:func:`build_kernel`) and load it: ``make setup`` calls it once, so that the
    first jobs of a fresh clone do not each build it, and a missing compiler is said at set-up."""
    _library()


#: The loaded kernel (:func:`_library`), one a process.
_loaded = None


def _library():
    """The kernel loaded (:func:`build_kernel`), its function's argument types declared."""
    global _loaded
    if _loaded is None:
        library = ctypes.CDLL(str(build_kernel()))
        p, n = ctypes.c_void_p, ctypes.c_int64
        library.roughlight_count_views.argtypes = [p, p, n, n, p, n, p, n, n, n, ctypes.c_int, p, p, p, p]
        library.roughlight_count_views.restype = None
        library.roughlight_star_discrepancy.argtypes = [p, p, p, p, p, n, p]
        library.roughlight_star_discrepancy.restype = None
        library.roughlight_compiler.restype = ctypes.c_char_p
        _loaded = library
    return _loaded


def _pointer(array: np.ndarray):
    """A C-contiguous array's data, for the kernel."""
    assert array.flags.c_contiguous
    return array.ctypes.data_as(ctypes.c_void_p)
