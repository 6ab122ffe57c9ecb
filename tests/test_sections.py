"""The report's sections as their modules declare them (roughlight.report.sections): one list gives the page its
order, and the rule that builds the page reads what the declarations name, for the sections the config switches
on."""

from __future__ import annotations

import inspect
from pathlib import Path

import pytest

from roughlight.report import registry, sections
from roughlight.study import config as rl_config

TEMPLATES = Path(registry.__file__).resolve().parent / "templates"
#: What a section's function may take that is not a workflow result: settings and the page's own state.
SETTINGS = {"section", "shown", "config", "provenance", "plan", "surface_settings", "followed", "table_aspects",
            "table_incidence"}


def default_config(**report):
    config = rl_config.validate_config({"report": report} if report else {})
    return config


def test_each_section_is_one_module_with_its_declaration():
    names = [s.name for s in sections.SECTIONS]
    assert len(names) == len(set(names))
    modules = {p.stem for p in Path(sections.__file__).parent.glob("*.py")} - {"__init__"}
    for s in sections.SECTIONS:
        module = inspect.getmodule(s.build)
        assert module.__name__.startswith("roughlight.report"), s.name
        assert (TEMPLATES / s.template).exists(), s.name
    # every module of sections/ is a section on the page (none left out of the list)
    declared = {inspect.getmodule(s.build).__name__.rsplit(".", 1)[-1] for s in sections.SECTIONS}
    assert modules - declared <= {"specular", "diffuse", "pictures"}  # these three share the figures' function
    assert sections.SECTIONS[0].name == "findings"  # above the contents
    assert [s.link for s in sections.SECTIONS if s.title][:3] == ["findings", "explorer", "study"]


def test_a_declaration_names_what_its_function_reads():
    """Every result a section declares is a parameter of its function, and every parameter of a function that is
    not a setting is declared by some section (so the rule reads it)."""
    declared = set()
    for s in sections.SECTIONS:
        params = set(inspect.signature(s.build).parameters)
        assert set(s.inputs) - {"study"} <= params, (s.name, set(s.inputs) - params)
        declared |= set(s.inputs)
    for s in sections.SECTIONS:
        wanted = set(inspect.signature(s.build).parameters) - SETTINGS
        assert wanted <= declared, (s.name, wanted - declared)


def test_the_rule_reads_the_switched_on_sections_inputs():
    on = sections.inputs(default_config(), "quick")  # the schema's defaults: the regular surface alone
    assert on["implicit_validation"] == "results/benchmarks/quick/implicit_validation.parquet"
    assert on["stability_png"] == "results/stability/quick/stability.png"
    assert on["explorer_data"] == "results/analysis/explorer_data.json"
    assert sorted(on["figures"]) == sorted(f.path for f in registry.FIGURES if f.rule in ("figures", "render_figures"))
    off = sections.inputs(default_config(implicit=False, stability=False, speed_accuracy=False,
                                         explorer={"enabled": False}), "quick")
    for name in ("implicit_validation", "stability", "speed_accuracy", "renderer_validation", "explorer_data"):
        assert name in on and name not in off, name
    assert off["thesis_tables"] == on["thesis_tables"] == "results/analysis/thesis_tables.csv"
    random = rl_config.validate_config({"surface": {"kind": ["pyramids", "random_pyramids"]}})
    assert "random_claims" in sections.inputs(random, "quick") and "random_claims" not in on


def test_two_sections_may_not_read_one_name_from_two_paths(monkeypatch):
    clash = registry.Section("clash", lambda thesis_tables=None: {}, "study.html",
                             inputs={"thesis_tables": "results/elsewhere.csv"})
    monkeypatch.setattr(sections, "SECTIONS", sections.SECTIONS + (clash,))
    with pytest.raises(ValueError, match="thesis_tables"):
        sections.inputs(default_config(), "quick")


def test_the_contents_and_the_body_follow_the_list():
    from roughlight.report import page

    html = page.build_report({}, {})
    nav = html[html.index("<nav>"):html.index("</nav>")]
    links = [s.link for s in sections.SECTIONS if s.title]
    positions = [nav.index(f'href="#{link}"') for link in links]
    assert positions == sorted(positions)
    body = [html.index(f'id="{link}"') for link in links[1:]]  # the findings sit above the contents
    assert body == sorted(body) and html.index('id="findings"') < html.index("<nav>")
