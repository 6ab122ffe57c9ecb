"""A run of the workflow in its directory: is ``results/`` writable, and is this the only run there.

The Snakefile calls these before any job (and stops with their message): :func:`results_problem` while the
workflow is parsed (dry runs too) and again, with a probe file, when a real run starts; :func:`acquire_run_lock`
when a run with work to do starts. The lock is an OS-level ``flock`` held by the run's process: the kernel
releases it when that process ends, even by SIGKILL, so a killed run never blocks the next.
"""

from __future__ import annotations

import fcntl
import os
import tempfile
import time

__all__ = ["RUN_LOCK", "RunLocked", "results_problem", "not_writable_message", "acquire_run_lock"]

#: The run lock's file, relative to the workflow's directory.
RUN_LOCK = ".snakemake/roughlight.lock"


class RunLocked(RuntimeError):
    """Another run of the workflow holds the directory's run lock (the message names it)."""


def results_problem(directory: str = "results", probe: bool = False) -> str | None:
    """Why ``directory`` cannot take the run's results, or None.

    Without ``probe`` only looks; with it also writes and removes a probe file (at the start of a real run).
    """
    if os.path.exists(directory) and not os.path.isdir(directory):
        return "it exists but is not a directory"
    if os.path.isdir(directory) and not os.access(directory, os.W_OK | os.X_OK):
        return "permission denied"
    parent = os.path.dirname(os.path.abspath(directory))
    if not os.path.exists(directory) and not (os.path.isdir(parent) and os.access(parent, os.W_OK)):
        return "it cannot be created here"
    if probe:
        try:
            os.makedirs(directory, exist_ok=True)
            with tempfile.NamedTemporaryFile(dir=directory, prefix=".write-check-"):
                pass
        except OSError as exc:
            return str(exc)
    return None


def not_writable_message(directory: str, problem: str) -> str:
    """The one message a run stops with when ``directory`` cannot take its results."""
    return (f"{directory}/ is not writable ({problem}): make it a writable directory (or run from a directory "
            "where it can be created) and rerun; nothing was computed or removed")


def acquire_run_lock(path: str = RUN_LOCK, command: str = "") -> int:
    """Take the run lock at ``path`` or raise :class:`RunLocked` at once, naming the run that holds it.

    Returns the lock's file descriptor: keep it open for as long as the run lasts (the lock goes with it). The
    file then names this run: its PID, start time and ``command``.
    """
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        holder = os.pread(fd, 4096, 0).decode("utf-8", "replace").strip() or "another snakemake process"
        os.close(fd)
        raise RunLocked(f"another run of this workflow is active in {os.getcwd()} ({holder}): wait for it to "
                        "finish, or stop it and rerun; this run stopped before touching anything") from None
    os.ftruncate(fd, 0)
    os.pwrite(fd, f"pid {os.getpid()}, started {time.strftime('%Y-%m-%d %H:%M:%S')}: {command}".encode(), 0)
    return fd
