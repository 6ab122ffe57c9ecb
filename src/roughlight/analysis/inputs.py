"""The columns of the study table each report job reads, and reading only those.

:func:`roughlight.study.tables.read_study` reads every column of ``results/study.parquet`` (23); the thesis's
analyses, the analytic models and the figures use 11 to 16 of them. Reading only those takes a third less time
and about 0.3 GB less memory a job on the default study (the labels ``kind`` and the settings columns are never
converted to pandas).
"""

from __future__ import annotations

import pandas as pd

from ..study.selection import SURFACE_KEYS

__all__ = ["VIEW_COLUMNS", "STUDY_COLUMNS", "read_regular_study"]

#: A view's keys and measurements: what every analysis of the regular surface reads.
VIEW_COLUMNS = SURFACE_KEYS + ["azimuth", "elevation", "phase", "component", "rough", "control", "coverage"]
#: The settings :func:`roughlight.study.selection.recorded_lighting` reads (with defaults for absent columns, so
#: they must all be read where it is called).
LIGHTING_COLUMNS = ["light", "ambient", "shininess", "specular_model", "shadows", "specular_shadows"]

#: The study columns of each rule that reads the regular surface's rows (:func:`read_regular_study`).
STUDY_COLUMNS = {
    # lobes, diffuse parts and levels, Tables 1-2, reflecting areas; render_timings and study_summary
    "analysis_tables": VIEW_COLUMNS + ["light", "shininess", "shadows", "method", "render_seconds"],
    "analysis_models": VIEW_COLUMNS + LIGHTING_COLUMNS,
    "figures": VIEW_COLUMNS + LIGHTING_COLUMNS,
}


def read_regular_study(path, columns) -> pd.DataFrame:
    """``read_study(path, rows="regular")[columns]``, reading only ``columns``.

    As :func:`roughlight.study.tables.read_study`, a column at a time, each cut to the regular surface's rows
    (kind ``pyramids``; every row of a table without ``kind``) before the next is read. A column the file lacks is
    a KeyError, as selecting it from ``read_study``'s frame would be.
    """
    import pyarrow.compute as pc
    import pyarrow.parquet as pq

    names = pq.read_schema(path).names
    missing = [name for name in columns if name not in names]
    if missing:
        raise KeyError(f"{path} lacks the column(s) {missing}")
    keep = pc.equal(pq.read_table(path, columns=["kind"]).column(0), "pyramids") if "kind" in names else None
    frame = {}
    for name in columns:
        column = pq.read_table(path, columns=[name]).column(0)
        frame[name] = (column if keep is None else column.filter(keep)).to_pandas()
        del column
    return pd.DataFrame(frame, copy=False)
