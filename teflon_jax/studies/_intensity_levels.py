"""Monte Carlo over a list of intensity levels (a multiple-stripe analysis): N stochastic motions
at each expected peak ground acceleration, their peaks in one result with the level of each
motion, and the counts of runs exceeding a limit at each level that `fit_fragility` takes.

Level j runs motions j N .. (j + 1) N - 1 of the key (`monte_carlo(first_motion=j N)`), so the
levels see other motions, as the binomial likelihood of the fit assumes (Baker 2015,
Earthquake Spectra 31(1), multiple-stripe analysis), and a motion's index in the result is
the one `monte_carlo_motion` draws again. The levels share one compiled chunk function: the
level is an argument of each call (`ChunkRunner`), not a constant of the program, so L levels
compile once and give the numbers L separate `monte_carlo` runs give.

With the draws of a bearing posterior (`bearings`, `bearing_draw`, `nested` of `monte_carlo`)
every level runs the same draws, also as arguments of the one program: nested, each of the K
bearings runs every level's N motions (peaks (K, L N)); one draw per motion, motion m of every
level takes draw `bearing_draw[m]`, so the levels differ in their motions and intensity only.
"""

import dataclasses
import time
from collections.abc import Callable, Sequence

import numpy as np

from ..excitation import (
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    VerticalGroundMotion,
)
from ._montecarlo import _plan, _result, _run_chunks
from ._results import MonteCarloResult, check_output_path, netcdf_engine


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
    `options`: further keywords of `monte_carlo` (e.g. `chunk_size`, `storey_height`, and
    `bearings`, `bearing_draw` (N,) or (K,), `nested`: the same draws at every level).

    **Returns:** (one `MonteCarloResult` of the L N motions, level after level, with
    `attrs["intensity_levels_m_s2"]`, `compile_s` of the one compilation and, with a vertical component, each motion's
    `uplift_time`; nested, peaks (K, L N) and `bearing_draw` (K,); one draw per motion,
    `bearing_draw` (L N,), the level's (N,) draws repeated; the level index (L N,) of each motion).
    """
    values = check_levels(levels)
    if "first_motion" in options:
        raise ValueError("first_motion: level j runs motions j n_motions .. (j + 1) n_motions - 1; leave it out.")
    start = time.perf_counter()
    plan = _plan(structure, model, n_motions, key=key, **options)  # checked once, compiled at the first call
    runs = plan.n_total if plan.draws is None else plan.draws.size  # per level: N, or K N nested
    total = values.size * runs
    parts = []
    for j, level in enumerate(values):
        def step(done, _total, offset=j * runs):
            if progress is not None:
                progress(offset + done, total)

        outputs = _run_chunks(plan.runner, model, plan.n_total, plan.chunk, plan.n_chunks, j * plan.n_total, step,
                              level=float(level), draws=plan.draws)
        parts.append(_result(plan, model, outputs, 0.0))
    return join_levels(parts, values, time.perf_counter() - start), np.repeat(np.arange(values.size), plan.n_total)


def join_levels(parts, levels, wall_s: float) -> MonteCarloResult:
    """One `MonteCarloResult` of the levels' results `parts` (in order; each of the same number
    of motions), with `attrs["intensity_levels_m_s2"]` and `attrs["motions_per_level"]`. The
    motions are joined along "motion"; nested runs of bearing draws keep their "bearing" axis,
    whose draws (`bearing_draw` (K,)) must be the same in every part (`ValueError`)."""
    first = parts[0]
    joined = {}
    for field in dataclasses.fields(MonteCarloResult):
        value = getattr(first, field.name)
        if field.name == "bearing_draw" and first.nested:
            if any(not np.array_equal(p.bearing_draw, value) for p in parts):
                raise ValueError("parts: nested runs of other bearing draws; every level must run the same draws.")
        elif isinstance(value, np.ndarray):
            axis = 0 if field.name in ("pga", "bearing_draw") else first.dims.index("motion")
            joined[field.name] = np.concatenate([getattr(p, field.name) for p in parts], axis=axis)
    return dataclasses.replace(
        first, **joined, wall_s=wall_s, compile_s=max(p.compile_s for p in parts),
        attrs={**first.attrs, "intensity_levels_m_s2": np.asarray(levels, float).tolist(),
               "motions_per_level": int(first.n_motions)})


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
