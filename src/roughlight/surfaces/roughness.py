"""Random roughness: periodic tiles of randomly varied facets (the thesis's Ch. VI conclusion).

The regular surface (:mod:`roughlight.surfaces.geometry`) has one facet orientation per
side; natural rough surfaces do not. A random surface here is a *tile* of
``cells x cells`` pyramid cells that repeats periodically, so everything that
holds for one period of the regular surface (the fast renderer's one-period
trick, the exact reference's lattice of copies) holds with the tile as the
period.

Conventions
-----------
* The tile is the unit period ``[0, 1]^2`` of the ``z = 0`` plane, like one
  period of the regular surface; a cell is ``1 / cells`` wide and every
  height is scaled by the same factor, so slopes (and so the reflectance)
  are those of the grid point's pyramids of width 1. The lowest point of a
  tile is at ``z = 0``; its :attr:`RandomSurface.height` is the highest.
* ``random_pyramids``: cell ``(i, j)`` holds a truncated pyramid on the whole
  cell with its own truncation ``t_ij = clip(t + s_t U, 0, 1)``, aspect
  ``a_ij = a (1 + s_a U)`` and apex displaced from the cell centre by
  ``s_p (w / 2) (U, U)`` (``U`` independent uniform on [-1, 1], ``w`` the
  cell width; ``s_t, s_a, s_p`` are :class:`Spread`). Each side is the plane
  through a base edge and the apex; the top is the horizontal cut at
  ``t_ij`` of the full height. All bases lie on ``z = 0`` on the cell
  boundaries, so neighbouring cells meet edge to edge: no gaps, no overlaps.
  ``s_a < 1`` keeps every aspect positive and ``s_p < 1`` keeps the apex
  inside its cell (no overhanging or vertical side).
* ``random_heightfield``: a periodic Gaussian random field with Gaussian
  autocorrelation of length :data:`CORRELATION_CELLS` cells on a grid of
  ``cells x VERTICES_PER_CELL`` vertices a side, each square split into two
  flat triangles (diagonals alternating as a checkerboard, so no diagonal
  direction is preferred), scaled so that its RMS slope equals the regular
  surface's at the same grid point, :func:`pyramid_rms_slope`.
* Randomness is reproducible: the generator is seeded with the seed and the
  grid point (:func:`random_generator`), so a surface is the same on every
  machine and every run, and adding seeds changes no existing surface.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .geometry import twice_signed_area
from .surface import LENGTH_EPS, Surface, label

__all__ = [
    "KINDS",
    "RANDOM_KINDS",
    "Spread",
    "RandomSurface",
    "pyramid_rms_slope",
    "rms_slope",
    "random_generator",
    "surface_label",
    "make_surface",
]

#: Surface kinds (``surface.kind``): the regular grid first (the study's default).
KINDS = ("pyramids", "random_pyramids", "random_heightfield")
#: The random kinds, each measured as an ensemble of seeds.
RANDOM_KINDS = KINDS[1:]
#: Default tile size, cells a side (chosen from the tile-size convergence measurement; docs/random-roughness.md).
DEFAULT_CELLS = 4
#: Vertices of the random heightfield per cell width.
VERTICES_PER_CELL = 4
#: Correlation length of the random heightfield, in cell widths (autocorrelation ``exp(-r^2 / l^2)``).
CORRELATION_CELLS = 0.5


@dataclass(frozen=True)
class Spread:
    """How far a random pyramid cell may vary around the grid point (``surface.spread``).

    Attributes
    ----------
    truncation : float
        Half-width of the uniform spread of each cell's truncation (absolute,
        the result clipped to [0, 1]); >= 0.
    aspect : float
        Half-width of the relative spread of each cell's aspect,
        ``a (1 + aspect U)``; in [0, 1) (1 would allow a flat side).
    apex : float
        How far the apex may move from the cell centre along x and y, as a
        fraction of the half cell; in [0, 1).
    corner : float
        How far each cell corner (shared by the four cells meeting there) may
        move along x and y, as a fraction of the half cell; in [0, 0.5]. It
        turns the cells' bases into varied convex quadrilaterals, so the side
        normals point in varied azimuths (with square bases, a side through an
        x-aligned base edge always faces along y, wherever the apex is).
        ``apex + corner < 1`` keeps every apex inside its base (no vertical or
        overhanging side).
    """

    truncation: float = 0.2
    aspect: float = 0.3
    apex: float = 0.5
    corner: float = 0.3

    def __post_init__(self):
        checks = {
            "truncation": (lambda v: 0.0 <= v <= 1.0, "within [0, 1]"),
            "aspect": (lambda v: 0.0 <= v < 1.0, "within [0, 1) (1 or more would make a flat or inverted side)"),
            "apex": (lambda v: 0.0 <= v < 1.0, "within [0, 1) (1 or more puts the apex outside its cell: an "
                                                "overhanging or vertical side)"),
            "corner": (lambda v: 0.0 <= v <= 0.5, "within [0, 0.5] (more could fold a cell's base)"),
        }
        for key, (ok, allowed) in checks.items():
            value = getattr(self, key)
            try:
                value = float(value)
            except (TypeError, ValueError):
                raise ValueError(f"surface.spread.{key} must be a number {allowed}, got {value!r}") from None
            if not (math.isfinite(value) and ok(value)):
                raise ValueError(f"surface.spread.{key} must be {allowed}, got {value!r}")
            object.__setattr__(self, key, value)
        if self.apex + self.corner >= 1.0:
            raise ValueError(f"surface.spread.apex + surface.spread.corner must be < 1 (else an apex can leave its "
                             f"cell's base: an overhanging or vertical side), got {self.apex} + {self.corner}")


def pyramid_rms_slope(truncation: float, aspect: float) -> float:
    """RMS slope ``|grad h|`` of the regular surface over its plan: ``2 a sqrt(1 - (1 - t)^2)``.

    The sides (slope ``2 a``) cover ``1 - (1 - t)^2`` of the plan, the top (slope 0) the rest.
    """
    t, a = float(truncation), float(aspect)
    return 2.0 * a * math.sqrt(max(0.0, 1.0 - (1.0 - t) ** 2))


def rms_slope(polygons) -> float:
    """Plan-area weighted RMS slope ``|grad h|`` of a set of facet polygons (``(name, (n, 3) array)``)."""
    total, weighted = 0.0, 0.0
    corners = np.array([v[:3] for _, v in polygons], float).reshape(-1, 3, 3)
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])  # one call, not one a facet
    for (_, v), normal in zip(polygons, normals):
        plan = 0.5 * abs(twice_signed_area(v[:, 0], v[:, 1]))
        slope2 = (normal[0] ** 2 + normal[1] ** 2) / normal[2] ** 2
        total += plan
        weighted += plan * slope2
    return math.sqrt(weighted / total)


def random_generator(kind: str, truncation: float, aspect: float, seed: int) -> np.random.Generator:
    """The seeded generator of one random surface: seed, kind and grid point (micro-units) as entropy."""
    return np.random.default_rng(
        [int(seed), KINDS.index(kind), int(round(float(truncation) * 1e6)), int(round(float(aspect) * 1e6))]
    )


def surface_label(kind: str, truncation_label: str, aspect_label: str, seed: int) -> str:
    """File stem of a surface: ``t0.5_a1`` for the regular one, ``random_pyramids_t0.5_a1_s3`` for a random one."""
    stem = f"t{truncation_label}_a{aspect_label}"
    return stem if kind == "pyramids" else f"{kind}_{stem}_s{int(seed)}"


def _random_pyramid_polygons(t, a, cells, spread: Spread, rng) -> list:
    w = 1.0 / cells
    n = cells * cells
    t_cell = np.clip(t + spread.truncation * rng.uniform(-1, 1, n), 0.0, 1.0)
    a_cell = a * (1.0 + spread.aspect * rng.uniform(-1, 1, n))
    shift = spread.apex * 0.5 * w * rng.uniform(-1, 1, (n, 2))
    # the cells' corners, shared by the four cells that meet there (periodic), moved up to corner * w / 2
    corner_shift = spread.corner * 0.5 * w * rng.uniform(-1, 1, (cells, cells, 2))

    def corner(i, j):
        return np.array([i * w, j * w]) + corner_shift[i % cells, j % cells]

    polygons = []
    for k in range(n):
        i, j = divmod(k, cells)
        quad = np.array([corner(i, j), corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1)])
        base = np.column_stack([quad, np.zeros(4)])
        apex_xy = np.array([(i + 0.5) * w, (j + 0.5) * w]) + shift[k]
        apex = np.array([apex_xy[0], apex_xy[1], a_cell[k] * w])
        tk = t_cell[k]
        if tk * a_cell[k] * w < LENGTH_EPS:
            polygons.append((f"c{i}_{j}_top", base))
            continue
        top = base + tk * (apex - base)  # the cut at height t * apex height, on each base-apex edge
        name = f"c{i}_{j}_"
        sides = {"south": (0, 1), "east": (1, 2), "north": (2, 3), "west": (3, 0)}
        for side, (p, q) in sides.items():
            verts = np.array([base[p], base[q], top[q], top[p]])
            if 1.0 - tk < LENGTH_EPS:
                verts = verts[:3]
                verts[2] = apex
            polygons.append((name + side, verts))
        if 1.0 - tk >= LENGTH_EPS:
            polygons.append((name + "top", top))
    return _wrap_into_period(polygons)


def _wrap_into_period(polygons) -> list:
    """Cut facets that cross the unit period's edges and move the pieces back inside, so the tile's plan is
    exactly ``[0, 1]^2`` (as one period of the regular surface). Each piece keeps its facet's plane; a cut
    facet's pieces are named ``{name}_w{k}{l}`` after the period copy ``(k, l)`` they came from."""
    import shapely
    from shapely.geometry import box
    from shapely.geometry.polygon import orient

    out = []
    for name, verts in polygons:
        plan = shapely.Polygon(verts[:, :2])
        lo, hi = verts[:, :2].min(axis=0), verts[:, :2].max(axis=0)
        if lo.min() >= 0.0 and hi.max() <= 1.0:
            out.append((name, verts))
            continue
        normal = np.cross(verts[1] - verts[0], verts[2] - verts[0])
        alpha, beta = -normal[0] / normal[2], -normal[1] / normal[2]
        gamma = verts[0, 2] - alpha * verts[0, 0] - beta * verts[0, 1]
        for k in range(int(np.floor(lo[0])), int(np.floor(hi[0])) + 1):
            for m in range(int(np.floor(lo[1])), int(np.floor(hi[1])) + 1):
                piece = plan.intersection(box(k, m, k + 1, m + 1))
                if piece.geom_type != "Polygon" or piece.area < 1e-15:
                    continue
                xy = np.asarray(orient(piece, 1.0).exterior.coords)[:-1]
                z = alpha * xy[:, 0] + beta * xy[:, 1] + gamma
                out.append((f"{name}_w{k}{m}", np.column_stack([xy[:, 0] - k, xy[:, 1] - m, z])))
    return out


def _gaussian_field(size: int, correlation: float, rng) -> np.ndarray:
    """A periodic Gaussian random field on ``size x size`` vertices, autocorrelation ``exp(-r^2/l^2)``,
    ``l = correlation`` in vertex spacings; zero mean, unit variance."""
    noise = rng.standard_normal((size, size))
    k = 2 * np.pi * np.fft.fftfreq(size)
    kx, ky = np.meshgrid(k, k, indexing="ij")
    # the power spectrum of exp(-r^2/l^2) is proportional to exp(-k^2 l^2 / 4): filter by its square root
    field = np.real(np.fft.ifft2(np.fft.fft2(noise) * np.exp(-(kx**2 + ky**2) * correlation**2 / 8.0)))
    field -= field.mean()
    return field / field.std()


def _heightfield_polygons(t, a, cells, rng) -> list:
    size = cells * VERTICES_PER_CELL
    z = _gaussian_field(size, CORRELATION_CELLS * VERTICES_PER_CELL, rng)
    step = 1.0 / size
    grid = np.arange(size + 1) * step
    zz = np.pad(z, ((0, 1), (0, 1)), mode="wrap")  # periodic: the last row and column repeat the first

    def triangles(heights):
        out = []
        for i in range(size):
            for j in range(size):
                p00 = (grid[i], grid[j], heights[i, j])
                p10 = (grid[i + 1], grid[j], heights[i + 1, j])
                p11 = (grid[i + 1], grid[j + 1], heights[i + 1, j + 1])
                p01 = (grid[i], grid[j + 1], heights[i, j + 1])
                if (i + j) % 2 == 0:  # diagonal p00-p11
                    pair = ([p00, p10, p11], [p00, p11, p01])
                else:  # diagonal p10-p01
                    pair = ([p00, p10, p01], [p10, p11, p01])
                for m, tri in enumerate(pair):
                    out.append((f"v{i}_{j}_{m}", np.array(tri, float)))
        return out

    target = pyramid_rms_slope(t, a)
    unit = rms_slope(triangles(zz))
    scale = target / unit if unit > 0 else 0.0
    heights = zz * scale
    return triangles(heights - heights.min())


@dataclass(frozen=True)
class RandomSurface:
    """One random rough surface: a kind, a grid point and a seed (a periodic tile of facets).

    Attributes
    ----------
    kind : str
        ``random_pyramids`` or ``random_heightfield`` (:data:`RANDOM_KINDS`).
    truncation, aspect : float
        The grid point the tile varies around (as :class:`roughlight.surfaces.surface.Surface`).
    seed : int
        >= 1; with the kind and the grid point it fixes the tile.
    cells : int
        Cells a side of the tile (>= 1).
    spread : Spread
        How random pyramid cells vary (the heightfield ignores it).

    The facets are built once, at construction; ``polygons`` holds them as
    ``(name, (n, 3) array)`` counter-clockwise seen from above, as
    :func:`roughlight.surfaces.geometry.facet_polygons` returns a period's.
    """

    kind: str
    truncation: float
    aspect: float
    seed: int = 1
    cells: int = DEFAULT_CELLS
    spread: Spread = field(default_factory=Spread)
    polygons: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        if self.kind not in RANDOM_KINDS:
            raise ValueError(f"surface.kind must be one of {KINDS}, got {self.kind!r}")
        grid = Surface(self.truncation, self.aspect)  # checks the grid point's ranges
        object.__setattr__(self, "truncation", grid.truncation)
        object.__setattr__(self, "aspect", grid.aspect)
        if isinstance(self.seed, bool) or int(self.seed) != self.seed or int(self.seed) < 1:
            raise ValueError(f"surface.seeds must be integers >= 1, got {self.seed!r}")
        object.__setattr__(self, "seed", int(self.seed))
        if isinstance(self.cells, bool) or int(self.cells) != self.cells or int(self.cells) < 1:
            raise ValueError(f"surface.cells must be an integer >= 1, got {self.cells!r}")
        object.__setattr__(self, "cells", int(self.cells))
        if not isinstance(self.spread, Spread):
            object.__setattr__(self, "spread", Spread(**dict(self.spread)))
        rng = random_generator(self.kind, self.truncation, self.aspect, self.seed)
        if self.kind == "random_pyramids":
            polygons = _random_pyramid_polygons(self.truncation, self.aspect, self.cells, self.spread, rng)
        else:
            polygons = _heightfield_polygons(self.truncation, self.aspect, self.cells, rng)
        object.__setattr__(self, "polygons", tuple(polygons))

    @property
    def height(self) -> float:
        """Highest point of the tile (units of the tile; the lowest is 0)."""
        return max(float(v[:, 2].max()) for _, v in self.polygons)

    @property
    def is_plate(self) -> bool:
        """True when the tile is flat (lower than :data:`roughlight.surfaces.surface.LENGTH_EPS`)."""
        return self.height < LENGTH_EPS

    @property
    def label(self) -> str:
        """File stem, e.g. ``random_pyramids_t0.5_a1_s3``."""
        return surface_label(self.kind, label(self.truncation), label(self.aspect), self.seed)


def make_surface(kind: str = "pyramids", truncation: float = 0.0, aspect: float = 0.0, seed: int = 0,
                 cells: int = DEFAULT_CELLS, spread=None):
    """The surface a sweep measures: the regular :class:`~roughlight.surfaces.surface.Surface` for ``pyramids``
    (``seed`` must be 0), else a :class:`RandomSurface` (as Snakemake's params give them)."""
    if kind == "pyramids":
        if int(seed) != 0:
            raise ValueError(f"the regular surface (kind pyramids) has seed 0, got {seed!r}")
        return Surface(truncation, aspect)
    return RandomSurface(kind, truncation, aspect, seed=seed, cells=cells, spread=Spread(**dict(spread or {})))


def kind_and_seed(surface) -> tuple[str, int]:
    """The study table's ``kind`` and ``seed`` of a surface (the regular one: ``pyramids``, 0)."""
    return (surface.kind, surface.seed) if isinstance(surface, RandomSurface) else ("pyramids", 0)
