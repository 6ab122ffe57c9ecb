"""The page's "Lobes": the arc lobes at the table aspects with the exact widths of both specular-shadow protocols,
the hemisphere's lobes, the lobe figures (``templates/lobes.html``)."""

from __future__ import annotations

import pandas as pd

from ...analysis.thesis import TABLE_ASPECTS
from ...study.selection import SURFACE_KEYS, find_aspect
from ...surfaces.surface import aspect_label
from ..page_templates import section_figures
from ..registry import Section, figures

#: The columns of the exact lobe peaks shown beside the measured lobes: the two specular-shadow protocols.
PROTOCOLS = ["exact_fwhm", "exact_peak_no_specular_shadows", "exact_fwhm_no_specular_shadows"]


def _at_table_aspects(frame: pd.DataFrame, table_aspects) -> pd.DataFrame:
    want = [find_aspect(frame["aspect"], a) for a in table_aspects]
    return frame[frame["aspect"].isin([a for a in want if a is not None])]


def lobes_section(lobes_arc: pd.DataFrame | None = None, lobes_hemisphere: pd.DataFrame | None = None,
                  exact_peaks: pd.DataFrame | None = None, figures: dict | None = None,
                  table_aspects=TABLE_ASPECTS) -> dict:
    """"Lobes": the arc lobes at the table aspects (with the exact widths of both protocols), the hemisphere's."""
    out = {"figures": section_figures("lobes", figures or {}), "arc": None, "protocols": False, "hemisphere": None}
    lobes, exact, hemi = lobes_arc, exact_peaks, lobes_hemisphere
    if lobes is not None and len(lobes):
        sel = _at_table_aspects(lobes, table_aspects)
        sel = sel[sel["lobe"].isin(["forward", "back"])].copy()
        sel["aspect"] = sel["aspect"].map(aspect_label)
        cols = ["truncation", "aspect", "incidence", "lobe", "predicted", "peak", "peak_elevation", "centroid",
                "fwhm", "phase_at_peak", "note"]
        if exact is not None and len(exact) and all(c in exact for c in PROTOCOLS):
            ex = exact[SURFACE_KEYS + ["lobe"] + PROTOCOLS].copy()
            ex["aspect"] = ex["aspect"].map(aspect_label)
            sel = sel.merge(ex, on=SURFACE_KEYS + ["lobe"], how="left")
            cols = cols[:-1] + PROTOCOLS + ["note"]
            out["protocols"] = True
        out["arc"] = sel[cols]
    if hemi is not None and len(hemi):
        sel = _at_table_aspects(hemi, table_aspects).copy()
        sel["aspect"] = sel["aspect"].map(aspect_label)
        out["hemisphere"] = sel
    return out


SECTION = Section("lobes", lobes_section, "lobes.html", title="Lobes",
                  inputs={"lobes_arc": "results/analysis/lobes_arc.parquet",
                          "lobes_hemisphere": "results/analysis/lobes_hemisphere.parquet",
                          "exact_peaks": "results/analysis/exact_peaks.csv",
                          "figures": tuple(f.path for f in figures(section="lobes"))})
