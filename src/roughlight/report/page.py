"""The study's report: one self-contained HTML page (tables inline, figures as data URIs).

:func:`build_report` takes the analysis tables (:mod:`roughlight.analysis.lobes`,
:mod:`roughlight.analysis.thesis`, :mod:`roughlight.analysis.glm`, ...), the figure PNGs
(:mod:`roughlight.report.figures`), the configuration and provenance, and returns the
page as a string; :func:`write_report` writes it atomically. The page is rendered from
Jinja2 templates, ``templates/base.html`` and one template a section, with the stylesheet
``templates/report.css`` inlined (:mod:`roughlight.report.page_templates`); the modules
:mod:`~roughlight.report.page_sections`, :mod:`~roughlight.report.page_thesis` and
:mod:`~roughlight.report.page_measurements` gather each section's data. The page loads
nothing from anywhere: no scripts, no fonts, no external images, so it opens from disk
without a server. Each figure's title and caption (what the thesis, Slattery 2001, saw
and what our study shows) come from :mod:`roughlight.report.registry`, that is from
``workflow/report/*.rst``, the same text ``snakemake --report`` shows.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import importlib.metadata
import os
import platform
from pathlib import Path

from ..analysis.thesis import TABLE_ASPECTS, THESIS_INCIDENCE
from ..atomic import write_text_atomic
from . import page_sections as sections
from .page_explorer import explorer_section
from .page_findings import findings_section
from .page_measurements import (
    RANDOM_MODELS,
    implicit_section,
    random_claim_rows,
    random_section,
    renderer_validation_html,
    renderer_validation_line,
    stability_section,
)
from .page_sections import (
    models_section_html,  # noqa: F401  (tests call the models section alone)
    regression_failures_html,
)
from .page_templates import TABLE_CAPTIONS, content_security_policy, png_data_uri, render, safe
from .page_thesis import tables_section, thesis_table_html

__all__ = [
    "TABLE_CAPTIONS",
    "RANDOM_MODELS",
    "package_versions",
    "file_provenance",
    "png_data_uri",
    "thesis_table_html",
    "regression_failures_html",
    "renderer_validation_line",
    "renderer_validation_html",
    "build_report",
    "write_report",
    "stability_section",
    "implicit_section",
    "random_section",
    "random_claim_rows",
]


# ---------------------------------------------------------------------------
# files and provenance


def package_versions(names=("roughlight", "numpy", "pandas", "pyarrow", "scipy", "statsmodels", "matplotlib",
                            "seaborn", "shapely", "trimesh", "pyrender2", "PyOpenGL", "snakemake")) -> dict:
    """Installed versions of the packages the study uses (missing ones are 'not installed')."""
    out = {"python": platform.python_version()}
    for name in names:
        try:
            out[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def file_provenance(path) -> dict:
    """Size, modification time and SHA-256 of a file."""
    p = Path(path)
    h = hashlib.sha256()
    with open(p, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    st = p.stat()
    return {"path": str(path), "bytes": st.st_size,
            "modified": _dt.datetime.fromtimestamp(st.st_mtime, _dt.UTC).isoformat(timespec="seconds"),
            "sha256": h.hexdigest()}


# ---------------------------------------------------------------------------
# the page


def build_report(
    tables: dict,
    figures: dict,
    config: dict | None = None,
    provenance: dict | None = None,
    messages: list | None = None,
    benchmarks: dict | None = None,
    stability_html: str | None = None,
    title: str = "roughlight: rough surface lighting behaviours, rebuilt",
    table_aspects=TABLE_ASPECTS,
    table_incidence: float = THESIS_INCIDENCE,
    implicit_html: str | None = None,
    random_html: str | None = None,
    followed=(),
    explorer: dict | None = None,
    measured: dict | None = None,
) -> str:
    """The report as one self-contained HTML string.

    Parameters
    ----------
    tables : dict of DataFrames (missing keys are reported, not an error): ``thesis_tables``, ``sine_refits``,
        ``lobes`` (arc lobes), ``lobes_hemisphere``, ``exact_peaks``, ``diffuse_parts``, ``glm_summary``,
        ``glm_coefficients``, ``model_fits``, ``model_fits_summary``, ``timings`` (per sweep); and dicts
        ``timings_summary``, ``study_summary``.
    figures : dict stem -> PNG path (:data:`roughlight.report.figures.FIGURES` stems).
    config : the configuration used (shown as YAML).
    provenance : dict with ``versions`` (package -> version), ``inputs``
        (list of :func:`file_provenance` dicts), ``settings`` (analysis settings).
    messages : list of str, shown as notes (what was left out and why).
    stability_html : "Where methods fail" (:func:`stability_section`); None: switched off (only the regressions).
    benchmarks : dict with optional ``png`` (path) and ``table`` (DataFrame) of the speed/accuracy benchmark;
        None: switched off (``report.speed_accuracy: false``).
    implicit_html : "An implicit rough surface" (:func:`implicit_section`); None: switched off.
    random_html : the "Random roughness" section (:func:`random_section`); None: no random kind measured.
    followed : lines naming the settings left unset that took the grid's values
        (:func:`roughlight.study.config.follow_grid`), shown in "The study".
    explorer : the hemisphere explorer's data (:func:`roughlight.report.explorer.explorer_data`, as rule
        ``explorer_data`` writes it); None: switched off (``report.explorer.enabled: false``).
    measured : frames of the sections rendered apart, for the findings (:func:`findings_section`): ``random_ensembles``
        and ``implicit_validation``; None or a missing key: the finding says it was not given.
    table_aspects, table_incidence : the aspects and incidence of Tables 1-2 (``report.table_aspects``,
        ``report.table_incidence``): every table and text of the page on "the table aspects" shows these.

    Returns
    -------
    str (UTF-8 HTML document)
    """
    tables = tables or {}
    page = _thesis_sections(tables, figures, list(messages or []), table_aspects, table_incidence, followed)
    page.update(_study_sections(tables, figures, config, provenance or {}, benchmarks))
    shown = {"random": bool(random_html), "implicit": bool(implicit_html)}
    page.update(findings=findings_section(tables, benchmarks, measured, table_aspects, table_incidence, shown=shown),
                explorer=explorer_section(explorer))
    return render(
        "base.html", title=title, now=_dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"), **page,
        csp=content_security_policy(page["explorer"]["scripts"] if page["explorer"] else ()),
        # the sections the workflow renders apart (stability_section, implicit_section, random_section)
        implicit_html=safe(implicit_html), random_html=safe(random_html), stability_html=safe(stability_html),
    )


def _thesis_sections(tables: dict, figures: dict, messages: list, table_aspects, table_incidence: float,
                     followed) -> dict:
    """The page's data for the sections that follow the table aspects: the study, Tables 1-2, the figure sections,
    the diffuse parts and the lobes."""
    study = tables.get("study_summary", {}) or {}
    return {
        "study": sections.study_section(study, messages, table_aspects, followed),
        "thesis": tables_section(tables, tables.get("thesis_tables"), tables.get("exact_peaks"), table_incidence),
        "specular": sections.figure_section("specular", figures),
        "diffuse": sections.figure_section("diffuse", figures),
        "diffuse_parts": sections.diffuse_parts_section(tables, table_aspects),
        "pictures": sections.figure_section("pictures", figures),
        "lobes": sections.lobes_section(tables, figures, table_aspects),
    }


def _study_sections(tables: dict, figures: dict, config, provenance: dict, benchmarks) -> dict:
    """The page's data for the grid-wide sections: GLMs, models, the regressions and provenance."""
    versions = provenance.get("versions") or package_versions()
    return {
        "glm": sections.glm_section(tables, figures),
        "models": sections.models_section(tables, figures, provenance),
        "regressions": sections.regressions_section(tables),
        "provenance": sections.provenance_section(tables, figures, config, provenance, benchmarks, versions),
    }


def write_report(path, html_text: str) -> str:
    """Write the report atomically; return the path."""
    write_text_atomic(path, html_text)
    return os.fspath(path)
