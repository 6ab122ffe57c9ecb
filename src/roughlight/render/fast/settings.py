"""The fast renderer's settings: :class:`FastSettings`, with the random tiles' own :class:`TileSettings`.

Building, checking and recording the settings loads no OpenGL. In the
config they are the keys of ``render:``; a random tile's are the ``tile_``-prefixed keys
(:meth:`FastSettings.from_config`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace

from .sampling import SAMPLINGS, sampling_matrix

__all__ = ["FastSettings", "TileSettings"]


def _at_least(name: str, value, low) -> None:
    if not (float(value) >= low):
        raise ValueError(f"render.{name} must be >= {low:g}, got {value!r}")


def _one_of(name: str, value) -> None:
    if value not in SAMPLINGS:
        raise ValueError(f"render.{name} must be one of {SAMPLINGS}, got {value!r}")


@dataclass(frozen=True)
class TileSettings:
    """How random tiles are drawn (config keys ``render.tile_*``), densities per cell (per pyramid).

    Attributes
    ----------
    sampling : str
        ``"adaptive"`` (the default) counts each region's (the exact lit or shadowed part of a facet) visible and
        hidden pixels on the CPU and corrects them by its exact area (:mod:`roughlight.render.fast.counting`), with
        no shadow map and no OpenGL; ``"lattice"`` and ``"grid"`` take the tile
        mean of the shader's values, shadowed by a shadow map of ``shadow_map_size`` texels a cell.
    pixels_per_period : int
        Pixels a cell along each direction.
    shadow_map_size : int
        Shadow texels a cell (coarser than the regular surface's: a 4-cell tile's at 512 texels a cell is 2048
        texels a side, which every fragment reads at random).
    grazing_scale : float
        Adaptive sampling: views within :data:`roughlight.render.fast.sampling.GRAZING_BAND` degrees of the
        horizon are counted at this many times ``pixels_per_period`` (rounded). There the facets facing the
        detector are stretched and long edges of whatever hides them cross the tile; at 16 pixels a cell a few
        such views were more than one 8-bit level off, at 20 none of the checked ones.
    """

    sampling: str = "adaptive"
    pixels_per_period: int = 16
    shadow_map_size: int = 128
    grazing_scale: float = 1.25

    def __post_init__(self):
        _one_of("tile_sampling", self.sampling)
        _at_least("tile_pixels_per_period", int(self.pixels_per_period), 1)
        _at_least("tile_shadow_map_size", int(self.shadow_map_size), 1)
        _at_least("tile_grazing_scale", self.grazing_scale, 1)


@dataclass(frozen=True)
class FastSettings:
    """Knobs of the ``fast`` renderer that trade speed for accuracy.

    Attributes
    ----------
    pixels_per_period : int
        Sampling density: about this many pixels per period along each
        direction (each view's tile holds one period of the projected
        surface, about ``pixels_per_period ** 2`` pixels).
    sampling : str
        ``"adaptive"`` (the default): views where every facet faces the
        detector are each region's exact projected area, unrendered; the others
        are drawn on the lattice chosen for the view among six (on the three
        best, averaged, where the best may be off by ``average_lattices_above``),
        and each region's pixel count is corrected by its exact area
        (:mod:`roughlight.render.fast.shares`). ``"lattice"``: the tile is a rotated square
        whose pixel centres sample the period on a rotated lattice (no row of
        samples along the facets' axis-aligned or diagonal edges); ``"grid"``:
        a plain square tile of ``pixels_per_period`` x ``pixels_per_period``
        pixels.
    shadow_map_size : int
        Texels per period (along each direction) of the periodic shadow map.
    shadow_bias : float
        Height tolerance of the shadow test, as a fraction of the surface
        height (the receiver-plane test needs only rounding slack).
    max_framebuffer : int
        Largest framebuffer side in pixels; views beyond one framebuffer are
        drawn in further passes.
    jitter : (float, float)
        Sub-pixel shift of the camera (equivalently of the surface) in pixels,
        for measuring how a value moves when the pixels fall elsewhere on the
        surface (the thesis's "flashing lines"). The mean over the infinite
        periodic surface does not depend on it; a sampled mean does.
    tile : TileSettings
        How random tiles are drawn (:meth:`tile_settings`).
    average_lattices_above : float
        Adaptive sampling: a view whose best lattice's value discrepancy (close
        to a bound on its error, :func:`roughlight.render.fast.shares.value_discrepancy`)
        is at least this many 8-bit levels is drawn on its three best lattices
        (:data:`roughlight.render.fast.shares.AVERAGED`) and the values averaged. ``inf``:
        one lattice a view.
    """

    pixels_per_period: int = 28
    sampling: str = "adaptive"
    shadow_map_size: int = 512
    shadow_bias: float = 1e-4
    max_framebuffer: int = 4096
    jitter: tuple = (0.0, 0.0)
    tile: TileSettings = field(default_factory=TileSettings)
    average_lattices_above: float = 1.6

    def __post_init__(self):
        _at_least("pixels_per_period", int(self.pixels_per_period), 1)
        _at_least("shadow_map_size", int(self.shadow_map_size), 1)
        _at_least("shadow_bias", self.shadow_bias, 0)
        if self.pixels_per_period > self.max_framebuffer // 2:
            raise ValueError("render.pixels_per_period exceeds the largest framebuffer")
        _one_of("sampling", self.sampling)
        _at_least("average_lattices_above", self.average_lattices_above, 0)
        if not isinstance(self.tile, TileSettings):
            raise TypeError(f"FastSettings.tile must be a TileSettings, got {type(self.tile).__name__}")

    @classmethod
    def from_config(cls, knobs: dict | None = None) -> FastSettings:
        """The settings from the config's ``render:`` keys (without ``method``): ``tile_<name>`` sets the tile's
        ``<name>``. An unknown key raises ``TypeError`` naming it."""
        knobs = dict(knobs or {})
        tile = {key.removeprefix("tile_"): knobs.pop(key) for key in list(knobs) if key.startswith("tile_")}
        return cls(**knobs, tile=TileSettings(**tile))

    def config(self) -> dict:
        """The inverse of :meth:`from_config`: the settings as the config's flat ``render:`` keys."""
        flat = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "tile"}
        flat.update({f"tile_{f.name}": getattr(self.tile, f.name) for f in fields(self.tile)})
        return flat

    def tile_settings(self) -> FastSettings:
        """The settings a random tile is drawn with, densities per cell: the tile's ``sampling``,
        ``pixels_per_period`` and ``shadow_map_size`` in place of the regular surface's."""
        return replace(self, sampling=self.tile.sampling, pixels_per_period=int(self.tile.pixels_per_period),
                       shadow_map_size=int(self.tile.shadow_map_size))

    def for_tile(self, cells: int) -> FastSettings:
        """The settings for a random tile of ``cells x cells`` cells drawn as one period.

        The configured densities are per cell (per pyramid, as on the regular
        surface), so the tile gets ``cells`` times the pixels and shadow texels
        a side: the same sampling of every facet, at ``cells^2`` times the pixels.
        """
        if int(cells) == 1:
            return self
        return replace(self, pixels_per_period=int(self.pixels_per_period) * int(cells),
                       shadow_map_size=int(self.shadow_map_size) * int(cells))

    def for_surface(self, surface) -> FastSettings:
        """The settings a surface is drawn with: a random tile's (it has ``cells``) per cell
        (:meth:`tile_settings`, :meth:`for_tile`), the regular surface's as they are."""
        if hasattr(surface, "cells"):
            return self.tile_settings().for_tile(surface.cells)
        return self

    def sampling_matrix(self):
        """Integer 2x2 matrix from cell coordinates to window pixels (see ``periodic.vert``)."""
        return sampling_matrix(int(self.pixels_per_period), self.sampling)

    def recorded(self, surface=None) -> dict:
        """How the surface was sampled, as the study table and the benchmark record it: ``pixels_per_period``,
        ``sampling`` and ``shadow_map_size`` (a random tile's per cell)."""
        used = self.tile_settings() if hasattr(surface, "cells") else self
        return {"pixels_per_period": int(used.pixels_per_period), "sampling": used.sampling,
                "shadow_map_size": int(used.shadow_map_size)}
