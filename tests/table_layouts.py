"""Share table layouts against the exact reference at the export's check pairs and at held-out ones
(docs/export.md, "Light azimuth nodes"): what each axis's nodes buy, measured with the C clipper.

    python tests/table_layouts.py                       # every layout below
    python tests/table_layouts.py default "psi 5"      # some of them, by name

Draws pairs as rule ``export``'s check draws them (``brdf_export.check_lights`` and ``check_views``): 3 lights x
400 views with seed 2001, and 40 lights x 30 views with seed 58 (the earlier stops' held-out pairs), off the
nodes of every layout here, so that each layout is read at the same pairs and none at its nodes. Takes the exact
reference's total at each (``methods.sweep("reference")``); measures each layout's table
(``tabulate.tabulate_surface``: the edge-on incidences of ``edge_on``'s light azimuths and the hot spot's view
nodes with them) and reads it in numpy (``table.table_values``, the shader's reading); prints the table's texture,
its build time and, at each set of pairs, the total's MAE, p99, worst view and views over a level. t 1, a 1; about
2 minutes for all.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from types import SimpleNamespace

import numpy as np

from roughlight.measurements.brdf_export import check_lights, check_views
from roughlight.render import methods, shading
from roughlight.render.implicit import tabulate
from roughlight.render.implicit.table import table_values
from roughlight.surfaces.surface import Surface

SURFACE = Surface(1.0, 1.0)
#: The pairs: (lights, views a light, seed).
PAIRS = ((3, 400, 2001), (40, 30, 58))


#: The nodes the layouts vary from: the default (light azimuth every 5 degrees since 30 November).
BASE = dict(tabulate.TABLE)
#: Closer light azimuth nodes where the light is low: 1.5 degrees up to incidence 25, 2.5 up to 50.
LOW = ((25.0, 1.5), (50.0, 2.5))
#: Light incidence every 2.5 degrees below 25.
CLOSE_INCIDENCE = [float(i) for i in np.arange(0.0, 25.0, 2.5)] + [float(i) for i in range(25, 91, 5)]
#: The default's view elevations and every 2.5 degrees from 25 to 65, where the side facets turn edge-on to the view.
CLOSE_ELEVATION = sorted(set(tabulate.TABLE["elevation"]) - {28.0, 32.0, 36.0} | set(np.arange(25.0, 65.1, 2.5).tolist()))


def _layout(light_step: float, azimuth_step: float = 2.5, edge_on=(0.0, 45.0), steps=(), **more) -> dict:
    return {**BASE, "light_azimuth": list(np.arange(0.0, 45.001, light_step)), "azimuth_step": azimuth_step,
            "edge_on": list(edge_on) if edge_on is not True else True, "light_azimuth_steps": [list(p) for p in steps],
            **more}


#: The layouts: the default's nodes but for the light azimuth steps, the view azimuth step, ``edge_on``, the
#: incidences and the elevations; the last, ``make bench``'s (``config/export_fine.yaml``).
LAYOUTS = {
    "psi 15, edge-on at every psi (the default before 30 November)": _layout(15.0, edge_on=True),
    "psi 9": _layout(9.0),
    "psi 7.5": _layout(7.5),
    "psi 5, edge-on at every psi": _layout(5.0, edge_on=True),
    "psi 5, no edge-on": _layout(5.0, edge_on=()),
    "psi 5 (the default)": _layout(5.0),
    "psi 5, view azimuth 1.25": _layout(5.0, 1.25),
    "psi 2.5": _layout(2.5),
    "psi 2.5, view azimuth 1.25": _layout(2.5, 1.25),
    "psi 2.5 up to incidence 50, 5 above": _layout(5.0, steps=((50.0, 2.5),)),
    "psi 1.5 up to 25, 2.5 to 50, 5 above": _layout(5.0, steps=LOW),
    "psi 2.5 up to 50, 5 above, view azimuth 1.25": _layout(5.0, 1.25, steps=((50.0, 2.5),)),
    "psi 1.5 up to 25, 2.5 to 50, 5 above, view azimuth 1.25": _layout(5.0, 1.25, steps=LOW),
    "the same as psi 2.5 up to 50, with incidence 2.5 apart below 25": _layout(5.0, 1.25, steps=((50.0, 2.5),),
                                                                             incidence=CLOSE_INCIDENCE),
    "that, and view elevation 2.5 apart from 25 to 65 (config/export_fine.yaml)": _layout(
        5.0, 1.25, steps=((50.0, 2.5),), incidence=CLOSE_INCIDENCE, elevation=CLOSE_ELEVATION),
}


def every_node():
    """The nodes of every layout together, as ``check_lights`` and ``check_views`` read a table's."""
    incidence = tabulate.incidence_nodes(SURFACE, sorted({i for nodes in LAYOUTS.values() for i in nodes["incidence"]}),
                                         [0.0, 45.0], True)
    light_azimuth = np.unique(np.concatenate([nodes["light_azimuth"] for nodes in LAYOUTS.values()]
                                             + [np.arange(0.0, 45.001, step) for _, step in LOW]))
    elevation = sorted({e for nodes in LAYOUTS.values() for e in nodes["elevation"]})
    return SimpleNamespace(surface=SURFACE, incidence=incidence, light_azimuth=light_azimuth,
                           elevation=tabulate.elevation_nodes(elevation, incidence))


def pairs(table_nodes) -> list:
    """Each set of pairs' lights, views and the exact reference's totals, drawn off ``table_nodes``' nodes."""
    lighting = replace(shading.Lighting(), ambient=0.0)
    out = []
    for lights, views, seed in PAIRS:
        azimuth, elevation = check_views(table_nodes, views, seed)
        rows = []
        for incidence, psi in check_lights(table_nodes, lights, seed):
            exact = methods.sweep("reference", SURFACE, incidence, azimuth, elevation, lighting, light_azimuth=psi)
            rows.append((np.tile(shading.light_direction(incidence, psi), (azimuth.size, 1)),
                         shading.view_direction(elevation, azimuth), np.asarray(exact["total"], float)))
        out.append((seed, *(np.concatenate(part) for part in zip(*rows))))
    return out


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("layouts", nargs="*", help="layout names (default: all)")
    parser.add_argument("--show", action="store_true", help="print each view over a level: its light and view")
    args = parser.parse_args(argv)
    lighting = replace(shading.Lighting(), ambient=0.0)
    checked = pairs(every_node())
    for name in args.layouts or LAYOUTS:
        start = time.perf_counter()
        table = tabulate.tabulate_surface(SURFACE, LAYOUTS[name])
        seconds = time.perf_counter() - start
        lines = []
        for seed, light, view, reference in checked:
            error = np.abs(table_values(table, light, view, lighting)["total"] - reference)
            for k in np.flatnonzero(error > 1.0) if args.show else ():
                (i, p, _), (e, a, _) = (np.degrees([np.arcsin(d[k, 2]), np.arctan2(d[k, 1], d[k, 0]) % (2 * np.pi), 0])
                                        for d in (light, view))
                print(f"  seed {seed}: light at incidence {i:.2f}, azimuth {p:.2f}; view at elevation {e:.2f}, "
                      f"azimuth {a:.2f}: {error[k]:.2f} off")
            lines.append(f"seed {seed}: MAE {error.mean():.3f}, p99 {np.percentile(error, 99):.2f}, "
                         f"worst {error.max():.2f}, over a level {int((error > 1).sum())}")
        print(f"{name}: {table.incidence.size} incidences, {table.lights} lights, {table.elevation.size} elevations, "
              f"{table.azimuth_nodes} azimuths, {table.nbytes / 1e6:.1f} MB, built in {seconds:.1f} s | "
              + " | ".join(lines), flush=True)


if __name__ == "__main__":
    main()
