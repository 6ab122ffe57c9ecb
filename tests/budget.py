"""The default workflow against its budgets: wall time, the largest job, and the time by part.

    python tests/budget.py            # (or `make budget`) a fresh copy of this tree, `snakemake --cores 2`
    python tests/budget.py --baseline ea48dc6   # (`make budget BASE=ea48dc6`) that commit first, then this
                                                # tree, back to back: the wall time as a ratio of the baseline's
    python tests/budget.py --run DIR  # an existing finished run's results/ (its wall time as --wall S)

The run happens in a temporary copy of the working tree (tracked and untracked files, without results/, reports/,
.snakemake/ and .venv/), so the user's own results stay as they are. The jobs' times and memory come from their
Snakemake benchmark files (``s`` and ``max_rss``). Prints a table; exits 0 either way (``--strict``: 1 when a budget
is exceeded), since the point is that the next change that adds work sees what it costs (docs/budgets.md).
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
#: The budgets (docs/budgets.md): the default workflow's wall seconds on 2 cores (and, measured back to back with
#: the baseline commit ea48dc6, the share of its wall time), one job's peak memory, MB, and a regular sweep's
#: start-up beyond rendering, seconds (issue 35).
WALL_BUDGET_S = 180.0
BASELINE = "ea48dc6"
RATIO_BUDGET = 0.5
JOB_BUDGET_MB = 1024.0
STARTUP_BUDGET_S = 0.3
SKIP = {"results", "reports", ".snakemake", ".venv", ".git", "__pycache__", ".pytest_cache", ".ruff_cache"}


def part(path: str) -> str:
    """The part of the workflow a benchmark file belongs to (relative to results/logs/)."""
    parts = Path(path).parts
    if parts[0] == "sweeps":
        return "random tile sweeps" if len(parts) > 3 else "regular and control sweeps"
    names = {"report": "report", "stability": "stability scans", "benchmarks": "benchmarks", "study": "study table",
             "claims": "claim sweeps"}
    return names.get(parts[0], parts[0])


def jobs(run: Path) -> pd.DataFrame:
    """One row a job: ``part``, ``job`` (its benchmark file under results/logs/), ``seconds``, ``max_rss_mb``."""
    rows = []
    logs = run / "results" / "logs"
    for f in sorted(logs.rglob("*.benchmark.tsv")):
        bench = pd.read_csv(f, sep="\t").iloc[0]
        rel = str(f.relative_to(logs)).removesuffix(".benchmark.tsv")
        rss = pd.to_numeric(bench.get("max_rss"), errors="coerce")
        peaks = [v for v in (float(rss), logged_peak(logs / f"{rel}.log")) if v == v]  # the sampled one can miss it
        rss = max(peaks) if peaks else float("nan")
        rows.append({"part": part(rel), "job": rel, "seconds": float(bench["s"]), "max_rss_mb": float(rss)})
    if not rows:
        raise SystemExit(f"{logs}: no benchmark files (is it a finished run?)")
    return pd.DataFrame(rows)


def logged_peak(log: Path) -> float:
    """The peak memory (MB) a job logged as it ended (``peak memory N MB``, workflow/scripts/_log.py's
    ``end_job``: its process's largest resident set, by getrusage); NaN where its log has none."""
    if not log.is_file():
        return float("nan")
    found = re.findall(r"peak memory (\d+) MB", log.read_text(errors="replace"))
    return max(map(float, found)) if found else float("nan")


def sweep_files(run: Path, job: str) -> list[Path]:
    """The sweep files a sweep job wrote (``job``: its benchmark file under results/logs/, without the suffix): a
    truncation's row (``sweeps/i30/t0.5``), an ensemble's folder (``sweeps/i30/random_pyramids/t1_a1``) or a
    control (``sweeps/i30/control``); a run from before sweeps were batched, one job a sweep, its one file."""
    where = run / "results" / Path(job).parent
    name = Path(job).name
    if (where / f"{name}.parquet").is_file():
        return [where / f"{name}.parquet"]
    if (where / name).is_dir():
        return sorted((where / name).glob("s*.parquet"))
    return sorted(where.glob(f"{name}_a*.parquet"))


def startup(run: Path, table: pd.DataFrame) -> pd.Series:
    """A regular sweep's start-up beyond rendering, seconds, a regular sweep job each (its rows): the job's wall
    time less its sweeps' ``render_seconds``, shared by its sweeps."""
    import pyarrow.parquet as pq

    out = {}
    for job in table.loc[table["part"] == "regular and control sweeps", "job"]:
        files = sweep_files(run, job)
        if Path(job).name == "control" or not files:
            continue
        rendered = sum(pq.read_table(f, columns=["render_seconds"]).column(0)[0].as_py() for f in files)
        seconds = float(table.loc[table["job"] == job, "seconds"].iloc[0])
        out[job] = (seconds - rendered) / len(files)
    return pd.Series(out, dtype=float)


def summary(table: pd.DataFrame, wall: float, startup: pd.Series | None = None) -> str:
    """The budget table: wall time, the largest job and (given) a regular sweep's start-up beyond rendering beside
    their budgets, then the time by part."""
    largest = table.loc[table["max_rss_mb"].idxmax()]
    by_part = (table.groupby("part")["seconds"].agg(jobs="count", job_seconds="sum", median="median", longest="max")
               .sort_values("job_seconds", ascending=False).round(2))
    lines = [
        f"wall time      {wall:8.1f} s    budget {WALL_BUDGET_S:.0f} s    {'OVER' if wall > WALL_BUDGET_S else 'ok'}",
        f"largest job    {largest['max_rss_mb']:8.0f} MB   budget {JOB_BUDGET_MB:.0f} MB   "
        f"{'OVER' if largest['max_rss_mb'] > JOB_BUDGET_MB else 'ok'}  ({largest['job']})",
        f"all jobs       {table['seconds'].sum():8.1f} s    = {table['seconds'].sum() / (2 * wall):.0%} of 2 cores",
    ]
    if startup is not None and len(startup):
        median = float(startup.median())
        lines.append(f"sweep start-up {median:8.2f} s    budget {STARTUP_BUDGET_S:.1f} s    "
                     f"{'OVER' if median > STARTUP_BUDGET_S else 'ok'}  (a regular sweep, beyond rendering: median "
                     f"of {len(startup)} jobs' wall less their sweeps' render_seconds, a sweep's share)")
    lines += [
        "",
        by_part.to_string(),
    ]
    return "\n".join(lines)


def fresh_run(cores: int, revision: str | None = None) -> tuple[Path, float]:
    """Copy the working tree (or the tracked files of the commit ``revision``) to a temporary directory and run the
    default workflow there, its own ``src/`` first on ``PYTHONPATH`` and its bytecode compiled first, as `make
    setup` compiles it; (its dir, wall s)."""
    where = Path(tempfile.mkdtemp(prefix="roughlight-budget-"))
    if revision is None:
        shutil.copytree(ROOT, where, ignore=lambda d, names: [n for n in names if n in SKIP], symlinks=True,
                        dirs_exist_ok=True)
    else:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", "--format=tar", revision], capture_output=True)
        if archive.returncode != 0:
            raise SystemExit(f"no commit {revision!r} here: {archive.stderr.decode()[-300:]}")
        subprocess.run(["tar", "-x", "-C", str(where)], input=archive.stdout, check=True)
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(where / "src")], capture_output=True)
    snakemake = str(Path(sys.executable).with_name("snakemake"))
    env = {**os.environ, "PYOPENGL_PLATFORM": os.environ.get("PYOPENGL_PLATFORM", "osmesa"),
           "PYTHONPATH": os.pathsep.join([str(where / "src"), *filter(None, [os.environ.get("PYTHONPATH")])])}
    start = time.perf_counter()
    done = subprocess.run([snakemake, "--cores", str(cores)], cwd=where, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"the workflow failed in {where}:\n{done.stderr[-3000:]}")
    return where, wall


def ratio_line(wall: float, baseline: str, baseline_wall: float) -> str:
    """The wall time against the baseline's, measured back to back, beside the budget (:data:`RATIO_BUDGET`)."""
    ratio = wall / baseline_wall
    return (f"against {baseline:<8} {ratio:6.2f}       budget {RATIO_BUDGET:.2f}    "
            f"{'OVER' if ratio > RATIO_BUDGET else 'ok'}  ({wall:.1f} s against {baseline_wall:.1f} s, back to back)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--run", type=Path, help="a finished run's directory instead of a fresh run")
    parser.add_argument("--wall", type=float, help="with --run: its wall time, seconds")
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--strict", action="store_true", help="exit 1 when a budget is exceeded")
    parser.add_argument("--keep", action="store_true", help="keep the fresh run's directory")
    parser.add_argument("--baseline", metavar="REV", help=f"run this commit first (the budget's: {BASELINE}) and "
                        "give the wall time as a ratio of its, back to back")
    args = parser.parse_args(argv)
    if args.run and args.baseline:
        parser.error("--baseline runs both workflows itself: it takes no --run")
    baseline_wall = None
    if args.baseline:
        base, baseline_wall = fresh_run(args.cores, args.baseline)
        shutil.rmtree(base, ignore_errors=True)
    if args.run:
        if args.wall is None:
            parser.error("--run needs --wall (the run's wall time, seconds)")
        run, wall = args.run, args.wall
    else:
        run, wall = fresh_run(args.cores)
    table = jobs(run)
    print(summary(table, wall, startup(run, table)))
    if baseline_wall is not None:
        print(ratio_line(wall, args.baseline, baseline_wall))
    if not args.run:
        print(f"\n(the run: {run})" if args.keep else "")
        if not args.keep:
            shutil.rmtree(run, ignore_errors=True)
    over = wall > WALL_BUDGET_S or table["max_rss_mb"].max() > JOB_BUDGET_MB or (
        baseline_wall is not None and wall / baseline_wall > RATIO_BUDGET)
    return 1 if (args.strict and over) else 0


if __name__ == "__main__":
    sys.exit(main())
