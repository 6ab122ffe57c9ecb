"""The package's architecture is its tree: one subpackage a stage, each importing only the stages below it,
no import circle between modules, and modules and functions short enough to read at once."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "roughlight"
#: the stages, bottom first, in the order the data flows
LAYERS = ["surfaces", "render", "study", "analysis", "measurements", "report"]
#: modules at the package's root that every stage may use (atomic writes)
SHARED = {"atomic", "__init__"}
MAX_MODULE_LINES = 600
MAX_FUNCTION_LINES = 60


def modules(root: Path = PACKAGE) -> dict[str, Path]:
    """Dotted module name under roughlight (``render.periodic``) -> file."""
    return {".".join(p.relative_to(root).with_suffix("").parts): p for p in sorted(root.rglob("*.py"))}


def imported(name: str, path: Path, root: Path = PACKAGE) -> set[str]:
    """The roughlight modules ``name`` imports, at its top or inside functions, as dotted names under roughlight."""
    package = name.split(".")[:-1]
    known = modules(root)
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - node.level + 1]
                target = base + (node.module.split(".") if node.module else [])
            elif node.module and node.module.split(".")[0] == "roughlight":
                target = node.module.split(".")[1:]
            else:
                continue
            dotted = ".".join(target)
            for alias in node.names:  # `from . import x` names a module
                candidate = f"{dotted}.{alias.name}" if dotted else alias.name
                out.add(candidate if candidate in known else dotted)
        elif isinstance(node, ast.Import):
            out |= {a.name.split(".", 1)[1] for a in node.names if a.name.startswith("roughlight.")}
    return {m for m in out if m in known or f"{m}.__init__" in known} - {name}


def stage(module: str) -> str:
    return module.split(".")[0]


def test_every_module_lives_in_a_stage():
    loose = [m for m in modules() if "." not in m and m not in SHARED]
    assert not loose, f"modules outside the stages: {loose}"
    assert {stage(m) for m in modules() if "." in m} == set(LAYERS)


@pytest.mark.parametrize("module", sorted(m for m in modules() if "." in m))
def test_a_stage_imports_only_the_stages_below_it(module):
    mine = LAYERS.index(stage(module))
    upward = sorted(m for m in imported(module, modules()[module])
                    if stage(m) in LAYERS and LAYERS.index(stage(m)) > mine)
    assert not upward, f"{module} ({stage(module)}) imports stages above it: {upward}"


#: render's rooms (render/README.md): a folder a method family, and the ground they stand on (the lighting equation in
#: numpy, the detector's orbit); each room imports only the rooms named here (and itself); the entry points
#: (``methods``, the registry, and ``pictures``) reach every method
RENDER_ROOMS = {"ground": set(), "gl": {"ground"}, "exact": {"ground"}, "fast": {"ground", "gl", "exact"},
                "naive": {"ground", "gl"}, "implicit": {"ground", "gl", "exact"}, "mitsuba": {"ground"}}
RENDER_GROUND = {"render", "render.__init__", "render.shading", "render.views", "render.sweep", "render.native"}


def render_room(module: str) -> str:
    """The room of a module of render/: its folder, ``ground`` or ``entry``."""
    parts = module.split(".")
    if len(parts) > 2:
        return parts[1]
    return "ground" if module in RENDER_GROUND else "entry"


@pytest.mark.parametrize("module", sorted(m for m in modules() if stage(m) == "render"))
def test_a_render_room_imports_only_the_rooms_below_it(module):
    room = render_room(module)
    if room == "entry":
        return
    assert room in RENDER_ROOMS, f"{module}: render/{room}/ is not a room of render/README.md's map"
    rooms = {render_room(m) for m in imported(module, modules()[module]) if stage(m) == "render"}
    outside = sorted(rooms - RENDER_ROOMS[room] - {room})
    assert not outside, f"{module} (render/{room}) imports the rooms {outside}"


def test_the_room_rule_sees_a_method_reaching_into_another(tmp_path):
    """The exact reference reaching into the fast renderer is outside its rooms; the fast renderer using the exact
    reference is not."""
    for name in ("render/exact/fake.py", "render/fast/periodic.py", "render/shading.py", "render/exact/clipping.py"):
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text("")
    fake = tmp_path / "render" / "exact" / "fake.py"
    fake.write_text("from ..fast.periodic import fast_sweep\nfrom ..shading import Lighting\n")
    rooms = {render_room(m) for m in imported("render.exact.fake", fake, root=tmp_path)}
    assert rooms == {"fast", "ground"} and rooms - RENDER_ROOMS["exact"] - {"exact"} == {"fast"}
    assert {"exact", "gl", "ground"} <= RENDER_ROOMS["fast"]


def inner_reaches(name: str, path: Path, root: Path = PACKAGE) -> list[str]:
    """The modules inside a room of render/ (``render.fast.periodic``: a method's folder, or ``gl/``) that
    ``path`` (module ``name``; a workflow script: any name outside render) imports: outside render/, a room is
    reached only through its face, the folder's ``__init__`` (render/README.md)."""
    return sorted(m for m in imported(name, path, root)
                  if stage(m) == "render" and len(m.split(".")) > 2 and not m.endswith(".__init__"))


def test_nothing_outside_render_reaches_into_a_rooms_modules():
    """The study, the analysis, the measurements, the report and the workflow's scripts take a method's names from
    its folder's face (``roughlight.render.fast``, ...) or from the registry (``roughlight.render.methods``),
    never from the modules inside the folder."""
    scripts = PACKAGE.parents[1] / "workflow" / "scripts"
    reaches = {m: inner_reaches(m, p) for m, p in modules().items() if stage(m) != "render"}
    reaches.update({f"workflow.scripts.{p.stem}": inner_reaches(f"scripts.{p.stem}", p) for p in scripts.glob("*.py")})
    reaches = {m: r for m, r in reaches.items() if r}
    assert not reaches, f"modules reaching into render's rooms: {reaches}"


def test_the_face_check_sees_a_reach_into_a_room(tmp_path):
    for name in ("render/fast/__init__.py", "render/fast/periodic.py", "analysis/fake.py", "analysis/__init__.py"):
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text("")
    fake = tmp_path / "analysis" / "fake.py"
    fake.write_text("from ..render.fast.periodic import fast_sweep\n")
    assert inner_reaches("analysis.fake", fake, root=tmp_path) == ["render.fast.periodic"]
    fake.write_text("from ..render.fast import fast_sweep\n")
    assert inner_reaches("analysis.fake", fake, root=tmp_path) == []


def settings_made_outside_the_registry(path: Path) -> list[str]:
    """Where ``path`` makes a method's settings itself: a call of a render room's settings type
    (``FastSettings(...)``, ``NaiveSettings(...)``, ``TileSettings(...)``, ...) or of its ``from_config``."""
    from roughlight.render import methods

    kinds = {m.settings_type.split(":")[1] for m in methods.METHODS.values()} | {"TileSettings"}
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Call):
            func = node.func
            name = func.id if isinstance(func, ast.Name) else func.attr if isinstance(func, ast.Attribute) else ""
            owner = func.value.id if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) else ""
            if name in kinds or (name == "from_config" and owner in kinds):
                found.append(f"{path.name}:{node.lineno}")
    return found


def test_a_methods_settings_are_made_through_the_registry():
    """Outside render/, a method's settings come from the registry (``methods.settings(name, knobs)``), which
    checks them against the method's name, never from the settings type itself."""
    scripts = PACKAGE.parents[1] / "workflow" / "scripts"
    paths = [p for m, p in modules().items() if stage(m) != "render"] + sorted(scripts.glob("*.py"))
    made = [where for path in paths for where in settings_made_outside_the_registry(path)]
    assert not made, f"settings made outside the registry: {made}"


def test_the_settings_check_sees_a_settings_type_called(tmp_path):
    fake = tmp_path / "fake.py"
    fake.write_text("from roughlight.render.fast import FastSettings\na = FastSettings(pixels_per_period=8)\n"
                    "b = FastSettings.from_config({})\nc = methods.settings('fast', {})\n")
    assert settings_made_outside_the_registry(fake) == ["fake.py:2", "fake.py:3"]


def test_every_name_of_a_rooms_face_is_there():
    """Each face names only what its modules hold, and loads no OpenGL until a name is taken."""
    import importlib
    import subprocess
    import sys

    for room in ("fast", "exact", "naive", "implicit", "gl", "mitsuba"):
        face = importlib.import_module(f"roughlight.render.{room}")
        for name, module in face.FACE.items():
            assert hasattr(importlib.import_module(f"roughlight.render.{room}.{module}"), name), (room, name)
    probe = ("import sys; from roughlight.render.fast import FastSettings; from roughlight.render.exact import "
             "LitScene; import roughlight.render.naive, roughlight.render.gl; "
             "from roughlight.render.mitsuba import MitsubaSettings, check_mitsuba; check_mitsuba(); "
             "print('OpenGL' in sys.modules, 'mitsuba' in sys.modules or 'drjit' in sys.modules)")
    assert subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          check=True).stdout == "False False\n"


def private_reaches(path: Path) -> list[str]:
    """Where ``path`` takes another roughlight module's ``_private`` name: ``from x import _name`` of a roughlight
    module (relative or absolute), or ``module._name`` of a roughlight module it imported."""
    tree = ast.parse(path.read_text())
    modules_seen, out = set(), []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith("roughlight")):
            for alias in node.names:
                if alias.name.startswith("_") and not alias.name.startswith("__"):
                    out.append(f"{path.name}:{node.lineno}: from {'.' * node.level}{node.module or ''} import {alias.name}")
                modules_seen.add(alias.asname or alias.name)
        elif isinstance(node, ast.Import):
            modules_seen |= {a.asname or a.name.split(".")[0] for a in node.names if a.name.startswith("roughlight")}
    for node in ast.walk(tree):
        if (isinstance(node, ast.Attribute) and node.attr.startswith("_") and not node.attr.startswith("__")
                and isinstance(node.value, ast.Name) and node.value.id in modules_seen):
            out.append(f"{path.name}:{node.lineno}: {node.value.id}.{node.attr}")
    return out


def test_no_module_reaches_into_anothers_private_names():
    """Public seams only: in the package, its workflow scripts and its tests, no module takes another's ``_name``."""
    root = PACKAGE.parents[1]
    paths = [*PACKAGE.rglob("*.py"), *(root / "tests").glob("*.py"), *(root / "workflow" / "scripts").glob("*.py")]
    reaches = [r for p in sorted(paths) for r in private_reaches(p)]
    assert not reaches, "private names taken from another module:\n" + "\n".join(reaches)


def test_the_seam_check_sees_a_private_reach(tmp_path):
    fake = tmp_path / "fake.py"
    fake.write_text("from roughlight.render.fast import shares\nfrom ..x import _hidden\n\nshares._front(1)\n")
    assert private_reaches(fake) == ["fake.py:2: from ..x import _hidden", "fake.py:4: shares._front"]


def test_no_import_circle():
    graph = {m: imported(m, p) for m, p in modules().items()}
    state: dict[str, int] = {}

    def visit(m, trail):
        state[m] = 1
        for n in sorted(graph.get(m, ())):
            if state.get(n) == 1:
                raise AssertionError("import circle: " + " -> ".join(trail[trail.index(n):] + [n]))
            if n not in state:
                visit(n, trail + [n])
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m, [m])


def test_the_checker_sees_an_upward_import(tmp_path):
    """The import reader finds an upward import at the top and one inside a function."""
    fake = tmp_path / "render" / "fake.py"
    for name in ("render/fake.py", "report/page.py", "study/config.py"):
        (tmp_path / name).parent.mkdir(exist_ok=True)
        (tmp_path / name).write_text("")
    fake.write_text("from ..report import page\n\ndef f():\n    from ..study.config import label\n")
    assert imported("render.fake", fake, root=tmp_path) == {"report.page", "study.config"}
@pytest.mark.parametrize("module", sorted(modules()))
def test_modules_and_functions_are_short(module):
    path = modules()[module]
    text = path.read_text()
    assert len(text.splitlines()) <= MAX_MODULE_LINES, f"{module}: {len(text.splitlines())} lines"
    long = [(n.name, n.end_lineno - n.lineno + 1) for n in ast.walk(ast.parse(text))
            if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)) and n.end_lineno - n.lineno + 1 > MAX_FUNCTION_LINES]
    assert not long, f"{module}: functions over {MAX_FUNCTION_LINES} lines: {long}"
