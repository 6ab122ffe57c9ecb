"""Issue 58's held-out trial of the implicit models (the clipped scene among them), as a user calls them: three
surfaces off the study's grid, three random lights each (incidence 10-80, any azimuth) and 40 random views a light
(elevation 1-179, any azimuth), each model through ``methods.sweep(model, surface, incidence, azimuth, elevation,
light_azimuth=psi)`` with no settings, against the exact reference under the same light. Prints each model's MAE and
worst view by component.

Run: ``PYTHONPATH=src python tests/implicit_held_out.py`` (the table model measures each surface's table once, kept
in ``ROUGHLIGHT_TABLE_CACHE`` or ``~/.cache/roughlight/share_tables``). With ``--frames``: the frame times of the
explicit field at N 256 and 512 against each implicit quad (512 x 512 pixels, one view, the fastest of 3 frames;
whole frames, and the drawing alone without the clear and the read-back),
the exact form both ways: its rays a pixel, and its shares once a frame (``render_field(frame_samples=M)``). With
``--samples``: the exact form's worst view and largest MAE against the exact reference at 4,181 to 28,657 samples a
view, on a 3 x 10 degree view grid of six surfaces and lights. With ``--grazing``: how fast the exact facet shares
move with the view's azimuth near the horizon, where the table model's worst view lies (the held-out trial's: t 1,
a 0.7, light at incidence 63.39 and azimuth 205.2), and what linear interpolation between nodes 2.5 degrees apart
misses there. With ``--phases``: where the correction's, the clipped scene's and the exact form's once-a-frame frames
go (first pass or the CPU's shares, clear, draw, read-back) at 28,657 to 233 samples, N 512. With ``--clipped``:
what the clipped scene's shares cost on the CPU (the exact reference's clipping once a frame): a light's scene and a
view's shares, over four surfaces, four random lights each and 50 random views a light. With ``--full-plan``: the
clipped scene through ``methods.sweep("implicit_clipped", ...)`` against the exact reference on every surface, light
and view of the full plan's validation (rule implicit_surface's ``full`` plan: its grid and random surfaces at every
view of the 1 x 5 degree grid, and its held-out lights and views), in two processes: each sweep's MAE and worst view
by component (about 20 minutes).
"""

from __future__ import annotations

import os
import time
from functools import partial

os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from roughlight.render import methods, shading  # noqa: E402
from roughlight.render import views as sweeps  # noqa: E402
from roughlight.surfaces.surface import Surface  # noqa: E402

SURFACES = (Surface(0.35, 0.55), Surface(0.75, 0.9), Surface(1.0, 0.7))
MODELS = ("implicit_exact", "implicit_correction", "implicit_table", "implicit_clipped")


def trial(seed: int = 58) -> pd.DataFrame:
    """One row a model, surface, light, view and component: the model's value and the reference's."""
    rng = np.random.default_rng(seed)
    rows = []
    for surface in SURFACES:
        for _ in range(3):
            incidence, psi = float(rng.uniform(10, 80)), float(rng.uniform(0, 360))
            azimuth, elevation = rng.uniform(0, 360, 40), rng.uniform(1, 179, 40)
            exact = methods.sweep("reference", surface, incidence, azimuth, elevation, light_azimuth=psi)
            for model in MODELS:
                start = time.perf_counter()
                out = methods.sweep(model, surface, incidence, azimuth, elevation, light_azimuth=psi)
                seconds = time.perf_counter() - start
                for c in shading.COMPONENTS:
                    rows.append(pd.DataFrame({"model": model, "truncation": surface.truncation,
                                              "aspect": surface.aspect, "incidence": incidence, "light_azimuth": psi,
                                              "azimuth": azimuth, "elevation": elevation, "component": c,
                                              "value": out[c], "exact": exact[c], "seconds": seconds}))
    frame = pd.concat(rows, ignore_index=True)
    frame["error"] = (frame["value"] - frame["exact"]).abs()
    return frame


def frames(view=(60.0, 20.0), incidence: float = 30.0) -> pd.DataFrame:
    """Frame times (ms, the fastest of 3 after one to warm up) of the explicit field at N 256 and 512 and of each
    implicit quad, on the frame benchmark's surface (t 1, a 1), one view."""
    from roughlight.measurements import implicit_surface
    from roughlight.render.implicit import cached_table

    surface, (elevation, azimuth) = implicit_surface.FIELD_SURFACE, view
    exact = methods.sweep("reference", surface, incidence, [azimuth], [elevation])["total"]
    table = cached_table(surface)
    quads = {"implicit_exact, rays a pixel": ("exact", None), "implicit_correction": ("correction", None),
             "implicit_exact, shares once a frame (28,657 samples)": ("exact", 28657),
             "implicit_exact, shares once a frame (6,765 samples)": ("exact", 6765), "implicit_table": ("table", None),
             "implicit_clipped": ("clipped", None)}
    lighting, rows = shading.Lighting(), []
    for n in (256, 512):
        rows += implicit_surface.explicit_frames(surface, incidence, lighting, n, 512, [view], 3, exact, None)
        for name, (model, frame_samples) in quads.items():
            rows += implicit_surface.implicit_frames(model, surface, incidence, lighting, n, 512, [view], 3, exact,
                                                     None, table, frame_samples, name)
    rows = [{key: row[key] for key in ("field", "method", "frame_ms", "draw_ms")} for row in rows]
    out = pd.DataFrame(rows)
    for column, ratio in (("frame_ms", "speedup"), ("draw_ms", "draw_speedup")):
        out[ratio] = out.groupby("field")[column].transform(lambda ms: ms.iloc[0] / ms)
    return out


def phases(counts=(28657, 6765, 1597, 233), field: int = 512, view=(60.0, 20.0), repeats: int = 15) -> pd.DataFrame:
    """Where a quad's frame goes (ms, the fastest of ``repeats`` frames after one to warm up, each phase ended by
    ``glFinish``): the correction's and the exact form's once a frame at ``counts`` samples, on the frame
    benchmark's surface (t 1, a 1), an N ``field`` field, 512 x 512 pixels, one view."""
    from roughlight.measurements import implicit_surface
    from roughlight.render.implicit import render_field

    lighting, rows = shading.Lighting(), []
    quads = [("correction", {}), ("clipped", {}), *((f"exact form, {m:,} samples", {"frame_samples": m}) for m in counts)]
    for name, kwargs in quads:
        draw = partial(render_field, name if name in ("correction", "clipped") else "exact", implicit_surface.FIELD_SURFACE,
                       30.0, view[0], view[1], field, 512, field / 2.0, lighting, **kwargs)
        _, seconds, phased = implicit_surface.fastest_frame(draw, repeats)
        rows.append({"quad": name, "frame_ms": 1000.0 * seconds, **{f"{k}_ms": 1000.0 * v for k, v in phased.items()}})
    return pd.DataFrame(rows)


def samples_needed(counts=(4181, 6765, 10946, 28657)) -> pd.DataFrame:
    """The exact form's sweep at ``counts`` samples a view against the exact reference: its worst view and largest
    MAE (any component) over six surfaces and lights on a 3 x 10 degree view grid (1,062 views above the plane)."""
    from roughlight.render import views as sweeps
    from roughlight.surfaces.surface import SQRT3_2

    azimuth, elevation = sweeps.view_grid(3.0, 10.0)
    seen = ~sweeps.is_grazing(elevation)
    cases = [(Surface(1.0, 1.0), 30.0, 0.0), (Surface(0.1, 1.0), 10.0, 0.0), (Surface(1.0, SQRT3_2), 30.0, 0.0),
             (Surface(0.37, 0.63), 47.0, 0.0), (Surface(0.65, 0.8), 22.0, 200.0), (Surface(1.0, 0.5), 75.0, 20.0)]
    exact = [methods.sweep("reference", s, i, azimuth, elevation, light_azimuth=p) for s, i, p in cases]
    rows = []
    for count in counts:
        worst, mae = 0.0, 0.0
        for (surface, incidence, psi), reference in zip(cases, exact):
            out = methods.sweep("implicit_exact", surface, incidence, azimuth, elevation,
                                settings={"samples": count}, light_azimuth=psi)
            for c in shading.COMPONENTS:
                error = np.abs(out[c] - reference[c])[seen]
                worst, mae = max(worst, float(error.max())), max(mae, float(error.mean()))
        rows.append({"samples": count, "worst": worst, "max_mae": mae, "views": int(seen.sum())})
    return pd.DataFrame(rows)


def grazing(elevations=(1.79, 5.0, 15.0), step: float = 0.25, node_step: float = 2.5) -> pd.DataFrame:
    """At each view elevation, azimuths 290-310 every ``step`` degrees (around the held-out trial's worst view of the
    table): the largest change of the ten exact shares (summed) between neighbouring azimuths, and the largest
    error (summed over the shares) of linear interpolation between nodes ``node_step`` apart."""
    from roughlight.render.exact import LitScene, shares_under

    scene = LitScene(Surface(1.0, 0.7), 63.39, True, 205.2)
    azimuth = np.arange(290.0, 310.0 + 1e-9, step)
    every = int(round(node_step / step))
    rows = []
    for elevation in elevations:
        shares = np.array([np.concatenate([part[0] for part in shares_under([scene], elevation, phi)])
                           for phi in azimuth])
        nodes = np.arange(0, azimuth.size, every)
        between = np.array([np.interp(azimuth, azimuth[nodes], shares[nodes, c]) for c in range(shares.shape[1])]).T
        rows.append({"elevation": elevation, "largest_change_a_step": float(np.abs(np.diff(shares, axis=0)).sum(1).max()),
                     "largest_interpolation_error": float(np.abs(between - shares).sum(1).max())})
    return pd.DataFrame(rows)


def clipped(seed: int = 58) -> pd.DataFrame:
    """Milliseconds the clipped scene's shares take on the CPU (``render.implicit.clipped_shares``, clipped in C by
    ``render.exact.pyramid``): a light's first view, which makes the light's scene (kept while the light stays), and
    a view's shares under it (every frame whose view moves): the median, the 90th
    percentile and the largest, over four surfaces, four random lights each (incidence 5-85, any azimuth) and 50
    random views a light (elevation 1-179, any azimuth)."""
    from roughlight.render.implicit import clipped_shares

    rng = np.random.default_rng(seed)
    seconds = {"light's scene": [], "view's shares": []}
    for surface in (Surface(1.0, 1.0), Surface(0.5, 0.5), Surface(0.2, 1.0), Surface(0.8, 0.3)):
        for _ in range(4):
            incidence, psi = rng.uniform(5.0, 85.0), rng.uniform(0.0, 360.0)
            views = list(zip(rng.uniform(1.0, 179.0, 50), rng.uniform(0.0, 360.0, 50)))
            start = time.perf_counter()
            clipped_shares(surface, incidence, *views[0], True, psi)  # the light's scene made, then kept
            seconds["light's scene"].append(time.perf_counter() - start)
            for elevation, azimuth in views:
                start = time.perf_counter()
                clipped_shares(surface, incidence, elevation, azimuth, True, psi)
                seconds["view's shares"].append(time.perf_counter() - start)
    return pd.DataFrame([{"step": step, "count": len(s), "median_ms": 1e3 * np.median(s),
                          "p90_ms": 1e3 * np.percentile(s, 90), "max_ms": 1e3 * np.max(s)}
                         for step, s in seconds.items()])


def _full_plan_sweep(job) -> list[dict]:
    """One sweep of :func:`full_plan`: the clipped scene and the reference under one light, the errors by
    component."""
    surface, incidence, light_azimuth, azimuth, elevation, kind = job
    clipped = methods.sweep("implicit_clipped", surface, incidence, azimuth, elevation, light_azimuth=light_azimuth)
    exact = methods.sweep("reference", surface, incidence, azimuth, elevation, light_azimuth=light_azimuth)
    seen = ~sweeps.is_grazing(elevation)
    return [{"truncation": surface.truncation, "aspect": surface.aspect, "incidence": incidence,
             "light_azimuth": light_azimuth, "kind": kind, "component": name, "views": int(seen.sum()),
             "mae": float(np.abs(clipped[name] - exact[name])[seen].mean()),
             "worst": float(np.abs(clipped[name] - exact[name])[seen].max())}
            for name in ("diffuse", "specular", "total")]


def full_plan() -> pd.DataFrame:
    """The clipped scene on every surface, light and view of the full plan's validation (``--full-plan``)."""
    from multiprocessing import get_context

    from roughlight.measurements import implicit_surface as bench

    azimuth, elevation = sweeps.view_grid(*bench.PLANS["full"]["steps"])
    jobs = [(surface, incidence, 0.0, azimuth, elevation, kind)
            for surface, incidence, kind in bench.validation_surfaces("full")]
    jobs += [(surface, incidence, psi, az, el, bench.HELD_OUT) for surface, incidence, psi, az, el
             in bench.held_out_lights("full")]
    with get_context("spawn").Pool(2) as pool:
        rows = [row for part in pool.imap_unordered(_full_plan_sweep, jobs) for row in part]
    return pd.DataFrame(rows).sort_values(["kind", "truncation", "aspect", "incidence", "light_azimuth", "component"])


if __name__ == "__main__":
    import sys

    modes = {"--full-plan": (full_plan, 3), "--clipped": (clipped, 2), "--grazing": (grazing, 4),
             "--samples": (samples_needed, 3), "--frames": (frames, 2), "--phases": (phases, 2)}
    for flag, (measure, decimals) in modes.items():
        if flag in sys.argv:
            print(measure().round(decimals).to_string(index=False))
            raise SystemExit
    frame = trial()
    summary = frame.groupby(["model", "component"])["error"].agg(mae="mean", worst="max", views="size")
    print(summary.round(3).to_string())
    worst = frame.loc[frame.groupby("model")["error"].idxmax()]
    print(worst[["model", "component", "truncation", "aspect", "incidence", "light_azimuth", "elevation", "azimuth",
                 "value", "exact"]].round(2).to_string(index=False))
