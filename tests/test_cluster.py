"""The study on a real (single-node) SLURM through profiles/slurm and Snakemake's executor plugin: the study table
equals a local run's bit for bit, and a second driver in the same directory stops at once. Runs where SLURM is
installed (`make test` and `make cluster-test` install it); needs root, as it writes /etc/slurm/slurm.conf for the
time of the scenario.

The scenario (tests/cluster/scenario.py) is mostly waiting on SLURM and the executor plugin's status checks: it
runs in the background from the moment the session has collected this test (tests/conftest.py), and the test
asserts what it recorded.
"""
import shutil
import sys
from pathlib import Path

import pandas as pd
import pytest

sys.path.insert(0, str(Path(__file__).parent / "cluster"))
import scenario  # noqa: E402

#: Columns that hold wall time, which no two runs share.
TIMING = ["render_seconds"]

pytestmark = pytest.mark.skipif(not scenario.available(),
                                reason="needs SLURM (make slurm installs slurmctld, slurmd, munge) and root")


def test_the_study_on_slurm_equals_a_local_run_and_a_second_driver_stops_at_once(cluster_scenario):
    directory = cluster_scenario
    seen = scenario.result(directory)
    assert "error" not in seen, seen.get("error")
    assert seen["local"]["returncode"] == 0, seen["local"]["log"]
    assert seen["lock_taken"], f"the cluster run never took the run lock:\n{seen['first']['log'][-6000:]}"
    second = seen["second"]
    assert second["returncode"] != 0 and "another run of this workflow is active" in second["log"], second["log"]
    log = seen["first"]["log"]
    assert seen["first"]["returncode"] == 0, log[-6000:]
    assert seen["conf_restored"]

    # the sweeps went to SLURM as group jobs: fewer cluster jobs than sweeps
    submitted = log.count("has been submitted with SLURM jobid")
    assert "Group job sweeps" in log and 2 <= submitted < 4 + 1, log[-3000:]
    on_cluster = pd.read_parquet(directory / "cluster" / scenario.STUDY).drop(columns=TIMING)
    here = pd.read_parquet(directory / "local" / scenario.STUDY).drop(columns=TIMING)
    pd.testing.assert_frame_equal(on_cluster, here, check_exact=True)
    shutil.rmtree(directory, ignore_errors=True)
