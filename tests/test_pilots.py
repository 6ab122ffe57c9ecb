"""The claim's registered pilots (roughlight.study.pilots): which ensembles' pilots a run renders, and the readings
it plans from."""
import copy

import numpy as np
import pandas as pd
import pytest
import yaml

from roughlight.atomic import write_frame
from roughlight.study import config as rl_config
from roughlight.study import pilots as P
from roughlight.study import plan

from .conftest import REPO

SCHEMA = REPO / "workflow" / "schemas" / "config.schema.yaml"


def shipped():
    with open(REPO / "config" / "config.yaml") as fh:
        return rl_config.validate_config(yaml.safe_load(fh), SCHEMA)


def readings(config, value=1.0, registered_key=None):
    """A readings table for every claim ensemble of ``config``, each reading ``value`` (its key, or
    ``registered_key`` for all)."""
    rows = [[kind, t, a, i, registered_key or key, name, value]
            for kind, t, a, i, key in P.pilot_keys(config) for name in ("back_contrast", "seeds")]
    return pd.DataFrame(rows, columns=P.COLUMNS)


def test_a_pilot_key_names_what_the_pilots_are_measured_with():
    config = shipped()
    key = P.pilot_key(config, "random_heightfield", 1.0, 1.0, 30.0)
    assert len(key) == 16 and key == P.pilot_key(copy.deepcopy(config), "random_heightfield", 1.0, 1.0, 30.0)
    assert key != P.pilot_key(config, "random_pyramids", 1.0, 1.0, 30.0)
    assert key != P.pilot_key(config, "random_heightfield", 1.0, 1.0, 40.0)
    for section, name, value in (("claims", "cells", 4), ("claims", "pilots", 6), ("material", "shininess", 32),
                                 ("sweep", "azimuth_step", 10), ("surface", "spread", {"apex": 0.4})):
        changed = copy.deepcopy(config)
        changed[section][name] = value if not isinstance(value, dict) else {**changed[section][name], **value}
        assert P.pilot_key(changed, "random_heightfield", 1.0, 1.0, 30.0) != key, (section, name)
    # the tested seeds are not the pilots' settings
    changed = copy.deepcopy(config)
    changed["claims"]["seeds"] = 3
    assert P.pilot_key(changed, "random_heightfield", 1.0, 1.0, 30.0) == key


def test_the_shipped_grid_renders_no_pilot_and_its_registered_readings_cover_every_ensemble():
    config = shipped()
    assert config["claims"]["registered_pilots"] == "config/claim_pilots.csv"
    assert P.rendered_folders(config) == []
    table = P.registered(config)
    keys = {(kind, t, a, i): key for kind, t, a, i, key in P.pilot_keys(config)}
    combined = P.combined_readings(table.iloc[:0], table, keys)
    assert set(combined["source"]) == {"registered"} and len(combined) == len(table)
    assert (combined.groupby(P.KEY_COLUMNS[:-1])["reading"].count() > 10).all()
    seeds = combined[combined["reading"] == "seeds"]["value"]
    assert (seeds == config["claims"]["pilots"]).all()


def test_only_ensembles_registered_under_their_own_settings_skip_their_pilots(tmp_path, monkeypatch):
    config = shipped()
    monkeypatch.chdir(tmp_path)  # the registered file is relative to the workflow's directory
    everything = plan.ensemble_folders(config, "pilots")
    table = readings(config)
    keys = {(kind, t, a, i): key for kind, t, a, i, key in P.pilot_keys(config)}
    first = table["truncation"].eq(table["truncation"].iloc[0]) & table["aspect"].eq(table["aspect"].iloc[0])
    table.loc[first, "key"] = "0" * 16  # those ensembles were registered with other settings
    (tmp_path / "config").mkdir()
    write_frame(table, tmp_path / "config" / "pilots.csv")
    config["claims"]["registered_pilots"] = "config/pilots.csv"
    rendered = P.rendered_folders(config)
    stale = {(kind, t, a) for kind, t, a in table.loc[first, ["kind", "truncation", "aspect"]].itertuples(
        index=False, name=None)}
    assert len(stale) == 2 and len(rendered) == len(stale) < len(everything)
    assert all(plan.ensemble_folder(k, t, a, 30, plan.claim_folder("pilots")) in rendered for k, t, a in stale)
    # those two are rendered, the rest registered; an ensemble with neither is named
    new = table.loc[first].assign(key=[keys[(k, t, a, i)] for k, t, a, i in table.loc[first, P.KEY_COLUMNS[:-1]]
                                       .itertuples(index=False, name=None)], value=2.0)
    combined = P.combined_readings(new, P.registered(config), keys)
    assert (combined.groupby("source").size() == pd.Series({"registered": 12, "rendered": 4})).all()
    assert combined.loc[combined["source"] == "rendered", "value"].eq(2.0).all()
    with pytest.raises(ValueError, match="no pilot readings for 2 ensembles"):
        P.combined_readings(new.iloc[:0], P.registered(config), keys)
    # a config naming a missing or foreign file is refused before any job, by name
    config["claims"]["registered_pilots"] = "config/none.csv"
    with pytest.raises(rl_config.ConfigError, match="claims.registered_pilots: config/none.csv does not exist"):
        rl_config.validate_config(config, SCHEMA)
    pd.DataFrame({"kind": ["x"]}).to_csv(tmp_path / "config" / "other.csv", index=False)
    config["claims"]["registered_pilots"] = "config/other.csv"
    with pytest.raises(rl_config.ConfigError, match="not a table of the claim's pilot readings"):
        rl_config.validate_config(config, SCHEMA)
    # and a missing registered third round, by name too
    config["claims"]["registered_pilots"] = "config/pilots.csv"
    config["claims"]["registered_third_round"] = "config/no_third.csv"
    with pytest.raises(rl_config.ConfigError, match="claims.registered_third_round: config/no_third.csv does not exist"):
        rl_config.validate_config(config, SCHEMA)


def test_registering_says_which_readings_moved(tmp_path):
    config = shipped()
    rendered = readings(config).assign(source="rendered")
    write_frame(rendered, tmp_path / "rendered.csv")
    target = tmp_path / "registered.csv"
    assert P.register(tmp_path / "rendered.csv", target) == "every registered reading is as before"
    pd.testing.assert_frame_equal(P.read_readings(target), rendered[P.COLUMNS].sort_values(P.COLUMNS[:-1])
                                  .reset_index(drop=True), check_exact=True)
    assert P.register(tmp_path / "rendered.csv", target) == "every registered reading is as before"
    rendered.loc[0, "value"] = np.nan
    write_frame(rendered, tmp_path / "rendered.csv")
    said = P.register(tmp_path / "rendered.csv", target)
    assert said.count("\n") == 0 and "1 readings changed (back_contrast)" in said
    write_frame(rendered.assign(source="registered"), tmp_path / "rendered.csv")
    with pytest.raises(ValueError, match="were themselves registered"):
        P.register(tmp_path / "rendered.csv", target)


def test_the_shipped_workflow_renders_only_the_tested_tiles_unless_the_pilots_are_asked_for(tmp_path):
    """The default run's DAG (a copy of the workflow, nothing measured yet) has rule claim_sweeps' tested jobs
    alone; `make claim-pilots`' setting (claims.registered_pilots "") adds every ensemble's pilots."""
    import subprocess
    import sys

    from .workflow_copy import copy_workflow

    workdir = copy_workflow(tmp_path)

    def jobs(*extra) -> dict:
        res = subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", "--directory", str(workdir),
                              "--snakefile", str(workdir / "Snakefile"), "-n", "--quiet", "rules", *extra],
                             capture_output=True, text=True, timeout=300)
        assert res.returncode == 0, (res.stdout + res.stderr)[-3000:]
        table = res.stdout.split("Job stats:")[-1].split("Reasons:")[0]
        return {line.split()[0]: int(line.split()[1]) for line in table.splitlines()
                if len(line.split()) == 2 and line.split()[1].isdigit()}

    ensembles = len(P.pilot_keys(shipped()))
    default = jobs()
    assert default["claim_sweeps"] == ensembles and default["claim_pilots"] == 1
    rendered = jobs("--config", 'claims={registered_pilots: ""}')
    assert rendered["claim_sweeps"] == 2 * ensembles and rendered["claim_pilots"] == 1
