"""The report's tables fit the page and fold (issue 33), and so does its secondary material.

One rule, in ``macros.html``'s ``table``: a table of more than ``FOLD_ROWS`` rows (10; the issue asks for 20) sits in a
``<details>`` whose summary line says what it holds (its caption, shortened, and its row count) and links the whole
frame as CSV in a ``data:`` URI; a shorter table its template calls secondary (``fold=true``) folds the same way, its
``<details>`` marked ``secondary``. Secondary charts and subsections fold under ``macros.html``'s ``fold``, whose
summary says what they hold, and a link into a fold opens it. The unit tests render the macros; the browser tests
open the small report of ``test_report.py`` in Chromium at 1280 px and measure it.
"""

from __future__ import annotations

import base64
import io
import math
import re
import time

import numpy as np
import pandas as pd
import pytest

from roughlight.report import page_templates as T

from .test_report import built  # noqa: F401  (the module fixture: a small rendered study's report)

CSV_PREFIX = "data:text/csv;charset=utf-8;base64,"


def frame(n: int) -> pd.DataFrame:
    """``n`` rows of every kind of cell: floats at full precision, NaN, integers, text with markup, booleans."""
    x = np.linspace(0.0, 1.0, n) / 3.0
    return pd.DataFrame({"value_<1>": x, "n": np.arange(n), "text": [f"x < y {i}, \"q\"" for i in range(n)],
                         "ok": [i % 2 == 0 for i in range(n)], "gap": [math.nan if i % 3 else i + 0.1 for i in range(n)]})


def csv_of(href: str) -> pd.DataFrame:
    """The frame a CSV link's ``data:`` URI holds."""
    assert href.startswith(CSV_PREFIX), href[:60]
    text = base64.b64decode(href[len(CSV_PREFIX):]).decode("utf-8")
    return pd.read_csv(io.StringIO(text))  # (pandas 3 reads floats back exactly)


def link(html: str) -> re.Match:
    return re.search(r'<a class="csv" download="([^"]+)" href="([^"]+)">CSV</a>', html)


# ---------------------------------------------------------------------------
# the macro


def test_a_table_of_more_than_fold_rows_is_folded_with_its_whole_frame_as_csv():
    assert T.FOLD_ROWS <= 20  # the issue: every table of more than 20 rows folds
    df = frame(T.FOLD_ROWS + 1)
    html = T.render_macro("macros.html", "table", df, "Seeds <needed> for a test", 2, "t-id")
    assert html.startswith(f'<details class="fold"><summary>Seeds &lt;needed&gt; for a test ({T.FOLD_ROWS + 1} rows) '
                           '<a class="csv" download="t-id.csv" href="data:text/csv;charset=utf-8;base64,')
    assert html.endswith("</table></details>") and html.count("<details") == 1
    assert '<table id="t-id"><caption>Seeds &lt;needed&gt; for a test</caption>' in html
    assert html.count("<tr>") == T.FOLD_ROWS + 2  # every row is still on the page, under the fold
    # the link holds the frame itself: every row and column, full precision (the cells show 2 decimals)
    name, href = link(html).groups()
    assert name == "t-id.csv"
    pd.testing.assert_frame_equal(csv_of(href), df)
    assert f"<td>{df['value_<1>'][1]:.2f}</td>" in html and f"{df['value_<1>'][1]!r}" not in html


def test_a_table_of_fold_rows_is_not_folded():
    html = T.render_macro("macros.html", "table", frame(T.FOLD_ROWS), "caption <c>", 3, "t-id")
    assert html.startswith('<table id="t-id"><caption>caption &lt;c&gt;</caption>')
    assert "<details" not in html and "data:text/csv" not in html and html.count("<tr>") == T.FOLD_ROWS + 1


def test_a_secondary_table_folds_whatever_its_rows_with_its_csv():
    html = T.render_macro("macros.html", "table", frame(2), "Sensitivity <s>", 3, "t-id", 400, True)
    assert html.startswith('<details class="fold secondary"><summary>Sensitivity &lt;s&gt; (2 rows) '
                           '<a class="csv" download="t-id.csv" href="data:text/csv;charset=utf-8;base64,')
    assert html.endswith("</table></details>") and html.count("<tr>") == 3
    pd.testing.assert_frame_equal(csv_of(link(html).group(2)), frame(2))


def test_the_fold_macro_says_what_it_holds_and_escapes_it():
    env = T.environment()
    html = env.from_string('{% import "macros.html" as m %}{% call m.fold("Maps <m> (figure)", id="f-id") %}'
                           '<figure id="fig-x"></figure>{% endcall %}').render()
    assert html.startswith('<details class="fold secondary" id="f-id"><summary>Maps &lt;m&gt; (figure)</summary>')
    assert '<figure id="fig-x"></figure>' in html and html.endswith("</details>") and " open" not in html


def test_a_folded_table_escapes_its_caption_labels_and_cells():
    html = T.render_macro("macros.html", "table", frame(25), "a <b> & c", 3)
    assert "<summary>a &lt;b&gt; &amp; c (25 rows) " in html and "<caption>a &lt;b&gt; &amp; c</caption>" in html
    assert "<th>value_<wbr>&lt;1&gt;</th>" in html  # a label may break after its underscore; its text is unchanged
    assert "<td>x &lt; y 0, &#34;q&#34;</td>" in html and "<b>" not in html and "x < y" not in html
    assert link(html).group(1) == "a-b-c.csv"  # no id: the file is named after the caption
    assert csv_of(link(html).group(2))["text"][0] == 'x < y 0, "q"'  # the CSV has the raw text


def test_the_summary_is_one_short_line_that_says_what_the_table_holds():
    long = ("Every statistic: random ensemble mean with its 95% bootstrap interval over seeds (boot_low, boot_high), "
            "beside the regular surface (lobes from the light's plane)")
    assert T.fold_summary(long, 96) == ("Every statistic: random ensemble mean with its 95% bootstrap interval over "
                                        "seeds … (96 rows)")
    assert T.fold_summary("Lobes on the azimuth-0 arc (peak 0-255; predicted centre, peak elevation, centroid and "
                          "FWHM in degrees; exact FWHM with the study's shadows)", 44) == \
        "Lobes on the azimuth-0 arc … (44 rows)"  # never cut inside brackets
    assert T.fold_summary("Render wall time per sweep.", 1320) == "Render wall time per sweep (1,320 rows)"
    assert T.fold_summary("word " * 40, 21).endswith("word … (21 rows)")
    assert all(len(T.fold_summary(c, 10)) <= T.SUMMARY_CHARS + 12 for c in (long, "x" * 300, "a, " * 80))
    assert T.csv_name("Speed and accuracy <benchmark>") == "speed-and-accuracy-benchmark.csv"
    assert T.csv_name("<>") == "table.csv"


def test_the_csv_is_compact():
    """No index, no padding: floats as their shortest round-trip text."""
    df = pd.DataFrame({"a": [0.1, 1 / 3], "b": ["x", "y"]})
    assert T.csv_text(df) == "a,b\n0.1,x\n0.3333333333333333,y\n"


# ---------------------------------------------------------------------------
# the small report in Chromium at 1280 px

LAYOUT = """(() => {
  const main = document.querySelector('main');
  const tables = [...document.querySelectorAll('table')].map(t => {
    const r = t.getBoundingClientRect(), d = t.closest('details'), a = d && d.querySelector('summary a.csv');
    const s = d && d.querySelector('summary');
    return {id: t.id, caption: t.caption ? t.caption.textContent : '', width: r.width, right: r.right,
            container: t.parentElement.clientWidth, rows: t.tBodies[0] ? t.tBodies[0].rows.length : 0,
            folded: !!d, secondary: !!d && d.classList.contains('secondary'), open: d ? d.open : null,
            summary: s ? s.textContent : null,
            summary_height: s ? s.getBoundingClientRect().height : null,
            download: a ? a.getAttribute('download') : null, href: a ? a.href : null,
            head: [...t.tHead.rows[0].cells].map(c => c.textContent),
            body: [...(t.tBodies[0] ? t.tBodies[0].rows : [])].map(r => [...r.cells].map(c => c.textContent))};
  });
  const folds = [...document.querySelectorAll('details.secondary')].map(d => {
    const s = d.querySelector('summary');
    return {summary: s.textContent, summary_height: s.getBoundingClientRect().height, open: d.open,
            holds: d.querySelectorAll('figure img, table').length, ids: [...d.querySelectorAll('[id]')].map(e => e.id)};
  });
  return {tables, folds, scroll_width: document.documentElement.scrollWidth, main_right: main.getBoundingClientRect().right,
          font_size: parseFloat(getComputedStyle(document.querySelector('summary') || main).fontSize)};
})()"""


def _shown(value) -> str | None:
    """What a CSV value looks like in a cell, when it is not a number (numbers are compared within precision)."""
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, float) and math.isnan(value):
        return "–"  # (or "" for a None in a column of text)
    return None


def _check_cells(table: dict, data: pd.DataFrame) -> None:
    """Each cell shown is the CSV's value, rounded as printed."""
    assert table["head"] == list(data.columns), table["id"]
    assert len(table["body"]) == min(len(data), 400), table["id"]
    for shown_row, (_, row) in zip(table["body"], data.iterrows()):
        for text, value in zip(shown_row, row):
            if _shown(value) is not None:
                assert text in (_shown(value), "" if _shown(value) == "–" else None), (table["id"], text, value)
            elif isinstance(value, (int, float, np.number)):
                decimals = len(text.split(".")[1]) if "." in text else 0
                assert abs(float(text) - value) <= 0.5 * 10 ** -decimals + 1e-9, (table["id"], text, value)
            elif _number(value) is not None:  # a label such as "1" beside "√3/2": the page prints it as a number
                decimals = len(text.split(".")[1]) if "." in text else 0
                assert abs(float(text) - _number(value)) <= 0.5 * 10 ** -decimals + 1e-9, (table["id"], text, value)
            else:
                assert text == str(value), (table["id"], text, value)


def _number(value):
    """``value`` as a float when it is a string that reads as one, else None."""
    try:
        return float(value)
    except (TypeError, ValueError):
        return None


@pytest.fixture(scope="module")
def layout(built):  # noqa: F811
    from .browser import Browser

    _, html_path, workdir = built
    downloads = workdir / "downloads"
    downloads.mkdir(exist_ok=True)
    with Browser(1280, 900) as b:
        b.open(html_path)
        closed = b.evaluate(LAYOUT)
        # a click on the CSV link downloads the file (the page's CSP allows it) and leaves the fold closed
        b.command("Browser.setDownloadBehavior", behavior="allow", downloadPath=str(downloads))
        x, y, name = b.evaluate("(() => { const a = document.querySelector('summary a.csv');"
                                " if (!a) return [0, 0, null]; a.scrollIntoView({block: 'center'});"
                                " const r = a.getBoundingClientRect();"
                                " return [r.x + r.width / 2, r.y + r.height / 2, a.getAttribute('download')]; })()")
        if name:
            b.click(x, y)
            deadline = time.monotonic() + 20
            while not (downloads / name).exists() and time.monotonic() < deadline:
                time.sleep(0.1)
        still_closed = b.evaluate("[...document.querySelectorAll('details')].every(d => !d.open)")
        # a link into a secondary fold (the findings link into some) opens it: each fold's first id, in turn
        followed = b.evaluate("""(async () => {
          const out = {};
          for (const d of document.querySelectorAll('details.secondary')) {
            const target = d.querySelector('[id]');
            if (!target) continue;
            location.hash = '';
            await new Promise(r => requestAnimationFrame(() => setTimeout(r, 30)));
            location.hash = '#' + target.id;
            await new Promise(r => requestAnimationFrame(() => setTimeout(r, 30)));
            out[target.id] = d.open;
            d.open = false;
          }
          return out; })()""")
        b.evaluate("document.querySelectorAll('details').forEach(d => d.open = true); true")
        opened = b.evaluate(LAYOUT)
        errors = b.errors()
    return {"closed": closed, "opened": opened, "errors": errors, "downloads": downloads, "clicked": name,
            "still_closed": still_closed, "followed": followed}


def test_no_table_is_wider_than_the_page(layout):
    assert layout["errors"] == []
    for state in ("closed", "opened"):  # with every fold closed, and with every fold open
        page = layout[state]
        assert page["scroll_width"] <= 1280, state
        for t in page["tables"]:
            if t["folded"] and state == "closed":
                continue
            assert t["width"] <= t["container"] + 0.5 and t["right"] <= page["main_right"] + 0.5, (state, t["id"],
                                                                                                 t["width"])


def test_every_table_of_more_than_fold_rows_is_folded_with_its_data(layout, built):  # noqa: F811
    study, _, _ = built
    tables = layout["closed"]["tables"]
    folded = [t for t in tables if t["rows"] > T.FOLD_ROWS]
    assert folded, "the small report has no table of more than FOLD_ROWS rows: the fold is not exercised"
    assert all(t["folded"] for t in folded)
    # a table of FOLD_ROWS rows or fewer folds only where its template calls it secondary, and then as a long one does
    assert not any(t["folded"] and not t["secondary"] for t in tables if t["rows"] <= T.FOLD_ROWS)
    secondary = [t for t in tables if t["secondary"] and t["rows"] <= T.FOLD_ROWS]
    assert secondary, "the small report has no secondary table: that fold is not exercised"
    for t in folded + secondary:
        assert t["open"] is False, t["id"]
        assert t["summary"].startswith(t["caption"].rstrip(".")[:20]) and f"({t['rows']:,} rows)" in t["summary"]
        assert t["summary_height"] < 1.8 * layout["closed"]["font_size"], t["summary"]  # one line
        assert t["download"] == f"{t['id']}.csv"
        _check_cells(t, csv_of(t["href"]))
    # the CSV is the analysis frame itself, at full precision
    from roughlight.analysis.surface_models import analytic_model_fits, model_fit_summary

    bands = next(t for t in folded if t["id"] == "model-summary-bands")
    want = model_fit_summary(analytic_model_fits(study))
    want = want[want["band"] != "all"].reset_index(drop=True)
    pd.testing.assert_frame_equal(csv_of(bands["href"]), want, check_dtype=False)


def test_secondary_material_is_folded_under_a_line_that_says_what_it_holds(layout):
    folds = layout["closed"]["folds"]
    assert len(folds) >= 4, folds  # the small report's secondary figures (registry: folded) and tables
    for f in folds:
        assert f["open"] is False and f["holds"] >= 1, f
        assert len(f["summary"].strip()) > 15, f  # it says what it holds
        assert f["summary_height"] < 1.8 * layout["closed"]["font_size"], f["summary"]  # one line
    assert any("(figure)" in f["summary"] for f in folds)


def test_a_link_into_a_fold_opens_it(layout):
    followed = layout["followed"]
    assert len(followed) >= 4 and all(followed.values()), followed


def test_the_csv_link_downloads_the_file_and_leaves_the_fold_closed(layout):
    name = layout["clicked"]
    assert name, "no CSV link on the page"
    href = next(t["href"] for t in layout["closed"]["tables"] if t["download"] == name)
    assert (layout["downloads"] / name).read_bytes() == base64.b64decode(href[len(CSV_PREFIX):])
    assert layout["still_closed"]
