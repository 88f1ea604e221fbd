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

Over several intensity levels (`monte_carlo_levels_distributed`) every chunk holds motions of
one level, the level an argument of the compiled call: the workers compile once for all the
levels, and level j's chunks are those of `monte_carlo_levels` (motions j N .. (j + 1) N - 1 of
the key, each level's last chunk padded), so the peaks are that run's. A building's storey
peaks (`storey_height`) stream with the others.

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
from ..systems import check_storey_height, response_layout
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
from ._intensity_levels import check_levels
from ._montecarlo import (
    ChunkRunner,
    _get,
    _Source,
    check_design_of,
    motion_attributes,
    probe_structure,
    stochastic_grid,
)
from ._montecarlo_parts import (
    bytes_per_motion,
    flat_peaks,
    surface_attributes,
    surface_groups,
)
from ._record_set import RecordSet
from ._result_variables import (
    BEYOND_PRESSURE_LAW,
    DESIGN_UNITS,
    GROUP_VARIABLES,
    RUN_FLAGS,
    STOREY_VARIABLES,
    SURFACE_VARIABLES,
    TIPPED,
    VARIABLES,
    surface_layout,
    surface_shapes,
)
from ._results import MonteCarloResult

PGA = ("m s-2", "peak |ground acceleration| of the motion")
UPLIFT = ("s", "time with the isolators' normal load <= 0")
FLAGS = ("converged", *RUN_FLAGS)
"""The boolean variables of a run's file (written as bytes)."""


def _runner(spec: dict) -> ChunkRunner:
    """The compiled chunk function of a run (built once per worker: `worker_cached`)."""
    key = None if spec["model"] is None else jax.random.key(spec["seed"])
    source = _Source(spec["model"], key, spec["time_step"], spec["samples"])
    design = None if spec["design"] is None else {k: jnp.asarray(v) for k, v in spec["design"].items()}
    return ChunkRunner(spec["structure"], source, spec["duration"], design, jax.devices()[:1], spec["chunk"],
                       spec["disp_width"], spec["shear_width"], storey_height=spec["storey_height"])


def _chunk_task(spec: dict, start: int, stop: int, payload):
    """Peaks of motions start..stop-1 (a Dask task; runs on a worker); `payload` (the recorded
    motions start..stop-1 or `None` for generated ones, the level [m/s^2] of generated ones or
    `None` for the model's)."""
    values, level = payload
    runner = worker_cached(spec, _runner)
    indices = lanes(start, stop, spec["chunk"])
    if values is not None:
        values = np.asarray(values)[indices - start]
    peaks, pga = _get(runner(indices, values, level))
    n = stop - start
    peaks = flat_peaks(peaks)  # each group's peaks as variables; a run beyond Table 1's law flagged
    names = _variables(spec["model"], spec["storey_height"], spec["groups"], spec["pressure_law"], spec["surfaces"])
    out = {name: np.asarray(peaks[name])[:n] for name in names}
    if spec["design"] is not None:  # (motion, design, ...) -> (design, motion, ...)
        out = {k: np.moveaxis(v, 0, 1) for k, v in out.items()}
    out["pga"] = np.asarray(pga)[:n]
    out["compile_s"] = runner.compile_s
    return out


def _variables(model, storey_height=None, groups=None, pressure_law=False, surfaces=None) -> dict:
    """The peak variables of a run's file: `VARIABLES`, `uplift_time` with a vertical component,
    the `STOREY_VARIABLES` with `storey_height` and the `GROUP_VARIABLES` of a structure whose
    `groups` (their number, else None) share the weight unevenly (and `tipped`), and `beyond_pressure_law`
    with Table 1's `pressure_law`, and the `SURFACE_VARIABLES` of the `surfaces` kept
    ((G, `surface_attributes`), else None): name -> (units, long name)."""
    variables = dict(VARIABLES)
    if isinstance(model, VerticalGroundMotion):
        variables["uplift_time"] = UPLIFT
    if storey_height is not None:
        variables.update({name: (units, long_name) for name, (_, units, long_name) in STOREY_VARIABLES.items()})
    if groups is not None:
        variables.update(GROUP_VARIABLES)
        variables["tipped"] = TIPPED
    if pressure_law:
        variables["beyond_pressure_law"] = BEYOND_PRESSURE_LAW
    labelled = {} if surfaces is None else surfaces[1]
    variables.update({name: (units, long_name) for name, (dim, units, long_name) in SURFACE_VARIABLES.items()
                      if f"{dim}_names" in labelled})
    return variables


def _layout(n_motions: int, design: Mapping | None, inputs: dict, model=None, storeys=None, levels=None,
            groups=None, pressure_law=False, surfaces=None) -> dict:
    """`create_netcdf`'s arguments for a run's file (the layout of `MonteCarloResult.to_dataset`,
    and of `levels_dataset` with `levels`, each motion's level (L N,) [m/s^2]); `storeys`:
    (storeys S, horizontal components) of a building whose storey peaks are kept, or `None`;
    `groups`: the number of bearing groups whose loads are kept (named by
    `inputs["group_names"]` where given), or `None`; `pressure_law`: runs beyond Table 1's
    pressure law are flagged (`beyond_pressure_law`); `surfaces`: (G groups,
    `surface_attributes`) of the surfaces whose peaks are kept, or `None`."""
    dims, peak_dims = {"motion": n_motions}, ("motion",)
    coords = {"motion": ("motion", np.arange(n_motions), None, None)}
    if design is not None:
        n_designs = len(next(iter(design.values())))
        dims["design"], peak_dims = n_designs, ("design", "motion")
        coords["design"] = ("design", np.arange(n_designs), None, None)
        coords.update({f"design_{k}": ("design", v, *DESIGN_UNITS.get(k, ("1", k))) for k, v in design.items()})
    variables = {name: (peak_dims, units, long_name, "bool" if name in FLAGS else "f8")
                 for name, (units, long_name) in _variables(model, groups=groups, pressure_law=pressure_law,
                                                            surfaces=surfaces).items()}
    if storeys is not None:
        n_storeys, components = storeys
        direction = ("direction",) if components == 2 else ()
        dims.update({"storey": n_storeys, "level": n_storeys + 1, **({"direction": 2} if direction else {})})
        coords["storey"] = ("storey", np.arange(1, n_storeys + 1), None, None)
        coords["level"] = ("level", np.arange(n_storeys + 1), None, None)
        if direction:
            coords["direction"] = ("direction", np.array(["x", "y"]), None, None)
        variables.update({name: (peak_dims + direction + (dim,), units, long_name, "f8")
                          for name, (dim, units, long_name) in STOREY_VARIABLES.items()})
    if groups is not None:
        dims["group"] = groups
        names = inputs.get("group_names") or [f"group {i + 1}" for i in range(groups)]
        coords["group"] = ("group", np.array([str(name) for name in names]), None, None)
        variables.update({name: (peak_dims + ("group",), units, long_name, "f8")
                          for name, (units, long_name) in GROUP_VARIABLES.items()})
    if surfaces is not None:  # the group axis named as the result names it (`MonteCarloResult.group_names`)
        count, labelled = surfaces
        names = inputs.get("group_names") or [f"group {i + 1}" for i in range(count)]
        surface_dims, surface_coords, surface_variables = surface_layout(*surface_shapes(count, labelled), names,
                                                                         peak_dims)
        dims.update(surface_dims)
        coords = surface_coords | coords
        variables.update(surface_variables)
    if levels is not None:
        coords["intensity_level"] = ("motion", np.asarray(levels, float), "m s-2", "expected peak ground "
                                     "acceleration of the motion's level (the model's nominal peak, not the record's)")
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
    storey_height=None,
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
    - `storey_height` [m]: a building's storey peaks too, as `monte_carlo(storey_height=...)`.

    **Returns:** the `MonteCarloResult` read back from `out` (48 bytes per motion and design,
    more with storey peaks).
    `ConnectionError` naming the address when no scheduler answers; `ValueError` for bad
    input or an output file that cannot be written (before anything starts);
    `ClusterRunError` naming the motions of a chunk that failed after its retries.
    """
    return _run(structure, motions, n_motions, None, out=out, seed=seed, scheduler=scheduler,
                chunk_size=chunk_size, duration=duration, design=design, disp_width=disp_width,
                shear_width=shear_width, retries=retries, connect_timeout=connect_timeout,
                compilation_cache=compilation_cache, progress=progress, attrs=attrs, storey_height=storey_height)


def monte_carlo_levels_distributed(
    structure: Callable,
    model: StochasticGroundMotion | TwoComponentGroundMotion | VerticalGroundMotion,
    levels,
    n_motions: int,
    *,
    out,
    seed: int = 0,
    progress: Callable[[int, int], None] | None = None,
    **options,
) -> tuple[MonteCarloResult, np.ndarray]:
    """`monte_carlo_levels` on a Dask cluster: `n_motions` motions at each expected peak ground
    acceleration of `levels` [m/s^2] (strictly increasing), level j's being motions
    j N .. (j + 1) N - 1 of `jax.random.key(seed)`, their peaks streamed to the NetCDF file
    `out` in the layout of `save_levels` (with `intensity_level`, each motion's level).

    **Arguments:** `options`: further keywords of `monte_carlo_distributed` (`scheduler`,
    `chunk_size`, `storey_height`, ...; no `design`).

    **Returns:** (the `MonteCarloResult` of the L N motions read back from `out`, with
    `attrs["intensity_levels_m_s2"]` and `attrs["motions_per_level"]`; the level index (L N,)
    of each motion), as `monte_carlo_levels` returns them.
    """
    values = check_levels(levels)
    if not isinstance(model, (StochasticGroundMotion, TwoComponentGroundMotion, VerticalGroundMotion)):
        raise ValueError(f"model: intensity levels scale a stochastic motion model, got {type(model).__name__}.")
    if options.get("design"):
        raise ValueError("design: design variants over intensity levels are not run on a cluster; run the "
                         "levels one design at a time.")
    result = _run(structure, model, n_motions, values, out=out, seed=seed, progress=progress, **options)
    return result, np.repeat(np.arange(values.size), result.n_motions // values.size)


def _spec(structure, motions, n_motions, *, seed, chunk_size, duration, design, disp_width, shear_width,
          storey_height) -> tuple[dict, dict]:
    """(the task's spec, the sizes of the run: n_total, n_dof, components, memory, n_storeys), checked."""
    n_total, model, time_step, samples = _source_of(motions, n_motions)
    chunk = min(check_count("chunk_size", chunk_size, 1), n_total)
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
    probe = probe_structure(structure, probe_source, probe_design)
    n_dof = int(probe.mass.shape[-1])
    groups = int(probe.bearing_load.shape[-1]) if response_layout(probe).overturning else None
    pressure_law = getattr(probe, "pressure_table", None) is not None
    surfaces = surface_attributes(probe)
    components = probe_source.components
    n_storeys = None  # refused here, before a cluster starts, for a rigid mass
    if storey_height is not None:
        n_storeys = check_storey_height(n_dof // components, storey_height).shape[0]
    spec = {"structure": structure, "model": model, "seed": int(seed), "time_step": time_step,
            "samples": samples, "duration": duration, "design": design_arrays, "chunk": chunk,
            "disp_width": disp_width, "shear_width": shear_width, "dtype": run_dtype(),
            "storey_height": storey_height, "groups": groups, "pressure_law": pressure_law,
            "surfaces": (surface_groups(probe), surfaces) if surfaces else None,
            "token": uuid.uuid4().hex}
    memory = chunk * bytes_per_motion((components + probe_source.vertical) * samples, n_dof, n_designs)
    return spec, {"n_total": n_total, "n_dof": n_dof, "components": components, "memory": memory,
                  "n_storeys": n_storeys}


def _run(structure, motions, n_motions, levels, *, out, seed=0, scheduler="local:2", chunk_size=256,
         duration=None, design=None, disp_width=None, shear_width=None, retries=2, connect_timeout=10.0,
         compilation_cache=None, progress=None, attrs=None, storey_height=None) -> MonteCarloResult:
    """A distributed run of `n_motions` motions at each of `levels` (or once at the model's own
    level, `None`), streamed to `out` (the arguments of `monte_carlo_distributed`)."""
    out = check_netcdf_output(out)
    spec, sizes = _spec(structure, motions, n_motions, seed=seed, chunk_size=chunk_size, duration=duration,
                        design=design, disp_width=disp_width, shear_width=shear_width, storey_height=storey_height)
    retries = check_count("retries", retries, 0)
    model, chunk, n_per_level = spec["model"], spec["chunk"], sizes["n_total"]
    at = [None] if levels is None else [float(x) for x in levels]
    n_total = len(at) * n_per_level
    inputs = {"duration_s": spec["duration"], "record_time_step_s": spec["time_step"], "n_dof": sizes["n_dof"],
              "seed": int(seed), "scheduler": scheduler, "n_motions": n_total, "precision": spec["dtype"],
              **motion_attributes(motions), **dict(attrs or {})}
    if getattr(structure, "group_names", ()):  # a plan's groups name the file's group axis
        inputs["group_names"] = list(structure.group_names)
    if spec["surfaces"] is not None:  # the sliders' and heated surfaces' names
        inputs.update(spec["surfaces"][1])
    if levels is not None:
        inputs.update({"intensity_levels_m_s2": list(at), "motions_per_level": n_per_level})
    # level j: its motions in chunks of `chunk` from j N, as monte_carlo_levels runs them
    chunks = [(j * n_per_level + start, j * n_per_level + min(start + chunk, n_per_level),
               (None if model is not None else np.asarray(motions.acceleration[start:start + chunk]), level))
              for j, level in enumerate(at) for start in range(0, n_per_level, chunk)]
    storeys = None if storey_height is None else (sizes["n_storeys"], sizes["components"])
    layout = _layout(n_total, spec["design"], inputs, model, storeys,
                     None if levels is None else np.repeat(np.asarray(at), n_per_level), spec["groups"],
                     spec["pressure_law"], spec["surfaces"])
    names = list(_variables(model, spec["storey_height"], spec["groups"], spec["pressure_law"], spec["surfaces"]))
    compile_s = [0.0]

    def write(handle, start, stop, part):
        for name in names:
            values = part[name].astype(np.int8) if name in FLAGS else part[name]
            variable = handle.variables[name]
            variable[(slice(None),) * variable.dimensions.index("motion") + (slice(start, stop),)] = values
        handle.variables["pga"][start:stop] = part["pga"]
        compile_s[0] = max(compile_s[0], float(part["compile_s"]))

    stream_to_netcdf(out, layout, _chunk_task, spec, chunks, write, scheduler=scheduler,
                     connect_timeout=connect_timeout, compilation_cache=compilation_cache, retries=retries,
                     progress=progress, what="motions",
                     finish=lambda done: {"n_devices": done["n_workers"], "chunk_size": chunk,
                                          "compile_s": compile_s[0], "memory_estimate_bytes": sizes["memory"]})
    result = MonteCarloResult.from_dataset(open_finished(out))
    add_attributes(out, {"n_converged": np.asarray(result.n_converged, dtype=np.int64)})
    return result
