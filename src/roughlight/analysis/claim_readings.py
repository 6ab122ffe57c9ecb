"""What the random-roughness claim reads of a surface: its back lobe and its hot spot, from the views measured.

A random surface is many tiles: the surface the thesis means is their mean, the seed-averaged views of an
ensemble (every view of every tile, each once). :func:`seed_stacks` lays an ensemble's tiles out as (seeds,
azimuth, elevation) arrays; :func:`surface_readings` reads the two lobes of one surface (a regular surface, one
tile, or the mean of several) and :func:`pooled_readings` reads an ensemble's mean with its delete-one jackknife
standard error over seeds: the uncertainty of the mean surface from resampling its seeds.

The two lobes (:data:`LOBES`):

* **back**: the specular around the light-facing facet's mirror direction, the lobe of Tables 1-2 and Fig. 19,
  read by :func:`roughlight.analysis.lobe_shape.lobe_reading` (its contrast over the disc's rim, squareness and
  phase shift);
* **hot spot**: the shadow-hiding function around V = L, the halo of Fig. 18, read by
  :func:`roughlight.analysis.hot_spot.hot_spot_reading` (its contrast, width and flatness).

Two readings of the same sweeps (:data:`READINGS`): ``unrounded`` (each view's mean before rounding:
``rough_unrounded``) and ``8-bit`` (the thesis's instrument: ``rough``, each pixel rounded; the hot spot's 8-bit
diffuse over the unrounded unshadowed one, since no 8-bit framebuffer draws the diffuse without shadows). Views
that were not rendered (coverage 0) are NaN in every field; nothing is mirrored or filled in.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..render.shading import light_direction
from ..study.selection import SURFACE_KEYS
from .hot_spot import hot_spot_reading, shadow_hiding
from .lobe_shape import lobe_reading, measured_field

__all__ = ["LOBES", "READINGS", "STATISTICS", "SeedStack", "seed_stacks", "surface_readings", "pooled_readings",
           "jackknife", "bootstrap", "BOOTSTRAP_RESAMPLES", "BOOTSTRAP_SEED", "lobe_centres", "mirrored_half",
           "mirrored_halves", "readings_table", "table_readings"]

#: The claim's lobes: the component (or field) each is read from.
LOBES = {"back": "specular", "hot_spot": "shadow hiding (diffuse)"}

#: The readings: the study-table column each takes its values from.
READINGS = {"unrounded": "rough_unrounded", "8-bit": "rough"}

#: Every statistic a reading gives: name -> (lobe, the reading's key, unit).
STATISTICS = {
    "back_contrast": ("back", "contrast", "levels"),
    "back_squareness": ("back", "squareness", ""),
    "back_phase_shift": ("back", "phase_shift", "deg"),
    "back_width": ("back", "width", "deg"),
    "hot_spot_contrast": ("hot_spot", "contrast_levels", "levels"),
    "hot_spot_flatness": ("hot_spot", "flatness", ""),
    "hot_spot_width": ("hot_spot", "width", "deg"),
}


class SeedStack:
    """One surface's views, a tile a row: the arrays a reading needs, (S, A, E) over seeds, azimuths and
    elevations (degrees; views laid out as the sweep's, elevation fastest).

    Attributes
    ----------
    key : (truncation, aspect, incidence)
    kind : str
    seeds : (S,) int array
    azimuth, elevation : (A,), (E,) float arrays, degrees
    coverage : (A, E), the views' coverage (the same on every tile: 0 where not rendered)
    specular, diffuse : dict reading -> (S, A, E) float arrays, 0-255
    unshadowed : (S, A, E) the diffuse with inner shadows off, unrounded, 0-255
    """

    def __init__(self, key, kind, seeds, azimuth, elevation, coverage, specular, diffuse, unshadowed):
        self.key, self.kind, self.seeds = tuple(key), str(kind), np.asarray(seeds, int)
        self.azimuth, self.elevation, self.coverage = azimuth, elevation, coverage
        self.specular, self.diffuse, self.unshadowed = specular, diffuse, unshadowed

    def __len__(self) -> int:
        return len(self.seeds)

    def subset(self, rows) -> SeedStack:
        """The same surface with only the tiles at ``rows`` (indices or a boolean mask)."""
        return SeedStack(self.key, self.kind, self.seeds[rows], self.azimuth, self.elevation, self.coverage,
                         {r: v[rows] for r, v in self.specular.items()},
                         {r: v[rows] for r, v in self.diffuse.items()}, self.unshadowed[rows])


def seed_stacks(study: pd.DataFrame, steps: tuple[float, float] | None = None) -> list[SeedStack]:
    """Every surface of ``study`` (kind x grid point) as a :class:`SeedStack` of its seeds, in order.

    Parameters
    ----------
    study : the study table's rows, or the claim's sweeps' rows in its columns (kind, seed, surface keys,
        azimuth, elevation, component, coverage, ``rough``, ``rough_unrounded``, ``rough_unshadowed``)
    steps : (azimuth step, elevation step), degrees: the rows are laid out on that whole view grid, a view no row
        gives is NaN with coverage 0 (the claim's tiles are measured around their lobes only); default the views
        the rows give, every seed at every one of them
    """
    out = []
    kinds = study["kind"].astype(str)
    for (kind, t, a, i), group in study.groupby([kinds] + SURFACE_KEYS, sort=True, observed=True):
        seeds = np.unique(group["seed"].to_numpy(int))
        if steps is None:
            az, el = np.unique(group["azimuth"].to_numpy(float)), np.unique(group["elevation"].to_numpy(float))
        else:
            az = np.arange(0.0, 180.0 - steps[0] / 2, steps[0])
            el = np.arange(0.0, 180.0 + steps[1] / 2, steps[1])
        arrays = {}
        for component, columns in (("specular", ("rough", "rough_unrounded")),
                                   ("diffuse", ("rough", "rough_unrounded", "rough_unshadowed", "coverage"))):
            part = group[group["component"].astype(str) == component]
            place = (np.searchsorted(seeds, part["seed"].to_numpy(int)), _index(az, part["azimuth"]),
                     _index(el, part["elevation"]))
            for column in columns:
                grid = np.full((len(seeds), len(az), len(el)), np.nan)
                grid[place] = part[column].to_numpy(float)
                arrays[component, column] = grid
        coverage = np.nan_to_num(arrays["diffuse", "coverage"], nan=0.0)
        if not (coverage == coverage[0]).all():
            raise ValueError(f"{kind} {t, a, i}: its seeds were not measured at the same views")
        out.append(SeedStack((float(t), float(a), float(i)), kind, seeds, az, el, coverage[0],
                             {r: arrays["specular", c] for r, c in READINGS.items()},
                             {r: arrays["diffuse", c] for r, c in READINGS.items()},
                             arrays["diffuse", "rough_unshadowed"]))
    return out


def _index(axis, values) -> np.ndarray:
    """Each of ``values`` (degrees) as its index on ``axis``; a value off the axis is an error."""
    values = np.asarray(values, float)
    index = np.clip(np.searchsorted(axis, values), 0, len(axis) - 1)
    if not np.allclose(axis[index], values, atol=1e-9):
        raise ValueError("a view lies off the view grid it is laid out on")
    return index


def surface_readings(stack: SeedStack, centres: dict, radii: dict, reading: str = "unrounded") -> dict:
    """Both lobes of the mean of ``stack``'s tiles (one tile: that tile).

    Parameters
    ----------
    stack : SeedStack
    centres : lobe -> (3,) unit direction the lobe is expected in (its regular facet's mirror direction; the
        light's for the hot spot)
    radii : lobe -> search radius, degrees (a lobe without one is not read)
    reading : a key of :data:`READINGS`

    Returns
    -------
    dict: every :data:`STATISTICS` name -> value (NaN where not read), and ``{lobe}_why`` ('' or why not).
    """
    az, el, cov = stack.azimuth, stack.elevation, stack.coverage
    out = {name: np.nan for name in STATISTICS}
    if "back" in radii:
        back = lobe_reading(measured_field(az, el, stack.specular[reading].mean(axis=0), cov), centres["back"],
                            radii["back"])
        back["width"] = math.sqrt(back["area"] / math.pi) if back["measurable"] else np.nan
        _put(out, "back", back)
    if "hot_spot" in radii:
        diffuse = stack.diffuse[reading].mean(axis=0)
        hiding = shadow_hiding(diffuse, stack.unshadowed.mean(axis=0))
        spot = hot_spot_reading(measured_field(az, el, hiding, cov), measured_field(az, el, diffuse, cov),
                                centres["hot_spot"], radii["hot_spot"])
        _put(out, "hot_spot", spot)
    return out


def _put(out: dict, lobe: str, reading: dict) -> None:
    """A lobe's reading into ``out``: its statistics (the shape's NaN unless measurable) and why not."""
    for name, (of, key, _) in STATISTICS.items():
        if of == lobe:
            contrast = name.endswith("_contrast")
            out[name] = float(reading[key]) if contrast or reading["measurable"] else np.nan
    out[f"{lobe}_why"] = reading["why"]


def jackknife(values) -> float:
    """The delete-one jackknife standard error of a statistic from its ``values`` with each seed left out in turn
    ((n,) array); NaN when fewer than 2 values or any is NaN (a resample whose lobe cannot be read)."""
    x = np.asarray(values, float)
    if len(x) < 2 or not np.isfinite(x).all():
        return np.nan
    return float(math.sqrt((len(x) - 1) / len(x) * np.sum((x - x.mean()) ** 2)))


#: The bootstrap's resamples and seed (:func:`pooled_readings` with ``error`` "bootstrap").
BOOTSTRAP_RESAMPLES, BOOTSTRAP_SEED = 400, 20261130


def bootstrap(values) -> float:
    """The bootstrap standard error of a statistic from its ``values`` on resamples of the seeds drawn with
    replacement ((B,) array): their standard deviation; NaN when fewer than 2 or any is NaN."""
    x = np.asarray(values, float)
    if len(x) < 2 or not np.isfinite(x).all():
        return np.nan
    return float(np.std(x, ddof=1))


def pooled_readings(stack: SeedStack, centres: dict, radii: dict, reading: str = "unrounded",
                    error: str = "jackknife") -> dict:
    """:func:`surface_readings` of the mean of all of ``stack``'s tiles, with each statistic's standard error over
    seeds (``{name}_se``) and the seeds it rests on (``seeds``).

    ``error`` "jackknife": the delete-one jackknife (:func:`jackknife`), the design's. "bootstrap": the seeds
    resampled with replacement :data:`BOOTSTRAP_RESAMPLES` times (:func:`bootstrap`, a fixed seed). A shape
    statistic read from a region on a grid moves in steps as one tile is left out, and the jackknife multiplies
    each step by the seeds (n - 1): on 548 random-pyramid tiles its error of the back lobe's squareness was 2.3
    times the spread of the statistic over disjoint batches of tiles, which the bootstrap matches
    (docs/random-roughness.md, "A sixth round")."""
    full = surface_readings(stack, centres, radii, reading)
    out = dict(full, seeds=len(stack))
    if len(stack) < 2:
        return {**out, **{f"{name}_se": np.nan for name in STATISTICS}}
    if error == "bootstrap":
        rng = np.random.default_rng(BOOTSTRAP_SEED)
        draws = [rng.integers(0, len(stack), len(stack)) for _ in range(BOOTSTRAP_RESAMPLES)]
        resampled = [surface_readings(stack.subset(rows), centres, radii, reading) for rows in draws]
        return {**out, **{f"{name}_se": bootstrap([r[name] for r in resampled]) for name in STATISTICS}}
    if error != "jackknife":
        raise ValueError(f"error is 'jackknife' or 'bootstrap', got {error!r}")
    left_out = [surface_readings(stack.subset(np.arange(len(stack)) != k), centres, radii, reading)
                for k in range(len(stack))]
    for name in STATISTICS:
        out[f"{name}_se"] = jackknife([r[name] for r in left_out])
    return out


def readings_table(readings: dict, keys: dict | None = None) -> pd.DataFrame:
    """Ensembles' readings (``(kind, truncation, aspect, incidence)`` -> :func:`pooled_readings`) as a long table
    (:data:`roughlight.study.pilots.COLUMNS`): kind, truncation, aspect, incidence, key (``keys``' value for the
    ensemble, "" without), reading (its name), value (float64), an ensemble's numbers in their own order (the
    notes of why a lobe's shape is not read, ``{lobe}_why``, are left out)."""
    rows = [(kind, float(t), float(a), float(i), (keys or {}).get((kind, t, a, i), ""), name, float(value))
            for (kind, t, a, i), reading in readings.items() for name, value in reading.items()
            if not isinstance(value, str)]
    return pd.DataFrame(rows, columns=["kind", "truncation", "aspect", "incidence", "key", "reading", "value"])


def table_readings(table: pd.DataFrame) -> dict:
    """:func:`readings_table`'s inverse: ``(kind, truncation, aspect, incidence)`` -> {reading: value}, the seeds
    an int."""
    out = {}
    for (kind, t, a, i), rows in table.groupby(["kind", "truncation", "aspect", "incidence"], sort=False):
        reading = dict(zip(rows["reading"], rows["value"].astype(float)))
        if "seeds" in reading:
            reading["seeds"] = int(reading["seeds"])
        out[(kind, float(t), float(a), float(i))] = reading
    return out


def mirrored_half(values, side: int) -> np.ndarray:
    """An (A, E) grid (azimuths 0, step, ... < 180; elevations symmetric about 90) whose views on one side of the
    light's plane are replaced by their mirror images' ((180 - phi, 180 - e)) from the other: ``side`` +1 keeps
    the views at y >= 0 (e <= 90), -1 those at y <= 0. Only for a surface that is itself mirror-symmetric in the
    light's plane (the regular pyramids): its two halves are then two separate measurements of one lobe."""
    vals = np.asarray(values, float)
    out = vals.copy()
    n_az, n_el = vals.shape
    half = (n_el - 1) // 2
    replace = np.arange(n_el) > half if side > 0 else np.arange(n_el) < half
    for k in range(1, n_az):
        out[k, replace] = vals[n_az - k, ::-1][replace]
    return out


def mirrored_halves(stack: SeedStack) -> list[SeedStack]:
    """A mirror-symmetric surface's two halves (:func:`mirrored_half`), each a surface of its own: the regular
    surface's rendering noise is the difference between what they read."""
    def half(side):
        flip = lambda v: np.stack([mirrored_half(x, side) for x in v])  # noqa: E731
        return SeedStack(stack.key, stack.kind, stack.seeds, stack.azimuth, stack.elevation, stack.coverage,
                         {r: flip(v) for r, v in stack.specular.items()},
                         {r: flip(v) for r, v in stack.diffuse.items()}, flip(stack.unshadowed))
    return [half(1), half(-1)]


def lobe_centres(key) -> dict:
    """The unit directions a surface's lobes are expected in: its light-facing facet's mirror direction (none when
    it lies below the horizon) and the light's."""
    from .lobes import lobe_directions

    t, a, i = key
    centres = {"hot_spot": light_direction(i)}
    back = lobe_directions(t, a, i).get("back")
    if back is not None:
        centres["back"] = back
    return centres
