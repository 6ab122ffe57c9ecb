"""The HTML report: built from a small rendered study, opened in headless Chromium.

The study is rendered here (fast renderer, a 3 x 4 grid, coarse views);
the report is built with the same package functions the workflow's scripts
call. Chromium loads it from disk and a script injected into a copy of the
page records, after ``load``, which images failed to decode; we read that
from ``--dump-dom``. A screenshot is kept in the test's directory.
"""

from __future__ import annotations

import base64
import fcntl
import hashlib
import json
import math
import os
import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from roughlight.analysis.areas import reflecting_areas
from roughlight.analysis.diffuse import diffuse_levels, diffuse_three_part
from roughlight.analysis.glm import grid_glms
from roughlight.analysis.lobes import arc_lobes, hemisphere_lobes
from roughlight.analysis.share_laws import share_law_fits
from roughlight.analysis.surface_models import analytic_model_fits, model_fit_summary
from roughlight.analysis.thesis import (
    exact_lobe_peaks,
    implied_scales,
    sine_refits,
    tables_at_implied_scale,
    thesis_tables,
)
from roughlight.analysis.timings import render_timings
from roughlight.render import pictures
from roughlight.render.gl import context as gl_context
from roughlight.render.shading import Lighting
from roughlight.report import figures as F
from roughlight.report import page as R
from roughlight.report import page_templates as T
from roughlight.report import registry
from roughlight.report.explorer import DEFAULT_BUDGET, explorer_data, study_columns
from roughlight.report.sections.explorer import explorer_script
from roughlight.study.selection import find_aspect
from roughlight.study.tables import study_summary
from roughlight.surfaces.surface import aspect_label

from .browser import Browser
from .conftest import REPO
from .test_analysis import make_study
from .test_explorer import check_explorer
from .users_workflow import GRIDS, MEASUREMENTS, grid_config, user_file
from .workflow_copy import copy_finished

S32 = math.sqrt(3.0) / 2.0
SETTINGS = {"table_aspects": [1.0, S32], "table_incidence": 30, "lobe_halfwidth": 40, "collinearity_limit": 100,
            "hapke_max_phase": 60, "exact_check": True}

#: The figures rules figures and render_figures draw: the page's figures when no measurement runs (each
#: measurement's chart is drawn by its own rule, through the same registry).
FIGURE_RULES_DRAW = [f for f in registry.FIGURES if f.rule in ("figures", "render_figures")]


def build_report_from_study(study: pd.DataFrame, workdir: Path, render: bool = True) -> Path:
    """Everything the workflow's report rules do, in-process: tables, figures, the HTML page."""
    lighting = Lighting()
    fig_dir = workdir / "figures"
    lobes = arc_lobes(study)
    parts = diffuse_three_part(study)
    levels = diffuse_levels(study)
    exact = exact_lobe_peaks(lobes, SETTINGS["table_aspects"], 30.0, lighting)
    tables, messages = thesis_tables(lobes, SETTINGS["table_aspects"], 30.0, m=127.0, exact=exact)
    sine = sine_refits(lobes, SETTINGS["table_aspects"], 30.0)
    glm_summary, glm_coefs, glm_diag, glm_messages = grid_glms(lobes, levels)
    laws = share_law_fits(lobes)
    fits = analytic_model_fits(study)
    per_sweep, timing_summary = render_timings(study)
    areas = pd.concat([reflecting_areas(a, 30.0, np.linspace(0, 1, 5)).assign(aspect=a)
                       for a in (find_aspect(study["aspect"], w) for w in SETTINGS["table_aspects"]) if a is not None],
                      ignore_index=True)
    figs = {
        "fig19_topdown": F.fig19_topdown(study),
        "fig21_specular_truncation": F.fig21_specular_truncation(study),
        "fig23_forward_models": F.fig23_forward_models(lobes, sine, exact_peaks=exact),
        "fig24_reflecting_areas": F.fig24_reflecting_areas(areas),
        "fig25_back_models": F.fig25_back_models(lobes, sine, exact_peaks=exact),
        "fig26_specular_aspect": F.fig26_specular_aspect(study),
        "fig27_diffuse_plate": F.fig27_diffuse_plate(study),
        "fig28_diffuse_truncation": F.fig28_diffuse_truncation(study, parts),
        "fig29_diffuse_aspect": F.fig29_diffuse_aspect(study),
        "lobe_geometry": F.fig_lobe_geometry(lobes),
        "diffuse_parts": F.fig_diffuse_parts(parts),
        "glm_diagnostics": F.fig_glm_diagnostics(glm_diag, glm_summary),
        "model_fits": F.fig_model_fits(fits),
        "hapke": F.fig_hapke(study, fits),
        "timings": F.fig_timings(per_sweep),
    }
    if render:
        plates = pictures.plate_sweeps([0, 30, 60, 90], [127, 255], elevation_step=2.0)
        figs["fig17_clipping"] = F.fig17_clipping(plates[plates["incidence"] == 30])
        figs["fig20_plate_incidence"] = F.fig20_plate_incidence(plates[plates["light"] == 127])
        for stem in ("fig09_shadows", "fig10_grazing", "fig13_tops"):
            _, views = pictures.PICTURE_SETS[stem]
            figs[stem] = F.fig_pictures(stem, pictures.surface_pictures(views[:2], size=(160, 120), periods=3))
    paths = {stem: F.save_figure(fig, fig_dir / f"{stem}.png") for stem, fig in figs.items()}
    summary = study_summary(study)
    html = R.build_report(
        {"study_summary": {"study": summary, "timings": timing_summary, "messages": messages}, "lobes_arc": lobes,
         "lobes_hemisphere": hemisphere_lobes(study), "diffuse_three_part": parts, "exact_peaks": exact,
         "thesis_tables": tables, "sine_refits": sine, "render_timings": per_sweep, "glm_summary": glm_summary,
         "glm_coefficients": glm_coefs, "glm_messages": glm_messages, "share_laws": laws, "model_fits": fits,
         "implied_scales": implied_scales(), "tables_at_implied_scale": tables_at_implied_scale(lobes),
         "model_fits_summary": model_fit_summary(fits),
         "explorer_data": explorer_data(study_columns(study), budget=DEFAULT_BUDGET)},
        paths, config={"grid": {"aspect": summary["aspects"]}},
        provenance={"settings": SETTINGS, "renderers": [gl_context.renderer()]},  # what make_study rendered on
    )
    out = workdir / "roughlight_report.html"
    R.write_report(out, html)
    (workdir / "thesis_tables.csv").write_text(tables.to_csv(index=False))
    return out


@pytest.fixture(scope="session")
def built(tmp_path_factory, worker_id):
    """A small rendered study and its report, built once a test session: the pytest-xdist workers share it (the
    first to come builds it under a lock, the others read it), as tests/test_report_tables.py reads it too."""
    shared = tmp_path_factory.getbasetemp() if worker_id == "master" else tmp_path_factory.getbasetemp().parent
    workdir = shared / "built-report"
    with open(shared / "built-report.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (workdir / "study.parquet").exists():
            workdir.mkdir(exist_ok=True)
            study = make_study([0.0, 0.5, 1.0], [0.0, 0.5, 1.0, S32], azimuths=np.arange(0.0, 180.0, 30.0),
                               elevations=np.arange(0.0, 181.0, 2.0), method="fast")
            build_report_from_study(study, workdir)
            study.to_parquet(workdir / ".study.parquet")
            os.replace(workdir / ".study.parquet", workdir / "study.parquet")
    return pd.read_parquet(workdir / "study.parquet"), workdir / "roughlight_report.html", workdir


class _Collect(HTMLParser):
    def __init__(self):
        super().__init__()
        self.imgs, self.tables, self.rows, self.cells = [], [], [], []
        self._row = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.imgs.append(a)
        elif tag == "table":
            self.tables.append(a)
        elif tag == "tr":
            self._row = []
        elif tag == "div" and a.get("id") == "img-check":
            self.check = a

    def handle_endtag(self, tag):
        if tag == "tr" and self._row is not None:
            self.rows.append((self.tables[-1] if self.tables else {}, self._row))
            self._row = None

    def handle_data(self, data):
        if self._row is not None and data.strip():
            self._row.append(data.strip())


def _parse(text):
    p = _Collect()
    p.feed(text)
    return p


IMAGE_CHECK = """(() => {
  const imgs = [...document.images];
  const bad = imgs.filter(i => !(i.complete && i.naturalWidth > 0)).map(i => i.getAttribute('alt'));
  return {total: imgs.length, loaded: imgs.length - bad.length, bad};
})()"""


def _loaded_in_chromium(html_path: Path, workdir: Path):
    """Open the page in Chromium (over the DevTools pipe: the page's policy refuses injected scripts); return the
    parse of its DOM after ``load``, with ``check``: how many images there are and which failed to decode."""
    with Browser(1280, 900, workdir=workdir) as browser:
        browser.open(html_path)
        check = browser.evaluate(IMAGE_CHECK)
        dom = _parse(browser.evaluate("document.documentElement.outerHTML"))
        shown = browser.evaluate("(() => { const e = document.getElementById('renderers');"
                                 " return e && e.offsetHeight > 0 ? e.innerText : null; })()")
    dom.check = {"data-total": str(check["total"]), "data-loaded": str(check["loaded"]),
                 "data-bad": json.dumps(check["bad"]), "renderers": shown}
    return dom


def test_report_is_self_contained(built):
    _, html_path, _ = built
    text = html_path.read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>")
    for pattern in (r"""(src|href)\s*=\s*["']?(https?:|//|file:)""", r"<link\b", r"@import", r"url\(",
                    r"<script[^>]*\bsrc\s*="):
        assert not re.search(pattern, text, re.I), f"external resource or script: {pattern}"
    # the only script that runs is the explorer's own, inline and named by its hash in the page's policy; the
    # explorer's data sit in blocks that never run
    scripts = re.findall(r"<script([^>]*)>(.*?)</script>", text, re.S | re.I)
    running = [body for attrs, body in scripts if "type=" not in attrs]
    assert running == [explorer_script()]
    assert {re.search(r'type="([^"]+)"', a).group(1) for a, _ in scripts if "type=" in a} == {
        "application/json", "application/octet-stream"}
    digest = base64.b64encode(hashlib.sha256(running[0].encode()).digest()).decode()
    policy = re.search(r'<meta http-equiv="Content-Security-Policy" content="([^"]+)"', text).group(1)
    assert policy.replace("&#39;", "'") == ("default-src 'none'; img-src data:; style-src 'unsafe-inline'; "
                                            f"script-src 'sha256-{digest}'; base-uri 'none'; form-action 'none'")
    imgs = _parse(text).imgs
    assert len(imgs) == len(FIGURE_RULES_DRAW)  # every figure of the report, one <img> each
    assert all(i["src"].startswith("data:image/png;base64,") for i in imgs)
    assert 'id="stability-regressions"' in text and 'id="regression-status"' in text
    assert 'id="share-laws"' in text and "best held out" in text
    assert 'id="implied-scale"' in text and "is impossible: the mean error would be -4.15" in text


def test_report_in_headless_chromium(built):
    _, html_path, workdir = built
    dom = _loaded_in_chromium(html_path, workdir)
    total = int(dom.check["data-total"])
    assert total == len(FIGURE_RULES_DRAW)
    assert json.loads(dom.check["data-bad"]) == [] and int(dom.check["data-loaded"]) == total
    # the provenance shows what the sweeps ran on (each sweep's record, study.parquet's in the workflow)
    assert "llvmpipe" in dom.check["renderers"] and "osmesa" in dom.check["renderers"]
    # Tables 1 and 2, for both aspects, with the thesis's rows and columns
    printed = [t for t in dom.tables if t.get("class") == "thesis-table"]
    assert {(t["data-table"], t["data-aspect"]) for t in printed} == {("1", "1"), ("2", "1"), ("1", "√3/2"),
                                                                           ("2", "√3/2")}
    for t in printed:
        rows = [cells for table, cells in dom.rows if table.get("id") == t["id"]]
        assert rows[0][:8] == ["Model", "Source", "Mean Abs Error", "Standard Deviation", "SD of |error|", "b0", "b1",
                               "RSS"]
        models = {r[0] for r in rows[1:] if r[0] not in ("ours", "exact geometry", "thesis 2001")}
        expected = {"Square Area Function", "Regressed Model"} if t["data-table"] == "1" else \
            {"Triangle Area Function", "Regressed Model"}
        assert models == expected
        thesis_rows = [r for r in rows if "thesis 2001" in r]
        assert len(thesis_rows) == 2
    # the values shown are the computed ones
    tables = pd.read_csv(workdir / "thesis_tables.csv")
    ours = tables[(tables["source"] == "ours") & (tables["table"] == 1) & (tables["model"] == "Square Area Function")
                  & (tables["aspect"] == 1.0)].iloc[0]
    t1 = next(t for t in printed if t["data-table"] == "1" and t["data-aspect"] == "1")
    row = next(cells for table, cells in dom.rows if table.get("id") == t1["id"] and "Square Area Function" in cells)
    assert row[2] == f"{ours['Mean Abs Error']:.2f}"
    thesis_row = next(cells for table, cells in dom.rows
                      if table.get("id") == t1["id"] and cells[0] == "thesis 2001")
    assert thesis_row[1:] == ["4.10", "3.08", "–", "-4.684", "1.012", "122.407"]  # it printed no SD of |error|
    # a screenshot for a human
    shot = workdir / "report.png"
    with Browser(1280, 6000, workdir=workdir) as browser:
        browser.open(html_path)
        browser.screenshot(shot)
    assert shot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    print(f"\nreport screenshot: {shot}\nreport: {html_path}")


def test_the_explorer_reads_back_the_study_in_chromium(built):
    study, html_path, workdir = built
    measured = check_explorer(html_path, study, workdir)
    assert measured["values"] >= 400 and measured["moves"] >= 6


def test_the_image_check_catches_a_broken_image(built):
    _, html_path, workdir = built
    text = html_path.read_text(encoding="utf-8")
    broken = workdir / "broken.html"
    first = re.search(r'src="(data:image/png;base64,[^"]+)"', text).group(1)
    broken.write_text(text.replace(first, "data:image/png;base64,iVBORw0KGgoAAAAAAAAA", 1), encoding="utf-8")
    dom = _loaded_in_chromium(broken, workdir)
    assert len(json.loads(dom.check["data-bad"])) == 1


def test_report_without_sqrt3_2_says_so(built, tmp_path):
    study, _, _ = built
    study = study[np.abs(study["aspect"] - S32) > 1e-9]
    lobes = arc_lobes(study)
    tables, messages = thesis_tables(lobes, SETTINGS["table_aspects"], 30.0)
    assert any("√3/2" in m for m in messages)
    html = R.build_report({"study_summary": {"study": study_summary(study), "messages": messages},
                           "thesis_tables": tables, "lobes_arc": lobes}, {})
    dom = _parse(html)
    assert {t["data-aspect"] for t in dom.tables if t.get("class") == "thesis-table"} == {"1"}
    assert "not in this study" in html and "Figure" in html  # missing figures are noted, not fatal


def test_captions_exist_for_every_figure():
    """Each registry figure has its caption file, a drawing function, and the page shows the caption's text."""
    for figure in registry.FIGURES:  # every chart of the page, whichever rule draws it, is drawn one way
        rst = REPO / "workflow" / "report" / f"{figure.name}.rst"
        assert rst.exists(), rst
        assert callable(getattr(F, figure.draw)) and F.draw_function(figure) is getattr(F, figure.draw)
        rule_file = (REPO / "workflow" / "rules").glob("*.smk")
        rules = {m.group(1): m.group(2) for path in rule_file
                 for m in re.finditer(r"^rule (\w+):\n(.*?)(?=^rule |\Z)", path.read_text(), re.M | re.S)}
        assert figure.rule in rules, figure
        if figure.rule in ("figures", "render_figures"):  # the thesis's figures and beyond: Thesis/Ours captions
            text = rst.read_text()
            assert "*Thesis:*" in text and "*Ours:*" in text
            caption = registry.caption(figure.name)
            assert caption["title"] and caption["thesis"] and caption["ours"]
            assert caption["ours"].split()[:5] == text.split("*Ours:*")[1].split()[:5]
        else:  # a measurement's chart: its rule writes it where the registry says, with its caption
            assert f'"{figure.path}"' in rules[figure.rule] and figure.caption_file in rules[figure.rule], figure
    with pytest.raises(KeyError, match="no figure"):
        registry.caption("fig99_missing")


@pytest.mark.slow
def test_workflow_builds_the_report_and_follows_its_settings(workflow_dir, users_workflow):
    """End to end: the user-grid runs' finished workflow (tests/users_workflow.py: every section on), its page
    whole, then `snakemake --report`, and report settings that reach their consumers without rendering any sweep
    again. (`snakemake --lint` finds nothing in any rule: tests/test_workflow.py's test_lint_is_clean.)"""
    last = len(GRIDS) - 1
    copy_finished(users_workflow, workflow_dir, ("results", ".snakemake", "reports", user_file(users_workflow, last).name))
    user = str(user_file(workflow_dir, last))
    env = {**os.environ, "PYOPENGL_PLATFORM": "osmesa"}
    snakemake = [sys.executable, "-m", "snakemake", "--cores", "2", "--directory", str(workflow_dir),
                 "--configfile", user]
    html = (workflow_dir / "reports" / "roughlight_report.html").read_text(encoding="utf-8")
    table_aspects = grid_config(last)[0]["report"]["table_aspects"]  # as they followed the grid
    assert html.count('class="thesis-table"') == 2 * len(table_aspects)  # Tables 1-2 at each table aspect
    assert html.count("<img ") == len(registry.FIGURES)  # every section on: every figure of the registry
    for figure in FIGURE_RULES_DRAW:  # every caption of the thesis's figures and beyond is on the page
        assert f'id="fig-{figure.name}"' in html
    # the provenance lists what the sweeps ran on, from the study table's record
    ran_on = re.search(r'<ul id="renderers">(.*?)</ul>', html, re.S).group(1)
    assert "llvmpipe" in ran_on and "osmesa" in ran_on
    dry = subprocess.run(snakemake + ["--dry-run"], capture_output=True, text=True, env=env, timeout=300)
    assert "Nothing to be done" in dry.stdout + dry.stderr, dry.stdout[-3000:]  # the copy is finished
    archive = workflow_dir / "report.zip"
    res = subprocess.run(snakemake + ["--report", str(archive)], capture_output=True, text=True, env=env, timeout=300)
    assert res.returncode == 0 and archive.stat().st_size > 0, res.stderr[-3000:]

    # every setting reaches every consumer: another table aspect, figure incidences and lights
    sweeps = sorted((workflow_dir / "results" / "sweeps").rglob("*.parquet"))
    stamps = [p.stat().st_mtime_ns for p in sweeps]
    # and the analyses that read none of them run not again (rules analysis_models, analysis_random)
    unread = [workflow_dir / "results" / "analysis" / name for name in ("model_fits.parquet", "random_statistics.parquet")]
    unread_stamps = [p.stat().st_mtime_ns for p in unread]
    other = next(a for a in GRIDS[last]["grid"]["aspect"] if a not in table_aspects)  # a grid aspect not shown yet
    follow = {"report": {"table_aspects": [other], "figure_incidences": [30, 60], "figure_lights": [127]}}
    (workflow_dir / "follow.yaml").write_text(json.dumps(follow))
    res = subprocess.run(snakemake + [str(workflow_dir / "follow.yaml")], capture_output=True, text=True, env=env,
                         timeout=600)
    assert res.returncode == 0, res.stderr[-4000:]
    assert [p.stat().st_mtime_ns for p in sweeps] == stamps  # report settings render no sweep again
    assert [p.stat().st_mtime_ns for p in unread] == unread_stamps
    html = (workflow_dir / "reports" / "roughlight_report.html").read_text(encoding="utf-8")
    shown = {t["data-aspect"] for t in _parse(html).tables if t.get("class") == "thesis-table"}
    assert shown == {aspect_label(other)} and html.count('class="thesis-table"') == 2
    plates = pd.read_parquet(workflow_dir / "results" / "analysis" / "plate_sweeps.parquet")
    assert set(plates["incidence"]) >= {30.0, 60.0} and set(plates["light"]) == {127.0}
    tables = pd.read_csv(workflow_dir / "results" / "analysis" / "thesis_tables.csv")
    assert set(tables.loc[tables["source"] == "ours", "aspect"]) == {other}
    arcs = pd.read_parquet(workflow_dir / "results" / "benchmarks" / MEASUREMENTS["plan"] / "arc_smoothness.parquet")
    assert set(arcs["aspect"]) <= {other}  # the renderer validation's arc curves follow the table aspects
    # each setting reruns only what reads it: the figure lights the plate's figures (rule render_figures), not the
    # figures drawn from the analysis; the export's checks its export, not its share table nor the implicit
    # measurement that reads the table
    follow["report"]["figure_lights"] = [255]
    (workflow_dir / "follow.yaml").write_text(json.dumps(follow))
    (workflow_dir / "checks.yaml").write_text(json.dumps({"export": {"check": {"views": 21}}}))
    res = subprocess.run(snakemake + [str(workflow_dir / "follow.yaml"), str(workflow_dir / "checks.yaml"), "--dry-run",
                                      "--quiet", "rules"], capture_output=True, text=True, env=env, timeout=300)
    planned = dict(re.findall(r"^(\w+)\s+(\d+)$", res.stdout.split("Job stats:")[-1], re.M))
    assert set(planned) - {"total", "all"} == {"render_figures", "export", "export_summary", "report_html"}, res.stdout


def test_optional_parts_follow_the_config_not_the_files(workflow_dir):
    """report.speed_accuracy / report.stability switch the measurements in and out of the DAG; files that
    happen to exist do not (the same command always builds the same DAG)."""
    config = {"grid": {"truncation": [0.5], "aspect": [1.0], "incidence": [30]},
              "sweep": {"elevation_step": 45, "azimuth_step": 90}}
    (workflow_dir / "config" / "config.yaml").write_text(json.dumps(config))
    snakemake = [sys.executable, "-m", "snakemake", "--cores", "2", "--directory", str(workflow_dir), "--snakefile",
                 str(workflow_dir / "Snakefile"), "-n", "--quiet", "rules"]
    off_keys = {"speed_accuracy": False, "stability": False, "implicit": False, "light_transport": {"enabled": False}}
    (workflow_dir / "off.yaml").write_text(json.dumps({"report": off_keys}))

    def jobs(*extra):
        res = subprocess.run(snakemake + list(extra), capture_output=True, text=True, timeout=300)
        assert res.returncode == 0, (res.stdout + res.stderr)[-3000:]
        return res.stdout.split("Job stats:")[-1].split("Reasons:")[0]

    default = jobs()
    # on by default, quick plan
    assert "speed_accuracy" in default and "stability_measurement" in default and "implicit_surface" in default
    assert "light_transport" in default
    off = jobs("--configfile", str(workflow_dir / "config" / "config.yaml"), str(workflow_dir / "off.yaml"))
    assert "speed_accuracy" not in off and "stability" not in off and "implicit_surface" not in off
    assert "light_transport" not in off
    # a stray full-size chart changes nothing: the DAG comes from the config
    (workflow_dir / "results" / "benchmarks" / "full").mkdir(parents=True)
    (workflow_dir / "results" / "benchmarks" / "full" / "speed_accuracy.png").write_bytes(b"not a chart")
    assert jobs("--configfile", str(workflow_dir / "config" / "config.yaml"), str(workflow_dir / "off.yaml")) == off
    full = jobs("--config", "measurements={plan: full}")
    assert "speed_accuracy" in full and "stability_measurement" in full and "implicit_surface" in full
    # the export: none unless export.surfaces names a surface, then its table and its export a surface, and the summary
    assert "export" not in default
    (workflow_dir / "export.yaml").write_text(json.dumps({"export": {"surfaces": [[1.0, 1.0], [0.5, 1.0]]}}))
    exported = jobs("--configfile", str(workflow_dir / "config" / "config.yaml"), str(workflow_dir / "export.yaml"))
    counts = dict(re.findall(r"^(export\w*|share_table)\s+(\d+)$", exported, re.M))
    assert counts == {"share_table": "2", "export": "2", "export_summary": "1"}, exported


def test_regressions_on_a_plate_only_grid_are_reported_not_crashed():
    """Truncation 0 only: every surface is the plate; the GLMs and Tables 1-2 say why nothing was fitted."""
    study = make_study([0.0], [0.0, 1.0], elevations=np.arange(0.0, 181.0, 10.0))
    lobes = arc_lobes(study)
    levels = diffuse_levels(study)
    thesis, _ = thesis_tables(lobes, [1.0], 30.0, m=127.0)
    summary, _, _, messages = grid_glms(lobes, levels)
    assert set(summary["status"]) == {"not fitted"}
    html = R.render_section("regressions", glm_summary=summary, glm_messages=messages, thesis_tables=thesis)
    assert 'id="stability-regressions"' in html and 'id="regression-status"' in html
    assert "nothing to fit" in html and "zero variance" in html
    assert 'id="regression-notes"' in html and "only 1 points: no regression line" in html
    assert "No bootstrap intervals" in html
    # and the whole report builds around it
    page = R.build_report({"glm_summary": summary, "glm_messages": messages, "thesis_tables": thesis}, {})
    assert page.count('id="stability-regressions"') == 1


def _html_tables(html_path):
    sys.path.insert(0, str(REPO / "tests"))
    from compare_results import report_tables

    return report_tables(Path(html_path))


def test_every_thesis_table_shows_the_frame_it_came_from(built):
    """Each printed Tables 1-2 cell is the analysis frame's value at the printed precision."""
    _, html_path, workdir = built
    frame = pd.read_csv(workdir / "thesis_tables.csv")
    printed = [t for t in _html_tables(html_path) if t["caption"].startswith("Table ")]
    assert len(printed) == 4
    digits = {"Mean Abs Error": 2, "Standard Deviation": 2, "SD of |error|": 2, "b0": 3, "b1": 3, "RSS": 3}
    checked = 0
    for table in printed:
        number = int(table["caption"].split(":")[0].split()[1])
        label = table["caption"].split("(aspect ")[1].split(",")[0]
        header, *rows = table["rows"]
        model = None
        for row in rows:
            if len(row) == len(header):
                model, row = row[0], row[1:]
            source, values = row[0], row[1:]
            want = frame[(frame["table"] == number) & (frame["aspect_label"] == label) & (frame["model"] == model)
                         & (frame["source"] == source)]
            assert len(want) == 1, (number, label, model, source)
            for metric, text in zip(header[2:], values):
                value = want.iloc[0][metric]
                if pd.isna(value):  # the thesis printed no SD of |error|
                    assert text == "–", (number, label, model, source, metric)
                    checked += 1
                    continue
                expected = f"{value:.{digits[metric]}f}"
                expected = expected[1:] if expected.startswith("-") and float(expected) == 0 else expected  # no "-0.000"
                assert text == expected, (number, label, model, source, metric)
                checked += 1
    assert checked == len(frame[frame["aspect_label"].isin(["1", "√3/2"])]) * 6


def test_lobe_table_shows_the_lobes_frame(built):
    study, html_path, _ = built
    lobes = arc_lobes(study)
    printed = next(t for t in _html_tables(html_path) if t["caption"].startswith("Lobes on the azimuth-0 arc"))
    header, *rows = printed["rows"]
    want = lobes[lobes["aspect"].isin([find_aspect(lobes["aspect"], a) for a in SETTINGS["table_aspects"]])
                 & lobes["lobe"].isin(["forward", "back"])]
    assert len(rows) == len(want)
    printed_peaks = sorted(r[header.index("peak")] for r in rows)
    assert printed_peaks == sorted("–" if np.isnan(p) else f"{p:.3f}" for p in want["peak"])


def test_fig21_plots_the_studys_arc(built):
    """Fig. 21's curves are the study's specular values on the light's arc, per truncation."""
    study, _, _ = built
    fig = F.fig21_specular_truncation(study, aspects=[1.0], incidence=30.0)
    ax = fig.axes[0]
    arc_views = study[(study["component"] == "specular") & (study["azimuth"] == 0.0) & (study["aspect"] == 1.0)]
    lines = [line for line in ax.get_lines() if len(line.get_xdata()) > 10]
    assert len(lines) == arc_views["truncation"].nunique()
    for line in lines:
        x, y = np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)
        matches = [t for t, g in arc_views.groupby("truncation")
                   if np.allclose(g.sort_values("elevation")["rough"].to_numpy(), y)
                   and np.allclose(g.sort_values("elevation")["elevation"].to_numpy(), x)]
        assert len(matches) == 1
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_pictures_are_rendered_from_the_view_they_name():
    """surface_pictures renders each (elevation, azimuth) as named: a swap would show another view."""
    from roughlight.render.naive.procedure import render_picture
    from roughlight.surfaces.surface import Surface

    views = [(1.0, 1.0, 30.0, 20.0, 60.0, "e20 phi60")]
    (_, picture), = pictures.surface_pictures(views, size=(80, 60), periods=2)
    direct = render_picture(Surface(1.0, 1.0), 30.0, elevation=20.0, azimuth=60.0, size=(80, 60), periods=2)
    swapped = render_picture(Surface(1.0, 1.0), 30.0, elevation=60.0, azimuth=20.0, size=(80, 60), periods=2)
    assert np.array_equal(picture, direct)
    assert not np.array_equal(direct, swapped)


def test_figures_say_what_their_lines_are(built):
    """Fig. 25 marks a sine refit whose omega exceeds pi/2 as outside the physical range; the Hapke panels
    call the dashed line the background term of the Hapke fit (the title quotes a background-only fit)."""
    import matplotlib.pyplot as plt

    study, _, _ = built
    lobes = arc_lobes(study)
    sine = sine_refits(lobes, [1.0], 30.0)
    sine.loc[(sine["lobe"] == "back") & (sine["parameter"] == "omega"), "estimate"] = 2.0
    fig = F.fig25_back_models(lobes, sine, aspects=[1.0])
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any("outside the physical range" in label for label in labels), labels
    plt.close(fig)
    fits = analytic_model_fits(study)
    fig = F.fig_hapke(study, fits)
    labels = [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]
    assert "background term of the Hapke fit" in labels and "linear phase background" not in labels
    plt.close(fig)


def test_intervals_are_labelled_as_sensitivity_not_sampling_uncertainty():
    """The study's data are deterministic: no table may call its intervals confidence intervals of draws."""
    captions = T.table_captions()
    for key in ("thesis_tables_bootstrap", "sine_refits", "glm_coefficients"):
        caption = captions[key]
        assert "confidence" not in caption and "other draws" not in caption, key
        assert "sensitiv" in caption.lower() and "sampling uncertainty" in caption, key  # what they are not
    for name in ("glm_coefficients", "sine_refits", "thesis_tables_bootstrap"):
        text = (REPO / "workflow" / "report" / f"{name}.rst").read_text()
        assert "confidence" not in text and "sensitiv" in text.lower(), name
