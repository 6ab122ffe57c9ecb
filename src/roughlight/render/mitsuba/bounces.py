"""Whether a BRDF file keeps light that bounces unbiased: Mitsuba's ``path`` integrator against its ``direct``.

When light bounces, a path tracer draws the next direction ``wo`` with the BSDF's own ``sample`` (the ``measured``
plugin draws it from the file's ``luminance``, then its ``vndf`` warp) and weighs it by ``eval / pdf``. That is
unbiased when ``sample``, ``pdf`` and ``eval`` agree, and when the luminance is nowhere 0 where the values are not:
a direction that can never be drawn never lights anything (:func:`roughlight.render.mitsuba.measured.write_measured`
floors it for that reason). A directional light cannot tell: its light is only ever reached by the light's own
sample. So the check lights the flat quad with a ``constant`` environment of radiance 1, where every ``wo`` is
reached both ways, and renders it three ways (:data:`INTEGRATORS`):

- ``path`` at one bounce (``max_depth`` 2): the light's sample and the BSDF's, weighed together (MIS), as a path
  tracer renders;
- ``direct`` with the light's samples alone: ``eval`` only, the reference;
- ``direct`` with the BSDF's samples alone: ``sample`` only.

All three converge to the quad's directional albedo ``int f_r cos(theta_o) d omega_o`` toward the view (the
file's numbers are ``f_r L_z``, the radiance under the sky of radiance 1). Each estimate's standard error comes
from its pixels (each pixel an independent mean of ``spp`` samples), so a difference is read in standard errors.
docs/export-mitsuba.md gives the numbers of the default export's file.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..shading import view_direction
from . import runtime
from .measured import QUAD_HALF_SIDE, quad_sensor

__all__ = ["INTEGRATORS", "REFERENCE", "albedo_estimates", "bounce_check", "random_views"]

#: The three renderings of :func:`albedo_estimates`, by name: Mitsuba integrators.
INTEGRATORS = {
    "path, one bounce": {"type": "path", "max_depth": 2},
    "direct, the light's samples": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
    "direct, the BSDF's samples": {"type": "direct", "emitter_samples": 0, "bsdf_samples": 1},
}
#: The estimate the others are read against: ``eval`` alone, no ``sample``.
REFERENCE = "direct, the light's samples"


def _sky_scene(mi, path, integrator: dict):
    """The flat quad ``z = 0`` (a ``rectangle``: its shading frame is the world's x, y, z) with the file's BRDF,
    under a ``constant`` environment of radiance 1."""
    h = QUAD_HALF_SIDE
    return mi.load_dict({
        "type": "scene", "integrator": dict(integrator),
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": 1.0}},
        "quad": {"type": "rectangle", "to_world": mi.ScalarTransform4f().scale([h, h, 1.0]),
                 "bsdf": {"type": "measured", "filename": str(Path(path).resolve())}},
    })


def _sky_scenes(mi, path) -> dict:
    """:func:`_sky_scene` for each of :data:`INTEGRATORS`, by name."""
    return {name: _sky_scene(mi, path, integrator) for name, integrator in INTEGRATORS.items()}


def albedo_estimates(path, elevation: float, azimuth: float, spp: int = 256, side: int = 16,
                     variant: str = "llvm_ad_rgb", seed: int = 0, scenes=None) -> dict:
    """The file's directional albedo toward one view, estimated by each of :data:`INTEGRATORS`.

    Parameters
    ----------
    path : a file Mitsuba's ``measured`` plugin loads (:func:`roughlight.render.mitsuba.measured.write_measured`)
    elevation, azimuth : float, degrees, the view (:func:`roughlight.render.shading.view_direction`; elevation in
        (0, 180))
    spp, side : samples a pixel and the film's side in pixels (the estimate's standard error falls as
        ``1 / (side sqrt(spp))``)
    variant : Mitsuba variant (:func:`roughlight.render.mitsuba.runtime.load`)
    seed : the sampler's seed, the same for every integrator
    scenes : dict by integrator name, optional: the scenes of ``path`` already loaded (:func:`bounce_check` loads
        them once for all its views)

    Returns
    -------
    dict by integrator name: ``(mean, standard_error)`` of the first channel over the film (radiance, no ``J``).
    """
    if not 0.0 < float(elevation) < 180.0:
        raise ValueError(f"elevation must be within (0, 180) degrees (a view above the plane), got {elevation!r}")
    mi, _ = runtime.load(variant)
    scenes = scenes or _sky_scenes(mi, path)
    sensor = quad_sensor(mi, view_direction(float(elevation), float(azimuth)), side, spp)
    out = {}
    for name in INTEGRATORS:
        pixels = np.asarray(mi.render(scenes[name], sensor=sensor, seed=int(seed)), np.float64)[..., 0].ravel()
        out[name] = (float(pixels.mean()), float(pixels.std(ddof=1) / np.sqrt(pixels.size)))
    return out


def bounce_check(path, elevation, azimuth, spp: int = 256, side: int = 16, variant: str = "llvm_ad_rgb"):
    """:func:`albedo_estimates` at several views, each estimate against :data:`REFERENCE`.

    Parameters
    ----------
    path : the file
    elevation, azimuth : array_like (broadcast), degrees, the views
    spp, side, variant : as :func:`albedo_estimates` (view ``k`` rendered with seed ``k``)

    Returns
    -------
    pandas.DataFrame, one row a view and integrator: ``elevation``, ``azimuth``, ``integrator``, ``albedo``,
    ``standard_error``, ``difference`` (from the reference's albedo) and ``sigmas`` (that difference over the two
    standard errors combined; 0 for the reference itself).
    """
    import pandas as pd

    elevation, azimuth = np.broadcast_arrays(np.atleast_1d(np.asarray(elevation, float)),
                                             np.atleast_1d(np.asarray(azimuth, float)))
    mi, _ = runtime.load(variant)
    scenes = _sky_scenes(mi, path)
    rows = []
    for k, (e, phi) in enumerate(zip(elevation.ravel(), azimuth.ravel())):
        estimates = albedo_estimates(path, e, phi, spp, side, variant, seed=k, scenes=scenes)
        ref, ref_se = estimates[REFERENCE]
        for name, (mean, se) in estimates.items():
            difference = mean - ref
            both = np.hypot(se, ref_se)
            sigmas = 0.0 if name == REFERENCE else (difference / both if both > 0 else np.inf * np.sign(difference))
            rows.append({"elevation": float(e), "azimuth": float(phi), "integrator": name, "albedo": mean,
                         "standard_error": se, "difference": difference, "sigmas": float(sigmas)})
    return pd.DataFrame(rows)


def random_views(count: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """``count`` views drawn uniformly over the hemisphere's solid angle with ``seed``: ``(elevation, azimuth)``
    arrays, degrees (elevation in (0, 90) with ``sin e`` uniform, azimuth uniform in [0, 360);
    :func:`roughlight.render.shading.view_direction`)."""
    rng = np.random.default_rng(int(seed))
    elevation = np.degrees(np.arcsin(rng.uniform(0.0, 1.0, int(count))))
    return elevation, rng.uniform(0.0, 360.0, int(count))


def _main(argv=None) -> None:
    import argparse

    parser = argparse.ArgumentParser(description="A BRDF file's albedo by path (one bounce) and direct, at random "
                                                 "views under a sky of radiance 1")
    parser.add_argument("path", help="the file (e.g. results/export/t1_a1/brdf.bsdf)")
    parser.add_argument("--views", type=int, default=8)
    parser.add_argument("--seed", type=int, default=59)
    parser.add_argument("--spp", type=int, default=1024)
    parser.add_argument("--variant", default="scalar_rgb")
    args = parser.parse_args(argv)
    elevation, azimuth = random_views(args.views, args.seed)
    table = bounce_check(args.path, elevation, azimuth, spp=args.spp, variant=args.variant)
    print(table.to_string(index=False, float_format=lambda x: f"{x:.4f}"))
    others = table[table["integrator"] != REFERENCE]
    print(f"largest |difference| {others['difference'].abs().max():.4f} of an albedo "
          f"{table['albedo'].min():.3f}-{table['albedo'].max():.3f}; largest |sigmas| {others['sigmas'].abs().max():.2f}")


if __name__ == "__main__":
    _main()
