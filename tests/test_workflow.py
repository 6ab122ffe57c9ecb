"""End to end: snakemake on a tiny grid in a temporary directory."""
import subprocess

import numpy as np
import pandas as pd
import pytest
import yaml

from roughlight.study.tables import STUDY_COLUMNS, renderers

from .workflow_copy import SNAKEMAKE, copy_finished, copy_workflow, once_a_session

TINY = {
    "grid": {"truncation": [0.0, 1.0], "aspect": [1.0], "incidence": [30]},
    "sweep": {"elevation_step": 30, "azimuth_step": 60},
}


def write_config(workdir, cfg):
    (workdir / "config" / "config.yaml").write_text(yaml.safe_dump(cfg))


def snakemake(workdir, *args, check=True, env=None):
    proc = subprocess.run(
        [SNAKEMAKE, "--cores", "2", *args], cwd=workdir, capture_output=True, text=True, timeout=600, env=env
    )
    if check and proc.returncode != 0:
        raise AssertionError(f"snakemake {' '.join(args)} failed:\n{proc.stdout}\n{proc.stderr}")
    return proc


STUDY = "results/study.parquet"  # the report's end-to-end run is tests/test_report.py's
MESH = "results/meshes/t1_a1.ply"


@pytest.fixture(scope="session")
def tiny_run(tmp_path_factory, worker_id):
    """A workflow copy where ``snakemake STUDY MESH`` ran on :data:`TINY`, once a test session: the pytest-xdist
    workers share it (the first to come runs it under a lock). The tests that start from TINY's finished study copy
    its results/ and .snakemake/ (:func:`finished_tiny`) instead of rendering the same sweeps again."""
    def build(workdir):
        copy_workflow(workdir)
        write_config(workdir, TINY)
        snakemake(workdir, STUDY, MESH)

    return once_a_session(tmp_path_factory, worker_id, "tiny-run", build)


def finished_tiny(workflow_dir, tiny_run):
    """TINY's config, study table, sweeps, mesh and Snakemake's records of them in ``workflow_dir``, as if
    ``snakemake STUDY MESH`` had just run there (times kept: nothing is out of date)."""
    write_config(workflow_dir, TINY)
    copy_finished(tiny_run, workflow_dir)


def _check_before_rounding(study):
    """The study's means before rounding and without inner shadows (fast, adaptive: every one given): within half a
    level of the 8-bit means at every measured view, 0 where nothing was measured; the plate's diffuse the
    equation's 127 sin 30 = 63.5 itself; the unshadowed diffuse never darker, and brighter where shadows are seen,
    but not at the hot spot V = L (phase 0), where no seen point is shadowed (the regular surface's shadow map may
    mark a sliver of the silhouettes there: within half a level)."""
    seen = study["coverage"] > 0
    for name, rounded in (("rough_unrounded", "rough"), ("control_unrounded", "control"), ("rough_unshadowed", None)):
        assert study[name].dtype == np.float64 and study[name].notna().all() and (study.loc[~seen, name] == 0).all()
        if rounded:
            assert (np.abs(study.loc[seen, name] - study.loc[seen, rounded]) <= 0.5 + 1e-6).all(), name
    diffuse = study[seen & (study.component == "diffuse")]
    np.testing.assert_allclose(diffuse["control_unrounded"], 127 * np.sin(np.radians(30.0)), rtol=0, atol=1e-9)
    assert (diffuse["rough_unshadowed"] >= diffuse["rough_unrounded"] - 1e-9).all()
    assert (diffuse["rough_unshadowed"] > diffuse["rough_unrounded"] + 1.0).any()  # the full pyramid's shadows
    hot = diffuse[diffuse["phase"] < 1e-9]
    assert len(hot) == 2  # the plate and the full pyramid
    assert (hot["rough_unshadowed"] - hot["rough_unrounded"] <= 0.5).all()
    plate = hot[hot.truncation == 0]
    assert (plate["rough_unrounded"] == plate["rough_unshadowed"]).all()


def planned_jobs(workdir):
    """Jobs a dry run for the study table would execute, by rule."""
    out = snakemake(workdir, STUDY, "--dry-run", "--quiet", "rules").stdout
    counts = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 2 and parts[1].isdigit() and parts[0] not in ("total", "rule"):
            counts[parts[0]] = int(parts[1])
    return counts


@pytest.mark.slow
def test_tiny_study_end_to_end(workflow_dir, tiny_run):
    finished_tiny(workflow_dir, tiny_run)  # snakemake STUDY MESH on TINY, run once a session
    study = pd.read_parquet(workflow_dir / "results" / "study.parquet")
    assert list(study.columns) == STUDY_COLUMNS
    views = 7 * 3  # elevations 0..180 by 30 x azimuths 0, 60, 120
    assert len(study) == 2 * views * 3
    assert set(study["component"]) == {"diffuse", "specular", "total"}
    assert (study["method"] == "fast").all() and study["shadows"].all()
    inner = study[(study.elevation > 0) & (study.elevation < 180)]
    assert (inner["coverage"] == 1).all()
    # the control is Lambert's plate: 127 sin 30 = 63.5 -> 64 on 8 bits
    assert np.allclose(inner.loc[inner.component == "diffuse", "control"], 64.0)
    # truncation 0 is the plate: rough equals control
    plate = study[study.truncation == 0]
    np.testing.assert_array_equal(plate["rough"], plate["control"])
    # the full pyramid differs from the plate and is darker in diffuse on average
    pyramid = inner[(inner.truncation == 1) & (inner.component == "diffuse")]
    assert pyramid["rough"].mean() < pyramid["control"].mean() - 5
    # phase is the angle between L and V
    row = study[(study.azimuth == 0) & (study.elevation == 30)].iloc[0]
    assert row["phase"] == pytest.approx(0.0, abs=1e-9)
    assert (study["render_seconds"] > 0).all()
    _check_before_rounding(study)
    assert (workflow_dir / "results" / "meshes" / "t1_a1.ply").exists()
    # the study table records what its sweeps ran on (the report's provenance lists it)
    ran_on = renderers([workflow_dir / "results" / "study.parquet"])
    assert len(ran_on) == 1 and "llvmpipe" in ran_on[0] and ran_on[0].endswith(", osmesa")

    # nothing changed: nothing to do
    assert planned_jobs(workflow_dir) == {}

    # a new truncation is one new job (its sweeps at every aspect), plus the aggregate
    cfg = yaml.safe_load(yaml.safe_dump(TINY))
    cfg["grid"]["truncation"].append(0.5)
    write_config(workflow_dir, cfg)
    assert planned_jobs(workflow_dir) == {"rough_sweeps": 1, "study_table": 1}

    # a new aspect reruns every truncation's job, but each renders only its new sweep: the others come from the
    # sweep store, byte for byte as first measured
    sweeps = workflow_dir / "results" / "sweeps" / "i30"
    before = {name: (sweeps / name).read_bytes() for name in ("t0_a1.parquet", "t1_a1.parquet")}
    cfg["grid"]["aspect"].append(0.5)
    write_config(workflow_dir, cfg)
    assert planned_jobs(workflow_dir) == {"rough_sweeps": 3, "study_table": 1}
    snakemake(workflow_dir, STUDY)
    logs = workflow_dir / "results" / "logs" / "sweeps" / "i30"
    said = {t: (logs / f"t{t}.log").read_text() for t in ("0", "0.5", "1")}
    assert "1 sweeps measured, 1 taken from the store" in said["0"], said["0"]
    assert "1 sweeps measured, 1 taken from the store" in said["1"], said["1"]
    assert "2 sweeps measured, 0 taken from the store" in said["0.5"], said["0.5"]
    for name, data in before.items():
        assert (sweeps / name).read_bytes() == data
    study = pd.read_parquet(workflow_dir / "results" / "study.parquet")
    assert len(study) == 3 * 2 * views * 3

    # the shadows switch re-renders the rough surfaces, not the control (a plate has no shadows)
    cfg["render"] = {"shadows": False}
    write_config(workflow_dir, cfg)
    jobs = planned_jobs(workflow_dir)
    assert jobs.get("rough_sweeps") == 3 and "control_sweep" not in jobs

    # a lighting change re-renders everything that sees the light
    cfg["render"] = {"shadows": True}
    cfg["material"] = {"shininess": 32}
    write_config(workflow_dir, cfg)
    jobs = planned_jobs(workflow_dir)
    assert jobs.get("rough_sweeps") == 3 and jobs.get("control_sweep") == 1

    # the OpenGL platform reaches every rendering job through its params: a change re-renders every sweep
    cfg["material"] = {"shininess": 64}
    cfg["render"] = {"platform": "egl"}
    write_config(workflow_dir, cfg)
    jobs = planned_jobs(workflow_dir)
    assert jobs.get("rough_sweeps") == 3 and jobs.get("control_sweep") == 1


@pytest.mark.slow
def test_bad_config_stops_before_any_rendering(workflow_dir):
    cfg = yaml.safe_load(yaml.safe_dump(TINY))
    # a grid with no valid combination at all: every problem in one message, nothing rendered
    cfg["grid"] = {"truncation": [1.5, -0.1], "aspect": [-1.0], "incidence": [95.0]}
    cfg["sweep"]["azimuth_step"] = "five"
    write_config(workflow_dir, cfg)
    proc = snakemake(workflow_dir, check=False)
    assert proc.returncode != 0
    text = proc.stdout + proc.stderr
    for problem in ("grid.truncation[0] = 1.5 must be <= 1", "grid.truncation[1] = -0.1 must be >= 0",
                    "grid.aspect[0] = -1.0 must be >= 0", "grid.incidence[0] = 95.0 must be <= 90",
                    "sweep.azimuth_step = 'five' must be of type number"):
        assert text.count(problem) >= 1, problem
    assert not (workflow_dir / "results" / "sweeps").exists()


@pytest.mark.slow
def test_lint_is_clean(workflow_dir):
    proc = snakemake(workflow_dir, "--lint", check=False)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "Congratulations" in proc.stdout + proc.stderr


@pytest.mark.slow
def test_killed_run_reruns_to_the_same_table(workflow_dir, tmp_path_factory):
    """SIGKILL in the middle of rendering, rerun: the table is whole and equals a clean run's."""
    import os
    import shutil
    import signal
    import time

    cfg = {
        "grid": {"truncation": [0.0, 0.3, 0.6, 1.0], "aspect": [0.5, 1.0], "incidence": [30]},
        "sweep": {"elevation_step": 5, "azimuth_step": 20},
    }
    write_config(workflow_dir, cfg)
    clean = tmp_path_factory.mktemp("clean")
    for name in ("Snakefile", "workflow", "config", "envs", "profiles"):
        src = workflow_dir / name
        (shutil.copytree if src.is_dir() else shutil.copy)(src, clean / name)

    proc = subprocess.Popen([SNAKEMAKE, "--cores", "2", STUDY], cwd=workflow_dir, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    sweeps = workflow_dir / "results" / "sweeps" / "i30"
    deadline = time.time() + 120
    while time.time() < deadline and len(list(sweeps.glob("t*.parquet"))) < 2:
        time.sleep(0.2)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    done = len(list(sweeps.glob("t*.parquet")))
    assert 2 <= done < 8, "the kill should land in the middle of rendering"
    assert not (workflow_dir / "results" / "study.parquet").exists()

    snakemake(workflow_dir, STUDY)  # a plain rerun completes (no --unlock, no --rerun-incomplete)
    snakemake(clean, STUDY)
    killed = pd.read_parquet(workflow_dir / "results" / "study.parquet").drop(columns="render_seconds")
    fresh = pd.read_parquet(clean / "results" / "study.parquet").drop(columns="render_seconds")
    assert len(killed) == 8 * 37 * 9 * 3
    pd.testing.assert_frame_equal(killed, fresh)  # bit-for-bit: rendering is deterministic


@pytest.mark.slow
def test_unwritable_results_and_corrupt_sweeps_end_with_one_clear_message(workflow_dir, tiny_run):
    write_config(workflow_dir, TINY)
    # results/ cannot be a directory here (a file stands in the way): stop before any job
    (workflow_dir / "results").write_text("not a directory")
    proc = snakemake(workflow_dir, STUDY, check=False)
    assert proc.returncode != 0
    assert "results/ is not writable" in proc.stdout + proc.stderr
    (workflow_dir / "results").unlink()

    # a corrupt sweep file left in results/: the aggregate names it and says what to do
    finished_tiny(workflow_dir, tiny_run)  # TINY's finished study (snakemake STUDY, run once a session)
    assert planned_jobs(workflow_dir) == {}
    bad = workflow_dir / "results" / "sweeps" / "i30" / "t1_a1.parquet"
    good = workflow_dir / "results" / "sweeps" / "i30" / "t0_a1.parquet"
    kept = good.read_bytes()
    bad.write_bytes(b"PAR1 truncated")
    proc = snakemake(workflow_dir, STUDY, "--force", check=False)  # rebuild the table from the sweeps
    text = proc.stdout + proc.stderr
    assert proc.returncode != 0
    assert "t1_a1.parquet is not a readable Parquet sweep" in text and "delete it and rerun" in text
    assert good.read_bytes() == kept  # nothing already computed is lost
    bad.unlink()
    snakemake(workflow_dir, STUDY)
    assert len(pd.read_parquet(workflow_dir / "results" / "study.parquet")) == 2 * 21 * 3


@pytest.mark.slow
def test_broken_osmesa_stops_before_any_job_and_keeps_what_was_computed(workflow_dir, broken_osmesa, tiny_run):
    import os

    finished_tiny(workflow_dir, tiny_run)  # TINY's finished study (snakemake STUDY, run once a session)
    table = workflow_dir / "results" / "study.parquet"
    kept = table.read_bytes()
    cfg = yaml.safe_load(yaml.safe_dump(TINY))
    cfg["grid"]["truncation"].append(0.5)  # new work that would need rendering
    write_config(workflow_dir, cfg)
    env = {**os.environ, "LD_LIBRARY_PATH": str(broken_osmesa)}
    proc = snakemake(workflow_dir, STUDY, check=False, env=env)
    text = proc.stdout + proc.stderr
    assert proc.returncode != 0
    assert "libOSMesa is broken" in text and "apt-get install libosmesa6" in text
    assert not (workflow_dir / "results" / "sweeps" / "i30" / "t0.5_a1.parquet").exists()
    assert table.read_bytes() == kept
    # the same with render.platform egl and a broken libEGL first on the library path
    broken_egl = broken_osmesa.parent / "broken_egl"
    broken_egl.mkdir()
    (broken_egl / "libEGL.so.1").write_bytes((broken_osmesa / "libOSMesa.so").read_bytes())
    write_config(workflow_dir, {**cfg, "render": {"platform": "egl"}})
    proc = snakemake(workflow_dir, STUDY, check=False, env={**os.environ, "LD_LIBRARY_PATH": str(broken_egl)})
    text = proc.stdout + proc.stderr
    assert proc.returncode != 0 and "libEGL is broken" in text and "libegl1" in text
    assert not (workflow_dir / "results" / "sweeps" / "i30" / "t0.5_a1.parquet").exists()
    assert table.read_bytes() == kept
    write_config(workflow_dir, cfg)
    snakemake(workflow_dir, STUDY)  # with the library path mended, the rerun does only the new work
    assert len(pd.read_parquet(table)) == 3 * 21 * 3


@pytest.mark.slow
def test_a_second_run_stops_at_once_and_a_killed_run_leaves_no_lock(workflow_dir):
    """Two runs in one directory: the second stops with one message naming the first and touches nothing;
    the first goes on. SIGKILL the first: the kernel releases its lock, so nothing blocks the next run."""
    import fcntl
    import os
    import signal
    import time

    # the study's own views: the first run must still be running when the second starts (it is killed after the
    # checks, so its size costs nothing); at 2 x 10 degrees the whole study once finished within the second's start
    cfg = {
        "grid": {"truncation": [0.0, 0.2, 0.4, 0.6, 0.8, 1.0], "aspect": [0.5, 0.8, 1.0], "incidence": [30]},
        "sweep": {"elevation_step": 1, "azimuth_step": 5},
    }
    write_config(workflow_dir, cfg)
    first = subprocess.Popen([SNAKEMAKE, "--cores", "2", STUDY], cwd=workflow_dir, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL, start_new_session=True)
    sweeps = workflow_dir / "results" / "sweeps" / "i30"
    try:
        deadline = time.time() + 120
        while time.time() < deadline and not list(sweeps.glob("t*.parquet")):
            time.sleep(0.2)
        # contents, not times: Snakemake touches a job's outputs once it has checked them
        before = {p.name: p.read_bytes() for p in sweeps.glob("[tc]*.parquet")}  # not the temporary files
        second = snakemake(workflow_dir, STUDY, check=False)
        text = second.stdout + second.stderr
        assert second.returncode != 0
        assert "another run of this workflow is active" in text and f"pid {first.pid}" in text, text[-2000:]
        assert "touching anything" in text
        assert first.poll() is None, "the first run goes on"
        after = {p.name: p.read_bytes() for p in sweeps.glob("[tc]*.parquet")}
        changed = [name for name, content in before.items() if after.get(name) != content]
        assert not changed, changed  # nothing of the first run's was touched
    finally:
        os.killpg(first.pid, signal.SIGKILL)
        first.wait()
    fd = os.open(workflow_dir / ".snakemake" / "roughlight.lock", os.O_RDWR)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # free again: the killed run holds nothing
    finally:
        os.close(fd)
