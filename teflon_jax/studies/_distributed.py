"""Monte Carlo on a Dask cluster: chunks of motions are tasks of the Dask engine (`_cluster`),
their peaks streamed to a NetCDF file of the layout `MonteCarloResult.to_dataset` writes.

The run of `monte_carlo` is cut into chunks of `chunk_size` consecutive motions; each chunk is
one task that a worker runs through one compiled, vmapped function (`ChunkRunner`, kept by
the worker for the whole run: `worker_cached`), so a worker compiles once whatever the number
of its chunks (and, with a persistent compilation cache folder shared by the workers, a
restarted worker reads the compiled function back). Motion i is drawn from
`fold_in(key(seed), i)` (`monte_carlo_motion`), one or two components alike, so which motion a
task draws does not depend on the number of workers or the chunk size; its peaks equal those
of `monte_carlo` with the same chunk size bit for bit (every call of a run has the chunk's
width: the last chunk is padded), and to round-off for another chunk size (XLA's vectorised
CPU code rounds the last digits differently for another batch width).

A worker that dies takes only its running chunks with it; the scheduler runs them again
elsewhere. A chunk whose task raises is run again `retries` times; after that the run stops
with a `ClusterRunError` naming its motions, the file left marked incomplete. Runs whose solve
failed are kept, flagged `converged` = False, and left out of the statistics, as in
`monte_carlo`.
"""

import uuid
from collections.abc import Callable, Mapping

import jax
import jax.numpy as jnp
import numpy as np

from ..excitation import (
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    VerticalGroundMotion,
)
from ._cluster import (
    add_attributes,
    check_count,
    check_netcdf_output,
    file_attributes,
    lanes,
    open_finished,
    run_dtype,
    stream_to_netcdf,
    worker_cached,
)
from ._montecarlo import (
    ChunkRunner,
    _get,
    _Source,
    bytes_per_motion,
    check_design_of,
    motion_attributes,
    probe_structure,
    stochastic_grid,
)
from ._record_set import RecordSet
from ._results import DESIGN_UNITS, VARIABLES, MonteCarloResult

PGA = ("m s-2", "peak |ground acceleration| of the motion")
UPLIFT = ("s", "time with the isolators' normal load <= 0")


def _runner(spec: dict) -> ChunkRunner:
    """The compiled chunk function of a run (built once per worker: `worker_cached`)."""
    key = None if spec["model"] is None else jax.random.key(spec["seed"])
    source = _Source(spec["model"], key, spec["time_step"], spec["samples"])
    design = None if spec["design"] is None else {k: jnp.asarray(v) for k, v in spec["design"].items()}
    return ChunkRunner(spec["structure"], source, spec["duration"], design, jax.devices()[:1], spec["chunk"],
                       spec["disp_width"], spec["shear_width"])


def _chunk_task(spec: dict, start: int, stop: int, values):
    """Peaks of motions start..stop-1 (a Dask task; runs on a worker); `values` the recorded
    motions start..stop-1, or `None` for generated ones."""
    runner = worker_cached(spec, _runner)
    indices = lanes(start, stop, spec["chunk"])
    if values is not None:
        values = np.asarray(values)[indices - start]
    peaks, pga = _get(runner(indices, values))
    n = stop - start
    out = {name: np.asarray(getattr(peaks, name))[:n] for name in _variables(spec["model"])}
    if spec["design"] is not None:  # (motion, design) -> (design, motion)
        out = {k: np.moveaxis(v, 0, 1) for k, v in out.items()}
    out["pga"] = np.asarray(pga)[:n]
    out["compile_s"] = runner.compile_s
    return out


def _variables(model) -> dict:
    """The peak variables of a run's file: `VARIABLES`, and `uplift_time` with a vertical component."""
    if not isinstance(model, VerticalGroundMotion):
        return VARIABLES
    return {**VARIABLES, "uplift_time": UPLIFT}


def _layout(n_motions: int, design: Mapping | None, inputs: dict, model=None) -> dict:
    """`create_netcdf`'s arguments for a run's file (the layout of `MonteCarloResult.to_dataset`)."""
    dims, peak_dims = {"motion": n_motions}, ("motion",)
    coords = {"motion": ("motion", np.arange(n_motions), None, None)}
    if design is not None:
        n_designs = len(next(iter(design.values())))
        dims["design"], peak_dims = n_designs, ("design", "motion")
        coords["design"] = ("design", np.arange(n_designs), None, None)
        coords.update({f"design_{k}": ("design", v, *DESIGN_UNITS.get(k, ("1", k))) for k, v in design.items()})
    variables = {name: (peak_dims, units, long_name, "bool" if name == "converged" else "f8")
                 for name, (units, long_name) in _variables(model).items()}
    variables["pga"] = (("motion",), *PGA, "f8")
    return {"dims": dims, "coords": coords, "variables": variables,
            "attrs": file_attributes("teflon-jax Monte Carlo peak responses", inputs)}


def _source_of(motions, n_motions):
    """(number of motions, stochastic model or None, record step [s], samples) of `motions`."""
    if isinstance(motions, RecordSet):
        count = motions.acceleration.shape[0]
        n_total = check_count("n_motions", count if n_motions is None else n_motions, 1)
        if n_total > count:
            raise ValueError(f"n_motions: {n_total} asked for but the RecordSet has {count} records.")
        return n_total, None, motions.time_step, motions.acceleration.shape[1]
    if isinstance(motions, (StochasticGroundMotion, TwoComponentGroundMotion, VerticalGroundMotion)):
        if n_motions is None:
            raise ValueError("n_motions: give the number of stochastic motions to draw (> 0).")
        time_step, samples, _ = stochastic_grid(motions)
        return check_count("n_motions", n_motions, 1), motions, time_step, samples
    raise ValueError("motions: expected a StochasticGroundMotion, a TwoComponentGroundMotion, a "
                     "VerticalGroundMotion or a RecordSet, "
                     f"got {type(motions).__name__}.")


def monte_carlo_distributed(
    structure: Callable,
    motions: StochasticGroundMotion | TwoComponentGroundMotion | RecordSet,
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
    attrs: Mapping | None = None,
) -> MonteCarloResult:
    """`monte_carlo` on a Dask cluster, streaming the peaks to the NetCDF file `out`.

    **Arguments** (as `monte_carlo` otherwise; `structure` must pickle, e.g. an
    `isolated_structure(...)` or `bidirectional_isolated_structure(...)`):

    - `out`: the ".nc" results file (checked writable before anything is computed or a
      cluster is started).
    - `seed`: motion i is `monte_carlo_motion(motions, jax.random.key(seed), i)`, the motion
      `monte_carlo(..., key=jax.random.key(seed))` runs as its i-th.
    - `scheduler`: "local:N" (a `LocalCluster` of N worker processes) or a scheduler address.
    - `chunk_size`: motions per task (per compiled call on a worker).
    - `retries`: times a task that raised is run again (a dead worker's tasks are rerun by
      the scheduler whatever this is).
    - `connect_timeout` [s]: how long to wait for a scheduler address to answer.
    - `compilation_cache`: a folder for JAX's persistent compilation cache (local workers).
    - `progress`: `progress(done, total)` after each chunk written.
    - `attrs`: more attributes of the file, e.g. what was run (structure, PTFE, pressure).

    **Returns:** the `MonteCarloResult` read back from `out` (48 bytes per motion and design).
    `ConnectionError` naming the address when no scheduler answers; `ValueError` for bad
    input or an output file that cannot be written (before anything starts);
    `ClusterRunError` naming the motions of a chunk that failed after its retries.
    """
    out = check_netcdf_output(out)
    n_total, model, time_step, samples = _source_of(motions, n_motions)
    chunk = min(check_count("chunk_size", chunk_size, 1), n_total)
    retries = check_count("retries", retries, 0)
    duration = (samples - 1) * time_step if duration is None else float(duration)
    if not duration > 0:
        raise ValueError(f"duration: must be > 0 s, got {duration}.")
    design_arrays, n_designs = None, 0
    if design:
        design_arrays = {k: np.atleast_1d(np.asarray(v, dtype=float)) for k, v in design.items()}
        if len({v.shape for v in design_arrays.values()}) != 1 or any(v.ndim != 1 for v in design_arrays.values()):
            raise ValueError("design: every variable needs a 1-D array of the same length.")
        n_designs = len(next(iter(design_arrays.values())))
        check_design_of(structure, design_arrays)
    probe_source = _Source(model, None if model is None else jax.random.key(0), time_step, samples)
    probe_design = None if design_arrays is None else {k: v[0] for k, v in design_arrays.items()}
    n_dof = int(probe_structure(structure, probe_source, probe_design).mass.shape[-1])
    dtype = run_dtype()
    spec = {"structure": structure, "model": model, "seed": int(seed), "time_step": time_step,
            "samples": samples, "duration": duration, "design": design_arrays, "chunk": chunk,
            "disp_width": disp_width, "shear_width": shear_width, "dtype": dtype, "token": uuid.uuid4().hex}
    memory = chunk * bytes_per_motion((probe_source.components + probe_source.vertical) * samples, n_dof, n_designs)
    inputs = {"duration_s": duration, "record_time_step_s": time_step, "n_dof": n_dof, "seed": int(seed),
              "scheduler": scheduler, "n_motions": n_total, "precision": dtype, **motion_attributes(motions),
              **dict(attrs or {})}
    chunks = [(start, min(start + chunk, n_total),
               None if model is not None else np.asarray(motions.acceleration[start:start + chunk]))
              for start in range(0, n_total, chunk)]
    compile_s = [0.0]

    def write(handle, start, stop, part):
        for name in _variables(model):
            values = part[name].astype(np.int8) if name == "converged" else part[name]
            handle.variables[name][..., start:stop] = values
        handle.variables["pga"][start:stop] = part["pga"]
        compile_s[0] = max(compile_s[0], float(part["compile_s"]))

    stream_to_netcdf(out, _layout(n_total, design_arrays, inputs, model), _chunk_task, spec, chunks, write,
                     scheduler=scheduler, connect_timeout=connect_timeout, compilation_cache=compilation_cache,
                     retries=retries, progress=progress, what="motions",
                     finish=lambda done: {"n_devices": done["n_workers"], "chunk_size": chunk,
                                          "compile_s": compile_s[0], "memory_estimate_bytes": memory})
    result = MonteCarloResult.from_dataset(open_finished(out))
    add_attributes(out, {"n_converged": np.asarray(result.n_converged, dtype=np.int64)})
    return result
