"""Shared test settings: OSMesa before anything imports OpenGL; llvmpipe in the rendering thread and one Dr.Jit
worker; one Dr.Jit kernel cache."""
import os
import shutil
import sys
import tempfile
import uuid
from pathlib import Path

import pytest

os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")
# llvmpipe rasterises in the test's own thread (no worker threads: 13% less CPU for the same pixels, as in a
# workflow job of one thread, workflow/scripts/_gl.py), and Dr.Jit runs one worker
os.environ.setdefault("LP_NUM_THREADS", "0")
os.environ.setdefault("ROUGHLIGHT_THREADS", "1")
# Mitsuba's kernels compiled once for every test, its workers and the workflows they run (each of which would
# otherwise compile them again in its own .snakemake/drjit: 10 s of the quick light_transport job, issue 46); the
# tests of where the cache goes set their own environment
os.environ.setdefault("DRJIT_CACHE_DIR", os.path.join(tempfile.gettempdir(), f"roughlight-drjit-tests-{os.getuid()}"))
os.makedirs(os.environ["DRJIT_CACHE_DIR"], exist_ok=True)
# share tables the implicit table model measures on demand: never the user's ~/.cache (tests of it set their own)
os.environ.setdefault("ROUGHLIGHT_TABLE_CACHE", os.path.join(tempfile.gettempdir(), f"roughlight-tables-tests-{os.getuid()}"))

from .workflow_copy import REPO, copy_workflow, once_a_session  # noqa: E402,F401 (tests import the first two here)

sys.path.insert(0, str(REPO / "tests" / "cluster"))
import scenario  # noqa: E402


@pytest.fixture
def workflow_dir(tmp_path):
    """A copy of the workflow (Snakefile, workflow/, config/) in a temporary directory."""
    return copy_workflow(tmp_path)


@pytest.fixture(scope="session")
def users_workflow(tmp_path_factory, worker_id):
    """The user-grid issue's grids run through snakemake one after the other in one workflow copy, once a session
    (tests/users_workflow.py): each grid's report and tables kept, the copy finished at the last grid."""
    from .users_workflow import run_grids

    return once_a_session(tmp_path_factory, worker_id, "users-workflow", run_grids)


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


# ---------------------------------------------------------------------------
# scheduling on pytest-xdist's workers (make test: -n 2 with xdist's default --dist load; pyproject's --no-loadscope-reorder)

#: Seconds a test (or a parametrized family: a node id prefix) took on the reference machine, from `pytest -n 2
#: --durations=40` (2026-11-28, issue 46; a test below the 40 slowest, 1.6 s and less, at 1.5). Only the order
#: comes from them: the longest run first, so that the two workers finish together instead of one starting a long
#: test while the other has nothing left.
EXPECTED_SECONDS = {
    "tests/test_user_grids.py::test_workflow_builds_a_report_for_each_users_grid": 1.5,  # reads what users_workflow kept
    "tests/test_user_grids.py::test_any_users_grid_gives_the_whole_report": 45,  # alone, with the drafts
    "tests/test_cluster.py::": 1.5,  # its scenario runs in the background from the start (scenario.py)
    "tests/test_report.py::test_workflow_builds_the_report_and_follows_its_settings": 25,
    "tests/test_workflow.py::test_tiny_study_end_to_end": 17,
    "tests/test_random.py::test_adding_a_seed_renders_only_it": 14,
    "tests/test_workflow.py::test_unwritable_results_and_corrupt_sweeps": 11,
    "tests/test_workflow.py::test_killed_run_reruns_to_the_same_table": 11,
    "tests/test_random.py::test_fast_renderer_matches_the_reference_on_a_random_tile": 10,
    "tests/test_workflow.py::test_broken_osmesa_stops_before_any_job": 7,
    "tests/test_report.py::test_optional_parts_follow_the_config_not_the_files": 7,
    "tests/test_workflow.py::test_a_second_run_stops_at_once": 6,
    "tests/test_config.py::test_validation_accepts_exactly_the_valid_grids": 1.5,
    "tests/test_random.py::test_the_random_parts_of_the_report_follow_surface_kind": 3,
    "tests/test_platforms.py::test_osmesa_and_egl_give_the_same_numbers_for_every_method": 3,
    "tests/test_user_grids.py::test_every_grid_validates_and_its_followers": 1.5,
    "tests/test_rendering.py::test_averaged_normals_shading_is_wrong_where_flat_is_right": 4,
    "tests/test_benchmark.py::": 1.5,
    "tests/test_packaging.py::test_the_package_runs_from_the_wheel_alone": 2,
    "tests/test_renderer_validation.py::": 8,
    "tests/test_implicit.py::": 6,
    "tests/test_implicit_table.py::": 2,
    "tests/test_random.py::test_random_accuracy_leaves_out": 2,
    "tests/test_random.py::test_a_one_cell_tile_without_spread": 6,
    "tests/test_random.py::test_tile_convergence_reads_every_statistic": 3,
    "tests/test_lighting_against_reference.py::": 2,
    "tests/test_random.py::test_ensemble_statistics_on_a_tiny_grid": 2,
    "tests/test_study_table.py::test_the_study_is_written_a_sweep_at_a_time": 1.5,
    "tests/test_workflow.py::": 6,
}

#: Tests that share an expensive module or session fixture (by node id prefix, the first match): each group is one
#: unit of xdist's work, run on one worker, which builds the fixture once (spread over both, a module fixture was
#: built twice: test_findings' 'tables' 14.7 + 14.6 s, test_analysis' 'exact_study' 11.7 + 11.5 s; and a worker
#: reaching the session's 'built' report second waited 27.5 s on the other's build). None: a test of its own.
GROUPS = (
    ("tests/test_workflow.py::test_tiny_study_end_to_end", "tiny_run"),
    ("tests/test_workflow.py::test_unwritable_results", "tiny_run"),
    ("tests/test_workflow.py::test_broken_osmesa", "tiny_run"),
    ("tests/test_report.py::test_workflow_builds_the_report_and_follows_its_settings", "users_workflow"),
    ("tests/test_user_grids.py::test_workflow_builds_a_report_for_each_users_grid", "users_workflow"),
    ("tests/test_report.py::test_optional_parts_follow_the_config_not_the_files", None),
    ("tests/test_report.py::", "built"),
    ("tests/test_report_tables.py::", "built"),
    ("tests/test_findings.py::", "findings"),
    ("tests/test_analysis.py::", "analysis"),
    ("tests/test_explorer.py::", "explorer"),
    ("tests/test_stability.py::", "stability"),
    ("tests/test_lighting_against_reference.py::", "lighting"),
    ("tests/test_packaging.py::", "packaging"),
)
#: The seconds of a group's fixtures (its place in the order: their tests' seconds and these).
FIXTURE_SECONDS = {"users_workflow": 60, "built": 12, "tiny_run": 5, "explorer": 6.5, "analysis": 3, "findings": 2,
                   "stability": 2, "lighting": 3.5, "packaging": 2}


def _expected(nodeid: str) -> float:
    return max((s for prefix, s in EXPECTED_SECONDS.items() if nodeid.startswith(prefix)), default=0.0)


def work_unit(nodeid: str) -> str:
    """The unit of xdist's work a test belongs to: its group (:data:`GROUPS`), else the test itself."""
    group = next((g for prefix, g in GROUPS if nodeid.startswith(prefix)), None)
    return group or nodeid


def pytest_collection_modifyitems(config, items):
    """The longest work first (a group placed by its sum), each group's tests together."""
    units: dict[str, float] = {}
    for item in items:
        unit = work_unit(item.nodeid)
        units[unit] = units.get(unit, FIXTURE_SECONDS.get(unit, 0.0)) + _expected(item.nodeid)
    order = {item.nodeid: n for n, item in enumerate(items)}
    items.sort(key=lambda item: (-units[work_unit(item.nodeid)], work_unit(item.nodeid), order[item.nodeid]))


def pytest_xdist_make_scheduler(config, log):
    """With -n (and xdist's default --dist load): one unit of work a group or test (:func:`work_unit`), handed out in
    the collection's order (longest first). xdist's own --dist loadgroup cannot be used: pytest 9 ignores the
    group suffix pytest-xdist 3.8 writes into the node ids, so its groups were silently spread over both workers."""
    if config.getvalue("dist") != "load":
        return None
    from xdist.scheduler import LoadScopeScheduling

    class Units(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return work_unit(nodeid)

    return Units(config, log)


# ---------------------------------------------------------------------------
# the cluster test's scenario, in the background (tests/cluster/scenario.py)

_RUN_ID = pytest.StashKey[str]()


def _cluster_directory(config) -> Path:
    """Where this session's cluster scenario runs: one directory for all of xdist's workers (their run's id)."""
    run_id = getattr(config, "workerinput", {}).get("testrunuid")
    if run_id is None:
        run_id = config.stash.setdefault(_RUN_ID, uuid.uuid4().hex)
    return Path(tempfile.gettempdir()) / f"roughlight-cluster-{run_id}"


@pytest.hookimpl(tryfirst=True)
def pytest_collection_finish(session):
    """Start the cluster scenario as soon as the session holds its test (on one worker: gw0, or the only process),
    so that its minute of waiting on SLURM passes while the other tests run."""
    config = session.config
    if config.option.collectonly or getattr(config, "workerinput", {}).get("workerid", "gw0") != "gw0":
        return
    if scenario.available() and any(item.nodeid.startswith("tests/test_cluster.py::") for item in session.items):
        scenario.launch(_cluster_directory(config))


def pytest_sessionfinish(session, exitstatus):
    """A scenario this process started ends before it does (its SLURM daemons torn down): waited for, or stopped
    at once when the session was interrupted."""
    scenario.finish(interrupted=exitstatus == pytest.ExitCode.INTERRUPTED)


@pytest.fixture
def cluster_scenario(request) -> Path:
    """The directory of this session's cluster scenario (started at collection, or now if it was not)."""
    return _cluster_directory(request.config)
