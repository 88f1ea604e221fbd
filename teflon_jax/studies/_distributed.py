"""Monte Carlo on a Dask cluster: chunks of motions are tasks, results stream to NetCDF.

The run of `monte_carlo` is cut into chunks of `chunk_size` motions; each chunk is a Dask
task that a worker runs through one compiled, vmapped function (`ChunkRunner`), kept by the
worker for the whole run, so a worker compiles once whatever the number of its chunks (and,
with a persistent compilation cache folder shared by the workers, a restarted worker reads
the compiled function back instead of compiling it). Motion i is drawn from
`fold_in(key(seed), i)` (`monte_carlo_motion`), so each motion's peaks are the same whatever
the number of workers or the chunk size. A worker that dies takes only its running chunks
with it; the scheduler runs them again on another worker. The driver writes each finished
chunk into the NetCDF file at its motions' place and forgets it: its memory holds the chunks
in flight, not the run.

Schedulers: "local:N" starts a `LocalCluster` of N worker processes on this machine; any
other string is the address of a running scheduler ("tcp://host:8786"), e.g. one started by
`dask-jobqueue` on a SLURM or PBS queue (see docs/distributed.md), or a cloud pool. Workers
run JAX in the precision of the caller: a LocalCluster inherits it; on remote workers a
mismatch is an error naming `JAX_ENABLE_X64`.
"""

import json
import time
import uuid
from collections.abc import Callable, Mapping

import jax
import jax.numpy as jnp
import numpy as np

from ..excitation import StochasticGroundMotion, TwoComponentGroundMotion
from ._cluster import start_client as _client
from ._montecarlo import (
    ChunkRunner,
    _get,
    _Source,
    bytes_per_motion,
    motion_attributes,
    probe_structure,
    stochastic_grid,
)
from ._record_set import RecordSet
from ._results import DESIGN_UNITS, VARIABLES, MonteCarloResult, check_output_path

_RUNNERS: dict = {}  # per worker process: run token -> ChunkRunner


def _chunk_task(spec: dict, start: int, stop: int, values):
    """Peaks of motions start..stop-1 (a Dask task; runs on a worker)."""
    dtype = str(jnp.result_type(float))
    if dtype != spec["dtype"]:
        raise RuntimeError(
            f"worker computes in {dtype} but the run asked for {spec['dtype']}: start the workers "
            f"with JAX_ENABLE_X64={'1' if spec['dtype'] == 'float64' else '0'}."
        )
    runner = _RUNNERS.get(spec["token"])
    if runner is None:
        source = _Source(spec["model"], None if spec["model"] is None else jax.random.key(spec["seed"]),
                         spec["time_step"], spec["samples"])
        design = None if spec["design"] is None else {k: jnp.asarray(v) for k, v in spec["design"].items()}
        runner = ChunkRunner(spec["structure"], source, spec["duration"], design, jax.devices()[:1],
                             spec["chunk"], spec["disp_width"], spec["shear_width"])
        _RUNNERS.clear()  # one run at a time per worker
        _RUNNERS[spec["token"]] = runner
    indices = np.minimum(np.arange(start, start + spec["chunk"]), stop - 1)  # pad with copies
    if values is not None:
        values = np.asarray(values)[indices - start]
    peaks, pga = _get(runner(indices, values))
    n = stop - start
    out = {name: np.asarray(getattr(peaks, name))[:n] for name in VARIABLES}
    if spec["design"] is not None:
        out = {k: np.moveaxis(v, 0, 1) for k, v in out.items()}
    out["pga"] = np.asarray(pga)[:n]
    out["compile_s"] = runner.compile_s
    return out


def _create_file(path, n_motions: int, design: Mapping | None, attrs: dict):
    """An empty NetCDF file with the layout of `MonteCarloResult.to_dataset`."""
    import netCDF4

    handle = netCDF4.Dataset(path, "w", format="NETCDF4")
    handle.createDimension("motion", n_motions)
    dims = ("motion",)
    motion = handle.createVariable("motion", "i8", ("motion",))
    motion[:] = np.arange(n_motions)
    if design is not None:
        n_designs = len(next(iter(design.values())))
        handle.createDimension("design", n_designs)
        handle.createVariable("design", "i8", ("design",))[:] = np.arange(n_designs)
        dims = ("design", "motion")
        for name, values in design.items():
            units, long_name = DESIGN_UNITS.get(name, ("1", name))
            variable = handle.createVariable(f"design_{name}", "f8", ("design",))
            variable[:] = np.asarray(values)
            variable.setncatts({"units": units, "long_name": long_name})
    for name, (units, long_name) in VARIABLES.items():
        if name == "converged":
            variable = handle.createVariable(name, "i1", dims)
            variable.setncatts({"units": units, "long_name": long_name, "dtype": "bool"})
        else:
            variable = handle.createVariable(name, "f8", dims)
            variable.setncatts({"units": units, "long_name": long_name})
    variable = handle.createVariable("pga", "f8", ("motion",))
    variable.setncatts({"units": "m s-2", "long_name": "peak |ground acceleration| of the motion"})
    handle.setncatts(attrs)
    return handle


def monte_carlo_distributed(
    structure: Callable,
    motions: StochasticGroundMotion | RecordSet,
    n_motions: int | None = None,
    *,
    out,
    seed: int = 0,
    scheduler: str = "local:2",
    chunk_size: int = 256,
    duration: float | None = None,
    design: Mapping | None = None,
    disp_width=None,
    shear_width=None,
    retries: int = 2,
    connect_timeout: float = 10.0,
    compilation_cache=None,
    progress: Callable[[int, int], None] | None = None,
) -> MonteCarloResult:
    """`monte_carlo` on a Dask cluster, streaming the peaks to the NetCDF file `out`.

    **Arguments** (as `monte_carlo` otherwise):

    - `out`: the ".nc" results file (checked writable before anything is computed).
    - `seed`: motion i is `sample(model, fold_in(jax.random.key(seed), i), 1)[0]`, the motion
      `monte_carlo(..., key=jax.random.key(seed))` runs as its i-th.
    - `scheduler`: "local:N" (a `LocalCluster` of N worker processes) or a scheduler address.
    - `chunk_size`: motions per task (per compiled call on a worker).
    - `retries`: times a task that raised is run again (a dead worker's tasks are rerun by
      the scheduler whatever this is).
    - `connect_timeout` [s]: how long to wait for a scheduler address to answer.
    - `compilation_cache`: a folder for JAX's persistent compilation cache (local workers).
    - `progress`: `progress(done, total)` after each chunk written.

    **Returns:** the `MonteCarloResult` read back from `out` (48 bytes per motion and design).
    `ConnectionError` naming the address when no scheduler answers; `ValueError` for bad
    input or an output file that cannot be written.
    """
    import netCDF4
    from distributed import as_completed

    tic = time.perf_counter()
    out = check_output_path(out)
    if out.suffix != ".nc":
        raise ValueError(f"out: {out}: the distributed run streams to NetCDF; give a .nc file.")
    if isinstance(motions, RecordSet):
        n_total = motions.acceleration.shape[0] if n_motions is None else n_motions
        model, time_step, samples = None, motions.time_step, motions.acceleration.shape[1]
    elif isinstance(motions, (StochasticGroundMotion, TwoComponentGroundMotion)):
        if n_motions is None:
            raise ValueError("n_motions: give the number of stochastic motions to draw (> 0).")
        n_total, model = n_motions, motions
        time_step, samples, _ = stochastic_grid(motions)
    else:
        raise ValueError(
            "motions: expected a StochasticGroundMotion, a TwoComponentGroundMotion or a RecordSet, "
            f"got {type(motions).__name__}."
        )
    for name, value, low in (("n_motions", n_total, 1), ("chunk_size", chunk_size, 1), ("retries", retries, 0)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
            raise ValueError(f"{name}: must be an integer >= {low}, got {value!r}.")
    if isinstance(motions, RecordSet) and n_total > motions.acceleration.shape[0]:
        raise ValueError(f"n_motions: {n_total} asked for but the RecordSet has {motions.acceleration.shape[0]} records.")
    duration = (samples - 1) * time_step if duration is None else float(duration)
    if not duration > 0:
        raise ValueError(f"duration: must be > 0 s, got {duration}.")
    design_arrays = None
    if design:
        design_arrays = {k: np.atleast_1d(np.asarray(v, dtype=float)) for k, v in design.items()}
        if len({v.shape for v in design_arrays.values()}) != 1 or any(v.ndim != 1 for v in design_arrays.values()):
            raise ValueError("design: every variable needs a 1-D array of the same length.")
    dtype = str(jnp.result_type(float))
    chunk = min(int(chunk_size), int(n_total))
    spec = {"structure": structure, "model": model, "seed": int(seed), "time_step": time_step,
            "samples": samples, "duration": duration, "design": design_arrays, "chunk": chunk,
            "disp_width": disp_width, "shear_width": shear_width, "dtype": dtype,
            "token": uuid.uuid4().hex}
    probe_design = None if design_arrays is None else {k: v[0] for k, v in design_arrays.items()}
    probe_source = _Source(model, None if model is None else jax.random.key(0), time_step, samples)
    probe = probe_structure(structure, probe_source, probe_design)
    n_dof = int(probe.mass.shape[-1])
    n_designs = 0 if design_arrays is None else len(next(iter(design_arrays.values())))
    client, cluster = _client(scheduler, connect_timeout, dtype, compilation_cache)
    attrs = {"duration_s": duration, "record_time_step_s": time_step, "n_dof": n_dof, "seed": int(seed),
             "scheduler": scheduler, "n_motions": int(n_total), "precision": dtype, **motion_attributes(motions)}
    handle = _create_file(out, int(n_total), design_arrays, {
        "Conventions": "CF-1.8", "title": "teflon-jax Monte Carlo peak responses",
        "teflon_jax_attrs": json.dumps(attrs), **attrs,
    })
    try:
        spec_future = client.scatter(spec, broadcast=True)
        futures = []
        for start in range(0, n_total, chunk):
            stop = min(start + chunk, n_total)
            values = None if model is not None else np.asarray(motions.acceleration[start:stop])
            futures.append(client.submit(_chunk_task, spec_future, start, stop, values, retries=retries,
                                         key=f"teflon-jax-chunk-{spec['token']}-{start}", pure=False))
        spans = {f.key: (int(f.key.rsplit("-", 1)[1])) for f in futures}
        done, compile_s = 0, 0.0
        for future in as_completed(futures):
            part = future.result()
            start = spans[future.key]
            stop = start + part["pga"].shape[0]
            for name in VARIABLES:
                target = handle.variables[name]
                values = part[name].astype(np.int8) if name == "converged" else part[name]
                if design_arrays is None:
                    target[start:stop] = values
                else:
                    target[:, start:stop] = values
            handle.variables["pga"][start:stop] = part["pga"]
            compile_s = max(compile_s, float(part["compile_s"]))
            future.release()
            done += stop - start
            if progress is not None:
                progress(done, n_total)
        n_workers = len(client.scheduler_info()["workers"])
        handle.setncatts({"n_devices": n_workers, "chunk_size": chunk, "compile_s": compile_s,
                          "memory_estimate_bytes": chunk * bytes_per_motion(probe_source.components * samples, n_dof, n_designs), "wall_s": time.perf_counter() - tic})
    finally:
        handle.close()
        client.close()
        if cluster is not None:
            cluster.close()
    result = MonteCarloResult.open(out)
    with netCDF4.Dataset(out, "a") as handle:
        handle.setncattr("n_converged", np.asarray(result.n_converged, dtype=np.int64))
    return result
