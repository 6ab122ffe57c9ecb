"""Geometry of the rough surface: one period of a grid of truncated square pyramids.

Conventions (the study's; see docs/conventions.md)
---------------------------------------------------
* The period (pyramid base width) is ``w = 1``. One period is the cell
  ``[0, 1] x [0, 1]`` of the ``z = 0`` plane; the surface repeats with the
  lattice ``Z^2``.
* The full pyramid's height is ``h = aspect * w``; its base edges run along
  x and y and its apex stands over the cell centre ``(0.5, 0.5)``.
* ``truncation`` ``t`` is the fraction of the pyramid's height that is kept:
  the truncated pyramid is ``t * h`` tall and its top face is a square of
  side ``(1 - t) * w``. ``t = 0`` (or ``aspect = 0``) is the flat plate,
  identical to the control; ``t = 1`` is the full pyramid. (The thesis's
  Ch. III.6 words truncation the other way round; its analysis chapter,
  Tables 1-2, uses this meaning.)
* Facets are flat: every triangle carries its true face normal; vertices
  are never shared between facets, so nothing averages normals.

A period needs no more than four trapezoids (two triangles each) and the
top square (two triangles): 10 triangles; the full pyramid needs four
triangles and the plate two.
"""

from __future__ import annotations

import math

import numpy as np

from .surface import LENGTH_EPS, PLATE, Surface

__all__ = [
    "FACET_NAMES",
    "top_side",
    "side_slope_deg",
    "facet_polygons",
    "period_triangles",
    "period_mesh",
    "control_mesh",
    "facet_areas",
    "facets",
    "lobe_centres",
    "ring_next",
    "twice_signed_area",
]

#: Facet names in the order :func:`facet_polygons` returns them. ``east`` is
#: the side facet whose normal leans toward +x (toward the light, whose
#: azimuth is 0), ``west`` toward -x, ``north`` toward +y, ``south`` toward -y.
FACET_NAMES = ("top", "east", "west", "north", "south")

def ring_next(points: np.ndarray) -> np.ndarray:
    """Each corner's successor around its ring: ``points`` ((n, ...) array, a ring's corners in order) shifted by
    one, the first last (``np.roll(points, -1, axis=0)``, without its per-call cost: a random tile has thousands
    of rings)."""
    return np.concatenate((points[1:], points[:1]))


def twice_signed_area(x: np.ndarray, y: np.ndarray) -> float:
    """Twice the signed area of the ring with corners ``(x, y)`` ((n,) arrays each, in order; positive
    counter-clockwise): the shoelace sum."""
    return float(np.dot(x, ring_next(y)) - np.dot(y, ring_next(x)))


def top_side(truncation: float) -> float:
    """Side of the top face, ``1 - t`` (units of the period)."""
    return 1.0 - float(truncation)


def side_slope_deg(aspect: float) -> float:
    """Tilt of the side facets from horizontal, ``atan(2 * aspect)`` in degrees.

    At ``aspect = sqrt(3)/2`` the side facets tilt 60 deg, so their normals
    stand 30 deg above the horizon: facing a light at incidence 30 deg.
    """
    return math.degrees(math.atan(2.0 * float(aspect)))


def facet_polygons(surface: Surface) -> list[tuple[str, np.ndarray]]:
    """The facets of one period as planar convex polygons.

    Parameters
    ----------
    surface : Surface
        See module docstring.

    Returns
    -------
    list of (name, vertices)
        ``vertices`` is an ``(n, 3)`` float array, counter-clockwise seen from
        above (from outside the solid), ``n`` = 3 or 4. Facets of zero area are
        left out: the plate is a single ``top`` square at ``z = 0``; the full
        pyramid (``t = 1``) has no top and four triangular sides. A random tile
        (:class:`roughlight.surfaces.roughness.RandomSurface`) returns its own facets,
        each named after its cell and side (or its heightfield triangle).
    """
    if not isinstance(surface, Surface):
        return [(name, np.array(verts, float)) for name, verts in surface.polygons]
    if surface.is_plate:
        return [("top", np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float))]
    t = surface.truncation
    height = surface.height
    lo = 0.5 - 0.5 * (1.0 - t)
    hi = 0.5 + 0.5 * (1.0 - t)
    b00, b10, b11, b01 = (0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)
    t00, t10, t11, t01 = (lo, lo, height), (hi, lo, height), (hi, hi, height), (lo, hi, height)
    quads = {
        "top": [t00, t10, t11, t01],
        "east": [b10, b11, t11, t10],
        "west": [b01, b00, t00, t01],
        "north": [b11, b01, t01, t11],
        "south": [b00, b10, t10, t00],
    }
    facets = []
    for name in FACET_NAMES:
        verts = np.array(quads[name], float)
        if 1.0 - t < LENGTH_EPS:
            if name == "top":
                continue
            # the two top corners coincide at the apex: keep a triangle
            verts = verts[:3]
        facets.append((name, verts))
    return facets


def period_triangles(surface: Surface) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Triangles of one period with their true face normals.

    Returns
    -------
    triangles : (n, 3, 3) float array
        Vertex positions, counter-clockwise seen from outside.
    normals : (n, 3) float array
        Unit face normals (z > 0 for every facet of this heightfield).
    names : list of str
        The facet each triangle belongs to.
    """
    tris, names = [], []
    for name, verts in facet_polygons(surface):
        for k in range(1, len(verts) - 1):
            tris.append(verts[[0, k, k + 1]])
            names.append(name)
    tris = np.asarray(tris, float)
    normals = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return tris, normals, names


def period_mesh(surface: Surface):
    """One period as a :class:`trimesh.Trimesh` with unshared vertices.

    Each triangle has its own three vertices, so per-vertex normals equal the
    face normal (flat facets). ``process=False`` keeps trimesh from merging
    vertices.
    """
    import trimesh

    tris, normals, _ = period_triangles(surface)
    vertices = tris.reshape(-1, 3)
    faces = np.arange(len(vertices)).reshape(-1, 3)
    mesh = trimesh.Trimesh(
        vertices=vertices,
        faces=faces,
        face_normals=normals,
        vertex_normals=np.repeat(normals, 3, axis=0),
        process=False,
    )
    return mesh


def control_mesh():
    """The control: the flat plate, one period of the ``z = 0`` plane."""
    return period_mesh(PLATE)


def facet_areas(surface: Surface) -> dict[str, float]:
    """True (not projected) area of each facet of one period, by name."""
    areas: dict[str, float] = {}
    tris, _, names = period_triangles(surface)
    cross = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    for name, area in zip(names, 0.5 * np.linalg.norm(cross, axis=1)):
        areas[name] = areas.get(name, 0.0) + float(area)
    return areas


def export_mesh_atomic(mesh, path) -> None:
    """Write a mesh (format from the file's extension, e.g. ``.ply``) under a temporary name, then rename."""
    from ..atomic import atomic_path

    with atomic_path(path) as tmp:
        mesh.export(tmp)


# ---------------------------------------------------------------------------
# facets and the directions they mirror the light to
def lobe_centres(incidence: float, aspect: float) -> dict:
    """Predicted elevations (phi = 0 arc) of the facets' mirror directions.

    Parameters
    ----------
    incidence : float
        Light elevation ``i``, degrees.
    aspect : float
        Pyramid height / period (sets the side tilt ``s = atan(2 aspect)``).

    Returns
    -------
    dict
        ``forward``: ``180 - i`` (top facet / plate); ``back``: ``180 - 2s - i``
        (the side facet facing the light), None when it leaves [0, 180] or the
        aspect is 0 (no side facets); ``west``: ``180 + 2s - i`` when it lies
        below 180 (only while ``2 s < i``), else None. Degrees.
    """
    i = float(incidence)
    s = side_slope_deg(aspect)
    out = {"forward": 180.0 - i, "back": None, "west": None}
    if float(aspect) > 0:
        back = 180.0 - 2.0 * s - i
        out["back"] = back if 0.0 < back < 180.0 else None
        west = 180.0 + 2.0 * s - i
        out["west"] = west if west < 180.0 else None
    return out


def facets(truncation: float, aspect: float) -> list[tuple[str, np.ndarray, float]]:
    """The facets of one period with their unit normal and plan (x-y projected) area.

    Returns
    -------
    list of (name, normal (3,) array, plan_area float); plan areas sum to 1.
    """
    surface = Surface(truncation, aspect)
    areas = facet_areas(surface)
    _, normals, names = period_triangles(surface)
    out = []
    for name, true_area in areas.items():
        n = normals[names.index(name)]
        out.append((name, np.asarray(n, float), float(true_area * n[2])))
    return out
