"""Snakemake adapter: the every-view check's tiles summed up, a row a tile and component."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import _log  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.atomic import read_frame, write_frame  # noqa: E402
from roughlight.measurements.random_tiles import every_view_summary  # noqa: E402

log = _log.setup(snakemake)
summary = every_view_summary(pd.concat([read_frame(path) for path in snakemake.input], ignore_index=True))
write_frame(summary, snakemake.output[0])
log(summary.round(4).to_string())
_log.end_job()
