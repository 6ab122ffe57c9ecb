"""The columns of the study table each report job reads.

``results/study.parquet`` has 26 columns; the thesis's analyses, the analytic models and the figures use 11 to 16
of them (none yet the means before rounding and without inner shadows, ``rough_unrounded``,
``control_unrounded`` and ``rough_unshadowed``). Reading only those
(:func:`roughlight.study.tables.read_study`'s ``columns``) takes a third less time and about 0.3 GB less memory
a job on the default study (the labels ``kind`` and the settings columns are never converted to pandas).
"""

from __future__ import annotations

from ..study.selection import SURFACE_KEYS

__all__ = ["VIEW_COLUMNS", "STUDY_COLUMNS"]

#: A view's keys and measurements: what every analysis of the regular surface reads.
VIEW_COLUMNS = SURFACE_KEYS + ["azimuth", "elevation", "phase", "component", "rough", "control", "coverage"]
#: The settings :func:`roughlight.study.selection.recorded_lighting` reads (with defaults for absent columns, so
#: they must all be read where it is called).
LIGHTING_COLUMNS = ["light", "ambient", "shininess", "specular_model", "shadows", "specular_shadows"]

#: The unrounded means the random-roughness claim reads (:mod:`roughlight.analysis.claim_readings`).
CLAIM_COLUMNS = ["rough_unrounded", "rough_unshadowed"]

#: The study columns each report rule reads (analysis_random: the random points' rows, the others the regular
#: surface's).
STUDY_COLUMNS = {
    # lobes, diffuse parts and levels, Tables 1-2, reflecting areas; render_timings and study_summary
    "analysis_tables": VIEW_COLUMNS + ["light", "shininess", "shadows", "method", "render_seconds"],
    "analysis_models": VIEW_COLUMNS + LIGHTING_COLUMNS,
    "figures": VIEW_COLUMNS + LIGHTING_COLUMNS,
    # per-seed statistics, seed-averaged views, the models refitted to every tile, the random maps
    "analysis_random": ["kind", "seed"] + VIEW_COLUMNS + LIGHTING_COLUMNS,
    # the claim's lobes, discs and design: the regular surfaces at the random grid points
    "claim_discs": ["kind", "seed"] + SURFACE_KEYS + ["azimuth", "elevation", "component", "rough", "coverage"]
    + CLAIM_COLUMNS,
}
