"""The study on a real (single-node) SLURM through profiles/slurm and Snakemake's executor plugin: the study table
equals a local run's bit for bit. Runs where SLURM is installed (`make test` and `make cluster-test` install it);
needs root, as it writes /etc/slurm/slurm.conf for the time of the test."""
import os
import shutil
import subprocess
import sys
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


def test_the_study_on_slurm_equals_a_local_run(workflow_dir, tmp_path_factory):
    (workflow_dir / "config" / "config.yaml").write_text(yaml.safe_dump(SMALL))
    local = tmp_path_factory.mktemp("local")
    shutil.copytree(workflow_dir, local, dirs_exist_ok=True)
    _run(local, "--cores", "2", timeout=600)

    cluster = single_node.start(state=tmp_path_factory.mktemp("slurm"))
    try:
        # the profile as a user has it, less the account (this cluster keeps none); a hard timeout, so that a
        # status query that never sees the jobs finish fails the test instead of hanging it
        log = _run(workflow_dir, "--profile", "profiles/slurm", "--slurm-no-account", timeout=420)
    finally:
        single_node.stop(cluster)
    assert not Path(single_node.CONF).exists() or single_node.MARK not in Path(single_node.CONF).read_text()

    # the sweeps went to SLURM as group jobs: fewer cluster jobs than sweeps
    submitted = log.count("has been submitted with SLURM jobid")
    assert "Group job sweeps" in log and 2 <= submitted < 4 + 1, log[-3000:]
    on_cluster = pd.read_parquet(workflow_dir / STUDY).drop(columns=TIMING)
    here = pd.read_parquet(local / STUDY).drop(columns=TIMING)
    pd.testing.assert_frame_equal(on_cluster, here, check_exact=True)
