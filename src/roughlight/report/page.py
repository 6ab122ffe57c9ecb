"""The study's report: one self-contained HTML page (tables inline, figures as data URIs).

:func:`build_report` takes the analysis tables (:mod:`roughlight.analysis.lobes`,
:mod:`roughlight.analysis.thesis`, :mod:`roughlight.analysis.glm`, ...), the figure PNGs
(:mod:`roughlight.report.figures`), the configuration and provenance, and returns the
page as a string, one function a section (``_section_*``) over shared HTML
helpers; :func:`write_report` writes it atomically. The page loads nothing from
anywhere: no scripts, no fonts, no external images, so it opens from disk
without a server. Each figure's title and caption (what the thesis, Slattery
2001, saw and what our study shows) come from :mod:`roughlight.report.registry`, that
is from ``workflow/report/*.rst``, the same text ``snakemake --report`` shows.
"""

from __future__ import annotations

import base64
import datetime as _dt
import hashlib
import html
import importlib.metadata
import math
import os
import platform
from pathlib import Path

import numpy as np
import pandas as pd

from ..analysis.thesis import TABLE_ASPECTS, TABLE_METRICS, THESIS_INCIDENCE, THESIS_TABLES, sd_bound
from ..atomic import write_text_atomic
from ..study.selection import ASPECT_TOL, SURFACE_KEYS, find_aspect
from ..surfaces.surface import aspect_label
from . import registry

__all__ = [
    "TABLE_CAPTIONS",
    "package_versions",
    "file_provenance",
    "png_data_uri",
    "thesis_table_html",
    "build_report",
    "write_report",
    "stability_section",
    "implicit_section",
]

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
# files and provenance


def package_versions(names=("roughlight", "numpy", "pandas", "pyarrow", "scipy", "statsmodels", "matplotlib",
                            "seaborn", "shapely", "trimesh", "pyrender2", "PyOpenGL", "snakemake")) -> dict:
    """Installed versions of the packages the study uses (missing ones are 'not installed')."""
    out = {"python": platform.python_version()}
    for name in names:
        try:
            out[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def file_provenance(path) -> dict:
    """Size, modification time and SHA-256 of a file."""
    p = Path(path)
    h = hashlib.sha256()
    with open(p, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    st = p.stat()
    return {"path": str(path), "bytes": st.st_size,
            "modified": _dt.datetime.fromtimestamp(st.st_mtime, _dt.UTC).isoformat(timespec="seconds"),
            "sha256": h.hexdigest()}


def png_data_uri(path) -> str:
    with open(path, "rb") as fh:
        data = fh.read()
    if not data.startswith(b"\x89PNG\r\n\x1a\n"):
        raise ValueError(f"{path} is not a PNG file")
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


# ---------------------------------------------------------------------------
# HTML helpers

CSS = """
body{font-family:-apple-system,'Segoe UI',Helvetica,Arial,sans-serif;margin:0;color:#222;background:#fafafa}
main{max-width:1180px;margin:0 auto;padding:1.5em 2em 4em;background:#fff}
h1{font-size:1.7em;margin-bottom:.2em}h2{border-bottom:2px solid #ddd;padding-bottom:.2em;margin-top:2em}
h3{margin-top:1.6em}
table{border-collapse:collapse;margin:.6em 0 1.2em;font-size:.82em}
th,td{border:1px solid #ccc;padding:3px 7px;text-align:right}
th{background:#f0f0f0}td:first-child,th:first-child{text-align:left}
caption{caption-side:top;text-align:left;font-weight:bold;padding:.3em 0}
figure{margin:1.2em 0 2em}figure img{max-width:100%;height:auto;border:1px solid #eee}
figcaption{font-size:.9em;line-height:1.4}figcaption .thesis{color:#555}
.note{background:#fff7e0;border-left:4px solid #e0a800;padding:.4em .8em;margin:.6em 0;font-size:.9em}
.ok{background:#eef8ee;border-left:4px solid #3a3;padding:.4em .8em;margin:.6em 0;font-size:.9em}
pre{background:#f5f5f5;padding:.8em;overflow-x:auto;font-size:.8em}
nav ul{columns:2;font-size:.9em}.ours td.src,.src{font-style:italic}
tr.thesis td{color:#666}tr.exact td{color:#245}
.formula{font-family:Menlo,Consolas,monospace;background:#f5f5f5;padding:0 .3em}
"""


def _e(text) -> str:
    return html.escape(str(text), quote=True)


def _fmt(x, digits=3):
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


def _table(df: pd.DataFrame, caption: str = "", digits: int = 3, table_id: str = "", max_rows: int = 400) -> str:
    """A DataFrame as an HTML table (escaped; numbers formatted)."""
    if df is None or len(df) == 0:
        return f'<p class="note">{_e(caption)}: no rows.</p>'
    df = df.head(max_rows)
    tid = f' id="{_e(table_id)}"' if table_id else ""
    head = "".join(f"<th>{_e(c)}</th>" for c in df.columns)
    body = []
    for _, row in df.iterrows():
        body.append("<tr>" + "".join(f"<td>{_e(_fmt(v, digits))}</td>" for v in row.to_numpy()) + "</tr>")
    cap = f"<caption>{_e(caption)}</caption>" if caption else ""
    return f"<table{tid}>{cap}<thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def thesis_table_html(tables: pd.DataFrame, table: int, aspect: float, incidence: float = THESIS_INCIDENCE) -> str:
    """One of the thesis's Tables 1-2 for one aspect, in the thesis's form, ours beside the thesis's values.

    Rows are the thesis's models; for each model a row per source ('ours',
    'exact geometry' when present, 'thesis 2001'); columns Mean Abs Error,
    Standard Deviation, b0, b1, RSS.
    """
    spec = THESIS_TABLES[table]
    sel = tables[(tables["table"] == table) & (np.abs(tables["aspect"] - aspect) <= ASPECT_TOL)]
    label = aspect_label(aspect)
    tid = f"table{table}-aspect-{label.replace('√3/2', 'sqrt3-2')}"
    metrics = TABLE_METRICS[:2] + ["SD of |error|"] + TABLE_METRICS[2:]  # both readings of the thesis's SD
    head = "<th>Model</th><th>Source</th>" + "".join(f"<th>{_e(m)}</th>" for m in metrics)
    rows = []
    order = {"ours": 0, "exact geometry": 1, "thesis 2001": 2}
    for model in spec["rows"]:
        block = sel[sel["model"] == model].sort_values("source", key=lambda s: s.map(order))
        for k, (_, r) in enumerate(block.iterrows()):
            cls = {"ours": "ours", "exact geometry": "exact", "thesis 2001": "thesis"}[r["source"]]
            first = f'<td rowspan="{len(block)}"><b>{_e(model)}</b></td>' if k == 0 else ""
            digits = {"Mean Abs Error": 2, "Standard Deviation": 2, "SD of |error|": 2, "b0": 3, "b1": 3, "RSS": 3}
            cells = "".join(f"<td>{_e(_fmt(r.get(m), digits[m]))}</td>" for m in metrics)
            rows.append(f'<tr class="{cls}">{first}<td class="src">{_e(r["source"])}</td>{cells}</tr>')
    cap = f"Table {table}: {spec['title']} (aspect {label}, incidence {incidence:g})"
    return (f'<table class="thesis-table" id="{tid}" data-table="{table}" data-aspect="{_e(label)}">'
            f"<caption>{_e(cap)}</caption><thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table>")


def _figure(stem: str, figures: dict, notes: dict | None = None) -> str:
    """A figure of the page with its caption (:func:`roughlight.report.registry.caption`), or a note that it is missing."""
    cap = registry.caption(stem)
    title = cap["title"]
    extra = (notes or {}).get(stem, "")
    path = figures.get(stem)
    if not path or not os.path.exists(path):
        return f'<p class="note">Figure {_e(title)} is missing ({_e(path or "not produced")}).</p>'
    uri = png_data_uri(path)
    extra_html = f"<br>{extra}" if extra else ""
    return (f'<figure id="fig-{_e(stem)}"><img src="{uri}" alt="{_e(title)}">'
            f"<figcaption><b>{_e(title)}.</b> <span class=\"thesis\"><i>Thesis:</i> {_e(cap['thesis'])}</span> "
            f"<i>Ours:</i> {_e(cap['ours'])}{extra_html}</figcaption></figure>")


def regression_failures_html(tables: dict) -> str:
    """The regressions' part of "Where methods fail": every fit that could not be made as asked.

    Lists the grid GLMs' status with what was kept out (zero-variance terms,
    near-collinear terms, the plate surfaces) and the reason, the Tables 1-2
    rows (ours and on exact peaks) whose regression line was not fitted or is
    exact, and points to the bootstrap intervals. ``tables`` as
    :func:`build_report` (``glm_summary``, ``glm_messages``, ``thesis_tables``,
    ``bootstrap_tables``); missing ones are said to be missing.
    """
    parts = ['<h3 id="stability-regressions">Where the regressions fail</h3>',
             "<p>Near-collinear predictors, zero-variance cells (truncation 0 and aspect 0 are both the plate) and "
             "IRLS that does not converge are reported here with the reason and kept out of the fits; no fit "
             "stops the report.</p>"]
    summary = tables.get("glm_summary")
    if summary is not None and len(summary):
        cols = [c for c in ("response", "n", "terms", "dropped", "converged", "condition_scaled", "status")
                if c in summary.columns]
        parts.append(_table(summary[cols], "Grid GLMs: what was fitted, what was kept out (dropped) and the "
                            "status", table_id="regression-status"))
    else:
        parts.append('<p class="note">No grid GLM summary was available.</p>')
    parts.append(_notes(tables.get("glm_messages") or []))
    thesis = tables.get("thesis_tables")
    if thesis is not None and len(thesis) and "note" in thesis:
        noted = thesis[(thesis["source"] != "thesis 2001") & (thesis["note"].fillna("") != "")]
        if len(noted):
            cols = [c for c in ("table", "aspect_label", "model", "source", "n", "converged", "note") if c in noted]
            parts.append(_table(noted[cols], "Tables 1–2 regressions with a note (no line fitted, exact fit or "
                                "not converged)", table_id="regression-notes"))
        else:
            parts.append("<p>Every Tables 1–2 regression line was fitted and converged.</p>")
    boot = tables.get("bootstrap_tables")
    if boot is not None and len(boot):
        parts.append('<p>How much each Tables 1–2 statistic depends on which truncations enter it (a sensitivity '
                     'measure: the renders are deterministic) is in <a href="#bootstrap-tables">the table under '
                     "Tables 1 and 2</a>.</p>")
    else:
        parts.append('<p class="note">No bootstrap intervals were available for Tables 1–2.</p>')
    return "".join(parts)


def _notes(messages) -> str:
    if not messages:
        return ""
    return "".join(f'<p class="note">{_e(m)}</p>' for m in messages)


# ---------------------------------------------------------------------------
# findings in words


def _stat(tables, table, aspect, model, source, metric):
    sel = tables[(tables["table"] == table) & (np.abs(tables["aspect"] - aspect) <= ASPECT_TOL)
                 & (tables["model"] == model) & (tables["source"] == source)]
    return float(sel[metric].iloc[0]) if len(sel) else float("nan")


def _sd_reading(n: int = 11) -> str:
    """What the thesis's SD column can be: a least-squares line leaves RSS <= (n - 1) SD^2 when SD is of the
    raw errors; the rows that break it at the thesis's 11 truncations cannot have that SD."""
    broken = []
    for table, spec in THESIS_TABLES.items():
        for model, values in spec["rows"].items():
            stats = dict(zip(TABLE_METRICS, values))
            bound = sd_bound(stats["Standard Deviation"], n)
            if stats["RSS"] > bound:
                broken.append(f"Table {table} {model}: RSS {stats['RSS']:.1f} > {bound:.1f}")
    text = ("<p><b>Which standard deviation?</b> For a least-squares line, RSS ≤ (n − 1)·SD² whenever SD is the "
            "standard deviation of the raw errors (the line of slope 1 through the mean error already leaves "
            f"that much). At the thesis's n = {n} truncations ")
    if broken:
        text += ("its rows " + _e("; ".join(broken)) + " break it: there the thesis's SD cannot be of the raw "
                 "errors at n = 11. Either it is the SD of the absolute errors, or its n was larger (lobe points "
                 "rather than peaks). The tables give both readings for our rows: <i>Standard Deviation</i> "
                 "(raw errors) and <i>SD of |error|</i>.</p>")
    else:
        text += "every row of the thesis keeps it.</p>"
    return text


def _best_fit(area: float, regressed: float, area_name: str, thesis: str) -> str:
    """How a lobe's area function and regressed model compare, or why they could not be."""
    if not (np.isfinite(area) and np.isfinite(regressed)):
        return ("could not be compared (too few truncations with this lobe at the table incidence for a "
                "regression: the notes above say which)")
    best = area_name if area < regressed else "the regressed sine model"
    return f"is fitted best by {best} (MAE {area:.2f} against {regressed:.2f}; the thesis: {thesis})"


def _table_findings(tables: pd.DataFrame, exact: pd.DataFrame | None) -> str:
    if tables is None or tables.empty:
        return '<p class="note">No table could be computed (see the notes above).</p>'
    out = []
    for aspect in sorted(tables["aspect"].unique(), reverse=True):
        lab = aspect_label(aspect)
        sq = _stat(tables, 1, aspect, "Square Area Function", "ours", "Mean Abs Error")
        fr = _stat(tables, 1, aspect, "Regressed Model", "ours", "Mean Abs Error")
        tr = _stat(tables, 2, aspect, "Triangle Area Function", "ours", "Mean Abs Error")
        br = _stat(tables, 2, aspect, "Regressed Model", "ours", "Mean Abs Error")
        out.append(f"<li>Aspect {_e(lab)}: the forward lobe {_best_fit(sq, fr, 'the square area function', '4.10 against 2.35')}"
                   f", the back lobe {_best_fit(tr, br, 'the triangle area function', '4.96 against 1.71')}.</li>")
    err = exact["error"].abs().dropna() if exact is not None and len(exact) else pd.Series(dtype=float)
    if len(err):
        ex_sq = tables[(tables["source"] == "exact geometry") & tables["model"].str.contains("Area")]
        exact_line = ""
        if ex_sq["Mean Abs Error"].notna().any():
            worst = float(ex_sq["Mean Abs Error"].max())
            exact_line = (" On the exact peaks the area functions are exact (MAE below 1e-9): they are the law of "
                          "these lobe peaks." if worst < 1e-9 else
                          f" On the exact peaks the area functions have MAE up to {worst:.3g}.")
        out.append(f"<li>The fast renderer's peaks differ from the exact ones by at most {err.max():.2f} "
                   f"(mean {err.mean():.2f}) on the 0-255 scale.{exact_line}</li>")
    return "<ul>" + "".join(out) + "</ul>"


WHY_DIFFERENT = """
<p>Where and why our tables differ from the thesis's:</p>
<ol>
<li><b>The ranking of the models is reversed.</b> In our study the forward lobe's peak is exactly the share of
the image covered by the pyramids' tops, seen from the mirror direction, times the source: <span class="formula">
m(1-t)²</span>. Our facets are flat with their true normals, and the Phong lobes (exponent 64, about 17° wide) of
the side facets point away from the forward mirror direction (by 2·atan(2·aspect) for the facets facing toward and
away from the light, out of the light's plane for the other two), so no side light reaches it at the aspects of the
tables (the exact rows below: the area function is exact). The
thesis saw extra forward light "from the sides of the pyramid" and fitted it with the sine model. The likely causes
are in the thesis itself: Java3D's Gouraud shading averages normals at shared vertices (the shading notes, "Gouraud
Shading"), which tilts the side facets' normals toward the vertical near the top edges; the 40 × 40-pixel capture
window of a finite, perspective patch mixes view angles (Ch. III.5, Fig. 12); pixelation and aliasing of small
facets (Ch. IV.A).</li>
<li><b>"The thesis's aspect 1.0 is our √3/2" is an inference, not a fact the thesis states.</b> Its
definition, "height-to-width aspect ratio", read as ours (height over base width) makes its aspect 1.0 our
aspect 1, with side facets tilted atan(2) = 63.4°. Three of its own observations point instead to facets tilted
60°, our aspect √3/2 = 0.866 (atan(2·0.866) = 60°): (i) the brightest facet's normal is "30° back in the direction
of the light source" (Ch. V.B), a 60° tilt; (ii) Fig. 21's back lobe is "centered at 30° elevation, which is also
the zero phase angle" at incidence 30: the mirror direction of 60° facets, where ours at aspect 1 peaks at 23.1°;
(iii) its diffuse model breaks at 120/121° (Ch. V.F), where 60° facets leave the view (ours: 120° at √3/2,
116.6° at aspect 1). Against it: the definition above, and its area formulas, which fit no single geometry (item
3). If the inference holds and the relation is a scale (for instance a height measured differently), the aspect
axis of its Figs. 26 and 29 is ours times 0.866 (its aspect 0.5 our 0.433), so its curves compare with ours at
0.866 times their label; if the thesis's facets were the tilts its definition gives, they compare label for
label. The lobe peaks, and so Tables 1–2, barely depend on this (the visible lit share is the same), which is why
the tables are shown at both aspects; the lobe's centre and the opposition behaviour do.</li>
<li><b>Units.</b> The thesis's area functions are not dimensionless ({2(1-t)/tanθ}² is an area in units of the
height); we use the normalised shares of the image, <span class="formula">m(1-t)²</span> for the top and
<span class="formula">m·k·(1-(1-t)²)</span> for the front facet with <span class="formula">k = 1/2</span> from
geometry (the front facet's visible lit share of the image from its mirror direction at t = 1, computed by exact
polygon clipping; Fig. 24), which equals the thesis's stated ratio of the back lobe at t = 1 to the forward lobe at
t = 0. <span class="formula">m = J·m_s</span> (127).</li>
<li><b>Our remaining error is the renderer's sampling.</b> The "exact geometry" rows recompute the statistics on
exact peaks (the same views, polygon clipping instead of pixels). The residual error of the area functions on our
rendered data comes from 8-bit pixels sampling thin facets (at t = 0.1 a side facet is 1/20 of a period wide): the
thesis's pixelation problem, in small.</li>
<li><b>Statistics.</b> MAE and SD are of the raw errors observed - predicted (SD with n - 1); b0, b1 and RSS come
from a Gaussian GLM fitted by IRLS (statsmodels) of observed on predicted, as the thesis's S-Plus run; RSS is that
regression's residual sum of squares. The thesis does not say whether its SD is of the raw or the absolute errors.</li>
</ol>
"""


def _model_findings(summary: pd.DataFrame) -> str:
    if summary is None or summary.empty:
        return ""
    out = []
    for comp, g in summary[summary["band"] != "all"].groupby("component", sort=False):
        parts = []
        for band, gb in g.groupby("band", sort=True):
            best = gb.sort_values(["best_in", "median_rmse"], ascending=[False, True]).iloc[0]
            parts.append(f"{band}: {best['model']} (median RMSE {best['median_rmse']:.2f})"
                         if np.isfinite(best["median_rmse"]) else f"{band}: no model could be fitted")
        out.append(f"<li><b>{_e(comp)}</b>: " + "; ".join(_e(p) for p in parts) + "</li>")
    return "<p>Best model per band (most surfaces where it has the smallest RMSE):</p><ul>" + "".join(out) + "</ul>"


# ---------------------------------------------------------------------------
# the page


def _section_study(study: dict, messages: list, table_aspects, followed=()) -> list[str]:
    """The report's section: the study."""
    parts = []
    parts.append('<h2 id="study">The study</h2>')
    if followed:
        parts.append('<p class="note" id="followed">Settings left unset that follow the grid '
                     "(config/README.md): " + "; ".join(_e(line) for line in followed) + ".</p>")
    if study:
        aspects = study.get("aspects", [])
        parts.append(
            f"<p>{_e(study.get('surfaces', '?'))} surfaces (truncation × aspect × incidence), "
            f"{_e(study.get('views_per_surface', '?'))} views each (azimuth 0–175 × elevation 0–180), "
            f"{_e(study.get('rows', '?'))} rows. "
            f"Truncations: {_e(', '.join(f'{t:g}' for t in study.get('truncations', [])))}. "
            f"Aspects: {_e(', '.join(aspect_label(a) for a in aspects))}. "
            f"Incidences: {_e(', '.join(f'{i:g}' for i in study.get('incidences', [])))}. "
            f"Light J = {_e(_fmt(study.get('light'), 0))}, shininess {_e(_fmt(study.get('shininess'), 0))}, "
            f"shadows {_e(study.get('shadows'))}, method {_e(study.get('method'))}.</p>")
        missing = [a for a in table_aspects if find_aspect(aspects, a) is None]
        if missing:
            parts.append('<p class="note">The table aspects ' + _e(", ".join(aspect_label(a) for a in missing))
                         + " (<code>report.table_aspects</code>) are not in this study: the tables and figures below "
                         "show the others only. Add them to <code>grid.aspect</code> to get their tables.</p>")
    parts.append(_notes(messages))
    return parts


def _implied_scale_parts(scales, at_scale) -> list[str]:
    """Which scale of its area functions the thesis's own numbers allow, and our rows at that scale."""
    if scales is None or not len(scales):
        return []
    items = []
    for _, r in scales.iterrows():
        verdict = ("possible" if r["stated_possible"] else
                   f"impossible: the mean error would be {r['mean_error_at_stated']:.2f}, larger in size than the "
                   f"MAE {r['mae']:.2f} it reports")
        items.append(f"<li>Table {int(r['table'])}, {_e(r['model'])}: its MAE, b0 and b1 allow a scale s in "
                     f"[{r['s_min_mae']:.1f}, {r['s_max_mae']:.1f}] (with SD of the raw errors: "
                     f"[{r['s_min_sd']:.1f}, {r['s_max_sd']:.1f}]); the stated {r['stated_scale']:g} is {verdict}.</li>")
    parts = ["<h3>Which functions the thesis evaluated</h3>",
             "<p>An area row predicts s·f(t) at the 11 truncations 0–1 and reports its regression of observed on "
             "predicted, y = b0 + b1·x, so its mean error is b0 + (b1 − 1)·s·mean(f) whatever the observations "
             "were, and a mean error is never larger in size than the MAE (nor, with SD of the raw errors, smaller "
             "than √(MAE² − (n − 1)/n·SD²)). That bounds the scale s the thesis's own numbers allow:</p>",
             "<ul>" + "".join(items) + "</ul>"]
    if at_scale is not None and len(at_scale) and (at_scale["scale"] == "implied").any():
        cols = [c for c in ("scale", "m", "table", "aspect_label", "model", "Mean Abs Error", "Standard Deviation",
                            "b0", "b1", "RSS") if c in at_scale]
        parts.append("<p>So our rows are shown once more with the area functions at the smallest scale the "
                     "thesis's numbers allow (the regressed model scaled alike): on comparable functions. At that "
                     "scale our square-area error is close to the thesis's, and the area function still beats the "
                     "regressed model on our peaks.</p>" if _area_still_wins(at_scale) else
                     "<p>Our rows at the smallest scale the thesis's numbers allow (the regressed model scaled "
                     "alike):</p>")
        parts.append(_table(at_scale[cols], "Our Tables 1-2 rows at the stated scale (m = 127) and at the scale the "
                            "thesis's numbers imply", table_id="implied-scale"))
    return parts


def _area_still_wins(at_scale) -> bool:
    implied = at_scale[at_scale["scale"] == "implied"]
    area = implied[implied["model"].str.contains("Area")]["Mean Abs Error"]
    regressed = implied[implied["model"] == "Regressed Model"]["Mean Abs Error"]
    return bool(len(area) and len(regressed) and area.max() < regressed.min())


def _section_tables_1_2(tables: dict, thesis, exact, table_incidence: float) -> list[str]:
    """The report's section: tables 1 and 2."""
    parts = []
    k_text = "k from geometry"
    if thesis is not None and len(thesis) and "k" in thesis:
        ks = thesis[thesis["source"] == "ours"].groupby("aspect_label")["k"].first()
        k_text = "k from geometry (" + ", ".join(
            f"{_e(a)}: {v:.4g}" if np.isfinite(v) else f"{_e(a)}: none, no side facets" for a, v in ks.items()) + ")"
    parts.append('<h2 id="tables">Tables 1 and 2</h2>')
    parts.append("<p>Data: the forward (mirror, elevation 180 − i) and back (the light-facing facet's mirror "
                 f"direction) specular lobe peaks on the light's plane (azimuth 0), incidence {table_incidence:g}, truncation "
                 "0–1. Models (m = J·m_s): square area <span class=\"formula\">m(1−t)²</span>, forward regressed "
                 "<span class=\"formula\">m(1 − sin(tπ/2))</span>, triangle area "
                 f"<span class=\"formula\">m·k·(1 − (1−t)²)</span> with {k_text}, back regressed "
                 "<span class=\"formula\">m·sin(tπ/2)/2</span>.</p>")
    if thesis is not None and len(thesis):
        for aspect in sorted(thesis["aspect"].unique(), reverse=True):
            for table in (1, 2):
                parts.append(thesis_table_html(thesis, table, aspect, table_incidence))
        parts.append(_table_findings(thesis, exact))
        parts.append(_sd_reading())
        parts += _implied_scale_parts(tables.get("implied_scales"), tables.get("tables_at_implied_scale"))
        parts.append(WHY_DIFFERENT)
    else:
        parts.append(f'<p class="note">None of the table aspects at incidence {table_incidence:g} is in the study: '
                     "Tables 1–2 could not be computed.</p>")
    boot = tables.get("bootstrap_tables")
    if boot is not None and len(boot):
        b = boot.copy()
        b["interval"] = [f"[{lo:.3g}, {hi:.3g}]" if np.isfinite(lo) and np.isfinite(hi) else "–"
                         for lo, hi in zip(b["low"], b["high"])]
        wide = b.pivot_table(index=["table", "aspect_label", "model"], columns="metric", values="interval",
                             aggfunc="first")
        wide = wide[[m for m in TABLE_METRICS if m in wide.columns]].reset_index()
        wide = wide.rename(columns={"aspect_label": "aspect"})
        n_boot = int(b["n_boot"].iloc[0])
        n_trunc = "/".join(str(int(n)) for n in sorted(b["n"].unique()))
        none = " – : too few truncations with this lobe to resample." if (b["interval"] == "–").any() else ""
        parts.append(_table(wide, TABLE_CAPTIONS["bootstrap_tables"] + f" ({n_boot} resamples of the {n_trunc} "
                            f"truncations, seeded).{none}", table_id="bootstrap-tables"))
    sine = tables.get("sine_refits")
    if sine is not None and len(sine):
        s = sine.copy()
        s["aspect"] = s["aspect_label"]
        parts.append(_table(s.drop(columns=["aspect_label"]), TABLE_CAPTIONS["sine_refits"] +
                            " Forward: A(1 − sin(ωt)); back: A·sin(ωt); the thesis fixed A = m or m/2 and"
                            " ω = π/2.",
                            table_id="sine-refits"))
    if exact is not None and len(exact):
        parts.append("<details><summary>Measured and exact lobe peaks of the table surfaces</summary>" +
                     _table(exact, "Lobe peaks: measured (fast renderer) against exact (polygon clipping)",
                            table_id="exact-peaks") + "</details>")
    return parts


#: Headings of the figure sections of the page (registry sections), in page order.
FIGURE_SECTIONS = {"specular": "The specular component (Figs. 17–26)", "diffuse": "The diffuse component (Figs. 27–29)",
                   "pictures": "Pictures of the surfaces (Figs. 9, 10, 13)"}


def _section_figures(section: str, figures: dict) -> list[str]:
    """A figure section of the page: its heading and its figures (:data:`roughlight.report.registry.FIGURES`)."""
    return [f'<h2 id="{section}">{_e(FIGURE_SECTIONS[section])}</h2>'] + [
        _figure(f.name, figures) for f in registry.figures(section=section)]


def _diffuse_parts_table(tables: dict, table_aspects) -> list[str]:
    """The three-part diffuse model's fits at the table aspects."""
    parts = []
    dp = tables.get("diffuse_parts")
    if dp is not None and len(dp):
        want = [a for a in table_aspects if find_aspect(dp["aspect"], a) is not None]
        sel = dp[np.isin(dp["aspect"].round(12), [round(find_aspect(dp["aspect"], a), 12) for a in want])] \
            if want else dp.head(0)
        cols = ["truncation", "aspect", "e1", "e2", "level1", "level3", "rate", "decay_length", "rmse", "jump_at_e2",
                "rate_continuous", "rmse_continuous", "note"]
        cols = [c for c in cols if c in sel]
        sel = sel[cols].copy()
        sel["aspect"] = sel["aspect"].map(aspect_label)
        parts.append(_table(sel, "The three-part diffuse model (Ch. V.F) fitted on the azimuth-0 arc: breaks e1 "
                                 "(incidence) and e2 (front facet edge-on), levels of parts one and three, decay "
                                 "rate k (1/deg) and length 1/k (deg) of part two, the whole arc's RMSE and the jump "
                                 "of the thesis's form at e2 (it does not reach level three there); then the same "
                                 "decay made continuous at both breaks, its rate and RMSE (the dashed fits of Fig. 28)",
                    table_id="diffuse-parts"))
    return parts


def _section_lobes(tables: dict, figures: dict, table_aspects) -> list[str]:
    """The report's section: lobes."""
    parts = []
    parts.append('<h2 id="lobes">Lobes</h2>')
    parts += [_figure(f.name, figures) for f in registry.figures(section="lobes")]
    lobes = tables.get("lobes")
    if lobes is not None and len(lobes):
        want = [find_aspect(lobes["aspect"], a) for a in table_aspects]
        want = [a for a in want if a is not None]
        sel = lobes[lobes["aspect"].isin(want) & lobes["lobe"].isin(["forward", "back"])].copy()
        sel["aspect"] = sel["aspect"].map(aspect_label)
        cols = ["truncation", "aspect", "incidence", "lobe", "predicted", "peak", "peak_elevation", "centroid",
                "fwhm", "phase_at_peak", "note"]
        exact = tables.get("exact_peaks")
        protocols = ["exact_fwhm", "exact_peak_no_specular_shadows", "exact_fwhm_no_specular_shadows"]
        if exact is not None and len(exact) and all(c in exact for c in protocols):
            ex = exact[SURFACE_KEYS + ["lobe"] + protocols].copy()
            ex["aspect"] = ex["aspect"].map(aspect_label)
            sel = sel.merge(ex, on=SURFACE_KEYS + ["lobe"], how="left")
            cols = cols[:-1] + protocols + ["note"]
            parts.append("<p>Specular shadows: the study shadows the specular like the diffuse; the thesis's specular "
                         "runs had none (Ch. V.D; <code>render.specular_shadows: false</code> is that protocol). The "
                         "peaks do not change, the widths do: the exact reference's FWHM on the arc under both "
                         "protocols stands beside the measured lobe.</p>")
        parts.append(_table(sel[cols], "Lobes on the azimuth-0 arc (peak 0-255; predicted centre, peak elevation, "
                                       "centroid and FWHM in degrees; exact FWHM with the study's specular shadows "
                                       "and without, the thesis's protocol)", table_id="arc-lobes"))
    hemi = tables.get("lobes_hemisphere")
    if hemi is not None and len(hemi):
        want = [find_aspect(hemi["aspect"], a) for a in table_aspects]
        want = [a for a in want if a is not None]
        sel = hemi[hemi["aspect"].isin(want)].copy()
        sel["aspect"] = sel["aspect"].map(aspect_label)
        parts.append("<details><summary>Lobes over the whole hemisphere</summary>" +
                     _table(sel, "Lobes over the hemisphere: peak, where it is, and the solid angle above half "
                                 "maximum (sr) with the equivalent cone's full angle (deg)",
                            table_id="hemisphere-lobes") + "</details>")
    return parts


def _section_glm(tables: dict, figures: dict) -> list[str]:
    """The report's section: GLMs."""
    parts = []
    parts.append('<h2 id="glm">Beyond the thesis: GLMs over the grid</h2>')
    parts.append("<p>Gaussian GLMs (IRLS) of the forward lobe peak, the back lobe peak and the diffuse level "
                 "(solid-angle weighted hemisphere mean) on truncation, aspect and their interaction (and incidence "
                 "when the grid has more than one). The plate surfaces (truncation 0 or aspect 0) are one surface "
                 "whatever the other parameter is and are kept out; terms are dropped when the design is "
                 "near-collinear: Belsley's scaled condition number (every column, the intercept's included, scaled "
                 "to unit length and not centred, the scaling his thresholds 30 and 100 assume) above 30.</p>")
    parts.append(_notes(tables.get("glm_messages", [])))
    parts.append(_table(tables.get("glm_summary"), TABLE_CAPTIONS["glm_summary"], table_id="glm-summary"))
    parts.append(_table(tables.get("glm_coefficients"), TABLE_CAPTIONS["glm_coefficients"],
                        table_id="glm-coefficients"))
    parts += _share_law_parts(tables.get("share_laws"))
    parts += [_figure(f.name, figures) for f in registry.figures(section="glm")]
    return parts


def _section_models(tables: dict, figures: dict, provenance: dict) -> list[str]:
    """The report's section: analytic models."""
    parts = []
    parts.append('<h2 id="models">Beyond the thesis: analytic rough-surface models</h2>')
    parts.append(
        "<p>Fitted to every view of every surface: <b>diffuse</b> — Lambert (the plate), Oren–Nayar's qualitative "
        "model with σ from the pyramid (RMS facet slope, σ = atan(2·aspect)·√(1 − (1−t)²)) and with σ fitted, "
        "and a "
        "Torrance–Sparrow facet model (each facet's 8-bit value × its share of the image × the V-cavity "
        "masking-shadowing term G = min(1, 2n_zV_z/(n·V), 2n_zL_z/(n·L))); <b>specular</b> — Phong on the plate, "
        "the facet model without masking and with the V-cavity term; <b>near opposition</b> — Hapke's shadow-hiding "
        "term B(g) = B0/(1 + tan(g/2)/h) on a linear phase background, fitted to the phase curve within "
        f"{_e(_fmt((provenance.get('settings') or {}).get('hapke_max_phase', 60), 0))}° of zero phase. Every model "
        "is scored by the RMSE of its 8-bit (quantized) predictions over the views that see the surface.</p>"
        "<p>These scores are <b>in-sample</b>: each model is scored on the views it was fitted to, and the data are "
        "deterministic, so a residual is lack of fit, not noise. Models with free parameters (Oren–Nayar's fitted "
        "σ, the Hapke surge's four) can only gain in-sample over models they nest, so the Hapke surge is also "
        "scored on <b>held-out</b> phase bins (fitted on every other bin, scored on the rest, both ways) and by "
        "Gaussian AIC (n·ln(RSS/n) + 2k, k = 4 against the background's 2).</p>")
    fits = tables.get("model_fits")
    if fits is not None and "hapke_aic" in fits:
        rough = fits[fits["truncation"] * fits["aspect"] > 0]
        ok = rough[["hapke_aic", "hapke_aic_constant", "rmse_hapke_heldout", "rmse_constant_heldout"]].dropna()
        if len(ok):
            by_aic = int((ok["hapke_aic"] < ok["hapke_aic_constant"]).sum())
            held = int((ok["rmse_hapke_heldout"] < ok["rmse_constant_heldout"]).sum())
            parts.append(f"<p>Hapke's surge against its own background on the {len(ok)} rough surfaces: preferred by "
                         f"AIC on {by_aic}, lower held-out RMSE on {held} (in-sample it can never lose).</p>")
    if fits is not None and "sigma_fitted_at_bound" in fits:
        rough = fits[fits["truncation"] * fits["aspect"] > 0]
        n_bound = int(rough["sigma_fitted_at_bound"].sum())
        if n_bound:
            parts.append(f'<p class="note">Oren–Nayar\'s fitted σ ended on a bound of its search (0–1.5 rad) on '
                         f"{n_bound} of {len(rough)} rough surfaces: there the fit is limited by the bound, not by "
                         "the data, and its σ is no roughness estimate.</p>")
    msum = tables.get("model_fits_summary")
    parts.append(_model_findings(msum))
    if msum is not None and len(msum):
        parts.append(_table(msum[msum["band"] == "all"], TABLE_CAPTIONS["model_fits_summary"] + " All surfaces.",
                            digits=2, table_id="model-summary"))
        parts.append("<details><summary>By band of surfaces</summary>" +
                     _table(msum[msum["band"] != "all"], TABLE_CAPTIONS["model_fits_summary"], digits=2,
                            table_id="model-summary-bands") + "</details>")
    parts += [_figure(f.name, figures) for f in registry.figures(section="models")]
    return parts


def _share_law_parts(laws) -> list[str]:
    """The combined models of the lobe peaks: share laws against a flexible GLM and the linear baseline."""
    if laws is None or not len(laws):
        return []
    parts = ["<h3>A combined model worth the name: share laws</h3>",
             "<p>The linear GLM misses the shape the geometry dictates. A lobe's peak is the reflecting facets' share "
             "of the image times their 8-bit value m at the mirror direction: the forward lobe is m·(1 − t)² with no "
             "free parameter, the back lobe m·k(aspect)·(1 − (1 − t)²), with k the full pyramid's share from "
             "geometry (exact polygon clipping) or fitted, one per aspect. Beside them, a flexible statistical "
             "model (a quasi-binomial GLM with a logit link on the share peak/m and truncation, aspect and their "
             "interaction) and the linear GLM. Held-out errors predict each surface from a fit without it.</p>"]
    best = laws.loc[laws.groupby(["lobe", "incidence"])["rmse_held_out"].idxmin()]
    items = [f"<li>{_e(r['lobe'])} lobe, incidence {r['incidence']:g}: best held out <b>{_e(r['model'])}</b> "
             f"(RMSE {r['rmse_held_out']:.2f} held out, {r['rmse']:.2f} in-sample, {int(r['parameters'])} "
             "parameters)</li>" for _, r in best.iterrows()]
    parts.append("<ul>" + "".join(items) + "</ul>")
    parts.append(_table(laws, TABLE_CAPTIONS["share_laws"], digits=3, table_id="share-laws"))
    return parts


def _section_stability(tables: dict, stability_html: str | None) -> list[str]:
    """The report's section: where methods fail: the renderers (make bench), then the regressions (always)."""
    parts = []
    if stability_html:
        parts.append(stability_html)
    else:
        parts.append('<h2 id="stability">Where methods fail</h2><p class="note">The stability scans are switched '
                     "off (<code>report.stability: false</code>): only the regressions are shown.</p>")
    parts.append(regression_failures_html(tables))
    return parts


def _section_provenance(tables: dict, figures: dict, config, provenance: dict, benchmarks) -> list[str]:
    """The report's section: provenance."""
    import yaml

    parts = []
    parts.append('<h2 id="provenance">Settings and provenance</h2>')
    ts = tables.get("timings_summary") or {}
    if ts:
        parts.append(f"<p>Render timings: {_e(ts.get('sweeps'))} sweeps, {_e(ts.get('views'))} views, "
                     f"{_e(_fmt(ts.get('total_seconds'), 1))} s in all "
                     f"(median {_e(_fmt(ts.get('median_seconds'), 2))} s, "
                     f"max {_e(_fmt(ts.get('max_seconds'), 2))} s for {_e(ts.get('slowest'))}); "
                     f"{_e(_fmt(ts.get('views_per_second'), 0))} views/s; method {_e(ts.get('methods'))}.</p>")
    timings = tables.get("timings")
    if timings is not None and len(timings):
        t = timings.copy()
        t["aspect"] = t["aspect"].map(aspect_label)
        parts.append("<details><summary>Per-sweep timings</summary>" +
                     _table(t, "Render wall time per sweep", digits=2, table_id="timings") + "</details>")
    parts += [_figure(f.name, figures) for f in registry.figures(section="provenance")]
    parts.append("<h3>Speed and accuracy of the renderer</h3>")
    if benchmarks and (benchmarks.get("png") or benchmarks.get("table") is not None):
        if benchmarks.get("png") and os.path.exists(benchmarks["png"]):
            parts.append(f'<figure id="fig-speed-accuracy"><img src="{png_data_uri(benchmarks["png"])}" '
                         'alt="speed and accuracy"><figcaption>Speed against accuracy of the renderer '
                         f"({_e(benchmarks['png'])}).</figcaption></figure>")
        if benchmarks.get("table") is not None:
            parts.append(_table(benchmarks["table"], "Speed and accuracy benchmark", table_id="speed-accuracy"))
        if benchmarks.get("validation") is not None:
            parts.append(renderer_validation_html(benchmarks["validation"], benchmarks.get("smoothness"),
                                                  benchmarks.get("validation_png")))
    else:
        parts.append('<p class="note">The speed/accuracy chart is switched off (<code>report.speed_accuracy: '
                     "false</code>).</p>")
    settings = provenance.get("settings")
    if settings:
        parts.append("<h3>Analysis settings</h3><pre>" + _e(yaml.safe_dump(settings, sort_keys=False)) + "</pre>")
    if config:
        parts.append("<h3>Configuration</h3><pre>" + _e(yaml.safe_dump(_plain(config), sort_keys=False)) + "</pre>")
    versions = provenance.get("versions") or package_versions()
    parts.append(_table(pd.DataFrame(sorted(versions.items()), columns=["package", "version"]), "Package versions",
                        table_id="versions"))
    inputs = provenance.get("inputs")
    if inputs:
        parts.append(_table(pd.DataFrame(inputs), "Inputs", table_id="inputs"))
    return parts


def build_report(
    tables: dict,
    figures: dict,
    config: dict | None = None,
    provenance: dict | None = None,
    messages: list | None = None,
    benchmarks: dict | None = None,
    stability_html: str | None = None,
    title: str = "roughlight: rough surface lighting behaviours, rebuilt",
    table_aspects=TABLE_ASPECTS,
    table_incidence: float = THESIS_INCIDENCE,
    implicit_html: str | None = None,
    random_html: str | None = None,
    followed=(),
) -> str:
    """The report as one self-contained HTML string.

    Parameters
    ----------
    tables : dict of DataFrames (missing keys are reported, not an error):
        ``thesis_tables``, ``sine_refits``, ``lobes`` (arc lobes),
        ``lobes_hemisphere``, ``exact_peaks``, ``diffuse_parts``,
        ``glm_summary``, ``glm_coefficients``, ``model_fits``,
        ``model_fits_summary``, ``timings`` (per sweep); and dicts
        ``timings_summary``, ``study_summary``.
    figures : dict stem -> PNG path (:data:`roughlight.report.figures.FIGURES` stems).
    config : the configuration used (shown as YAML).
    provenance : dict with ``versions`` (package -> version), ``inputs``
        (list of :func:`file_provenance` dicts), ``settings`` (analysis settings).
    messages : list of str, shown as notes (what was left out and why).
    stability_html : the "Where methods fail" section (:func:`stability_section`);
        None: switched off (``report.stability: false``), only the regressions are shown.
    benchmarks : dict with optional ``png`` (path) and ``table`` (DataFrame)
        of the speed/accuracy benchmark; None: switched off (``report.speed_accuracy: false``).
    implicit_html : the "An implicit rough surface" section (:func:`implicit_section`);
        None: switched off (``report.implicit: false``).
    random_html : the "Random roughness" section (:func:`random_section`); None: no random kind measured.
    followed : lines naming the settings left unset that took the grid's values
        (:func:`roughlight.study.config.follow_grid`), shown in "The study".
    table_aspects, table_incidence : the aspects and incidence of Tables 1-2
        (``report.table_aspects``, ``report.table_incidence``): every table and text of the
        page that speaks of "the table aspects" shows these.

    Returns
    -------
    str (UTF-8 HTML document)
    """
    tables = tables or {}
    messages = list(messages or [])
    provenance = provenance or {}
    study = tables.get("study_summary", {}) or {}
    thesis = tables.get("thesis_tables")
    exact = tables.get("exact_peaks")
    now = _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds")
    parts = [f"<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>{_e(title)}</title>"
             f"<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><style>{CSS}</style></head>"
             "<body><main>"]
    parts.append(f"<h1>{_e(title)}</h1>")
    parts.append("<p>A rebuild of C. Slattery, <i>Analysis of Rough Surface Lighting Behaviors with OpenGL</i>, "
                 f"NPS thesis, 2001 (Ch. V, Tables 1–2). Generated {_e(now)}.</p>")
    nav = [("study", "The study"), ("tables", "Tables 1 and 2"), ("specular", "Specular: Figs. 17–26"),
           ("diffuse", "Diffuse: Figs. 27–29"), ("pictures", "Pictures: Figs. 9, 10, 13"),
           ("lobes", "Lobes"), ("glm", "Grid GLMs"), ("models", "Analytic models"),
           ("implicit", "An implicit rough surface"), ("random", "Random roughness"),
           ("stability", "Where methods fail"),
           ("provenance", "Settings and provenance")]
    parts.append("<nav><ul>" + "".join(f'<li><a href="#{a}">{_e(b)}</a></li>' for a, b in nav) + "</ul></nav>")

    parts += _section_study(study, messages, table_aspects, followed)
    parts += _section_tables_1_2(tables, thesis, exact, table_incidence)
    parts += _section_figures("specular", figures)
    parts += _section_figures("diffuse", figures)
    parts += _diffuse_parts_table(tables, table_aspects)
    parts += _section_figures("pictures", figures)
    parts += _section_lobes(tables, figures, table_aspects)
    parts += _section_glm(tables, figures)
    parts += _section_models(tables, figures, provenance)
    if implicit_html:
        parts.append(implicit_html)
    else:
        parts.append('<h2 id="implicit">An implicit rough surface</h2><p class="note">Switched off '
                     "(<code>report.implicit: false</code>).</p>")
    if random_html:
        parts.append(random_html)
    else:
        parts.append('<h2 id="random">Random roughness</h2><p class="note">Not measured: <code>surface.kind</code> '
                     "lists no random kind (config/README.md).</p>")
    parts += _section_stability(tables, stability_html)
    parts += _section_provenance(tables, figures, config, provenance, benchmarks)
    parts.append("</main></body></html>")
    return "\n".join(p for p in parts if p)





def _plain(obj):
    """Config values as plain YAML-safe types (Snakemake's Namedlist/dict subclasses)."""
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    return obj


def write_report(path, html_text: str) -> str:
    """Write the report atomically; return the path."""
    write_text_atomic(path, html_text)
    return os.fspath(path)


def _fmt_domain(v):
    """A safe-domain cell: a bound to 3 significant digits, 'never' where no tested value was within tolerance."""
    if isinstance(v, str):
        return html.escape(v)
    if v is None or (isinstance(v, float) and not np.isfinite(v)):
        return "never"
    return f"{v:.3g}"


def renderer_validation_line(validation: pd.DataFrame) -> str:
    """One sentence: the default renderer's worst view, p99 and MAE against the exact reference."""
    from ..measurements.renderer_validation import validation_summary

    summary = validation_summary(validation)
    if "setting" not in summary.columns:
        summary["setting"] = "configured"
    n_surfaces = len(validation[["truncation", "aspect", "incidence"]].drop_duplicates())
    views = int(validation["n_views"].max())
    texts = []
    for setting, rows in summary.groupby("setting", sort=False):
        parts = [f"{r.component} {r.worst:.2f} (p99 {r.p99:.2f}, MAE up to {r.largest_mae:.3f})"
                 for r in rows.itertuples()]
        name = "the configured renderer" if setting == "configured" else f"sampling {setting} px/period"
        texts.append(f"{name}: worst view {'; '.join(parts)}, {rows['views_per_second'].iloc[0]:,.0f} views/s")
    return (f"The fast renderer at every view ({n_surfaces} surfaces x {views:,} views against the exact "
            f"reference; the goal is a worst view within one 8-bit level): {'. '.join(texts)}.")


def renderer_validation_html(validation: pd.DataFrame, smoothness: pd.DataFrame | None, png_path=None) -> str:
    """The default renderer at every view: the summary line, the per-surface table, the arc curves' largest
    deviations (Figs. 21 and 28) and the chart of :func:`roughlight.report.figures.plot_renderer_validation`."""
    parts = ['<h3 id="renderer-validation">Accuracy at every view</h3>',
             f"<p>{html.escape(renderer_validation_line(validation))}</p>"]
    if png_path and os.path.exists(png_path):
        parts.append(f'<figure id="fig-renderer-validation"><img src="{png_data_uri(png_path)}" '
                     'alt="the default renderer against the exact reference"><figcaption>The default renderer '
                     f"against the exact reference ({_e(png_path)}).</figcaption></figure>")
    parts.append(_table(validation, "The default renderer against the exact reference, per surface and component",
                        table_id="renderer-validation"))
    if smoothness is not None and len(smoothness):
        worst = smoothness.sort_values("largest_deviation", ascending=False).iloc[0]
        parts.append(f"<p>Smoothness of the figures' curves: the largest deviation of an arc curve of Figs. 21 and "
                     f"28 from the exact curve is {worst['largest_deviation']:.2f} ({_e(worst['figure'])}, "
                     f"truncation {worst['truncation']:g}, aspect {worst['aspect']:.3g}, "
                     f"e = {worst['at_elevation']:g}).</p>")
        parts.append(_table(smoothness, "Arc curves of Figs. 21 and 28 against the exact curves",
                            table_id="arc-smoothness"))
    return "".join(parts)


def stability_section(tables: dict, figure_png_path, plan: str = "full", renderer_validation=None) -> str:
    """HTML fragment for the report: the safe-domain table, the figure, what fails where (with the default
    renderer's worst view at every view when ``renderer_validation``, the frame of
    :func:`roughlight.measurements.renderer_validation.validate_renderer`, is given).

    Parameters
    ----------
    tables : dict
        ``"safe_domain"``: the frame of :func:`safe_domain`; optionally
        ``"stability"``: the long frame (for the clipping numbers).
    figure_png_path : path of the PNG from :func:`roughlight.report.figures.plot_stability`.
    plan : the size the measurements ran at (:data:`roughlight.measurements.stability.PLANS`).
    """
    from ..measurements.stability import TOLERANCE, normals_table, plan_surfaces

    surfaces_of = plan_surfaces(plan)
    safe = tables["safe_domain"]
    if not isinstance(safe, pd.DataFrame):
        safe = pd.DataFrame(safe)
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in safe.columns)
    body = "".join("<tr>" + "".join(f"<td>{_fmt_domain(v)}</td>" for v in row) + "</tr>" for row in safe.itertuples(index=False))
    clip_text = ""
    long = tables.get("stability")
    if long is not None:
        cf = long[(long["experiment"] == "clipping") & (long["metric"] == "clipped_fraction")]
        parts = [f"{s} at {x:g}: {v:.0%}" for s, x, v in zip(cf["setting"], cf["x"], cf["value"])]
        clip_text = " Fraction of views (azimuth 0) with the total clipped: " + html.escape("; ".join(parts)) + "."
    normals_html = ""
    nt = normals_table(long) if long is not None else pd.DataFrame()
    if len(nt):
        n_head = "<th>shading</th>" + "".join(f"<th>{html.escape(c)}</th>" for c in nt.columns)
        n_body = "".join(f"<tr><td>{html.escape(str(m))}</td>" + "".join(f"<td>{_fmt_domain(v)}</td>" for v in row) + "</tr>"
                         for m, row in zip(nt.index, nt.itertuples(index=False)))
        surfaces = ", ".join(f"t={s.truncation:g} a={s.aspect:.3g}" for s, _ in surfaces_of["normals"])
        normals_html = (
            '<h3 id="stability-normals">Shading on faceted geometry</h3>'
            "<p>The pyramids are flat facets, so the study shades each facet with its true normal (flat). "
            "Gouraud and Phong shading with normals averaged over the facets that meet at a vertex bend every "
            "facet's normal towards its neighbours': mae is against the exact reference, mae_vs_flat against "
            "the same renderer with true normals (what the averaged normals alone change), and highlight_ratio is "
            "the brightest specular view over the reference's (below 1: highlights missed). Naive method, "
            f"surfaces {html.escape(surfaces)}, incidence 30.</p>"
            f'<table class="stability-normals"><thead><tr>{n_head}</tr></thead><tbody>{n_body}</tbody></table>'
            "<p>Mach banding (the eye's overshoot at a change of intensity slope along Gouraud's triangle edges) "
            "is a perceptual effect, not a change of a capture window's mean: the pictures in the figure's "
            "bottom row show it; the means above show what the averaged normals do to the measurement.</p>"
        )
    validation_html = ""
    if renderer_validation is not None and len(renderer_validation):
        validation_html = (f'<p id="stability-every-view">{html.escape(renderer_validation_line(renderer_validation))} '
                           'See <a href="#renderer-validation">Accuracy at every view</a>.</p>')
    return (
        '<section id="stability"><h2>Where methods fail</h2>'
        f"<p>Each method against the exact reference ({html.escape(plan)} plan): the fast method on "
        f"{len(surfaces_of['fast'])} surfaces, the naive one (one render a view) on {len(surfaces_of['naive'])}, "
        "on coarse view sets. The table gives, per "
        f"method, the domain where the mean absolute error stays within {TOLERANCE} on the 0&ndash;255 scale for "
        "every component (diffuse, specular, total); &ldquo;never&rdquo; means no tested value was within tolerance "
        "(the best_mae columns then say how close it came).</p>"
        f'<table class="stability"><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>'
        f'<figure><img alt="stability" src="{png_data_uri(figure_png_path)}" style="max-width:100%">'
        "<figcaption>Worst-component MAE against pixels per period, jitter spread, view elevation, incidence "
        "(by shadow bias), shadow-map size and shininess; the dotted line is the tolerance. Middle row, right: "
        "the total in the light's plane at source 127 and 255, and how far each lobe moves. Bottom row: "
        "averaged vertex normals against true face normals by component, and one surface under each "
        "shading model.</figcaption></figure>"
        "<p>What fails where. The naive procedure (pyrender as it comes: 10 pixels a period, a finite patch, "
        "one render per view) aliases: at whole numbers of pixels per period every pixel samples the same "
        "point of the period and a sub-pixel shift of the camera moves the value by tens of levels (the "
        "thesis's &ldquo;flashing lines&rdquo; and pixelation, Ch. IV); its patch, sized for views above 10&deg;, "
        "runs out at grazing views (coverage below 1); its fixed shadow map and pyramid edges leave errors of a "
        "few levels even at its best. The fast method needs at least 2 pixels a period by construction (its "
        "tile is one period) and converges as the pixels grow; a shadow bias of 0 gives shadow acne and a large one "
        "peter-panning (lost shadows) at low incidence. Clipping at 255, which the thesis avoided by using a "
        "source of 127 after seeing it bend its lobes (Fig. 17), flattens the lobes' peaks and moves their "
        "centres (on a clipped plateau the peak's position is arbitrary; the centre is the measure)."
        f"{clip_text}</p>{validation_html}{normals_html}</section>"
    )


#: The first-order correction term, in one formula (the README gives the same).
CORRECTION_FORMULA = (
    "I = Σ<sub>f</sub> q<sub>f</sub>(lit) A<sub>f</sub><sup>lit</sup> + q<sub>f</sub>(shadow) "
    "A<sub>f</sub><sup>shadow</sup>, over the top and the four sides f; top: A = (1 − t)², seen and lit whole; "
    "side with outward direction h, s = 2a, P<sub>s</sub> = (1 − (1 − t)²)/4, view shear x = s (V·h)/V<sub>z</sub>, "
    "light shear x<sub>L</sub> = s (L·h)/L<sub>z</sub>, G(x) = min(1, 2/(1 + x)): seen share "
    "A = a + w (b − a) with a = P<sub>s</sub> (1 + x)<sup>+</sup> G(x), b = 4 P<sub>s</sub> (1 + x)<sup>+</sup> / "
    "Σ(1 + x)<sup>+</sup>, w = t · clip((x<sub>2</sub> − 1)/c, 0, 1), x<sub>2</sub> the second-largest view "
    "shear, c = 3 (fitted); lit share A<sup>lit</sup> = A · min(1, G(x<sub>L</sub>) / G<sub>eff</sub>), "
    "G<sub>eff</sub> = A / (P<sub>s</sub> (1 + x)); q the facet's 8-bit value of the OpenGL lighting equation."
)


def _caption_text(name: str) -> str:
    """A caption's whole text from ``workflow/report/{name}.rst`` (for parts the registry does not list)."""
    return (registry.CAPTION_DIR / f"{name}.rst").read_text(encoding="utf-8").strip()


def implicit_section(validation: pd.DataFrame, frames: pd.DataFrame, figure_png_path, plan: str = "full",
                     maps_png_path=None) -> str:
    """HTML fragment: "An implicit rough surface: the thesis's goal" (validation and frame times)."""
    from ..measurements.implicit_surface import summary

    parts = ['<h2 id="implicit">An implicit rough surface: the thesis\'s goal</h2>',
             "<p>The thesis set out to find a correction to the OpenGL lighting equation with which a surface of few "
             "polygons reflects as if it were rough (Ch. I.A). Two implicit models draw the whole rough surface as "
             "<b>one flat quad</b> (two triangles, <code>src/roughlight/shaders/implicit.frag</code>) with "
             "truncation, aspect and the material as uniforms:</p><ul>"
             "<li><b>Exact form</b> (<code>render.method: implicit_exact</code>): each pixel casts its view ray "
             "through the analytic heightfield h = min(2a·c, t·a), c the distance to the nearest cell edge, takes "
             "the first facet met and casts a ray toward the light for the shadow. No mesh and no table (0 bytes a "
             "surface): it holds for every truncation and aspect. A sweep's view is 28,657 pixels on a Fibonacci "
             "lattice over one period.</li>"
             "<li><b>First-order correction</b> (<code>render.method: implicit_correction</code>): no ray casting; "
             f"each facet's share of the image is a closed form: {CORRECTION_FORMULA} Each pixel shows one facet's "
             "8-bit value, chosen by a dither threshold, so the image mean is the facet sum.</li></ul>"]
    if plan != "full":
        parts.append(f'<p class="note">Measured at the <code>{_e(plan)}</code> plan (a few surfaces, coarse views); '
                     "<code>make bench</code> measures every view of 24 grid surfaces and 20 random ones.</p>")
    n_surfaces = validation.groupby(["truncation", "aspect", "incidence"]).ngroups
    parts.append(f"<p>Validation: {n_surfaces} surfaces, {int(validation['n_views'].iloc[0]):,} views each, against "
                 "the exact reference (polygon clipping). Goals: exact form MAE ≤ 0.1 and worst view ≤ 1.0; "
                 "correction median MAE ≤ 0.25 and worst surface's MAE ≤ 1.0.</p>")
    parts.append(_table(summary(validation), "Error against the exact reference (0–255): per method, component and "
                        "band, the median and largest surface MAE, the largest p99 and the worst view",
                        table_id="implicit-validation"))
    parts.append("<p>The correction's error sits at near-grazing views off the light's plane. There the pyramids "
                 "line up in rows along the lattice's directions, and the exact split of the image between the two "
                 "visible sides jumps with the azimuth (README, \"An implicit rough surface\"): a smooth term in "
                 "truncation, aspect, view and light can only follow its average. The exact form follows it.</p>")
    if figure_png_path and os.path.exists(figure_png_path):
        parts.append(f'<figure id="fig-implicit"><img src="{png_data_uri(figure_png_path)}" alt="implicit surface">'
                     f"<figcaption>{_e(_caption_text('implicit'))}"
                     "</figcaption></figure>")
    if maps_png_path and os.path.exists(maps_png_path):
        parts.append(f'<figure id="fig-implicit-maps"><img src="{png_data_uri(maps_png_path)}" alt="hemisphere maps">'
                     f"<figcaption>{_e(_caption_text('implicit_maps'))}"
                     "</figcaption></figure>")
    f = frames.groupby(["field", "method"], as_index=False).agg(
        triangles=("triangles", "first"), frame_ms=("frame_ms", "mean"), error=("error", "max"))
    explicit = f[f["method"] == "explicit"].set_index("field")["frame_ms"]
    f["speedup_vs_explicit"] = f["frame_ms"].rdiv(f["field"].map(explicit))
    parts.append(_table(f, "Frame time of an N × N field, 512 × 512 pixels, OSMesa (llvmpipe): explicit mesh with "
                        "pyrender's shadow pass against one implicit quad (the correction computes its shares and "
                        "facet values once a frame, in the vertex stage; the exact form casts two rays a pixel); "
                        "error = largest |image mean − exact| over the views (0–255)", table_id="implicit-frames"))
    return "\n".join(parts)


def _interval(row) -> str:
    if not np.isfinite(row["mean"]):
        return "– (no lobe)"
    if not np.isfinite(row["ci_low"]):
        return f"{row['mean']:.3g} (one seed: no interval)"
    return f"{row['mean']:.3g} [{row['ci_low']:.3g}, {row['ci_high']:.3g}]"


def random_claim_rows(ensembles: pd.DataFrame) -> pd.DataFrame:
    """The thesis's rectangular-lobe claim in numbers: back-lobe rectangularity and phase shift, regular against
    each random kind's ensemble (mean and 95% interval over seeds, one-sample t-test against the regular value)."""
    claim = ensembles[ensembles["statistic"].isin(["back_rectangularity", "back_phase_shift"])]
    rows = []
    for _, r in claim.iterrows():
        rows.append({"kind": r["kind"], "truncation": r["truncation"], "aspect": r["aspect"],
                     "incidence": r["incidence"], "statistic": r["statistic"], "regular": r["regular"],
                     "random mean [95% CI]": _interval(r), "seeds": int(r["seeds"]), "t": r["t"],
                     "p_value": r["p_value"], "seed-averaged views": r.get("pooled", np.nan)})
    return pd.DataFrame(rows)


def random_section(ensembles: pd.DataFrame, seeds_needed: pd.DataFrame, model_fits: pd.DataFrame,
                   ensembles_png=None, maps_png=None, surface_settings: dict | None = None,
                   accuracy: pd.DataFrame | None = None, convergence: pd.DataFrame | None = None,
                   tiles_png=None, plan: str = "full") -> str:
    """HTML fragment: "Random roughness" (ensembles against the regular surface, the rectangular-lobe claim,
    the analytic models refitted, seeds needed)."""
    from ..analysis.ensembles import ELLIPSE_FILL

    settings = surface_settings or {}
    spread = settings.get("spread", {})
    parts = ['<h2 id="random">Random roughness</h2>',
             "<p>The thesis concludes that its regular pyramids, with one normal per facet orientation, give "
             "“rectangular reflection patterns” and a phase shift off the light's plane (Fig. 19) where natural rough "
             "surfaces give circular lobes, and that “any attempt to simulate rough surfaces must incorporate this random "
             "nature” (Ch. IV.C, VI). Two random kinds are measured beside the regular surface at the same grid points, "
             "each as an ensemble of seeded tiles that repeat periodically:</p><ul>"
             f"<li><b>random pyramids</b>: a tile of {settings.get('cells', '?')} × {settings.get('cells', '?')} cells, "
             f"each a truncated pyramid with truncation t ± {spread.get('truncation', '?')}, aspect a·(1 ± "
             f"{spread.get('aspect', '?')}) and its apex moved up to {spread.get('apex', '?')} of the half cell;</li>"
             "<li><b>random heightfield</b>: a periodic Gaussian random field (Gaussian autocorrelation, half a cell "
             "long) of flat triangles, scaled to the regular surface's RMS slope 2a·√(1 − (1 − t)²).</li></ul>"
             "<p>Two numbers put the claim to the test, both of the back lobe (the light-facing facets' mirror "
             "direction): <b>rectangularity</b>, the area of the lobe's half-maximum region over the area of its "
             f"bounding rectangle along its principal axes (1 for a rectangle, π/4 = {ELLIPSE_FILL:.3f} for any "
             "ellipse, circles included), and the <b>phase shift</b>, the mean distance (degrees) of each off-plane "
             "arc's peak from where a circular lobe around the same peak would put it (arcs 5°–60° where the lobe "
             "stands above half its maximum). Intervals are Student-t 95% over seeds; the test is a two-sided "
             "one-sample t-test of the seeds against the regular surface's value. Each seed is a small patch of a "
             "random surface; the <b>seed-averaged views</b> (the mean over seeds of every view, what a surface "
             "made of many tiles reflects) give each statistic once more.</p>"]
    claim = random_claim_rows(ensembles)
    verdicts = []
    for (kind, t, a, i), g in ensembles.groupby(["kind", "truncation", "aspect", "incidence"], sort=True):
        rect = g[g["statistic"] == "back_rectangularity"]
        shift = g[g["statistic"] == "back_phase_shift"]
        if rect.empty or not np.isfinite(rect["regular"].iloc[0]):
            continue
        r, sh = rect.iloc[0], shift.iloc[0]
        verdicts.append(f"<li>t {t:g}, a {aspect_label(a)}, i {i:g}, {_e(kind.replace('_', ' '))}: rectangularity "
                        f"{r['regular']:.3f} regular against {_interval(r)} random (p = {r['p_value']:.2g}; "
                        f"seed-averaged {r.get('pooled', np.nan):.3f}); phase shift {sh['regular']:.2f}° regular "
                        f"against {_interval(sh)}° random (p = {sh['p_value']:.2g}; seed-averaged "
                        f"{sh.get('pooled', np.nan):.2f}°).</li>")
    if verdicts:
        parts.append("<p>As measured:</p><ul>" + "".join(verdicts) + "</ul>")
    parts.append(_table(claim, "The rectangular-lobe claim: back-lobe rectangularity (ratio) and phase shift (deg), "
                        "regular against each random kind", table_id="random-claim"))
    for png, stem, alt in ((ensembles_png, "random_ensembles", "ensembles"), (maps_png, "random_maps", "maps")):
        if png and os.path.exists(png):
            parts.append(f'<figure id="fig-{stem.replace("_", "-")}"><img src="{png_data_uri(png)}" alt="{alt}">'
                         f"<figcaption>{_e(_caption_text(stem))}</figcaption></figure>")
    shown = ensembles[[c for c in ("kind", "truncation", "aspect", "incidence", "statistic", "unit", "seeds", "mean",
                                   "ci_low", "ci_high", "regular", "difference", "p_value", "pooled") if c in ensembles]]
    parts.append(_table(shown, "Every statistic: random ensemble mean with its 95% interval over seeds, beside the "
                        "regular surface (lobes from the light's plane, diffuse level over the hemisphere, the "
                        "three-part diffuse model's levels and continuous decay rate)", table_id="random-ensembles"))
    rmse = [c for c in model_fits.columns if c.startswith("rmse_")]
    fits = model_fits.groupby(["kind", "truncation", "aspect", "incidence"], as_index=False)[rmse].mean()
    parts.append(_best_models(fits))
    parts.append("<p>The analytic models refitted on every tile (RMSE over all views, 0–255, mean over seeds). "
                 "<code>rmse_regular_*</code> predicts a tile by the regular surface at its grid point: what the "
                 "implicit shader's exact form, which reproduces the regular surface, would predict.</p>")
    parts.append(_table(fits, "Analytic models on random tiles against the regular surface (mean RMSE over seeds)",
                        table_id="random-models"))
    needed_cols = [c for c in seeds_needed.columns if c.startswith("seeds_for_")]
    parts.append(_table(seeds_needed[["kind", "truncation", "aspect", "incidence", "statistic", "mean", "sd"]
                                     + needed_cols],
                        "Seeds needed for a 95% interval whose half-width is 10%, 5% or 2% of the mean (from each "
                        "ensemble's seed-to-seed SD)", table_id="random-seeds"))
    parts += _random_tiles_parts(accuracy, convergence, tiles_png, plan)
    return "\n".join(parts)


#: The analytic models compared on random tiles, by component: (column, name in the text).
RANDOM_MODELS = {
    "diffuse": (("rmse_lambert", "Lambert (the plate)"), ("rmse_oren_nayar", "Oren–Nayar, geometric σ"),
                ("rmse_oren_nayar_fitted", "Oren–Nayar, fitted σ"), ("rmse_facet_vcavity_diffuse", "V-cavity facets"),
                ("rmse_regular_diffuse", "the regular surface (implicit exact form)")),
    "specular": (("rmse_phong_plate", "Phong on the plate"), ("rmse_facet_nomask_specular", "facets, no masking"),
                 ("rmse_facet_vcavity_specular", "V-cavity facets"),
                 ("rmse_regular_specular", "the regular surface (implicit exact form)")),
}


def _best_models(fits: pd.DataFrame) -> str:
    """One line per kind and component: which analytic model has the lowest mean RMSE over its grid points."""
    items = []
    for kind, g in fits.groupby("kind", sort=False):
        for component, models in RANDOM_MODELS.items():
            present = [(c, name) for c, name in models if c in g and not (kind == "pyramids" and "regular" in c)]
            if not present:
                continue
            means = {name: float(g[c].mean()) for c, name in present}
            best = min(means, key=means.get)
            others = "; ".join(f"{name} {value:.2f}" for name, value in sorted(means.items(), key=lambda kv: kv[1]))
            items.append(f"<li>{_e(kind.replace('_', ' '))}, {component}: best <b>{_e(best)}</b> (mean RMSE over its "
                         f"grid points: {_e(others)})</li>")
    return "<p>Which model fits best, by kind:</p><ul>" + "".join(items) + "</ul>" if items else ""


def _random_tiles_parts(accuracy, convergence, tiles_png, plan) -> list:
    """The random tiles' benchmark: the fast renderer against the exact reference, views per second, tile size."""
    from ..measurements.random_tiles import convergence_summary

    parts = []
    if accuracy is not None and len(accuracy):
        parts.append(f"<p>The fast renderer on random tiles (benchmark plan <code>{_e(plan)}</code>): a tile of n × n "
                     "cells is drawn as one period at n times the configured pixels and shadow texels a side, so each "
                     "facet is sampled as on the regular surface at n² times the pixels. Tolerance: MAE ≤ 0.5.</p>")
        parts.append(_table(accuracy, "Fast renderer against the exact reference on random tiles and on the regular "
                            "surface at the same grid point (0–255; views per second of the fast renderer)",
                            table_id="random-accuracy"))
    if convergence is not None and len(convergence):
        parts.append(_table(convergence_summary(convergence), "Tile-size convergence: each statistic's mean over "
                            "seeds and its 95% half-width against cells a side, beside the regular surface",
                            table_id="random-convergence"))
    if tiles_png and os.path.exists(tiles_png):
        parts.append(f'<figure id="fig-random-tiles"><img src="{png_data_uri(tiles_png)}" alt="random tiles">'
                     f"<figcaption>{_e(_caption_text('random_tiles'))}</figcaption></figure>")
    return parts
