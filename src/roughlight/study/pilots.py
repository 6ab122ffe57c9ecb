"""The claim's registered pilots: the readings its pilot tiles gave, kept so that a run need not render them again.

The claim's pilots (``claims.pilots``, rule ``claim_sweeps``' pilot tiles) plan how many tested seeds each test
needs (rule ``claim_design``); the plan is fixed before any tested seed is read, and the tested seeds it asks for
are written into the config (``claims.seeds``). What the plan reads of the pilots is small: each ensemble's
pooled readings (a lobe's contrast, width and shape statistics with their jackknife errors and the seeds behind
them; rule ``claim_pilots``' ``results/analysis/random_claim_pilots.csv``). ``claims.registered_pilots`` names a
copy of that table under ``config/`` (``make claim-pilots`` writes it): an ensemble whose pilots are measured
with the same settings as the registered ones (:func:`pilot_key`) takes its readings from there, and only the
other ensembles' pilots are rendered. The code's version is not part of the key: ``make claim-pilots`` renders
every pilot again and says which readings moved.

Paths are relative to the workflow's directory.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from . import config as rl_config
from . import plan

__all__ = ["COLUMNS", "KEY_COLUMNS", "pilot_key", "pilot_keys", "registered", "registered_ensembles",
           "rendered_folders", "read_readings", "combined_readings", "register"]

#: A readings table: an ensemble's reading a row (``reading`` names it, as
#: :func:`roughlight.analysis.claim_readings.pooled_readings` does; ``value`` is float64).
COLUMNS = list(rl_config.PILOT_READING_COLUMNS)
#: An ensemble's pilots: its kind, grid point, incidence and :func:`pilot_key`.
KEY_COLUMNS = COLUMNS[:5]


def pilot_key(config: dict, kind: str, truncation: float, aspect: float, incidence: float) -> str:
    """What an ensemble's pilots are measured with, as a digest (:func:`roughlight.study.plan.claim_tiles_key` of
    the pilot seeds at ``claims.cells`` with ``surface.spread``, the incidence, the views' steps, the lighting, the
    method and its render settings, as rule ``claim_sweeps`` gives them)."""
    return plan.claim_tiles_key(plan.claim_measurement(config), kind, truncation, aspect, incidence,
                                rl_config.pilot_seeds(config))


def pilot_keys(config: dict) -> list[list]:
    """Every claim ensemble's pilots: [kind, truncation, aspect, incidence, :func:`pilot_key`] lists (params)."""
    return [[kind, t, a, float(i), pilot_key(config, kind, t, a, i)]
            for i in plan.grid(config, "incidence") for kind, t, a, _ in plan.ensembles(config, "pilots")]


def read_readings(path) -> pd.DataFrame:
    """A readings table (:data:`COLUMNS`) from CSV (pandas reads back every float as written); raises
    ``ValueError`` naming the file and the columns it lacks."""
    frame = pd.read_csv(path, dtype={"kind": str, "key": str, "reading": str})
    missing = [c for c in COLUMNS if c not in frame.columns]
    if missing:
        raise ValueError(f"{path}: not a table of the claim's pilot readings (no column {', '.join(missing)})")
    return frame.astype({"truncation": float, "aspect": float, "incidence": float, "value": float})


def registered(config: dict) -> pd.DataFrame | None:
    """The registered readings (``claims.registered_pilots``) as :func:`read_readings` gives them; None when
    none are (a validated config's file exists and is such a table:
    :func:`roughlight.study.config.validate_config`)."""
    path = rl_config.claims(config).get("registered_pilots")
    return read_readings(path) if path else None


def registered_ensembles(config: dict, table: pd.DataFrame | None = None) -> set[tuple]:
    """The claim ensembles whose pilots are registered under their own key: (kind, truncation, aspect,
    incidence) tuples. ``table``: :func:`registered` (read when not given)."""
    table = registered(config) if table is None else table
    if table is None:
        return set()
    held = set(table[KEY_COLUMNS].itertuples(index=False, name=None))
    return {(kind, t, a, i) for kind, t, a, i, key in pilot_keys(config) if (kind, t, a, i, key) in held}


def rendered_folders(config: dict) -> list[str]:
    """The pilot folders a run renders (rule ``claim_sweeps``, role pilots): every claim ensemble's but the
    registered ones'."""
    held = registered_ensembles(config)
    return [plan.ensemble_folder(kind, t, a, i, plan.claim_folder("pilots"))
            for i in plan.grid(config, "incidence") for kind, t, a, _ in plan.ensembles(config, "pilots")
            if (kind, t, a, float(i)) not in held]


def combined_readings(rendered: pd.DataFrame, registered: pd.DataFrame | None, keys: dict) -> pd.DataFrame:
    """Every claim ensemble's pilot readings (rule ``claim_pilots``' table, :data:`COLUMNS` and ``source``,
    "rendered" or "registered"): the ``rendered`` ensembles' own, the others' from ``registered`` under their key.

    ``keys``: (kind, truncation, aspect, incidence) -> :func:`pilot_key`, every ensemble of the claim. Raises
    ``ValueError`` naming an ensemble that has neither."""
    found = {ensemble: rows[COLUMNS].assign(source="rendered")
             for ensemble, rows in rendered.groupby(KEY_COLUMNS[:-1], sort=False)}
    for (*ensemble, key), rows in ([] if registered is None else registered.groupby(KEY_COLUMNS, sort=False)):
        ensemble = tuple(ensemble)
        if ensemble not in found and keys.get(ensemble) == key:
            found[ensemble] = rows[COLUMNS].assign(source="registered")
    missing = [ensemble for ensemble in keys if ensemble not in found]
    if missing:
        raise ValueError(f"no pilot readings for {len(missing)} ensembles, e.g. {missing[0]}: neither rendered nor "
                         "registered under their settings")
    return pd.concat([found[ensemble] for ensemble in keys], ignore_index=True)


def register(rendered, target) -> str:
    """Write the rendered readings (rule ``claim_pilots``' table, every ensemble rendered) to ``target`` (the
    registered file), atomically; return what changed against the file it replaces, a line an ensemble."""
    from ..atomic import write_frame

    new = read_readings(rendered)
    if "source" in new.columns and (new["source"] != "rendered").any():
        raise ValueError(f"{rendered}: some readings were themselves registered, not rendered: run with "
                         "claims.registered_pilots null (`make claim-pilots`)")
    new = new[COLUMNS].sort_values(COLUMNS[:-1], kind="stable").reset_index(drop=True)
    lines = []
    if Path(target).is_file():
        old = read_readings(target)[COLUMNS]
        both = new.merge(old, on=COLUMNS[:-1], how="outer", suffixes=("", "_before"), indicator=True)
        for ensemble, rows in both.groupby(KEY_COLUMNS[:-1], sort=True):
            value, before = rows["value"].to_numpy(), rows["value_before"].to_numpy()
            differs = (value != before) & ~(np.isnan(value) & np.isnan(before))
            moved = rows[(rows["_merge"] != "both").to_numpy() | differs]
            if len(moved):
                names = ", ".join(moved["reading"].astype(str).head(6))
                lines.append(f"{' '.join(map(str, ensemble))}: {len(moved)} readings changed ({names}"
                             f"{', ...' if len(moved) > 6 else ''})")
    write_frame(new, target)
    return "\n".join(lines) if lines else "every registered reading is as before"


def main(argv=None) -> int:
    """``python -m roughlight.study.pilots RENDERED TARGET``: :func:`register`, printing what changed."""
    parser = argparse.ArgumentParser(description=register.__doc__.split(";")[0])
    parser.add_argument("rendered", help="rule claim_pilots' table, every ensemble rendered")
    parser.add_argument("target", help="the registered file (claims.registered_pilots)")
    args = parser.parse_args(argv)
    print(register(args.rendered, args.target))
    return 0


if __name__ == "__main__":
    sys.exit(main())
