"""Ways to read the share table between its light azimuth nodes, tried against each other (docs/export.md,
"Resolution": the light's azimuth at low incidence holds the table off a level):

* ``linear``: multilinear between the nodes, the view in the lattice's frame (the table's reading before the hot
  spot's);
* ``turned``: each light node's shares read at the view turned with the light (the view's azimuth relative to the
  light kept, not to the lattice), so that a hot spot or a shadow's direction stays where the light puts it;
* ``cubic``: a Catmull-Rom cubic through four light azimuth nodes (the ends mirrored: the shares are even about
  0 and 45 degrees), in place of the line through two;
* ``hot spot``: the table's own (``table_shares``): linear, with the shadowed part read turned near ``V = L``
  (``--blend``: within how many degrees of it).

    python tests/table_light_reading.py results/export/t1_a1             # 8 low lights (8-35 degrees) x 200 views
    python tests/table_light_reading.py results/export/t1_a1 --seed 11   # other lights and views
    python tests/table_light_reading.py results/export/t1_a1 --check     # the export's own 1,200 lights and views
    python tests/table_light_reading.py results/export/t1_a1 --blend 30  # the hot spot's reading 30 degrees wide

Reads the export's ``shares.npz`` (and, with ``--check``, its ``check.parquet``, whose reference values it takes);
else draws the lights (incidence uniform in [8, 35], any azimuth) and views (``brdf_export.check_views``) with the
seed and takes the exact reference's values. Prints each reading's total error against the reference.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd

from roughlight.measurements import brdf_export as B
from roughlight.render import methods, shading
from roughlight.render.implicit import load_table
from roughlight.render.implicit import table as T
from roughlight.render.implicit.model import facet_normals
from roughlight.surfaces.symmetry import canonical_directions


def azimuth_weights(nodes, psi, reading: str) -> np.ndarray:
    """(n, nodes) weights of each light azimuth node at ``psi`` (degrees, the table's turned azimuths)."""
    n = len(nodes)
    lower, t = T.node_weights(nodes, psi)
    weights = np.zeros((len(psi), n))
    rows = np.arange(len(psi))
    if reading != "cubic":
        weights[rows, lower] += 1.0 - t
        weights[rows, np.minimum(lower + 1, n - 1)] += t
        return weights
    terms = [(-t ** 3 + 2 * t ** 2 - t) / 2, (3 * t ** 3 - 5 * t ** 2 + 2) / 2, (-3 * t ** 3 + 4 * t ** 2 + t) / 2,
             (t ** 3 - t ** 2) / 2]
    for shift, term in zip((-1, 0, 1, 2), terms):
        node = lower + shift
        node = np.where(node < 0, -node, node)  # mirrored about the first node
        node = np.where(node > n - 1, 2 * (n - 1) - node, node)  # and about the last
        np.add.at(weights, (rows, node), term)
    return weights


def read(table, light, view, lighting, reading: str) -> np.ndarray:
    """The table's total at (light, view) pairs ((n, 3) each), its light azimuths read the ``reading`` way."""
    light_c, view_c = canonical_directions(table.surface, light, view)
    incidence, psi, elevation, phi = T.table_angles(light_c, view_c)
    i0, wi = T.node_weights(table.incidence, incidence)
    e0, we = T.node_weights(table.elevation, elevation)
    by_node = azimuth_weights(table.light_azimuth, psi, reading)
    step, shares = table.azimuth_step, np.zeros((len(light_c), T.CHANNELS))
    for di, fi in ((0, 1.0 - wi), (1, wi)):
        ii = np.minimum(i0 + di, table.incidence.size - 1)
        for p, node_psi in enumerate(table.light_azimuth):
            turned = np.mod(phi - psi + node_psi, 360.0) if reading == "turned" else phi
            a0, wa = np.floor(turned / step).astype(int) % table.azimuth_nodes, turned / step - np.floor(turned / step)
            for de, fe in ((0, 1.0 - we), (1, we)):
                for da, fa in ((0, 1.0 - wa), (1, wa)):
                    node = table.shares[ii, p, np.minimum(e0 + de, table.elevation.size - 1),
                                        (a0 + da) % table.azimuth_nodes]
                    shares += (fi * by_node[:, p] * fe * fa)[:, None] * node
    shares = np.clip(shares / T.SCALE, 0.0, 1.0)
    return shading.facet_sum(facet_normals(table.surface), light_c[:, None, :], view_c, shares[:, :5],
                             shares[:, 5:], lighting, True)["total"]


def hot_spot(table, light, view, lighting, blend: float) -> np.ndarray:
    """The table's own reading (``table_shares``) at a hot spot's width ``blend``: the total."""
    lit, shadow, light_c, view_c = T.table_shares(table, light, view, hot_spot_blend=blend)
    return shading.facet_sum(facet_normals(table.surface), light_c[:, None, :], view_c, lit, shadow, lighting,
                             True)["total"]


def pairs(table, export: Path, check: bool, seed: int, lighting):
    """(light, view, reference total) of the check's pairs or of low lights of one's own."""
    if check:
        rows = pd.read_parquet(export / "check.parquet")
        rows = rows[(rows["method"] == "implicit_table") & (rows["component"] == "total")]
        light = np.array([shading.light_direction(i, p) for i, p in zip(rows["incidence"], rows["light_azimuth"])])
        return light, shading.view_direction(rows["elevation"].to_numpy(), rows["azimuth"].to_numpy()), \
            rows["reference"].to_numpy()
    rng = np.random.default_rng(seed)
    azimuth, elevation = B.check_views(table, 200, seed)
    view = shading.view_direction(elevation, azimuth)
    lights, views, reference = [], [], []
    for _ in range(8):
        incidence, psi = round(float(rng.uniform(8.0, 35.0)), 2), round(float(rng.uniform(0.0, 360.0)), 2)
        exact = methods.sweep("reference", table.surface, incidence, azimuth, elevation, lighting, light_azimuth=psi)
        lights.append(np.broadcast_to(shading.light_direction(incidence, psi), view.shape))
        views.append(view)
        reference.append(exact["total"])
    return np.concatenate(lights), np.concatenate(views), np.concatenate(reference)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("export", type=Path, help="a finished run's export folder (shares.npz, check.parquet)")
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--check", action="store_true", help="the export's own checked lights and views")
    parser.add_argument("--blend", type=float, default=T.HOT_SPOT_BLEND, help="the hot spot's reading's width, degrees")
    args = parser.parse_args(argv)
    table = load_table(args.export / "shares.npz")
    lighting = replace(shading.Lighting(), ambient=0.0)
    light, view, reference = pairs(table, args.export, args.check, args.seed, lighting)
    print("| reading | MAE | p99 | worst | views over a level |\n|---|---|---|---|---|")
    for reading in ("linear", "turned", "cubic", "hot spot"):
        values = (hot_spot(table, light, view, lighting, args.blend) if reading == "hot spot"
                  else read(table, light, view, lighting, reading))
        error = np.abs(values - reference)
        print(f"| {reading} | {error.mean():.3f} | {np.quantile(error, 0.99):.2f} | {error.max():.2f} | "
              f"{int((error > 1).sum())} of {len(error)} |")


if __name__ == "__main__":
    main()
