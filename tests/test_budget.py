"""tests/budget.py reads a run's benchmark files into the budget table, and says OVER where a budget is exceeded."""
import os
import sys
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

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


def test_a_peak_the_benchmark_file_missed_is_read_from_the_jobs_log(tmp_path):
    """Snakemake's benchmark file samples a job's memory and can miss its peak; the job logs its own as it ends
    (workflow/scripts/_log.py), and the budget table takes the larger: here the implicit job's 873 MB over the
    400 its benchmark file sampled, and a job whose log has no peak keeps its benchmark file's."""
    logs = tmp_path / "results" / "logs"
    _bench(logs / "benchmarks/quick/implicit.benchmark.tsv", 30.0, 400)
    (logs / "benchmarks/quick/implicit.log").write_text("2026-11-30 00:41:27,061 N=512: explicit 707 ms\n"
                                                        "2026-11-30 00:41:28,000 peak memory 873 MB\n")
    _bench(logs / "study.benchmark.tsv", 8.0, 723)
    (logs / "study.log").write_text("2026-11-30 00:41:00,000 wrote the study table\n")
    table = budget.jobs(tmp_path).set_index("job")["max_rss_mb"]
    assert table["benchmarks/quick/implicit"] == 873.0 and table["study"] == 723.0
    assert "873 MB" in budget.summary(budget.jobs(tmp_path), wall=100.0).splitlines()[1]


def _sweep(path: Path, render_seconds: float) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    pq.write_table(pa.table({"render_seconds": [render_seconds] * 3}), path)


def test_a_regular_sweeps_start_up_is_its_jobs_time_beyond_rendering_shared_by_its_sweeps(tmp_path):
    logs, sweeps = tmp_path / "results" / "logs", tmp_path / "results" / "sweeps"
    _bench(logs / "sweeps/i30/t0.5.benchmark.tsv", 3.0, 300)  # a truncation's row of two sweeps
    _sweep(sweeps / "i30/t0.5_a0.5.parquet", 1.0)
    _sweep(sweeps / "i30/t0.5_a1.parquet", 1.2)
    _bench(logs / "sweeps/i30/t1.benchmark.tsv", 5.0, 300)
    _sweep(sweeps / "i30/t1_a1.parquet", 4.0)
    _bench(logs / "sweeps/i30/control.benchmark.tsv", 9.0, 300)  # not a regular sweep
    _sweep(sweeps / "i30/control.parquet", 0.1)
    _bench(logs / "sweeps/i30/random_pyramids/t1_a1.benchmark.tsv", 9.0, 300)  # an ensemble: not regular
    _sweep(sweeps / "i30/random_pyramids/t1_a1/s1.parquet", 1.0)
    table = budget.jobs(tmp_path)
    assert [len(budget.sweep_files(tmp_path, job)) for job in table["job"]] == [1, 1, 2, 1]
    shares = budget.startup(tmp_path, table)
    assert shares.to_dict() == pytest.approx({"sweeps/i30/t0.5": 0.4, "sweeps/i30/t1": 1.0})
    line = budget.summary(table, 100.0, shares).splitlines()[3]
    assert line.startswith("sweep start-up     0.70 s") and "OVER" in line


def test_a_baseline_runs_first_from_its_own_commit_and_the_ratio_is_against_its_budget(tmp_path, monkeypatch):
    """``--baseline REV``: the commit's tracked files in a directory of their own, run first; the tree's run next;
    the ratio of their wall times printed beside its budget, OVER past it."""
    runs = []

    def fake(cores, revision=None):
        where = tmp_path / (revision or "tree")
        _bench(where / "results" / "logs" / "study.benchmark.tsv", 5.0, 300)
        runs.append(revision)
        return where, {"ea48dc6": 300.0, None: 200.0}[revision]

    monkeypatch.setattr(budget, "fresh_run", fake)
    assert budget.main(["--baseline", "ea48dc6", "--keep", "--strict"]) == 1  # 0.67 > 0.5
    assert runs == ["ea48dc6", None]
    line = budget.ratio_line(200.0, "ea48dc6", 300.0)
    assert "0.67" in line and "OVER" in line and "200.0 s against 300.0 s" in line
    assert "ok" in budget.ratio_line(140.0, "ea48dc6", 300.0)


def test_a_baseline_is_the_commits_tracked_files(tmp_path, monkeypatch):
    """The baseline's directory holds the commit's tracked files, not the working tree's: a repository made here
    (the tests run from a release tarball too, which is no repository), whose README changed after the commit and
    whose tree holds untracked files and a results/ folder."""
    import subprocess

    repo = _repository(tmp_path / "repo", {"README.md": "as committed\n", "Snakefile": "rule all:\n"})
    (repo / "README.md").write_text("changed since\n")
    (repo / "untracked.txt").write_text("never committed\n")
    (repo / "results").mkdir()
    (repo / "results" / "study.parquet").write_text("a result\n")
    monkeypatch.setattr(budget, "ROOT", repo)
    monkeypatch.setattr(budget.subprocess, "run", _no_snakemake(subprocess.run))
    copies = tmp_path / "copies"
    copies.mkdir()
    monkeypatch.setattr(budget.tempfile, "tempdir", str(copies))  # its copy under pytest's, not left in /tmp
    where, _ = budget.fresh_run(1, "HEAD")
    assert where.parent == copies
    assert (where / "README.md").read_text() == "as committed\n" and (where / "Snakefile").is_file()
    assert not (where / "untracked.txt").exists() and not (where / "results").exists()
    assert not (where / ".git").exists()
    with pytest.raises(SystemExit, match="no commit 'no-such-commit'"):
        budget.fresh_run(1, "no-such-commit")


def _repository(where: Path, files: dict) -> Path:
    """A git repository at ``where`` with ``files`` (name -> text) committed, its own identity and settings (none
    of the user's configuration: no signing, no hooks)."""
    import subprocess

    where.mkdir(parents=True)
    for name, text in files.items():
        (where / name).write_text(text)
    env = {"GIT_CONFIG_GLOBAL": "/dev/null", "GIT_CONFIG_SYSTEM": "/dev/null", "GIT_AUTHOR_NAME": "test",
           "GIT_AUTHOR_EMAIL": "test@example.org", "GIT_COMMITTER_NAME": "test", "GIT_COMMITTER_EMAIL": "test@example.org"}
    for args in (["init", "-q"], ["add", "--", *files], ["commit", "-q", "-m", "the files"]):
        subprocess.run(["git", "-C", str(where), *args], check=True, capture_output=True,
                       env={**{k: v for k, v in os.environ.items() if not k.startswith("GIT_")}, **env})
    return where


def _no_snakemake(run):
    """subprocess.run, but a snakemake call returns at once with success."""
    import subprocess

    def fake(cmd, *args, **kwargs):
        if str(cmd[0]).endswith("snakemake"):
            return subprocess.CompletedProcess(cmd, 0, "", "")
        return run(cmd, *args, **kwargs)

    return fake
