"""Writing Monte Carlo results to files (kept for callers of `save_montecarlo`)."""

from ._results import MonteCarloResult


def save_montecarlo(result: MonteCarloResult, path) -> list:
    """`result.save(path)`: the format the suffix names (".nc" NetCDF, ".zarr", ".csv",
    ".npz"), or a `ValueError` with the reason; never another format than asked. Returns the
    list of paths written."""
    return [result.save(path)]
