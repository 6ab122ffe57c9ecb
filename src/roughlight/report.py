"""The study's report: one self-contained HTML page (tables inline, figures as data URIs).

:func:`build_report` takes the analysis tables (:mod:`roughlight.analysis`),
the figure PNGs (:mod:`roughlight.figures`), the configuration and
provenance, and returns the page as a string; :func:`write_report` writes it
atomically. The page loads nothing from anywhere: no scripts, no fonts, no
external images, so it opens from disk without a server.

:data:`CAPTIONS` holds, for every figure, what the thesis (Slattery 2001)
saw and what our study shows; ``workflow/report/*.rst`` carry the same text
for ``snakemake --report``.
"""

from __future__ import annotations

import base64
import datetime as _dt
import hashlib
import html
import importlib.metadata
import json
import math
import os
import platform
from pathlib import Path

import numpy as np
import pandas as pd

from .atomic import write_text_atomic
from .selection import ASPECT_TOL, SURFACE_KEYS, find_aspect
from .surface import SQRT3_2, aspect_label
from .thesis import TABLE_METRICS, THESIS_TABLES

__all__ = [
    "CAPTIONS",
    "TABLE_CAPTIONS",
    "package_versions",
    "file_provenance",
    "png_data_uri",
    "thesis_table_html",
    "build_report",
    "write_report",
    "caption_rst",
    "study_summary",
]

# ---------------------------------------------------------------------------
# captions: what the thesis saw, what we see

CAPTIONS = {
    "fig09_shadows": {
        "thesis": "Fig. 9 showed the simulator's hand-made shadows on full and truncated pyramids at several "
                  "incidences, each cast by an identical pyramid in front; shadows beyond these cases were "
                  "'extremely difficult' to compute.",
        "ours": "Our renderer casts every shadow with a shadow map, so each picture shows self- and cast "
                "shadows on all facets; the shadowed share of the view grows as the incidence falls.",
    },
    "fig10_grazing": {
        "thesis": "Fig. 10 showed that near grazing views the finite surface fills little of the window, "
                  "which is why a fixed 40 x 40 capture window at the centre was used.",
        "ours": "Our measurements do not depend on a window: every view samples one period of the infinite "
                "surface (coverage 1 except exactly at grazing). The pictures of a finite patch show what the "
                "thesis's window had to cope with.",
    },
    "fig13_tops": {
        "thesis": "Fig. 13 showed truncated tops reflecting light forward at low incidence: the flat tops act "
                  "as the 'slightly rounded peaks' that make rough surfaces shine near grazing.",
        "ours": "Seen from the mirror side at low incidence, only the flat tops reflect; their share of the "
                "image, (1-t)^2, sets the forward glint.",
    },
    "fig17_clipping": {
        "thesis": "Fig. 17: at source 255 the specular lobe of the flat plate was cut off at the 8-bit maximum; "
                  "at 127 it was not, so the thesis ran at 127.",
        "ours": "The same: the specular alone reaches 255 at source 255, and diffuse plus specular is clamped "
                "at 255 over the whole top of the lobe; at 127 the total stays below the ceiling.",
    },
    "fig19_topdown": {
        "thesis": "Fig. 19: top-down contour plots showed a rectangular reflection pattern whose peak shifts "
                  "in phase as the view azimuth moves away from the light: the pyramids' single set of "
                  "normals, not a physical random surface.",
        "ours": "The same rectangular pattern: the back lobe is the mirror image of the light in the facet "
                "facing it, so away from azimuth 0 the brightest view drifts off zero phase (bottom right) "
                "instead of staying centred on the light. At aspect 1 the lobe's centre is off zero phase even "
                "at azimuth 0; at aspect √3/2 it sits on it.",
    },
    "fig20_plate_incidence": {
        "thesis": "Fig. 20: on the smooth surface the specular lobe travels with the mirror direction, 180 - i, "
                  "and keeps the source's intensity 127 for every incidence.",
        "ours": "The same: the plate's Phong lobe peaks at 127 at 180 - i for every incidence above 0 "
                "(at incidence 0 N.L = 0 and there is no specular).",
    },
    "fig21_specular_truncation": {
        "thesis": "Fig. 21: as truncation grows the forward lobe (150 deg) fades and a back lobe appears; the "
                  "thesis places it at 30 deg, zero phase, at its aspect 1.0.",
        "ours": "The same trade between the two lobes, with widths unchanged. The back lobe is where the facet "
                "facing the light mirrors it, 180 - 2 atan(2 aspect) - i: 23.1 deg at our aspect 1, 30 deg "
                "(zero phase) at aspect √3/2, the thesis's 60-degree facets.",
    },
    "fig23_forward_models": {
        "thesis": "Fig. 23 / Table 1: the regressed model m(1 - sin(t pi/2)) fitted the forward lobe better "
                  "than the square area function, which the thesis explained by light added from the sides.",
        "ours": "Our forward peaks follow the top's share of the image, m(1-t)^2, to within the renderer's "
                "sampling error; the regressed sine model lies above them at mid truncation. With flat facets "
                "and true normals no side light reaches the forward mirror direction.",
    },
    "fig24_reflecting_areas": {
        "thesis": "Fig. 24: the areas of the top square and the front triangle against truncation; the ratio "
                  "of the square at t = 0 to the triangle at t = 1 matched that of the two lobes.",
        "ours": "Computed exactly (polygon clipping) as the visible, lit share of the image seen from each "
                "mirror direction: the top gives (1-t)^2, the front facet k(1-(1-t)^2) with k = 1/2 at both "
                "aspects, which is the thesis's ratio.",
    },
    "fig25_back_models": {
        "thesis": "Fig. 25 / Table 2: the regressed model m sin(t pi/2)/2 fitted the back lobe better than the "
                  "triangle area function.",
        "ours": "Our back peaks follow the front facet's share, (m/2)(1-(1-t)^2); the sine model rises too "
                "slowly at low truncation. Deviations are the renderer's sampling of thin facets.",
    },
    "fig26_specular_aspect": {
        "thesis": "Fig. 26: aspect moves the lobes as well as scaling them; at very low aspect a second lobe "
                  "from the back side of the pyramid appears (seen at truncation 0.2).",
        "ours": "The same: the back lobe moves from the forward lobe toward the light as aspect grows, and at "
                "aspect 0.1 the facet facing away mirrors the light to 180 + 2 atan(2 aspect) - i, the "
                "thesis's second lobe.",
    },
    "fig27_diffuse_plate": {
        "thesis": "Fig. 27: the diffuse component of the smooth surface is independent of the view.",
        "ours": "The same: the plate's diffuse is J sin(i) at every view (grazing views see no surface and "
                "are left out).",
    },
    "fig28_diffuse_truncation": {
        "thesis": "Fig. 28: with truncation the diffuse becomes view dependent, in three parts: constant up to "
                  "the incidence (0-30), an exponential-like decay (31-120) from inner shadows, then constant "
                  "(121-180).",
        "ours": "The same three parts, with the breaks from geometry: the incidence (zero phase; no shadow is "
                "visible below it) and 180 - atan(2 aspect), where the lit front facet turns edge-on (116.6 deg "
                "at aspect 1, 120 at √3/2). Dashed: the fitted three-part model.",
    },
    "fig29_diffuse_aspect": {
        "thesis": "Fig. 29: aspect has effects like truncation on the diffuse; not examined further.",
        "ours": "Like truncation, aspect raises part one and lowers part three; the second break moves with "
                "the front facet's tilt (markers).",
    },
    "lobe_geometry": {
        "thesis": "The thesis noted that truncation changes the lobes' intensity only, and aspect their centre.",
        "ours": "Measured lobe centres against the mirror directions of the top and the facet facing the "
                "light, and the lobes' widths: truncation does not change the width.",
    },
    "diffuse_parts": {
        "thesis": "The thesis derived no formulas for the three parts.",
        "ours": "Levels of parts one and three, the decay length of part two and the model's error over the "
                "whole grid.",
    },
    "glm_diagnostics": {
        "thesis": "The thesis did not combine truncation and aspect (Ch. V.G).",
        "ours": "Gaussian GLMs over the grid; residuals against fitted values and influence (leverage, Cook's "
                "distance). Curved residual bands show the linear predictor misses the (1-t)^2 shape.",
    },
    "model_fits": {
        "thesis": "Beyond the thesis.",
        "ours": "RMSE of analytic rough-surface models against every surface of the study.",
    },
    "hapke": {
        "thesis": "The thesis aimed at the opposition effect (Ch. II) but fitted no opposition law.",
        "ours": "The total component near zero phase with Hapke's shadow-hiding term fitted to the phase "
                "curve (binned over all azimuths) on a linear phase background.",
    },
    "timings": {
        "thesis": "The thesis's simulator took minutes per surface (Java3D, screen capture per view).",
        "ours": "Wall time of every sweep of the study.",
    },
}

TABLE_CAPTIONS = {
    "thesis_tables": "Tables 1 and 2 of the thesis recomputed from our lobe peaks (incidence 30), beside the "
                     "thesis's values and the same statistics on exact (polygon clipping) peaks.",
    "bootstrap_tables": "95% percentile bootstrap intervals of our Tables 1–2 statistics: how much each "
                        "number would move with other draws of the same truncations",
    "sine_refits": "Nonlinear least-squares refits of the thesis's sine models with 95% confidence intervals.",
    "glm_summary": "Grid GLMs (Gaussian, IRLS): convergence, condition numbers and what was kept out.",
    "glm_coefficients": "Grid GLM coefficients with 95% confidence intervals.",
    "model_fits_summary": "Analytic models: median RMSE and number of surfaces where each fits best, by band.",
}


def caption_rst(stem: str) -> str:
    """The reStructuredText caption of a figure (for ``snakemake --report``)."""
    from .figures import FIGURES

    c = CAPTIONS[stem]
    title = FIGURES.get(stem, stem)
    return f"**{title}.**\n\n*Thesis:* {c['thesis']}\n\n*Ours:* {c['ours']}\n"


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


def thesis_table_html(tables: pd.DataFrame, table: int, aspect: float) -> str:
    """One of the thesis's Tables 1-2 for one aspect, in the thesis's form, ours beside the thesis's values.

    Rows are the thesis's models; for each model a row per source ('ours',
    'exact geometry' when present, 'thesis 2001'); columns Mean Abs Error,
    Standard Deviation, b0, b1, RSS.
    """
    spec = THESIS_TABLES[table]
    sel = tables[(tables["table"] == table) & (np.abs(tables["aspect"] - aspect) <= ASPECT_TOL)]
    label = aspect_label(aspect)
    tid = f"table{table}-aspect-{label.replace('√3/2', 'sqrt3-2')}"
    head = "<th>Model</th><th>Source</th>" + "".join(f"<th>{_e(m)}</th>" for m in TABLE_METRICS)
    rows = []
    order = {"ours": 0, "exact geometry": 1, "thesis 2001": 2}
    for model in spec["rows"]:
        block = sel[sel["model"] == model].sort_values("source", key=lambda s: s.map(order))
        for k, (_, r) in enumerate(block.iterrows()):
            cls = {"ours": "ours", "exact geometry": "exact", "thesis 2001": "thesis"}[r["source"]]
            first = f'<td rowspan="{len(block)}"><b>{_e(model)}</b></td>' if k == 0 else ""
            digits = {"Mean Abs Error": 2, "Standard Deviation": 2, "b0": 3, "b1": 3, "RSS": 3}
            cells = "".join(f"<td>{_e(_fmt(r[m], digits[m]))}</td>" for m in TABLE_METRICS)
            rows.append(f'<tr class="{cls}">{first}<td class="src">{_e(r["source"])}</td>{cells}</tr>')
    cap = f"Table {table}: {spec['title']} (aspect {label}, incidence 30)"
    return (f'<table class="thesis-table" id="{tid}" data-table="{table}" data-aspect="{_e(label)}">'
            f"<caption>{_e(cap)}</caption><thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table>")


def _figure(stem: str, figures: dict, notes: dict | None = None) -> str:
    from .figures import FIGURES

    title = FIGURES.get(stem, stem)
    cap = CAPTIONS.get(stem, {"thesis": "", "ours": ""})
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
        parts.append('<p>How far each Tables 1–2 statistic can be trusted: the bootstrap 95% intervals are in '
                     '<a href="#bootstrap-tables">the table under Tables 1 and 2</a>.</p>')
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
        fwd = "the square area function" if sq < fr else "the regressed sine model"
        bwd = "the triangle area function" if tr < br else "the regressed sine model"
        out.append(
            f"<li>Aspect {_e(lab)}: the forward lobe is fitted best by {fwd} (MAE {sq:.2f} against {fr:.2f}; "
            f"the thesis: 4.10 against 2.35), the back lobe by {bwd} (MAE {tr:.2f} against {br:.2f}; "
            f"the thesis: 4.96 against 1.71).</li>")
    if exact is not None and len(exact):
        err = exact["error"].abs()
        ex_sq = tables[(tables["source"] == "exact geometry") & tables["model"].str.contains("Area")]
        exact_line = ""
        if len(ex_sq):
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
<li><b>The thesis's "aspect 1.0" is our aspect √3/2.</b> The thesis says the brightest facet's normal at its aspect
1.0 is "30° back in the direction of the light source": side facets tilted 60°, i.e. our aspect √3/2
(atan(2·0.866) = 60°). At our aspect 1 (facets tilted 63.4°) the back lobe peaks at 23.1°, seven degrees off zero
phase. The lobe peaks, and so Tables 1–2, barely depend on this (the visible lit share is the same), but the lobe's
centre and the opposition behaviour do.</li>
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
            parts.append(f"{band}: {best['model']} (median RMSE {best['median_rmse']:.2f})")
        out.append(f"<li><b>{_e(comp)}</b>: " + "; ".join(_e(p) for p in parts) + "</li>")
    return "<p>Best model per band (most surfaces where it has the smallest RMSE):</p><ul>" + "".join(out) + "</ul>"


# ---------------------------------------------------------------------------
# the page


def build_report(
    tables: dict,
    figures: dict,
    config: dict | None = None,
    provenance: dict | None = None,
    messages: list | None = None,
    benchmarks: dict | None = None,
    stability_html: str | None = None,
    title: str = "roughlight: rough surface lighting behaviours, rebuilt",
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
    figures : dict stem -> PNG path (:data:`roughlight.figures.FIGURES` stems).
    config : the configuration used (shown as YAML).
    provenance : dict with ``versions`` (package -> version), ``inputs``
        (list of :func:`file_provenance` dicts), ``settings`` (analysis settings).
    messages : list of str, shown as notes (what was left out and why).
    stability_html : the "Where methods fail" section
        (:func:`roughlight.stability.report_section`); None: the section says
        how to make it (``make bench``).
    benchmarks : dict with optional ``png`` (path) and ``table`` (DataFrame)
        of the speed/accuracy benchmark; None: the section says it is absent.

    Returns
    -------
    str (UTF-8 HTML document)
    """
    import yaml

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
           ("stability", "Where methods fail"), ("provenance", "Settings and provenance")]
    parts.append("<nav><ul>" + "".join(f'<li><a href="#{a}">{_e(b)}</a></li>' for a, b in nav) + "</ul></nav>")

    # --- the study
    parts.append('<h2 id="study">The study</h2>')
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
        if find_aspect(aspects, SQRT3_2) is None:
            parts.append('<p class="note">Aspect √3/2 (0.8660254037844386, side facets at 60°, facing a light at '
                         "incidence 30 — the thesis's actual geometry) is not in this study: the tables and figures "
                         "below show aspect 1 only. Add it to <code>grid.aspect</code> to get its tables.</p>")
    parts.append(_notes(messages))

    # --- tables 1 and 2
    k_text = "k from geometry"
    if thesis is not None and len(thesis) and "k" in thesis:
        ks = thesis[thesis["source"] == "ours"].groupby("aspect_label")["k"].first()
        k_text = "k from geometry (" + ", ".join(f"{_e(a)}: {v:.4g}" for a, v in ks.items()) + ")"
    parts.append('<h2 id="tables">Tables 1 and 2</h2>')
    parts.append("<p>Data: the forward (mirror, elevation 180 − i) and back (the light-facing facet's mirror "
                 "direction) specular lobe peaks on the light's plane (azimuth 0), incidence 30, truncation "
                 "0–1. Models (m = J·m_s): square area <span class=\"formula\">m(1−t)²</span>, forward regressed "
                 "<span class=\"formula\">m(1 − sin(tπ/2))</span>, triangle area "
                 f"<span class=\"formula\">m·k·(1 − (1−t)²)</span> with {k_text}, back regressed "
                 "<span class=\"formula\">m·sin(tπ/2)/2</span>.</p>")
    if thesis is not None and len(thesis):
        for aspect in sorted(thesis["aspect"].unique(), reverse=True):
            for table in (1, 2):
                parts.append(thesis_table_html(thesis, table, aspect))
        parts.append(_table_findings(thesis, exact))
        parts.append(WHY_DIFFERENT)
    else:
        parts.append('<p class="note">Neither aspect 1 nor √3/2 at incidence 30 is in the study: Tables 1–2 '
                     "could not be computed.</p>")
    boot = tables.get("bootstrap_tables")
    if boot is not None and len(boot):
        b = boot.copy()
        b["interval"] = [f"[{lo:.3g}, {hi:.3g}]" for lo, hi in zip(b["low"], b["high"])]
        wide = b.pivot_table(index=["table", "aspect_label", "model"], columns="metric", values="interval",
                             aggfunc="first")
        wide = wide[[m for m in TABLE_METRICS if m in wide.columns]].reset_index()
        wide = wide.rename(columns={"aspect_label": "aspect"})
        n_boot = int(b["n_boot"].iloc[0])
        n_trunc = "/".join(str(int(n)) for n in sorted(b["n"].unique()))
        parts.append(_table(wide, TABLE_CAPTIONS["bootstrap_tables"] + f" ({n_boot} resamples of the {n_trunc} "
                            "truncations, seeded).", table_id="bootstrap-tables"))
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

    # --- figures
    parts.append('<h2 id="specular">The specular component (Figs. 17–26)</h2>')
    for stem in ("fig17_clipping", "fig20_plate_incidence", "fig21_specular_truncation", "fig23_forward_models",
                 "fig24_reflecting_areas", "fig25_back_models", "fig26_specular_aspect", "fig19_topdown"):
        parts.append(_figure(stem, figures))
    parts.append('<h2 id="diffuse">The diffuse component (Figs. 27–29)</h2>')
    for stem in ("fig27_diffuse_plate", "fig28_diffuse_truncation", "fig29_diffuse_aspect"):
        parts.append(_figure(stem, figures))
    dp = tables.get("diffuse_parts")
    if dp is not None and len(dp):
        want = [a for a in (1.0, SQRT3_2) if find_aspect(dp["aspect"], a) is not None]
        sel = dp[np.isin(dp["aspect"].round(12), [round(find_aspect(dp["aspect"], a), 12) for a in want])] \
            if want else dp.head(0)
        cols = ["truncation", "aspect", "e1", "e2", "level1", "level3", "rate", "decay_length", "rmse", "note"]
        sel = sel[cols].copy()
        sel["aspect"] = sel["aspect"].map(aspect_label)
        parts.append(_table(sel, "The three-part diffuse model (Ch. V.F) fitted on the azimuth-0 arc: breaks e1 "
                                 "(incidence) and e2 (front facet edge-on), levels of parts one and three, decay "
                                 "rate k (1/deg) and length 1/k (deg) of part two", table_id="diffuse-parts"))
    parts.append(_figure("diffuse_parts", figures))
    parts.append('<h2 id="pictures">Pictures of the surfaces (Figs. 9, 10, 13)</h2>')
    for stem in ("fig09_shadows", "fig10_grazing", "fig13_tops"):
        parts.append(_figure(stem, figures))

    # --- lobes
    parts.append('<h2 id="lobes">Lobes</h2>')
    parts.append(_figure("lobe_geometry", figures))
    lobes = tables.get("lobes")
    if lobes is not None and len(lobes):
        want = [find_aspect(lobes["aspect"], a) for a in (1.0, SQRT3_2)]
        want = [a for a in want if a is not None]
        sel = lobes[lobes["aspect"].isin(want) & lobes["lobe"].isin(["forward", "back"])].copy()
        sel["aspect"] = sel["aspect"].map(aspect_label)
        sel = sel[["truncation", "aspect", "incidence", "lobe", "predicted", "peak", "peak_elevation", "centroid",
                   "fwhm", "phase_at_peak", "note"]]
        parts.append(_table(sel, "Lobes on the azimuth-0 arc (peak 0-255; predicted centre, peak elevation, "
                                 "centroid and FWHM in degrees)", table_id="arc-lobes"))
    hemi = tables.get("lobes_hemisphere")
    if hemi is not None and len(hemi):
        want = [find_aspect(hemi["aspect"], a) for a in (1.0, SQRT3_2)]
        want = [a for a in want if a is not None]
        sel = hemi[hemi["aspect"].isin(want)].copy()
        sel["aspect"] = sel["aspect"].map(aspect_label)
        parts.append("<details><summary>Lobes over the whole hemisphere</summary>" +
                     _table(sel, "Lobes over the hemisphere: peak, where it is, and the solid angle above half "
                                 "maximum (sr) with the equivalent cone's full angle (deg)",
                            table_id="hemisphere-lobes") + "</details>")

    # --- GLMs
    parts.append('<h2 id="glm">Beyond the thesis: GLMs over the grid</h2>')
    parts.append("<p>Gaussian GLMs (IRLS) of the forward lobe peak, the back lobe peak and the diffuse level "
                 "(solid-angle weighted hemisphere mean) on truncation, aspect and their interaction (and incidence "
                 "when the grid has more than one). The plate surfaces (truncation 0 or aspect 0) are one surface "
                 "whatever the other parameter is and are kept out; terms are dropped when the centred and scaled "
                 "design is near-collinear.</p>")
    parts.append(_notes(tables.get("glm_messages", [])))
    parts.append(_table(tables.get("glm_summary"), TABLE_CAPTIONS["glm_summary"], table_id="glm-summary"))
    parts.append(_table(tables.get("glm_coefficients"), TABLE_CAPTIONS["glm_coefficients"],
                        table_id="glm-coefficients"))
    parts.append(_figure("glm_diagnostics", figures))

    # --- analytic models
    parts.append('<h2 id="models">Beyond the thesis: analytic rough-surface models</h2>')
    parts.append(
        "<p>Fitted to every view of every surface: <b>diffuse</b> — Lambert (the plate), Oren–Nayar's qualitative "
        "model with σ from the pyramid (RMS facet slope, σ = atan(2·aspect)·√(1 − (1−t)²)) and with σ fitted, "
        "and a "
        "Torrance–Sparrow facet model (each facet's 8-bit value × its share of the image × the V-cavity "
        "masking-shadowing term G = min(1, 2n_zV_z/(n·V), 2n_zL_z/(n·L))); <b>specular</b> — Phong on the plate, "
        "the facet model without masking and with the V-cavity term; <b>near opposition</b> — Hapke's shadow-hiding "
        "term B(g) = B0/(1 + tan(g/2)/h) on a linear phase background, fitted to the phase curve within "
        f"{_e(_fmt((provenance.get('settings') or {}).get('hapke_max_phase', 60), 0))}° of zero phase.</p>")
    msum = tables.get("model_fits_summary")
    parts.append(_model_findings(msum))
    if msum is not None and len(msum):
        parts.append(_table(msum[msum["band"] == "all"], TABLE_CAPTIONS["model_fits_summary"] + " All surfaces.",
                            digits=2, table_id="model-summary"))
        parts.append("<details><summary>By band of surfaces</summary>" +
                     _table(msum[msum["band"] != "all"], TABLE_CAPTIONS["model_fits_summary"], digits=2,
                            table_id="model-summary-bands") + "</details>")
    parts.append(_figure("model_fits", figures))
    parts.append(_figure("hapke", figures))

    # --- where methods fail: the renderers (make bench), then the regressions (always)
    if stability_html:
        parts.append(stability_html)
    else:
        parts.append('<h2 id="stability">Where methods fail</h2><p class="note">No stability measurements '
                     "(results/stability/) were available when this report was built: run <code>make bench</code> "
                     "and rebuild the report.</p>")
    parts.append(regression_failures_html(tables))
    # --- provenance
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
    parts.append(_figure("timings", figures))
    parts.append("<h3>Speed and accuracy of the renderer</h3>")
    if benchmarks and (benchmarks.get("png") or benchmarks.get("table") is not None):
        if benchmarks.get("png") and os.path.exists(benchmarks["png"]):
            parts.append(f'<figure id="fig-speed-accuracy"><img src="{png_data_uri(benchmarks["png"])}" '
                         'alt="speed and accuracy"><figcaption>Speed against accuracy of the renderer '
                         "(results/benchmarks/speed_accuracy.png).</figcaption></figure>")
        if benchmarks.get("table") is not None:
            parts.append(_table(benchmarks["table"], "Speed and accuracy benchmark", table_id="speed-accuracy"))
    else:
        parts.append('<p class="note">No speed/accuracy benchmark (results/benchmarks/speed_accuracy.png/.parquet) '
                     "was available when this report was built: section skipped.</p>")
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


def study_summary(study: pd.DataFrame) -> dict:
    """What the report says about the study table (grid, views, settings)."""
    keys = study[SURFACE_KEYS].drop_duplicates()
    comp = study["component"].astype(str)
    first = study.loc[comp == comp.iloc[0]]
    per = first.groupby(SURFACE_KEYS).size()
    row = study.iloc[0]
    return {
        "rows": int(len(study)),
        "surfaces": int(len(keys)),
        "views_per_surface": int(per.median()) if len(per) else 0,
        "truncations": sorted(float(x) for x in keys["truncation"].unique()),
        "aspects": sorted(float(x) for x in keys["aspect"].unique()),
        "incidences": sorted(float(x) for x in keys["incidence"].unique()),
        "light": float(row["light"]),
        "shininess": float(row["shininess"]),
        "shadows": bool(row["shadows"]),
        "method": str(row["method"]),
    }


def messages_json(messages) -> str:
    return json.dumps(list(messages), indent=1)
