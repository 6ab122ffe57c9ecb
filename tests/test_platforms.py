"""OpenGL's headless platforms: OSMesa and EGL give the same numbers, EGL chooses its device as documented, an old
OpenGL is refused by name, and every sweep records what it ran on."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from roughlight.render.gl import egl

#: A fixed set of sweeps of every method (and a random tile), run in a fresh process on the platform given.
SWEEPS = r"""
import json, sys
import numpy as np
from roughlight.render import methods
from roughlight.render.gl import context
from roughlight.render.views import view_grid
from roughlight.surfaces.roughness import make_surface
from roughlight.surfaces.surface import Surface

az, el = view_grid(30.0, 45.0)
out, ran_on = {}, set()
for name, surface in [("fast", Surface(0.5, 1.0)), ("fast", make_surface("random_pyramids", 1.0, 1.0, 1)),
                      ("naive", Surface(0.5, 1.0)), ("implicit_exact", Surface(1.0, 0.8)),
                      ("implicit_correction", Surface(1.0, 0.8)), ("fast", Surface(1.0, 1.0))]:
    keep = slice(None, 12) if name == "naive" else slice(None)
    result = methods.sweep(name, surface, 30.0, az[keep], el[keep])
    ran_on.add(result["renderer"])
    for c in ("diffuse", "specular", "total", "coverage"):
        out[f"{name}/{surface}/{c}"] = np.asarray(result[c])
np.savez(sys.argv[1], **out)
print(json.dumps(sorted(ran_on)))
"""


def _run(platform: str, path, extra_env=None) -> list:
    env = {**os.environ, "PYOPENGL_PLATFORM": platform, "LP_NUM_THREADS": "0", **(extra_env or {})}
    done = subprocess.run([sys.executable, "-c", SWEEPS, str(path)], capture_output=True, text=True, env=env,
                          timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_osmesa_and_egl_give_the_same_numbers_for_every_method(tmp_path):
    """On llvmpipe, every method's values are the same to the bit under both platforms (each in its own process:
    PyOpenGL's platform is chosen once a process), and each sweep says which platform it ran on."""
    from roughlight.render.fast import raster

    osmesa_on = _run("osmesa", tmp_path / "osmesa.npz")
    egl_on = _run("egl", tmp_path / "egl.npz")
    assert len(set(osmesa_on) - set(egl_on)) == 1  # the GL renderer alone tells them apart
    # random tiles are counted on the CPU, whatever the platform: the same record under both
    counted = [raster.identity()]
    osmesa_on, egl_on = ([r for r in on if r not in counted] for on in (osmesa_on, egl_on))
    assert len(osmesa_on) == 1 and osmesa_on[0].endswith(", osmesa") and "OpenGL 4." in osmesa_on[0]
    assert len(egl_on) == 1 and egl_on[0].endswith(", egl") and "llvmpipe" in egl_on[0]
    a, b = np.load(tmp_path / "osmesa.npz"), np.load(tmp_path / "egl.npz")
    assert sorted(a.files) == sorted(b.files) and len(a.files) == 24
    differ = [key for key in a.files if not np.array_equal(a[key], b[key])]
    assert not differ, differ
    assert all(np.any(a[key] > 0) for key in a.files if key.endswith("/total"))  # something was drawn


def _devices(*kinds):
    return [egl.Device(k, "EGL_MESA_device_software" if kind == "soft" else "EGL_EXT_device_drm",
                       None if kind == "soft" else f"/dev/dri/card{k}") for k, kind in enumerate(kinds)]


def test_the_egl_device_is_the_one_asked_for_else_the_first_gpu_else_software():
    said = []
    found = _devices("soft", "gpu", "gpu")
    assert egl.choose_device(found, log=said.append).index == 1 and not said  # the first hardware device
    assert egl.choose_device(found, 2, log=said.append).index == 2  # an explicit index, whatever it is
    assert egl.choose_device(found, 0, log=said.append).software and not said
    only_software = _devices("soft")
    assert egl.choose_device(only_software, log=said.append).software
    assert len(said) == 1 and "software device" in said[0]  # the fallback is logged
    with pytest.raises(egl.EGLUnavailable, match="render.egl_device is 3 but EGL offers 3 device"):
        egl.choose_device(found, 3)
    with pytest.raises(egl.EGLUnavailable, match="no device"):
        egl.choose_device([])


def test_thedevice_index_reaches_a_job_through_its_environment(monkeypatch):
    monkeypatch.setenv("ROUGHLIGHT_EGL_DEVICE", "")
    assert egl.device_index() is None
    monkeypatch.setenv("ROUGHLIGHT_EGL_DEVICE", "1")
    assert egl.device_index() == 1
    monkeypatch.setenv("ROUGHLIGHT_EGL_DEVICE", "gpu1")
    with pytest.raises(egl.EGLUnavailable, match="device index"):
        egl.device_index()


def test_a_missing_or_broken_egl_is_named_with_what_to_install(broken_osmesa, tmp_path):
    with pytest.raises(egl.EGLUnavailable, match="libEGL is missing .*libegl1"):
        egl.check_egl(names=("libNoSuchEGL.so.1",))
    broken = tmp_path / "libEGL.so.1"  # a real shared library without EGL in it
    broken.write_bytes((broken_osmesa / "libOSMesa.so").read_bytes())
    with pytest.raises(egl.EGLUnavailable, match="libEGL is broken: .* lacks eglGetProcAddress.*libegl1"):
        egl.check_egl(names=(str(broken),))
    assert "EGL device 0" in egl.check_egl()  # this machine's: Mesa's software device


def test_an_opengl_older_than_4_3_is_refused_by_name():
    from roughlight.render.gl import context

    assert context.check_version("4.5 (Core Profile) Mesa 22.3.6") == (4, 5)
    assert context.check_version("4.3.0 NVIDIA 535.104") == (4, 3)
    with pytest.raises(context.Unavailable, match="OpenGL 3.3 .* older than 4.3 core, the oldest the renderers"):
        context.check_version("3.3 (Core Profile) Mesa 20.0", "llvmpipe")
    with pytest.raises(context.Unavailable, match="no version"):
        context.check_version("")


def test_each_sweep_and_the_study_table_record_what_they_ran_on(tmp_path):
    from roughlight.render.shading import Lighting
    from roughlight.study import tables
    from roughlight.surfaces.surface import Surface

    sweep = {"elevation_step": 60, "azimuth_step": 90}
    paths = []
    for method in ("fast", "reference"):
        paths.append(tmp_path / f"{method}.parquet")
        tables.run_sweep(str(paths[-1]), Surface(0.5, 1.0), 30.0, sweep, Lighting().as_dict(), method, {})
    ran_on = tables.renderers(paths)
    assert len(ran_on) == 2 and "exact (no OpenGL)" in ran_on
    assert any("llvmpipe" in r and r.endswith(", osmesa") for r in ran_on)
