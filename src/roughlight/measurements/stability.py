"""Where methods fail: each method against the exact reference, knob by knob.

The thesis (Ch. IV) saw, but never measured, pixelation and aliasing of the
finely sampled pyramids ("flashing lines" as the camera moved), values
clipped at 255 bending the lobes (its Fig. 17), and trouble at grazing views
and low incidence. This module measures those failures on a few surfaces and
coarse view sets, for the ``naive`` method (the thesis's procedure in
pyrender, :func:`roughlight.render.naive.procedure.naive_sweep`) and the ``fast`` method
(:func:`roughlight.render.fast.periodic.fast_sweep`), always against the exact
reference (:func:`roughlight.measurements.comparison.reference`). Each measurement is
a *scan*: one knob varied over its values (a *sweep* is one surface seen from
every view). Its chart is drawn by :mod:`roughlight.report.figures` and its report
section written by :mod:`roughlight.report.page`.

Every measurement returns a long pandas frame with the columns

``experiment`` (str), ``method`` (str), ``variable`` (name of the scanned
knob), ``x`` (its value, float), ``setting`` (str, the other knob held
fixed, "" when none), ``component`` (``diffuse``, ``specular``, ``total`` or
``all``), ``metric`` (str) and ``value`` (float).

Metrics: ``mae`` (mean absolute error against the reference, 0-255 scale,
over the surfaces and views), ``max_error`` (0-255), ``jitter_sd`` (standard
deviation of a view's value over sub-pixel camera jitters, 0-255, averaged
over views and surfaces), ``coverage`` (mean fraction of the capture window
showing the surface; means over a scan's views count each view once:
:func:`roughlight.render.views.distinct_views`), ``clipped_fraction`` (fraction of views whose total has
a pixel clamped at 255), ``peak_shift`` / ``centre_shift`` (degrees of
elevation a lobe's peak / intensity-weighted centre moves from source 127 to
source 255) and ``peak_ratio`` (lobe peak at 255 over twice the peak at 127).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..render import methods as registry
from ..render import shading
from ..render.shading import COMPONENTS, SHADINGS
from ..render.views import distinct_views
from ..surfaces.surface import PLATE, SQRT3_2, Surface
from . import comparison

__all__ = [
    "TOLERANCE",
    "SURFACES",
    "pixel_scan",
    "elevation_scan",
    "shadow_scan",
    "shininess_scan",
    "normals_scan",
    "normals_pictures",
    "clipping_scan",
    "MEASUREMENTS",
    "run_measurement",
    "JOBS",
    "run_job",
    "safe_domain",
    "normals_table",
]

#: Largest mean absolute error (0-255 scale, each component) counted as "within tolerance".
TOLERANCE = 0.5
#: Surfaces under a light, (Surface, incidence), the fast method is measured on: the thesis's
#: aspect-1 quarter, half and full pyramids, a low half pyramid, the 30-degree facets
#: (aspect sqrt(3)/2, its side facets facing a light at incidence 30) and a wide low mesa.
SURFACES = ((Surface(0.25, 1.0), 30.0), (Surface(0.5, 1.0), 30.0), (Surface(1.0, 1.0), 30.0),
            (Surface(0.5, 0.5), 30.0), (Surface(1.0, SQRT3_2), 30.0), (Surface(0.8, 0.3), 30.0))
#: The naive method's surfaces (the thesis's half and full pyramids of aspect 1): it renders
#: one view at a time (about 18 views/s) and is outside tolerance everywhere on these already.
NAIVE_SURFACES = ((Surface(0.5, 1.0), 30.0), (Surface(1.0, 1.0), 30.0))
#: Which surfaces each method is measured on (a plain sequence given to a scan serves every method).
PLAN = {"fast": SURFACES, "naive": NAIVE_SURFACES}
FAST_PIXELS = (2, 3, 4, 6, 8, 12, 16, 20, 24, 28, 32, 48)
NAIVE_PIXELS = (0.25, 0.5, 1.0, 2.0, 4.0, 10.0, 32.0)
GRAZING = (0.5, 1.0, 2.0, 3.0, 5.0, 10.0, 20.0, 45.0, 90.0)
#: View azimuths of the elevation scan (degrees): every 15 for fast, every 30 for naive.
AZIMUTHS = {"fast": tuple(np.arange(0.0, 180.0, 15.0)), "naive": tuple(np.arange(0.0, 180.0, 30.0))}
INCIDENCES = (1.0, 2.0, 5.0, 10.0, 20.0, 45.0)
BIASES = (0.0, 1e-6, 1e-4, 1e-2, 1e-1)
MAP_SIZES = (16, 32, 64, 128, 256, 512, 1024, 2048)
SHININESS = (1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0)
#: The surfaces of the shading-normals measurement: averaged vertex normals matter where
#: facets meet at an angle, so every one has sloped sides.
NORMALS_SURFACES = SURFACES[:4]


# The renderers load OpenGL: imported when a scan renders (the registry imports a method's sweep on first use), so
# that importing this module (the workflow reads MEASUREMENTS while it parses) does not.
def _render_picture(*args, **kwargs):
    from ..render.naive import render_picture

    return render_picture(*args, **kwargs)


def _for(plan, method):
    """``plan[method]`` when ``plan`` is a per-method dict, else ``plan`` itself."""
    return plan[method] if isinstance(plan, dict) else plan


def _views(elevations, azimuths):
    a, e = np.meshgrid(np.asarray(azimuths, float), np.asarray(elevations, float), indexing="ij")
    return a.ravel(), e.ravel()


def _jitters(n, seed=0):
    """``n`` seeded sub-pixel camera shifts (pixels), uniform in [-0.5, 0.5)^2."""
    return [tuple(j) for j in np.random.default_rng(seed).uniform(-0.5, 0.5, (n, 2))]


def _compare(surfaces, azimuth, elevation, lighting, run):
    """``run(surface, incidence)`` against the reference (:func:`roughlight.measurements.comparison.reference`)
    on every (Surface, incidence) of ``surfaces``.

    Returns ({component: |error| over every surface's views, 0-255}, mean coverage, [outputs]): over the views
    each once (:func:`roughlight.render.views.distinct_views`).
    """
    truths, outputs = [], []
    for surface, incidence in surfaces:
        truths.append(comparison.reference(surface, incidence, azimuth, elevation, lighting))
        outputs.append(run(surface, incidence))
    seen = distinct_views(azimuth, elevation)
    coverage = float(np.concatenate([np.asarray(out["coverage"])[seen] for out in outputs]).mean())
    return comparison.pooled_errors(zip(outputs, truths), seen), coverage, outputs


def _rows(experiment, method, variable, x, setting, errors, extra=None, per_component=None):
    """Rows for one (method, x, setting): ``errors`` is {component: concatenated |error|};
    ``extra`` {metric: value} (component 'all'); ``per_component`` {metric: {component: value}}."""
    base = dict(experiment=experiment, method=method, variable=variable, x=float(x), setting=setting)
    rows = []
    for c, err in errors.items():
        statistics = comparison.error_statistics(err, ("mae", "worst"))
        rows.append({**base, "component": c, "metric": "mae", "value": statistics["mae"]})
        rows.append({**base, "component": c, "metric": "max_error", "value": statistics["worst"]})
    for metric, value in (extra or {}).items():
        rows.append({**base, "component": "all", "metric": metric, "value": float(value)})
    for metric, values in (per_component or {}).items():
        for c, value in values.items():
            rows.append({**base, "component": c, "metric": metric, "value": float(value)})
    return rows


def pixel_scan(surfaces=PLAN, fast_pixels=FAST_PIXELS, naive_pixels=NAIVE_PIXELS, n_jitter=4,
                naive_jitter_pixels=(1.0, 2.0, 10.0), lighting=None, fast_views=None, naive_views=None, seed=0):
    """Error and jitter spread against pixels per period (pixelation, aliasing, "flashing lines").

    Parameters
    ----------
    surfaces : sequence of (Surface, incidence), or {method: sequence}
        Default :data:`PLAN` (fast on :data:`SURFACES`, naive on :data:`NAIVE_SURFACES`).
    fast_pixels : ints >= 2
        ``pixels_per_period`` of the fast method (its tile is one
        period, so fewer than 2 pixels a period is not a valid setting).
    naive_pixels : floats, pixels per period
        The naive method's 400-pixel window spans ``400 / ppp`` periods (below 1:
        several pyramids per pixel). Its patch is sized to cover the capture
        window at the views' lowest elevation.
    n_jitter : int
        Seeded sub-pixel camera shifts per setting (uniform in [-0.5, 0.5) px).
    naive_jitter_pixels : floats
        The naive settings whose jitter spread is measured (each costs
        ``n_jitter`` renders a view).
    fast_views, naive_views : (azimuth, elevation) arrays, degrees
        Default: fast 9 elevations x 6 azimuths; naive 3 views (one render each).

    Returns
    -------
    Long frame (module docstring): ``mae``/``max_error`` of the unjittered
    render, ``jitter_sd`` (0-255, 'total', averaged over views) and ``coverage``.
    """
    lighting = lighting or shading.Lighting()
    if fast_views is None:
        fast_views = _views((10, 20, 45, 70, 90, 110, 135, 160, 170), (0, 30, 60, 90, 120, 150))
    naive_views = naive_views if naive_views is not None else (np.array([0.0, 0.0, 90.0]), np.array([90.0, 60.0, 60.0]))
    jitters = _jitters(n_jitter, seed)
    rows = []
    for method, pixels, views in (("fast", fast_pixels, fast_views), ("naive", naive_pixels, naive_views)):
        az, el = (np.asarray(v, float) for v in views)
        lowest = float(np.min(el))
        for p in pixels:
            def run(surface, i, jitter=(0.0, 0.0), method=method, p=p, az=az, el=el, lowest=lowest):
                if method == "fast":
                    settings = registry.settings("fast", {"pixels_per_period": int(p), "jitter": jitter})
                else:  # the 400-pixel window spans 400 / p periods
                    settings = registry.settings("naive", {"view_periods": 400.0 / p, "lowest_elevation": lowest,
                                                         "jitter": jitter})
                return registry.sweep(method, surface, i, az, el, lighting, settings)

            errors, coverage, _ = _compare(_for(surfaces, method), az, el, lighting, run)
            extra = {"coverage": coverage}
            if method == "fast" or p in naive_jitter_pixels:
                spread = [np.std([run(*s, jitter=j)["total"] for j in jitters], axis=0)[distinct_views(az, el)]
                          for s in _for(surfaces, method)]
                extra["jitter_sd"] = np.concatenate(spread).mean()
            rows += _rows("pixels", method, "pixels_per_period", p, "", errors, extra)
    return pd.DataFrame(rows)


def elevation_scan(surfaces=PLAN, elevations=GRAZING, azimuths=AZIMUTHS, lighting=None, methods=("fast", "naive")):
    """Error and coverage against view elevation down to grazing.

    ``x`` is the elevation above the horizon, degrees: views at e and at the
    mirror 180 - e are pooled, at every azimuth of ``azimuths`` (a sequence, or
    {method: sequence}). The naive method runs as it comes (10 pixels a
    period, its patch sized for views down to 10 degrees), so below that its
    capture window runs off the patch (coverage < 1).
    """
    lighting = lighting or shading.Lighting()
    rows = []
    for x in elevations:
        for method in methods:
            az, el = _views(np.unique([x, 180.0 - x]), _for(azimuths, method))
            errors, coverage, _ = _compare(
                _for(surfaces, method), az, el, lighting,
                lambda surface, i, method=method, az=az, el=el, lighting=lighting:
                registry.sweep(method, surface, i, az, el, lighting))
            rows += _rows("elevation", method, "elevation", x, "", errors, {"coverage": coverage})
    return pd.DataFrame(rows)


def shadow_scan(surfaces=PLAN, incidences=INCIDENCES, biases=BIASES, map_sizes=MAP_SIZES, lighting=None,
                 views=None, naive=True):
    """Shadow acne and peter-panning against incidence, shadow bias and shadow-map size.

    Fast: every ``shadow_bias`` (map 512) at every incidence
    (experiment ``shadow_bias``, x = incidence, setting ``bias=...``) and every
    ``shadow_map_size`` (bias default) at every incidence (experiment
    ``shadow_map``, x = map size, setting ``i=...``). Naive: pyrender's fixed
    2048^2 shadow map (experiment ``shadow_bias``, setting ``naive``). The
    surfaces' own incidences are replaced by each of ``incidences``.
    """
    lighting = lighting or shading.Lighting()
    az, el = views if views is not None else _views((30, 60, 90, 120, 150), (0, 30, 60, 90, 120, 150))
    az, el = np.asarray(az, float), np.asarray(el, float)
    rows = []
    for inc in incidences:
        def at(method, inc=inc):
            return [(surface, inc) for (surface, _) in _for(surfaces, method)]

        # (experiment, variable, x, setting, fast renderer's settings)
        plan = [("shadow_bias", "incidence", inc, f"bias={b:g}", registry.settings("fast", {"shadow_bias": b})) for b in biases]
        plan += [("shadow_map", "shadow_map_size", size, f"i={inc:g}", registry.settings("fast", {"shadow_map_size": int(size)}))
                 for size in map_sizes]
        for experiment, variable, x, setting, s in plan:
            errors, _, _ = _compare(at("fast"), az, el, lighting,
                                    lambda surface, i, s=s: registry.sweep("fast", surface, i, az, el, lighting, s))
            rows += _rows(experiment, "fast", variable, x, setting, errors)
        if naive:
            errors, _, _ = _compare(at("naive"), az, el, lighting,
                                    lambda surface, i: registry.sweep("naive", surface, i, az, el, lighting))
            rows += _rows("shadow_bias", "naive", "incidence", inc, "naive", errors)
    return pd.DataFrame(rows)


def shininess_scan(surfaces=PLAN, shininess=SHININESS, lighting=None, views=None, methods=("fast", "naive")):
    """Error against the specular exponent (``Lighting(shininess=...)``, 1-128)."""
    base = (lighting or shading.Lighting()).as_dict()
    az, el = views if views is not None else _views((45, 90, 120, 150, 165), (0, 30))
    az, el = np.asarray(az, float), np.asarray(el, float)
    rows = []
    for z in shininess:
        lighting = shading.Lighting(**{**base, "shininess": float(z)})
        for method in methods:
            errors, _, _ = _compare(_for(surfaces, method), az, el, lighting,
                                    lambda surface, i, method=method, az=az, el=el, lighting=lighting:
                registry.sweep(method, surface, i, az, el, lighting))
            rows += _rows("shininess", method, "shininess", z, "", errors)
    return pd.DataFrame(rows)


def normals_scan(surfaces=NORMALS_SURFACES, models=SHADINGS, lighting=None, views=None):
    """Shading on faceted geometry: true face normals against averaged vertex normals.

    The naive method with each ``shading_model`` (``flat``: the study's true
    face normals; ``gouraud``: lighting at the vertices with averaged normals,
    interpolated; ``phong``: averaged normals interpolated, lighting per
    pixel), experiment ``normals``, ``x`` the model's index in ``models``,
    ``setting`` its name. Per component: ``mae``/``max_error`` against the
    reference; ``mae_vs_flat`` against the same renderer with flat normals
    (what the averaged normals alone change, the sampling error taken out);
    ``highlight_ratio`` (component ``specular``): the brightest specular view
    over the reference's, averaged over surfaces (below 1: highlights missed,
    Gouraud's failure in the shading notes).

    Views default to elevations 10..170 by 10 at azimuths 0, 45 and 90.
    """
    lighting = lighting or shading.Lighting()
    az, el = views if views is not None else _views(np.arange(10.0, 171.0, 10.0), (0, 45, 90))
    az, el = np.asarray(az, float), np.asarray(el, float)
    rows, flat = [], None
    for k, model in enumerate(models):
        errors, _, outputs = _compare(
            surfaces, az, el, lighting,
            lambda surface, i, model=model: registry.sweep("naive", surface, i, az, el, lighting,
                                                          {"shading_model": model}))
        if model == "flat":
            flat = outputs
        per = {}
        if flat is not None:
            per["mae_vs_flat"] = {c: comparison.error_statistics(err, ("mae",))["mae"] for c, err in
                                  comparison.pooled_errors(zip(outputs, flat), distinct_views(az, el)).items()}
        ratios = []
        for (surface, incidence), out in zip(surfaces, outputs):
            peak = float(np.max(comparison.reference(surface, incidence, az, el, lighting)["specular"]))
            if peak > 0.5:
                ratios.append(float(np.max(out["specular"])) / peak)
        per["highlight_ratio"] = {"specular": np.mean(ratios) if ratios else np.nan}
        rows += _rows("normals", "naive", "shading", k, model, errors, per_component=per)
    return pd.DataFrame(rows)


def normals_pictures(surface=NORMALS_SURFACES[1][0], incidence=30.0, elevation=60.0, azimuth=20.0, models=SHADINGS,
                     lighting=None, size=(240, 180), periods=3):
    """Pictures of one surface under each shading model ({model: (H, W, 3) uint8}, total)."""
    return {m: _render_picture(surface, incidence, elevation, azimuth, lighting, size=size, periods=periods,
                                    shading_model=m) for m in models}


def _lobes(elevation, values, split=90.0):
    """(peak elevation, centre elevation, peak value) of the back (e < split) and forward lobes."""
    out = {}
    for name, mask in (("back", elevation < split), ("forward", elevation > split)):
        e, v = elevation[mask], values[mask]
        w = np.clip(v - v.min(), 0.0, None)
        centre = float((w * e).sum() / w.sum()) if w.sum() > 0 else float("nan")
        out[name] = (float(e[np.argmax(v)]), centre, float(v.max()))
    return out


def clipping_scan(surfaces=((PLATE, 30.0),) + SURFACES, lights=(127.0, 255.0),
                   elevation_step=2.0, lighting=None):
    """Where clipping at 255 bends the lobes (thesis Fig. 17): source 127 against 255.

    Views in the light's plane (azimuth 0, elevation 1..179). A view's total
    counts as clipped when its 8-bit mean (clamped per facet, the
    framebuffer) falls more than 0.5 below the unclamped mean. Lobe peak and
    centre (intensity-weighted elevation above the lobe's minimum) of the
    total, back lobe (e < 90) and forward lobe (e > 90); ``setting`` names the
    surface. Returns also the curves (metric ``curve``: x = elevation, one
    row per light in ``setting`` "t.._a.._i.. J=..", component ``total``).
    """
    base = (lighting or shading.Lighting()).as_dict()
    el = np.arange(1.0, 179.0 + 1e-9, elevation_step)
    az = np.zeros_like(el)
    rows = []
    for (surface, i) in surfaces:
        name = f"t{surface.truncation:g}_a{surface.aspect:.3g}_i{i:g}"
        lobes = {}
        for light in lights:
            lighting = shading.Lighting(**{**base, "light": float(light)})
            q = registry.sweep("reference", surface, i, az, el, lighting, {"quantized": True})
            raw = registry.sweep("reference", surface, i, az, el, lighting, {"quantized": False})
            clipped = (raw["total"] - q["total"]) > 0.5
            rows.append(dict(experiment="clipping", method="reference", variable="light", x=light, setting=name,
                             component="total", metric="clipped_fraction", value=float(clipped.mean())))
            for e, v in zip(el, q["total"]):
                rows.append(dict(experiment="clipping", method="reference", variable="elevation", x=float(e),
                                 setting=f"{name} J={light:g}", component="total", metric="curve", value=float(v)))
            lobes[light] = _lobes(el, np.asarray(q["total"], float))
        low, high = lobes[lights[0]], lobes[lights[-1]]
        scale = lights[-1] / lights[0]
        for lobe in ("back", "forward"):
            for metric, value in (("peak_shift", high[lobe][0] - low[lobe][0]),
                                  ("centre_shift", high[lobe][1] - low[lobe][1]),
                                  ("peak_ratio", high[lobe][2] / (scale * low[lobe][2]) if low[lobe][2] > 0 else np.nan)):
                rows.append(dict(experiment="clipping", method="reference", variable="lobe", x=0.0 if lobe == "back" else 1.0,
                                 setting=f"{name} {lobe}", component="total", metric=metric, value=float(value)))
    return pd.DataFrame(rows)


def tile_pixel_scan(lighting=None, **sizes) -> pd.DataFrame:
    """The random tiles' sampling against pixels a cell (:func:`roughlight.measurements.random_tiles.tile_pixel_scan`)."""
    from .random_tiles import tile_pixel_scan as scan

    return scan(lighting=lighting, **sizes)


#: The measurements, by name (the workflow runs them in the jobs :data:`JOBS` names).
MEASUREMENTS = {
    "pixels": pixel_scan,
    "elevation": elevation_scan,
    "shadows": shadow_scan,
    "shininess": shininess_scan,
    "normals": normals_scan,
    "clipping": clipping_scan,
    "tiles": tile_pixel_scan,
}


#: The quick plan's surfaces: the thesis's half and full pyramids (fast) and its half pyramid (naive).
QUICK_SURFACES = {"fast": SURFACES[1:3], "naive": NAIVE_SURFACES[:1]}
#: The smoke plan's surfaces: the thesis's full pyramid, for each method.
SMOKE_SURFACES = {"fast": SURFACES[2:3], "naive": NAIVE_SURFACES[1:]}

#: Sizes of the measurements, by name (``measurements.plan`` in the config): ``full`` is ``make bench``'s
#: (every measurement at its defaults above); ``quick`` runs the same code on fewer surfaces, settings and
#: views, sized for the default workflow's "Where methods fail" section; ``smoke`` the same code on one surface and
#: two or three values a knob (a check that a config builds the whole report, in seconds; its numbers are not for
#: reading).
PLANS = {
    "full": {name: {} for name in MEASUREMENTS},
    "quick": {
        "pixels": {"surfaces": QUICK_SURFACES, "fast_pixels": (4, 8, 16, 24, 32), "naive_pixels": (10.0,),
                   "n_jitter": 2, "naive_jitter_pixels": ()},
        "elevation": {"surfaces": QUICK_SURFACES, "elevations": (1.0, 5.0, 20.0, 90.0),
                      "azimuths": {"fast": (0.0, 60.0, 120.0), "naive": (0.0, 90.0)}},
        "shadows": {"surfaces": QUICK_SURFACES, "incidences": (5.0, 45.0), "biases": (0.0, 1e-4),
                    "map_sizes": (32, 512)},
        "shininess": {"surfaces": QUICK_SURFACES, "shininess": (4.0, 64.0)},
        "normals": {"surfaces": NORMALS_SURFACES[1:2], "views": _views((30.0, 60.0, 90.0, 120.0, 150.0), (0.0, 90.0))},
        "clipping": {"surfaces": ((PLATE, 30.0),) + SURFACES[1:3], "elevation_step": 4.0},
        "tiles": {"kinds": ("random_pyramids",), "pixels": (4, 8, 16)},
    },
    "smoke": {
        "pixels": {"surfaces": SMOKE_SURFACES, "fast_pixels": (8, 16), "naive_pixels": (10.0,), "n_jitter": 2,
                   "naive_jitter_pixels": ()},
        "elevation": {"surfaces": SMOKE_SURFACES, "elevations": (5.0, 90.0), "azimuths": {"fast": (0.0,), "naive": (0.0,)}},
        "shadows": {"surfaces": SMOKE_SURFACES, "incidences": (45.0,), "biases": (0.0, 1e-4), "map_sizes": (32, 512)},
        "shininess": {"surfaces": SMOKE_SURFACES, "shininess": (64.0,)},
        "normals": {"surfaces": NORMALS_SURFACES[1:2], "views": _views((60.0, 120.0), (0.0,))},
        "clipping": {"surfaces": ((PLATE, 30.0), SURFACES[2]), "elevation_step": 10.0},
        "tiles": {"kinds": ("random_pyramids",), "pixels": (8, 16)},
    },
}


def plan_surfaces(plan: str = "full") -> dict:
    """The (Surface, incidence) pairs each method is measured on in a plan: {method: tuple} (the pixel scan's, and
    the normals scan's as ``normals``)."""
    size = comparison.plan_size(PLANS, plan, "stability")
    return {**size["pixels"].get("surfaces", PLAN), "normals": size["normals"].get("surfaces", NORMALS_SURFACES)}


def run_measurement(name, lighting=None, plan: str = "full") -> pd.DataFrame:
    """One measurement of :data:`MEASUREMENTS` at the size of ``plan`` (:data:`PLANS`; long frame)."""
    if name not in MEASUREMENTS:
        raise ValueError(f"no stability measurement {name!r}: one of {', '.join(MEASUREMENTS)}")
    return MEASUREMENTS[name](lighting=lighting, **comparison.plan_size(PLANS, plan, "stability")[name])


#: The jobs of the workflow's rule ``stability_measurement`` at each plan, one file each
#: (``results/stability/{plan}/measurements/{job}.parquet``): a measurement's name runs that measurement, ``all``
#: every one in one process (:func:`run_job`). ``full``: one job a measurement (minutes each: both cores busy, and
#: an interrupted run keeps the scans already written); ``quick``: one job for all (seconds each, about what a
#: job's own start-up costs: the interpreter, the imports, the OpenGL context, the renderers' shaders).
JOBS = {"full": tuple(MEASUREMENTS), "quick": ("all",), "smoke": ("all",)}


def run_job(job, lighting=None, plan: str = "full") -> pd.DataFrame:
    """One job of :data:`JOBS`: the measurement ``job`` names, or ``all`` of them in :data:`MEASUREMENTS`' order,
    at the size of ``plan`` (:func:`run_measurement`), as one long frame."""
    names = tuple(MEASUREMENTS) if job == "all" else (job,)
    return pd.concat([run_measurement(name, lighting, plan) for name in names], ignore_index=True)


def _worst(frame, experiment, method, setting=None):
    """Worst component MAE per x (sorted) for one experiment and method."""
    sel = (frame["experiment"] == experiment) & (frame["method"] == method) & (frame["metric"] == "mae")
    if setting is not None:
        sel &= frame["setting"] == setting
    curve = frame[sel].groupby("x")["value"].max().sort_index()
    return curve


def _safe_from(curve, tol=TOLERANCE):
    """Smallest x from which every larger x is within tolerance (NaN: never)."""
    ok = (curve <= tol).to_numpy()
    if len(ok) == 0 or not ok[-1]:
        return float("nan")
    k = len(ok) - 1
    while k > 0 and ok[k - 1]:
        k -= 1
    return float(curve.index[k])


def _safe_up_to(curve, tol=TOLERANCE):
    """Largest x up to which every smaller x is within tolerance (NaN: never)."""
    ok = (curve <= tol).to_numpy()
    if len(ok) == 0 or not ok[0]:
        return float("nan")
    k = 0
    while k < len(ok) - 1 and ok[k + 1]:
        k += 1
    return float(curve.index[k])


def safe_domain(frames, tol=TOLERANCE) -> pd.DataFrame:
    """One row per method: the domain where its worst-component MAE stays <= ``tol`` (0-255).

    Columns (NaN: no tested value is within tolerance, or not measured):
    ``min_pixels_per_period`` (and ``best_mae_pixels``, the lowest worst-component MAE
    of that sweep; the random tiles' rows, one per kind and sampling, give only these,
    per cell), ``jitter_sd_at_min_pixels`` (0-255), ``min_elevation``
    (degrees above the horizon, pooled with the mirror view),
    ``min_incidence`` (degrees; fast at its default bias 1e-4, naive with
    pyrender's map), ``shadow_bias_ok`` (fast: the biases within tolerance at
    every tested incidence), ``min_shadow_map_size`` (fast: texels a period,
    at every tested incidence where the largest map is within tolerance),
    ``max_shininess``, ``outside_tolerance`` (the tested values, per knob,
    where the worst-component MAE exceeds ``tol``; fast's incidences at its
    default bias).
    """
    frame = frames if isinstance(frames, pd.DataFrame) else pd.concat(list(frames), ignore_index=True)
    rows = []
    for method in ("naive", "fast"):
        row = _sampling_domain(frame, method, tol)
        row.update(_fast_shadow_domain(frame, tol) if method == "fast" else _naive_shadow_domain(frame, tol))
        row["outside_tolerance"] = _outside_tolerance(frame, method, tol)
        rows.append(row)
    tiles = frame[frame["experiment"] == "tile_pixels"]
    for method in sorted(tiles["method"].unique()):  # the random tiles: pixels a cell only
        curve = _worst(frame, "tile_pixels", method)
        bad = [f"{x:g}" for x, v in curve.items() if v > tol]
        rows.append({"method": method, "min_pixels_per_period": _safe_from(curve, tol),
                     "best_mae_pixels": float(curve.min()), "outside_tolerance": f"ppc {','.join(bad)}" if bad else "none"})
    return pd.DataFrame(rows)


def _default_bias(method: str) -> str:
    """The ``shadow_bias`` experiment's setting of a method at its default bias (naive: pyrender's, fixed)."""
    return "naive" if method == "naive" else f"bias={registry.settings('fast').shadow_bias:g}"


def _sampling_domain(frame: pd.DataFrame, method: str, tol: float) -> dict:
    """:func:`safe_domain`'s limits of one method on the knobs both methods have: pixels per period (with the
    jitter there), elevation, incidence at the default bias and shininess, and the best MAEs (0-255)."""
    pix = _worst(frame, "pixels", method)
    p_min = _safe_from(pix, tol)
    jit = frame[(frame["experiment"] == "pixels") & (frame["method"] == method) & (frame["metric"] == "jitter_sd")]
    jit = jit.set_index("x")["value"].sort_index()
    return {
        "method": method,
        "min_pixels_per_period": p_min,
        "best_mae_pixels": float(pix.min()) if len(pix) else np.nan,
        "jitter_sd_at_min_pixels": float(jit.get(p_min, np.nan)) if np.isfinite(p_min) else np.nan,
        "min_elevation": _safe_from(_worst(frame, "elevation", method), tol),
        "best_mae_elevation": float(_worst(frame, "elevation", method).min()),
        "min_incidence": _safe_from(_worst(frame, "shadow_bias", method, _default_bias(method)), tol),
        "max_shininess": _safe_up_to(_worst(frame, "shininess", method), tol),
        "best_mae_shininess": float(_worst(frame, "shininess", method).min()),
    }


def _fast_shadow_domain(frame: pd.DataFrame, tol: float) -> dict:
    """The fast method's shadow knobs: the biases within ``tol`` at every tested incidence and the smallest
    shadow map (texels a period) within it wherever the largest map is; its one shading model."""
    sb = frame[(frame["experiment"] == "shadow_bias") & (frame["method"] == "fast") & (frame["metric"] == "mae")]
    worst = sb.groupby("setting")["value"].max()
    sm = frame[(frame["experiment"] == "shadow_map") & (frame["metric"] == "mae")]
    sm = sm.groupby(["setting", "x"])["value"].max().unstack("x").sort_index(axis=1)
    # incidences where even the largest map is out of tolerance are not the map's fault
    sm = sm[sm.iloc[:, -1] <= tol] if sm.shape[1] else sm
    return {"shadow_bias_ok": ", ".join(s.split("=")[1] for s in worst.index[worst <= tol]) or "none",
            "min_shadow_map_size": _safe_from(sm.max(axis=0), tol) if len(sm) else np.nan,
            "shading_ok": "flat (true face normals, the only model)"}


def _naive_shadow_domain(frame: pd.DataFrame, tol: float) -> dict:
    """The naive method's shadow knobs (pyrender's, fixed) and the shading models within ``tol`` of flat
    normals on every component (:func:`normals_table`)."""
    nt = normals_table(frame)
    if len(nt):
        worst = nt[[f"mae_vs_flat {c}" for c in COMPONENTS]].max(axis=1)
        ok = [m for m, v in worst.items() if m != "flat" and v <= tol]
        shading_ok = ", ".join(["flat"] + ok)
    else:
        shading_ok = "not measured"
    return {"shadow_bias_ok": "fixed (pyrender)", "min_shadow_map_size": np.nan, "shading_ok": shading_ok}


def _outside_tolerance(frame: pd.DataFrame, method: str, tol: float) -> str:
    """The tested values, per knob, where the method's worst-component MAE exceeds ``tol`` ('none' if none)."""
    fails = []
    for experiment, label in (("pixels", "ppp"), ("elevation", "elevation"), ("shininess", "shininess"),
                              ("shadow_bias", "incidence")):
        setting = _default_bias(method) if experiment == "shadow_bias" else None
        curve = _worst(frame, experiment, method, setting)
        bad = [f"{x:g}" for x, v in curve.items() if v > tol]
        if bad:
            fails.append(f"{label} {','.join(bad)}")
    return "; ".join(fails) or "none"


def normals_table(frames) -> pd.DataFrame:
    """One row per shading model (index): ``mae {component}`` against the reference,
    ``mae_vs_flat {component}`` against flat normals (0-255) and ``highlight_ratio``."""
    frame = frames if isinstance(frames, pd.DataFrame) else pd.concat(list(frames), ignore_index=True)
    d = frame[(frame["experiment"] == "normals") & frame["metric"].isin(["mae", "mae_vs_flat", "highlight_ratio"])]
    if not len(d):
        return pd.DataFrame()
    wide = d.pivot_table(index=["x", "setting"], columns=["metric", "component"], values="value", aggfunc="first")
    wide.columns = [m if m == "highlight_ratio" else f"{m} {c}" for m, c in wide.columns]
    wide = wide.reset_index(level="x", drop=True)
    wide.index.name = "shading"
    cols = [f"{m} {c}" for m in ("mae", "mae_vs_flat") for c in COMPONENTS] + ["highlight_ratio"]
    return wide[[c for c in cols if c in wide.columns]]
