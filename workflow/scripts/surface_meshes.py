"""Snakemake adapter: write one period of every surface of the study (the grid, the control and every random
tile) as PLY, in one job (a mesh takes milliseconds, a job's start-up most of a second)."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.surfaces import geometry  # noqa: E402
from roughlight.surfaces.roughness import make_surface  # noqa: E402

log = _log.setup(snakemake)
for path in snakemake.output:
    surface = make_surface(**snakemake.params.surfaces[path])
    mesh = geometry.period_mesh(surface)
    geometry.export_mesh_atomic(mesh, path)
    log(f"{path}: {len(mesh.faces)} triangles, {surface}")
_log.end_job()
