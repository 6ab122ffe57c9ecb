"""The study table: per-sweep Parquet files and their aggregate.

Schema of ``results/study.parquet`` (one row per surface x view x component)
-------------------------------------------------------------------------
============== ======= =====================================================
column         type    meaning
============== ======= =====================================================
kind           string  'pyramids' (the regular grid), 'random_pyramids' or 'random_heightfield'
seed           int64   the random tile's seed (>= 1); 0 for the regular surface
truncation     float64 fraction of the pyramid's height kept, [0, 1] (a random tile's grid point)
aspect         float64 pyramid height / base width, >= 0
incidence      float64 light elevation above the plane, degrees [0, 90]
azimuth        float64 view azimuth, degrees [0, 180)
elevation      float64 view elevation, degrees [0, 180]
phase          float64 angle between light and view directions, degrees
component      string  'diffuse', 'specular' or 'total'
rough          float64 rough surface: mean 8-bit value of the view, 0-255
control        float64 flat plate under the same light and view, 0-255
coverage       float64 fraction of the capture window showing the surface (0: not rendered, e = 0 and 180;
                       its rough and control are no measurement)
rough_unrounded   float64 rough's mean before rounding: each pixel's value clamped to [0, 255], not rounded
                       (within 0.5 of rough, and the rounding's tie slack); NaN where the method averages
                       8-bit framebuffer pixels (naive, fast lattice and grid sampling, implicit_exact and
                       implicit_correction)
control_unrounded float64 control's mean before rounding (NaN as rough_unrounded)
rough_unshadowed  float64 rough_unrounded with inner shadows off: every seen point lit (NaN also for mitsuba,
                       whose light always casts them)
light          float64 light intensity J, 0-255
ambient        float64 ambient light level A, fraction of J
shininess      float64 specular exponent
specular_model string  'phong' or 'blinn'
shadows        bool    inner shadows cast
specular_shadows bool  the shadows take the specular too (false: the thesis's specular protocol)
method         string  'fast', 'naive', 'reference', 'implicit_exact', 'implicit_correction' or 'mitsuba'
pixels_per_period int64 pixels per period (a random tile's: per cell; naive: 10, its window's; reference: 0;
                       implicit: sqrt of its pixels a view, rounded)
sampling       string  'adaptive', 'lattice' or 'grid' (fast), 'window' (naive), 'exact' (reference),
                       'fibonacci' (implicit; 'table', 'clipped' for those models), 'mitsuba <variant>, <n> spp,
                       <bounces>' (mitsuba)
shadow_map_size   int64 shadow texels per side (a random tile's: per cell; naive: pyrender's 2048;
                       reference, implicit and mitsuba: 0)
render_seconds float64 wall time of the sweep that produced the row
============== ======= =====================================================

Per-sweep files (``results/sweeps/i{incidence}/...``) hold the same columns
but ``control`` and ``control_unrounded`` (the rough sweep's ``value``, ``value_unrounded`` and
``value_unshadowed`` are renamed ``rough``, ``rough_unrounded`` and ``rough_unshadowed`` when the aggregate joins
it to its control sweep, whose ``value`` and ``value_unrounded`` become ``control`` and ``control_unrounded``).
Their format is :data:`SWEEP_FORMAT`.
"""

from __future__ import annotations

import numpy as np

from ..atomic import write_frame
from ..render.shading import COMPONENTS, phase_angle
from ..surfaces.roughness import KINDS
from ..surfaces.surface import Surface

__all__ = [
    "STUDY_COLUMNS",
    "SWEEP_FORMAT",
    "sweep_table",
    "read_sweep",
    "claim_rows",
    "aggregate",
    "join_controls",
    "regular",
    "read_study",
]

KEY_COLUMNS = ["kind", "seed", "truncation", "aspect", "incidence", "azimuth", "elevation", "phase", "component"]
SETTING_COLUMNS = [
    "light",
    "ambient",
    "shininess",
    "specular_model",
    "shadows",
    "specular_shadows",
    "method",
    "pixels_per_period",
    "sampling",
    "shadow_map_size",
]
#: Each view's means before rounding and with inner shadows off (:data:`roughlight.render.sweep.EXTRA_KEYS`), as a
#: rough sweep's study columns; the plate has no inner shadows, so its control has no ``_unshadowed``.
EXTRA_COLUMNS = ["rough_unrounded", "control_unrounded", "rough_unshadowed"]
STUDY_COLUMNS = KEY_COLUMNS + ["rough", "control", "coverage"] + EXTRA_COLUMNS + SETTING_COLUMNS + ["render_seconds"]
SWEEP_COLUMNS = (KEY_COLUMNS + ["value", "coverage", "value_unrounded", "value_unshadowed"] + SETTING_COLUMNS
                 + ["render_seconds"])
#: The sweep files' format, part of the sweep store's key (:func:`roughlight.study.sweep_store.sweep_key`) and a
#: param of the sweep rules, so that a sweep of an earlier format is never taken for one of this: 1, the 8-bit
#: means; 2, with each view's ``value_unrounded`` and ``value_unshadowed``.
SWEEP_FORMAT = 2


def sweep_table(result: dict, surface: Surface, incidence, azimuth, elevation, lighting, method, render_settings):
    """One sweep's measurements as a long ``pyarrow.Table`` (rows: view x component).

    Parameters
    ----------
    result : dict
        Output of :func:`roughlight.render.methods.sweep`.
    surface : Surface or RandomSurface
    incidence : float
    azimuth, elevation : (n_views,) arrays, degrees
    lighting : roughlight.render.shading.Lighting
    method : str
    render_settings : dict
        How the method sampled (:func:`roughlight.render.methods.recorded`):
        ``pixels_per_period``, ``sampling``, ``shadow_map_size``.

    The columns are built from their buffers (:func:`_column`, :func:`_labels`): ``pyarrow.array`` imports pandas
    on its first call, 0.15 s of every sweep job, which needs none of it.
    """
    import pyarrow as pa

    azimuth = np.asarray(azimuth, float)
    elevation = np.asarray(elevation, float)
    n = azimuth.size
    k = len(COMPONENTS)
    from ..surfaces.roughness import kind_and_seed

    kind, seed = kind_and_seed(surface)
    rows = n * k
    columns = {
        "kind": _labels([kind], np.zeros(rows, np.int8)),
        "seed": np.full(rows, seed, np.int64),
        "truncation": np.full(rows, surface.truncation),
        "aspect": np.full(rows, surface.aspect),
        "incidence": np.full(rows, float(incidence)),
        "azimuth": np.repeat(azimuth, k),
        "elevation": np.repeat(elevation, k),
        "phase": np.repeat(phase_angle(incidence, elevation, azimuth), k),
        "component": _labels(COMPONENTS, np.tile(np.arange(k, dtype=np.int8), n)),
        "value": _by_component(result, ""),
        "coverage": np.repeat(np.asarray(result["coverage"], float), k),
        "value_unrounded": _by_component(result, "_unrounded"),
        "value_unshadowed": _by_component(result, "_unshadowed"),
        "light": np.full(rows, float(lighting.light)),
        "ambient": np.full(rows, float(lighting.ambient)),
        "shininess": np.full(rows, float(lighting.shininess)),
        "specular_model": _labels([lighting.specular_model], np.zeros(rows, np.int8)),
        "shadows": np.full(rows, bool(lighting.shadows)),
        "specular_shadows": np.full(rows, bool(lighting.specular_shadows)),
        "method": _labels([method], np.zeros(rows, np.int8)),
        "pixels_per_period": np.full(rows, int(render_settings["pixels_per_period"]), np.int64),
        "sampling": _labels([render_settings["sampling"]], np.zeros(rows, np.int8)),
        "shadow_map_size": np.full(rows, int(render_settings["shadow_map_size"]), np.int64),
        "render_seconds": np.full(rows, float(result["seconds"])),
    }
    names = list(columns)
    table = pa.Table.from_arrays([c if isinstance(c, pa.Array) else _column(c) for c in columns.values()],
                                 names=names)
    return table.replace_schema_metadata({RENDERER_KEY: str(result.get("renderer", ""))})


def _by_component(result: dict, suffix: str) -> np.ndarray:
    """A sweep's per-view arrays ``{component}{suffix}`` as one column, a view's components in a row."""
    return np.stack([np.asarray(result[c + suffix], float) for c in COMPONENTS], axis=1).ravel()


#: The Parquet metadata key of what a sweep ran on (:func:`roughlight.render.methods.sweep`'s ``renderer``);
#: the study table holds those of all its sweeps under :data:`RENDERERS_KEY`, as a JSON list.
RENDERER_KEY = "roughlight.renderer"
RENDERERS_KEY = "roughlight.renderers"


def renderers(paths) -> list[str]:
    """What the sweeps (or study tables) at ``paths`` ran on, each once, sorted: from their Parquet metadata
    (:data:`RENDERER_KEY`, :data:`RENDERERS_KEY`); a file written before it was recorded adds nothing."""
    import json

    import pyarrow.parquet as pq

    found = set()
    for path in paths:
        try:
            meta = pq.read_schema(path).metadata or {}
        except Exception:  # a corrupt file: read_sweep's message says which and what to do
            read_sweep(path)
            raise
        if RENDERER_KEY.encode() in meta and meta[RENDERER_KEY.encode()]:
            found.add(meta[RENDERER_KEY.encode()].decode())
        if RENDERERS_KEY.encode() in meta:
            found.update(json.loads(meta[RENDERERS_KEY.encode()]))
    return sorted(found)


def _column(values: np.ndarray):
    """A pyarrow array of a 1-D numpy array of float64, int64 or bool, from its buffer (no pandas)."""
    import pyarrow as pa

    values = np.ascontiguousarray(values)
    if values.dtype == bool:
        bits = np.packbits(values, bitorder="little")
        return pa.Array.from_buffers(pa.bool_(), len(values), [None, pa.py_buffer(bits)])
    kinds = {np.dtype(np.float64): pa.float64(), np.dtype(np.int64): pa.int64()}
    return pa.Array.from_buffers(kinds[values.dtype], len(values), [None, pa.py_buffer(values)])


def _labels(labels, codes: np.ndarray):
    """A dictionary array (int8 codes into ``labels``, strings) from its buffers (no pandas)."""
    import pyarrow as pa

    data = [str(label).encode() for label in labels]
    offsets = np.concatenate([[0], np.cumsum([len(d) for d in data])]).astype(np.int32)
    strings = pa.StringArray.from_buffers(len(data), pa.py_buffer(offsets), pa.py_buffer(b"".join(data)))
    indices = pa.Array.from_buffers(pa.int8(), len(codes), [None, pa.py_buffer(np.ascontiguousarray(codes, np.int8))])
    return pa.DictionaryArray.from_arrays(indices, strings)


def read_sweep(path):
    """Read one sweep file as a DataFrame, with a clear error if it is not a readable sweep."""
    import pandas as pd

    try:
        frame = pd.read_parquet(path)
    except Exception as exc:  # pyarrow raises several types for a corrupt file
        raise ValueError(
            f"{path} is not a readable Parquet sweep ({exc}); delete it and rerun snakemake to rebuild it"
        ) from exc
    if "kind" not in frame.columns:  # written before random surfaces existed: the regular surface
        frame.insert(0, "kind", "pyramids")
        frame.insert(1, "seed", 0)
    if "specular_shadows" not in frame.columns:  # written before the setting existed: the default
        frame["specular_shadows"] = True
    missing = [c for c in SWEEP_COLUMNS if c not in frame.columns]
    if missing:
        raise ValueError(f"{path} lacks columns {missing}; delete it and rerun snakemake to rebuild it")
    return frame


def claim_rows(folders):
    """The claim's pilot or tested tiles (rule ``claim_sweeps``' folders, a file ``s{seed}.parquet`` a seed) as rows in the
    study table's columns (kind, seed, surface keys, views, component, ``rough``, ``rough_unrounded``,
    ``rough_unshadowed``, coverage)."""
    from pathlib import Path

    import pandas as pd

    frames = [read_sweep(path) for folder in folders for path in sorted(Path(folder).glob("s*.parquet"))]
    columns = KEY_COLUMNS + ["rough", "rough_unrounded", "rough_unshadowed", "coverage"]
    if not frames:
        return pd.DataFrame(columns=columns)
    frame = pd.concat(frames, ignore_index=True).rename(columns={
        "value": "rough", "value_unrounded": "rough_unrounded", "value_unshadowed": "rough_unshadowed"})
    return frame[columns]


def aggregate(rough_paths, control_paths):
    """Join rough sweeps to their control sweeps: the study table (see module docstring).

    Parameters
    ----------
    rough_paths : list of paths to rough-surface sweep files (regular and random)
    control_paths : list of paths to control sweep files (one per incidence)

    Returns
    -------
    pandas.DataFrame with :data:`STUDY_COLUMNS`, sorted by surface, incidence,
    azimuth, elevation and component.
    """
    import pandas as pd

    return pd.concat(list(study_parts(rough_paths, control_paths)), ignore_index=True)


def write_study(rough_paths, control_paths, path, metadata: dict | None = None) -> int:
    """:func:`aggregate` written to ``path`` (Parquet, atomically) a sweep at a time, never held whole: the same
    file as writing the aggregate (3.9 million rows by default, 0.6 GB as a DataFrame). Returns its rows."""
    from ..atomic import write_frame_parts

    return write_frame_parts(study_parts(rough_paths, control_paths), path, metadata)


def study_parts(rough_paths, control_paths):
    """The study table a sweep at a time, in the table's row order: each rough sweep joined to its control
    (:meth:`_ControlViews.joined`), the sweeps ordered by kind (in :data:`~roughlight.surfaces.roughness.KINDS`
    order), seed, truncation, aspect and incidence, each one's rows by azimuth, elevation and component (in
    :data:`~roughlight.render.shading.COMPONENTS` order). A labelled column takes the dtype ``pandas.concat`` gives
    the whole table (a categorical stays one where every sweep has the same categories).

    Yields
    ------
    DataFrame with :data:`STUDY_COLUMNS`, one a rough sweep.
    """
    import pandas as pd

    keys = [_sweep_key(path) for path in rough_paths]
    seen = {}
    for path, key in zip(rough_paths, keys):
        if key[:5] in seen:
            raise ValueError(f"{seen[key[:5]]} and {path} measure the same surface under the same light")
        seen[key[:5]] = path
    dtypes = {name: pd.concat([pd.Series([], dtype=key[5][name]) for key in keys]).dtype for name in LABELLED}
    controls = _ControlViews(pd.concat([read_sweep(p) for p in control_paths], ignore_index=True))
    for done, n in enumerate(sorted(range(len(rough_paths)), key=lambda n: keys[n][:5])):
        frame = _sweep_rows(controls.joined(read_sweep(rough_paths[n])))
        for name, dtype in dtypes.items():
            if frame[name].dtype != dtype:
                frame[name] = frame[name].astype(dtype)
        yield frame
        del frame
        if done % 16 == 15:
            _release_memory()  # what reading left behind


#: A sweep's columns of labels whose dtype is each sweep's own (a categorical of its dictionary).
LABELLED = ["specular_model", "method", "sampling"]
#: A view's sort keys within its sweep, in order (:func:`study_parts`).
VIEW_ORDER = ["azimuth", "elevation", "_component"]


def _sweep_key(path):
    """A sweep file's place in the study's order (kind's index in :data:`~roughlight.surfaces.roughness.KINDS`,
    seed, truncation, aspect, incidence) and its :data:`LABELLED` columns' dtypes as :func:`read_sweep` reads them,
    from those columns alone."""
    import pyarrow.parquet as pq

    from ..surfaces.roughness import KINDS

    try:
        names = pq.read_schema(path).names
        if any(name not in names for name in ["truncation", "aspect", "incidence"] + LABELLED):
            raise ValueError("columns missing")
        frame = pq.read_table(path, columns=[n for n in ["kind", "seed", "truncation", "aspect", "incidence"]
                                             + LABELLED if n in names]).to_pandas()
    except Exception:  # a corrupt or incomplete file: read_sweep's message says what to do
        read_sweep(path)
        raise
    kind = str(frame["kind"].iloc[0]) if "kind" in frame else "pyramids"
    seed = int(frame["seed"].iloc[0]) if "seed" in frame else 0
    for name in ["kind", "seed", "truncation", "aspect", "incidence"]:
        if name in frame and frame[name].nunique() > 1:
            raise ValueError(f"{path} holds more than one {name}: a sweep is one surface under one light")
    place = (list(KINDS).index(kind), seed) + tuple(float(frame[n].iloc[0]) for n in ["truncation", "aspect",
                                                                                        "incidence"])
    return place + ({name: frame[name].dtype for name in LABELLED},)


def _sweep_rows(columns):
    """One sweep's study rows from its joined columns (:meth:`_ControlViews.joined`): :data:`STUDY_COLUMNS`, the
    rows in :data:`VIEW_ORDER`, a fresh index."""
    import pandas as pd

    order = np.lexsort([np.asarray(columns[name]) for name in reversed(VIEW_ORDER)])

    def taken(values):
        if isinstance(values, pd.Series):
            return values.take(order).reset_index(drop=True)
        return pd.Series(np.asarray(values)[order])

    return pd.DataFrame({name: taken(columns[name]) for name in STUDY_COLUMNS}, copy=False)


def join_controls(rough, control):
    """The study table from sweep frames (:func:`sweep_table`'s columns): each rough view joined to the
    control's same view (see :func:`aggregate`)."""
    return _sweep_rows(_ControlViews(control).joined(rough))


#: The view of a control row a rough row is joined to.
CONTROL_KEY = ["incidence", "azimuth", "elevation", "component"]


class _ControlViews:
    """The control sweeps' values, looked up by view (:data:`CONTROL_KEY`)."""

    def __init__(self, control):
        import pandas as pd

        self.views = pd.MultiIndex.from_arrays([control[name].astype(str) if name == "component" else control[name]
                                                for name in CONTROL_KEY])
        if not self.views.is_unique:
            raise ValueError("the control sweeps measure some view twice (one control sweep an incidence is expected)")
        self.values = control["value"].to_numpy()
        self.unrounded = control["value_unrounded"].to_numpy()

    def joined(self, rough) -> dict:
        """A rough sweep frame's columns (:func:`sweep_table`'s), each a Series of its own memory (columns that
        share a frame's block would not be freed one by one), with ``kind`` and ``component`` as strings, its
        ``value`` as ``rough`` (``value_unrounded``, ``value_unshadowed`` as ``rough_unrounded``,
        ``rough_unshadowed``), the control's value of each row's view as ``control`` (its ``value_unrounded`` as
        ``control_unrounded``), and the sort codes of
        ``kind`` and ``component`` (in :data:`~roughlight.surfaces.roughness.KINDS` and
        :data:`~roughlight.render.shading.COMPONENTS` order)."""
        import pandas as pd

        columns = {name: frame_column.copy() for name, frame_column in rough.items()}
        for extra in ("", "_unrounded", "_unshadowed"):
            columns["rough" + extra] = columns.pop("value" + extra)
        columns["kind"], columns["component"] = columns["kind"].astype(str), columns["component"].astype(str)
        where = self.views.get_indexer(pd.MultiIndex.from_arrays([columns[name] for name in CONTROL_KEY]))
        if np.any(where < 0):
            missing = rough.loc[where < 0, CONTROL_KEY[:3]].drop_duplicates()
            raise ValueError(f"no control measurement for {len(missing)} views, e.g. {missing.iloc[0].to_dict()}")
        columns["control"] = pd.Series(self.values[where])
        columns["control_unrounded"] = pd.Series(self.unrounded[where])
        columns["_kind"] = pd.Categorical(columns["kind"], categories=list(KINDS)).codes
        columns["_component"] = pd.Categorical(columns["component"], categories=list(COMPONENTS)).codes
        return columns


def _release_memory() -> None:
    """Give freed heap memory back to the system (glibc's ``malloc_trim``; nothing elsewhere). The sweeps' columns
    are small allocations that glibc keeps for reuse, while the table's large columns are mapped afresh: without
    this the job's memory would hold both."""
    import ctypes
    import ctypes.util

    import pyarrow as pa

    pa.default_memory_pool().release_unused()  # the string columns' memory
    try:
        ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):
        pass


#: Which rows :func:`read_study` keeps.
STUDY_ROWS = ("all", "regular", "random_points", "regular_points")


def read_study(path, rows: str = "all", columns=None):
    """Read the study table (``results/study.parquet``), or part of its rows and columns.

    Parameters
    ----------
    path : str
    rows : str
        ``"all"``; ``"regular"``: the regular surface's rows (what :func:`regular` keeps); ``"random_points"``:
        the random tiles' rows and the regular surface's at their grid points (what
        :func:`roughlight.analysis.ensembles.random_points` keeps; all rows when there is no random tile);
        ``"regular_points"``: the regular surface's rows at those grid points alone (the random-roughness claim's
        rules; all rows when there is no random tile).
    columns : list of str, optional
        Only these columns, in this order (a job reads the few it uses: a third less time and 0.2-0.3 GB less
        memory on the default study); a column the file lacks is a KeyError. Default: every column.

    The file is read a column at a time, each converted to pandas, cut to the rows kept, and its Arrow memory
    dropped before the next; the frame is assembled without copying the columns. The read peaks near the
    frame's own size (the regular rows of the default study, a 0.42 GB frame: 0.52 GB over the interpreter's
    own, where reading the table whole and converting it took 0.87 GB). The frame equals the rows of
    ``pd.read_parquet(path)`` kept, in their order, with a fresh index.
    """
    import pandas as pd
    import pyarrow.parquet as pq

    if rows not in STUDY_ROWS:
        raise ValueError(f"rows must be one of {STUDY_ROWS}, got {rows!r}")
    names = pq.read_schema(path).names
    missing = [name for name in (columns or []) if name not in names]
    if missing:
        raise KeyError(f"{path} lacks the column(s) {missing}")
    keep = _kept_rows(path, rows) if "kind" in names else None
    frame = {}
    for name in names if columns is None else columns:
        column = pq.read_table(path, columns=[name]).column(0)
        frame[name] = (column if keep is None else column.filter(keep)).to_pandas()
        del column
    return pd.DataFrame(frame, copy=False)


def _kept_rows(path, rows: str):
    """The boolean mask (a pyarrow array, or None for every row) of the rows :func:`read_study` keeps."""
    import pyarrow.compute as pc
    import pyarrow.parquet as pq

    if rows == "all":
        return None
    kind = pq.read_table(path, columns=["kind"]).column(0)
    is_regular = pc.equal(kind, "pyramids")
    if rows == "regular":
        return is_regular
    if pc.all(is_regular).as_py():
        return None
    grid = pq.read_table(path, columns=["truncation", "aspect"])
    points = grid.filter(pc.invert(is_regular)).group_by(["truncation", "aspect"]).aggregate([])
    at_points = None
    for t, a in zip(points.column("truncation").to_pylist(), points.column("aspect").to_pylist()):
        here = pc.and_(pc.equal(grid.column("truncation"), t), pc.equal(grid.column("aspect"), a))
        at_points = here if at_points is None else pc.or_(at_points, here)
    if rows == "regular_points":
        return pc.and_(is_regular, at_points)
    return pc.or_(pc.invert(is_regular), at_points)


def regular(study):
    """The regular surface's rows (kind ``pyramids``): what the thesis's analyses (Tables 1-2, lobes,
    diffuse fits, GLMs, figures) are about. A table without a ``kind`` column is all regular."""
    if "kind" not in study.columns:
        return study
    return study.loc[study["kind"].astype(str) == "pyramids"].reset_index(drop=True)


def run_sweep(path, surface: Surface, incidence, sweep, lighting, method, render, log=None, views=None):
    """Measure one sweep and write its table to ``path`` atomically.

    Parameters
    ----------
    path : str
        Output Parquet file.
    surface : Surface
    incidence : float
        Light elevation, degrees.
    sweep : dict with ``elevation_step`` and ``azimuth_step`` (degrees)
    lighting : dict of :class:`roughlight.render.shading.Lighting` fields
    method : str, one of :data:`roughlight.render.methods.NAMES`
    render : dict, the method's config keys (:meth:`roughlight.render.methods.Method.settings`; may be empty)
    log : callable taking a message, optional
    views : (azimuth, elevation) arrays, degrees, optional
        Only these views of the sweep's grid (rule ``claim_sweeps``: the views around the claim's lobes); default
        every view of the grid.
    """
    from ..render import methods, shading
    from ..render import views as sweeps

    log = log or (lambda message: None)
    lighting = shading.Lighting(**lighting)
    settings = methods.settings(method, render)
    azimuth, elevation = (sweeps.view_grid(sweep["elevation_step"], sweep["azimuth_step"]) if views is None
                          else (np.asarray(views[0], float), np.asarray(views[1], float)))
    log(
        f"sweep {surface} incidence={incidence}: "
        f"{azimuth.size} views, method={method}, {lighting}, {settings}"
    )
    result = methods.sweep(method, surface, incidence, azimuth, elevation, lighting, settings)
    log(f"measured {azimuth.size} views in {result['seconds']:.2f} s ({azimuth.size / result['seconds']:.0f} views/s)")
    table = sweep_table(result, surface, incidence, azimuth, elevation, lighting, method,
                        methods.recorded(method, settings, surface))
    write_frame(table, path)
    log(f"wrote {table.num_rows} rows to {path}")
    return result


def study_summary(study) -> dict:
    """What the report says about the study table (grid, views, settings)."""
    from .selection import SURFACE_KEYS

    keys = study[SURFACE_KEYS].drop_duplicates()
    comp = study["component"].astype(str)
    first = study.loc[comp == comp.iloc[0]]
    per = first.groupby(SURFACE_KEYS).size()
    row = study.iloc[0]
    return {
        "rows": int(len(study)),
        "surfaces": int(len(keys)),
        "views_per_surface": int(per.median()) if len(per) else 0,
        "truncations": sorted(float(x) for x in keys["truncation"].unique()),
        "aspects": sorted(float(x) for x in keys["aspect"].unique()),
        "incidences": sorted(float(x) for x in keys["incidence"].unique()),
        "light": float(row["light"]),
        "shininess": float(row["shininess"]),
        "shadows": bool(row["shadows"]),
        "method": str(row["method"]),
    }
