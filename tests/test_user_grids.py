"""A user's grid edit always gives a complete study and report (issue 22).

Users edit ``grid`` (and the ``sweep`` steps) and rerun, leaving every other key at its default. The keys that
depend on the grid (``surface.random_grid``, ``report.table_aspects``, ``report.table_incidence``) follow it when
left unset; set outside the grid, they stop the run before any work. The whole report is built here for grids
drawn by hypothesis and for the issue's first grid (in one process: :mod:`tests.report_chain`), and by snakemake for
its second (``test_workflow_builds_a_report_for_each_users_grid``).
"""

from __future__ import annotations

import json
import math
import re
from html.parser import HTMLParser

import pandas as pd
import pytest
from hypothesis import HealthCheck, example, given, seed, settings
from hypothesis import strategies as st

from roughlight.study import config as rl_config
from roughlight.surfaces.surface import aspect_label

from .report_chain import SCHEMA, resolved, whole_report
from .users_workflow import CLAIM_TILES, DEFAULT, GRIDS, ISSUE_GRIDS, MEASUREMENTS, SEEDS, grid_config, kept

S32 = math.sqrt(3.0) / 2.0
SECTIONS = ("study", "tables", "specular", "diffuse", "lobes", "glm", "models", "implicit", "export", "random",
            "light-transport", "stability", "provenance")


#: The random tiles' cells a side in the in-process whole reports (the hypothesis test): their size has tests of its
#: own too (the tile-size benchmark, tests/test_random.py), and the snakemake test below builds its grids with the
#: shipped 4. Two cells a side took the largest example from 15.8-18.9 s to 11.6-12.5 s (issue 46).
DRAWN_CELLS = 2


def user_config(grid: dict, sweep: dict | None = None) -> dict:
    """config/config.yaml with the user's edits of grid (and sweep), as a user's --configfile merges them, and
    :data:`SEEDS` study tiles and the claim's tiles of :data:`CLAIM_TILES` a random kind."""
    cfg = json.loads(json.dumps(DEFAULT))
    cfg["surface"]["seeds"] = SEEDS
    cfg["claims"].update(CLAIM_TILES)
    cfg["grid"].update(grid)
    if sweep:
        cfg["sweep"].update(sweep)
    return cfg


# ---------------------------------------------------------------------------
# the keys that follow the grid


def test_the_default_grid_keeps_the_default_values():
    cfg, notes = resolved(DEFAULT)
    assert cfg["surface"]["random_grid"] == {"truncation": [0.5, 1.0], "aspect": [0.5, 1.0]}
    assert cfg["report"]["table_aspects"] == [1.0, S32] and cfg["report"]["table_incidence"] == 30.0
    assert len(notes) == 4 and all(note.endswith("(as by default)") for note in notes)


def test_unset_keys_take_the_nearest_grid_values_and_say_so():
    cfg, notes = resolved(user_config({"truncation": [0.3, 1.0], "aspect": [0.6], "incidence": [20, 45]}))
    assert cfg["surface"]["random_grid"] == {"truncation": [0.3, 1.0], "aspect": [0.6]}
    assert cfg["report"]["table_aspects"] == [0.6]  # 1 and sqrt(3)/2 both nearest to 0.6: listed once
    assert cfg["report"]["table_incidence"] == 20.0  # nearest to 30 (a tie goes to the first listed)
    assert "report.table_aspects is not set: it follows grid.aspect, 0.6 (the grid values nearest to the default " \
           "1, 0.866025)" in notes
    assert any(note.startswith("surface.random_grid.truncation is not set: it follows grid.truncation, 0.3, 1")
               for note in notes)


def test_without_random_kinds_the_random_grid_is_not_mentioned():
    cfg, notes = resolved({"grid": {"truncation": [0.2], "aspect": [0.4]}})
    assert rl_config.random_surfaces(cfg) == []
    assert [n.split(" ")[0] for n in notes] == ["report.table_aspects", "report.table_incidence"]


@pytest.mark.parametrize("key, value, axis", [
    (("surface", "random_grid", "truncation"), [0.5], "grid.truncation"),
    (("surface", "random_grid", "aspect"), [0.25], "grid.aspect"),
    (("report", "table_aspects"), [S32], "grid.aspect"),
    (("report", "table_incidence"), 30, "grid.incidence"),
])
def test_a_value_set_outside_the_grid_stops_before_any_work(key, value, axis):
    cfg = user_config({"truncation": [0.3, 1.0], "aspect": [0.6], "incidence": [45]})
    parent = cfg
    for part in key[:-1]:
        parent = parent.setdefault(part, {})
    parent[key[-1]] = value
    name = r"\.".join(key)
    with pytest.raises(rl_config.ConfigError, match=rf"{name} = .* must be values of {axis}"):
        rl_config.validate_config(cfg, SCHEMA)


@pytest.mark.parametrize("kind", ["random_pyramids", ["random_heightfield"], ["pyramids"], "pyramids"])
def test_the_regular_grid_is_measured_whether_listed_or_not(kind):
    cfg, _ = resolved({"grid": {"truncation": [0.5, 1.0], "aspect": [1.0]}, "surface": {"kind": kind}})
    kinds = rl_config.kinds(cfg)
    assert kinds[0] == "pyramids"
    listed = {kind} if isinstance(kind, str) else set(kind)
    assert set(kinds) == listed | {"pyramids"}


values = st.lists(st.sampled_from([0.0, 0.1, 0.25, 0.3, 0.5, 0.6, 0.75, 0.9, 1.0]), min_size=1, max_size=5,
                  unique=True)
aspects = st.lists(st.sampled_from([0.0, 0.1, 0.3, 0.5, 0.6, S32, 0.9, 1.0, 1.5, 3.0]), min_size=1, max_size=5,
                   unique=True)
incidences = st.lists(st.sampled_from([0, 5, 10, 20, 30, 45, 60, 75, 89, 90]), min_size=1, max_size=3, unique=True)


@settings(max_examples=60, deadline=None)
@given(truncation=values, aspect=aspects, incidence=incidences)
def test_every_grid_validates_and_its_followers_are_the_nearest_grid_values(truncation, aspect, incidence):
    cfg, notes = resolved(user_config({"truncation": truncation, "aspect": aspect, "incidence": incidence}))
    for values_, preferred in ((cfg["surface"]["random_grid"]["truncation"], [0.5, 1.0]),
                               (cfg["surface"]["random_grid"]["aspect"], [0.5, 1.0]),
                               (cfg["report"]["table_aspects"], [1.0, S32]),
                               ([cfg["report"]["table_incidence"]], [30.0])):
        grid = truncation if values_ is cfg["surface"]["random_grid"]["truncation"] else (
            incidence if preferred == [30.0] else aspect)
        assert set(values_) <= set(map(float, grid)) and len(values_) == len(set(values_))
        for want in preferred:  # each preferred value has its nearest grid value among them
            assert min(abs(v - want) for v in values_) == min(abs(float(g) - want) for g in grid)
    assert len(notes) == 4
    assert rl_config.random_surfaces(cfg)  # the default kinds: the random ensembles always have grid points


# ---------------------------------------------------------------------------
# the whole report for any grid


class _Page(HTMLParser):
    """The page's element ids and its text, section by section (each ``h2``'s id starts one)."""

    def __init__(self):
        super().__init__()
        self.ids, self.text, self.sections, self._section = set(), [], {}, "top"

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if "id" in attrs:
            self.ids.add(attrs["id"])
            if tag == "h2":
                self._section = attrs["id"]

    def handle_data(self, data):
        self.text.append(data)
        self.sections.setdefault(self._section, []).append(data)


def check_complete(html: str, followed: list[str]) -> str:
    """Every section is on the page, the followed keys are named, and nothing printed as nan. Returns the text."""
    page = _Page()
    page.feed(html)
    text = " ".join(page.text)
    missing = [s for s in SECTIONS if s not in page.ids]
    assert not missing, f"sections missing from the page: {missing}"
    assert "followed" in page.ids and all(line in text for line in followed)
    assert "could not be drawn for this study" not in text  # the figures' last-resort placeholder never fires
    for section, parts in page.sections.items():  # a value that cannot be computed says why, not "nan"
        if section != "random":  # the random section's own rewrite is issue 24's
            found = re.findall(r".{0,80}\bnan\b.{0,40}", " ".join(parts))
            assert not found, f"section {section} prints nan: {found[:3]}"
    return text


coarse = st.fixed_dictionaries({"elevation_step": st.sampled_from([15, 30, 45, 90, 180]),
                                "azimuth_step": st.sampled_from([45, 60, 90, 180])})


#: A user's grid and coarse sweep, as hypothesis draws them for the whole report.
user_grids = {"truncation": st.lists(st.sampled_from([0.0, 0.2, 0.5, 0.8, 1.0]), min_size=1, max_size=3, unique=True),
              "aspect": st.lists(st.sampled_from([0.0, 0.4, S32, 0.9, 1.0, 2.0]), min_size=1, max_size=2, unique=True),
              "incidence": st.lists(st.sampled_from([0, 20, 30, 60, 90]), min_size=1, max_size=2, unique=True),
              "sweep": coarse}

#: The seed of the six drawn grids, fixed. With ``derandomize`` alone hypothesis seeds the draw from the test's source,
#: so any edit (a docstring, an example) drew six other grids, at another cost (issue 46). This is the seed
#: ``derandomize`` gave the test's source until then, so the grids are those the suite always drew (:data:`DRAWN`).
DRAW_SEED = int("18155c9dc690637aac8d84efabcc2d4715337a2821ab03b2c157f0b9956936263501118db576fa6d1a3e8d431a3293bd", 16)
#: The grids :data:`DRAW_SEED` draws (truncation, aspect, incidence, sweep steps: elevation, azimuth).
DRAWN = [([0.0], [0.0], [0], (15, 45)), ([0.2, 0.0, 0.8], [0.4], [60, 0], (15, 180)),
         ([1.0], [2.0, S32], [90], (180, 60)), ([0.0, 1.0], [2.0], [20], (180, 45)),
         ([0.2], [2.0], [30, 60], (45, 180)), ([0.2, 1.0], [0.9, 2.0], [60], (45, 60))]
WHOLE_REPORT = settings(max_examples=6, deadline=None,
                        suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


def test_the_whole_report_draws_the_same_grids():
    """The drawn grids stay those of :data:`DRAWN` (a new hypothesis could draw others: say so, and their cost)."""
    drawn = []

    @seed(DRAW_SEED)
    @WHOLE_REPORT
    @given(**user_grids)
    def record(truncation, aspect, incidence, sweep):
        drawn.append((truncation, aspect, incidence, (sweep["elevation_step"], sweep["azimuth_step"])))

    record()
    assert drawn == DRAWN


@seed(DRAW_SEED)
@WHOLE_REPORT
@given(**user_grids)
# the issue's first grid (tests/users_workflow.py's ISSUE_GRIDS[0]); its second is built end to end by snakemake
# (tests/users_workflow.py, checked below)
@example(truncation=ISSUE_GRIDS[0]["grid"]["truncation"], aspect=ISSUE_GRIDS[0]["grid"]["aspect"], incidence=[30],
         sweep=ISSUE_GRIDS[0]["sweep"])
@example(truncation=[0.5], aspect=[1.0], incidence=[45], sweep={"elevation_step": 45, "azimuth_step": 180})
def test_any_users_grid_gives_the_whole_report(tmp_path_factory, truncation, aspect, incidence, sweep):
    user = user_config({"truncation": truncation, "aspect": aspect, "incidence": incidence}, sweep)
    user["surface"]["cells"] = DRAWN_CELLS
    html, cfg, followed, study = whole_report(user, tmp_path_factory.mktemp("grid"))
    text = check_complete(html, followed)
    assert set(study["kind"]) == {"pyramids", "random_pyramids", "random_heightfield"}
    # Tables 1-2 for the table aspects that followed the grid, or a sentence on why there are none
    shown = set(re.findall(r'class="thesis-table"[^>]*data-aspect="([^"]+)"', html))
    assert shown <= {aspect_label(a) for a in cfg["report"]["table_aspects"]}
    assert shown or "Tables 1–2 could not be computed" in text


# ---------------------------------------------------------------------------
# the same through snakemake, as a user runs it


@pytest.mark.slow
def test_workflow_builds_a_report_for_each_users_grid(users_workflow):
    """The issue's grid run by snakemake (tests/users_workflow.py's GRIDS, one after the other in one directory:
    its second; the first is an example of the in-process test above), edited into a user's --configfile over
    config/config.yaml as shipped (a random kind, every report section; :data:`SEEDS` seeds a kind, the measurements
    at :data:`MEASUREMENTS`' plan): each run ends with the whole report."""
    for k, grid in enumerate(GRIDS):
        out = kept(users_workflow, k)
        log = (out / "snakemake.log").read_text()
        cfg, followed = grid_config(k)
        for line in followed:  # the log says which values were used
            assert f"config: {line}" in log
        html = (out / "report.html").read_text(encoding="utf-8")
        check_complete(html, followed)
        study = pd.read_parquet(out / "study.parquet")
        assert sorted(set(study.loc[study["kind"] == "pyramids", "truncation"])) == grid["grid"]["truncation"]
        tables = pd.read_csv(out / "thesis_tables.csv")
        assert set(tables.loc[tables["source"] == "ours", "aspect"]) == set(cfg["report"]["table_aspects"])
        # the export does not follow the grid: export.surfaces' own surface, whatever the grid
        exported = pd.read_csv(out / "export_summary.csv")
        assert set(exported["method"]) == {"implicit_table", "mitsuba_measured"} and (exported["views"] == 20).all()
        assert 'id="fig-export"' in html and "truncation 0.5, aspect 1: the share table" in html
    # the measured sections at the users' plan, and only there
    assert sorted(p.name for p in (users_workflow / "results" / "benchmarks").iterdir()) == [MEASUREMENTS["plan"]]


def test_the_chains_draft_draws_every_artist(tmp_path):
    """The in-process chain's drafts paint no pixel but draw every artist: text laid out with its font (mathtext
    parsed) and images through their colour maps, so a figure that would fail in the workflow fails here too."""
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.colors import LogNorm

    from .report_chain import DRAFT_PNG, draft

    fig, ax = plt.subplots()
    ax.imshow(np.arange(1.0, 7.0).reshape(2, 3), norm=LogNorm())
    ax.set_title(r"$\sqrt{3}/2$")
    assert draft(fig, tmp_path / "ok.png") == str(tmp_path / "ok.png")
    assert (tmp_path / "ok.png").read_bytes() == DRAFT_PNG
    fig, ax = plt.subplots()
    ax.set_title(r"$\notacommand{3}$")  # Agg raises on it when it lays the title out
    with pytest.raises(ValueError):
        draft(fig, tmp_path / "mathtext.png")
    fig, ax = plt.subplots()
    ax.imshow(np.array([[-1.0, 0.0], [0.0, -2.0]]), norm=LogNorm(vmin=-1.0, vmax=1.0))  # invalid on drawing
    with pytest.raises(ValueError):
        draft(fig, tmp_path / "norm.png")
    assert not (tmp_path / "mathtext.png").exists() and not (tmp_path / "norm.png").exists()
