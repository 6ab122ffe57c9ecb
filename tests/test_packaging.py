"""`pip install .` (not editable) gives a working package: the wheel holds every file the code opens at run time,
and the package runs from the wheel alone (its schema, captions, shaders and page templates)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from .conftest import REPO

PACKAGE = REPO / "src" / "roughlight"
UV = Path(sys.executable).with_name("uv")


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The wheel built from a copy of the project (the build leaves nothing in the work tree)."""
    if not UV.exists():
        pytest.fail(f"uv is not in the environment ({UV}): run `make setup`")
    source = tmp_path_factory.mktemp("source")
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(REPO / name, source / name)
    shutil.copytree(REPO / "src", source / "src", ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    out = tmp_path_factory.mktemp("dist")
    proc = subprocess.run([str(UV), "build", "--wheel", "--out-dir", str(out), str(source)], capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    (found,) = out.glob("roughlight-*.whl")
    return found


def data_files() -> set[str]:
    """Every file of the package that is not Python: what the code opens at run time."""
    return {p.relative_to(PACKAGE.parent).as_posix() for p in PACKAGE.rglob("*")
            if p.is_file() and p.suffix not in {".py", ".pyc"} and "__pycache__" not in p.parts}


def test_the_wheel_holds_every_file_of_the_package(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    expected = data_files() | {p.relative_to(PACKAGE.parent).as_posix() for p in PACKAGE.rglob("*.py")}
    assert expected - names == set()
    # the files the code is known to open, by name: a pattern dropped from package-data is caught here too
    for name in ("roughlight/render/shaders/implicit_model.glsl", "roughlight/render/shaders/periodic.frag",
                 "roughlight/study/config.schema.yaml", "roughlight/report/captions/fig19_topdown.rst",
                 "roughlight/render/fast/raster.c"):
        assert name in names


SMOKE = """
import numpy as np, roughlight
from pathlib import Path
assert Path(roughlight.__file__).is_relative_to(Path({where!r})), roughlight.__file__
from roughlight.study import config
cfg = config.validate_config({{}})                                 # the schema
from roughlight.report import registry
assert all(registry.caption(f.name) for f in registry.FIGURES)    # every caption
from roughlight.render import methods
from roughlight.surfaces.surface import Surface
for method in ("fast", "naive", "implicit_exact"):                # every shader program, implicit_model.glsl too
    out = methods.sweep(method, Surface(0.5, 1.0), 30.0, np.array([0.0]), np.array([60.0]))
    assert np.isfinite(out["total"]).all(), method
from roughlight.render.fast import raster                         # the C kernel, built from the wheel's raster.c
assert raster.build_kernel().is_relative_to(Path({where!r})), raster.build_kernel()
square = np.array([[[0, 0, 0], [1, 0, 0], [1, 1, 0]], [[0, 0, 0], [1, 1, 0], [0, 1, 0]]])  # the period, flat
visible, total, per_tile = raster.count_views(square, np.array([0, 0]), 1, np.zeros((1, 2)), np.eye(2, dtype=int) * 4)
assert visible.sum() == total.sum() == per_tile == 16, (visible, total)
from roughlight.render.exact import pyramid                      # the clipper, built from the wheel's pyramid.c
assert pyramid.build_kernel().is_relative_to(Path({where!r})), pyramid.build_kernel()
lit, shadowed = pyramid.pyramid_shares(Surface(0.5, 1.0), 30.0, 60.0, 20.0)
assert abs(lit.sum() + shadowed.sum() - 1.0) < 1e-12, (lit, shadowed)
from roughlight.report import page
html = page.build_report({{}}, {{}})                                # the page's templates
assert "<html" in html
print("ok")
"""


def test_the_package_runs_from_the_wheel_alone(wheel, tmp_path):
    where = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(where)
    env = {**os.environ, "PYTHONPATH": str(where), "PYOPENGL_PLATFORM": "osmesa", "LP_NUM_THREADS": "0"}
    proc = subprocess.run([sys.executable, "-c", SMOKE.format(where=str(where))], capture_output=True, text=True,
                          env=env, cwd=tmp_path, timeout=600)
    assert proc.returncode == 0 and proc.stdout.strip().endswith("ok"), proc.stderr[-3000:]
