"""Where methods fail: each method against the exact reference, knob by knob.

The thesis (Ch. IV) saw, but never measured, pixelation and aliasing of the
finely sampled pyramids ("flashing lines" as the camera moved), values
clipped at 255 bending the lobes (its Fig. 17), and trouble at grazing views
and low incidence. This module measures those failures on a few surfaces and
coarse view sets, for the ``naive`` method (the thesis's procedure in
pyrender, :func:`roughlight.rendering.naive_sweep`) and the ``fast`` method
(:func:`roughlight.rendering.render_sweep`), always against the exact
reference (:func:`roughlight.reference.reference_sweep`).

Every measurement returns a long pandas frame with the columns

``experiment`` (str), ``method`` (str), ``variable`` (name of the swept
knob), ``x`` (its value, float), ``setting`` (str, the other knob held
fixed, "" when none), ``component`` (``diffuse``, ``specular``, ``total`` or
``all``), ``metric`` (str) and ``value`` (float).

Metrics: ``mae`` (mean absolute error against the reference, 0-255 scale,
over the surfaces and views), ``max_error`` (0-255), ``jitter_sd`` (standard
deviation of a view's value over sub-pixel camera jitters, 0-255, averaged
over views and surfaces), ``coverage`` (mean fraction of the capture window
showing the surface), ``clipped_fraction`` (fraction of views whose total has
a pixel clamped at 255), ``peak_shift`` / ``centre_shift`` (degrees of
elevation a lobe's peak / intensity-weighted centre moves from source 127 to
source 255) and ``peak_ratio`` (lobe peak at 255 over twice the peak at 127).
"""

from __future__ import annotations

import base64
import html
import math
import time

import numpy as np
import pandas as pd

from . import reference, rendering, shading

__all__ = [
    "TOLERANCE",
    "SURFACES",
    "pixel_sweep",
    "elevation_sweep",
    "shadow_sweep",
    "shininess_sweep",
    "clipping_sweep",
    "run_all",
    "safe_domain",
    "plot_stability",
    "report_section",
]

#: Largest mean absolute error (0-255 scale, each component) counted as "within tolerance".
TOLERANCE = 0.5
COMPONENTS = ("diffuse", "specular", "total")
#: Surfaces (truncation, aspect, incidence): half and full pyramids of aspect 1 (the thesis's).
SURFACES = ((0.5, 1.0, 30.0), (1.0, 1.0, 30.0))
FAST_PIXELS = (2, 3, 4, 6, 8, 12, 16, 24, 32)
NAIVE_PIXELS = (0.25, 0.5, 1.0, 2.0, 4.0, 10.0, 32.0)
GRAZING = (0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 45.0, 90.0)
INCIDENCES = (1.0, 2.0, 5.0, 10.0, 20.0, 45.0)
BIASES = (0.0, 1e-6, 1e-4, 1e-2, 1e-1)
MAP_SIZES = (16, 32, 64, 128, 256, 512, 1024, 2048)
SHININESS = (1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0)


def _views(elevations, azimuths):
    a, e = np.meshgrid(np.asarray(azimuths, float), np.asarray(elevations, float), indexing="ij")
    return a.ravel(), e.ravel()


def _jitters(n, seed=0):
    """``n`` seeded sub-pixel camera shifts (pixels), uniform in [-0.5, 0.5)^2."""
    return [tuple(j) for j in np.random.default_rng(seed).uniform(-0.5, 0.5, (n, 2))]


def _rows(experiment, method, variable, x, setting, errors, extra=None):
    """Rows for one (method, x, setting): errors is {component: concatenated |error|}."""
    rows = []
    for c, err in errors.items():
        err = np.asarray(err, float)
        rows.append(dict(experiment=experiment, method=method, variable=variable, x=float(x), setting=setting,
                         component=c, metric="mae", value=float(err.mean())))
        rows.append(dict(experiment=experiment, method=method, variable=variable, x=float(x), setting=setting,
                         component=c, metric="max_error", value=float(err.max())))
    for metric, value in (extra or {}).items():
        rows.append(dict(experiment=experiment, method=method, variable=variable, x=float(x), setting=setting,
                         component="all", metric=metric, value=float(value)))
    return rows


def _naive_periods(view_periods, min_sine, capture=40, window=400):
    """Patch side (periods, odd) covering the capture window down to an elevation of sine ``min_sine``."""
    capture_periods = view_periods * capture / window
    return int(2 * math.ceil(capture_periods / min_sine / 2.0 + 2)) + 1


def pixel_sweep(surfaces=SURFACES[1:], fast_pixels=FAST_PIXELS, naive_pixels=NAIVE_PIXELS, n_jitter=4,
                naive_jitter_pixels=(1.0, 2.0, 10.0), lighting=None, fast_views=None, naive_views=None, seed=0):
    """Error and jitter spread against pixels per period (pixelation, aliasing, "flashing lines").

    Parameters
    ----------
    surfaces : sequence of (truncation, aspect, incidence)
    fast_pixels : ints >= 2
        ``RenderSettings.pixels_per_period`` of the fast method (its tile is one
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

    Returns
    -------
    Long frame (module docstring): ``mae``/``max_error`` of the unjittered
    render, ``jitter_sd`` (0-255, 'total', averaged over views) and ``coverage``.
    """
    lighting = lighting or shading.Lighting()
    fast_views = fast_views if fast_views is not None else _views((20, 45, 70, 90, 110, 135, 160), (0, 45, 90))
    naive_views = naive_views if naive_views is not None else (np.array([0.0, 0.0, 90.0]), np.array([90.0, 60.0, 60.0]))
    jitters = _jitters(n_jitter, seed)
    rows = []
    for method, pixels, views in (("fast", fast_pixels, fast_views), ("naive", naive_pixels, naive_views)):
        az, el = views
        min_sine = float(np.min(np.sin(np.radians(el))))
        truths = [reference.reference_sweep(t, a, i, az, el, lighting) for (t, a, i) in surfaces]
        for p in pixels:
            def run(jitter, surface):
                t, a, i = surface
                if method == "fast":
                    settings = rendering.RenderSettings(pixels_per_period=int(p), jitter=jitter)
                    return rendering.render_sweep(t, a, i, az, el, lighting, settings)
                vp = 400.0 / p
                return rendering.naive_sweep(t, a, i, az, el, lighting, view_periods=vp,
                                             periods=_naive_periods(vp, min_sine), jitter=jitter)

            errors = {c: [] for c in COMPONENTS}
            coverage, spread = [], []
            for surface, truth in zip(surfaces, truths):
                out = run((0.0, 0.0), surface)
                for c in COMPONENTS:
                    errors[c].append(np.abs(out[c] - truth[c]))
                coverage.append(out["coverage"])
                if method == "fast" or p in naive_jitter_pixels:
                    values = np.array([run(j, surface)["total"] for j in jitters])
                    spread.append(values.std(axis=0))
            extra = {"coverage": np.concatenate(coverage).mean()}
            if spread:
                extra["jitter_sd"] = np.concatenate(spread).mean()
            rows += _rows("pixels", method, "pixels_per_period", p, "",
                          {c: np.concatenate(v) for c, v in errors.items()}, extra)
    return pd.DataFrame(rows)


def elevation_sweep(surfaces=SURFACES, elevations=GRAZING, azimuths=(0.0, 30.0, 60.0, 90.0, 120.0, 150.0),
                    lighting=None, methods=("fast", "naive")):
    """Error and coverage against view elevation down to grazing.

    ``x`` is the elevation above the horizon, degrees: views at e and at the
    mirror 180 - e are pooled. The naive method runs as it comes (10 pixels a
    period, its patch sized for views down to 10 degrees), so below that its
    capture window runs off the patch (coverage < 1).
    """
    lighting = lighting or shading.Lighting()
    rows = []
    for x in elevations:
        el = np.unique([x, 180.0 - x])
        az, e = _views(el, azimuths)
        truths = [reference.reference_sweep(t, a, i, az, e, lighting) for (t, a, i) in surfaces]
        for method in methods:
            errors = {c: [] for c in COMPONENTS}
            coverage = []
            for (t, a, i), truth in zip(surfaces, truths):
                out = rendering.measure_sweep(method, t, a, i, az, e, lighting)
                for c in COMPONENTS:
                    errors[c].append(np.abs(out[c] - truth[c]))
                coverage.append(out["coverage"])
            rows += _rows("elevation", method, "elevation", x, "", {c: np.concatenate(v) for c, v in errors.items()},
                          {"coverage": np.concatenate(coverage).mean()})
    return pd.DataFrame(rows)


def shadow_sweep(surfaces=SURFACES, incidences=INCIDENCES, biases=BIASES, map_sizes=MAP_SIZES, lighting=None,
                 views=None, naive=True):
    """Shadow acne and peter-panning against incidence, shadow bias and shadow-map size.

    Fast: every ``shadow_bias`` (map 512) at every incidence
    (experiment ``shadow_bias``, x = incidence, setting ``bias=...``) and every
    ``shadow_map_size`` (bias default) at every incidence (experiment
    ``shadow_map``, x = map size, setting ``i=...``). Naive: pyrender's fixed
    2048^2 shadow map (experiment ``shadow_bias``, setting ``naive``).
    """
    lighting = lighting or shading.Lighting()
    az, el = views if views is not None else _views((30, 60, 90, 120, 150), (0, 30, 60, 90, 120, 150))
    rows = []
    for inc in incidences:
        truths = [reference.reference_sweep(t, a, inc, az, el, lighting) for (t, a, _) in surfaces]

        def errors_of(run):
            errs = {c: [] for c in COMPONENTS}
            for (t, a, _), truth in zip(surfaces, truths):
                out = run(t, a)
                for c in COMPONENTS:
                    errs[c].append(np.abs(out[c] - truth[c]))
            return {c: np.concatenate(v) for c, v in errs.items()}

        for b in biases:
            s = rendering.RenderSettings(shadow_bias=b)
            rows += _rows("shadow_bias", "fast", "incidence", inc, f"bias={b:g}",
                          errors_of(lambda t, a: rendering.render_sweep(t, a, inc, az, el, lighting, s)))
        for size in map_sizes:
            s = rendering.RenderSettings(shadow_map_size=int(size))
            rows += _rows("shadow_map", "fast", "shadow_map_size", size, f"i={inc:g}",
                          errors_of(lambda t, a: rendering.render_sweep(t, a, inc, az, el, lighting, s)))
        if naive:
            rows += _rows("shadow_bias", "naive", "incidence", inc, "naive",
                          errors_of(lambda t, a: rendering.naive_sweep(t, a, inc, az, el, lighting)))
    return pd.DataFrame(rows)


def shininess_sweep(surfaces=SURFACES, shininess=SHININESS, lighting=None, views=None, methods=("fast", "naive")):
    """Error against the specular exponent (``Lighting(shininess=...)``, 1-128)."""
    base = (lighting or shading.Lighting()).as_dict()
    az, el = views if views is not None else _views((45, 90, 120, 150), (0, 30))
    rows = []
    for z in shininess:
        lighting = shading.Lighting(**{**base, "shininess": float(z)})
        truths = [reference.reference_sweep(t, a, i, az, el, lighting) for (t, a, i) in surfaces]
        for method in methods:
            errs = {c: [] for c in COMPONENTS}
            for (t, a, i), truth in zip(surfaces, truths):
                out = rendering.measure_sweep(method, t, a, i, az, el, lighting)
                for c in COMPONENTS:
                    errs[c].append(np.abs(out[c] - truth[c]))
            rows += _rows("shininess", method, "shininess", z, "", {c: np.concatenate(v) for c, v in errs.items()})
    return pd.DataFrame(rows)


def _lobes(elevation, values, split=90.0):
    """(peak elevation, centre elevation, peak value) of the back (e < split) and forward lobes."""
    out = {}
    for name, mask in (("back", elevation < split), ("forward", elevation > split)):
        e, v = elevation[mask], values[mask]
        w = np.clip(v - v.min(), 0.0, None)
        centre = float((w * e).sum() / w.sum()) if w.sum() > 0 else float("nan")
        out[name] = (float(e[np.argmax(v)]), centre, float(v.max()))
    return out


def clipping_sweep(surfaces=((0.0, 0.0, 30.0),) + SURFACES + ((1.0, 0.8660254037844386, 30.0),), lights=(127.0, 255.0),
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
    for (t, a, i) in surfaces:
        name = f"t{t:g}_a{a:.3g}_i{i:g}"
        lobes = {}
        for light in lights:
            lighting = shading.Lighting(**{**base, "light": float(light)})
            q = reference.reference_sweep(t, a, i, az, el, lighting, quantized=True)
            raw = reference.reference_sweep(t, a, i, az, el, lighting, quantized=False)
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


def run_all(lighting=None, log=None) -> pd.DataFrame:
    """Every measurement at its default (small) size, concatenated long frame."""
    log = log or (lambda message: None)
    frames = []
    for name, fn in (("pixels", pixel_sweep), ("elevation", elevation_sweep), ("shadows", shadow_sweep),
                     ("shininess", shininess_sweep), ("clipping", clipping_sweep)):
        start = time.perf_counter()
        frames.append(fn(lighting=lighting))
        log(f"{name}: {time.perf_counter() - start:.1f} s")
    return pd.concat(frames, ignore_index=True)


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
    of that sweep), ``jitter_sd_at_min_pixels`` (0-255), ``min_elevation``
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
        pix = _worst(frame, "pixels", method)
        p_min = _safe_from(pix, tol)
        jit = frame[(frame["experiment"] == "pixels") & (frame["method"] == method) & (frame["metric"] == "jitter_sd")]
        jit = jit.set_index("x")["value"].sort_index()
        row = {
            "method": method,
            "min_pixels_per_period": p_min,
            "best_mae_pixels": float(pix.min()) if len(pix) else np.nan,
            "jitter_sd_at_min_pixels": float(jit.get(p_min, np.nan)) if np.isfinite(p_min) else np.nan,
            "min_elevation": _safe_from(_worst(frame, "elevation", method), tol),
            "best_mae_elevation": float(_worst(frame, "elevation", method).min()),
            "min_incidence": _safe_from(_worst(frame, "shadow_bias", method,
                                               "naive" if method == "naive" else f"bias={rendering.RenderSettings().shadow_bias:g}"), tol),
            "max_shininess": _safe_up_to(_worst(frame, "shininess", method), tol),
            "best_mae_shininess": float(_worst(frame, "shininess", method).min()),
        }
        if method == "fast":
            sb = frame[(frame["experiment"] == "shadow_bias") & (frame["method"] == "fast") & (frame["metric"] == "mae")]
            worst = sb.groupby("setting")["value"].max()
            row["shadow_bias_ok"] = ", ".join(s.split("=")[1] for s in worst.index[worst <= tol]) or "none"
            sm = frame[(frame["experiment"] == "shadow_map") & (frame["metric"] == "mae")]
            sm = sm.groupby(["setting", "x"])["value"].max().unstack("x").sort_index(axis=1)
            # incidences where even the largest map is out of tolerance are not the map's fault
            sm = sm[sm.iloc[:, -1] <= tol] if sm.shape[1] else sm
            row["min_shadow_map_size"] = _safe_from(sm.max(axis=0), tol) if len(sm) else np.nan
        else:
            row["shadow_bias_ok"] = "fixed (pyrender)"
            row["min_shadow_map_size"] = np.nan
        fails = []
        for experiment, label in (("pixels", "ppp"), ("elevation", "elevation"), ("shininess", "shininess")):
            curve = _worst(frame, experiment, method)
            bad = [f"{x:g}" for x, v in curve.items() if v > tol]
            if bad:
                fails.append(f"{label} {','.join(bad)}")
        setting = "naive" if method == "naive" else f"bias={rendering.RenderSettings().shadow_bias:g}"
        curve = _worst(frame, "shadow_bias", method, setting)
        bad = [f"{x:g}" for x, v in curve.items() if v > tol]
        if bad:
            fails.append(f"incidence {','.join(bad)}")
        row["outside_tolerance"] = "; ".join(fails) or "none"
        rows.append(row)
    return pd.DataFrame(rows)


def plot_stability(frames, path) -> None:
    """Six panels: worst-component MAE against pixels per period, jitter spread, elevation,
    incidence by shadow bias, shadow-map size and shininess; plus the clipped lobes."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import seaborn as sns

    frame = frames if isinstance(frames, pd.DataFrame) else pd.concat(list(frames), ignore_index=True)
    sns.set_theme(style="whitegrid")
    fig, axes = plt.subplots(2, 4, figsize=(20, 9))
    floor = 1e-2

    def worst(experiment, by=("method", "setting", "x")):
        d = frame[(frame["experiment"] == experiment) & (frame["metric"] == "mae")]
        d = d.groupby(list(by), as_index=False)["value"].max()
        d["value"] = d["value"].clip(lower=floor)
        return d

    def tol_line(ax):
        ax.axhline(TOLERANCE, ls=":", c="k", lw=1)

    ax = axes[0, 0]
    sns.lineplot(data=worst("pixels"), x="x", y="value", hue="method", marker="o", ax=ax)
    ax.set(xscale="log", yscale="log", xlabel="pixels per period", ylabel="worst-component MAE (0-255)",
           title="pixelation / aliasing")
    tol_line(ax)
    ax = axes[0, 1]
    d = frame[(frame["experiment"] == "pixels") & (frame["metric"] == "jitter_sd")].copy()
    d["value"] = d["value"].clip(lower=floor)
    sns.lineplot(data=d, x="x", y="value", hue="method", marker="o", ax=ax)
    ax.set(xscale="log", yscale="log", xlabel="pixels per period", ylabel="SD over sub-pixel jitter (0-255)",
           title="flashing lines: jitter spread of total")
    tol_line(ax)
    ax = axes[0, 2]
    sns.lineplot(data=worst("elevation"), x="x", y="value", hue="method", marker="o", ax=ax)
    ax.set(xscale="log", yscale="log", xlabel="view elevation above horizon (deg, e and 180-e)",
           ylabel="worst-component MAE", title="grazing views")
    tol_line(ax)
    d = frame[(frame["experiment"] == "elevation") & (frame["metric"] == "coverage")]
    ax2 = ax.twinx()
    sns.lineplot(data=d, x="x", y="value", hue="method", ls="--", legend=False, ax=ax2)
    ax2.set(ylabel="coverage (dashed)", ylim=(0, 1.05))
    ax2.grid(False)
    ax = axes[0, 3]
    sns.lineplot(data=worst("shadow_bias"), x="x", y="value", hue="setting", marker="o", ax=ax)
    ax.set(xscale="log", yscale="log", xlabel="incidence (deg)", ylabel="worst-component MAE",
           title="shadow acne / peter-panning (fast by bias; naive)")
    tol_line(ax)
    ax = axes[1, 0]
    sns.lineplot(data=worst("shadow_map"), x="x", y="value", hue="setting", marker="o", ax=ax)
    ax.set(xscale="log", yscale="log", xlabel="fast shadow map (texels per period)", ylabel="worst-component MAE",
           title="shadow-map resolution by incidence")
    tol_line(ax)
    ax = axes[1, 1]
    sns.lineplot(data=worst("shininess"), x="x", y="value", hue="method", marker="o", ax=ax)
    ax.set(xscale="log", yscale="log", xlabel="shininess", ylabel="worst-component MAE", title="specular exponent")
    tol_line(ax)
    ax = axes[1, 2]
    d = frame[(frame["experiment"] == "clipping") & (frame["metric"] == "curve")].copy()
    d["surface"] = d["setting"].str.split(" ").str[0]
    d["source"] = d["setting"].str.split(" ").str[1]
    sns.lineplot(data=d, x="x", y="value", hue="surface", style="source", ax=ax)
    ax.axhline(255, c="r", lw=1)
    ax.set(xlabel="view elevation at azimuth 0 (deg)", ylabel="total (0-255)", title="clipping at 255 (Fig. 17)")
    ax = axes[1, 3]
    d = frame[(frame["experiment"] == "clipping") & frame["metric"].isin(["peak_shift", "centre_shift"])].copy()
    sns.barplot(data=d, y="setting", x="value", hue="metric", orient="h", ax=ax)
    ax.set(xlabel="lobe shift, source 127 -> 255 (deg elevation)", ylabel="", title="how far clipping moves the lobes")
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def _fmt(v):
    if isinstance(v, str):
        return html.escape(v)
    if v is None or (isinstance(v, float) and not np.isfinite(v)):
        return "never"
    return f"{v:.3g}"


def report_section(tables: dict, figure_png_path) -> str:
    """HTML fragment for the report: the safe-domain table, the figure, what fails where.

    Parameters
    ----------
    tables : dict
        ``"safe_domain"``: the frame of :func:`safe_domain`; optionally
        ``"stability"``: the long frame (for the clipping numbers).
    figure_png_path : path of the PNG from :func:`plot_stability`.
    """
    safe = tables["safe_domain"]
    if not isinstance(safe, pd.DataFrame):
        safe = pd.DataFrame(safe)
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in safe.columns)
    body = "".join("<tr>" + "".join(f"<td>{_fmt(v)}</td>" for v in row) + "</tr>" for row in safe.itertuples(index=False))
    with open(figure_png_path, "rb") as fh:
        data = base64.b64encode(fh.read()).decode("ascii")
    clip_text = ""
    long = tables.get("stability")
    if long is not None:
        cf = long[(long["experiment"] == "clipping") & (long["metric"] == "clipped_fraction")]
        parts = [f"{s} at {x:g}: {v:.0%}" for s, x, v in zip(cf["setting"], cf["x"], cf["value"])]
        clip_text = " Fraction of views (azimuth 0) with the total clipped: " + html.escape("; ".join(parts)) + "."
    return (
        '<section id="stability"><h2>Where methods fail</h2>'
        f"<p>Each method against the exact reference on a few surfaces and coarse view sets. The table gives, per "
        f"method, the domain where the mean absolute error stays within {TOLERANCE} on the 0&ndash;255 scale for "
        "every component (diffuse, specular, total); &ldquo;never&rdquo; means no tested value was within tolerance "
        "(the best_mae columns then say how close it came).</p>"
        f'<table class="stability"><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>'
        f'<figure><img alt="stability" src="data:image/png;base64,{data}" style="max-width:100%">'
        "<figcaption>Worst-component MAE against pixels per period, jitter spread, view elevation, incidence "
        "(by shadow bias), shadow-map size and shininess; the dotted line is the tolerance. Bottom right: "
        "the total in the light's plane at source 127 and 255, and how far each lobe moves.</figcaption></figure>"
        "<p>What fails where. The naive procedure (pyrender as it comes: 10 pixels a period, a finite patch, "
        "one render per view) aliases: at whole numbers of pixels per period every pixel samples the same "
        "point of the period and a sub-pixel shift of the camera moves the value by tens of levels (the "
        "thesis's &ldquo;flashing lines&rdquo; and pixelation, Ch. IV); its patch, sized for views above 10&deg;, "
        "runs out at grazing views (coverage below 1); its fixed shadow map and pyramid edges leave errors of a "
        "few levels even at its best. The fast method needs at least 2 pixels a period by construction (its "
        "tile is one period) and converges as the pixels grow; a shadow bias of 0 gives shadow acne and a large one "
        "peter-panning (lost shadows) at low incidence. Clipping at 255, which the thesis avoided by using a "
        "source of 127 after seeing it bend its lobes (Fig. 17), flattens the forward lobe's peak and moves its "
        f"centre.{clip_text}</p></section>"
    )
