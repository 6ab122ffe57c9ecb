"""A copy of the workflow for a test to run Snakemake in (the tests' fixtures and the cluster scenario, which runs
as a script of its own), the command that runs it, and a finished run shared by the tests of a session."""
import fcntl
import shutil
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
#: The snakemake command of the environment the tests run in.
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
#: What a run of the workflow needs from the repository.
WORKFLOW = ("Snakefile", "workflow", "config", "envs", "profiles")


def copy_workflow(directory: Path) -> Path:
    """A copy of the workflow (Snakefile, workflow/, config/, envs/, profiles/) in ``directory``."""
    for name in WORKFLOW:
        src = REPO / name
        if src.is_dir():
            shutil.copytree(src, directory / name, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            shutil.copy(src, directory / name)
    return directory


def once_a_session(tmp_path_factory, worker_id: str, name: str, build) -> Path:
    """``build(directory)`` once a test session, in a directory named ``name`` that every pytest-xdist worker
    shares: the first to come builds it under a lock, the others wait for it and read it. A build that raised is
    tried again by the next test that asks."""
    shared = tmp_path_factory.getbasetemp() if worker_id == "master" else tmp_path_factory.getbasetemp().parent
    directory = shared / name
    with open(shared / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (directory / "done").exists():
            shutil.rmtree(directory, ignore_errors=True)
            directory.mkdir()
            build(directory)
            (directory / "done").touch()
    return directory


def copy_finished(source: Path, directory: Path, names=("results", ".snakemake")) -> Path:
    """A finished run's ``names`` (its results/ and Snakemake's records of them, by default) from ``source`` into
    the workflow copy ``directory``, times kept: to Snakemake nothing there is out of date."""
    for name in names:
        src = source / name
        if src.is_dir():
            shutil.copytree(src, directory / name, symlinks=True, dirs_exist_ok=True)
        else:
            shutil.copy2(src, directory / name)
    return directory
