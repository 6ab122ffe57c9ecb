"""Snakemake adapter: one random tile (kind, grid point, seed) as a PLY mesh under results/meshes/."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.surfaces import geometry  # noqa: E402
from roughlight.surfaces.roughness import make_surface  # noqa: E402

log = _log.setup(snakemake)
surface = make_surface(**snakemake.params.surface)
mesh = geometry.period_mesh(surface)
geometry.export_mesh_atomic(mesh, snakemake.output[0])
log(f"{snakemake.output[0]}: {len(mesh.faces)} triangles, {surface}")
_log.end_job()
