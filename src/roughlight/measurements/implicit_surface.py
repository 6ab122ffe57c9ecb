"""The implicit rough surface measured: validation against the exact reference, and frame times.

Two measurements, each at a size named by a plan (:data:`PLANS`: ``full`` is ``make bench``'s, ``quick`` the same
code on a few surfaces and coarse views):

* :func:`validation`: on every view of each validation surface, the error against the exact reference
  (:func:`roughlight.render.exact.reference.reference_sweep`) of the implicit exact form and first-order correction
  (both through the shader, :func:`roughlight.render.implicit.shader.implicit_sweep`), the explicit fast renderer and
  the V-cavity facet model (the best analytic model the report fits,
  :func:`roughlight.analysis.surface_models.facet_model`): MAE, p99 and worst view per surface, method and component.
* :func:`frame_times`: the thesis's trade-off. One square field of ``N x N`` pyramids drawn explicitly by pyrender
  (``N^2 x 10`` triangles, with its shadow pass) against the same field as one implicit quad, at the same image size
  and views; frame time, triangles and the image mean's error against the exact value.
"""

from __future__ import annotations

import math
import time
from functools import partial

import numpy as np

from ..render import methods, shading
from ..render import views as sweeps
from ..surfaces.geometry import period_triangles
from ..surfaces.surface import SQRT3_2, Surface
from . import comparison

__all__ = ["PLANS", "GOAL", "MODEL_METHODS", "EXACT_ONCE_A_FRAME", "FRAME_DRAWINGS", "HELD_OUT", "HELD_OUT_BAND",
           "validation_surfaces", "held_out_lights", "held_out_counts", "validation", "frame_times", "explicit_frames",
           "implicit_frames", "fastest_frame", "summary", "goal", "hemisphere_maps", "load_tables", "share_table"]

#: Validation incidences, degrees.
INCIDENCES = (10.0, 30.0, 50.0, 70.0)

#: Surfaces of the default grid validated at every incidence: its corners, its middle and the
#: table aspects (truncation, aspect).
GRID_SURFACES = ((0.1, 0.1), (1.0, 0.1), (0.1, 1.0), (1.0, 1.0), (0.5, 0.5), (1.0, SQRT3_2))

#: Methods of the validation, in the order of its table (``implicit_table`` on the surfaces that have a table).
VALIDATED = ("implicit_exact", "implicit_correction", "implicit_table", "implicit_clipped", "fast", "v_cavity")

#: The sweeps of the validation, in its order (the V-cavity model is a closed form in numpy).
SWEPT = ("implicit_exact", "implicit_correction", "fast")

#: The measured plans. The frame times reach N 512, where the goal is judged (:func:`goal`: the largest field timed):
#: at N 256 a 512 x 512 quad's own clear, draw and read-back on llvmpipe (about 2 ms) cap every quad near 50x the
#: explicit field's 115 ms (docs/implicit-surface.md, "The clipped scene"); the explicit N 512 field peaks near
#: 800 MB in its job.
PLANS = {
    "full": {"grid": GRID_SURFACES, "incidences": INCIDENCES, "random": 20, "steps": (1.0, 5.0),
             "fields": (16, 64, 256, 512), "frame_views": ((30.0, 0.0), (60.0, 20.0), (90.0, 45.0), (120.0, 0.0)),
             "repeats": 3, "held_out": {"lights": 3, "views": 40}},
    "quick": {"grid": ((1.0, 1.0), (0.5, 0.5)), "incidences": (30.0,), "random": 1, "steps": (6.0, 30.0),
              "fields": (16, 512), "frame_views": ((60.0, 20.0),), "repeats": 3,
              "held_out": {"lights": 2, "views": 40}},
    # a check that a config builds the whole report, in seconds (its numbers are not for reading)
    "smoke": {"grid": ((1.0, 1.0),), "incidences": (30.0,), "random": 1, "steps": (15.0, 45.0),
              "fields": (16,), "frame_views": ((60.0, 20.0),), "repeats": 1,
              "held_out": {"lights": 1, "views": 10}},
}

#: Seed of the random (truncation, aspect, incidence) triples.
RANDOM_SEED = 20011

#: Seed of the held-out lights and views (:func:`held_out_lights`).
HELD_OUT_SEED = 58
#: The held-out lights' incidences and the views' elevations, degrees: any light the goal names (issue 58:
#: incidence 5-85, any azimuth) and any view above the horizon but the last degree at either end, where no method
#: but the reference shows the surface (grazing views).
HELD_OUT_INCIDENCE = (5.0, 85.0)
HELD_OUT_ELEVATION = (1.0, 179.0)
#: The ``kind`` of the held-out rows of :func:`validation`, and their band in :func:`summary`.
HELD_OUT = "held out"
HELD_OUT_BAND = "held-out lights and views"


def held_out_counts(validation) -> dict:
    """How the validation was drawn: ``surfaces`` (surface and incidence pairs on the plan's view grid),
    ``views`` (each one's distinct views), ``lights`` (held-out lights) and ``light_views`` (the most distinct views
    a held-out light was checked at)."""
    held = validation["kind"] == HELD_OUT if "kind" in validation else np.zeros(len(validation), bool)
    grid, off = validation[~held], validation[held]
    return {"surfaces": grid.groupby(["truncation", "aspect", "incidence"]).ngroups,
            "views": int(grid["n_views"].iloc[0]) if len(grid) else 0,
            "lights": off.groupby(["truncation", "aspect", "incidence", "light_azimuth"]).ngroups if len(off) else 0,
            "light_views": int(off["n_views"].max()) if len(off) else 0}


def validation_surfaces(plan: str = "full") -> list[tuple[Surface, float, str]]:
    """(surface, incidence, kind) of a plan: the grid surfaces at every incidence, then random triples.

    The random triples (``kind`` ``"random"``) are drawn with :data:`RANDOM_SEED`:
    truncation in [0.05, 1], aspect in [0.05, 1.2], incidence in [5, 85],
    each off the default grid's values.
    """
    size = comparison.plan_size(PLANS, plan, "implicit benchmark")
    out = [(Surface(t, a), float(i), "grid") for i in size["incidences"] for t, a in size["grid"]]
    rng = np.random.default_rng(RANDOM_SEED)
    while sum(kind == "random" for *_, kind in out) < size["random"]:
        t, a, i = rng.uniform(0.05, 1.0), rng.uniform(0.05, 1.2), rng.uniform(5.0, 85.0)
        on_grid = min(abs(t * 10 - round(t * 10)), abs(a * 10 - round(a * 10))) < 0.05
        if not on_grid:
            out.append((Surface(round(t, 4), round(a, 4)), round(i, 2), "random"))
    return out


def held_out_lights(plan: str = "full") -> list[tuple[Surface, float, float, np.ndarray, np.ndarray]]:
    """The validation's lights and views off every node: on each surface of :func:`validation_surfaces`, the
    plan's ``held_out["lights"]`` lights drawn at random (incidence uniform in :data:`HELD_OUT_INCIDENCE`, azimuth
    uniform in [0, 360)), each seen from ``held_out["views"]`` random views (azimuth uniform in [0, 360), elevation
    uniform in :data:`HELD_OUT_ELEVATION`), all drawn with :data:`HELD_OUT_SEED` before any model is measured.

    Returns
    -------
    list of (surface, incidence, light_azimuth, azimuth, elevation): degrees; ``azimuth`` and ``elevation`` are
    (views,) arrays of the study's view convention (:func:`roughlight.render.shading.view_direction`).
    """
    size = comparison.plan_size(PLANS, plan, "implicit benchmark")["held_out"]
    rng = np.random.default_rng(HELD_OUT_SEED)
    surfaces = list(dict.fromkeys(surface for surface, *_ in validation_surfaces(plan)))
    out = []
    for surface in surfaces:
        for _ in range(size["lights"]):
            incidence, light_azimuth = round(rng.uniform(*HELD_OUT_INCIDENCE), 2), round(rng.uniform(0.0, 360.0), 2)
            azimuth = rng.uniform(0.0, 360.0, size["views"])
            elevation = rng.uniform(*HELD_OUT_ELEVATION, size["views"])
            out.append((surface, float(incidence), float(light_azimuth), azimuth, elevation))
    return out


def _band(surface: Surface) -> str:
    if surface.truncation > 0.5 and surface.aspect > 0.5:
        return "t > 0.5, aspect > 0.5"
    return "other"


def validation(plan: str = "full", lighting=None, log=None, tables=None):
    """Errors against the exact reference on every view of each validation surface.

    ``tables``: share tables by (truncation, aspect) (:class:`roughlight.render.implicit.table.ShareTable`, or its
    file), for ``implicit_table``'s rows: the surfaces that have one (rule ``export``'s, ``export.surfaces``); with
    the ``full`` plan every other validation surface's is measured here (:func:`share_table`).

    Then the lights and views off every node (:func:`held_out_lights`): each surface under random lights from any
    azimuth, seen from random views, one row a light, method and component (``kind`` :data:`HELD_OUT`). The
    V-cavity model lights from azimuth 0 only and has no held-out rows.

    Returns
    -------
    pandas.DataFrame, one row per surface (or held-out light) x method x component: ``truncation``,
    ``aspect``, ``incidence``, ``light_azimuth`` (degrees), ``kind`` (grid | random | held out), ``band``, ``method``
    (:data:`VALIDATED`), ``component``, ``n_views`` (views with surface,
    0 < e < 180, that the reference could compute, each once: the zenith
    once, not once per azimuth), ``mae``, ``p99``,
    ``worst`` (0-255), ``seconds`` (the method's time for the sweep) and
    ``reference_failures`` (views where the exact reference's own check
    refused its clipping: left out of the comparison and counted here).
    """
    import pandas as pd

    size = comparison.plan_size(PLANS, plan, "implicit benchmark")
    log = log or (lambda message: None)
    azimuth, elevation = sweeps.view_grid(*size["steps"])
    rows = []
    surfaces = validation_surfaces(plan)
    tables = load_tables(tables)
    held_out = held_out_lights(plan)
    late = {surface: [] for surface, *_ in held_out}  # each surface's held-out rows, in held_out's order at the end
    last = {surface: n for n, (surface, *_) in enumerate(surfaces, 1)}
    read_later = {_key(FIELD_SURFACE)} | {_key(s) for s, _ in MAP_SURFACES}  # by frame_times and hemisphere_maps
    for n, (surface, incidence, kind) in enumerate(surfaces, 1):
        table = tables.get(_key(surface))
        if table is None and plan == "full":
            table = tables[_key(surface)] = share_table(surface, lighting, log)
        new = validate_surface(surface, incidence, kind, azimuth, elevation, lighting, table)
        rows += new
        worst = {m: max(r["worst"] for r in new if r["method"] == m) for m in ("implicit_exact", "fast")}
        log(f"[{n}/{len(surfaces)}] t={surface.truncation:g} aspect={surface.aspect:g} i={incidence:g}: "
            f"worst view exact form {worst['implicit_exact']:.2f}, fast {worst['fast']:.2f}")
        if last[surface] == n:  # its last light: its held-out lights now, then a table measured for it dropped
            late[surface] = _held_out_rows(surface, held_out, lighting, table)
            tables.drop_measured(_key(surface), keep=read_later)  # 22 MB at the default nodes
    rows += [row for parts in late.values() for row in parts]
    exact_worst = max([r["worst"] for r in rows if r["kind"] == HELD_OUT and r["method"] == "implicit_exact"], default=math.nan)
    log(f"{len(held_out)} held-out lights from any azimuth, {size['held_out']['views']} random views each: "
        f"worst view exact form {exact_worst:.2f}")
    return pd.DataFrame(rows)


def _held_out_rows(surface: Surface, held_out, lighting, table) -> list:
    """The validation's rows of ``surface``'s lights of ``held_out`` (:func:`held_out_lights`)."""
    return [row for s, i, psi, azimuth, elevation in held_out if s == surface
            for row in validate_surface(surface, i, HELD_OUT, azimuth, elevation, lighting, table, psi)]


def _key(surface: Surface) -> tuple[float, float]:
    return (round(float(surface.truncation), 9), round(float(surface.aspect), 9))


def load_tables(tables) -> dict:
    """``tables`` (a mapping (truncation, aspect) -> ShareTable or its file, or None) keyed by :func:`_key`, the
    files read; a mapping made so is returned as it is (:func:`validation` adds to it the tables it measures)."""
    from ..render.implicit import ShareTable, load_table

    if isinstance(tables, _Tables):
        return tables
    out = _Tables({_key(Surface(t, a)): table if isinstance(table, ShareTable) else load_table(table)
                   for (t, a), table in (tables or {}).items()})
    out.loaded = frozenset(out)
    return out


class _Tables(dict):
    """Share tables keyed by :func:`_key` (:func:`load_tables`): those given, and those :func:`validation` measures."""

    loaded: frozenset = frozenset()

    def drop_measured(self, key, keep=()) -> None:
        """Forget the table of ``key`` unless it was given or is in ``keep`` (one :func:`validation` is done with)."""
        if key not in self.loaded and key not in keep:
            self.pop(key, None)


def share_table(surface: Surface, lighting=None, log=None):
    """A validation surface's share table at the export's default nodes
    (:data:`roughlight.measurements.brdf_export.TABLE`), measured by the exact reference."""
    from .brdf_export import tabulate_surface

    (log or (lambda message: None))(f"share table of t {surface.truncation:g}, a {surface.aspect:g}")
    return tabulate_surface(surface, shadows=(lighting or shading.Lighting()).shadows)


#: Sweeps of the reference and the implicit models kept in a process (:func:`_sweep`).
_SWEEPS: dict = {}


def _sweep(method: str, surface: Surface, incidence: float, azimuth, elevation, lighting, table=None,
           light_azimuth: float = 0.0) -> dict:
    """``methods.sweep(method, ...)``, computed once per surface, light, views and lighting in a process: the
    validation and the hemisphere maps share their surfaces' sweeps where their plan's views are the same (the
    quick plan's full pyramid at incidence 30). The reference through :func:`roughlight.measurements.comparison.
    reference`'s cache. Shared between callers: read it, do not change it."""
    if method == "reference":
        return comparison.reference(surface, incidence, azimuth, elevation, lighting, light_azimuth=light_azimuth)
    azimuth, elevation = np.asarray(azimuth, float), np.asarray(elevation, float)
    key = (method, surface, float(incidence), azimuth.shape, azimuth.tobytes(), elevation.tobytes(), lighting,
           id(table), float(light_azimuth))
    if key not in _SWEEPS:
        if len(_SWEEPS) >= comparison.REFERENCE_CACHE_SIZE:
            _SWEEPS.clear()
        settings = {"table": table} if method == "implicit_table" else None
        _SWEEPS[key] = methods.sweep(method, surface, incidence, azimuth, elevation, lighting, settings,
                                     light_azimuth=light_azimuth)
    return _SWEEPS[key]


def validate_surface(surface: Surface, incidence: float, kind: str, azimuth, elevation, lighting=None,
                     table=None, light_azimuth: float = 0.0) -> list:
    """The validation's rows (dicts, columns of :func:`validation`) of one surface under the light at ``incidence``
    and ``light_azimuth`` (degrees) on the given views (``implicit_table``'s with the surface's share ``table``, when
    given; the V-cavity model's only for a light from azimuth 0, the only one it lights from)."""
    from ..render.exact import reference_views

    lighting = lighting or shading.Lighting()
    seen = sweeps.distinct_views(azimuth, elevation)  # rendered, each once: the zenith once, not once per azimuth
    # a view the reference's own checks refuse is left out of the comparison and counted
    try:
        exact = _sweep("reference", surface, incidence, azimuth, elevation, lighting, light_azimuth=light_azimuth)
        failed = np.zeros(np.size(azimuth), bool)
    except RuntimeError:
        exact, failed = reference_views(surface, incidence, azimuth, elevation, lighting, light_azimuth)
    seen &= ~failed
    results = {}
    for method in SWEPT:
        results[method] = _sweep(method, surface, incidence, azimuth, elevation, lighting, light_azimuth=light_azimuth)
    if table is not None:
        results["implicit_table"] = _sweep("implicit_table", surface, incidence, azimuth, elevation, lighting, table,
                                           light_azimuth)
    results["implicit_clipped"] = _sweep("implicit_clipped", surface, incidence, azimuth, elevation, lighting,
                                         light_azimuth=light_azimuth)
    if light_azimuth == 0.0:
        results["v_cavity"] = _v_cavity(surface, incidence, azimuth, elevation, lighting)
    from ..render.implicit import clipped_state_bytes

    # what a model holds a surface: the table's shares, the clipped scene's facets and light, else its uniforms alone
    held = {"implicit_clipped": clipped_state_bytes(surface, incidence, lighting.shadows, light_azimuth),
            **({"implicit_table": table.nbytes} if table is not None else {})}
    rows = []
    for method, out in results.items():
        memory = held.get(method, 0 if method in MODEL_METHODS else math.nan)
        for component, err in comparison.absolute_errors(out, exact, seen).items():
            rows.append({"truncation": surface.truncation, "aspect": surface.aspect, "incidence": incidence,
                         "light_azimuth": float(light_azimuth), "kind": kind, "band": _band(surface),
                         "method": method, "component": component,
                         "n_views": int(seen.sum()), **comparison.error_statistics(err),
                         "seconds": float(out["seconds"]), "reference_failures": int(failed.sum()),
                         "memory_bytes": memory})
    return rows


def _v_cavity(surface: Surface, incidence: float, azimuth, elevation, lighting) -> dict:
    """The V-cavity facet model's sweep (:func:`roughlight.analysis.surface_models.facet_model`, the light at
    azimuth 0), with its ``total`` and ``seconds``."""
    from ..analysis.surface_models import facet_model

    start = time.perf_counter()
    model = facet_model(surface.truncation, surface.aspect, incidence, elevation, azimuth, lighting.light,
                        lighting.shininess, lighting.diffuse_reflectance, lighting.specular_reflectance,
                        lighting.ambient, lighting.ambient_reflectance)
    model["total"] = model["diffuse"] + model["specular"]
    model["seconds"] = time.perf_counter() - start
    return model


#: The implicit models, by their methods' names; ``implicit_clipped``: the facet shares clipped exactly on the CPU
#: (in C) once a frame and drawn on one quad as the correction draws its own
#: (:func:`roughlight.render.implicit.shader.clipped_sweep`; a method of the registry, not of the study's grid).
MODEL_METHODS = ("implicit_exact", "implicit_correction", "implicit_table", "implicit_clipped")

#: The frame benchmark's other ways of drawing a model's scene, each with the method whose validation it shares:
#: the exact form with its shares once a frame (``render_field(frame_samples=...)`` at the sweep's own samples, so
#: the exact form's validation is its accuracy).
EXACT_ONCE_A_FRAME = "implicit_exact, shares once a frame"
FRAME_DRAWINGS = {EXACT_ONCE_A_FRAME: "implicit_exact"}

#: The thesis's goal for one flat quad (Ch. I.A, issue 45's numbers): every surface's total within this MAE and its
#: worst view within one 8-bit level of the exact reference, drawn this many times as fast as the explicit field.
GOAL = {"max_mae": 0.25, "worst": 1.0, "speedup": 100.0}


def goal(validation, frames) -> list[dict]:
    """Which implicit model meets the thesis's goal (:data:`GOAL`), at what cost: per model, its validated surfaces,
    the largest surface MAE and the worst view of the total, the table's bytes (0: the model is its uniforms), and
    its frame rate against the explicit field at the largest field of ``frames`` (mean frame times over the views).

    Returns
    -------
    list of dict, one a model validated and one a frame drawing of :data:`FRAME_DRAWINGS` timed (with its model's
    validation): ``method``, ``surfaces``, ``max_mae``, ``worst``, ``memory_bytes``,
    ``field``, ``frame_ms``, ``speedup``, ``draw_ms`` and ``draw_speedup`` (the drawing alone, without clear and
    read-back, :func:`frame_times`), ``accurate`` (both error goals), ``fast`` (the speed goal, on whole frames) and
    ``meets``.
    """
    out = []
    total = validation[validation["component"] == "total"]
    largest = int(frames["field"].max())
    at = frames[frames["field"] == largest].groupby("method")["frame_ms"].mean()
    drawn = (frames[frames["field"] == largest].groupby("method")["draw_ms"].mean() if "draw_ms" in frames
             else {})
    for method in MODEL_METHODS + tuple(FRAME_DRAWINGS):
        rows = total[total["method"] == FRAME_DRAWINGS.get(method, method)]
        if rows.empty or (method in FRAME_DRAWINGS and method not in at):
            continue
        frame = float(at.get(method, math.nan))
        speedup = float(at.get("explicit", math.nan)) / frame if frame > 0 else math.nan
        draw = float(drawn.get(method, math.nan))
        draw_speedup = float(drawn.get("explicit", math.nan)) / draw if draw > 0 else math.nan
        accurate = bool(rows["mae"].max() <= GOAL["max_mae"] and rows["worst"].max() <= GOAL["worst"])
        fast = bool(speedup >= GOAL["speedup"])
        memory = rows["memory_bytes"].max() if "memory_bytes" in rows else math.nan
        out.append({"method": method, "surfaces": int(len(rows)), "max_mae": float(rows["mae"].max()),
                    "worst": float(rows["worst"].max()), "memory_bytes": float(memory), "field": largest,
                    "frame_ms": frame, "speedup": speedup, "draw_ms": draw, "draw_speedup": draw_speedup,
                    "accurate": accurate, "fast": fast,
                    "meets": accurate and fast})
    return out


def summary(table):
    """Per method and component: median and largest surface MAE, largest p99 and the worst view.

    Also per band (``t > 0.5, aspect > 0.5`` and the rest) and over the held-out lights and views alone
    (:data:`HELD_OUT_BAND`; ``surfaces`` there counts lights). Returns a DataFrame.
    """
    import pandas as pd

    parts = []
    groups = [("all", table)] + list(table.groupby("band"))
    if "kind" in table and (table["kind"] == HELD_OUT).any():
        groups.append((HELD_OUT_BAND, table[table["kind"] == HELD_OUT]))
    for band, rows in groups:
        g = rows.groupby(["method", "component"], sort=False)
        part = g.agg(median_mae=("mae", "median"), max_mae=("mae", "max"), max_p99=("p99", "max"),
                     worst=("worst", "max"), surfaces=("mae", "size")).reset_index()
        part.insert(0, "band", band)
        parts.append(part)
    return pd.concat(parts, ignore_index=True)


class _Field:
    """An N x N field drawn explicitly by pyrender: the mesh, one directional light with its shadow
    map (redrawn every frame, as pyrender does), an orthographic camera; programs compiled once."""

    def __init__(self, surface: Surface, incidence: float, lighting, field_size: int, size: int, span: float):
        from ..render.naive import CompiledShaders, NaiveScene, look_pose

        self.look_pose = look_pose
        self.scene = NaiveScene(surface, incidence, lighting, (size, size), field_size, span)
        # the patch is centred on the origin; the implicit field spans [0, N]^2 (same surface, shifted
        # by whole periods when N is even)
        from ..render.gl import offscreen_renderer, release_contexts

        release_contexts()
        self.renderer = offscreen_renderer(size, size)
        self.renderer._renderer._program_cache = CompiledShaders()
        self.triangles = int(field_size * field_size * len(period_triangles(surface)[0]))

    def render(self, view, phases: dict | None = None):
        """The frame along ``view``: its picture and seconds; ``phases`` (a dict) receives ``read``, pyrender's
        read-back of the picture (its colour and depth read, with its blit where it draws into a framebuffer object;
        timed again right after the frame), and ``draw``, the rest (shadow pass and draw)."""
        pyrender = self.scene.pyrender
        from ..render.naive import up_vector

        pose = self.look_pose(view, up_vector(view), self.scene.distance)
        self.scene.scene.set_pose(self.scene.camera_node, pose)
        flags = pyrender.RenderFlags.SHADOWS_DIRECTIONAL if self.scene.shadows else pyrender.RenderFlags.NONE
        start = time.perf_counter()
        color, _ = self.renderer.render(self.scene.scene, flags=flags)
        seconds = time.perf_counter() - start
        if phases is not None:
            phases["read"] = self._read_again(flags)
            phases["draw"] = seconds - phases["read"]
        return color, seconds

    def _read_again(self, flags) -> float:
        """Seconds of pyrender's read-back of the frame just drawn, done again as its offscreen renderer does it:
        from its framebuffer object where the platform has them (EGL), else colour and depth from the default one
        (OSMesa)."""
        platform, renderer = self.renderer._platform, self.renderer._renderer
        platform.make_current()
        start = time.perf_counter()
        if platform.supports_framebuffers():
            renderer._read_main_framebuffer(self.scene.scene, flags | self.scene.pyrender.RenderFlags.OFFSCREEN)
        else:
            renderer.read_depth_buf()
            renderer.read_color_buf()
        seconds = time.perf_counter() - start
        platform.make_uncurrent()
        return seconds

    def delete(self):
        self.renderer.delete()


#: The surface of the frame-time fields: the full pyramid of aspect 1 (the thesis's runs).
FIELD_SURFACE = Surface(1.0, 1.0)


def frame_times(plan: str = "full", surface: Surface = FIELD_SURFACE, incidence: float = 30.0,
                size: int = 512, lighting=None, log=None, pictures: dict | None = None, tables=None):
    """Frame time of an N x N field drawn explicitly against one implicit quad, same views and image size.

    The picture shows the field's central ``N / 2`` periods (the field fills
    it down to elevation 30). Each frame's value is the mean of the total
    channel over the picture; its error is against the exact mean over the
    infinite surface (:func:`roughlight.render.exact.reference.reference_sweep`).

    Returns
    -------
    pandas.DataFrame, one row per field size x method x view: ``field``
    (N), ``method`` (``explicit``, ``implicit_exact``, ``implicit_correction``, and ``implicit_table`` where
    ``tables`` (as :func:`validation` takes them) holds the surface's: its textures are uploaded before the timer,
    as a scene keeps them),
    ``triangles``, ``elevation``, ``azimuth``, ``frame_ms`` (fastest of the
    plan's repeats), ``fps``, ``draw_ms`` (that frame's drawing alone: the passes that draw, without the clear and
    the picture's read-back; the explicit field's without pyrender's read-back), ``read_ms`` (its read-back),
    ``mean_total``, ``exact_total``, ``error``.
    ``pictures``, when a dict is given, receives the pictures (total, 8-bit,
    (size, size)) of the smallest field at the first view, by method: the
    thesis's own test, "if it looks good, it is good".
    """
    import pandas as pd

    size_plan = comparison.plan_size(PLANS, plan, "implicit benchmark")
    lighting = lighting or shading.Lighting()
    log = log or (lambda message: None)
    views = size_plan["frame_views"]
    el = np.array([v[0] for v in views])
    az = np.array([v[1] for v in views])
    exact = methods.sweep("reference", surface, incidence, az, el, lighting)["total"]
    repeats = size_plan["repeats"]
    table = load_tables(tables).get(_key(surface))
    rows = []
    pictures = {} if pictures is None else pictures
    for n in size_plan["fields"]:
        kept = pictures if n == size_plan["fields"][0] else None
        rows += explicit_frames(surface, incidence, lighting, n, size, views, repeats, exact, kept)
        for model in ("exact", "correction", "clipped") + (("table",) if table is not None else ()):
            rows += implicit_frames(model, surface, incidence, lighting, n, size, views, repeats, exact, kept,
                                     table)
        rows += implicit_frames("exact", surface, incidence, lighting, n, size, views, repeats, exact, None,
                                 frame_samples=methods.settings("implicit_exact").pixels, method=EXACT_ONCE_A_FRAME)
        last = [r for r in rows if r["field"] == n]
        log(f"N={n}: explicit {np.mean([r['frame_ms'] for r in last if r['method'] == 'explicit']):.1f} ms, "
            f"implicit exact {np.mean([r['frame_ms'] for r in last if r['method'] == 'implicit_exact']):.1f} ms")
    return pd.DataFrame(rows)


def fastest_frame(render, repeats: int):
    """Call ``render(phases=...)`` (-> picture, seconds) once to warm up, then ``repeats`` times: the last picture,
    the fastest time (seconds) and that frame's phases (a dict of seconds, :func:`render_field`'s)."""
    render(phases={})  # warm up
    best, picture, fastest = math.inf, None, {}
    for _ in range(repeats):
        phases = {}
        picture, seconds = render(phases=phases)
        if seconds < best:
            best, fastest = seconds, phases
    return picture, best, fastest


def explicit_frames(surface, incidence, lighting, n: int, size: int, views, repeats: int, exact, pictures) -> list:
    """:func:`frame_times`' rows of the explicit ``n`` x ``n`` field, one a view ((elevation, azimuth), degrees;
    ``exact`` the reference's total at each). ``pictures`` (a dict or None) receives the first view's total.
    The field's pyrender context is released after its frames."""
    from ..render.gl import release_contexts

    field = _Field(surface, incidence, lighting, n, size, n / 2.0)
    rows = []
    for k, (e, phi) in enumerate(views):
        color, seconds, phases = fastest_frame(partial(field.render, shading.view_direction(e, phi)), repeats)
        rows.append(_frame_row(n, "explicit", field.triangles, e, phi, seconds, color[..., 2], exact[k], phases))
        if pictures is not None and k == 0:
            pictures["explicit"] = color[..., 2].copy()
    field.delete()
    release_contexts()
    return rows


def implicit_frames(model: str, surface, incidence, lighting, n: int, size: int, views, repeats: int, exact,
                     pictures, table=None, frame_samples=None, method=None) -> list:
    """:func:`frame_times`' rows of the ``n`` x ``n`` field drawn as one implicit quad with ``model`` (see
    :func:`explicit_frames`), named ``method`` (default ``implicit_{model}``); ``frame_samples``: the exact form's
    shares once a frame (:func:`roughlight.render.implicit.shader.render_field`)."""
    from ..render.implicit import render_field

    rows = []
    method = method or f"implicit_{model}"
    for k, (e, phi) in enumerate(views):
        draw = partial(render_field, model, surface, incidence, e, phi, n, size, n / 2.0, lighting,
                       table=table if model == "table" else None, frame_samples=frame_samples)
        image, seconds, phases = fastest_frame(draw, repeats)
        rows.append(_frame_row(n, method, 2, e, phi, seconds, image[..., 2], exact[k], phases))
        if pictures is not None and k == 0:
            pictures[method] = image[..., 2].copy()
    return rows


def _frame_row(n, method, triangles, elevation, azimuth, seconds, channel, exact, phases):
    mean = float(np.asarray(channel, float).mean())
    return {"field": int(n), "method": method, "triangles": int(triangles), "elevation": float(elevation),
            "azimuth": float(azimuth), "frame_ms": 1000.0 * seconds, "fps": 1.0 / seconds if seconds > 0 else math.inf,
            "draw_ms": 1000.0 * (phases["draw"] + phases.get("first_pass", 0.0) + phases.get("shares", 0.0)),
            "read_ms": 1000.0 * phases["read"], "mean_total": mean, "exact_total": float(exact),
            "error": abs(mean - float(exact))}


#: Telling surfaces of the hemisphere maps: the thesis's full pyramid and its 30-degree facets, at incidence 30.
MAP_SURFACES = ((Surface(1.0, 1.0), 30.0), (Surface(1.0, SQRT3_2), 30.0))


def hemisphere_maps(plan: str = "full", lighting=None, tables=None):
    """Every view of the telling surfaces by the exact reference and both implicit models (through the shader).

    Returns
    -------
    pandas.DataFrame: ``truncation``, ``aspect``, ``incidence``, ``azimuth``,
    ``elevation``, ``method`` (``reference``, ``implicit_exact``,
    ``implicit_correction``, and ``implicit_table`` where ``tables``, as :func:`validation` takes them, holds the
    surface's) and the three components (0-255), on the plan's
    view grid; NaN at the views that were not rendered (coverage 0: e = 0 and 180, where the detector looks
    along the plane), which are no measurement and are not drawn (:func:`_rendered_values`).
    """
    import pandas as pd

    size = comparison.plan_size(PLANS, plan, "implicit benchmark")
    lighting = lighting or shading.Lighting()
    azimuth, elevation = sweeps.view_grid(*size["steps"])
    parts = []
    tables = load_tables(tables)
    for surface, incidence in MAP_SURFACES:
        table = tables.get(_key(surface))
        for method in ("reference", "implicit_exact", "implicit_correction", "implicit_table"):
            if method == "implicit_table" and table is None:
                continue
            out = _sweep(method, surface, incidence, azimuth, elevation, lighting, table)
            parts.append(pd.DataFrame({"truncation": surface.truncation, "aspect": surface.aspect,
                                       "incidence": incidence, "azimuth": azimuth, "elevation": elevation,
                                       "method": method, **_rendered_values(out, elevation)}))
    return pd.concat(parts, ignore_index=True)


def _rendered_values(out: dict, elevation) -> dict:
    """A sweep's components (component -> (n_views,) 0-255) with NaN at the views it did not render: coverage 0,
    and the grazing views (e = 0, 180) whatever they hold. ``out`` is left as it is (a cached sweep's)."""
    missing = (np.asarray(out["coverage"], float) <= 0) | sweeps.is_grazing(elevation)
    return {c: np.where(missing, np.nan, np.asarray(out[c], float)) for c in shading.COMPONENTS}
