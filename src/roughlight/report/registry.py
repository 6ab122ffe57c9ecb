"""The report's figures, and what a section of the page declares: the list of figures and the :class:`Section` type,
from which the workflow, the figure scripts and the HTML page are made.

Each :class:`Figure` names a PNG under ``results/figures/``, where it sits in the
report (Snakemake's ``report()`` category and subcategory, the HTML page's
section) and whether it is drawn from the analysis tables or rendered. Its title
and caption live in one place, ``workflow/report/{name}.rst`` (what Snakemake's
``report(caption=...)`` reads): a bold title line, then ``*Thesis:*`` (what the
thesis saw) and ``*Ours:*`` (what we see); :func:`caption` reads them for the
HTML page. The function that draws a figure is ``{name}`` (``fig_{name}`` for names that do not start with
``fig``) of its section's module of :mod:`roughlight.report.figures` (:data:`SECTION_MODULES`), and is
importable from :mod:`roughlight.report.figures` itself too.

Each :class:`Section` of the page is declared by its own module of :mod:`roughlight.report.sections`: its title and
anchor, its template, the results it reads and the config switch that turns it on, and a function from its inputs
to the data its template (``templates/{template}``) renders. The function names its inputs by its parameter names,
which are the names of the analysis outputs (their files' stems; a chart's stem and ``_png``, as rule
``report_html`` names its inputs), of the figures (``figures``) and of the settings (``table_aspects``, ``plan``,
...). :data:`roughlight.report.sections.SECTIONS` lists them in the page's order.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

#: workflow/report/: the captions (reStructuredText), beside the rules that cite them.
CAPTION_DIR = Path(__file__).resolve().parent / "captions"  # workflow/report links to it


@dataclass(frozen=True)
class Figure:
    """One figure of the report: every chart of the page, whichever rule draws it.

    Attributes
    ----------
    name : str
        File stem: ``{folder}/{name}.png``, caption ``workflow/report/{name}.rst``.
    section : str
        The HTML page's section (``specular``, ``diffuse``, ``pictures``, ``lobes``, ``glm``, ``models``,
        ``provenance``, ``speed``, ``stability``, ``implicit``, ``random``).
    rule : str
        The rule that draws it: ``figures`` (from the study and analysis tables), ``render_figures`` (plate sweeps
        and pictures it renders), or the measurement or analysis rule whose tables it charts.
    folder : str
        Where it is written (``{plan}``: ``measurements.plan``, as the measurement rules' wildcard).
    dpi : int or None
        Its resolution (None: :data:`roughlight.report.figures.DPI`).
    tight : bool
        Whether it is saved with a tight bounding box.
    folded : bool
        Whether the HTML page shows it folded, under its title (secondary to its section: a diagnostic, a timing),
        so that what a reader must see stays open and the page short (docs/report.md, "Size and speed").
    """

    name: str
    section: str
    rule: str = "figures"
    folder: str = "results/figures"
    dpi: int | None = None
    tight: bool = True
    folded: bool = False

    @property
    def rendered(self) -> bool:
        """Whether it is rendered (rule ``render_figures``) rather than drawn from tables."""
        return self.rule == "render_figures"

    @property
    def path(self) -> str:
        return f"{self.folder}/{self.name}.png"

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


#: Snakemake report subcategory of each section of the HTML page whose figures rules ``figures`` and
#: ``render_figures`` draw (the measurement rules' charts are in categories of their own).
SUBCATEGORIES = {"specular": "Specular", "diffuse": "Diffuse", "pictures": "Pictures", "lobes": "Beyond the thesis",
                 "glm": "Beyond the thesis", "models": "Beyond the thesis", "provenance": "Provenance"}

#: The module of :mod:`roughlight.report.figures` that draws each section's figures (the render times, shown
#: under provenance, with the other speed charts).
SECTION_MODULES = {"specular": "specular", "diffuse": "diffuse", "pictures": "pictures", "lobes": "lobes",
                   "glm": "glm", "models": "models", "provenance": "speed", "speed": "speed",
                   "stability": "stability", "implicit": "implicit", "random": "random_roughness",
                   "light_transport": "light_transport", "export": "export"}

_BENCHMARKS = "results/benchmarks/{plan}"

#: Every figure, in the order the HTML page shows them within a section.
FIGURES = (
    Figure("fig17_clipping", "specular", rule="render_figures"),
    Figure("fig20_plate_incidence", "specular", rule="render_figures"),
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
    Figure("fig09_shadows", "pictures", rule="render_figures"),
    Figure("fig10_grazing", "pictures", rule="render_figures"),
    Figure("fig13_tops", "pictures", rule="render_figures"),
    Figure("lobe_geometry", "lobes"),
    Figure("glm_diagnostics", "glm", folded=True),
    Figure("model_fits", "models"),
    Figure("hapke", "models", folded=True),
    Figure("timings", "provenance", folded=True),
    Figure("implicit", "implicit", rule="implicit_surface", folder=_BENCHMARKS, dpi=120),
    Figure("implicit_maps", "implicit", rule="implicit_surface", folder=_BENCHMARKS, dpi=110),
    Figure("random_ensembles", "random", rule="analysis_random"),
    Figure("random_maps", "random", rule="analysis_random"),
    Figure("random_tiles", "random", rule="random_tiles", folder=_BENCHMARKS),
    Figure("stability", "stability", rule="stability", folder="results/stability/{plan}", dpi=80, tight=False),
    Figure("speed_accuracy", "speed", rule="speed_accuracy", folder=_BENCHMARKS, dpi=120),
    Figure("renderer_validation", "speed", rule="renderer_validation", folder=_BENCHMARKS, dpi=120),
    Figure("light_transport", "light_transport", rule="light_transport", folder=_BENCHMARKS, dpi=110),
    Figure("export", "export", rule="export_summary", folder="results/export", dpi=100),
)

_BY_NAME = {f.name: f for f in FIGURES}


def figures(rule: str | None = None, section: str | None = None) -> list[Figure]:
    """The figures, optionally only those one rule draws, or one section's."""
    return [f for f in FIGURES if (rule is None or f.rule == rule) and (section is None or f.section == section)]


def figure(name: str) -> Figure:
    """The registry's figure called ``name``."""
    if name not in _BY_NAME:
        raise KeyError(f"no figure {name!r} in the registry")
    return _BY_NAME[name]


#: An RST inline literal (its text between two pairs of backquotes): Snakemake's report sets it as code, the HTML
#: page as its plain text.
_LITERAL = re.compile(r"``(.+?)``", re.S)


def caption_source(name: str) -> str:
    """A caption file's text (``captions/{name}.rst``) as the HTML page shows it: plain text, its inline literals'
    markup taken off (the page escapes what it shows; only Snakemake's report renders the RST)."""
    return _LITERAL.sub(r"\1", (CAPTION_DIR / f"{name}.rst").read_text(encoding="utf-8"))


def caption(name: str) -> dict:
    """Title and caption of a figure from its .rst file: ``{"title", "thesis", "ours"}`` (plain text)."""
    if name not in _BY_NAME:
        raise KeyError(f"no figure {name!r} in the registry")
    text = caption_source(name)
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
    """One section of the HTML page, as its module under :mod:`roughlight.report.sections` declares it.

    Attributes
    ----------
    name : str
        The section's name: its data on the page (``templates/base.html`` includes its template with that data as
        ``s``). A function's parameter called ``section`` is given this name.
    build : callable
        The function that gathers the section's data from its inputs, named by its parameters (a parameter
        ``shown``, which sections are on the page, makes it gathered after the others); it returns a dict, or None
        when the section is switched off (its template then says so).
    template : str
        The template under ``templates/`` that renders the data.
    title : str or None
        Its entry in the page's contents (None: it has none, being part of the section before it).
    anchor : str or None
        The id its entry links to (None: ``name``).
    inputs : dict
        What the section reads, name -> path as the workflow writes it (``{plan}``: ``measurements.plan``);
        ``figures``: a tuple of the registry's figure paths. Rule ``report_html`` takes the union of the sections'
        inputs that are switched on (:func:`roughlight.report.sections.inputs`).
    switch : str, callable or None
        What turns the section on: a dotted config key that holds a bool (``"report.implicit"``), or a function of
        the config; None: always on. A switched-off section's inputs are not made, and its function gets None.
    """

    name: str
    build: Callable
    template: str
    title: str | None = None
    anchor: str | None = None
    inputs: Mapping = field(default_factory=dict)
    switch: str | Callable | None = None

    @property
    def link(self) -> str:
        """The id its entry in the contents links to."""
        return self.anchor or self.name

    def switched_on(self, config: Mapping) -> bool:
        """Whether ``config`` (the workflow's, validated) turns the section on."""
        if self.switch is None:
            return True
        if callable(self.switch):
            return bool(self.switch(config))
        value = config
        for key in self.switch.split("."):
            value = value[key]
        return bool(value)

    def paths(self, plan: str) -> dict:
        """Its inputs with ``{plan}`` filled in: name -> path (``figures``: a list of paths)."""
        return {name: [p.format(plan=plan) for p in path] if isinstance(path, (list, tuple)) else path.format(plan=plan)
                for name, path in self.inputs.items()}


#: The page's own code, under this package: what rule ``report_html`` writes the page with (its sections, templates
#: and captions); ``figures/`` is drawn by the figure rules and left out.
PAGE_CODE_SKIP = ("figures", "__pycache__", "README.md")


def page_code_digest(root=None) -> str:
    """A SHA-256 digest of the page's own code: every file under ``root`` (default: the report package) but
    :data:`PAGE_CODE_SKIP`, by relative path and content. Rule ``report_html`` takes it as a param, so that a
    changed template, caption or section reruns the page (Snakemake's code trigger sees its script alone)."""
    import hashlib

    root = Path(__file__).resolve().parent if root is None else Path(root)
    digest = hashlib.sha256()
    for path in sorted(p for p in root.rglob("*") if p.is_file()):
        rel = path.relative_to(root)
        if rel.parts[0] in PAGE_CODE_SKIP or "__pycache__" in rel.parts:
            continue
        digest.update(str(rel).encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()
