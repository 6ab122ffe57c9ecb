"""The periodic field Mitsuba renders and the detector that looks at it, in numpy (no Mitsuba).

The capture window
------------------
The exact reference's value of a view is the mean over one period of the view's oblique base-plane coordinates
``(s, u) = (x - z Vx/Vz, y - z Vy/Vz)``, where every view ray crosses ``z = 0`` (render/exact/reference.py); the
fast method draws one such period. Here the detector is an orthographic camera whose to-world transform is sheared
so that its film maps onto the square ``[-K/2, K/2]^2`` of that plane, ``K`` = ``periods`` whole periods (a random
tile's period is the tile): each pixel is the same area of the base plane, and the image mean is the periodic
surface's mean, as in the reference, whatever the view. Rays start above the field's highest point and run along
``-V``.

The field
---------
A finite patch of the periodic surface stands in for the infinite one. A ray of the window can meet the surface
only between ``z = H`` (the highest point) and ``z = 0``, that is within ``H (Vx/Vz, Vy/Vz)`` of its base point,
and the point it meets can be shadowed only by facets within ``H (Lx/Lz, Ly/Lz)`` of it, toward the light. A
field holds every period that can matter to any of its views (the convex hull of those offsets around the window,
one period more all round), so no ray of the window ever sees an edge or the light ever slips under one.

Over a whole sweep that hull is a disc of radius ``H cot e`` for the lowest elevation ``e`` (57 heights at 1
degree): 3,200 periods for t 0.5, a 1, but 3 million triangles for a tall random heightfield tile. A sweep whose
one field would pass :data:`FIELD_BUDGET` triangles is split by azimuth (:func:`view_groups`): one half great
circle of the orbit needs only a strip along its azimuth, so each group of neighbouring azimuths gets a field of
its own, within the budget.
"""

from __future__ import annotations

import numpy as np

from ...surfaces import geometry

__all__ = ["MAX_TRIANGLES", "FIELD_BUDGET", "MARGIN", "tile_triangles", "surface_height", "field_cells",
           "view_groups", "field_triangles", "sensor_matrix"]

#: The most triangles a field may hold: Mitsuba with its BVH takes about 400 bytes a triangle (a field of 395,000
#: triangles peaked at 250 MB in all), so 800 MB.
MAX_TRIANGLES = 2_000_000
#: Triangles a sweep's field may hold before its views are split by azimuth (:func:`view_groups`).
FIELD_BUDGET = 400_000
#: Periods added all round the field (floating point, and the pixels' sample positions).
MARGIN = 1.0
#: Height above the field's top where the rays start.
CLEARANCE = 1.0


def tile_triangles(surface) -> np.ndarray:
    """One period's facets (a random tile's: the tile's) as triangles, ``(n, 3, 3)``, counter-clockwise seen from
    above (normals up; :func:`roughlight.surfaces.geometry.facet_polygons`), each convex facet fanned."""
    triangles = [verts[[0, k, k + 1]] for _, verts in geometry.facet_polygons(surface)
                 for k in range(1, len(verts) - 1)]
    return np.asarray(triangles, float)


def surface_height(surface) -> float:
    """The highest point of the surface, periods (0 for the plate)."""
    return 0.0 if surface.is_plate else float(surface.height)


def field_cells(height: float, light_dir, view_dirs, periods: int, lit: bool = True) -> np.ndarray:
    """The periods ``(i, j)`` (the cell ``[i, i+1] x [j, j+1]``) any of the views can see or be shadowed by.

    Parameters
    ----------
    height : float, the surface's highest point (periods)
    light_dir : (3,) unit vector toward the light
    view_dirs : (m, 3) unit vectors toward the detector, none grazing
    periods : int, side of the capture window ``[-periods/2, periods/2]^2``
    lit : bool, whether any light reaches the surface (else no shadow margin)

    Returns
    -------
    (n, 2) int array of the cells' lower corners.
    """
    import shapely

    views = np.atleast_2d(np.asarray(view_dirs, float))
    half = 0.5 * float(periods)
    window = np.array([[-half, -half], [half, -half], [half, half], [-half, half]])
    reach = np.vstack([[0.0, 0.0], height * views[:, :2] / views[:, 2:3]])
    light = np.asarray(light_dir, float)
    shadow = np.array([[0.0, 0.0]] + ([height * light[:2] / light[2]] if lit and height > 0 else []))
    points = (window[:, None, None, :] + reach[None, :, None, :] + shadow[None, None, :, :]).reshape(-1, 2)
    hull = shapely.MultiPoint(points).convex_hull.buffer(MARGIN)
    x0, y0, x1, y1 = hull.bounds
    i, j = np.meshgrid(np.arange(np.floor(x0), np.ceil(x1)), np.arange(np.floor(y0), np.ceil(y1)), indexing="ij")
    i, j = i.ravel(), j.ravel()
    keep = shapely.intersects(hull, shapely.box(i, j, i + 1, j + 1))
    return np.column_stack([i[keep], j[keep]]).astype(np.int64)


def view_groups(triangles: int, height: float, light_dir, view_dirs, periods: int, lit: bool = True,
                budget: int = FIELD_BUDGET) -> list[tuple[np.ndarray, np.ndarray]]:
    """The sweep's views in groups, each with the cells of its own field (:func:`field_cells`).

    One group of all the views when their field holds at most ``budget`` triangles (``triangles`` a period);
    else the views by azimuth (modulo 180 degrees: a half great circle of the orbit), neighbouring azimuths
    together while their field stays within the budget.

    Returns
    -------
    list of (indices into ``view_dirs``, (n, 2) cells)
    """
    views = np.atleast_2d(np.asarray(view_dirs, float))

    def cells(index):
        return field_cells(height, light_dir, views[index], periods, lit)

    everything = np.arange(len(views))
    whole = cells(everything)
    if len(whole) * triangles <= budget:
        return [(everything, whole)]
    azimuth = np.round(np.degrees(np.arctan2(views[:, 1], views[:, 0])) % 180.0, 6) % 180.0
    groups, current, current_cells = [], None, None
    for value in np.unique(azimuth):
        members = np.flatnonzero(azimuth == value)
        if current is not None:
            joined = np.concatenate([current, members])
            joined_cells = cells(joined)
            if len(joined_cells) * triangles <= budget:
                current, current_cells = joined, joined_cells
                continue
            groups.append((current, current_cells))
        current, current_cells = members, cells(members)
    groups.append((current, current_cells))
    return groups


def field_triangles(tile: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """The tile's triangles copied to every cell, ``(len(cells) * n, 3, 3)`` float32; ValueError beyond
    :data:`MAX_TRIANGLES`."""
    count = len(tile) * len(cells)
    if count > MAX_TRIANGLES:
        raise ValueError(f"the mitsuba method's field would hold {count:,} triangles ({len(cells):,} periods), "
                         f"more than {MAX_TRIANGLES:,}: views or a light this close to grazing on so tall a surface "
                         f"need a wider field than it renders; measure them with the reference or fast method")
    shifts = np.zeros((len(cells), 1, 1, 3))
    shifts[:, 0, 0, :2] = cells
    return (tile[None] + shifts).reshape(-1, 3, 3).astype(np.float32)


def sensor_matrix(view_dir, periods: int, height: float) -> tuple[np.ndarray, float]:
    """The orthographic detector's to-world transform for the view ``view_dir`` and its far clip.

    Mitsuba's orthographic camera sends the film point ``(x, y)`` of ``[-1, 1]^2`` from ``to_world (x, y, near)``
    along ``to_world (0, 0, 1)``. Columns ``(K/2, 0, 0)``, ``(0, K/2, 0)`` and ``-V``, and the origin
    ``T V`` with ``T V_z = height + CLEARANCE``, make that ray cross ``z = 0`` at ``(x K/2, y K/2)``: the film is the
    window ``[-K/2, K/2]^2`` of the oblique base plane, and every ray starts above the surface.

    Returns
    -------
    matrix : (4, 4) float array
    far_clip : float, beyond ``z = 0`` along every ray
    """
    v = np.asarray(view_dir, float)
    start = (float(height) + CLEARANCE) / v[2]
    matrix = np.eye(4)
    matrix[:3, 0] = [0.5 * periods, 0.0, 0.0]
    matrix[:3, 1] = [0.0, 0.5 * periods, 0.0]
    matrix[:3, 2] = -v
    matrix[:3, 3] = start * v
    return matrix, 2.0 * start + 10.0
