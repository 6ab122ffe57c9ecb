"""The hemisphere explorer's data: every measured view of the study's sweeps, packed for the report page.

The page's explorer (``templates/explorer.js``) draws any surface of the study over the hemisphere. It holds, in
this order of priority, the control plate at each incidence, every regular surface, every random kind's ensemble
mean (the mean over seeds of ``rough`` at each view) and then single random seeds, as many as the byte budget
(``report.explorer.budget``) holds. Whatever does not fit is listed, never dropped silently.

One *sweep* here is one surface under one light at every view and component: an array of shape
``(3, n_azimuths, n_elevations)`` (components :data:`COMPONENTS`; azimuth φ and elevation e in degrees on the
sweep's grid, :mod:`roughlight.render.views`), values on the 0-255 scale. The encoding (:data:`ENCODING`):

1. values as whole hundredths of a level, ``round(100 v)`` (the page's values are exact to 0.01);
2. ``total`` stored as ``total - diffuse - specular`` (not exactly zero: each is clamped and averaged on its own);
3. differences along elevation, each half great circle starting from 0, modulo 2**16;
4. the 16-bit numbers split into two byte planes (all low bytes, then all high bytes);
5. the planes of every sweep held, one after another, deflated as one stream (zlib).

Views a sweep lacks (NaN) are stored as 0 and named by a bit mask (``numpy.packbits`` of the NaN flags in the
same order, base64). The budget takes or leaves single sweeps, each costed as if deflated on its own.
"""

from __future__ import annotations

import base64
import json
import math
import zlib
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..surfaces.surface import aspect_label

__all__ = ["COMPONENTS", "ENCODING", "Sweeps", "study_columns", "read_study_columns", "study_sweeps", "ensemble_means",
           "sweep_planes", "decode_sweep", "held_sweeps", "explorer_data", "DEFAULT_BUDGET"]

#: The components of a sweep, in the order the encoding stores them.
COMPONENTS = ("diffuse", "specular", "total")

#: The encoding's name and its steps (the page's script checks the name).
ENCODING = ("roughlight-explorer/1: hundredths of a level; total stored as total - diffuse - specular; "
            "differences along elevation modulo 2**16; low and high byte planes; every sweep in one zlib stream")

#: The explorer's default byte budget: the base64 text of its data and its index, in bytes.
DEFAULT_BUDGET = 2_500_000

#: Columns of the study table the explorer reads.
COLUMNS = ["kind", "seed", "truncation", "aspect", "incidence", "azimuth", "elevation", "component", "rough",
           "control"]


@dataclass(frozen=True)
class Sweeps:
    """A study table as arrays: one sweep a row of ``keys``.

    Attributes
    ----------
    azimuths, elevations : (n_azimuths,), (n_elevations,) float arrays, degrees, ascending: the views' grid.
    keys : DataFrame, one row a sweep (kind, seed, truncation, aspect, incidence).
    values : (n_sweeps, 3, n_azimuths, n_elevations) float array, ``rough`` (0-255; NaN: view not measured).
    incidences : (n_incidences,) float array, degrees.
    control : (n_incidences, 3, n_azimuths, n_elevations) float array, the flat plate at each incidence.
    """

    azimuths: np.ndarray
    elevations: np.ndarray
    keys: pd.DataFrame
    values: np.ndarray
    incidences: np.ndarray
    control: np.ndarray


def study_columns(study: pd.DataFrame) -> dict:
    """The columns of a study table the explorer reads, as numpy arrays (:func:`study_sweeps` takes them):
    ``kind`` as codes into ``kind_labels``, ``component`` as codes into :data:`COMPONENTS`, the rest as floats. A
    table without ``kind`` (and ``seed``) is all regular."""
    if "kind" not in study:  # a table without kind and seed is all regular (roughlight.study.tables.regular)
        study = study.assign(kind="pyramids", seed=0)
    missing = [c for c in COLUMNS if c not in study]
    if missing:
        raise ValueError(f"the study table lacks the column(s) {missing}")
    kinds = pd.Categorical(study["kind"].astype(str))
    out = {"kind": kinds.codes.astype(np.int16), "kind_labels": [str(k) for k in kinds.categories],
           "component": _component_codes(study["component"].astype(str).to_numpy())}
    out.update({c: study[c].to_numpy(float) for c in COLUMNS if c not in ("kind", "component")})
    return out


def read_study_columns(path) -> dict:
    """:func:`study_columns` of ``results/study.parquet``, read a column at a time, the string columns as their
    dictionary codes: the default study's 3.9 million rows take about 0.3 GB so, where the whole table as a
    DataFrame takes 0.9 GB."""
    import pyarrow.parquet as pq

    names = pq.read_schema(path).names
    missing = [c for c in COLUMNS if c not in names]
    if missing:
        raise ValueError(f"{path} lacks the column(s) {missing}: not a study table")
    out = {}
    for name in COLUMNS:
        column = pq.read_table(path, columns=[name], read_dictionary=[name] if name in ("kind", "component")
                               else None).column(0)
        if name == "kind":
            out["kind_labels"] = sorted({label for chunk in column.chunks for label in chunk.dictionary.to_pylist()})
            values = _dictionary_codes(column, out["kind_labels"])
        elif name == "component":
            values = _dictionary_codes(column, list(COMPONENTS))
        else:
            values = column.to_numpy().astype(float, copy=False)
        del column
        out[name] = values
    return out


def _dictionary_codes(column, labels: list) -> np.ndarray:
    """A dictionary-encoded pyarrow column as codes into ``labels`` (int16), chunk by chunk."""
    parts = []
    for chunk in column.chunks:
        names = chunk.dictionary.to_pylist()
        unknown = sorted(set(names) - set(labels))
        if unknown:
            raise ValueError(f"unexpected value(s) {unknown}: expected {labels}")
        lookup = np.array([labels.index(n) for n in names], np.int16)
        parts.append(lookup[chunk.indices.to_numpy(zero_copy_only=False)])
    return np.concatenate(parts) if parts else np.zeros(0, np.int16)


def _component_codes(labels: np.ndarray) -> np.ndarray:
    codes = pd.Categorical(labels, categories=list(COMPONENTS)).codes
    if (codes < 0).any():
        raise ValueError(f"the study table has components other than {COMPONENTS}")
    return codes.astype(np.int8)


def _cube(columns: dict, group: np.ndarray, n_groups: int, name: str, az: np.ndarray, el: np.ndarray):
    """``columns[name]`` placed into an (n_groups, 3, n_azimuths, n_elevations) array (NaN where absent)."""
    cube = np.full((n_groups, 3, len(az), len(el)), np.nan)
    cube[group, columns["component"], np.searchsorted(az, columns["azimuth"]),
         np.searchsorted(el, columns["elevation"])] = columns[name]
    return cube


def study_sweeps(columns: dict) -> Sweeps:
    """The study table's sweeps as arrays (:class:`Sweeps`).

    Parameters
    ----------
    columns : the study table's columns (:func:`study_columns` or :func:`read_study_columns`).
    """
    az, el = np.unique(columns["azimuth"]), np.unique(columns["elevation"])
    parts = [columns["kind"], columns["seed"], columns["truncation"], columns["aspect"], columns["incidence"]]
    combined = np.zeros(len(parts[0]), np.int64)
    for part in parts:
        values, inverse = np.unique(part, return_inverse=True)
        combined = combined * len(values) + inverse.ravel()
    ids, first, group = np.unique(combined, return_index=True, return_inverse=True)
    keys = pd.DataFrame({"kind": np.asarray(columns["kind_labels"], object)[columns["kind"][first]],
                         "seed": columns["seed"][first].astype(np.int64), "truncation": columns["truncation"][first],
                         "aspect": columns["aspect"][first], "incidence": columns["incidence"][first]})
    values = _cube(columns, group.ravel(), len(ids), "rough", az, el)
    incidences = np.unique(columns["incidence"])
    control = _cube(columns, np.searchsorted(incidences, columns["incidence"]), len(incidences), "control", az, el)
    return Sweeps(az, el, keys, values, incidences, control)


def ensemble_means(sweeps: Sweeps) -> tuple[pd.DataFrame, np.ndarray]:
    """Each random kind's ensemble mean at each of its grid points: the mean over seeds of every view.

    Returns
    -------
    keys : DataFrame, one row an ensemble (kind, truncation, aspect, incidence, seeds: how many).
    values : (n_ensembles, 3, n_azimuths, n_elevations) float array (NaN where a seed lacks the view).
    """
    random = sweeps.keys[sweeps.keys["kind"] != "pyramids"]
    rows, means = [], []
    for (kind, t, a, i), g in random.groupby(["kind", "truncation", "aspect", "incidence"], sort=True):
        rows.append({"kind": kind, "truncation": t, "aspect": a, "incidence": i, "seeds": len(g)})
        means.append(sweeps.values[g.index.to_numpy()].mean(axis=0))
    shape = (0, 3, len(sweeps.azimuths), len(sweeps.elevations))
    return pd.DataFrame(rows), (np.stack(means) if means else np.zeros(shape))


def sweep_planes(values: np.ndarray) -> tuple[bytes, str | None]:
    """One sweep in the explorer's encoding (:data:`ENCODING`), before deflation.

    Parameters
    ----------
    values : (3, n_azimuths, n_elevations) float array, 0-255, NaN for views not measured.

    Returns
    -------
    planes : the low byte plane, then the high one (2 * values.size bytes).
    missing : base64 of ``numpy.packbits`` of the NaN flags (C order), or None when every view is measured.
    """
    values = np.asarray(values, float)
    if values.ndim != 3 or values.shape[0] != 3:
        raise ValueError(f"a sweep is (3, n_azimuths, n_elevations), got {values.shape}")
    nan = np.isnan(values)
    q = np.rint(np.where(nan, 0.0, values) * 100.0).astype(np.int64)
    if q.min(initial=0) < 0 or q.max(initial=0) > 32767:
        raise ValueError("sweep values must lie within 0-327.67 (8-bit levels)")
    q[2] -= q[0] + q[1]
    steps = (np.diff(q, axis=-1, prepend=0) & 0xFFFF).astype("<u2").ravel()
    planes = steps.view(np.uint8).reshape(-1, 2).T.tobytes()
    missing = base64.b64encode(np.packbits(nan.ravel()).tobytes()).decode("ascii") if nan.any() else None
    return planes, missing


def decode_sweep(planes: bytes, n_azimuths: int, n_elevations: int, missing: str | None = None) -> np.ndarray:
    """The inverse of :func:`sweep_planes`: (3, n_azimuths, n_elevations) values in levels, to 0.01 (NaN where
    not measured). The page's script does the same in JavaScript."""
    planes = np.frombuffer(planes, np.uint8)
    n = planes.size // 2
    steps = (planes[:n].astype(np.int64) | (planes[n:].astype(np.int64) << 8)).reshape(3, n_azimuths, n_elevations)
    q = np.cumsum(steps, axis=-1) & 0xFFFF
    q = np.where(q >= 0x8000, q - 0x10000, q)
    q[2] += q[0] + q[1]
    out = q / 100.0
    if missing is not None:
        flags = np.unpackbits(np.frombuffer(base64.b64decode(missing), np.uint8))[: out.size].astype(bool)
        out[flags.reshape(out.shape)] = np.nan
    return out


def held_sweeps(data: dict) -> list[np.ndarray]:
    """Every sweep the explorer's data hold (:func:`explorer_data`), decoded, in the order of ``data["datasets"]``."""
    planes = zlib.decompress(base64.b64decode(data["data"])) if data["data"] else b""
    naz, nel = len(data["azimuths"]), len(data["elevations"])
    return [decode_sweep(planes[d["offset"]:d["offset"] + d["length"]], naz, nel, d.get("missing"))
            for d in data["datasets"]]


def _entries(sweeps: Sweeps) -> list[tuple[dict, np.ndarray]]:
    """Every sweep the explorer could hold, in order of priority: (its index entry, its values)."""
    out = [({"kind": "control", "seed": None, "truncation": None, "aspect": None, "incidence": float(i)},
            sweeps.control[k]) for k, i in enumerate(sweeps.incidences)]
    keys = sweeps.keys
    for k in np.flatnonzero(keys["kind"].to_numpy() == "pyramids"):
        r = keys.iloc[k]
        out.append(({"kind": "pyramids", "seed": None, "truncation": float(r.truncation), "aspect": float(r.aspect),
                     "incidence": float(r.incidence)}, sweeps.values[k]))
    mean_keys, means = ensemble_means(sweeps)
    for k, r in mean_keys.iterrows():
        out.append(({"kind": r.kind, "seed": None, "truncation": float(r.truncation), "aspect": float(r.aspect),
                     "incidence": float(r.incidence), "seeds": int(r.seeds)}, means[k]))
    seeds = keys[keys["kind"] != "pyramids"].sort_values(["seed", "kind", "incidence", "truncation", "aspect"])
    for k, r in seeds.iterrows():
        out.append(({"kind": r.kind, "seed": int(r.seed), "truncation": float(r.truncation),
                     "aspect": float(r.aspect), "incidence": float(r.incidence)}, sweeps.values[k]))
    return out


def _b64_size(n_bytes: int) -> int:
    return 4 * math.ceil(n_bytes / 3)


def _left_out(entries: list[dict]) -> list[dict]:
    """What the budget left out, grouped: per kind (control, regular, ensemble means, seeds), how many and which."""
    groups = {}
    for e in entries:
        what = "seeds" if e["seed"] is not None else ("ensemble means" if e["kind"] not in ("control", "pyramids")
                                                      else "sweeps")
        g = groups.setdefault((e["kind"], what), {"kind": e["kind"], "what": what, "count": 0, "seeds": set()})
        g["count"] += 1
        if e["seed"] is not None:
            g["seeds"].add(e["seed"])
    return [{**g, "seeds": sorted(g["seeds"])} for g in groups.values()]


def explorer_data(columns: dict, budget: int = DEFAULT_BUDGET) -> dict:
    """The explorer's data for the page: its index and the encoded sweeps that fit the byte budget.

    Sweeps are taken in order of priority (:func:`_entries`) while the base64 of each one deflated on its own,
    with its index entry, fits what is left of the budget; the ones held are then deflated as one stream, which
    the page inflates at once (no larger than the parts: the budget's count is an upper bound).

    Parameters
    ----------
    columns : the study table's columns (:func:`study_columns` or :func:`read_study_columns`).
    budget : bytes of base64 text the data may take, index included (``report.explorer.budget``).

    Returns
    -------
    dict (JSON-ready): ``encoding``, ``components``, ``azimuths``, ``elevations`` (degrees),
    ``aspect_labels`` ([aspect, label] pairs: √3/2 for sqrt(3)/2), ``datasets`` (the index: kind, seed (None
    for the regular surface, the control and an ensemble mean), truncation, aspect, incidence, the ``offset`` and
    ``length`` of its byte planes in the inflated stream, ``missing``, and an ensemble mean's ``seeds``),
    ``data`` (base64 of the deflated stream of every held sweep's planes, one after another), ``bytes`` (the
    base64 text's length and the index entries'), ``budget``, ``offered`` (sweeps the study could give) and
    ``left_out`` (what did not fit, grouped by kind and what: ``sweeps``, ``ensemble means`` or ``seeds``, with
    how many and which seeds).
    """
    sweeps = study_sweeps(columns)
    held, planes, dropped, offset, size = [], [], [], 0, 0
    for entry, values in _entries(sweeps):
        raw, missing = sweep_planes(values)
        item = {**entry, "offset": offset, "length": len(raw)}
        if missing is not None:
            item["missing"] = missing
        cost = _b64_size(len(zlib.compress(raw, 9))) + len(json.dumps(item)) + 1
        if size + cost > budget:
            dropped.append(entry)
            continue
        held.append(item)
        planes.append(raw)
        offset += len(raw)
        size += cost
    data = base64.b64encode(zlib.compress(b"".join(planes), 9)).decode("ascii") if planes else ""
    aspects = sorted({float(a) for a in sweeps.keys["aspect"]})
    return {"encoding": ENCODING, "components": list(COMPONENTS), "azimuths": sweeps.azimuths.tolist(),
            "elevations": sweeps.elevations.tolist(), "aspect_labels": [[a, aspect_label(a)] for a in aspects],
            "datasets": held, "data": data, "bytes": len(data) + sum(len(json.dumps(d)) + 1 for d in held),
            "budget": int(budget), "offered": len(held) + len(dropped), "left_out": _left_out(dropped)}
