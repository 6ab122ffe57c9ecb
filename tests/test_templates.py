"""The report page's Jinja2 templates: each renders from small data, shows that data, and escapes its text.

Every template of ``src/roughlight/report/templates/`` has a case here (a new template without one fails
``test_every_template_has_a_case``). A case is the data the template reads, with a ``<`` in its strings, and the
escaped text that must appear on the rendered HTML; the raw markup must not.
"""

from __future__ import annotations

import math
from pathlib import Path

import jinja2
import numpy as np
import pandas as pd
import pytest

from roughlight.report import page
from roughlight.report import page_templates as T

TEMPLATES = Path(T.__file__).resolve().parent / "templates"
NAN = float("nan")


@pytest.fixture
def png(tmp_path) -> str:
    """A file png_data_uri takes for a PNG (the signature is all it checks)."""
    path = tmp_path / "chart.png"
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + b"\x00" * 16)
    return str(path)


def figure(title: str, path=None, folded=False) -> dict:
    return {"stem": "fig99_test", "title": title, "thesis": "thesis <saw>", "ours": "ours <see>", "path": path,
            "exists": path is not None, "folded": folded}


def line() -> dict:
    """macros.html's validation_line data: one sampling setting, one component."""
    return {"n_surfaces": 2, "views": 12345, "settings": [
        {"setting": "configured", "views_per_second": 4321.0,
         "rows": [{"component": "total <c>", "worst": 0.61, "p99": 0.4, "largest_mae": 0.0213}]}]}


def thesis_table(model="Square <Area>") -> dict:
    return {"table": 1, "id": "table1-aspect-1", "label": "1", "title": "Forward <lobe>", "incidence": 30.0,
            "metrics": ["Mean Abs Error", "b0"], "digits": {"Mean Abs Error": 2, "b0": 3},
            "blocks": [{"model": model, "rows": [{"cls": "ours", "source": "ours", "cells": [1.234, -0.0001]},
                                                 {"cls": "thesis", "source": "thesis 2001", "cells": [4.1, NAN]}]}]}


# ---------------------------------------------------------------------------
# one case a template: (the template's data, the escaped text it must show, the raw text it must not)


def case_study(png):
    s = {"study": {"surfaces": 4, "aspects": [1.0, math.sqrt(3) / 2], "truncations": [0.0, 0.5],
                   "incidences": [30.0], "light": 127.0, "shininess": 64.0, "method": "fast <m>"},
         "followed": ["grid <follows>"], "missing": [0.5], "messages": ["left out <why>"]}
    return {"s": s}, ["fast &lt;m&gt;", "grid &lt;follows&gt;", "left out &lt;why&gt;", "Aspects: 1, √3/2",
                      "The table aspects 0.5", "shadows None"], ["<m>", "<why>"]


def case_tables(png):
    scales = pd.DataFrame({"table": [1.0], "model": ["Square <Area>"], "s_min_mae": [10.0], "s_max_mae": [20.0],
                           "s_min_sd": [11.0], "s_max_sd": [19.0], "stated_scale": [127.0], "stated_possible": [False],
                           "mean_error_at_stated": [-4.149], "mae": [4.1]})
    s = {"incidence": 30.0, "k": [("<1>", 0.5), ("0", NAN)], "printed": [thesis_table()],
         "maes": [{"label": "<a>", "forward_area": 1.0, "forward_regressed": 2.0, "back_area": NAN,
                   "back_regressed": 1.0}],
         "exact_error": {"max": 0.5, "mean": 0.25, "worst": 1e-12},
         "sd": {"n": 11, "broken": [{"table": 1, "model": "Model <1>", "rss": 122.4, "bound": 94.9}]},
         "implied": {"scales": scales, "at_scale": None, "area_wins": False},
         "bootstrap": {"wide": pd.DataFrame({"model": ["<boot>"], "b0": ["[1, 2]"]}), "n_boot": 200, "n_trunc": "11",
                       "unresampled": True},
         "sine": None, "exact": None}
    return {"s": s}, ["k from geometry (&lt;1&gt;: 0.5, 0: none, no side facets)", "Aspect &lt;a&gt;: the forward lobe is "
                      "fitted best by the square area function (MAE 1.00 against 2.00", "the back lobe could not be "
                      "compared", "they are the law of these lobe peaks.", "Table 1 Model &lt;1&gt;: RSS 122.4 > 94.9",
                      "is impossible: the mean error would be -4.15", "(200 resamples of the 11 truncations, seeded). – :",
                      'id="bootstrap-tables"', "<td>&lt;boot&gt;</td><td>[1, 2]</td>",
                      "The ranking of the models is reversed", 'class="thesis-table"'], ["<boot>", "<a>", "<1>"]


def case_thesis_table(png):
    return {"t": thesis_table()}, ['data-table="1" data-aspect="1"', "Forward &lt;lobe&gt; (aspect 1, incidence 30)",
                                   '<td rowspan="2"><b>Square &lt;Area&gt;</b></td>', "<td>1.23</td>",
                                   "<td>0.000</td>", "<td>–</td>"], ["<Area>", "-0.000"]


def case_figures(png):
    s = {"section": "specular", "figures": [figure("Fig. <1>", png), figure("Fig. <2>"), figure("Fig. <3>", png, True)]}
    return {"s": s}, ['<h2 id="specular">The specular component', 'id="fig-fig99_test"', 'alt="Fig. &lt;1&gt;"',
                      "<b>Fig. &lt;1&gt;.</b>", "thesis &lt;saw&gt;", "Figure Fig. &lt;2&gt; is missing (not produced)",
                      "data:image/png;base64,", '<details class="fold secondary"><summary>Fig. &lt;3&gt; (figure)'
                      '</summary>\n<figure id="fig-fig99_test"><img'], ["<saw>", "<see>"]


def case_diffuse_parts(png):
    return {"s": {"table": pd.DataFrame({"truncation": [0.5], "note": ["fit <failed>"]})}}, [
        'id="diffuse-parts"', "<td>0.500</td>", "fit &lt;failed&gt;"], ["<failed>"]


def case_lobes(png):
    arc = pd.DataFrame({"lobe": ["<forward>"], "peak": [NAN]})
    s = {"figures": [figure("Lobes <g>")], "arc": arc, "protocols": True, "hemisphere": arc.head(0)}
    shown = ['id="arc-lobes"', "&lt;forward&gt;", "<td>–</td>", "the exact reference's FWHM",
             '<p class="note">Lobes over the hemisphere: peak, where', ": no rows."]
    return {"s": s}, shown, ["<forward>", "<g>", "<details"]  # one row: not folded


def case_glm(png):
    laws = pd.DataFrame({"lobe": ["back"], "incidence": [30.0], "model": ["share <k>"], "rmse_held_out": [1.234],
                         "rmse": [1.0], "parameters": [2.0]})
    s = {"messages": ["term <dropped>"], "summary": pd.DataFrame({"status": ["<ok>"]}), "coefficients": None,
         "laws": laws, "best_laws": laws, "figures": []}
    return {"s": s}, ["term &lt;dropped&gt;", "&lt;ok&gt;", 'id="glm-summary"', "95% intervals computed as if the "
                      "residuals were noise: the data are deterministic, the residuals are lack of fit, so these measure "
                      "sensitivity, not sampling uncertainty.: no rows.",
                      "back lobe, incidence 30: best held out <b>share &lt;k&gt;</b> (RMSE 1.23 held out, 1.00 in-sample, "
                      "2 parameters)", 'id="share-laws"'], ["<dropped>", "<k>"]


def case_models(png):
    summary = pd.DataFrame({"band": ["all"], "model": ["<lambert>"], "median_rmse": [1.0]})
    s = {"hapke_max_phase": 45.0, "hapke": {"n": 3, "by_aic": 2, "held": 1}, "sigma_bound": {"n_bound": 1, "n_rough": 2},
         "findings": [{"component": "<diffuse>", "bands": [{"band": "low", "model": "<on>", "rmse": 1.5},
                                                          {"band": "high", "model": "x", "rmse": NAN}]}],
         "summary_all": summary, "summary_bands": summary.head(0), "figures": []}
    return {"s": s}, ["within 45° of zero phase", "on the 3 rough surfaces: preferred by AIC on 2, lower held-out "
                      "RMSE on 1", "on 1 of 2 rough surfaces", "<b>&lt;diffuse&gt;</b>: low: &lt;on&gt; (median RMSE "
                      "1.50); high: no model could be fitted", "<td>1.00</td>", 'id="model-summary"'], ["<on>"]


def case_regressions(png):
    s = {"summary": pd.DataFrame({"response": ["back_peak"], "status": ["not <fitted>"]}), "messages": ["why <not>"],
         "noted": pd.DataFrame(), "bootstrap": False}
    return {"s": s}, ['<h3 id="stability-regressions">', 'id="regression-status"', "not &lt;fitted&gt;",
                      "why &lt;not&gt;", "Every Tables 1–2 regression line was fitted and converged.",
                      "No bootstrap intervals were available"], ["<fitted>", "<not>", 'id="regression-notes"']


def case_provenance(png):
    s = {"timings_summary": {"sweeps": 2, "views": 10, "total_seconds": 1.26, "median_seconds": 0.5,
                             "max_seconds": 0.75, "slowest": "t <1>", "views_per_second": 7.9, "methods": "fast"},
         "timings": None, "figures": [],
         "settings": "hapke_max_phase: 60\nnote: a <b>\n", "config": None,
         "versions": pd.DataFrame({"package": ["numpy"], "version": ["<2>"]}), "inputs": None,
         "renderers": ["llvmpipe <x>, OpenGL 4.5, egl"]}
    return {"s": s}, ["2 sweeps, 10 views, 1.3 s in all (median 0.50 s, max 0.75 s for t &lt;1&gt;); 8 views/s",
                      "<pre>hapke_max_phase: 60\nnote: a &lt;b&gt;\n</pre>", "&lt;2&gt;", 'id="versions"',
                      '<ul id="renderers"><li>llvmpipe &lt;x&gt;, OpenGL 4.5, egl</li></ul>'], ["<b>", "<1>", "<x>"]


def case_light_transport(png):
    agreement = pd.DataFrame({"kind": ["<pyramids>"], "component": ["diffuse"], "worst": [0.3]})
    summary = pd.DataFrame({"truncation": [0.5], "aspect": [1.0], "albedo": [1.0], "views": ["<hemisphere>"]})
    s = {"plan": "quick", "level": 1.0, "bounces": 8, "png": png, "caption": "caption <c>", "summary": summary,
         "agreement": {"rows": [{"component": "<diffuse>", "surfaces": 12, "views": 336, "worst": 0.31,
                                 "worst_surface": "random <x>", "largest_mae": 0.04}],
                       "within": True, "variant": "mitsuba <llvm>", "table": agreement},
         "gains": [{"albedo": 1.0, "surfaces": 9, "within": 1, "within_surfaces": [(0.25, 0.25)], "mean_low": 0.5,
                    "mean_high": 12.0, "percent_low": 3.0, "percent_high": 95.0, "worst": 30.2, "worst_percent": 140.0,
                    "worst_surface": (1.0, 1.0)}]}
    return {"s": s}, ['<h2 id="light-transport">', "Mitsuba (mitsuba &lt;llvm&gt;)", "&lt;diffuse&gt; worst 0.31 (on "
                      "random &lt;x&gt;)", "336 views. Every view is within one level", "bounces 8 times",
                      "albedo 1: a mean gain of 0.5–12.0 levels over the hemisphere (3–95% of direct light), at worst "
                      "30.2 levels (140%) on truncation 1, aspect 1; 1 of 9 surfaces stay within one level at every "
                      "view (t 0.25, a 0.25)", 'id="fig-light-transport"', "caption &lt;c&gt;", "&lt;pyramids&gt;",
                      "&lt;hemisphere&gt;", "make bench"], ["<diffuse>", "<llvm>", "<c>", "switched off"]


def case_speed(png):
    s = {"png": png, "table": pd.DataFrame({"label": ["<l>"]}), "validation": None}
    return {"s": s}, ['<h2 id="speed">', 'id="fig-speed-accuracy"', f"Speed against accuracy of the renderer ({png}).",
                      "&lt;l&gt;"], ["<l>", "switched off"]


def case_renderer_validation(png):
    smooth = pd.DataFrame({"figure": ["fig <21>"], "truncation": [0.5], "aspect": [0.8660254], "at_elevation": [150.0],
                           "largest_deviation": [0.456]})
    tiles = {"table": pd.DataFrame({"kind": ["random_<x>"], "worst": [0.78]}), "worst": 0.78, "largest_mae": 0.085}
    s = {"line": line(), "png": None, "validation": pd.DataFrame({"component": ["<d>"]}), "smoothness": smooth,
         "worst": smooth.iloc[0], "tiles": tiles}
    return {"s": s}, ["(2 surfaces x 12,345 views", "the configured renderer: worst view total &lt;c&gt; 0.61 (p99 "
                      "0.40, MAE up to 0.021), 4,321 views/s.", "&lt;d&gt;", "is 0.46 (fig &lt;21&gt;, truncation 0.5, "
                      "aspect 0.866, e = 150)", 'id="arc-smoothness"', "the worst view of any tile is 0.78 of an 8-bit "
                      "level", "largest MAE of a tile's component 0.085", 'id="renderer-validation-tiles"',
                      "random_&lt;x&gt;"], ["<d>", "<21>", "fig-renderer-validation", "<x>"]


def case_stability(png):
    safe = pd.DataFrame({"method": ["<fast>"], "min_pixels": [8.0], "max_shininess": [NAN]})
    normals = pd.DataFrame({"mae total": [1.5]}, index=["<gouraud>"])
    s = {"plan": "<quick>", "n_fast": 3, "n_naive": 2, "tolerance": 0.5, "safe": safe, "png": png,
         "clipped": [("<src>", 255.0, 0.25)], "line": line(), "normals": {"table": normals, "surfaces": [(0.5, 1.0)]}}
    return {"s": s}, ["(&lt;quick&gt; plan): the fast method on 3 surfaces, the naive one (one render a view) on 2",
                      "<td>&lt;fast&gt;</td><td>8</td><td>never</td>", "total clipped: &lt;src&gt; at 255: 25%.",
                      'id="stability-every-view">The fast renderer at every view', "surfaces t=0.5 a=1, incidence 30",
                      "<tr><td>&lt;gouraud&gt;</td><td>1.5</td></tr>"], ["<fast>", "<gouraud>", "<quick>"]


def case_implicit(png):
    s = {"plan": "<quick>", "n_surfaces": 4, "n_views": 2000, "summary": pd.DataFrame({"method": ["<exact>"]}),
         "held_out": {"surfaces": 4, "views": 2000, "lights": 12, "light_views": 40},
         "png": png, "caption": "caption <text>", "maps_png": None, "maps_caption": None,
         "frames": pd.DataFrame({"field": [4], "frame_ms": [1.5]}),
         "targets": {"max_mae": 0.25, "worst": 1.0, "speedup": 100.0},
         "goal": [{"method": "implicit_<exact>", "surfaces": 4, "max_mae": 0.02, "worst": 0.25, "memory_bytes": 0.0,
                   "field": 256, "frame_ms": 40.0, "speedup": 2.0, "draw_ms": 38.5, "draw_speedup": 2.1, "accurate": True,
                   "fast": False, "meets": False},
                  {"method": "implicit_table", "surfaces": 1, "max_mae": 0.04, "worst": 0.9, "memory_bytes": 8.2e6,
                   "field": 256, "frame_ms": 1.0, "speedup": 120.0, "draw_ms": 0.6, "draw_speedup": 190.0, "accurate": True,
                   "fast": True, "meets": True}]}
    return ({"s": s}, ["Measured at the <code>&lt;quick&gt;</code> plan", "Validation: 4 surfaces, 2,000 views each",
                      "off every node, 12 lights drawn at random (incidence 5–85°, any azimuth) on the same surfaces, "
                      "each seen from 40 random views",
                      "&lt;exact&gt;", 'id="fig-implicit"', "caption &lt;text&gt;",
                      "<td>4.000</td><td>1.500</td>",  # a row of numbers only is floats, as iterrows gives it
                      "x<sub>2</sub> the second-largest view shear", 'id="implicit-goal"',
                      "implicit_&lt;exact&gt; is accurate enough but 2× is short of the speed",
                      "<b>implicit_table meets it</b>", "<td>0 (uniforms)</td>", "<td>8.20 MB</td>",
                      "<b>Table</b> (<code>render.method: implicit_table</code>)"],
                     ["<exact>", "<text>", "fig-implicit-maps"])


def case_export(png):
    methods = {"implicit_table": {"mae": 0.39, "p99": 3.4, "worst": 12.06, "within": False, "megabytes": 8.21,
                                  "file_megabytes": 2.2, "views": 1200, "worst_above": 11.0, "worst_incidence": 17.0},
               "mitsuba_measured": {"mae": 1.18, "p99": 7.0, "worst": 16.2, "within": False, "megabytes": 4.4,
                                    "file_megabytes": 4.43, "views": 1200, "worst_above": 11.0,
                                    "worst_incidence": 17.0, "worst_component": "diffuse"}}
    elsewhere = {**methods, "mitsuba_measured": {**methods["mitsuba_measured"], "worst_above": 45.0,
                                                 "worst_incidence": 43.3, "worst_component": "specular"}}
    s = {"surfaces": [{"truncation": 1.0, "aspect": 1.0, "methods": methods, "seconds": 25.0, "table_seconds": 18.0},
                      {"truncation": 0.5, "aspect": 1.0, "methods": elsewhere, "seconds": 25.0, "table_seconds": 18.0}],
         "summary": pd.DataFrame({"method": ["<implicit_table>"], "worst": [12.06]}), "png": png,
         "caption": "caption <export>"}
    return ({"s": s}, ['<h2 id="export">', "truncation 1, aspect 1: the share table (8.2 MB of texture, 2.2 MB on "
                      "disk) has an MAE of 0.39 over 1,200 views and its worst view is 12.1 levels off (a view 11° above the "
                      "plane, the light at incidence 17°)",
                      "the Mitsuba file (4.4 MB), rendered by Mitsuba on a flat quad, an MAE of 1.18 and a worst view "
                      "16.2 off (the same view)", "a worst view 16.2 off (a view 45° above the plane, the light at "
                      "incidence 43°)",
                      "neither is within one level at every view", "Measured and checked in 25 s",
                      'need nodes closer than these (docs/export.md, "Light azimuth nodes"). Measured',
                      "and the Mitsuba file's worst view is its specular's, the Phong lobe's peak",
                      'id="fig-export"', "caption &lt;export&gt;", "&lt;implicit_table&gt;"],
                     ["<export>", "<implicit_table>", "Nothing exported"])


def case_random(png):
    frame = pd.DataFrame({"kind": ["random_<x>"], "mean": [0.7]})
    claim = pd.DataFrame({"kind": ["random <x>"], "test": ["back lobe: squareness"], "unrounded: verdict": ["undecided"],
                          "why (unrounded)": ["<more seeds>"]})
    s = {"settings": {"cells": 4, "spread": {"truncation": "<0.2>"}},
         "tests": [{"test": "phase <shift>", "role": "shape", "claim": "random lobes <peak>", "shows": "mean <distance>",
                    "unit": "deg", "low": 0.012, "high": 0.05, "from": "view <grid>"}],
         "family": {"tests": 28, "level": 1 - 0.05 / 28, "alpha": 0.05}, "design": frame, "geometry": frame,
         "grid": frame, "counts": {"unrounded": {"lobe": 8, "no <lobe>": 4}},
         "claim": claim, "charts": [("fig-random-maps", png, "maps", "maps <caption>")], "shown": frame,
         "best": [{"kind": "random_<x>", "component": "diffuse", "model": "<lambert>",
                   "means": [("<lambert>", 1.0), ("facets", 2.5)]}],
         "fits": frame, "opposition": frame, "seeds": frame, "plan": "quick", "accuracy": None, "convergence": None,
         "tiles_png": None, "tiles_caption": None}
    return {"s": s}, ["a tile of 4 × 4 cells", "truncation t ± &lt;0.2&gt;, aspect a·(1 ± ?)",
                      "<b>phase &lt;shift&gt;</b>: random lobes &lt;peak&gt;; the mean &lt;distance&gt;. Margin "
                      "0.012–0.05° over the grid points, set most often by the view &lt;grid&gt;", 'id="random-claim"',
                      "the 28 planned tests are corrected together (Bonferroni): each interval is a Student-t interval "
                      "at the 99.82% level", 'id="random-claim-plan"', 'id="random-claim-geometry"',
                      'id="random-claim-grid"', "8 lobe, 4 no &lt;lobe&gt;",
                      "&lt;more seeds&gt;", 'id="fig-random-maps"', "maps &lt;caption&gt;",
                      "random &lt;x&gt;, diffuse: best <b>&lt;lambert&gt;</b> (mean RMSE over its grid points: "
                      "&lt;lambert&gt; 1.00; facets 2.50)", 'id="random-seeds"',
                      'id="random-models-opposition"'], ["<x>", "<lambert>", "random-accuracy"]


def case_findings(png):
    lobe = {"lobe": "forward", "table": 1, "area": (0.04, 0.06), "regressed": (3.42, 3.42), "ours": "area",
            "thesis": "regressed", "thesis_area": 4.1, "thesis_regressed": 2.35}
    test = {"name": "back_phase_shift", "test": "phase <shift>", "claim": "less <shift>", "unit": "deg", "n": 8,
            "verdicts": [("difference against the claim", 7), ("undecided", 1)], "mean": (4.871, 13.67),
            "regular": (0.08, 0.53), "margin": (2.38, 2.38), "seeds": (16, 16)}
    s = {"accuracy": {"n_surfaces": 3, "views": 1315, "setting": "configured", "worst": 0.49, "component": "<diffuse>",
                      "mae": 0.0461, "tiles": {"worst": 0.42, "largest_mae": 0.086}, "target": "renderer-validation"},
         "exact": {"max": 0.29, "mean": 0.06, "worst": 4.6e-15, "target": "exact-peaks"},
         "implicit": {"why": "switched_off"},
         "implied": {"scales": [{"table": 1, "model": "Square <Area>", "mae": 4.1, "low": 139.04, "high": 1115.2,
                                 "stated": 127.0, "possible": False}],
                     "at_scale": [{"table": 1, "model": "Square <Area>", "scale": 139.04, "area": (4.21, 4.27),
                                   "thesis": 4.1, "regressed": (7.96, 8.02), "area_wins": True}],
                     "target": "implied-scale"},
         "incidence": 30.0, "laws": {"why": "no_laws"},
         "random": {"readings": {"unrounded": {"tests": [test], "headline": "refuted", "n_tests": 8},
                                 "8-bit": {"tests": [test], "headline": "mixed", "n_tests": 8}},
                    "regular": {"back": {"span": (-0.18, -0.15), "points": 2, "shape": "ellipse"},
                                "halo": {"span": (0.76, 0.99), "points": 4, "shape": "flat"}},
                    "kinds": 2, "points": 4, "level": 1 - 0.05 / 8, "target": "random-claim"},
         "ranking": {"labels": ["<1>"], "lobes": [lobe], "verdict": "reversed", "target": "tables"},
         "speed": {"label": "fast <P=28>", "views": 72, "fast_vps": 1177.2, "naive_vps": 29.1, "speedup": 40.47,
                   "fast_worst": 0.21, "naive_worst": 8.11, "fast_mae": 0.0406, "naive_mae": 1.968,
                   "target": "speed-accuracy"},
         "light": {"agreement": [("<diffuse>", 0.31)], "agrees": True, "target": "light-transport",
                   "albedos": [{"albedo": 1.0, "within": 2, "surfaces": 9, "worst": 28.4, "mean": (0.4, 12.5),
                                "percent": (3.0, 96.0)},
                               {"albedo": 0.5, "within": 5, "surfaces": 9, "worst": 9.1, "mean": (0.2, 4.1),
                                "percent": (1.0, 33.0)}]},
         "table_aspects": [1.0]}
    return {"s": s}, ['<section id="findings"><h2>Findings</h2>', "the other way round from the thesis",
                      "within a level of physical light transport on 2 of 9 surfaces", "&lt;diffuse&gt; worst 0.31",
                      "albedo 0.5 adds 0.2–4.1 levels on average over the hemisphere (1–33%), at worst 9.1",
                      '<a href="#light-transport">',
                      "MAE at aspects &lt;1&gt;, incidence 30: forward lobe, square area function 0.04–0.06 against the "
                      "regressed model's 3.42 (the thesis: 4.10 against 2.35)", '<a href="#tables">',
                      "their MAE is at most 4.6e-15", "allow its square &lt;area&gt; a scale s in [139.0, 1115.2], not "
                      "the stated 127", "At s = 139.0, the smallest allowed", '<a href="#implied-scale">',
                      "No share law could be fitted", "(<code>report.implicit: false</code>)",
                      "its squareness is -0.180 to -0.150 at the 2 grid points", "flatness 0.76–0.99 at 4 grid points",
                      "No test of the thesis's random-roughness claim finds "
                      "the difference it claims.", "phase &lt;shift&gt;: difference against the claim in 7, undecided "
                      "in 1 of 8 (random 4.87–13.67° against the regular 0.08–0.53°)",
                      "Read at 8 bits, as the thesis's framebuffer: phase &lt;shift&gt;: difference against",
                      "worst view 0.49 (&lt;diffuse&gt;), "
                      "MAE at most 0.046 (3 surfaces × 1,315 views); random tiles: worst view 0.42",
                      "40.5 times as fast as the naive method and more accurate", "(fast &lt;P=28&gt;) it draws 1,177 "
                      "views/s against the naive method's 29", '<a href="#speed-accuracy">'], ["<shift>", "<P=28>",
                                                                                             "<diffuse>", "<1>"]


def case_explorer(png):
    s = {"index": '{"datasets":[]}', "data": "eJwDAAAAAAE=", "script": "window.x = '<raw>';", "scripts": [],
         "held": {"control": 1, "regular": 2, "means": 0, "seeds": 0}, "views": 12345, "azimuths": 5,
         "elevations": 2469, "bytes": 1_234_567, "budget": 2_000_000,
         "left_out": [{"kind": "k", "name": "kind <k>", "what": "seeds", "count": 3, "seeds": [2, 3, 4]}]}
    return {"s": s}, ['<section id="explorer">', "every one of its 12,345 views (5 azimuths × 2469 elevations)",
                      "1 control sweep(s), 2 regular surface(s)", "(1.23 MB of the <code>report.explorer.budget"
                      "</code> of 2.00 MB)", "3 seeds of kind &lt;k&gt; (seeds 2, 3, 4)",
                      '<script type="application/json" id="explorer-index">{"datasets":[]}</script>',
                      "<script>window.x = '<raw>';</script>"], ["kind <k>"]


CASES = {"explorer.html": case_explorer, "findings.html": case_findings, "study.html": case_study,
         "tables.html": case_tables,
         "thesis_table.html": case_thesis_table, "figures.html": case_figures, "diffuse_parts.html": case_diffuse_parts,
         "lobes.html": case_lobes,
         "glm.html": case_glm, "models.html": case_models, "regressions.html": case_regressions,
         "provenance.html": case_provenance, "speed.html": case_speed, "light_transport.html": case_light_transport,
         "renderer_validation.html": case_renderer_validation,
         "stability.html": case_stability, "implicit.html": case_implicit, "random.html": case_random,
         "export.html": case_export}
#: Templates tested apart: the page (base.html), the pieces the others use (macros.html) and the static text
#: tables.html includes (why_different.html, in case_tables).
APART = {"base.html", "macros.html", "why_different.html"}


def test_every_template_has_a_case():
    assert {p.name for p in TEMPLATES.glob("*.html")} == set(CASES) | APART
    assert (TEMPLATES / "report.css").exists()


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_template_renders_its_data_escaped(name, png):
    context, shown, hidden = CASES[name](png)
    html = T.render(name, **context)
    for text in shown:
        assert text in html, (name, text)
    for text in hidden:
        assert text not in html, (name, text)
    assert "{{" not in html and "{%" not in html and "{#" not in html, name


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_template_names_what_it_lacks(name, png):
    """Undefined data is an error, not an empty string on the page."""
    context, _, _ = CASES[name](png)
    key = next(iter(context))
    data = dict(context[key])
    data.pop(sorted(data)[0])
    with pytest.raises(jinja2.UndefinedError):
        T.render(name, **{key: data})


def test_the_page_inlines_the_stylesheet_and_escapes_its_title():
    html = page.build_report({"study_summary": {"messages": ["a note <with> markup"]}}, {}, title="roughlight <test>",
                             followed=["report.table_aspects <follows>"])
    assert html.startswith("<!DOCTYPE html>") and html.rstrip().endswith("</html>")
    assert "<title>roughlight &lt;test&gt;</title>" in html and "<h1>roughlight &lt;test&gt;</h1>" in html
    assert '<p class="note">a note &lt;with&gt; markup</p>' in html and "<with>" not in html
    assert "report.table_aspects &lt;follows&gt;" in html
    css = (TEMPLATES / "report.css").read_text(encoding="utf-8").strip()
    assert css and css in html and html.count("<style>") == 1
    for anchor in ("study", "tables", "specular", "diffuse", "pictures", "lobes", "glm", "models", "implicit", "random",
                   "stability", "speed", "provenance"):  # every section is on the page, and in the contents
        assert f'<h2 id="{anchor}">' in html and f'<a href="#{anchor}">' in html, anchor


def test_every_section_is_data_its_template_renders_on_the_page():
    """One contract for the page's sections (sections.SECTIONS): a function from inputs named by its parameters to
    its template's data, which base.html includes once; no section arrives as HTML, and a section rendered alone is
    the page's."""
    import inspect

    from roughlight.report import sections

    base = (TEMPLATES / "base.html").read_text(encoding="utf-8")
    for section in sections.SECTIONS:
        assert (TEMPLATES / section.template).exists(), section.name
        parameters = inspect.signature(section.build).parameters.values()
        assert all(p.default is not p.empty for p in parameters if p.name != "section"), section.name
        assert not any(p.name.endswith("_html") for p in parameters), section.name
    assert "_html" not in base and "|safe" not in base
    off = page.build_report({}, {})
    assert '<h2 id="stability">Where methods fail</h2><p class="note">The stability scans are switched off' in off
    assert page.render_section("models") in off and page.render_section("regressions") in off


def test_the_table_macro_formats_and_escapes_cells():
    frame = pd.DataFrame({"a <1>": [1.23456, -0.0001], "n": [np.int64(3), np.int64(4)], "s": ["x < y", None]})
    html = T.render_macro("macros.html", "table", frame, "caption <c>", 2, "t-id")
    assert html.startswith('<table id="t-id"><caption>caption &lt;c&gt;</caption>')
    assert "<th>a &lt;1&gt;</th>" in html and "<td>1.23</td>" in html and "<td>0.00</td>" in html
    assert "<td>x &lt; y</td>" in html and "<td>3</td>" in html and "<td>–</td>" in html  # None: missing
    assert T.render_macro("macros.html", "table", frame.head(0), "empty <e>") == \
        '<p class="note">empty &lt;e&gt;: no rows.</p>'


def test_the_filters_format_numbers_as_the_page_did():
    assert [T.cell(v) for v in (1.0, -0.0001, NAN, math.inf, True, np.int64(7), None, "a")] == \
        ["1.000", "0.000", "–", "∞", "yes", "7", "", "a"]
    assert [T.domain(v) for v in (0.12345, NAN, None, "flat")] == ["0.123", "never", "never", "flat"]


def test_the_validation_line_is_plain_text():
    """renderer_validation_line renders the template's sentence and returns it unescaped, as before."""
    text = T.plain_text(T.render_macro("macros.html", "validation_line", line()))
    assert text == ("The fast renderer at every view (2 surfaces x 12,345 views against the exact reference; the goal is "
                    "a worst view within one 8-bit level): the configured renderer: worst view total <c> 0.61 (p99 0.40, "
                    "MAE up to 0.021), 4,321 views/s.")


def test_the_templates_load_from_the_package():
    env = T.environment()
    assert isinstance(env.loader, jinja2.PackageLoader) and env.autoescape is True
    assert set(env.list_templates()) >= set(CASES) | APART | {"report.css"}


def test_a_changed_template_caption_or_section_changes_the_pages_code_digest(tmp_path):
    """Rule report_html takes the page's code digest as a param: a template, caption or section edited reruns the
    page; the figures' code (drawn by the figure rules), caches and the package's README do not."""
    import shutil

    from roughlight.report import registry

    root = tmp_path / "report"
    shutil.copytree(Path(registry.__file__).resolve().parent, root)
    digest = registry.page_code_digest(root)
    assert digest == registry.page_code_digest(root) == registry.page_code_digest()
    for left_out in ("figures/common.py", "README.md"):
        (root / left_out).write_text((root / left_out).read_text() + "\n# edited\n")
    (root / "__pycache__").mkdir(exist_ok=True)
    (root / "__pycache__" / "x.pyc").write_bytes(b"cache")
    assert registry.page_code_digest(root) == digest
    for edited in ("templates/random.html", "captions/random_claims.rst", "sections/random.py"):
        before = registry.page_code_digest(root)
        (root / edited).write_text((root / edited).read_text() + " ")
        assert registry.page_code_digest(root) != before, edited


def test_captions_the_page_shows_whole_lose_their_rst_literal_markup(tmp_path, monkeypatch):
    """The page shows a caption file as plain text: an RST inline literal (two backquotes either side, what
    Snakemake's report sets as code) reaches the page as its text alone, whichever way the page reads the file."""
    from roughlight.report import registry

    shipped = T.caption_text("random_ensembles")
    assert "surface.seeds" in shipped and "``" not in shipped
    assert "``surface.seeds``" in (registry.CAPTION_DIR / "random_ensembles.rst").read_text(encoding="utf-8")
    (tmp_path / "x.rst").write_text("A ``results/a.csv`` and\n``b``.\n\n*On the page:* the ``c`` column.\n")
    monkeypatch.setattr(registry, "CAPTION_DIR", tmp_path)
    assert T.caption_text("x") == "A results/a.csv and\nb.\n\n*On the page:* the c column."
    assert T.table_caption("x") == "the c column."
