"""Shared test settings: OSMesa before anything imports OpenGL; one llvmpipe thread."""
import os
import shutil
from pathlib import Path

import pytest

os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")
os.environ.setdefault("LP_NUM_THREADS", "1")

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture
def workflow_dir(tmp_path):
    """A copy of the workflow (Snakefile, workflow/, config/) in a temporary directory."""
    for name in ("Snakefile", "workflow", "config", "envs", "profiles"):
        src = REPO / name
        if src.is_dir():
            shutil.copytree(src, tmp_path / name, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            shutil.copy(src, tmp_path / name)
    return tmp_path
