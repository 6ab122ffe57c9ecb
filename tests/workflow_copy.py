"""A copy of the workflow for a test to run Snakemake in (the tests' fixtures and the cluster scenario, which runs
as a script of its own)."""
import shutil
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
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
