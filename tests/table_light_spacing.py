"""How close the share table's light azimuth nodes must be: the error of reading a light between two azimuth nodes
alone (docs/export.md, "Resolution"), at one incidence at a time.

    python tests/table_light_spacing.py                       # t 1, a 1; incidences 5..70; spacings 15..1.5 deg
    python tests/table_light_spacing.py --surface 0.5 1 --incidence 10 30 --step 15 5

For each incidence, the exact reference's facet shares (:func:`roughlight.render.exact.shares_under`) of random
views (seeded; 2-88 degrees above the plane, any azimuth) under lights every 0.5 degree of azimuth over the table's
[0, 45]; then, for each node spacing, the shares read linearly between the nodes (the table's reading along that axis
alone: the light's incidence and the view exact) and the facet sum's total (0-255, the study's lighting, 8-bit
facets, as ``table_values``) against the exact one. Prints the worst and the 99th percentile over views and lights.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from roughlight.render import shading
from roughlight.render.exact.reference import LitScene
from roughlight.render.implicit import channel_shares
from roughlight.render.implicit.model import facet_normals
from roughlight.surfaces.surface import Surface

#: The lights' azimuths, degrees: every half degree over the table's [0, 45] (every spacing's nodes are among them).
FINE = np.arange(0.0, 45.0 + 1e-9, 0.5)


def exact_shares(surface: Surface, incidence: float, views) -> np.ndarray:
    """(views, lights, 10): each facet's lit then shadowed share (a table node's channels) at every light of FINE."""
    scenes = [LitScene(surface, incidence, True, float(p)) for p in FINE]
    return np.stack([channel_shares(scenes, elevation, azimuth) for elevation, azimuth in views])


def totals(surface: Surface, incidence: float, views, shares: np.ndarray, lighting) -> np.ndarray:
    """(views, lights): the facet sum's total of ``shares`` under each light of FINE."""
    light = np.stack([shading.light_direction(incidence, p) for p in FINE])
    return np.stack([shading.facet_sum(facet_normals(surface), light[:, None, :],
                                       np.broadcast_to(shading.view_direction(elevation, azimuth), light.shape),
                                       node[:, :5], node[:, 5:], lighting)["total"]
                     for (elevation, azimuth), node in zip(views, shares)])


def read_between(shares: np.ndarray, step: float) -> np.ndarray:
    """``shares`` read linearly between azimuth nodes ``step`` apart (0, step, ..., 45)."""
    nodes = np.arange(0.0, 45.0 + 1e-9, step)
    at = np.round(nodes / 0.5).astype(int)
    out = np.empty_like(shares)
    for k in range(shares.shape[0]):
        for c in range(shares.shape[2]):
            out[k, :, c] = np.interp(FINE, nodes, shares[k, at, c])
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--surface", type=float, nargs=2, default=(1.0, 1.0), metavar=("TRUNCATION", "ASPECT"))
    parser.add_argument("--incidence", type=float, nargs="+", default=[5.0, 10.0, 17.0, 25.0, 35.0, 50.0, 70.0])
    parser.add_argument("--step", type=float, nargs="+", default=[15.0, 7.5, 5.0, 3.0, 2.5, 1.5])
    parser.add_argument("--views", type=int, default=80)
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args(argv)
    for step in args.step:
        if abs(45.0 / step - round(45.0 / step)) > 1e-9 or abs(step / 0.5 - round(step / 0.5)) > 1e-9:
            parser.error(f"--step {step:g}: a spacing must divide 45 and be a multiple of 0.5 degree")
    surface, lighting = Surface(*args.surface), shading.Lighting()
    rng = np.random.default_rng(args.seed)
    views = list(zip(rng.uniform(2.0, 88.0, args.views), rng.uniform(0.0, 360.0, args.views)))
    print(f"t {surface.truncation:g}, a {surface.aspect:g}: worst (p99) |total - exact| over {args.views} views x "
          f"{FINE.size} light azimuths, by the spacing of the light azimuth nodes (degrees)")
    for incidence in args.incidence:
        start = time.perf_counter()
        shares = exact_shares(surface, incidence, views)
        exact = totals(surface, incidence, views, shares, lighting)
        cells = []
        for step in args.step:
            error = np.abs(totals(surface, incidence, views, read_between(shares, step), lighting) - exact)
            cells.append(f"{step:g}: {error.max():.2f} ({np.percentile(error, 99):.2f})")
        print(f"incidence {incidence:g} ({time.perf_counter() - start:.1f} s): " + "; ".join(cells), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
