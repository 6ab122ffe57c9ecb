"""Snakemake adapter: a random kind's claim tiles at a grid point (its tested seeds, claims.seeds), each measured at
the claim's views alone, through the sweep store (roughlight.study.sweep_store)."""
import os
import sys

# llvmpipe's worker threads: as many as the rule's `threads`, set before OpenGL loads
os.environ.setdefault("LP_NUM_THREADS", str(snakemake.threads))
sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform, before anything loads OpenGL

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.analysis.claim_instrument import claim_views  # noqa: E402
from roughlight.study.sweep_store import measure_sweeps  # noqa: E402
from roughlight.study.tables import run_sweep  # noqa: E402
from roughlight.surfaces.roughness import make_surface  # noqa: E402

log = _log.setup(snakemake)
params = snakemake.params
first = params.surfaces[0]
key = (float(first["truncation"]), float(first["aspect"]), float(params.incidence))
views = claim_views(pd.read_csv(snakemake.input.geometry), key, params.sweep["azimuth_step"],
                    params.sweep["elevation_step"])
log(f"claim views at t {key[0]:g}, a {key[1]:g}, incidence {key[2]:g}: {len(views[0])} of the grid's views")
# the store's key: every param but the job's own surfaces and files and the store's folder, and the views
settings = {name: value for name, value in params.items() if name not in ("surfaces", "files", "store")}
settings["views"] = [[float(a), float(e)] for a, e in zip(*views)]


def measure(path, surface):
    run_sweep(path, surface=make_surface(**surface), incidence=params.incidence, sweep=params.sweep,
              lighting=params.lighting, method=params.method, render=params.render, log=log, views=views)


os.makedirs(snakemake.output[0], exist_ok=True)
measure_sweeps(list(params.files), params.surfaces, settings, measure, store=params.store, log=log)
_log.end_job()
