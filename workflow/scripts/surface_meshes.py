"""Snakemake adapter: write one period of every surface of the grid (and the control) as PLY."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.study import config  # noqa: E402
from roughlight.surfaces import geometry  # noqa: E402
from roughlight.surfaces.surface import PLATE, Surface  # noqa: E402

log = _log.setup(snakemake)
targets = {
    f"results/meshes/t{config.label(t)}_a{config.label(a)}.ply": Surface(t, a)
    for t in snakemake.params.grid["truncation"]
    for a in snakemake.params.grid["aspect"]
}
targets["results/meshes/control.ply"] = PLATE
for path in snakemake.output:
    surface = targets[path]
    mesh = geometry.period_mesh(surface)
    geometry.export_mesh_atomic(mesh, path)
    log(f"{path}: {len(mesh.faces)} triangles, truncation={surface.truncation}, aspect={surface.aspect}")
_log.end_job()
