"""Snakemake adapter: a job's sweeps (a truncation's row of rough surfaces, a random ensemble's tiles, the control,
or a claim ensemble's pilot or tested tiles at the claim's views alone), each to its Parquet file, through the sweep
store (roughlight.study.sweep_store)."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _gl  # noqa: E402

_gl.use(snakemake)  # render.platform and the renderers' threads, before anything loads OpenGL

import _log  # noqa: E402

from roughlight.study.sweep_store import measure_sweeps  # noqa: E402
from roughlight.study.tables import run_sweep  # noqa: E402
from roughlight.surfaces.roughness import make_surface  # noqa: E402

log = _log.setup(snakemake)
params = snakemake.params
# the store's key: every param but the job's own surfaces and files and the store's folder, so that a setting a
# rule passes to its sweeps is part of the key without being listed here
settings = {key: value for key, value in params.items() if key not in ("surfaces", "files", "store")}
views = None
if "geometry" in snakemake.input.keys():  # rule claim_sweeps: the views around the claim's lobes alone
    import pandas as pd

    from roughlight.analysis.claim_instrument import claim_views

    first = params.surfaces[0]
    key = (float(first["truncation"]), float(first["aspect"]), float(params.incidence))
    views = claim_views(pd.read_csv(snakemake.input.geometry), key, params.sweep["azimuth_step"],
                        params.sweep["elevation_step"])
    log(f"claim views at t {key[0]:g}, a {key[1]:g}, incidence {key[2]:g}: {len(views[0])} of the grid's views")
    settings["views"] = [[float(a), float(e)] for a, e in zip(*views)]  # and the views enter the store's key


def measure(path, surface):
    run_sweep(path, surface=make_surface(**surface), incidence=params.incidence, sweep=params.sweep,
              lighting=params.lighting, method=params.method, render=params.render, log=log, views=views)


# a job's sweep files: its outputs, or those in its output folder (random_sweeps: an ensemble, a file a seed)
files = list(getattr(params, "files", None) or snakemake.output)
measure_sweeps(files, params.surfaces, settings, measure, store=params.store, log=log)
_log.end_job()
