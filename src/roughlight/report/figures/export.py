"""The measured BRDF exported: the share table's reflection over the hemisphere for lights the study never used,
and how far each export is from the exact reference off its nodes."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ...render import shading
from ...render.implicit import table_values
from .common import placeholder, theme

__all__ = ["fig_export", "LIGHTS"]

#: The lights of the hemisphere panels, (incidence, light azimuth) in degrees: the study's, and two it never used.
LIGHTS = ((30.0, 0.0), (30.0, 30.0), (60.0, 120.0))


def _hemisphere(ax, table, incidence: float, light_azimuth: float, lighting, vmax: float):
    """The table's total over the hemisphere of views seen from above (x = cos e cos phi, y = cos e sin phi), one
    light; the light's direction marked."""
    x, y = np.meshgrid(np.linspace(-1, 1, 161), np.linspace(-1, 1, 161))
    inside = x**2 + y**2 < 1.0
    view = np.column_stack([x[inside], y[inside], np.sqrt(1.0 - x[inside] ** 2 - y[inside] ** 2)])
    light = shading.light_direction(incidence, light_azimuth)
    total = np.full(x.shape, np.nan)
    total[inside] = table_values(table, np.tile(light, (len(view), 1)), view, lighting)["total"]
    image = ax.imshow(total, origin="lower", extent=(-1, 1, -1, 1), cmap="magma", vmin=0.0, vmax=vmax)
    ax.plot([light[0]], [light[1]], marker="*", color="cyan", markersize=9)
    ax.set_title(f"light: incidence {incidence:g}, azimuth {light_azimuth:g}", fontsize=8)
    ax.set_xticks([])
    ax.set_yticks([])
    return image


def fig_export(tables: list, check: pd.DataFrame | None, lighting=None):
    """The first exported surface's share table drawn as the ``implicit_table`` model reads it: its total (0-255)
    over the hemisphere of views for three lights (:data:`LIGHTS`, the star is the light); and every checked view's
    error against the exact reference (levels, log scale) by its elevation above the plane, for the OpenGL table and
    the Mitsuba file, one level dotted.

    Parameters
    ----------
    tables : list of ShareTable (the exported surfaces', in ``export.surfaces``' order)
    check : the exported surfaces' checks (:func:`roughlight.measurements.brdf_export.check`, with ``truncation``
        and ``aspect``)
    lighting : Lighting, optional
    """
    theme()
    if not tables or check is None or check.empty:
        return placeholder("The measured BRDF exported", "no surface exported (export.surfaces)")
    lighting = lighting or shading.Lighting()
    table = tables[0]
    fig, axes = plt.subplots(1, len(LIGHTS) + 1, figsize=(4.0 * (len(LIGHTS) + 1), 3.8),
                             gridspec_kw={"width_ratios": [1] * len(LIGHTS) + [1.5]})
    vmax = float(check["reference"][check["component"] == "total"].quantile(0.99))  # the checked views' range
    for ax, (incidence, psi) in zip(axes, LIGHTS):
        image = _hemisphere(ax, table, incidence, psi, lighting, vmax=max(vmax, 1.0))
    fig.colorbar(image, ax=list(axes[: len(LIGHTS)]), shrink=0.8, label="total (0-255)")
    ax = axes[-1]
    total = check[check["component"] == "total"]
    for (method, colour) in (("implicit_table", "tab:blue"), ("mitsuba_measured", "tab:orange")):
        rows = total[total["method"] == method]
        up = np.minimum(rows["elevation"], 180.0 - rows["elevation"])
        ax.scatter(up, np.maximum(rows["error"], 1e-3), s=4, alpha=0.5, color=colour, label=method)
    ax.axhline(1.0, color="0.3", ls=":", lw=1)
    ax.set_yscale("log")
    ax.set_xlabel("view elevation above the plane, degrees")
    ax.set_ylabel("|export - exact| (levels), total")
    ax.set_title("off every node: lights and views drawn at random", fontsize=8)
    ax.legend(fontsize=7, loc="upper right")
    fig.suptitle(f"The measured BRDF exported: truncation {table.truncation:g}, aspect {table.aspect:g}", fontsize=10)
    return fig
