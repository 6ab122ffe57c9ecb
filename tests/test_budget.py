"""tests/budget.py reads a run's benchmark files into the budget table, and says OVER where a budget is exceeded."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import budget  # noqa: E402


def _bench(path: Path, seconds: float, rss_mb: float) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("s\th:m:s\tmax_rss\tmax_vms\n" f"{seconds}\t0:00:01\t{rss_mb}\t100\n")


def test_the_budget_table_sums_the_jobs_by_part_and_names_the_largest(tmp_path):
    logs = tmp_path / "results" / "logs"
    _bench(logs / "sweeps/i30/t0.5_a1.benchmark.tsv", 1.0, 300)
    _bench(logs / "sweeps/i30/t1_a1.benchmark.tsv", 3.0, 310)
    _bench(logs / "sweeps/i30/random_pyramids/t1_a1_s1.benchmark.tsv", 6.0, 500)
    _bench(logs / "study.benchmark.tsv", 8.0, 1100)
    _bench(logs / "report/report_html.benchmark.tsv", 4.0, 200)
    table = budget.jobs(tmp_path)
    assert dict(table.groupby("part")["seconds"].sum()) == {
        "regular and control sweeps": 4.0, "random tile sweeps": 6.0, "study table": 8.0, "report": 4.0}
    text = budget.summary(table, wall=100.0)
    assert "wall time" in text and "100.0 s" in text and "ok" in text.splitlines()[0]
    assert "OVER  (study)" in text.splitlines()[1]  # 1100 MB > 1 GB
    assert "11% of 2 cores" in text
    assert "OVER" in budget.summary(table, wall=200.0).splitlines()[0]
    assert budget.main(["--run", str(tmp_path), "--wall", "200", "--strict"]) == 1
    assert budget.main(["--run", str(tmp_path), "--wall", "200"]) == 0
