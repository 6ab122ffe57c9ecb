"""A random tile's region triangles counted on the CPU: each view's visible and total pixels of each region.

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

:func:`count_views` runs that for many views in compiled code (numba); OpenGL on llvmpipe took three to six times
as long for the same counts, set up and rasterised triangle by triangle (docs/budgets.md). Coordinates are
double precision, so a centre is misplaced only within rounding of an edge, where llvmpipe snaps vertices to 1/256
of a pixel.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["torus_basis", "count_views", "identity", "compile_kernel"]


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
    region = np.asarray(region, np.int64)
    if region.size and (region.min() < 0 or region.max() >= n_regions):
        raise ValueError(f"regions must lie in [0, {n_regions})")
    visible, total = _kernel()(np.ascontiguousarray(triangles, np.float64), region, int(n_regions),
                               np.ascontiguousarray(shears, np.float64), np.asarray(matrix, np.float64),
                               a, b, c, bool(totals))
    return visible, (total if totals else None), a * c


def identity() -> str:
    """What the counts run on, as a sweep records it in place of an OpenGL renderer: ``"counted on the CPU
    (numba 0.68.1)"``."""
    from importlib import metadata

    return f"counted on the CPU (numba {metadata.version('numba')})"


def compile_kernel() -> None:
    """Compile the counting kernel now, or load it from the cache: ``make setup`` calls it once, so that the first
    jobs of a fresh clone, starting together, do not each spend seconds compiling it."""
    count_views(np.zeros((1, 3, 3)), np.zeros(1, np.int64), 1, np.zeros((1, 2)), np.eye(2, dtype=np.int64))


#: :func:`_scan` and :func:`_count` compiled, set by :func:`_kernel` on first use (``_count`` calls ``_scan``).
_scan_compiled = _count_compiled = None


def _kernel():
    """The compiled :func:`_count` (numba, cached on disk beside this module: a process pays about half a second to
    load it, the first one on a machine about two seconds to compile it)."""
    global _scan_compiled, _count_compiled
    if _count_compiled is None:
        import numba

        jit = numba.njit(cache=True, nogil=True)
        _scan_compiled = jit(_scan)
        _count_compiled = jit(_count)
    return _count_compiled


def _count(tris, region, n_regions, shears, matrix, a, b, c, totals):  # pragma: no cover - compiled
    """Each view: the buffers cleared, every triangle scanned (:func:`_scan`), the visible regions tallied."""
    n_views, n_pix = shears.shape[0], a * c
    visible = np.zeros((n_views, n_regions))
    total = np.zeros((n_views, n_regions))
    zbuf = np.empty(n_pix)
    rbuf = np.empty(n_pix, np.int64)
    px, py = np.empty(3), np.empty(3)
    for v in range(n_views):
        zbuf[:] = -np.inf
        rbuf[:] = -1
        for t in range(tris.shape[0]):
            for k in range(3):  # the corner in pixels: matrix @ ((x, y) - z d)
                cx = tris[t, k, 0] - tris[t, k, 2] * shears[v, 0]
                cy = tris[t, k, 1] - tris[t, k, 2] * shears[v, 1]
                px[k] = matrix[0, 0] * cx + matrix[0, 1] * cy
                py[k] = matrix[1, 0] * cx + matrix[1, 1] * cy
            _scan_compiled(px, py, tris[t, :, 2], region[t], a, b, c, zbuf, rbuf, total[v], totals)
        for p in range(n_pix):
            if rbuf[p] >= 0:
                visible[v, rbuf[p]] += 1.0
    return visible, total


def _scan(px, py, pz, r, a, b, c, zbuf, rbuf, total, totals):  # pragma: no cover - compiled
    """One triangle, its corners at pixels ``(px, py)`` and heights ``pz``, scanned onto the torus ``(a, b, c)``:
    each centre inside adds one to ``total[r]`` (if ``totals``) and keeps ``r`` where it is the highest yet."""
    twice = (px[1] - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (py[1] - py[0])
    if twice <= 0.0:  # faces away, or edge-on
        return
    # the height over the pixel plane: z = z_base + gx x + gy y
    e1z, e2z = pz[1] - pz[0], pz[2] - pz[0]
    gx = (e1z * (py[2] - py[0]) - e2z * (py[1] - py[0])) / twice
    gy = (e2z * (px[1] - px[0]) - e1z * (px[2] - px[0])) / twice
    z_base = pz[0] - gx * px[0] - gy * py[0]
    # corners in (y, x) order: each edge is walked from its lower end, the same way in both its triangles
    i0, i1, i2 = 0, 1, 2
    if py[i1] < py[i0] or (py[i1] == py[i0] and px[i1] < px[i0]):
        i0, i1 = i1, i0
    if py[i2] < py[i1] or (py[i2] == py[i1] and px[i2] < px[i1]):
        i1, i2 = i2, i1
        if py[i1] < py[i0] or (py[i1] == py[i0] and px[i1] < px[i0]):
            i0, i1 = i1, i0
    x0, y0, x1, y1, x2, y2 = px[i0], py[i0], px[i1], py[i1], px[i2], py[i2]
    first, middle, last = math.ceil(y0 - 0.5), math.ceil(y1 - 0.5), math.ceil(y2 - 0.5)
    if last <= first:
        return
    s02 = (x2 - x0) / (y2 - y0)
    s01 = (x1 - x0) / (y1 - y0) if y1 > y0 else 0.0
    s12 = (x2 - x1) / (y2 - y1) if y2 > y1 else 0.0
    for j in range(first, last):  # rows whose centre y = j + 1/2 lies in [y0, y2)
        yc = j + 0.5
        xa = x0 + (yc - y0) * s02
        xb = x0 + (yc - y0) * s01 if j < middle else x1 + (yc - y1) * s12
        if xa > xb:
            xa, xb = xb, xa
        i_first, i_last = math.ceil(xa - 0.5), math.ceil(xb - 0.5)  # centres xa <= i + 1/2 < xb
        if i_last <= i_first:
            continue
        if totals:
            total[r] += i_last - i_first
        q = j // c
        row = (j - q * c) * a
        col = (i_first - q * b) % a
        z = z_base + gy * yc + gx * (i_first + 0.5)
        for _ in range(i_first, i_last):
            if z > zbuf[row + col]:
                zbuf[row + col] = z
                rbuf[row + col] = r
            z += gx
            col += 1
            if col == a:
                col = 0
