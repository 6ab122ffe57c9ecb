"""The page's figures of pictures of the surfaces, Figs. 9, 10 and 13: the registry's figures of section ``pictures``
(``templates/figures.html``)."""

from __future__ import annotations

from ..page_templates import figure_section
from ..registry import Section, figures

SECTION = Section("pictures", figure_section, "figures.html", title="Pictures: Figs. 9, 10, 13",
                  inputs={"figures": tuple(f.path for f in figures(section="pictures"))})
