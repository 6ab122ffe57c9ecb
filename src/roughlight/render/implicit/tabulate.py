"""A regular surface's table of facet shares measured by the exact reference, and kept: the ``implicit_table``
model's table, built the first time a surface asks for it.

:func:`measure_table` clips each row of view nodes once for all the light nodes, in C
(:func:`roughlight.render.exact.pyramid.shares_under_lights`: the exact reference's shares to about 1e-11)
and stores the shares as a :class:`~roughlight.render.implicit.table.ShareTable`; :func:`tabulate_surface` takes the
default nodes (:data:`TABLE`, or ``export.table``'s); :func:`cached_table` builds a surface's table once and keeps it
on disk (:func:`cache_dir`), named by the surface and the nodes (:func:`table_key`), for every later sweep.

Angles in degrees: incidence above the plane, azimuths from the lattice's x axis (:mod:`roughlight.render.shading`).
"""

from __future__ import annotations

import hashlib
import json
import logging
import math
import os
from pathlib import Path

import numpy as np

from ...surfaces.geometry import FACET_NAMES
from ...surfaces.roughness import kind_and_seed
from ...surfaces.surface import Surface
from ..exact.pyramid import shares_under_lights
from ..exact.reference import shares_under
from .table import CHANNELS, SCALE, ShareTable, light_rows, load_table, save_table

__all__ = ["TABLE", "incidence_nodes", "elevation_nodes", "row_azimuths", "channel_shares", "measure_table",
           "tabulate_surface", "cache_dir", "table_key", "cached_table"]

LOG = logging.getLogger("roughlight.implicit")

#: The share table's nodes by default (``export.table``, the schema's defaults): light incidence every 5 degrees
#: (and, with ``edge_on``, where a side facet turns edge-on to a light at azimuth 0 or 45: :func:`incidence_nodes`),
#: light azimuth every 5 in [0, 45] for every incidence row (``light_azimuth_steps`` gives low rows closer ones:
#: :func:`row_azimuths`), view elevations closer near the horizon, where the shares change fastest (and, with
#: ``hot_spot_views``, at every incidence node: :func:`elevation_nodes`), and view azimuth every 2.5. Light azimuth
#: nodes 5 degrees apart where they were 15 took the export's check from 6.62 levels to 2.51 at its worst view; the
#: edge-on incidences of every one of them would double the texture for no gain off the nodes, so only the
#: lattice's axis (the study's light) and its diagonal have them; closer nodes everywhere (``config/export_fine.yaml``)
#: cost five times the texture for a worst view of 1.75 (docs/export.md, "Light azimuth nodes").
TABLE = {"incidence": [float(i) for i in range(0, 91, 5)], "edge_on": [0.0, 45.0], "hot_spot_views": True,
         "light_azimuth": [float(p) for p in range(0, 46, 5)], "light_azimuth_steps": [],
         "elevation": [1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 10.0, 12.0, 14.0, 16.0, 19.0, 22.0, 25.0,
                       28.0, 32.0, 36.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0, 90.0],
         "azimuth_step": 2.5}


def incidence_nodes(surface: Surface, incidence, light_azimuth, edge_on=True) -> np.ndarray:
    """The table's light incidence nodes: ``incidence`` and the incidences at which a side facet turns edge-on to a
    light at an azimuth of ``edge_on``, ``atan(2 a |cos psi|)`` (east and west) and ``atan(2 a |sin psi|)`` (north
    and south), degrees. ``edge_on`` is a list of light azimuths (degrees), or ``True`` for every one of
    ``light_azimuth``, ``False`` for none. There a facet's lit share starts or stops (and the shadows it casts with
    it): a kink no linear interpolation between nodes either side can follow (on the full pyramid at incidence 63.1,
    with nodes every 5 degrees, the mean error over the views was 0.29 of a level without the node at 63.4 and 0.04
    with it)."""
    nodes = {float(i) for i in incidence}
    azimuths = light_azimuth if edge_on is True else (edge_on or [])
    if not surface.is_plate:
        for psi in np.radians(np.asarray(azimuths, float)):
            for part in (abs(math.cos(psi)), abs(math.sin(psi))):
                edge = round(math.degrees(math.atan(2.0 * surface.aspect * part)), 6)
                if 0.0 < edge < 90.0:
                    nodes.add(edge)
    return np.array(sorted(nodes))


def elevation_nodes(elevation, incidence, hot_spot_views: bool = True) -> np.ndarray:
    """The table's view elevation nodes: ``elevation`` and, with ``hot_spot_views``, every light incidence node in
    (0, 90] (``incidence``, :func:`incidence_nodes`' with the edge-on ones), so that each tabulated light's hot
    spot ``V = L`` (the view at the light's elevation and azimuth, a cusp of the shares: no shadow is seen there)
    lies on a view node, and between light nodes the table's turned reading of the hot spot
    (:func:`roughlight.render.implicit.table.table_shares`) reads every node's own there. On t 1, a 1 at the
    study's light (incidence 30, on the nodes), the worst of its 6,444 views went from 3.05 levels at the hot spot to
    1.13 elsewhere (docs/export.md, "Resolution"), for 8 nodes more (39), 22% more time and 2.1 MB more texture."""
    nodes = {float(e) for e in elevation}
    if hot_spot_views:
        nodes |= {float(i) for i in incidence if 0.0 < float(i) <= 90.0}
    return np.array(sorted(nodes))


def channel_shares(scenes, elevation: float, azimuth: float) -> np.ndarray:
    """The exact reference's shares of one view under each of several lights of one surface
    (:func:`roughlight.render.exact.shares_under`), as a table's node holds them: ``(len(scenes), CHANNELS)``, each
    facet's lit share then its shadowed share, in :data:`roughlight.surfaces.geometry.FACET_NAMES`' order (a facet
    the surface lacks, 0: the full pyramid has no top, the plate only one)."""
    lit, shadow = shares_under(scenes, float(elevation), float(azimuth))
    where = [FACET_NAMES.index(name) for name in scenes[0].surf.names]
    out = np.zeros((len(scenes), CHANNELS))
    out[:, where] = lit
    out[:, [5 + f for f in where]] = shadow
    return out


def measure_table(surface: Surface, incidence, light_azimuth, elevation, azimuth_step: float, shadows: bool = True,
                  log=None) -> ShareTable:
    """The exact reference's facet shares at every node of a share table.

    Parameters
    ----------
    surface : Surface
        A regular surface (truncated square pyramids, or the plate).
    incidence, elevation : sequences of float
        The light incidence and view elevation nodes, degrees (:class:`~roughlight.render.implicit.table.ShareTable`).
    light_azimuth : sequence of float, or one such sequence for each incidence node
        The light azimuth nodes, degrees: of every incidence row, or each row's own.
    azimuth_step : float
        Degrees between view azimuth nodes; divides 360.
    shadows : bool
        Whether the surface casts shadows.
    log : callable, optional
        Takes a progress line (every tenth of the view nodes).

    Returns
    -------
    ShareTable
    """
    nodes = 360.0 / float(azimuth_step)
    if not float(azimuth_step) > 0 or abs(nodes - round(nodes)) > 1e-9:
        raise ValueError(f"export.table.azimuth_step must divide 360 degrees, got {azimuth_step!r}")
    n_azimuth = int(round(nodes))
    elevation = np.asarray(elevation, float)
    lights = sum(row.size for row in light_rows(np.size(incidence), light_azimuth))
    # the table checks its nodes before any clipping; its shares are filled in place, a row of view nodes at a time
    table = ShareTable(surface.truncation, surface.aspect, bool(shadows), incidence, light_azimuth, elevation,
                       n_azimuth, np.zeros((lights, elevation.size, n_azimuth, CHANNELS), np.uint16))
    log = log or (lambda message: None)
    light_nodes = list(zip(table.slice_incidence.tolist(), table.slice_azimuth.tolist()))
    azimuth = np.arange(n_azimuth) * float(azimuth_step)
    for k in range(elevation.size):  # a row of view nodes at a time, every light at once (in C)
        lit, shadow = shares_under_lights(surface, light_nodes, np.full(n_azimuth, elevation[k]), azimuth,
                                          bool(shadows))
        row = np.concatenate([lit, shadow], axis=2)  # (lights, azimuths, CHANNELS): lit shares, then shadowed
        table.shares[:, k] = np.round(np.clip(row, 0.0, 1.0) * SCALE).astype(np.uint16)
        if (k + 1) % max(1, elevation.size // 10) == 0:
            log(f"share table t {surface.truncation:g}, a {surface.aspect:g}: {(k + 1) * n_azimuth}/"
                f"{elevation.size * n_azimuth} view nodes")
    return table


def row_azimuths(incidence, light_azimuth, steps=()) -> list[np.ndarray]:
    """Each incidence row's light azimuth nodes, degrees: a row at or below the incidence of a pair of ``steps``
    (``[incidence, step]``, ascending; the first that holds) takes nodes every ``step`` degrees over [0, 45] (the
    step dividing 45), a row above every pair ``light_azimuth``. Low lights need them closer: their long shadows
    sweep across the facets as the light turns (docs/export.md, "Light azimuth nodes")."""
    rows = []
    for i in np.asarray(incidence, float):
        step = next((float(s) for up_to, s in steps if i <= float(up_to) + 1e-9), None)
        if step is not None and (not step > 0 or abs(45.0 / step - round(45.0 / step)) > 1e-9):
            raise ValueError(f"export.table.light_azimuth_steps: a step must divide 45 degrees, got {step!r}")
        rows.append(np.asarray(light_azimuth, float) if step is None else np.arange(round(45.0 / step) + 1) * step)
    return rows


def tabulate_surface(surface: Surface, nodes=None, shadows: bool = True, log=None) -> ShareTable:
    """A surface's share table at the nodes ``nodes`` (``export.table``'s keys over :data:`TABLE`): the incidences
    with their edge-on ones (:func:`incidence_nodes`), each row's light azimuths (:func:`row_azimuths`), the
    elevations with the incidences (:func:`elevation_nodes`, ``hot_spot_views``; a ``nodes`` without the key, as
    one that replaces :data:`TABLE` whole, has none), measured by :func:`measure_table`."""
    nodes = {**TABLE, **(nodes or {})}
    incidence = incidence_nodes(surface, nodes["incidence"], nodes["light_azimuth"], nodes["edge_on"])
    elevation = elevation_nodes(nodes["elevation"], incidence, nodes.get("hot_spot_views", False))
    rows = row_azimuths(incidence, nodes["light_azimuth"], nodes.get("light_azimuth_steps", ()))
    return measure_table(surface, incidence, rows, elevation, nodes["azimuth_step"], shadows, log)



def cache_dir() -> Path:
    """Where built share tables are kept: ``ROUGHLIGHT_TABLE_CACHE`` if set; in a workflow's directory (it holds a
    ``Snakefile``) ``results/cache/share_tables``; else ``$XDG_CACHE_HOME/roughlight/share_tables`` (``~/.cache``
    when unset). Made when first written."""
    if os.environ.get("ROUGHLIGHT_TABLE_CACHE"):
        return Path(os.environ["ROUGHLIGHT_TABLE_CACHE"])
    if Path("Snakefile").is_file():
        return Path("results") / "cache" / "share_tables"
    home = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(home) / "roughlight" / "share_tables"


def table_key(surface: Surface, nodes=None, shadows: bool = True) -> str:
    """The file name of ``surface``'s table at ``nodes`` (``export.table``'s keys over :data:`TABLE`) with or
    without ``shadows``: ``t{t}_a{a}_{shadows}_{digest}.npz``, the digest of the surface, the nodes and the table's
    storage (:data:`SCALE`, :data:`CHANNELS`), so that other settings never read this table."""
    nodes = {**TABLE, **(nodes or {})}
    what = {"truncation": float(surface.truncation), "aspect": float(surface.aspect), "shadows": bool(shadows),
            "nodes": {k: nodes[k] for k in sorted(nodes)}, "scale": SCALE, "channels": CHANNELS}
    digest = hashlib.sha256(json.dumps(what, sort_keys=True, default=float).encode()).hexdigest()[:16]
    return f"t{surface.truncation:g}_a{surface.aspect:g}_{'shadows' if shadows else 'lit'}_{digest}.npz"


def cached_table(surface: Surface, nodes=None, shadows: bool = True, folder=None) -> ShareTable:
    """``surface``'s share table at ``nodes`` (default :data:`TABLE`), read from ``folder`` (default
    :func:`cache_dir`) or, the first time, measured there (:func:`tabulate_surface`: about 3 s at the
    default nodes on one core, its progress logged to the ``roughlight.implicit`` logger) and written atomically.

    Raises ValueError for a surface that has no table: a random tile (no symmetry, no facets named as a pyramid's).
    """
    if kind_and_seed(surface)[0] != "pyramids":
        raise ValueError(f"the implicit table model tabulates regular surfaces (truncated square pyramids), not "
                         f"{surface!r}: a random tile has no share table; measure it with render.method fast")
    path = Path(folder or cache_dir()) / table_key(surface, nodes, shadows)
    if path.is_file():
        return load_table(path)
    LOG.info("share table of t %g, a %g: measuring it once (kept at %s)", surface.truncation, surface.aspect, path)
    table = tabulate_surface(surface, nodes, shadows, log=LOG.info)
    path.parent.mkdir(parents=True, exist_ok=True)
    save_table(path, table)
    return table
