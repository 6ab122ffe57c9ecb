"""The page's figures of the diffuse component, Figs. 27-29: the registry's figures of section ``diffuse``
(``templates/figures.html``)."""

from __future__ import annotations

from ..page_templates import figure_section
from ..registry import Section, figures

SECTION = Section("diffuse", figure_section, "figures.html", title="Diffuse: Figs. 27–29",
                  inputs={"figures": tuple(f.path for f in figures(section="diffuse"))})
