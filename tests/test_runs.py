"""A run in its directory (roughlight.study.runs): results/ writable or one message why, and one run at a time.

The workflow tests (tests/test_workflow.py) run snakemake against these; here they are checked alone."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from roughlight.study import runs


def test_a_writable_or_creatable_results_has_no_problem(tmp_path):
    assert runs.results_problem(str(tmp_path / "results")) is None  # not there yet: it can be made
    assert runs.results_problem(str(tmp_path / "results"), probe=True) is None
    assert (tmp_path / "results").is_dir() and list((tmp_path / "results").iterdir()) == []  # the probe is gone


def test_a_file_in_the_way_or_an_impossible_parent_is_named(tmp_path):
    (tmp_path / "results").write_text("not a directory")
    assert runs.results_problem(str(tmp_path / "results")) == "it exists but is not a directory"
    assert runs.results_problem(str(tmp_path / "results" / "sub")) == "it cannot be created here"
    message = runs.not_writable_message("results", "permission denied")
    assert message.startswith("results/ is not writable (permission denied)") and "nothing was computed" in message


def test_a_second_lock_is_refused_naming_the_first_and_a_closed_one_is_free(tmp_path):
    path = str(tmp_path / ".snakemake" / "roughlight.lock")
    first = runs.acquire_run_lock(path, "snakemake --cores 2")
    try:
        with pytest.raises(runs.RunLocked, match=rf"pid {os.getpid()}, started .*: snakemake --cores 2\)"):
            runs.acquire_run_lock(path, "snakemake --cores 1")
    finally:
        os.close(first)
    second = runs.acquire_run_lock(path, "snakemake --cores 1")  # the lock went with its file descriptor
    os.close(second)


def test_a_killed_holder_leaves_no_lock(tmp_path):
    """The kernel releases the lock of a process killed by SIGKILL: the next run takes it."""
    path = str(tmp_path / "roughlight.lock")
    code = (f"import os, sys, time; from roughlight.study import runs; runs.acquire_run_lock({path!r}, 'held'); "
            "print('held', flush=True); time.sleep(60)")
    holder = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(runs.RunLocked, match="held"):
            runs.acquire_run_lock(path)
    finally:
        holder.kill()
        holder.wait()
    os.close(runs.acquire_run_lock(path))
