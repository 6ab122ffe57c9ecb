"""How large the Mitsuba file must be to hold the share table's BRDF (docs/export-mitsuba.md, "Size against error"):
the file's own error, the table's set aside, at the export's check pairs and at held-out ones, for files of more
half-vector and detector nodes.

    python tests/mitsuba_file_sizes.py results/export/t1_a1     # a finished run's export of t 1, a 1

Takes the export's ``shares.npz``; draws the check's pairs (``brdf_export.check_lights`` and ``check_views``: 3
lights x 400 views, seed 2001) and 40 lights x 30 views with seed 58, off the table's nodes; for each layout writes a
file of the diffuse, specular and total in R, G, B (``brdf_export.mitsuba_tables``, the default warp) to a temporary
folder, evaluates it with Mitsuba's plugin (``measured.evaluate``) and prints its size, its build time and each
component's MAE and worst view against the table's values (``table.table_values``, 8-bit facets). About a minute.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from roughlight.measurements import brdf_export as B
from roughlight.render import shading
from roughlight.render.implicit import load_table
from roughlight.render.implicit.table import table_values
from roughlight.render.mitsuba import measured, write_measured

#: The pairs: (lights, views a light, seed).
PAIRS = ((3, 400, 2001), (40, 30, 58))
_ELEVATION = B.MITSUBA["elevation"]
#: The detector's elevation nodes with one more between each two.
DOUBLED = sorted(set(_ELEVATION) | {(a + b) / 2 for a, b in zip(_ELEVATION[:-1], _ELEVATION[1:])})
#: The layouts: ``brdf_export.mitsuba_tables`` keywords.
LAYOUTS = {
    "default (18 x 19 x 32^2)": {},
    "half-vector grid 40^2": {"resolution": 40},
    "half-vector grid 48^2": {"resolution": 48},
    "half-vector grid 64^2": {"resolution": 64},
    "35 elevations, 48^2": {"resolution": 48, "elevation": DOUBLED},
    "35 elevations, 37 azimuths, 48^2": {"resolution": 48, "elevation": DOUBLED, "phi_nodes": 37},
    "no warp, 64^2": {"resolution": 64, "warp": False},
}


def pairs(table) -> list:
    """Each set of pairs' seed, lights and views (stacked (n, 3) unit vectors)."""
    out = []
    for lights, views, seed in PAIRS:
        azimuth, elevation = B.check_views(table, views, seed)
        light = [np.tile(shading.light_direction(i, p), (azimuth.size, 1)) for i, p in B.check_lights(table, lights, seed)]
        out.append((seed, np.vstack(light), np.tile(shading.view_direction(elevation, azimuth), (lights, 1))))
    return out


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("export", type=Path, help="a finished run's export folder (shares.npz)")
    args = parser.parse_args(argv)
    table = load_table(args.export / "shares.npz")
    lighting = replace(shading.Lighting(), ambient=0.0)
    checked = [(seed, light, view, table_values(table, light, view, lighting)) for seed, light, view in pairs(table)]
    scale = np.pi * lighting.light
    with tempfile.TemporaryDirectory() as scratch:
        for name, keywords in LAYOUTS.items():
            start = time.perf_counter()
            theta, phi, rgb, vndf = B.mitsuba_tables(table, lighting, channels="components", **keywords)
            seconds = time.perf_counter() - start
            path = write_measured(Path(scratch) / "components.bsdf", theta, phi, rgb, "components", vndf=vndf)
            lines = []
            for seed, light, view, reference in checked:
                got = measured.evaluate(path, light, view) * scale
                errors = [np.abs(got[:, k] - reference[c]) for k, c in enumerate(shading.COMPONENTS)]
                lines.append(f"seed {seed}: " + ", ".join(f"{c} {e.mean():.3f} / {e.max():.2f}"
                                                         for c, e in zip(shading.COMPONENTS, errors)))
            print(f"{name}: {path.stat().st_size / 1e6:.1f} MB, tabulated in {seconds:.1f} s | " + " | ".join(lines),
                  flush=True)


if __name__ == "__main__":
    main()
