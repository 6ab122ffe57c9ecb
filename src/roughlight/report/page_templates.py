"""The page's templates: one Jinja2 environment over ``templates/`` (shipped with the package), its filters, and
the helpers every section's module shares.

The templates hold the page's layout and sentences; Python hands them data frames, numbers and plain strings.
Numbers are formatted by the filters registered here (``cell`` for a table cell, ``fmt`` for a format spec,
``domain`` for a safe-domain bound, ``aspect`` for an aspect's label),
figures are inlined by ``png_data_uri``. Autoescape is on: every string a template prints is escaped.

A table of more than :data:`FOLD_ROWS` rows is folded (``macros.html``'s ``table``): it sits in a closed
``<details>`` under a one-line summary (``fold_summary``) with its whole frame as a CSV link (``csv_data_uri``,
``csv_name``); column labels may wrap after an underscore (``breakable``).
"""

from __future__ import annotations

import base64
import hashlib
import inspect
import math
import os
import re
from functools import cache

import jinja2
import markupsafe
import numpy as np
import pandas as pd

from ..surfaces.surface import aspect_label
from . import registry

#: The tables whose page caption is the ``*On the page:*`` paragraph of ``captions/{name}.rst`` (the same file
#: Snakemake's report shows): a table's caption is written once, there (:func:`table_caption`).
TABLE_CAPTION_NAMES = ("thesis_tables_bootstrap", "sine_refits", "glm_summary", "share_laws", "glm_coefficients",
                       "model_fits_summary")


#: A table of more rows than this is folded under a one-line summary, its data downloadable as CSV: the issue asks
#: for more than 20, and ten keeps the default report within 25,000 px with every fold closed (docs/report.md).
FOLD_ROWS = 10
#: A folded table's summary line: at most this many characters of its caption (then its row count).
SUMMARY_CHARS = 100


# ---------------------------------------------------------------------------
# filters and tests


def png_data_uri(path) -> str:
    """A PNG file as a ``data:`` URI (the page loads nothing from anywhere)."""
    with open(path, "rb") as fh:
        data = fh.read()
    if not data.startswith(b"\x89PNG\r\n\x1a\n"):
        raise ValueError(f"{path} is not a PNG file")
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def content_security_policy(scripts=()) -> str:
    """The page's Content-Security-Policy: nothing loads from anywhere (no fetch, font, frame or remote image), the
    stylesheet and images are inline (``data:``), and the only scripts that run are ``scripts``, the texts of the
    page's own inline ``<script>`` elements, each allowed by its SHA-256 (none: no script runs at all)."""
    hashes = " ".join(f"'sha256-{base64.b64encode(hashlib.sha256(s.encode('utf-8')).digest()).decode()}'"
                      for s in scripts)
    script_src = hashes or "'none'"
    return (f"default-src 'none'; img-src data:; style-src 'unsafe-inline'; script-src {script_src}; "
            "base-uri 'none'; form-action 'none'")


def cell(x, digits=3) -> str:
    """A table cell: numbers to ``digits`` decimals, NaN as –, infinity as ∞, no "-0.000", booleans as yes/no."""
    if x is None:
        return ""
    if isinstance(x, (bool, np.bool_)):
        return "yes" if x else "no"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    try:
        xf = float(x)
    except (TypeError, ValueError):
        return str(x)
    if math.isnan(xf):
        return "–"
    if math.isinf(xf):
        return "∞"
    text = f"{xf:.{digits}f}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def fmt(x, spec: str = "") -> str:
    """``format(x, spec)``: the template's f-string (``{{ x|fmt('.2f') }}``)."""
    return format(x, spec)


def domain(v) -> str:
    """A safe-domain cell: a bound to 3 significant digits, 'never' where no tested value was within tolerance."""
    if isinstance(v, str):
        return v
    if v is None or (isinstance(v, float) and not np.isfinite(v)):
        return "never"
    return f"{v:.3g}"


def rows(df: pd.DataFrame) -> list[list]:
    """A frame's rows as lists of values, as ``iterrows`` gives them (a row of numbers only is all floats)."""
    return [list(row.to_numpy()) for _, row in df.iterrows()]


def breakable(text) -> markupsafe.Markup:
    """A column label escaped, with a line break allowed after each underscore (``<wbr>``): long snake_case
    labels wrap instead of widening their table. The text is unchanged."""
    return markupsafe.Markup(str(markupsafe.escape(text)).replace("_", "_<wbr>"))


def csv_text(df: pd.DataFrame) -> str:
    """A frame as CSV: every row and column, no index, numbers at full precision (the shortest text that reads
    back to the same float)."""
    return df.to_csv(index=False, lineterminator="\n")


def csv_data_uri(df: pd.DataFrame) -> str:
    """A frame's CSV (``csv_text``) as a ``data:`` URI, for a download link that needs no server."""
    return "data:text/csv;charset=utf-8;base64," + base64.b64encode(csv_text(df).encode("utf-8")).decode("ascii")


def csv_name(name: str) -> str:
    """A download's file name from a table's id (or caption): lower case letters, digits and dashes, ``.csv``."""
    slug = re.sub(r"[^a-z0-9]+", "-", str(name).lower()).strip("-")[:60].strip("-")
    return f"{slug or 'table'}.csv"


def fold_summary(caption: str, n_rows: int, limit: int = SUMMARY_CHARS) -> str:
    """A folded table's one-line summary: its caption, cut at the last clause (``:``, ``;``, ``,`` or `` (``)
    that leaves its brackets closed and fits in ``limit`` characters (else at a word; a clause of fewer than 20
    characters says too little), and its row count: "Seeds needed for a 95% interval … (96 rows)"."""
    text = " ".join(str(caption or "Table").split()).rstrip(".")
    if len(text) > limit:
        cuts = [m.start() for m in re.finditer(r"[:;,]\s| \(", text)
                if m.start() <= limit and text[:m.start()].count("(") == text[:m.start()].count(")")]
        cut = cuts[-1] if cuts and cuts[-1] >= 20 else text.rfind(" ", 0, limit)
        text = text[:cut if cut > 0 else limit].rstrip(" ,;:") + " …"
    return f"{text} ({n_rows:,} rows)"


def finite(x) -> bool:
    """Jinja test ``is finite``: a number that is neither NaN nor infinite."""
    return bool(np.isfinite(x))


# ---------------------------------------------------------------------------
# the environment


@cache
def environment() -> jinja2.Environment:
    """The templates' environment (autoescape on, undefined names an error), loaded from the installed package."""
    env = jinja2.Environment(loader=jinja2.PackageLoader("roughlight.report", "templates"), autoescape=True,
                             undefined=jinja2.StrictUndefined, trim_blocks=True, lstrip_blocks=True)
    env.filters.update(cell=cell, fmt=fmt, domain=domain, rows=rows, aspect=aspect_label,
                       png_data_uri=png_data_uri, breakable=breakable, csv_data_uri=csv_data_uri, csv_name=csv_name,
                       fold_summary=fold_summary)
    env.tests["finite"] = finite
    env.globals["table_captions"] = table_captions()
    env.globals["fold_rows"] = FOLD_ROWS
    return env


def render(name: str, **context) -> str:
    """Render ``templates/{name}`` with ``context``; the HTML without leading or trailing whitespace."""
    return environment().get_template(name).render(**context).strip()


def render_macro(template: str, macro: str, *args) -> str:
    """Call the macro ``macro`` of ``templates/{template}`` (the HTML it gives)."""
    return str(getattr(environment().get_template(template).module, macro)(*args)).strip()


def plain_text(html: str) -> str:
    """A template's sentence as plain text (its entities unescaped)."""
    return markupsafe.Markup(html).unescape()


def safe(fragment: str | None):
    """An HTML fragment rendered by this package's own templates, to be placed on the page as it is."""
    return markupsafe.Markup(fragment) if fragment else None


# ---------------------------------------------------------------------------
# data the templates share


def figure(stem: str, figures: dict) -> dict:
    """One figure of the registry for ``macros.html``'s ``figure``: its caption, its PNG, whether it exists and
    whether the page folds it (the registry's ``folded``)."""
    cap = registry.caption(stem)
    path = figures.get(stem)
    return {"stem": stem, "title": cap["title"], "thesis": cap["thesis"], "ours": cap["ours"], "path": path,
            "exists": bool(path and os.path.exists(path)), "folded": registry.figure(stem).folded}


def section_figures(section: str, figures: dict) -> list[dict]:
    """The registry's figures of one section of the page, in page order."""
    return [figure(f.name, figures) for f in registry.figures(section=section)]


def figure_section(section: str, figures: dict | None = None) -> dict:
    """A figure section of the page (specular, diffuse, pictures; ``templates/figures.html``): its registry
    figures."""
    return {"section": section, "figures": section_figures(section, figures or {})}


def table_caption(name: str) -> str:
    """A table's caption on the page: the ``*On the page:*`` paragraph of ``captions/{name}.rst``, as one line."""
    text = registry.caption_source(name)
    found = re.search(r"^\*On the page:\*\s*(.+?)\s*(?=^\*|\Z)", text, re.M | re.S)
    if not found:
        raise ValueError(f"captions/{name}.rst has no *On the page:* paragraph")
    return " ".join(found.group(1).split())


def table_captions() -> dict:
    """Every :data:`TABLE_CAPTION_NAMES` table's page caption (:func:`table_caption`), by name."""
    return {name: table_caption(name) for name in TABLE_CAPTION_NAMES}


def caption_text(name: str) -> str:
    """A caption's whole text from ``workflow/report/{name}.rst`` (for parts the registry does not list)."""
    return registry.caption_source(name).strip()


def existing(path) -> str | None:
    """``path`` if it names a file, else None (a chart that was not made is left out)."""
    return path if path and os.path.exists(path) else None


def frame_or_none(df) -> pd.DataFrame | None:
    """A frame with rows, or None."""
    return df if df is not None and len(df) else None


def named_arguments(function, values: dict) -> dict:
    """What ``function``'s parameters name, taken from ``values`` by name (a name ``values`` lacks leaves its
    parameter at its default): how a section's function is given its inputs."""
    return {name: values[name] for name in inspect.signature(function).parameters if name in values}
