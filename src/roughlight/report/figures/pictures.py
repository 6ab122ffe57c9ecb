"""Pictures of the surfaces as rendered: the thesis's Figs. 9, 10 and 13."""

from __future__ import annotations

import matplotlib.pyplot as plt

from .common import placeholder, theme

__all__ = ["fig_pictures", "fig09_shadows", "fig10_grazing", "fig13_tops"]


def fig_pictures(stem: str, pictures):
    """A row of rendered pictures with their labels (Figs. 9, 10, 13)."""
    theme()
    from ...render.pictures import PICTURE_SETS

    title = PICTURE_SETS[stem][0] if stem in PICTURE_SETS else stem
    n = len(pictures)
    if n == 0:
        return placeholder(title, "no pictures")
    fig, axes = plt.subplots(1, n, figsize=(3.2 * n, 2.9), squeeze=False)
    for ax, (label, img) in zip(axes[0], pictures):
        ax.imshow(img)
        ax.set_title(label, fontsize=9)
        ax.axis("off")
    fig.suptitle(title, fontsize=10, y=1.02)
    return fig


def fig09_shadows(pictures):
    """Fig. 9: inner shadows (:data:`roughlight.render.pictures.PICTURE_SETS`' pictures, :func:`fig_pictures`)."""
    return fig_pictures("fig09_shadows", pictures)


def fig10_grazing(pictures):
    """Fig. 10: the surface at grazing views (:func:`fig_pictures`)."""
    return fig_pictures("fig10_grazing", pictures)


def fig13_tops(pictures):
    """Fig. 13: the tops of the pyramids (:func:`fig_pictures`)."""
    return fig_pictures("fig13_tops", pictures)
