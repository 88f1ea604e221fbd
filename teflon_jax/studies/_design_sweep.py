"""Sweeps of the design variables over a grid, for plots and starting points.

`design_sweep` evaluates the grid in this process, `design_sweep_distributed` as chunks of
design points on a Dask cluster (`_cluster`), streaming each chunk into a NetCDF file of the
layout `sweep_dataset` writes. A point's values depend on the width of the vmapped call that
computed it only in the last digits (XLA's vectorised CPU code rounds differently for another
batch width; seen: 3e-16 relative): with `chunk_size` equal to the in-process `batch_size` they
are the same bit for bit, whatever the number of workers and whichever worker ran a chunk.
"""

import json
import uuid
from collections.abc import Mapping

import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import check_design
from ..systems import IsolatedStructure
from ._cluster import (
    check_count,
    check_netcdf_output,
    file_attributes,
    lanes,
    open_finished,
    run_dtype,
    stream_to_netcdf,
    worker_cached,
)
from ._design import (
    Bounds,
    check_limit_statistic,
    constrained_response,
    expected_response,
    penalised_objective,
)
from ._design_records import components_of, records_array
from ._result_variables import DESIGN_UNITS

SWEEP_VARIABLES = {
    "objective": ("1", "penalised objective E[V_s] + rho max(0, D_s / limit - 1)^2, with the limit "
                       "on the smoothed statistic D_s that the sweep ran on (attribute disp_limit_m)"),
    "shear": ("1", "mean smooth peak base shear / weight E[V_s] over the motions"),
    "disp": ("m", "smooth peak base displacement over the motions: its mean E[D_s], or its 95th "
                  "percentile with limit_statistic p95"),
    "converged": ("1", "every motion's solve converged at this design point"),
    "n_failed": ("1", "motions with a time step whose Newton solve did not converge"),
}
"""Variables of a sweep's NetCDF file on the grid dimensions: name -> (units, long name)."""

DESIGN_OBJECTIVES = {
    "objective": ("1", "penalised objective E[V_s] + rho max(0, D_s / limit - 1)^2 with the limit on the "
                       "smoothed statistic D_s lowered as the optimiser's (attribute smooth_disp_limit_m), "
                       "the objective grid_best is the least of; NaN where converged is 0"),
    "objective_at_disp_limit": ("1", "penalised objective with the limit as given (attribute disp_limit_m) on "
                                     "the smoothed statistic D_s, which lies below the true peaks: the sweep's own"),
}
"""The objectives of a sweep's file once `write_design_objective` has run: name -> (units, long name)."""


def _evaluator(structure, records, record_time_step, disp_limit, penalty, duration, disp_width, shear_width,
               statistic="mean"):
    """The jitted function {name: (B,) design values} -> (objective, shear, disp, n_failed) (B,),
    disp the smoothed `statistic` (`LIMIT_STATISTICS`) the limit applies to."""

    @jax.jit
    def evaluate(points):
        def one(point):
            r = constrained_response(expected_response(
                structure, point, records, record_time_step, duration=duration,
                disp_width=disp_width, shear_width=shear_width,
            ), statistic)
            return penalised_objective(r, disp_limit, penalty), r["shear"], r["disp"], r["n_failed"]

        return jax.vmap(one)(points)

    return evaluate


def _grid(structure, grid: Mapping):
    names = list(grid)
    axes = [np.atleast_1d(np.asarray(grid[n], dtype=float)) for n in names]
    if not names or any(a.ndim != 1 or a.size < 1 for a in axes):
        raise ValueError("grid: give each design variable a 1-D array of at least one value.")
    check_design(structure, dict(zip(names, axes)))
    mesh = np.meshgrid(*axes, indexing="ij")
    return names, axes, mesh, {n: m.reshape(-1) for n, m in zip(names, mesh)}


def _sweep_dict(names, mesh, objective, shear, disp, failed, n_motions) -> dict:
    shape = mesh[0].shape
    objective, shear, disp, failed = (np.asarray(a).reshape(shape) for a in (objective, shear, disp, failed))
    return {"grid": dict(zip(names, mesh)), "objective": objective, "shear": shear, "disp": disp,
            "converged": failed == 0, "n_failed": failed.astype(int), "n_motions": int(n_motions)}


def design_sweep(
    structure: IsolatedStructure,
    records,
    record_time_step: float,
    *,
    grid: Mapping,
    disp_limit: float,
    penalty: float = 100.0,
    duration: float | None = None,
    disp_width=1e-3,
    shear_width=1e-3,
    batch_size: int = 16,
    limit_statistic: str = "mean",
) -> dict:
    """The same objective on the tensor grid of `grid` (name -> 1-D values), vmapped over
    design points in batches of `batch_size` (one compilation); `disp_limit` applies to the
    `limit_statistic` of the smooth peak base displacement (`optimise_design`).

    **Returns:** {"grid": {name: (G...) mesh}, "objective", "shear", "disp" (the limited
    statistic): (G...) arrays,
    "converged": (G...) bool, every motion's solve converged at that point, "n_failed": (G...)
    motions with a failed step, "n_motions"}. `sweep_start` skips points that did not converge.
    """
    names, _, mesh, flat = _grid(structure, grid)
    records = records_array(records, record_time_step, components_of(structure))
    evaluate = _evaluator(structure, records, record_time_step, disp_limit, penalty, duration,
                          disp_width, shear_width, check_limit_statistic(limit_statistic))
    total = mesh[0].size
    batch = min(check_count("batch_size", batch_size, 1), total)
    outputs = []
    for begin in range(0, total, batch):
        index = lanes(begin, min(begin + batch, total), batch)
        outputs.append(jax.device_get(evaluate({n: jnp.asarray(v[index]) for n, v in flat.items()})))
    parts = [np.concatenate(p)[:total] for p in zip(*outputs)]
    return _sweep_dict(names, mesh, *parts, records.shape[0])


def _sweep_task(spec: dict, start: int, stop: int, payload):
    """(objective, shear, disp, n_failed) of design points start..stop-1 (a Dask task)."""
    evaluate = worker_cached(spec, lambda s: _evaluator(
        s["structure"], jnp.asarray(s["records"]), s["record_time_step"], s["disp_limit"], s["penalty"],
        s["duration"], s["disp_width"], s["shear_width"], s["limit_statistic"]))
    index = lanes(0, stop - start, spec["chunk"])
    values = jax.device_get(evaluate({n: jnp.asarray(np.asarray(v)[index]) for n, v in payload.items()}))
    return [np.asarray(v)[: stop - start] for v in values]


def design_sweep_distributed(
    structure: IsolatedStructure,
    records,
    record_time_step: float,
    *,
    grid: Mapping,
    disp_limit: float,
    out,
    penalty: float = 100.0,
    duration: float | None = None,
    disp_width=1e-3,
    shear_width=1e-3,
    scheduler: str = "local:2",
    chunk_size: int = 4,
    retries: int = 2,
    connect_timeout: float = 10.0,
    compilation_cache=None,
    progress=None,
    attrs: dict | None = None,
    limit_statistic: str = "mean",
) -> dict:
    """`design_sweep` on a Dask cluster: chunks of `chunk_size` design points (each evaluated
    over all the motions) are tasks; the results stream to the NetCDF file `out` (checked
    writable before anything starts) at each point's place on the grid.

    **Arguments** (as `design_sweep` otherwise): `scheduler` "local:N" or a scheduler address;
    `retries`: runs again of a task that raised (a dead worker's tasks are rerun whatever this
    is); `connect_timeout` [s]; `compilation_cache`: folder of JAX's persistent compilation
    cache (local workers); `progress(done, total)` after each chunk; `attrs`: more attributes
    of the file (the run's inputs); `limit_statistic` as `design_sweep`.

    **Returns:** the dict of `design_sweep`, read back from `out` (`open_sweep`): every design
    point's values are those of `design_sweep(..., batch_size=chunk_size)` bit for bit,
    whatever the number of workers (module docstring).
    """
    out = check_netcdf_output(out)
    names, axes, mesh, flat = _grid(structure, grid)
    records = np.asarray(records_array(records, record_time_step, components_of(structure)))
    total = mesh[0].size
    chunk = min(check_count("chunk_size", chunk_size, 1), total)
    retries = check_count("retries", retries, 0)
    dtype = run_dtype()
    spec = {"structure": structure, "records": records, "record_time_step": float(record_time_step),
            "disp_limit": disp_limit, "penalty": penalty, "duration": duration, "disp_width": disp_width,
            "shear_width": shear_width, "chunk": chunk, "dtype": dtype, "token": uuid.uuid4().hex,
            "limit_statistic": check_limit_statistic(limit_statistic)}
    settings = {"n_motions": int(records.shape[0]), "record_time_step_s": float(record_time_step),
                "disp_limit_m": float(disp_limit), "penalty": float(penalty), "scheduler": scheduler,
                "chunk_size": chunk, "precision": dtype, "limit_statistic": limit_statistic}
    shape = mesh[0].shape

    def write(handle, start, stop, part):
        for flat_index in range(start, stop):
            place = np.unravel_index(flat_index, shape)
            for name, values in zip(("objective", "shear", "disp", "n_failed"), part):
                handle.variables[name][place] = values[flat_index - start]
            handle.variables["converged"][place] = np.int8(part[3][flat_index - start] == 0)

    chunks = [(start, min(start + chunk, total), {n: v[start:start + chunk] for n, v in flat.items()})
              for start in range(0, total, chunk)]
    stream_to_netcdf(out, _sweep_layout(names, axes, {**settings, **(attrs or {})}), _sweep_task, spec, chunks,
                     write, scheduler=scheduler, connect_timeout=connect_timeout,
                     compilation_cache=compilation_cache, retries=retries, progress=progress,
                     what="design points (flat grid index)")
    return open_sweep(out)


def _sweep_layout(names, axes, attrs: dict) -> dict:
    """`create_netcdf`'s arguments for a sweep's file (the layout of `sweep_dataset`)."""
    dims = tuple(names)
    variables = {name: (dims, units, long_name, {"converged": "bool", "n_failed": "i8"}.get(name, "f8"))
                 for name, (units, long_name) in SWEEP_VARIABLES.items()}
    coords = {n: (n, a, *DESIGN_UNITS.get(n, ("1", n))) for n, a in zip(names, axes)}
    return {"dims": {n: a.size for n, a in zip(names, axes)}, "coords": coords, "variables": variables,
            "attrs": file_attributes("teflon-jax design sweep", attrs)}


def sweep_dataset(sweep: Mapping, attrs: dict | None = None):
    """A `design_sweep` result as an `xarray.Dataset`: a dimension per design variable (its
    values as coordinate, with units), `SWEEP_VARIABLES` on the grid, `attrs` added."""
    import xarray

    names = list(sweep["grid"])
    dims = tuple(names)
    coords = {}
    for axis, name in enumerate(names):
        index = [0] * len(names)
        index[axis] = slice(None)
        units, long_name = DESIGN_UNITS.get(name, ("1", name))
        coords[name] = (name, np.asarray(sweep["grid"][name])[tuple(index)], {"units": units, "long_name": long_name})
    data = {}
    for name, (units, long_name) in SWEEP_VARIABLES.items():
        values = np.asarray(sweep[name])
        data[name] = (dims, values.astype(np.int64) if name == "n_failed" else values,
                      {"units": units, "long_name": long_name})
    file_attrs = {"Conventions": "CF-1.8", "title": "teflon-jax design sweep", "n_motions": sweep["n_motions"],
                  "teflon_jax_attrs": json.dumps(attrs or {}), **(attrs or {})}
    return xarray.Dataset(data, coords=coords, attrs=file_attrs)


def open_sweep(path) -> dict:
    """The `design_sweep` dict a sweep NetCDF file holds (`sweep_dataset`, `design_sweep_distributed`);
    its "objective" is the file's, at the lowered limit once `write_design_objective` has run."""
    dataset = open_finished(path)
    names = list(dataset["objective"].dims)
    mesh = np.meshgrid(*[np.asarray(dataset[n].values, dtype=float) for n in names], indexing="ij")
    values = [np.asarray(dataset[k].values) for k in ("objective", "shear", "disp", "n_failed")]
    return _sweep_dict(names, mesh, *values, dataset.attrs["n_motions"])


def sweep_start(sweep: Mapping, bounds: Bounds, *, margin: float = 0.0) -> dict:
    """The converged grid point of `sweep` with the lowest objective, moved inside `bounds` by
    `margin` of each range (default none: a point on a bound starts BFGS there, where a
    bound that is the optimum holds it from the first step): a start for BFGS on a
    non-convex objective (global look by the grid, local refinement by the gradient)."""
    objective = np.asarray(sweep["objective"], dtype=float).reshape(-1)
    if "converged" in sweep:
        objective = np.where(np.asarray(sweep["converged"]).reshape(-1), objective, np.inf)
    if not np.any(np.isfinite(objective)):
        raise ValueError("sweep: no grid point converged for every motion; no start can be chosen "
                         "(try a smaller structure time step).")
    best = int(np.argmin(objective))
    start = {}
    for name, (lo, hi) in bounds.ranges.items():
        value = float(sweep["grid"][name].reshape(-1)[best])
        start[name] = min(max(value, lo + margin * (hi - lo)), hi - margin * (hi - lo))
    return start


def sweep_objective(sweep: Mapping, disp_limit: float, penalty: float = 100.0) -> np.ndarray:
    """The objective J of `penalised_objective` on the grid of `sweep` for another limit
    `disp_limit` [m] on the smoothed mean displacement (e.g. a `DesignResult`'s
    `smooth_disp_limit`), from the sweep's mean smooth shear and displacement; NaN where a
    motion did not converge."""
    shear, disp = (np.asarray(sweep[k], dtype=float) for k in ("shear", "disp"))
    objective = shear + penalty * np.maximum(disp / disp_limit - 1.0, 0.0) ** 2
    return np.where(np.asarray(sweep.get("converged", True)), objective, np.nan)


def write_design_objective(path, sweep: Mapping, smooth_disp_limit: float, penalty: float = 100.0) -> None:
    """Make the objective of the sweep file `path` (of `sweep`) the one a design chooses by:
    `sweep_objective` at the optimiser's lowered limit `smooth_disp_limit` [m] (a
    `DesignResult`'s, NaN where a motion did not converge), the file's attribute
    `smooth_disp_limit_m`; the sweep's own objective, at the limit as given, stays as
    `objective_at_disp_limit` (`DESIGN_OBJECTIVES`)."""
    import netCDF4

    lowered = sweep_objective(sweep, smooth_disp_limit, penalty)
    with netCDF4.Dataset(path, "a") as handle:
        given = handle.variables["objective"]
        if "objective_at_disp_limit" not in handle.variables:  # a second call keeps the sweep's own
            kept = handle.createVariable("objective_at_disp_limit", "f8", given.dimensions)
            kept[...] = np.ma.filled(given[...], np.nan)
        for name, (units, long_name) in DESIGN_OBJECTIVES.items():
            handle.variables[name].setncatts({"units": units, "long_name": long_name})
        given[...] = lowered
        handle.setncatts({"smooth_disp_limit_m": float(smooth_disp_limit)})
