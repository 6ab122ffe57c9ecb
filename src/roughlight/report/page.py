"""The study's report: one self-contained HTML page (tables inline, figures as data URIs).

:func:`build_report` takes the named inputs of the page's sections (the analysis outputs by their files' stems, the
measurements' tables and charts, the figure PNGs, the configuration and provenance, the settings) and returns the
page as a string; :func:`write_report` writes it atomically. Each section of the page is one module of
:mod:`roughlight.report.sections`: a function from its inputs to the data its template renders, and its declaration
(title, anchor, template, inputs, switch); :data:`roughlight.report.sections.SECTIONS` gives the page its order. The
page is rendered from Jinja2 templates, ``templates/base.html`` and one template a section, with the stylesheet
``templates/report.css`` inlined (:mod:`roughlight.report.page_templates`). The page loads nothing from anywhere:
no scripts, no fonts, no external images, so it opens from disk without a server. Each figure's title and caption
(what the thesis, Slattery 2001, saw and what our study shows) come from :mod:`roughlight.report.registry`, that is
from ``workflow/report/*.rst``, the same text ``snakemake --report`` shows.
"""

from __future__ import annotations

import datetime as _dt
import inspect
import json
import os

import pandas as pd

from ..analysis.thesis import TABLE_ASPECTS, THESIS_INCIDENCE
from ..atomic import read_frame, write_text_atomic
from . import registry, sections
from .page_templates import content_security_policy, named_arguments, render
from .sections.provenance import file_provenance, package_versions

__all__ = [
    "package_versions",
    "file_provenance",
    "read_inputs",
    "section_data",
    "render_section",
    "build_report",
    "write_report",
]

TITLE = "roughlight: rough surface lighting behaviours, rebuilt"


# ---------------------------------------------------------------------------
# the inputs


def read_input(path):
    """One input of the page read from its file: a table (``.parquet``, ``.csv``) as a DataFrame, a ``.json`` file
    as what it holds; any other file (a chart's PNG) is given as its path."""
    path = os.fspath(path)
    if path.endswith(".parquet"):
        return pd.read_parquet(path)
    if path.endswith(".csv"):
        return read_frame(path)
    if path.endswith(".json"):
        with open(path) as fh:
            return json.load(fh)
    return path


def read_inputs(paths: dict) -> dict:
    """The page's inputs read from their files (:func:`read_input`), by the same names; ``figures``, a list of the
    registry's figure PNGs, becomes a dict stem -> path."""
    out = {}
    for name, path in paths.items():
        if name == "figures":
            out[name] = {os.path.splitext(os.path.basename(p))[0]: p for p in path}
        else:
            out[name] = read_input(path)
    return out


# ---------------------------------------------------------------------------
# the sections


def section_data(section: registry.Section, values: dict):
    """A section's data: its function (:attr:`registry.Section.build`) given what its parameters name from
    ``values`` (``section``: the section's name)."""
    return section.build(**named_arguments(section.build, {**values, "section": section.name}))


def takes_shown(section: registry.Section) -> bool:
    """Whether the section's data depend on which other sections are on the page (a parameter ``shown``): it is
    gathered after them."""
    return "shown" in inspect.signature(section.build).parameters


def render_section(name: str, **values) -> str:
    """One section of the page alone (its HTML), from its inputs by name: the same template and data the page
    places."""
    section = sections.section(name)
    return render(section.template, s=section_data(section, values))


# ---------------------------------------------------------------------------
# the page


def build_report(inputs: dict | None = None, figures: dict | None = None, title: str = TITLE, **named) -> str:
    """The report as one self-contained HTML string.

    Parameters
    ----------
    inputs : dict name -> value: the analysis outputs by their files' stems (DataFrames: ``thesis_tables``,
        ``lobes_arc``, ``exact_peaks``, ``glm_summary``, ``model_fits``, ...; ``study_summary``, a dict with
        ``study``, ``timings`` and ``messages``; ``glm_messages``, a list), the measurements (``speed_accuracy``,
        ``renderer_validation``, ``stability``, ``safe_domain``, ``implicit_validation``, ``random_ensembles``,
        ...) and their charts (``{stem}_png``: paths), ``explorer_data``: whatever a section of
        :data:`roughlight.report.sections.SECTIONS` names. A name left out is reported, not an error; a section
        whose inputs are all left out says it is switched off.
    figures : dict stem -> PNG path (:data:`roughlight.report.registry.FIGURES` stems); None: ``inputs["figures"]``.
    title : the page's title.
    **named : more inputs by name: ``config`` (the configuration used, shown as YAML), ``provenance`` (``versions``,
        ``inputs``: :func:`file_provenance` dicts, ``settings``), ``followed`` (the settings that followed the grid,
        :func:`roughlight.study.config.follow_grid`), ``table_aspects`` and ``table_incidence`` (Tables 1-2:
        ``report.table_aspects``, ``report.table_incidence``), ``plan`` (``measurements.plan``),
        ``surface_settings`` (``surface.cells``, ``surface.spread``).

    Returns
    -------
    str (UTF-8 HTML document)
    """
    values = {"table_aspects": TABLE_ASPECTS, "table_incidence": THESIS_INCIDENCE, "figures": {}, **(inputs or {}),
              **named}
    if figures is not None:
        values["figures"] = figures
    page = {}
    for section in sorted(sections.SECTIONS, key=takes_shown):  # those that say what is shown, last
        page[section.name] = section_data(section, {**values, "shown": {k: v is not None for k, v in page.items()}})
    return render(
        "base.html", title=title, now=_dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        sections=sections.SECTIONS, page=page,
        csp=content_security_policy(page["explorer"]["scripts"] if page["explorer"] else ()),
    )


def write_report(path, html_text: str) -> str:
    """Write the report atomically; return the path."""
    write_text_atomic(path, html_text)
    return os.fspath(path)
