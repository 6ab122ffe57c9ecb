"""The page's figures of the specular component, Figs. 17-26: the registry's figures of section ``specular``
(``templates/figures.html``)."""

from __future__ import annotations

from ..page_templates import figure_section
from ..registry import Section, figures

SECTION = Section("specular", figure_section, "figures.html", title="Specular: Figs. 17–26",
                  inputs={"figures": tuple(f.path for f in figures(section="specular"))})
