"""A single-node SLURM cluster on this machine, from Debian's packages, for the cluster test.

``start()`` writes ``/etc/slurm/slurm.conf`` (the executor plugin's job steps strip ``SLURM_*`` variables, so
the configuration must be where SLURM looks by default), starts ``munged``, ``slurmctld`` and ``slurmd`` as
background processes (no systemd) and waits until ``sinfo`` shows the node idle; ``stop()`` ends them by their
PIDs and puts back a ``slurm.conf`` that was there before. Run as a script it brings the cluster up, runs the
command given after ``--`` and tears it down whatever happens::

    python tests/cluster/single_node.py -- snakemake --profile profiles/slurm

Needs root and the packages ``slurmctld slurmd slurm-client munge`` (``make slurm`` installs them).
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CONF = Path("/etc/slurm/slurm.conf")
MARK = "# written by roughlight's tests/cluster/single_node.py"
#: Seconds a finished job stays visible to squeue; at least three times the executor's
#: init-seconds-before-status-checks (profiles/slurm sets 10), or Snakemake can miss that a job finished.
MIN_JOB_AGE = 120
PARTITION = "main"


def installed() -> bool:
    return all(shutil.which(tool) for tool in ("slurmctld", "slurmd", "munged", "sinfo", "sbatch"))


def slurm_conf(state: Path, host: str, cpus: int, memory_mb: int) -> str:
    return f"""{MARK}
ClusterName=roughlight
SlurmctldHost={host}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
MinJobAge={MIN_JOB_AGE}
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
StateSaveLocation={state}/state
SlurmdSpoolDir={state}/spool
SlurmctldPidFile={state}/slurmctld.pid
SlurmdPidFile={state}/slurmd.pid
SlurmctldLogFile={state}/slurmctld.log
SlurmdLogFile={state}/slurmd.log
NodeName={host} CPUs={cpus} RealMemory={memory_mb} State=UNKNOWN
PartitionName={PARTITION} Nodes={host} Default=YES MaxTime=INFINITE State=UP
"""


class Cluster:
    """The running daemons (``processes``: name -> Popen) and where their state and logs are (``state``)."""

    def __init__(self, state: Path, backup: Path | None):
        self.state = state
        self.backup = backup
        self.processes: dict[str, subprocess.Popen] = {}

    def logs(self) -> str:
        parts = []
        for name in ("slurmctld.log", "slurmd.log", "munged.log"):
            path = self.state / name
            if path.exists():
                parts.append(f"--- {name}\n" + path.read_text(errors="replace")[-3000:])
        return "\n".join(parts)


def _memory_mb() -> int:
    with open("/proc/meminfo") as meminfo:
        total_kb = int(next(line for line in meminfo if line.startswith("MemTotal")).split()[1])
    return max(1024, total_kb // 1024 - 1024)


def _wait(predicate, seconds: float, what: str, cluster: Cluster):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if predicate():
            return
        for name, process in cluster.processes.items():
            if process.poll() is not None:
                raise RuntimeError(f"{name} exited with {process.returncode} while waiting for {what}\n{cluster.logs()}")
        time.sleep(0.5)
    raise RuntimeError(f"timed out after {seconds:g} s waiting for {what}\n{cluster.logs()}")


def _node_idle() -> bool:
    out = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True)
    return out.returncode == 0 and out.stdout.strip().startswith("idle")


def start(state: Path | None = None, cpus: int | None = None) -> Cluster:
    """Bring up munge, slurmctld and slurmd; return when the node is idle."""
    if os.geteuid() != 0:
        raise RuntimeError("the single-node SLURM needs root (it writes /etc/slurm/slurm.conf)")
    if not installed():
        raise RuntimeError("SLURM is not installed: `make slurm` installs slurmctld slurmd slurm-client munge")
    state = Path(state or tempfile.mkdtemp(prefix="roughlight-slurm-"))
    for sub in ("state", "spool", "munge"):
        (state / sub).mkdir(parents=True, exist_ok=True)
    backup = None
    if CONF.exists() and MARK not in CONF.read_text(errors="replace"):
        backup = state / "slurm.conf.before"
        shutil.copy2(CONF, backup)
    CONF.parent.mkdir(parents=True, exist_ok=True)
    host = socket.gethostname().split(".")[0]
    CONF.write_text(slurm_conf(state, host, cpus or os.cpu_count() or 1, _memory_mb()))
    cluster = Cluster(state, backup)
    try:
        if not Path("/etc/munge/munge.key").exists():
            subprocess.run(["mungekey", "--create", "--force"], check=True, capture_output=True)
        munge_dir = state / "munge"
        socket_path = Path("/run/munge/munge.socket.2")  # where the SLURM daemons' libmunge looks
        socket_path.parent.mkdir(parents=True, exist_ok=True)
        cluster.processes["munged"] = subprocess.Popen(
            ["munged", "--foreground", "--force", f"--socket={socket_path}", f"--pid-file={munge_dir}/munged.pid",
             f"--log-file={state}/munged.log", f"--seed-file={munge_dir}/munged.seed"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _wait(socket_path.exists, 20, "munged's socket", cluster)
        for daemon in ("slurmctld", "slurmd"):
            cluster.processes[daemon] = subprocess.Popen(
                [daemon, "-D"], stdout=open(state / f"{daemon}.out", "w"), stderr=subprocess.STDOUT)
        _wait(_node_idle, 60, "the node to be idle in sinfo", cluster)
    except BaseException:
        stop(cluster)
        raise
    return cluster


def stop(cluster: Cluster) -> None:
    """End the daemons (SIGTERM, then SIGKILL after 10 s), cancel what is left, restore slurm.conf."""
    if "slurmctld" in cluster.processes and cluster.processes["slurmctld"].poll() is None:
        subprocess.run(["scancel", "--full", "--state=PENDING,RUNNING"], capture_output=True, timeout=20)
    for name in ("slurmd", "slurmctld", "munged"):
        process = cluster.processes.get(name)
        if process is None or process.poll() is not None:
            continue
        process.send_signal(signal.SIGTERM)
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=10)
    if cluster.backup is not None:
        shutil.copy2(cluster.backup, CONF)
    elif CONF.exists() and MARK in CONF.read_text(errors="replace"):
        CONF.unlink()


def _terminate(signum, frame):
    raise SystemExit(128 + signum)  # so that the cluster is torn down (finally) on SIGTERM too


def main(argv: list[str]) -> int:
    command = argv[argv.index("--") + 1:] if "--" in argv else []
    signal.signal(signal.SIGTERM, _terminate)
    cluster = start()
    print(f"single-node SLURM up (state and logs in {cluster.state})", flush=True)
    try:
        if not command:
            return 0
        return subprocess.run(command).returncode
    finally:
        stop(cluster)
        print("single-node SLURM stopped", flush=True)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
