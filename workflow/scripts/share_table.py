"""Snakemake adapter: one exported surface's share table, measured by the exact reference at its nodes (no OpenGL),
and what measuring it took (``table.json``, for the export's summary)."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402

from roughlight.atomic import write_text_atomic  # noqa: E402
from roughlight.measurements import brdf_export  # noqa: E402
from roughlight.surfaces.surface import Surface  # noqa: E402

log = _log.setup(snakemake)
out, params = snakemake.output, snakemake.params
built = brdf_export.build_table(Surface(*params.surface), out.shares, params.nodes, params.shadows, log)
write_text_atomic(out.table, json.dumps({"seconds": built["seconds"]}))
_log.end_job()  # outputs written: leave without the interpreter's teardown
