"""How the Mitsuba file's warp was chosen (docs/export-mitsuba.md, "The warp"): the file against the share table
it is read from (its own error, the table's set aside), at design pairs drawn as the export's check draws them but
with another seed, for the identity warp, three curvature densities and the facets' NDF.

    python tests/warp_design.py results/export/t1_a1          # a finished run's export of t 1, a 1
    python tests/warp_design.py results/export/t1_a1 --cost   # what the warp costs rule export, back to back

Takes the export's ``shares.npz``; writes each candidate file (the components in R, G, B) to a temporary folder,
evaluates it with Mitsuba's plugin (``measured.evaluate``, ``scalar_rgb``) at 6 lights x 300 views (seed 7) and
prints the total's MAE, p99 and worst view against the table's values (``brdf_export.brdf_values``), per warp.
With ``--cost`` it times rule ``export``'s work instead (``brdf_export.export_surface``: the file, the check's file
and the check's renders) without and with the warp, alternately, three times each, in a temporary folder.
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from roughlight.measurements import brdf_export as B
from roughlight.render import shading
from roughlight.render.implicit import load_table
from roughlight.render.implicit.model import facet_normals
from roughlight.render.mitsuba import measured
from roughlight.render.mitsuba import warp as W

#: The design pairs' seed (the check's is ``brdf_export.CHECK["seed"]``, 2001) and their counts.
SEED, LIGHTS, VIEWS = 7, 6, 300
#: The candidates: a name and the density from the regular table (None: the identity).
CANDIDATES = {
    "identity": None,
    "curvature, each slice its own (power 0.5)": dict(floor=0.3, power=0.5, own=1.0, side=None),
    "curvature, one for all slices (power 1)": dict(floor=0.3, power=1.0, own=0.0, side=None),
    "curvature, half own, half the mean (power 0.75), at the values' 32 x 32 nodes": dict(
        floor=W.WARP_FLOOR, power=W.WARP_POWER, own=W.WARP_OWN, side=None),
    "the same at 16 x 16 warp nodes (the default)": dict(floor=W.WARP_FLOOR, power=W.WARP_POWER, own=W.WARP_OWN,
                                                         side=16),
    "the same at 8 x 8 warp nodes": dict(floor=W.WARP_FLOOR, power=W.WARP_POWER, own=W.WARP_OWN, side=8),
    "the facets' NDF (their normals by area, widened 6 degrees, 30% even)": "ndf",
}


def facet_density(table, n_u: int, shape, width: float = 6.0, floor: float = 0.3) -> np.ndarray:
    """The facets' NDF as a warp density: a Gaussian of ``width`` degrees about each facet's normal, weighed by the
    facet's area (plan area over ``n_z``: the top ``(1 - t)^2``, each side a quarter of the rest), ``floor`` even."""
    normals = facet_normals(table.surface)
    top = (1.0 - table.truncation) ** 2
    area = np.array([top] + [(1.0 - top) / 4.0] * 4) / normals[:, 2]
    angle = np.degrees(np.arccos(np.clip(measured.half_vectors(n_u) @ normals.T, -1.0, 1.0)))
    need = (area * np.exp(-0.5 * (angle / width) ** 2)).sum(axis=-1)
    density = (1.0 - floor) * need / need.mean() + floor
    return np.broadcast_to(density, shape).astype(np.float32).copy()


def export_cost(table, shares: Path, pairs: int = 3) -> None:
    """Seconds of ``brdf_export.export_surface`` (the default settings) without and with the warp, alternately."""
    with tempfile.TemporaryDirectory() as folder:
        paths = {"shares": shutil.copy(shares, folder), "mitsuba": str(Path(folder) / "brdf.bsdf")}
        for _ in range(pairs):
            times = []
            for warp in (False, True):
                start = time.perf_counter()
                B.export_surface(table, paths, mitsuba={"warp": warp})
                times.append(time.perf_counter() - start)
            print(f"without the warp {times[0]:.2f} s, with it {times[1]:.2f} s")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("export", type=Path, help="a finished run's export folder (shares.npz)")
    parser.add_argument("--cost", action="store_true", help="time rule export's work without and with the warp")
    args = parser.parse_args(argv)
    table = load_table(args.export / "shares.npz")
    if args.cost:
        export_cost(table, args.export / "shares.npz")
        return
    lighting = replace(shading.Lighting(), ambient=0.0)
    values = B.brdf_values(table, lighting)
    theta, phi = B.mitsuba_nodes(B.MITSUBA["elevation"], B.MITSUBA["phi_nodes"])
    n_u = B.MITSUBA["resolution"]
    regular = measured.tabulate(values, theta, phi, n_u, lighting, "components")
    lights = B.check_lights(table, LIGHTS, SEED)
    azimuth, elevation = B.check_views(table, VIEWS, SEED)
    view = shading.view_direction(elevation, azimuth)
    print("| warp | MAE | p99 | worst |\n|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for k, (name, choice) in enumerate(CANDIDATES.items()):
            if choice is None:
                rgb, vndf = regular, None
            else:
                vndf = (facet_density(table, n_u, regular[:, :, 0].shape) if choice == "ndf"
                        else W.warp_density(regular, **choice))
                rgb = measured.tabulate(values, theta, phi, n_u, lighting, "components", vndf=vndf)
            path = measured.write_measured(Path(folder) / f"{k}.bsdf", theta, phi, rgb, name, vndf=vndf)
            errors = []
            for incidence, psi in lights:
                light = np.broadcast_to(shading.light_direction(incidence, psi), view.shape)
                got = np.pi * lighting.light * measured.evaluate(path, light, view, variant="scalar_rgb")[:, 2]
                errors.append(np.abs(got - values(light, view)["total"]))
            e = np.concatenate(errors)
            print(f"| {name} | {e.mean():.3f} | {np.quantile(e, 0.99):.2f} | {e.max():.2f} |")


if __name__ == "__main__":
    main()
