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


@pytest.fixture
def broken_osmesa(tmp_path_factory):
    """A directory whose libOSMesa.so is a real shared library without OpenGL in it (zlib):
    put first on LD_LIBRARY_PATH, it is what PyOpenGL would load."""
    import ctypes
    import ctypes.util

    zlib = ctypes.util.find_library("z")
    ctypes.CDLL(zlib)  # the machine has it (numpy needs it too)
    with open("/proc/self/maps") as maps:
        source = next(line.split()[-1] for line in maps if "/libz.so" in line)
    directory = tmp_path_factory.mktemp("broken_osmesa")
    shutil.copy(source, directory / "libOSMesa.so")
    return directory
