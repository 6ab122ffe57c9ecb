"""The report's sections: one module a section, and :data:`SECTIONS`, the list that gives the page its order.

A section's module holds everything about it: the function that gathers its data from its inputs (named by its
parameters) and its declaration, ``SECTION`` (:class:`roughlight.report.registry.Section`): its title and anchor
in the page's contents, its template under ``templates/``, the results it reads (name -> path) and the config
switch that turns it on. ``templates/base.html`` loops over :data:`SECTIONS` for the contents and the body, and rule
``report_html`` takes its inputs from the same declarations (:func:`inputs`). Adding a section is one module, one
template and one line here (``report/README.md``).
"""

from __future__ import annotations

from collections.abc import Mapping

from ..registry import Section
from . import (
    diffuse,
    diffuse_parts,
    explorer,
    export,
    findings,
    glm,
    implicit,
    light_transport,
    lobes,
    models,
    pictures,
    provenance,
    random,
    regressions,
    specular,
    speed,
    stability,
    study,
    tables,
)

__all__ = ["SECTIONS", "section", "inputs"]

#: The page's sections in the page's order: the findings first (above the contents), then the contents' order.
SECTIONS: tuple[Section, ...] = (
    findings.SECTION,
    explorer.SECTION,
    study.SECTION,
    tables.SECTION,
    specular.SECTION,
    diffuse.SECTION,
    diffuse_parts.SECTION,
    pictures.SECTION,
    lobes.SECTION,
    glm.SECTION,
    models.SECTION,
    implicit.SECTION,
    export.SECTION,
    random.SECTION,
    light_transport.SECTION,
    stability.SECTION,
    regressions.SECTION,
    speed.SECTION,
    provenance.SECTION,
)

_BY_NAME = {s.name: s for s in SECTIONS}


def section(name: str) -> Section:
    """The section of the page called ``name``."""
    if name not in _BY_NAME:
        raise KeyError(f"no section {name!r} in the registry")
    return _BY_NAME[name]


def inputs(config: Mapping, plan: str) -> dict:
    """What rule ``report_html`` reads: the union of the inputs of every section ``config`` switches on, with
    ``{plan}`` filled in (``measurements.plan``), by name; ``figures``: one list of paths.

    A name two sections read must name one path (``ValueError`` otherwise)."""
    out: dict = {}
    for s in SECTIONS:
        if not s.switched_on(config):
            continue
        for name, path in s.paths(plan).items():
            if isinstance(path, list):
                out[name] = out.get(name, []) + [p for p in path if p not in out.get(name, [])]
            elif out.setdefault(name, path) != path:
                raise ValueError(f"sections read {name!r} from two paths: {out[name]} and {path}")
    return out
