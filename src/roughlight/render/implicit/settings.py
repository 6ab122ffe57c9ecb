"""The implicit shader's settings (:class:`ImplicitSettings`): which model, and how many pixels a view."""

from __future__ import annotations

import functools
import os
from dataclasses import dataclass

from .model import FIBONACCI, model_samples

__all__ = ["ImplicitSettings", "CLIPPED_PICTURE"]

#: The clipped scene's pictures (``model`` ``"clipped"``: :func:`roughlight.render.implicit.shader.clipped_sweep`):
#: pixels a side, and the field and the periods across each picture, so that the field fills the picture down to
#: the lowest view a sweep measures (elevation 1: span / sin 1 degree = 458 periods deep).
CLIPPED_PICTURE = {"size": 128, "field_size": 8192, "span": 8.0}


@dataclass(frozen=True)
class ImplicitSettings:
    """Knobs of the implicit methods (one quad through the implicit shader).

    Attributes
    ----------
    model : str
        ``"exact"`` (ray casting), ``"correction"`` (the first-order correction) or ``"table"`` (the shares read
        from a table), :data:`MODELS`; or ``"clipped"`` (the clipped scene: the shares clipped exactly in C, each
        view one picture of :data:`CLIPPED_PICTURE`).
    samples : int or None
        Pixels a view, a Fibonacci number (:data:`FIBONACCI`); None: the model's own
        (:func:`roughlight.render.implicit.model.model_samples`). The clipped scene takes none (its pictures are
        :data:`CLIPPED_PICTURE`'s).
    table : str, os.PathLike, ShareTable or None
        The ``table`` model's table of shares (:class:`roughlight.render.implicit.table.ShareTable`) or the file
        that holds it (:func:`roughlight.render.implicit.table.save_table`, as rule ``export`` writes it); None:
        the surface's own at the default nodes, measured the first time and kept
        (:func:`roughlight.render.implicit.tabulate.cached_table`). The other models take none.
    """

    model: str = "exact"
    samples: int | None = None
    table: object = None

    def __post_init__(self):
        if self.model == "clipped":
            if self.samples is not None:
                raise ValueError(f"the clipped scene draws {CLIPPED_PICTURE['size']}² pictures: it takes no samples")
        else:
            model_samples(self.model)  # refuses an unknown model
        if self.samples is not None and int(self.samples) not in FIBONACCI:
            raise ValueError(f"samples must be one of the Fibonacci numbers {FIBONACCI}, got {self.samples!r}")
        if self.model != "table" and self.table is not None:
            raise ValueError(f"the implicit {self.model} model takes no table")

    def share_table(self, surface=None, shadows: bool = True):
        """The table model's :class:`~roughlight.render.implicit.table.ShareTable` (read from its file once); with
        no table, ``surface``'s own with or without ``shadows`` (:func:`~roughlight.render.implicit.tabulate.
        cached_table`: measured the first time, then read); ``ValueError`` when there is neither."""
        from .table import ShareTable

        if self.table is None:
            if surface is None:
                raise ValueError("the implicit table model reads its shares from a table: give its settings one "
                                 "(ImplicitSettings(model='table', table=...): a ShareTable or the file rule share_table "
                                 "writes, results/export/t{truncation}_a{aspect}/shares.npz), or a surface to "
                                 "tabulate")
            from .tabulate import cached_table

            return cached_table(surface, shadows=shadows)
        if isinstance(self.table, ShareTable):
            return self.table
        if not os.path.exists(self.table):
            raise FileNotFoundError(f"the implicit table model's table: no share table at {self.table!r} (rule "
                                    "export writes one)")
        return _loaded(os.path.abspath(self.table), os.path.getmtime(self.table))

    @property
    def pixels(self) -> int:
        """Pixels a view."""
        if self.model == "clipped":
            return CLIPPED_PICTURE["size"] ** 2
        return model_samples(self.model) if self.samples is None else int(self.samples)

    def recorded(self, surface=None) -> dict:
        """How the surface was sampled: ``pixels`` on one period, sqrt(pixels) a period along each direction (the
        clipped scene: its picture's pixels a period, ``sampling`` ``clipped``)."""
        if self.model == "clipped":
            across = CLIPPED_PICTURE["size"] / CLIPPED_PICTURE["span"]
            return {"pixels_per_period": int(round(across)), "sampling": "clipped", "shadow_map_size": 0}
        sampling = "table" if self.model == "table" else "fibonacci"
        return {"pixels_per_period": int(round(self.pixels**0.5)), "sampling": sampling, "shadow_map_size": 0}


@functools.lru_cache(maxsize=4)
def _loaded(path: str, mtime: float):
    """The share table at ``path`` as of ``mtime`` (read once a process)."""
    from .table import load_table

    return load_table(path)
