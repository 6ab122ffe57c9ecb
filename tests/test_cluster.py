"""The study on a real (single-node) SLURM through profiles/slurm and Snakemake's executor plugin: the study table
equals a local run's bit for bit. Runs where SLURM is installed (`make test` and `make cluster-test` install it);
needs root, as it writes /etc/slurm/slurm.conf for the time of the test."""
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest
import yaml

sys.path.insert(0, str(Path(__file__).parent / "cluster"))
import single_node  # noqa: E402

SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
STUDY = "results/study.parquet"
#: Three surfaces and the control at a coarse sweep: two group jobs of sweeps, then the study table.
SMALL = {
    "grid": {"truncation": [0.0, 0.5, 1.0], "aspect": [1.0], "incidence": [30]},
    "sweep": {"elevation_step": 30, "azimuth_step": 60},
}
#: Columns that hold wall time, which no two runs share.
TIMING = ["render_seconds"]

pytestmark = pytest.mark.skipif(
    not single_node.installed() or os.geteuid() != 0,
    reason="needs SLURM (make slurm installs slurmctld, slurmd, munge) and root",
)


def _run(workdir, *args, timeout):
    env = {**os.environ, "PYOPENGL_PLATFORM": "osmesa"}
    proc = subprocess.run([SNAKEMAKE, STUDY, *args], cwd=workdir, capture_output=True, text=True, timeout=timeout,
                          env=env)
    assert proc.returncode == 0, f"snakemake {' '.join(args)} failed:\n{proc.stdout[-4000:]}\n{proc.stderr[-6000:]}"
    return proc.stdout + proc.stderr


def test_the_study_on_slurm_equals_a_local_run_and_a_second_driver_stops_at_once(workflow_dir, tmp_path_factory):
    (workflow_dir / "config" / "config.yaml").write_text(yaml.safe_dump(SMALL))
    local = tmp_path_factory.mktemp("local")
    shutil.copytree(workflow_dir, local, dirs_exist_ok=True)
    _run(local, "--cores", "2", timeout=600)

    cluster = single_node.start(state=tmp_path_factory.mktemp("slurm"))
    env = {**os.environ, "PYOPENGL_PLATFORM": "osmesa"}
    command = [SNAKEMAKE, STUDY, "--profile", "profiles/slurm", "--slurm-no-account"]
    first = None
    try:
        # the profile as a user has it, less the account (this cluster keeps none); a hard timeout, so that a
        # status query that never sees the jobs finish fails the test instead of hanging it
        first = subprocess.Popen(command, cwd=workflow_dir, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                 text=True, env=env)
        lock = workflow_dir / ".snakemake" / "roughlight.lock"
        deadline = time.monotonic() + 120
        while not (lock.exists() and lock.read_text().strip()) and first.poll() is None:
            assert time.monotonic() < deadline, "the cluster run never took the run lock"
            time.sleep(0.2)
        # a second driver in the same directory stops at once, naming the first, while the first goes on
        second = subprocess.run(command, cwd=workflow_dir, capture_output=True, text=True, timeout=120, env=env)
        assert second.returncode != 0 and "another run of this workflow is active" in second.stderr + second.stdout
        log, _ = first.communicate(timeout=420)
        assert first.returncode == 0, log[-6000:]
    finally:
        if first is not None and first.poll() is None:
            first.kill()
        single_node.stop(cluster)
    assert not Path(single_node.CONF).exists() or single_node.MARK not in Path(single_node.CONF).read_text()

    # the sweeps went to SLURM as group jobs: fewer cluster jobs than sweeps
    submitted = log.count("has been submitted with SLURM jobid")
    assert "Group job sweeps" in log and 2 <= submitted < 4 + 1, log[-3000:]
    on_cluster = pd.read_parquet(workflow_dir / STUDY).drop(columns=TIMING)
    here = pd.read_parquet(local / STUDY).drop(columns=TIMING)
    pd.testing.assert_frame_equal(on_cluster, here, check_exact=True)
