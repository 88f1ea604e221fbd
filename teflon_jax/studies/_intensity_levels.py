"""Monte Carlo over a list of intensity levels (a multiple-stripe analysis): N stochastic motions
at each expected peak ground acceleration, their peaks in one result with the level of each
motion, and the counts of runs exceeding a limit at each level that `fit_fragility` takes.

Level j runs motions j N .. (j + 1) N - 1 of the key (`monte_carlo(first_motion=j N)`), so the
levels see other motions, as the binomial likelihood of the fit assumes (Baker 2015,
Earthquake Spectra 31(1), multiple-stripe analysis), and a motion's index in the result is
the one `monte_carlo_motion` draws again.
"""

import dataclasses
from collections.abc import Callable, Sequence

import equinox as eqx
import numpy as np

from ..excitation import (
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    VerticalGroundMotion,
)
from ._montecarlo import monte_carlo
from ._results import MonteCarloResult, check_output_path, netcdf_engine


def motions_at_level(model, level: float):
    """`model` with the expected peak ground acceleration `level` [m/s^2] of its (major)
    horizontal component; with a vertical component (`VerticalGroundMotion`) the vertical
    one's peak, `vertical_ratio` times the horizontal one's, scales with it."""
    if isinstance(model, VerticalGroundMotion):
        return eqx.tree_at(lambda m: m.model, model, motions_at_level(model.model, level))
    if isinstance(model, TwoComponentGroundMotion):
        return eqx.tree_at(lambda m: m.model.peak_ground_acceleration, model, level)
    return eqx.tree_at(lambda m: m.peak_ground_acceleration, model, level)


def check_levels(levels) -> np.ndarray:
    """`levels` [m/s^2] as an array once positive, finite and strictly increasing; else a
    `ValueError` naming the level."""
    values = np.asarray(levels, float).reshape(-1)
    if values.size < 1 or not np.all(np.isfinite(values)) or not np.all(values > 0):
        raise ValueError(f"levels: need one or more finite intensities > 0, got {values.tolist()}.")
    for j in range(1, values.size):
        if not values[j] > values[j - 1]:
            raise ValueError(f"levels: must increase; level {j + 1} ({values[j]:g}) is not above level {j} "
                             f"({values[j - 1]:g}).")
    return values


def monte_carlo_levels(
    structure: Callable,
    model: StochasticGroundMotion | TwoComponentGroundMotion | VerticalGroundMotion,
    levels: Sequence[float],
    n_motions: int,
    *,
    key=None,
    progress: Callable[[int, int], None] | None = None,
    **options,
) -> tuple[MonteCarloResult, np.ndarray]:
    """`monte_carlo` at each expected peak ground acceleration of `levels` [m/s^2] (strictly
    increasing), `n_motions` motions each (module docstring).

    **Arguments:** `structure`, `model` (its `peak_ground_acceleration` is replaced by each
    level, `motions_at_level`: a vertical component scales with it), `n_motions`, `key` as for `monte_carlo`; `progress(done, total)` over all levels;
    `options`: further keywords of `monte_carlo` (e.g. `chunk_size`, `storey_height`).

    **Returns:** (one `MonteCarloResult` of the L N motions, level after level, with
    `attrs["intensity_levels_m_s2"]` and, with a vertical component, each motion's
    `uplift_time`; the level index (L N,) of each motion).
    """
    values = check_levels(levels)
    total = values.size * n_motions
    parts = []
    for j, level in enumerate(values):
        def step(done, _total, offset=j * n_motions):
            if progress is not None:
                progress(offset + done, total)

        parts.append(monte_carlo(structure, motions_at_level(model, float(level)), n_motions, key=key,
                                 first_motion=j * n_motions, progress=step, **options))
    first = parts[0]
    joined = {}
    for field in dataclasses.fields(MonteCarloResult):
        value = getattr(first, field.name)
        if isinstance(value, np.ndarray):
            axis = 0 if field.name == "pga" else first.dims.index("motion")
            joined[field.name] = np.concatenate([getattr(p, field.name) for p in parts], axis=axis)
    result = dataclasses.replace(
        first, **joined, wall_s=sum(p.wall_s for p in parts), compile_s=sum(p.compile_s for p in parts),
        attrs={**first.attrs, "intensity_levels_m_s2": values.tolist(), "motions_per_level": int(n_motions)})
    return result, np.repeat(np.arange(values.size), n_motions)


def exceedance_counts(peaks, converged, level_index, n_levels: int, limit: float) -> tuple[np.ndarray, np.ndarray]:
    """(n_runs (L,), n_exceed (L,)): at each level the runs whose solve converged and those of
    them whose peak is above `limit` (failed runs count in neither)."""
    peaks = np.asarray(peaks, float)
    ok = np.asarray(converged, bool)
    index = np.asarray(level_index)
    n_runs = np.bincount(index[ok], minlength=n_levels)
    n_exceed = np.bincount(index[ok & (peaks > limit)], minlength=n_levels)
    return n_runs, n_exceed


def levels_dataset(result: MonteCarloResult, level_index):
    """`result.to_dataset()` with `intensity_level` (motion,) [m s-2], each motion's level."""
    dataset = result.to_dataset()
    levels = np.asarray(result.attrs["intensity_levels_m_s2"])
    dataset["intensity_level"] = (("motion",), levels[np.asarray(level_index)],
                                  {"units": "m s-2", "long_name": "expected peak ground acceleration of the "
                                   "motion's level (the model's nominal peak, not the record's)"})
    return dataset


def save_levels(result: MonteCarloResult, level_index, path):
    """Write `levels_dataset(result, level_index)` to `path`: ".nc" NetCDF or ".zarr" (other
    suffixes: `ValueError`, the level of each motion would be lost). Returns the path."""
    path = check_output_path(path)
    if path.suffix not in (".nc", ".zarr"):
        raise ValueError(f"{path}: the motions' levels are kept in NetCDF (.nc) or Zarr (.zarr) only.")
    dataset = levels_dataset(result, level_index)
    if path.suffix == ".zarr":
        dataset.to_zarr(path, mode="w")
    else:
        dataset.to_netcdf(path, engine=netcdf_engine())
    return path
