"""Compare two runs of the workflow: the study table, the analysis tables and the report's tables.

Used to show that a change of code that should not change any number (a restructure)
did not: run the default workflow before and after, then

    python tests/compare_results.py BEFORE/results AFTER/results \
        [--report BEFORE/reports/roughlight_report.html AFTER/reports/roughlight_report.html]

The study table must be equal bit for bit (every column but ``render_seconds``, the wall
time of the sweep, which no two runs share); every analysis table equal to 1e-12
(``render_timings.csv``, ``seconds`` columns and the timing fields of ``study_summary.json``
are wall times and are left out). Exits 1 and names every difference otherwise. Not collected by pytest
(its name does not start with ``test_``).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from html.parser import HTMLParser
from pathlib import Path

import pandas as pd

TOLERANCE = 1e-12
# wall-clock measurements: they differ between any two runs
TIMED_FILES = {"render_timings.csv"}
TIMED_COLUMNS = {"render_seconds", "seconds"}


def compare_study(before: Path, after: Path) -> list[str]:
    """Bit-for-bit equality of two study tables, every column but the wall times."""
    a = pd.read_parquet(before).drop(columns=list(TIMED_COLUMNS), errors="ignore")
    b = pd.read_parquet(after).drop(columns=list(TIMED_COLUMNS), errors="ignore")
    try:
        pd.testing.assert_frame_equal(a, b, check_exact=True)
    except AssertionError as exc:
        return [f"study table differs: {exc}"]
    return []


def _frame(path: Path) -> pd.DataFrame:
    if path.suffix == ".parquet":
        return pd.read_parquet(path)
    return pd.read_csv(path)


def _close(x, y) -> bool:
    if isinstance(x, dict) and isinstance(y, dict):
        return x.keys() == y.keys() and all(_close(x[k], y[k]) for k in x)
    if isinstance(x, list) and isinstance(y, list):
        return len(x) == len(y) and all(_close(p, q) for p, q in zip(x, y))
    if isinstance(x, float) and isinstance(y, float):
        return (math.isnan(x) and math.isnan(y)) or math.isclose(x, y, rel_tol=TOLERANCE, abs_tol=TOLERANCE)
    return x == y


def _untimed(obj):
    """A JSON document without its wall-time fields (keys naming seconds or time, and the slowest sweep)."""
    if isinstance(obj, dict):
        return {k: _untimed(v) for k, v in obj.items() if "second" not in k and "time" not in k and k != "slowest"}
    if isinstance(obj, list):
        return [_untimed(v) for v in obj]
    return obj


def compare_analysis(before: Path, after: Path) -> list[str]:
    """Every analysis table of ``before`` present in ``after`` and equal to 1e-12."""
    problems = []
    for old in sorted(before.iterdir()):
        if old.name in TIMED_FILES:
            continue
        new = after / old.name
        if not new.exists():
            problems.append(f"analysis/{old.name} is missing")
            continue
        if old.suffix == ".json":
            if not _close(_untimed(json.loads(old.read_text())), _untimed(json.loads(new.read_text()))):
                problems.append(f"analysis/{old.name} differs")
            continue
        untimed = [_frame(p).drop(columns=list(TIMED_COLUMNS), errors="ignore") for p in (old, new)]
        try:
            pd.testing.assert_frame_equal(*untimed, rtol=TOLERANCE, atol=TOLERANCE)
        except AssertionError as exc:
            problems.append(f"analysis/{old.name} differs: {exc}")
    return problems


class _Tables(HTMLParser):
    """The text of every cell of every <table>, as lists of rows, with the table's caption."""

    def __init__(self):
        super().__init__()
        self.tables: list[dict] = []
        self._cell: list[str] | None = None
        self._caption: list[str] | None = None

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self.tables.append({"caption": "", "rows": []})
        elif tag == "tr" and self.tables:
            self.tables[-1]["rows"].append([])
        elif tag in ("td", "th") and self.tables:
            self._cell = []
        elif tag == "caption" and self.tables:
            self._caption = []

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self.tables[-1]["rows"][-1].append(" ".join("".join(self._cell).split()))
            self._cell = None
        elif tag == "caption" and self._caption is not None:
            self.tables[-1]["caption"] = " ".join("".join(self._caption).split())
            self._caption = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)
        elif self._caption is not None:
            self._caption.append(data)


def report_tables(html_path: Path) -> list[dict]:
    """Every table of an HTML report: ``{"caption": str, "rows": [[cell text, ...], ...]}``."""
    parser = _Tables()
    parser.feed(html_path.read_text())
    return parser.tables


# tables of wall times, input hashes and package versions differ between any two runs
UNCOMPARED_TABLE_WORDS = ("second", "time", "views/s", "sha256", "package")


def compare_reports(before: Path, after: Path, skip_words=UNCOMPARED_TABLE_WORDS) -> list[str]:
    """Each table of the old report found, cell for cell, in the new one (but timing, hash, version tables)."""
    new_tables = [t["rows"] for t in report_tables(after)]
    problems = []
    for table in report_tables(before):
        text = (table["caption"] + " " + " ".join(" ".join(r) for r in table["rows"][:1])).lower()
        if any(word in text for word in skip_words):
            continue
        if table["rows"] not in new_tables:
            problems.append(f"report table not found unchanged in the new report: {table['caption'][:80]!r}")
    return problems


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path, help="results/ of the first run")
    parser.add_argument("after", type=Path, help="results/ of the second run")
    parser.add_argument("--report", nargs=2, type=Path, metavar=("BEFORE_HTML", "AFTER_HTML"))
    args = parser.parse_args(argv)
    problems = compare_study(args.before / "study.parquet", args.after / "study.parquet")
    problems += compare_analysis(args.before / "analysis", args.after / "analysis")
    n_tables = 0
    if args.report:
        n_tables = len(report_tables(args.report[0]))
        problems += compare_reports(*args.report)
    for problem in problems:
        print(problem)
    if problems:
        return 1
    n_analysis = sum(1 for p in (args.before / "analysis").iterdir() if p.name not in TIMED_FILES)
    tables = f", {n_tables} report tables (but timing, hash and version tables)" if args.report else ""
    print(f"equal: the study table bit for bit, {n_analysis} analysis tables to {TOLERANCE:g}{tables}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
