"""The page's "Where methods fail": the stability scans at ``measurements.plan``, the safe domain, what fails where
(``templates/stability.html``); switched by ``report.stability``."""

from __future__ import annotations

import pandas as pd

from ..registry import Section
from .speed import validation_line


def stability_data(safe_domain: pd.DataFrame | None = None, stability: pd.DataFrame | None = None,
                   stability_png=None, plan: str = "full", renderer_validation: pd.DataFrame | None = None) -> dict | None:
    """"Where methods fail": the safe-domain table, the chart, what fails where (with the default renderer's worst
    view at every view when ``renderer_validation``, the frame of
    :func:`roughlight.measurements.renderer_validation.validate_renderer`, is given); None: switched off.

    Parameters
    ----------
    safe_domain : the frame of :func:`roughlight.measurements.stability.safe_domain`.
    stability : the long frame of the scans (for the clipping numbers and the normals), or None.
    stability_png : path of the PNG rule ``stability`` draws (the registry's figure ``stability``).
    plan : the size the measurements ran at (:data:`roughlight.measurements.stability.PLANS`).
    """
    from ...measurements.stability import TOLERANCE, normals_table, plan_surfaces

    if safe_domain is None:
        return None
    surfaces_of = plan_surfaces(plan)
    safe = safe_domain if isinstance(safe_domain, pd.DataFrame) else pd.DataFrame(safe_domain)
    long = stability
    clipped = None
    if long is not None:
        cf = long[(long["experiment"] == "clipping") & (long["metric"] == "clipped_fraction")]
        clipped = list(zip(cf["setting"], cf["x"], cf["value"]))
    nt = normals_table(long) if long is not None else pd.DataFrame()
    normals = {"table": nt, "surfaces": [(s.truncation, s.aspect) for s, _ in surfaces_of["normals"]]} \
        if len(nt) else None
    line = validation_line(renderer_validation) \
        if renderer_validation is not None and len(renderer_validation) else None
    return {"plan": plan, "n_fast": len(surfaces_of["fast"]), "n_naive": len(surfaces_of["naive"]),
            "tolerance": TOLERANCE, "safe": safe, "png": stability_png, "clipped": clipped, "line": line,
            "normals": normals}


SECTION = Section("stability", stability_data, "stability.html", title="Where methods fail", switch="report.stability",
                  inputs={"stability": "results/stability/{plan}/stability.parquet",
                          "safe_domain": "results/stability/{plan}/safe_domain.csv",
                          "stability_png": "results/stability/{plan}/stability.png"})
