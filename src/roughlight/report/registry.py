"""The report's figures and the page's sections: two lists, from which the workflow, the figure scripts and the
HTML page are made.

Each :class:`Figure` names a PNG under ``results/figures/``, where it sits in the
report (Snakemake's ``report()`` category and subcategory, the HTML page's
section) and whether it is drawn from the analysis tables or rendered. Its title
and caption live in one place, ``workflow/report/{name}.rst`` (what Snakemake's
``report(caption=...)`` reads): a bold title line, then ``*Thesis:*`` (what the
thesis saw) and ``*Ours:*`` (what we see); :func:`caption` reads them for the
HTML page. The function that draws a figure is ``{name}`` (``fig_{name}`` for names that do not start with
``fig``) of its section's module of :mod:`roughlight.report.figures` (:data:`SECTION_MODULES`), and is
importable from :mod:`roughlight.report.figures` itself too.

Each :class:`Section` of the page is a function from its inputs to the data its template
(``templates/{template}``) renders: the function names its inputs by its parameter names, which are the names
of the analysis outputs (their files' stems; a chart's stem and ``_png``, as rule ``report_html`` names its inputs),
of the figures (``figures``) and of the settings (``table_aspects``, ``plan``, ...). :data:`SECTIONS` lists them;
:func:`roughlight.report.page.build_report` calls each and ``templates/base.html`` places their templates.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

#: workflow/report/: the captions (reStructuredText), beside the rules that cite them.
CAPTION_DIR = Path(__file__).resolve().parent / "captions"  # workflow/report links to it


@dataclass(frozen=True)
class Figure:
    """One figure of the report.

    Attributes
    ----------
    name : str
        File stem: ``results/figures/{name}.png``, caption ``workflow/report/{name}.rst``.
    section : str
        The HTML page's section (``specular``, ``diffuse``, ``pictures``, ``lobes``, ``glm``,
        ``models``, ``provenance``) and Snakemake report subcategory.
    rendered : bool
        True: rendered by ``rule render_figures`` (pictures, plate sweeps); False: drawn from
        the study and analysis tables by ``rule figures``.
    """

    name: str
    section: str
    rendered: bool = False

    @property
    def path(self) -> str:
        return f"results/figures/{self.name}.png"

    @property
    def caption_file(self) -> str:
        """The caption's path relative to workflow/rules/ (as ``report(caption=...)`` takes it)."""
        return f"../report/{self.name}.rst"

    @property
    def draw(self) -> str:
        """Name of the function of :mod:`roughlight.report.figures` that draws it."""
        return self.name if self.name.startswith("fig") else f"fig_{self.name}"

    @property
    def module(self) -> str:
        """The module that holds :attr:`draw`: its section's module of :mod:`roughlight.report.figures`."""
        return f"roughlight.report.figures.{SECTION_MODULES[self.section]}"


#: Snakemake report subcategory of each section of the HTML page.
SUBCATEGORIES = {"specular": "Specular", "diffuse": "Diffuse", "pictures": "Pictures", "lobes": "Beyond the thesis",
                 "glm": "Beyond the thesis", "models": "Beyond the thesis", "provenance": "Provenance"}

#: The module of :mod:`roughlight.report.figures` that draws each section's figures (the render times, shown
#: under provenance, with the other speed charts).
SECTION_MODULES = {"specular": "specular", "diffuse": "diffuse", "pictures": "pictures", "lobes": "lobes",
                   "glm": "glm", "models": "models", "provenance": "speed"}

#: Every figure, in the order the HTML page shows them within a section.
FIGURES = (
    Figure("fig17_clipping", "specular", rendered=True),
    Figure("fig20_plate_incidence", "specular", rendered=True),
    Figure("fig21_specular_truncation", "specular"),
    Figure("fig23_forward_models", "specular"),
    Figure("fig24_reflecting_areas", "specular"),
    Figure("fig25_back_models", "specular"),
    Figure("fig26_specular_aspect", "specular"),
    Figure("fig19_topdown", "specular"),
    Figure("fig27_diffuse_plate", "diffuse"),
    Figure("fig28_diffuse_truncation", "diffuse"),
    Figure("fig29_diffuse_aspect", "diffuse"),
    Figure("diffuse_parts", "diffuse"),
    Figure("fig09_shadows", "pictures", rendered=True),
    Figure("fig10_grazing", "pictures", rendered=True),
    Figure("fig13_tops", "pictures", rendered=True),
    Figure("lobe_geometry", "lobes"),
    Figure("glm_diagnostics", "glm"),
    Figure("model_fits", "models"),
    Figure("hapke", "models"),
    Figure("timings", "provenance"),
)

_BY_NAME = {f.name: f for f in FIGURES}


def figures(rendered: bool | None = None, section: str | None = None) -> list[Figure]:
    """The figures, optionally only the rendered (or drawn) ones, or one section's."""
    return [f for f in FIGURES if (rendered is None or f.rendered == rendered) and (section is None or f.section == section)]


def caption(name: str) -> dict:
    """Title and caption of a figure from its .rst file: ``{"title", "thesis", "ours"}`` (plain text)."""
    if name not in _BY_NAME:
        raise KeyError(f"no figure {name!r} in the registry")
    text = (CAPTION_DIR / f"{name}.rst").read_text(encoding="utf-8")
    title = re.search(r"^\*\*(.+?)\.?\*\*", text, re.M)
    thesis = re.search(r"^\*Thesis:\*\s*(.+?)\s*(?=^\*Ours:\*|\Z)", text, re.M | re.S)
    ours = re.search(r"^\*Ours:\*\s*(.+?)\s*\Z", text, re.M | re.S)
    return {
        "title": title.group(1).strip() if title else name,
        "thesis": " ".join(thesis.group(1).split()) if thesis else "",
        "ours": " ".join(ours.group(1).split()) if ours else "",
    }


def title(name: str) -> str:
    """A figure's title (the bold first line of its caption)."""
    return caption(name)["title"]


@dataclass(frozen=True)
class Section:
    """One section of the HTML page.

    Attributes
    ----------
    name : str
        The section's name: the page's data for ``templates/base.html`` (which includes its template with that
        data as ``s``). A function's parameter called ``section`` is given this name.
    module : str
        The module of :mod:`roughlight.report` that holds :attr:`build`.
    build : str
        The function that gathers the section's data from its inputs, named by its parameters; it returns a dict,
        or None when the section's inputs were not given (the page says the section is switched off).
    template : str
        The template under ``templates/`` that renders the data.
    """

    name: str
    module: str
    build: str
    template: str

    @property
    def path(self) -> str:
        """The module's full name."""
        return f"roughlight.report.{self.module}"


#: The page's sections, in the order their data are gathered: the page's order, but for the findings, gathered last
#: since they say which sections are on the page (``shown``).
SECTIONS = (
    Section("explorer", "page_explorer", "explorer_section", "explorer.html"),
    Section("study", "page_sections", "study_section", "study.html"),
    Section("tables", "page_thesis", "tables_section", "tables.html"),
    Section("specular", "page_sections", "figure_section", "figures.html"),
    Section("diffuse", "page_sections", "figure_section", "figures.html"),
    Section("diffuse_parts", "page_sections", "diffuse_parts_section", "diffuse_parts.html"),
    Section("pictures", "page_sections", "figure_section", "figures.html"),
    Section("lobes", "page_sections", "lobes_section", "lobes.html"),
    Section("glm", "page_sections", "glm_section", "glm.html"),
    Section("models", "page_sections", "models_section", "models.html"),
    Section("implicit", "page_measurements", "implicit_data", "implicit.html"),
    Section("random", "page_measurements", "random_data", "random.html"),
    Section("stability", "page_measurements", "stability_data", "stability.html"),
    Section("regressions", "page_sections", "regressions_section", "regressions.html"),
    Section("provenance", "page_sections", "provenance_section", "provenance.html"),
    Section("findings", "page_findings", "findings_section", "findings.html"),
)

_SECTIONS_BY_NAME = {s.name: s for s in SECTIONS}


def section(name: str) -> Section:
    """The section of the page called ``name``."""
    if name not in _SECTIONS_BY_NAME:
        raise KeyError(f"no section {name!r} in the registry")
    return _SECTIONS_BY_NAME[name]
