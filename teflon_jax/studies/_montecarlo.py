"""Monte Carlo of isolated structures under many ground motions, chunked and sharded.

A batch of N ground motions (drawn from `StochasticGroundMotion` with explicit PRNG keys, or
a `RecordSet` of recorded motions, scaled and zero-padded) is run through one structure, or
through D design variants of it, in chunks of `chunk_size` motions: one jit-compiled,
vmapped function per chunk, compiled once (the last chunk is padded), so memory is bounded
by the chunk and not by N. Each chunk is sharded along its batch axis over all JAX devices
(`jax.shard_map` over a 1-D mesh, each device with its own time stepping and Newton loops),
so the same call runs on one CPU, one device per CPU core, a GPU or several devices; a chunk
is rounded up to a multiple of the device count.

Each structure runs through the one peak driver (`systems.peak_response`), which folds the
response's reducers along the run keeping only running peaks and smooth maxima, never the
response histories: the memory per motion is that of its record.

Multi-host runs: call `jax.distributed.initialize()` (coordinator address, number of
processes and process id, or the cluster's environment variables) in every process before
any other JAX call; `jax.devices()` then lists the devices of all hosts and `monte_carlo`
shards each chunk over all of them (every process runs the same script with the same seed;
each host generates only the motions of its own shard). Results are gathered to every host.

Reference for the structures: Constantinou, Mokha & Reinhorn (1990), "Teflon bearings in base
isolation II: Modeling", J. Struct. Eng. 116(2), Figs. 7-11.
"""

import time
from collections.abc import Callable, Mapping, Sequence
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import check_design
from ..excitation import (
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    VerticalGroundMotion,
    uniform_signal,
)
from ..systems import (
    PEAK_REDUCERS,
    STEPS_PER_LOOP_PASS,
    SURFACE_REDUCERS,
    IsolatedStructure,
    StructureOnSliders,
    check_storey_height,
    flag_pressure_law,
    peak_arrays,
    peak_response,
)
from ._montecarlo_parts import (
    _check_chunk_and_first_motion,
    _chunk_counts,
    _peak_fields,
    _read_every,
    _run_duration,
    bytes_per_motion,
    check_chunk_memory,
    surface_attributes,
    surface_peaks,
)
from ._motion_source import _Source, level_of, motion_attributes, stochastic_grid
from ._posterior_motions import (
    check_bearings,
    draw_bearing,
    nest_runs,
    run_draws,
    with_bearing,
)
from ._record_set import RecordSet
from ._results import MonteCarloResult

# --------------------------------------------------------------------------- batch runs


def probe_structure(structure, source: _Source, design):
    """The shapes of one system `structure` builds for `source`'s motions (nothing computed);
    `ValueError` naming `structure` when it does not take that number of components."""
    two = source.components == 2
    if source.vertical != bool(getattr(structure, "vertical", False)):
        raise ValueError("structure: motions with a vertical component (VerticalGroundMotion) need "
                         "with_vertical_component(isolated_structure(...)), and only they.")
    if two and isinstance(structure, IsolatedStructure) and structure.components == 1:
        raise ValueError("structure: two-component motions need bidirectional_isolated_structure(...), "
                         "not isolated_structure(...).")
    if not two and isinstance(structure, IsolatedStructure) and structure.components == 2:
        raise ValueError("structure: a bidirectional structure needs two-component motions "
                         "(TwoComponentGroundMotion).")
    shape = jax.ShapeDtypeStruct((source.samples,), jnp.result_type(float))

    def build(values):
        ground = uniform_signal(values, source.time_step)
        horizontal = (ground, ground) if two else ground
        return structure((horizontal, ground) if source.vertical else horizontal, design)

    probe = jax.eval_shape(build, shape)
    if two != _two_components(probe):
        raise ValueError(f"structure: builds a {type(probe).__name__}, which does not take "
                         f"{source.components}-component motions.")
    return probe


def _two_components(system) -> bool:
    """Whether `system` steps under two horizontal ground components."""
    return isinstance(system, StructureOnSliders) and system.components == 2


def _put(array: np.ndarray, sharding):
    """A host array as a global array laid out by `sharding` (each process fills only its
    own devices' shards, so this also works across hosts)."""
    array = np.asarray(array)
    return jax.make_array_from_callback(array.shape, sharding, lambda index: array[index])


def _get(tree):
    """Fetch a (possibly multi-host) sharded result to NumPy on every process."""
    if jax.process_count() > 1:
        from jax.experimental import multihost_utils

        return multihost_utils.process_allgather(tree, tiled=True)
    return jax.device_get(tree)


class ChunkRunner:
    """One compiled function that runs `chunk` motions (vmapped, sharded over `devices`) and
    returns their peaks (`peak_arrays` of `peak_response`) and peak |a_g|: compiled at the first call, reused after
    (a Dask worker keeps one per run, so it compiles once whatever the number of chunks).
    The expected peak ground acceleration of generated motions is an argument of the call,
    not a constant of the program: one compilation serves every intensity level. With stacked
    `bearings` (a `SlidingBearing` whose leaves lead with an axis of draws) each run takes the
    draw its call names in place of the structure's bearing, as traced values: one compilation
    serves every draw."""

    def __init__(self, structure, source, duration, design_arrays, devices, chunk, disp_width, shear_width,
                 read_every=1, storey_height=None, bearings=None):
        self.devices, self.chunk, self.compile_s = list(devices), int(chunk), 0.0
        mesh = jax.sharding.Mesh(np.array(self.devices), ("batch",))
        # no gradients are taken here: two steps per pass of the uniaxial peak loop
        loop_options = {} if source.components == 2 else {"steps_per_pass": STEPS_PER_LOOP_PASS}
        if storey_height is not None:  # the building's peak drifts and floor accelerations too
            loop_options["storey_height"] = storey_height
        # the sliders' travel and the heated surfaces' temperature rise, where the isolator has them
        loop_options["reducers"] = PEAK_REDUCERS + SURFACE_REDUCERS + (
            () if storey_height is None else ("storey_drift_ratio", "level_acceleration"))
        self.batched = jax.sharding.NamedSharding(mesh, jax.sharding.PartitionSpec("batch"))
        replicated = jax.sharding.NamedSharding(mesh, jax.sharding.PartitionSpec())

        def run_chunk(indices, values, design_all, level, draws=None, stacked=None):
            def per_motion(index, row, draw):
                signal = source.signal(index, row, level)
                built = structure if stacked is None else with_bearing(structure, draw_bearing(stacked, draw))

                def one(design_one):
                    system = flag_pressure_law(built(signal, design_one))  # a run beyond Table 1: flagged
                    peaks = peak_response(system, duration, disp_width=disp_width, shear_width=shear_width,
                                          read_every=read_every, **loop_options)
                    return surface_peaks(system, peak_arrays(peaks))

                peaks = one(None) if design_all is None else jax.vmap(one)(design_all)
                horizontal = signal[0] if source.vertical else signal  # pga: the horizontal one's
                if source.components == 2:  # peak resultant |a_g|
                    return peaks, jnp.max(jnp.hypot(horizontal[0].values, horizontal[1].values))
                return peaks, jnp.max(jnp.abs(horizontal.values))

            return jax.vmap(per_motion)(indices, values, draws)

        # shard_map, not automatic partitioning: every device steps its own motions with its
        # own Newton loops; partitioned automatically, the batched while loop's "any member
        # not converged" test would become a cross-device reduction in every iteration.
        spec = jax.sharding.PartitionSpec
        drawn = () if bearings is None else (spec("batch"), spec())  # each run's draw; the draws
        self.function = jax.jit(
            jax.shard_map(
                run_chunk,
                mesh=mesh,
                in_specs=(spec("batch"), spec("batch"), spec(), spec()) + drawn,
                out_specs=spec("batch"),
                check_vma=False,
            ),
            in_shardings=(self.batched, self.batched, replicated, replicated)
            + (() if bearings is None else (self.batched, replicated)),
            out_shardings=self.batched,
        )
        self.design = None if design_arrays is None else jax.device_put(design_arrays, replicated)
        self.bearings = None if bearings is None else jax.device_put(bearings, replicated)
        self.replicated, self.default_level = replicated, 0.0 if source.model is None else level_of(source.model)
        self.compiled = None
        # On a CPU a series pendulum's program runs about 1.5 x faster compiled with XLA's older
        # fusion emitters, flat sliders' slower (benchmarks/README.md, "Fusion emitters").
        series = getattr(structure, "pendulum", None) is not None
        self.options = {"xla_cpu_use_fusion_emitters": False} if series and self.devices[0].platform == "cpu" else None

    def __call__(self, indices, values=None, level=None, draws=None):
        """Peaks of the motions `indices` (a chunk's worth; `values` (chunk, nt) [m/s^2] for
        recorded motions, `None` for generated ones; `level` [m/s^2] the expected peak ground
        acceleration of generated ones, default the model's; `draws` (chunk,) each run's draw
        of the stacked bearings, with them only), as sharded device arrays."""
        indices = np.asarray(indices)
        values = np.zeros((indices.shape[0], 1)) if values is None else np.asarray(values)
        level = jnp.asarray(self.default_level if level is None else level, dtype=jnp.result_type(float))
        args = (_put(indices.astype(np.int32), self.batched), _put(values, self.batched), self.design,
                jax.device_put(level, self.replicated))
        if (draws is None) != (self.bearings is None):
            raise ValueError("draws: give each run's draw exactly when the runner has stacked bearings.")
        if draws is not None:
            args += (_put(np.asarray(draws).astype(np.int32), self.batched), self.bearings)
        if self.compiled is None:
            tic = time.perf_counter()
            self.compiled = self.function.lower(*args).compile(compiler_options=self.options)
            self.compile_s = time.perf_counter() - tic
        return self.compiled(*args)


def monte_carlo(
    structure: Callable,
    motions: StochasticGroundMotion | RecordSet,
    n_motions: int | None = None,
    *,
    key=None,
    duration: float | None = None,
    design: Mapping | None = None,
    chunk_size: int = 512,
    devices: Sequence | None = None,
    progress: Callable[[int, int], None] | None = None,
    disp_width=None,
    shear_width=None,
    memory_limit_bytes: int | None = None,
    first_motion: int = 0,
    peak_interval: float | None = None,
    storey_height=None,
    bearings=None,
    bearing_draw=None,
    nested: bool = False,
) -> MonteCarloResult:
    """Peak responses of `structure` under N ground motions (and D design variants, or the
    draws of a bearing posterior).

    Motion i of a stochastic set is `sample(model, fold_in(key, i), 1)[0]`, so a run's
    numbers do not depend on the chunk size or the number of devices. The batch runs in
    chunks of `chunk_size` motions through one compiled function (vmap over motions and
    design variants, `peak_response` inside); each chunk's batch axis is split over
    `devices` (`shard_map` on a 1-D mesh "batch": every device steps its own motions).
    Multi-host: see the module docstring (`jax.distributed.initialize()` first).

    On a CPU, JAX makes one device of the whole processor, and a batch of small per-motion
    operations then uses about one core. `jax.config.update("jax_num_cpu_devices",
    os.cpu_count())` right after `import jax` (the `teflon-jax` command does this) gives one
    device per core; on 2 cores this ran 2.3x faster (benchmarks B3). On a processor with
    AVX-512, `prefer_wide_cpu_vectors()` before JAX's first computation asks XLA for 512-bit
    vector code (the command does both): 15-18 % less CPU per record, the same peaks.

    **Arguments:**

    - `structure`: callable `(ground_acceleration, design) -> StructureOnSliders`, e.g.
      `isolated_structure("building", ...)`; `ground_acceleration` is a uniform `Signal`. For
      two-component motions a callable `((ground_x, ground_y), design) ->
      StructureOnSliders`, e.g. `bidirectional_isolated_structure("rigid", ...)`; the
      peaks are then resultants (`peak_response`) and `pga` the peak |(a_x, a_y)|.
    - `motions`: a `StochasticGroundMotion` or a `TwoComponentGroundMotion` (with `n_motions`
      and `key`; motion i's major component is then the one-component motion i), either inside a
      `VerticalGroundMotion` (with `structure = with_vertical_component(...)`; the horizontal
      components are then those drawn without it, the result holds `uplift_time`), or a `RecordSet`.
    - `n_motions`: N > 0 (stochastic; for a `RecordSet` defaults to all its records).
    - `key`: JAX PRNG key (stochastic motions); default `jax.random.key(0)`.
    - `duration` [s]: default the record length.
    - `design`: dict of `DESIGN_VARIABLES` -> (D,) arrays, run for every motion; or `None`.
    - `chunk_size`: motions per compiled call (rounded up to a multiple of the devices).
    - `devices`: JAX devices to shard over (default all of `jax.devices()`).
    - `progress`: called as `progress(done, total)` after each chunk (e.g. a tqdm update).
    - `disp_width` [m], `shear_width` [-]: widths of the smooth maxima (`peak_response`).
    - `memory_limit_bytes`: memory a chunk may use (default: half of the free memory).
    - `first_motion`: index of the first stochastic motion (motions `first_motion` ..
      `first_motion + N - 1` of the key are run; how `monte_carlo_distributed` splits a run).
    - `peak_interval` [s]: read the peaks every `peak_interval` (a multiple of the structure's
      step, e.g. the record step, to compare with a program that records there); default
      every step.
    - `storey_height` [m]: a building: also keep each storey's peak drift ratio and each
      level's peak total acceleration (`peak_response`; with two components in x and y),
      e.g. `load_table2().storey_height`; default `None`.
    - `bearings`: S draws of the structure's bearing stacked as one `SlidingBearing` whose
      leaves lead with an axis of S (`BearingPosterior.bearings(point)`), run in place of the
      structure's own (built with `bearing=point`) as traced values; not with `design`.
    - `bearing_draw`: with `bearings`, int draw indices in [0, S): one per motion (N,)
      (`motion_draws`), or with `nested=True` the K draws (K,) (`nested_draws`) each run on
      all N motions (the result's dims are then ("bearing", "motion"), the peaks (K, N)).
      The result's `bearing_draw` keeps them.

    **Returns:** a `MonteCarloResult`.
    """
    start = time.perf_counter()
    plan = _plan(structure, motions, n_motions, key=key, duration=duration, design=design, chunk_size=chunk_size,
                 devices=devices, disp_width=disp_width, shear_width=shear_width,
                 memory_limit_bytes=memory_limit_bytes, first_motion=first_motion, peak_interval=peak_interval,
                 storey_height=storey_height, bearings=bearings, bearing_draw=bearing_draw, nested=nested)
    outputs = _run_chunks(plan.runner, motions, plan.n_total, plan.chunk, plan.n_chunks, first_motion, progress,
                          draws=plan.draws)
    return _result(plan, motions, outputs, time.perf_counter() - start)


class _Plan(NamedTuple):
    """A checked run of `monte_carlo`: its compiled-once chunk function and its sizes."""

    runner: ChunkRunner
    n_total: int
    chunk: int
    n_chunks: int
    design_arrays: dict | None
    n_dof: int
    duration: float
    time_step: float
    vertical: bool
    storeys: bool
    estimate: int
    draws: np.ndarray | None = None  # each run's draw of the stacked bearings
    bearing_draw: np.ndarray | None = None
    nested: bool = False
    group_names: tuple = ()  # a plan's groups (`BuiltStructure.group_names`): the results' group axis
    surface_names: dict = {}  # the surfaces' labels (`surface_attributes`)


def _plan(structure, motions, n_motions, *, key=None, duration=None, design=None, chunk_size=512, devices=None,
          disp_width=None, shear_width=None, memory_limit_bytes=None, first_motion=0, peak_interval=None,
          storey_height=None, bearings=None, bearing_draw=None, nested=False) -> _Plan:
    """The checked inputs of `monte_carlo` (same arguments) and its `ChunkRunner` (not yet compiled)."""
    source, n_total = _motion_source(motions, n_motions, key)
    _check_chunk_and_first_motion(chunk_size, first_motion)
    duration = _run_duration(source, duration)
    design_arrays, n_designs = _design_arrays(design, structure)
    draws = _bearing_runs(structure, design_arrays, bearings, bearing_draw, nested, n_total)
    devices = list(jax.devices() if devices is None else devices)
    chunk, n_chunks = _chunk_counts(chunk_size, n_total if draws is None else draws.size, len(devices))
    # Shapes of one system, without computing it: degrees of freedom for the memory estimate.
    probe_design = None if design_arrays is None else {k: v[0] for k, v in design_arrays.items()}
    probe = probe_structure(structure, source, probe_design)
    n_dof = probe.mass.shape[-1]
    per_motion = bytes_per_motion((source.components + source.vertical) * source.samples, n_dof, n_designs)
    check_chunk_memory(chunk, per_motion, memory_limit_bytes, devices)
    read_every = _read_every(peak_interval, probe.time_step)
    if storey_height is not None:  # refused here, before the compile, for a rigid mass
        # x and y: 2 n coordinates, but one set of masses for a series pendulum's structure
        per_direction = n_dof // source.components if probe.planar else n_dof
        check_storey_height(per_direction, storey_height)
    runner = ChunkRunner(structure, source, duration, design_arrays, devices, chunk, disp_width,
                         shear_width, read_every, storey_height, bearings=None if draws is None else bearings)
    return _Plan(runner, n_total, chunk, n_chunks, design_arrays, int(n_dof), duration, source.time_step,
                 source.vertical, storey_height is not None, int(chunk * per_motion), draws,
                 None if draws is None else np.asarray(bearing_draw), bool(nested and draws is not None),
                 tuple(getattr(structure, "group_names", ())), surface_attributes(probe))


def _bearing_runs(structure, design_arrays, bearings, bearing_draw, nested, n_total):
    """Each run's draw of the stacked `bearings` (`run_draws`), checked; `None` without them."""
    if bearings is None:
        if bearing_draw is not None or nested:
            raise ValueError("bearing_draw, nested: apply to stacked bearings; give bearings=... too.")
        return None
    if design_arrays is not None:
        raise ValueError("design: the runs take the bearings' draws; run design variants without bearings.")
    return run_draws(bearing_draw, check_bearings(structure, bearings), n_total, nested)


def _result(plan: _Plan, motions, outputs, wall_s: float) -> MonteCarloResult:
    """The `MonteCarloResult` of the chunks' `outputs` (host arrays, in order) of `plan`."""
    n_runs = plan.n_total if plan.draws is None else plan.draws.size
    peaks, pga = jax.tree_util.tree_map(lambda *xs: np.concatenate(xs, axis=0)[:n_runs], *outputs)
    if plan.nested:  # runs r = k N + m: (K, N) arrays; a motion's pga is the same for every bearing
        peaks, pga = nest_runs(peaks, plan.bearing_draw.size), pga[:plan.n_total]
    design_arrays = plan.design_arrays
    dims = ("motion",) if design_arrays is None else ("design", "motion")
    return MonteCarloResult(
        **_peak_fields(peaks, design_arrays is not None, plan.storeys, plan.vertical),
        pga=np.asarray(pga),
        design={} if design_arrays is None else {k: np.asarray(v) for k, v in design_arrays.items()},
        dims=("bearing", "motion") if plan.nested else dims,
        bearing_draw=plan.bearing_draw,
        n_devices=len(plan.runner.devices),
        chunk_size=plan.chunk,
        wall_s=wall_s,
        compile_s=plan.runner.compile_s,
        memory_estimate_bytes=plan.estimate,
        attrs={"duration_s": plan.duration, "record_time_step_s": plan.time_step, "n_dof": plan.n_dof,
               **motion_attributes(motions), **({"group_names": list(plan.group_names)} if plan.group_names else {}),
               **plan.surface_names},
    )


def _motion_source(motions, n_motions, key) -> tuple:
    """(`_Source` of the motions, number of motions to run), checked."""
    if isinstance(motions, RecordSet):
        n_total = motions.acceleration.shape[0] if n_motions is None else n_motions
        source = _Source(None, None, motions.time_step, motions.acceleration.shape[1])
    elif isinstance(motions, (StochasticGroundMotion, TwoComponentGroundMotion, VerticalGroundMotion)):
        if n_motions is None:
            raise ValueError("n_motions: give the number of stochastic motions to draw (> 0).")
        n_total = n_motions
        key = jax.random.key(0) if key is None else key
        time_step, samples, _ = stochastic_grid(motions)
        source = _Source(motions, key, time_step, samples)
    else:
        raise ValueError(
            "motions: expected a StochasticGroundMotion, a TwoComponentGroundMotion, a VerticalGroundMotion "
            "or a RecordSet, "
            f"got {type(motions).__name__}."
        )
    if isinstance(n_total, bool) or not isinstance(n_total, (int, np.integer)) or n_total <= 0:
        raise ValueError(f"n_motions: must be a positive integer, got {n_total!r}.")
    n_total = int(n_total)
    if isinstance(motions, RecordSet) and n_total > motions.acceleration.shape[0]:
        raise ValueError(
            f"n_motions: {n_total} asked for but the RecordSet has {motions.acceleration.shape[0]} records."
        )
    return source, n_total


def _design_arrays(design, structure) -> tuple:
    """(design variables as (D,) arrays or `None`, D or 0), checked."""
    if not design:
        return None, 0
    design_arrays = {name: jnp.atleast_1d(jnp.asarray(v, dtype=float)) for name, v in design.items()}
    sizes = {v.shape[0] for v in design_arrays.values()}
    if len(sizes) != 1 or any(v.ndim != 1 for v in design_arrays.values()):
        raise ValueError(
            f"design: every variable needs a 1-D array of the same length, got shapes "
            f"{ {k: tuple(v.shape) for k, v in design_arrays.items()} }."
        )
    n_designs = sizes.pop()
    check_design_of(structure, design_arrays)
    return design_arrays, n_designs


def check_design_of(structure, design_arrays) -> None:
    """`check_design` of a flat-slider or single-pendulum `structure` (one or two components,
    with or without a vertical one); series pendulums check their own."""
    if isinstance(structure, IsolatedStructure) and structure.pendulum is None:
        check_design(structure, design_arrays)


def _run_chunks(runner, motions, n_total, chunk, n_chunks, first_motion, progress, level=None, draws=None) -> list:
    """Each chunk's peaks on the host, one chunk after another: `progress` is called when a
    chunk's peaks are on the host, so the times between calls are the chunks' run times. (On a
    GPU a call that holds `while_loop`s returns only when it is done, since XLA reads each loop's
    condition on the host; fetching a chunk while the next one runs then gained nothing, and
    the calls came one chunk late.) `level` [m/s^2]: the generated motions' expected peak
    ground acceleration (default the model's). `draws`: each run's draw of the runner's stacked
    bearings, run r taking motion r mod `n_total` (`run_draws`); `progress` then counts runs."""
    outputs = []
    n_runs = n_total if draws is None else draws.size
    for c in range(n_chunks):
        runs = np.minimum(np.arange(c * chunk, (c + 1) * chunk), n_runs - 1)  # pad the last chunk with copies
        indices = runs % n_total
        values = motions.acceleration[indices] if isinstance(motions, RecordSet) else None
        outputs.append(_get(runner(indices + first_motion, values, level,
                                   draws=None if draws is None else draws[runs])))
        if progress is not None:
            progress(min((c + 1) * chunk, n_runs), n_runs)
    return outputs
