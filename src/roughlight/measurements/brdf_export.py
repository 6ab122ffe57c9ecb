"""A surface's measured BRDF exported for any light: a table of facet shares one quad draws (OpenGL) and a file
Mitsuba 3's ``measured`` plugin loads, each checked against the exact reference where it holds no node.

Three steps, each a function:

* :func:`measure_table` (:mod:`roughlight.render.implicit.tabulate`'s, as are :data:`TABLE`,
  :func:`incidence_nodes` and :func:`tabulate_surface`): the exact reference's facet shares
  (:func:`roughlight.render.exact.shares_under`) at every node of a
  :class:`~roughlight.render.implicit.table.ShareTable`: light incidences x light azimuths in [0, 45] (the square
  pyramids' symmetry gives every other light) x view elevations x view azimuths. The ``implicit_table`` method
  draws one quad with it (:mod:`roughlight.render.implicit.shader`). :func:`build_table` measures and writes it
  (rule ``share_table``), :func:`export_surface` takes it from there (rule ``export``): the Mitsuba file's nodes
  and the checks' size measure no table again.
* :func:`mitsuba_tables`: the BRDF the table gives (:func:`roughlight.render.implicit.table.table_values`,
  the study's lighting equation a facet) converted to BRDF units and laid out as Mitsuba's ``measured`` file
  (:mod:`roughlight.render.mitsuba.measured`: the file stores ``f_r L_z = I / (pi J)``).
* :func:`check`: lights and views drawn at random off every node of both tables (seeded), each export's value
  against the exact reference's on the study's 0-255 scale: the ``implicit_table`` sweep through the shader, and a
  flat quad with the Mitsuba file rendered by Mitsuba (the Mitsuba method's light and detector).

Angles in degrees: incidence above the plane, azimuths from the lattice's x axis, ``V = (cos e cos phi,
cos e sin phi, sin e)`` (:mod:`roughlight.render.shading`).
"""

from __future__ import annotations

import math
import os
import tempfile
import time
from dataclasses import replace

import numpy as np

from ..render import methods, shading
from ..render.implicit import TABLE, ShareTable, incidence_nodes, measure_table, table_values, tabulate_surface
from ..surfaces.surface import Surface
from . import comparison

__all__ = ["TABLE", "MITSUBA", "CHECK", "LAYOUTS", "incidence_nodes", "measure_table", "tabulate_surface", "mitsuba_nodes",
           "brdf_values", "mitsuba_tables", "build_table", "write_mitsuba", "check_lights", "check_views", "check", "summary",
           "export_surface", "gather", "resolution_study"]

#: The Mitsuba file by default (``export.mitsuba``): the detector's elevation nodes (``theta_i = 90 - elevation``;
#: closer near the horizon), its azimuth nodes over the quarter the plugin folds views into (the square's mirrors:
#: reduction 4), the half-vector grid's side, and whether the plugin's warp places the half-vector nodes where the
#: values curve (:func:`roughlight.render.mitsuba.measured.warp_density`; else the identity warp).
MITSUBA = {"elevation": [1.5, 3.0, 4.5, 6.0, 8.0, 10.0, 13.0, 16.0, 20.0, 25.0, 30.0, 37.0, 45.0, 53.0, 62.0, 72.0,
                         81.0, 90.0], "phi_nodes": 19, "resolution": 32, "warp": True}

#: The checks by default (``export.check``): lights and views drawn off the nodes, and the random seed.
CHECK = {"lights": 3, "views": 400, "seed": 2001}

#: The Mitsuba variant of the checks' flat quad: one quad needs no vectorised kernels (``llvm_ad_rgb`` compiles
#: for about 10 s from a cold cache, then renders the same values).
CHECK_VARIANT = "scalar_rgb"


def brdf_values(table: ShareTable, lighting):
    """``values(L, V)`` of :func:`roughlight.render.mitsuba.measured.tabulate`: the table's facet sum on the 0-255
    scale, the study's 8-bit facet values, without the ambient term (no BRDF: it does not depend on the light)."""
    lighting = replace(lighting, ambient=0.0)

    def values(light, view):
        return table_values(table, light, view, lighting)

    return values


def mitsuba_nodes(elevation, phi_nodes: int):
    """The Mitsuba file's ``theta_i`` nodes (from the detector's ``elevation`` nodes, degrees: ``theta_i = 90 -
    elevation``, ascending) and ``phi_i`` nodes (:func:`roughlight.render.mitsuba.measured.table_nodes`, reduction
    4), float32 radians."""
    from ..render.mitsuba import table_nodes

    theta = np.radians(90.0 - np.asarray(elevation, float))[::-1].astype(np.float32)
    return theta, table_nodes(2, int(phi_nodes), reduction=4)[1]


def mitsuba_tables(table: ShareTable, lighting=None, elevation=MITSUBA["elevation"],
                   phi_nodes: int = MITSUBA["phi_nodes"], resolution: int = MITSUBA["resolution"],
                   warp: bool = MITSUBA["warp"], channels: str = "total"):
    """The Mitsuba ``measured`` file's nodes, ``rgb`` table and warp of the share table's BRDF.

    With ``warp`` the table is tabulated twice: on the regular half-vector grid, whose curvature gives the warp
    (:func:`roughlight.render.mitsuba.measured.warp_density`), then at the nodes that warp places (the same warp
    whatever ``channels``: it follows the total).

    Returns
    -------
    theta, phi : float32 arrays, radians (:func:`mitsuba_nodes`)
    rgb : (phi, theta, 3, resolution, resolution) float32, ``f_r L_z`` (``channels`` as
        :func:`roughlight.render.mitsuba.measured.tabulate`)
    vndf : (phi, theta, resolution, resolution) float32, or None without ``warp`` (the identity)
    """
    from ..render.mitsuba import tabulate, warp_density

    lighting = lighting or shading.Lighting()
    theta, phi = mitsuba_nodes(elevation, phi_nodes)
    values = brdf_values(table, lighting)
    regular = tabulate(values, theta, phi, int(resolution), lighting, "components" if warp else channels)
    if not warp:
        return theta, phi, regular, None
    vndf = warp_density(regular)
    return theta, phi, tabulate(values, theta, phi, int(resolution), lighting, channels, vndf=vndf), vndf


def description(table: ShareTable, lighting) -> str:
    """The Mitsuba file's description: what surface, what lighting constants, what scale."""
    return (f"roughlight: truncated square pyramids, truncation {table.truncation:g}, aspect {table.aspect:g}; "
            f"the OpenGL lighting equation (m_d {lighting.diffuse_reflectance:g}, m_s {lighting.specular_reflectance:g}, "
            f"shininess {lighting.shininess:g}, {lighting.specular_model}) with inner shadows "
            f"{'on' if table.shadows else 'off'}; stored f_r cos(theta_light) = I / (pi J), 1/sr; docs/export.md")


def build_table(surface: Surface, path, table_nodes=None, shadows: bool = True, log=None) -> dict:
    """Measure a surface's share table (:func:`tabulate_surface`) and write it to ``path`` (``.npz``, atomically):
    rule ``share_table``, apart from the Mitsuba file and the checks, so that neither's settings measure it again.

    Returns
    -------
    dict: ``table`` (the ShareTable), ``seconds`` (to measure it)
    """
    from ..render.implicit import save_table

    log = log or (lambda message: None)
    start = time.perf_counter()
    table = tabulate_surface(surface, table_nodes, shadows, log)
    seconds = time.perf_counter() - start
    log(f"share table: {table.incidence.size} incidences x {table.light_azimuth.size} light azimuths x "
        f"{table.elevation.size} elevations x {table.azimuth_nodes} azimuths in {seconds:.1f} s")
    save_table(path, table)
    return {"table": table, "seconds": seconds}


def write_mitsuba(table: ShareTable, path, lighting=None, mitsuba=None) -> dict:
    """Write the Mitsuba file of ``table``'s BRDF (:func:`mitsuba_tables`) to ``path``, atomically: the total in
    its three channels, the file for users.

    Returns
    -------
    dict: ``bytes`` (the file's size), ``seconds`` (to tabulate and write it) and ``tables`` (:func:`mitsuba_tables`
    with the components in R, G, B: what :func:`check` renders, the same nodes and warp)
    """
    from ..render.mitsuba import write_measured

    lighting = lighting or shading.Lighting()
    start = time.perf_counter()
    tables = mitsuba_tables(table, lighting, channels="components", **(mitsuba or {}))
    theta, phi, rgb, vndf = tables
    write_measured(path, theta, phi, rgb[:, :, [2, 2, 2]], description(table, lighting), vndf=vndf)
    return {"bytes": os.path.getsize(path), "seconds": time.perf_counter() - start, "tables": tables}


def _off(value: float, nodes) -> bool:
    """Whether ``value`` is at least 0.5 degrees from every one of ``nodes``."""
    return bool(np.min(np.abs(np.asarray(nodes, float) - value)) >= 0.5)


def check_lights(table: ShareTable, count: int, seed: int) -> list[tuple[float, float]]:
    """``count`` lights (incidence, light azimuth), degrees, drawn with ``seed``: incidence uniform in [10, 80],
    azimuth uniform on the circle, each turned to the table's azimuths off every node of the table (both axes)."""
    from ..surfaces.symmetry import canonical_light

    rng = np.random.default_rng(seed)
    lights = []
    while len(lights) < count:
        incidence, psi = float(rng.uniform(10.0, 80.0)), float(rng.uniform(0.0, 360.0))
        if _off(incidence, table.incidence) and _off(canonical_light(table.surface, psi)[0], table.light_azimuth):
            lights.append((round(incidence, 2), round(psi, 2)))
    return lights


def check_views(table: ShareTable, count: int, seed: int):
    """``count`` views (azimuth in [0, 180), elevation in [1, 179]: the study's half great circles), degrees,
    drawn with ``seed``, off the table's view elevation nodes (the azimuth nodes move with each light's turn)."""
    rng = np.random.default_rng(seed + 1)
    azimuth, elevation = [], []
    while len(azimuth) < count:
        a, e = float(rng.uniform(0.0, 180.0)), float(rng.uniform(1.0, 179.0))
        if _off(min(e, 180.0 - e), table.elevation):
            azimuth.append(round(a, 3))
            elevation.append(round(e, 3))
    return np.array(azimuth), np.array(elevation)


def check(table: ShareTable, mitsuba_path, lighting=None, lights: int = CHECK["lights"],
          views: int = CHECK["views"], seed: int = CHECK["seed"], mitsuba=None, variant: str = CHECK_VARIANT,
          tables=None):
    """Both exports against the exact reference at lights and views off their nodes.

    ``implicit_table``: the shader's sweep with the table (:mod:`roughlight.render.implicit.shader`).
    ``mitsuba_measured``: a flat quad with the Mitsuba file's BRDF, rendered by Mitsuba
    (:func:`roughlight.render.mitsuba.measured.render_flat`); for the components a file of the same nodes with the
    diffuse, specular and total in its three channels is written beside ``mitsuba_path``'s folder's temporary
    space and removed (the exported file holds the total alone); ``tables`` (:func:`write_mitsuba`'s) are its
    nodes, values and warp, else tabulated here. The reference's value and both exports leave out the ambient term
    (the Mitsuba file is a BRDF: ``light.ambient`` is 0 in the study).

    Returns
    -------
    pandas.DataFrame, one row a method x light x view x component: ``method``, ``incidence``,
    ``light_azimuth``, ``azimuth``, ``elevation``, ``component``, ``value``, ``reference``, ``error``
    (absolute, 0-255) and ``seconds`` (the method's time for the light's views).
    """
    import pandas as pd

    from ..render.mitsuba import render_flat, write_measured

    lighting = replace(lighting or shading.Lighting(), ambient=0.0)
    azimuth, elevation = check_views(table, views, seed)
    folder = os.path.dirname(os.path.abspath(mitsuba_path))
    with tempfile.TemporaryDirectory(dir=folder) as scratch:
        components = os.path.join(scratch, "components.bsdf")
        theta, phi, rgb, vndf = tables or mitsuba_tables(table, lighting, channels="components", **(mitsuba or {}))
        write_measured(components, theta, phi, rgb, "components: diffuse, specular, total in R, G, B", vndf=vndf)
        rows = []
        for incidence, psi in check_lights(table, lights, seed):
            exact = methods.sweep("reference", table.surface, incidence, azimuth, elevation, lighting,
                                  light_azimuth=psi)
            start = time.perf_counter()
            drawn = methods.sweep("implicit_table", table.surface, incidence, azimuth, elevation, lighting,
                                  {"table": table}, light_azimuth=psi)
            got = {"implicit_table": (drawn, time.perf_counter() - start)}
            start = time.perf_counter()
            flat = render_flat(components, incidence, psi, azimuth, elevation, lighting, variant=variant)
            got["mitsuba_measured"] = ({c: flat[:, k] for k, c in enumerate(shading.COMPONENTS)},
                                       time.perf_counter() - start)
            for method, (out, seconds) in got.items():
                for component in shading.COMPONENTS:
                    rows.append(pd.DataFrame({
                        "method": method, "incidence": incidence, "light_azimuth": psi, "azimuth": azimuth,
                        "elevation": elevation, "component": component, "value": np.asarray(out[component], float),
                        "reference": np.asarray(exact[component], float),
                        "error": np.abs(np.asarray(out[component], float) - np.asarray(exact[component], float)),
                        "seconds": seconds}))
    return pd.concat(rows, ignore_index=True)


def summary(checked, sizes: dict | None = None):
    """Per method and component: views, MAE, p99, the worst view (its error, light and view) and whether every
    view is within one 8-bit level; ``sizes`` (method -> bytes of its file) adds ``megabytes``."""
    import pandas as pd

    rows = []
    for (method, component), part in checked.groupby(["method", "component"], sort=False):
        worst = part.loc[part["error"].idxmax()]
        rows.append({"method": method, "component": component, "views": int(len(part)),
                     **comparison.error_statistics(part["error"]), "worst_incidence": float(worst["incidence"]),
                     "worst_light_azimuth": float(worst["light_azimuth"]), "worst_azimuth": float(worst["azimuth"]),
                     "worst_elevation": float(worst["elevation"]), "within_level": bool(worst["error"] <= 1.0),
                     "megabytes": (sizes or {}).get(method, math.nan) / 1e6})
    return pd.DataFrame(rows)


def export_surface(table: ShareTable, paths: dict, mitsuba=None, checks=None, lighting=None,
                   table_seconds: float = math.nan) -> dict:
    """Export one surface's measured share table (:func:`build_table`): write its Mitsuba file, check both off
    their nodes (rule ``export``).

    Parameters
    ----------
    table : ShareTable
    paths : dict
        ``shares`` (the table's ``.npz``, as written: its size is reported), ``mitsuba`` (the file to write).
    mitsuba, checks : dict, optional
        ``export.mitsuba`` and ``export.check`` (defaults :data:`MITSUBA`, :data:`CHECK`).
    lighting : Lighting, optional
    table_seconds : float
        What measuring the table took (:func:`build_table`), reported beside the other steps.

    Returns
    -------
    dict: ``check`` (:func:`check`'s frame), ``summary`` (:func:`summary`'s, with the surface, the files' sizes
    and the seconds of each step)
    """
    lighting = lighting or shading.Lighting()
    mitsuba, checks = {**MITSUBA, **(mitsuba or {})}, {**CHECK, **(checks or {})}
    written = write_mitsuba(table, paths["mitsuba"], lighting, mitsuba)
    seconds = {"table_seconds": float(table_seconds), "mitsuba_seconds": written["seconds"]}
    start = time.perf_counter()
    checked = check(table, paths["mitsuba"], lighting, checks["lights"], checks["views"], checks["seed"], mitsuba,
                    tables=written["tables"])
    seconds["check_seconds"] = time.perf_counter() - start
    out = summary(checked, {"implicit_table": table.nbytes, "mitsuba_measured": written["bytes"]})
    out.insert(0, "aspect", table.aspect)
    out.insert(0, "truncation", table.truncation)
    out["file_megabytes"] = out["method"].map({"implicit_table": os.path.getsize(paths["shares"]),
                                               "mitsuba_measured": written["bytes"]}) / 1e6
    for key, value in seconds.items():
        out[key] = value
    return {"check": checked, "summary": out}


def gather(summaries, checks):
    """Every exported surface's summary (CSV files) in one frame, and their checks (Parquet files) in one, each
    check's rows with its surface's ``truncation`` and ``aspect``."""
    import pandas as pd

    frames = [pd.read_csv(path) for path in summaries]
    parts = []
    for path, part in zip(checks, frames):
        rows = pd.read_parquet(path)
        rows.insert(0, "aspect", float(part["aspect"].iloc[0]))
        rows.insert(0, "truncation", float(part["truncation"].iloc[0]))
        parts.append(rows)
    empty = pd.DataFrame()
    return (pd.concat(frames, ignore_index=True) if frames else empty,
            pd.concat(parts, ignore_index=True) if parts else empty)


#: The resolution study's share-table layouts (:func:`resolution_study`): the default, and each axis closer or
#: coarser by itself.
LAYOUTS = {
    "default": {},
    "elevation 16": {"elevation": [1.0, 2.0, 3.0, 5.0, 7.0, 10.0, 14.0, 19.0, 25.0, 32.0, 40.0, 50.0, 60.0, 70.0,
                                   80.0, 90.0]},
    "no edge-on": {"edge_on": False},
    "azimuth 5": {"azimuth_step": 5.0},
    "light azimuth 15": {"light_azimuth": [0.0, 15.0, 30.0, 45.0], "edge_on": True},
}


def resolution_study(surface: Surface, layouts=None, lights: int = 8, views: int = 400, seed: int = 9, log=None):
    """What a share table's nodes cost and buy: for each layout (``export.table`` keys over :data:`TABLE`), its
    build time and bytes, and its total's error against the exact reference (numpy, :func:`table_values`) on the
    study's full view grid (1 by 5 degrees; its rendered views, each once: the zenith once, not once per azimuth)
    at the study's light azimuth, incidences 10, 30 (nodes), 37.3 and 63.1 (off the nodes), and at ``lights`` x
    ``views`` lights and views drawn at random (any azimuth).

    Returns
    -------
    pandas.DataFrame, one row a layout x test: ``layout``, ``seconds``, ``megabytes``, ``test``, ``mae``, ``worst``,
    ``worst_above_5`` (the worst view 5 degrees or more above the plane)
    """
    import pandas as pd

    from ..render import views as sweeps

    log = log or (lambda message: None)
    rows = []
    azimuth, elevation = sweeps.view_grid(1.0, 5.0)
    seen = sweeps.distinct_views(azimuth, elevation)
    rng = np.random.default_rng(seed)
    drawn = [(rng.uniform(10, 80), rng.uniform(0, 360), rng.uniform(0, 180, views), rng.uniform(1, 179, views))
             for _ in range(lights)]
    tests = [(f"study views, incidence {i:g}", [(i, 0.0, azimuth[seen], elevation[seen])]) for i in
             (10.0, 30.0, 37.3, 63.1)] + [("random lights and views", drawn)]
    for name, layout in (layouts or LAYOUTS).items():
        start = time.perf_counter()
        table = tabulate_surface(surface, layout)
        seconds = time.perf_counter() - start
        for test, pairs in tests:
            errors, above = [], []
            for i, psi, az, el in pairs:
                exact = methods.sweep("reference", surface, i, az, el, light_azimuth=psi)["total"]
                light = np.tile(shading.light_direction(i, psi), (len(az), 1))
                got = table_values(table, light, shading.view_direction(el, az))["total"]
                errors.append(np.abs(got - exact))
                above.append(np.minimum(el, 180.0 - el) >= 5.0)
            error, above = np.concatenate(errors), np.concatenate(above)
            rows.append({"layout": name, "seconds": seconds, "megabytes": table.nbytes / 1e6, "test": test,
                         "mae": float(error.mean()), "worst": float(error.max()),
                         "worst_above_5": float(error[above].max())})
        log(f"{name}: {seconds:.1f} s, {table.nbytes / 1e6:.2f} MB")
    return pd.DataFrame(rows)


def _main(argv=None) -> None:
    """``python -m roughlight.measurements.brdf_export [truncation aspect]``: the resolution study (default t 1,
    a 1) as a table."""
    import sys

    args = sys.argv[1:] if argv is None else argv
    surface = Surface(float(args[0]), float(args[1])) if len(args) >= 2 else Surface(1.0, 1.0)
    frame = resolution_study(surface, log=print)
    print(frame.round(3).to_string(index=False))


if __name__ == "__main__":
    _main()
