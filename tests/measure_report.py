"""Measure a report as a reviewer meets it, in headless Chromium at 1280 px: its size, its height with every fold
closed (and each section's share of it: from its heading to the next section's), the widest thing on it, the tables
of more than 20 rows left open, and when the hemisphere explorer is ready.

    python tests/measure_report.py reports/roughlight_report.html [--loads 3]

Prints one JSON object. Not collected by pytest (its name does not start with ``test_``); docs/report.md quotes it.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tests.browser import Browser  # noqa: E402

LAYOUT = """(() => {
  const tables = [...document.querySelectorAll('table')];
  const caption = t => (t.caption ? t.caption.textContent : t.id).slice(0, 60);
  return {height: document.documentElement.scrollHeight, width: document.documentElement.scrollWidth,
          widest_table: Math.round(Math.max(0, ...tables.map(t => t.getBoundingClientRect().width))),
          tables: tables.length, folds: document.querySelectorAll('details').length,
          open_over_20_rows: tables.filter(t => t.tBodies[0] && t.tBodies[0].rows.length > 20 && !t.closest('details'))
                                   .map(caption),
          figures: document.querySelectorAll('figure img').length, sections: sections()};
  function sections() {  // the title and its line, then each <h2> to the next (the contents in the findings')
    const heads = [...document.querySelectorAll('main h2')], top = e => e.getBoundingClientRect().top + scrollY;
    const out = {}, ends = [...heads.map(top), document.documentElement.scrollHeight];
    out.top = Math.round(ends[0]);
    heads.forEach((h, i) => { out[h.id || h.closest('[id]')?.id || h.textContent] = Math.round(ends[i + 1] - ends[i]); });
    return out;
  }
})()"""

READY = """window.roughlight && window.roughlight.explorer ? window.roughlight.explorer.ready.then(() => {
  const e = window.roughlight.explorer, n = performance.getEntriesByType('navigation')[0];
  return {ready_ms: Math.round(e.readyAt), decode_and_draw_ms: Math.round(e.readyAt - e.startedAt),
          load_event_ms: Math.round(n.loadEventEnd)};
}) : null"""


def measure(path, loads: int = 3) -> dict:
    """The measures of the page at ``path`` (the explorer's timings from each of ``loads`` fresh browsers)."""
    out = {"bytes": os.path.getsize(path)}
    with Browser(1280, 900) as browser:
        browser.open(path)
        out.update(browser.evaluate(LAYOUT))
        out["errors"] = browser.errors()
    out["explorer"] = []
    for _ in range(loads):
        with Browser(1280, 900) as browser:
            browser.open(path)
            out["explorer"].append(browser.evaluate(READY))
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("report")
    parser.add_argument("--loads", type=int, default=3, help="fresh page loads to time the explorer over")
    args = parser.parse_args(argv)
    print(json.dumps(measure(args.report, args.loads), indent=1, ensure_ascii=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
