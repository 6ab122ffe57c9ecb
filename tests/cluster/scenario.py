"""The cluster test's scenario, run in the background of the test session.

The scenario is about a minute of waiting (SLURM's start, the executor plugin's status checks, 10 s apart and
more after each check that finds no job done) around some 10 s of work. Run inside the test it held one of
``make test``'s two workers for all of that minute. ``tests/conftest.py`` starts it instead as a process of its
own as soon as the session has collected the cluster test (one worker starts it, :func:`launch`); the test, when
its turn comes, reads what it recorded (:func:`result`) and asserts everything the scenario saw.

What it runs, in a directory of its own (``python tests/cluster/scenario.py DIRECTORY``):

1. a copy of the workflow with :data:`SMALL` as its config, run locally (``local/``);
2. the same copy on a single-node SLURM through ``profiles/slurm`` (``cluster/``), and, while that driver holds
   the run lock, a second driver in the same directory, which must stop at once;
3. the cluster torn down, ``/etc/slurm/slurm.conf`` put back.

It writes ``result.json`` (atomically) with the drivers' return codes and logs, or the error that stopped it.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import traceback
from pathlib import Path

import yaml

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parents[1]))
import single_node  # noqa: E402

from tests.workflow_copy import SNAKEMAKE, copy_workflow  # noqa: E402

STUDY = "results/study.parquet"
#: Three surfaces and the control at a coarse sweep: two group jobs of sweeps, then the study table.
SMALL = {
    "grid": {"truncation": [0.0, 0.5, 1.0], "aspect": [1.0], "incidence": [30]},
    "sweep": {"elevation_step": 30, "azimuth_step": 60},
}
#: Seconds the whole scenario may take before the session's end stops it (the test waits as long).
TIMEOUT = 900


def available() -> bool:
    """Whether the scenario can run here: SLURM installed (``make slurm``) and root (it writes slurm.conf)."""
    return single_node.installed() and os.geteuid() == 0


def _workflow(directory: Path) -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    copy_workflow(directory)
    (directory / "config" / "config.yaml").write_text(yaml.safe_dump(SMALL))
    return directory


def run(directory: Path) -> dict:
    """The scenario in ``directory``; returns what the test asserts on (see the module's docstring)."""
    env = {**os.environ, "PYOPENGL_PLATFORM": "osmesa"}
    local, on_cluster = _workflow(directory / "local"), _workflow(directory / "cluster")
    proc = subprocess.run([SNAKEMAKE, STUDY, "--cores", "2"], cwd=local, capture_output=True, text=True,
                          timeout=600, env=env)
    out = {"local": {"returncode": proc.returncode, "log": (proc.stdout + proc.stderr)[-6000:]}}
    if proc.returncode != 0:
        return out
    cluster = single_node.start(state=directory / "slurm")
    command = [SNAKEMAKE, STUDY, "--profile", "profiles/slurm", "--slurm-no-account"]
    first = None
    try:
        # the profile as a user has it, less the account (this cluster keeps none); a hard timeout, so that a
        # status query that never sees the jobs finish fails the test instead of hanging it
        first = subprocess.Popen(command, cwd=on_cluster, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                 text=True, env=env)
        lock = on_cluster / ".snakemake" / "roughlight.lock"
        deadline = time.monotonic() + 120
        while not (lock.exists() and lock.read_text().strip()) and first.poll() is None and time.monotonic() < deadline:
            time.sleep(0.2)
        out["lock_taken"] = lock.exists() and bool(lock.read_text().strip()) and first.poll() is None
        if out["lock_taken"]:  # a second driver in the same directory stops at once, while the first goes on
            second = subprocess.run(command, cwd=on_cluster, capture_output=True, text=True, timeout=120, env=env)
            out["second"] = {"returncode": second.returncode, "log": (second.stdout + second.stderr)[-6000:]}
        log, _ = first.communicate(timeout=420)
        out["first"] = {"returncode": first.returncode, "log": log}
    finally:
        if first is not None and first.poll() is None:
            first.kill()
        single_node.stop(cluster)
    out["conf_restored"] = not single_node.CONF.exists() or single_node.MARK not in single_node.CONF.read_text()
    return out


def _write(path: Path, record: dict) -> None:
    partial = path.with_name(path.name + ".partial")
    partial.write_text(json.dumps(record))
    os.replace(partial, path)


def _interrupted(signum, frame):
    raise SystemExit(128 + signum)  # so that the cluster is torn down (run's finally) on SIGTERM too


def main(directory: str) -> int:
    signal.signal(signal.SIGTERM, _interrupted)
    directory = Path(directory)
    try:
        record = run(directory)
    except BaseException:
        record = {"error": traceback.format_exc()}
    _write(directory / "result.json", record)
    return 0


# ---------------------------------------------------------------------------
# in the test session

#: The process this session started (on the one worker that starts it), for :func:`finish`.
_started: subprocess.Popen | None = None


def launch(directory: Path) -> None:
    """Start the scenario in ``directory`` in the background, once: a directory that has it started is left."""
    global _started
    directory.mkdir(parents=True, exist_ok=True)
    try:
        with open(directory / "pid", "x") as pid:  # the first to create the file starts the scenario
            log = open(directory / "scenario.log", "w")
            _started = subprocess.Popen([sys.executable, str(Path(__file__)), str(directory)], stdout=log,
                                        stderr=subprocess.STDOUT, start_new_session=True)
            pid.write(str(_started.pid))
    except FileExistsError:
        pass


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
        return not Path(f"/proc/{pid}/stat").read_text().split(") ")[-1].startswith("Z")
    except (ProcessLookupError, FileNotFoundError):  # gone, or gone between the two
        return False


def result(directory: Path, timeout: float = TIMEOUT) -> dict:
    """What the scenario in ``directory`` recorded, once it has (starting it if no one has)."""
    launch(directory)
    path, deadline = directory / "result.json", time.monotonic() + timeout
    while not path.exists():
        pid = int((directory / "pid").read_text() or 0)  # 0: its starter is writing it
        log_file = directory / "scenario.log"
        log = log_file.read_text(errors="replace")[-3000:] if log_file.exists() else ""
        if pid and not _alive(pid) and not path.exists():
            raise RuntimeError(f"the cluster scenario ended without a result:\n{log}")
        if time.monotonic() > deadline:
            raise TimeoutError(f"the cluster scenario took more than {timeout:g} s:\n{log}")
        time.sleep(0.5)
    return json.loads(path.read_text())


def finish(interrupted: bool = False) -> None:
    """At the session's end: wait for a scenario this process started (it tears its cluster down), or stop it at
    once when the session was interrupted (SIGTERM: the scenario's ``finally`` still stops its SLURM daemons)."""
    if _started is None or _started.poll() is not None:
        return
    try:
        if interrupted:
            raise subprocess.TimeoutExpired(_started.args, 0)
        _started.wait(timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        _started.terminate()
        _started.wait(timeout=60)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
