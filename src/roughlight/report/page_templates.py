"""The page's templates: one Jinja2 environment over ``templates/`` (shipped with the package), its filters, and
the helpers every section's module shares.

The templates hold the page's layout and sentences; Python hands them data frames, numbers and plain strings.
Numbers are formatted by the filters registered here (``cell`` for a table cell, ``fmt`` for a format spec,
``domain`` for a safe-domain bound, ``aspect`` for an aspect's label),
figures are inlined by ``png_data_uri``. Autoescape is on: every string a template prints is escaped.
"""

from __future__ import annotations

import base64
import math
import os
from functools import cache

import jinja2
import markupsafe
import numpy as np
import pandas as pd

from ..surfaces.surface import aspect_label
from . import registry

TABLE_CAPTIONS = {
    "thesis_tables": "Tables 1 and 2 of the thesis recomputed from our lobe peaks (incidence 30), beside the "
                     "thesis's values and the same statistics on exact (polygon clipping) peaks.",
    "bootstrap_tables": "Sensitivity of our Tables 1–2 statistics to which truncations enter them: 95% percentile "
                        "ranges over resampled truncations. The renders are deterministic, so these are not "
                        "sampling uncertainty",
    "sine_refits": "Nonlinear least-squares refits of the thesis's sine models, with 95% intervals computed as if "
                   "the residuals were noise: the data are deterministic, the residuals are lack of fit, so read "
                   "them as the fit's sensitivity, not as sampling uncertainty.",
    "glm_summary": "Grid GLMs (Gaussian, IRLS): convergence, condition numbers and what was kept out.",
    "share_laws": "Combined models of the lobe peaks: RMSE over the grid (in-sample) and leave-one-surface-out "
                  "(0-255), with the free parameters each fits.",
    "glm_coefficients": "Grid GLM coefficients, with standard errors, p-values and 95% intervals computed as if the "
                        "residuals were noise: the data are deterministic, the residuals are lack of fit, so these "
                        "measure sensitivity, not sampling uncertainty.",
    "model_fits_summary": "Analytic models: median RMSE and number of surfaces where each fits best, by band.",
}


# ---------------------------------------------------------------------------
# filters and tests


def png_data_uri(path) -> str:
    """A PNG file as a ``data:`` URI (the page loads nothing from anywhere)."""
    with open(path, "rb") as fh:
        data = fh.read()
    if not data.startswith(b"\x89PNG\r\n\x1a\n"):
        raise ValueError(f"{path} is not a PNG file")
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


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
                       png_data_uri=png_data_uri)
    env.tests["finite"] = finite
    env.globals["table_captions"] = TABLE_CAPTIONS
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
    """One figure of the registry for ``macros.html``'s ``figure``: its caption, its PNG and whether it exists."""
    cap = registry.caption(stem)
    path = figures.get(stem)
    return {"stem": stem, "title": cap["title"], "thesis": cap["thesis"], "ours": cap["ours"], "path": path,
            "exists": bool(path and os.path.exists(path))}


def section_figures(section: str, figures: dict) -> list[dict]:
    """The registry's figures of one section of the page, in page order."""
    return [figure(f.name, figures) for f in registry.figures(section=section)]


def caption_text(name: str) -> str:
    """A caption's whole text from ``workflow/report/{name}.rst`` (for parts the registry does not list)."""
    return (registry.CAPTION_DIR / f"{name}.rst").read_text(encoding="utf-8").strip()


def existing(path) -> str | None:
    """``path`` if it names a file, else None (a chart that was not made is left out)."""
    return path if path and os.path.exists(path) else None


def frame_or_none(df) -> pd.DataFrame | None:
    """A frame with rows, or None."""
    return df if df is not None and len(df) else None
