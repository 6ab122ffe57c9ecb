"""A trial of the share table with light azimuth nodes that differ by incidence (docs/export.md, "Resolution"):
close where the light is low, as ``tests/table_light_spacing.py`` says they must be, and the default's above. The
table's format holds one list of azimuth nodes for every incidence, so the trial measures and reads its own, in
numpy, and checks it at the export's own lights and views.

    python tests/table_light_nodes_trial.py results/export/t1_a1     # a finished run's export of t 1, a 1
    python tests/table_light_nodes_trial.py results/export/t1_a1 --spacing 35:5 50:5   # 5-degree nodes below 50
    python tests/table_light_nodes_trial.py results/export/t1_a1 --lights 40 --views 30  # its own lights and views

Takes the export's ``shares.npz`` (its incidence and view nodes) and ``check.parquet`` (the 1,200 lights and views
drawn off every node, with the exact reference's values), or, with ``--lights``, draws its own as the check draws
them (``brdf_export.check_lights`` and ``check_views``, seeded, off every node) and takes the exact reference's
values; measures the exact reference's shares at the trial's nodes (:func:`roughlight.render.exact.shares_under`;
under a minute); reads each pair multilinearly as ``table_values`` does, but between the azimuth nodes of each
incidence row; prints the default table's errors beside the trial's, and the trial's size and time.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import pandas as pd

from roughlight.render import shading
from roughlight.render.exact.reference import LitScene
from roughlight.render.implicit import channel_shares, load_table
from roughlight.render.implicit import table as T
from roughlight.render.implicit.model import facet_normals
from roughlight.surfaces.symmetry import canonical_directions

#: The trial's light azimuth spacing by incidence, degrees: (up to this incidence, spacing), the first that holds;
#: the default's 15 above the last.
SPACING = ((35.0, 1.5), (50.0, 5.0))


def azimuth_nodes(incidence: float, spacing=SPACING) -> np.ndarray:
    """The trial's light azimuth nodes at one incidence node, degrees over [0, 45]: 1.5 apart below incidence 35,
    5 up to 50 (both ends), 15 above (:data:`SPACING`)."""
    step = next((s for up_to, s in spacing if incidence < up_to or (incidence == up_to and up_to == spacing[-1][0])),
                15.0)
    return np.arange(0.0, 45.0 + 1e-9, step)


def measure(surface, incidence, elevation, azimuth_nodes_: int, azimuth_step: float, spacing=SPACING, log=print):
    """The exact reference's shares at every (incidence row, its azimuth node) light and every view node:
    ``(lights, E, A, 10)`` float32, and each row's nodes."""
    rows = [azimuth_nodes(i, spacing) for i in incidence]
    scenes = [LitScene(surface, float(i), True, float(p)) for i, nodes in zip(incidence, rows) for p in nodes]
    shares = np.zeros((len(scenes), elevation.size, azimuth_nodes_, 10), np.float32)
    for k, e in enumerate(elevation):
        for a in range(azimuth_nodes_):
            shares[:, k, a] = channel_shares(scenes, e, a * azimuth_step)
        log(f"elevation node {k + 1}/{elevation.size}")
    return shares, rows


def read(shares, rows, incidence, elevation, azimuth_nodes_: int, azimuth_step: float, light, view) -> np.ndarray:
    """Each pair's shares, (n, 10): multilinear in incidence, in the azimuth nodes of each incidence row, and in the
    view's elevation and azimuth (the pairs turned to the table's azimuths first)."""
    offsets = np.cumsum([0] + [len(r) for r in rows])
    incidence_, psi, e, phi = T.table_angles(light, view)
    i0, wi = T.node_weights(incidence, incidence_)
    e0, we = T.node_weights(elevation, e)
    a0 = np.floor(phi / azimuth_step).astype(int) % azimuth_nodes_
    wa = phi / azimuth_step - np.floor(phi / azimuth_step)
    out = np.zeros((len(light), 10))
    for k in range(len(light)):
        for di, fi in ((0, 1.0 - wi[k]), (1, wi[k])):
            row = min(i0[k] + di, incidence.size - 1)
            p0, wp = T.node_weights(rows[row], [psi[k]])
            for dp, fp in ((0, 1.0 - wp[0]), (1, wp[0])):
                at = offsets[row] + min(p0[0] + dp, rows[row].size - 1)
                for de, fe in ((0, 1.0 - we[k]), (1, we[k])):
                    for da, fa in ((0, 1.0 - wa[k]), (1, wa[k])):
                        out[k] += fi * fp * fe * fa * shares[at, min(e0[k] + de, elevation.size - 1),
                                                             (a0[k] + da) % azimuth_nodes_]
    return out


def drawn_pairs(table, lights: int, views: int, seed: int) -> pd.DataFrame:
    """``lights`` x ``views`` pairs drawn off every node as the export's check draws them, each with the exact
    reference's total (:func:`roughlight.measurements.comparison.reference`) and the default table's
    (``table_values``), as the check's rows hold them (``value``, ``reference``)."""
    from roughlight.measurements import brdf_export, comparison

    lighting, parts = shading.Lighting(), []
    azimuth, elevation = brdf_export.check_views(table, views, seed)
    for incidence, psi in brdf_export.check_lights(table, lights, seed):
        reference = comparison.reference(table.surface, incidence, azimuth, elevation, lighting, light_azimuth=psi)
        light = np.broadcast_to(shading.light_direction(incidence, psi), (views, 3))
        view = np.stack([shading.view_direction(e, a) for e, a in zip(elevation, azimuth)])
        value = T.table_values(table, light, view, lighting)["total"]
        parts.append(pd.DataFrame({"incidence": incidence, "light_azimuth": psi, "elevation": elevation,
                                   "azimuth": azimuth, "value": value, "reference": reference["total"]}))
    return pd.concat(parts, ignore_index=True)


def errors_line(name: str, error: np.ndarray, rows: pd.DataFrame) -> str:
    k = int(np.argmax(error))
    return (f"{name}: MAE {error.mean():.3f}, p99 {np.percentile(error, 99):.2f}, worst {error.max():.2f} (light at "
            f"incidence {rows['incidence'][k]:.2f}, azimuth {rows['light_azimuth'][k]:.2f}; view at elevation "
            f"{rows['elevation'][k]:.2f}), views over a level {(error > 1.0).sum()} of {len(error)}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("export", type=Path, help="a finished export's folder (shares.npz, check.parquet)")
    parser.add_argument("--lights", type=int, default=0, help="draw this many lights (0: the export's check)")
    parser.add_argument("--views", type=int, default=30, help="views a drawn light")
    parser.add_argument("--seed", type=int, default=58, help="the drawn lights' and views' seed")
    parser.add_argument("--spacing", nargs="+", default=[f"{i:g}:{s:g}" for i, s in SPACING],
                        help="INCIDENCE:STEP pairs, ascending: azimuth nodes STEP degrees apart below INCIDENCE (the "
                             "last up to it), 15 above; STEP divides 45")
    args = parser.parse_args(argv)
    spacing = tuple((float(i), float(s)) for i, s in (pair.split(":") for pair in args.spacing))
    if any(abs(45.0 / s - round(45.0 / s)) > 1e-9 for _, s in spacing):
        parser.error(f"--spacing {args.spacing}: every STEP must divide 45 degrees")
    table = load_table(args.export / "shares.npz")
    if args.lights:
        rows = drawn_pairs(table, args.lights, args.views, args.seed)
    else:
        checked = pd.read_parquet(args.export / "check.parquet")
        rows = checked[(checked["method"] == "implicit_table")
                       & (checked["component"] == "total")].reset_index(drop=True)
    start = time.perf_counter()
    shares, nodes = measure(table.surface, table.incidence, table.elevation, table.azimuth_nodes, table.azimuth_step,
                            spacing, log=lambda message: None)
    seconds = time.perf_counter() - start
    light = np.stack([shading.light_direction(i, p) for i, p in zip(rows["incidence"], rows["light_azimuth"])])
    view = np.stack([shading.view_direction(e, a) for e, a in zip(rows["elevation"], rows["azimuth"])])
    light_c, view_c = canonical_directions(table.surface, light, view)
    got = read(shares, nodes, table.incidence, table.elevation, table.azimuth_nodes, table.azimuth_step, light_c,
               view_c)
    total = shading.facet_sum(facet_normals(table.surface), light_c[:, None, :], view_c, got[:, :5], got[:, 5:],
                              shading.Lighting())["total"]
    total = np.where(view[:, 2] > 0.0, total, 0.0)
    reference = rows["reference"].to_numpy(float)
    print(errors_line(f"the export's table ({table.incidence.size * table.light_azimuth.size} lights)",
                      np.abs(rows["value"].to_numpy(float) - reference), rows))
    print(errors_line(f"the trial ({len(shares)} lights, spacing {' '.join(args.spacing)})", np.abs(total - reference),
                      rows))
    print(f"the trial's table: {shares.size * 2 / 1e6:.1f} MB as 16-bit shares, measured in {seconds:.1f} s "
          f"(the export's: {table.nbytes / 1e6:.1f} MB)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
