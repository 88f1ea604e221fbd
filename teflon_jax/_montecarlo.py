"""Monte Carlo of isolated structures under many ground motions, chunked and sharded.

A batch of N ground motions (drawn from `StochasticGroundMotion` with explicit PRNG keys, or
a `RecordSet` of recorded motions, scaled and zero-padded) is run through one structure, or
through D design variants of it, in chunks of `chunk_size` motions: one jit-compiled,
vmapped function per chunk, compiled once (the last chunk is padded), so memory is bounded
by the chunk and not by N. Each chunk is sharded along its batch axis over all JAX devices
(`jax.shard_map` over a 1-D mesh, each device with its own time stepping and Newton loops),
so the same call runs on one CPU, one device per CPU core, a GPU or several devices; a chunk
is rounded up to a multiple of the device count.

The structure is integrated with the `RiccatiNewmark` step of `StructureOnSliders`
(`exact_step`) inside a `lax.scan` that keeps only running peaks and smooth maxima, never
the response histories: the memory per motion is that of its record.

Multi-host runs: call `jax.distributed.initialize()` (coordinator address, number of
processes and process id, or the cluster's environment variables) in every process before
any other JAX call; `jax.devices()` then lists the devices of all hosts and `monte_carlo`
shards each chunk over all of them (every process runs the same script with the same seed;
each host generates only the motions of its own shard). Results are gathered to every host.

Reference for the structures: Constantinou, Mokha & Reinhorn (1990), "Teflon bearings in base
isolation II: Modeling", J. Struct. Eng. 116(2), Figs. 7-11.
"""

import dataclasses
import math
import os
import time
from collections.abc import Callable, Mapping, Sequence

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._bearing import paper_bearing
from ._checks import concrete
from ._friction import FrictionParameters
from ._models import rigid_mass, six_storey_building
from ._motion import uniform_signal
from ._stochastic import StochasticGroundMotion, num_time_steps, sample
from ._structure import StructureOnSliders, initial_state
from ._tables import friction_table
from ._units import PSI, STANDARD_GRAVITY

STRUCTURES = ("rigid", "building")
DESIGN_VARIABLES = (
    "isolation_period",
    "pressure",
    "isolation_damping",
    "f_max",
    "delta_f",
    "rate_a",
    "breakaway_ratio",
)
"""Names a design dict may set: T_b [s], contact pressure [Pa] (Eq. 1 constants and b from
Table 1 at that pressure), zeta_b [-], and Eq. 1 / Eq. 17 constants overriding Table 1."""

RECOMMENDED_TIME_STEPS = {"rigid": 0.0025, "building": 0.0025}
"""Structure step [s] per structure: with it the peak base displacement and base shear of
every one of 100 forty-second Clough-Penzien motions (records at 0.01 s) lie within 0.2 % of
0.5 ms steps (benchmarks/bench_scale.py, B3 accuracy). At 5 ms the worst motions were off by
0.51 % (rigid mass) and 1.6 % (building): the error gathers in the steps where the sliding
velocity reverses under a strong pulse, and in the building's short storey modes."""

RESPONSE_NAMES = ("base_disp", "base_shear_ratio")
"""Peak |base displacement| [m] and peak |base shear| / weight above the isolators [-]."""


class PeakResponse(eqx.Module):
    """Peaks of one response history (scalars, or batched by `monte_carlo`).

    - `base_disp` max_t |u_0(t)| [m]: isolator displacement relative to the ground.
    - `base_shear_ratio` max_t |V(t)| / W_s [-]: V = sum_j m_j a_j^total over the masses
      above the isolators (floors 1.. of a building: the first-storey shear), or m a^total for
      a rigid mass; W_s their weight.
    - `smooth_base_disp`, `smooth_base_shear_ratio`: the same maxima through `smooth_max`
      (differentiable); equal to the peaks' lower bounds when no width is given.
    - `converged`: every step's Newton iteration converged.
    """

    base_disp: jnp.ndarray
    base_shear_ratio: jnp.ndarray
    smooth_base_disp: jnp.ndarray
    smooth_base_shear_ratio: jnp.ndarray
    converged: jnp.ndarray


def smooth_max(x, width, axis=-1):
    """Smooth maximum of |x| along `axis`: the log-mean-cosh

        M_w(x) = w log( (1/n) sum_t cosh(x_t / w) ),

    with max|x| - w log(2 n) <= M_w(x) <= max|x| and M_w -> max|x| as w -> 0; smooth in x for
    w > 0 (its gradient is a softmax weighting of the samples near the peak).

    **Arguments:** `x` (any shape); `width` w > 0 [units of x]; `axis`: time axis.

    **Returns:** M_w(x) with `axis` removed.
    """
    x = jnp.asarray(x)
    n = x.shape[axis]
    top = jax.lax.stop_gradient(jnp.max(jnp.abs(x), axis=axis, keepdims=True))
    terms = 0.5 * (jnp.exp((x - top) / width) + jnp.exp((-x - top) / width))
    return jnp.squeeze(top, axis) + width * jnp.log(jnp.sum(terms, axis=axis) / n)


def _shear_ratio(system: StructureOnSliders, relative_acceleration, t):
    """|V| / W_s for the relative accelerations [m/s^2] at time t (see `PeakResponse`)."""
    total = relative_acceleration + system.ground_acceleration(t)
    mass = system.mass if system.mass.shape[-1] == 1 else system.mass[1:]
    acc = total if system.mass.shape[-1] == 1 else total[1:]
    return jnp.sum(mass * acc) / (jnp.sum(mass) * STANDARD_GRAVITY)


def peak_response(
    system: StructureOnSliders,
    duration: float,
    *,
    disp_width=None,
    shear_width=None,
) -> PeakResponse:
    """Integrate `system` from rest over `duration` [s] and keep only peaks.

    The same `RiccatiNewmark` step as `simulate_structure` (Newmark average acceleration
    with the exact Bouc-Wen update), advanced in a `lax.scan` whose carry holds the state,
    the running maxima and a running log-sum-exp for `smooth_max` (the t = 0 rest state
    included, as in `simulate_structure`'s saved times). jit/vmap/grad-safe.

    **Arguments:**

    - `system`: a `StructureOnSliders` (rigid mass or building; DOF 0 = isolator).
    - `duration` [s]: end time, rounded down to a multiple of `system.time_step`.
    - `disp_width` [m], `shear_width` [-]: widths w of `smooth_max` for the base displacement
      and base shear ratio (default: 1e-3 m and 1e-3).

    **Returns:** a `PeakResponse`.
    """
    dt = float(system.time_step)
    n_steps = int(round(duration / dt + 1e-9))
    if n_steps < 1:
        raise ValueError(f"duration: must be at least one time step ({dt} s), got {duration}.")
    dtype = system.mass.dtype
    widths = (
        jnp.asarray(1e-3 if disp_width is None else disp_width, dtype),
        jnp.asarray(1e-3 if shear_width is None else shear_width, dtype),
    )

    def lse_update(top, total, x, width):
        new_top = jnp.maximum(top, jax.lax.stop_gradient(jnp.abs(x)))
        total = total * jnp.exp((top - new_top) / width) + 0.5 * (
            jnp.exp((x - new_top) / width) + jnp.exp((-x - new_top) / width)
        )
        return new_top, total

    def body(carry, step):
        y, a, peaks, tops, totals, ok = carry
        t0 = step * dt
        y1, converged = system.newmark_step(t0, t0 + dt, y, a)
        a1 = system._acceleration(t0 + dt, y1)
        values = (y1["u"][0], _shear_ratio(system, a1, t0 + dt))
        peaks = tuple(jnp.maximum(p, jnp.abs(v)) for p, v in zip(peaks, values))
        updated = [lse_update(a, s, v, w) for a, s, v, w in zip(tops, totals, values, widths)]
        tops = tuple(u[0] for u in updated)
        totals = tuple(u[1] for u in updated)
        return (y1, a1, peaks, tops, totals, ok & converged), None

    zero = jnp.zeros((), dtype)
    one = jnp.ones((), dtype)
    y0 = initial_state(system)
    carry = (y0, system._acceleration(0.0, y0), (zero, zero), (zero, zero), (one, one), jnp.array(True))
    (_, _, peaks, tops, totals, ok), _ = jax.lax.scan(body, carry, jnp.arange(n_steps))
    smooth = [a + w * jnp.log(s / (n_steps + 1)) for a, s, w in zip(tops, totals, widths)]
    return PeakResponse(
        base_disp=peaks[0],
        base_shear_ratio=peaks[1],
        smooth_base_disp=smooth[0],
        smooth_base_shear_ratio=smooth[1],
        converged=ok,
    )


# --------------------------------------------------------------------------- structures


class IsolatedStructure(eqx.Module):
    """Builds the rigid mass or the six-storey building for one motion and one design.

    Call as `structure(ground_acceleration, design)` with `design` a dict of some of
    `DESIGN_VARIABLES` (arrays, traced or not; missing ones take the defaults below).

    **Fields:**

    - `kind` (static): "rigid" (`rigid_mass`) or "building" (`six_storey_building`, Table 2).
    - `ptfe`, `direction` (static): Table 1 rows, e.g. "UF", "P".
    - `pressure` [Pa]: bearing contact pressure; Eq. 1 constants and the breakaway ratio b
      are interpolated in Table 1 at it (differentiable).
    - `isolation_period` T_b [s] of the restoring springs (`None` for a rigid mass on flat
      sliders without springs).
    - `isolation_damping` zeta_b [-] of the rigid-body mode.
    - `breakaway` (static): use Table 1's b (Eq. 17) when True; no breakaway when False.
    - `friction_model` (static): "hysteretic", "coulomb" or "none".
    - `time_step` [s] (static): structure step; `weight` [N] of the rigid mass.
    """

    pressure: jnp.ndarray
    isolation_period: jnp.ndarray | None
    isolation_damping: jnp.ndarray
    kind: str = eqx.field(static=True, default="rigid")
    ptfe: str = eqx.field(static=True, default="UF")
    direction: str = eqx.field(static=True, default="P")
    breakaway: bool = eqx.field(static=True, default=True)
    friction_model: str = eqx.field(static=True, default="hysteretic")
    time_step: float = eqx.field(static=True, default=0.0025)
    weight: float = eqx.field(static=True, default=100e3)

    def table(self):
        """The Table 1 rows (extrapolation switched off by our own range check)."""
        return friction_table(self.ptfe, self.direction, extrapolate=True)

    def __call__(self, ground_acceleration, design: Mapping | None = None) -> StructureOnSliders:
        design = {} if design is None else dict(design)
        unknown = sorted(set(design) - set(DESIGN_VARIABLES))
        if unknown:
            raise ValueError(
                f"design: unknown variable(s) {unknown}; accepted: {', '.join(DESIGN_VARIABLES)}."
            )
        pressure = design.get("pressure", self.pressure)
        params, b = self.table().at(pressure)
        params = FrictionParameters(
            f_max=design.get("f_max", params.f_max),
            delta_f=design.get("delta_f", params.delta_f),
            rate_a=design.get("rate_a", params.rate_a),
        )
        b = design.get("breakaway_ratio", b)
        bearing = paper_bearing(params, breakaway_ratio=b if self.breakaway else None)
        period = design.get("isolation_period", self.isolation_period)
        damping = design.get("isolation_damping", self.isolation_damping)
        if self.kind == "rigid":
            return rigid_mass(
                weight=self.weight,
                bearing=bearing,
                ground_acceleration=ground_acceleration,
                time_step=self.time_step,
                isolation_period=period,
                damping_ratio=damping if period is not None else 0.0,
                friction_model=self.friction_model,
            )
        return six_storey_building(
            bearing=bearing,
            ground_acceleration=ground_acceleration,
            time_step=self.time_step,
            isolation_period=period,
            isolation_damping=damping,
            friction_model=self.friction_model,
        )


def isolated_structure(
    kind: str = "rigid",
    *,
    ptfe: str = "UF",
    direction: str = "P",
    pressure=1000 * PSI,
    isolation_period=2.0,
    isolation_damping=0.05,
    breakaway: bool = True,
    friction_model: str = "hysteretic",
    time_step: float | None = None,
) -> IsolatedStructure:
    """An `IsolatedStructure` with its inputs checked (`ValueError` naming the parameter).

    **Arguments:** see `IsolatedStructure`; `pressure` [Pa] must lie inside the Table 1 rows
    of `ptfe`/`direction` (1000-6500 psi for UF, P), `isolation_period` [s] > 0 (or `None`
    for a rigid mass on flat sliders), `isolation_damping` >= 0, `time_step` > 0 [s]
    (default `RECOMMENDED_TIME_STEPS[kind]`).
    """
    if kind not in STRUCTURES:
        raise ValueError(f"structure: unknown {kind!r}; accepted: {', '.join(STRUCTURES)}.")
    time_step = RECOMMENDED_TIME_STEPS[kind] if time_step is None else time_step
    if not (isinstance(time_step, (int, float)) and time_step > 0):
        raise ValueError(f"time_step: must be a positive number of seconds, got {time_step!r}.")
    structure = IsolatedStructure(
        pressure=jnp.asarray(pressure, dtype=float),
        isolation_period=None if isolation_period is None else jnp.asarray(isolation_period, float),
        isolation_damping=jnp.asarray(isolation_damping, dtype=float),
        kind=kind,
        ptfe=ptfe,
        direction=direction,
        breakaway=breakaway,
        friction_model=friction_model,
        time_step=float(time_step),
    )
    check_design(structure, {"pressure": pressure})
    if isolation_period is None and kind == "building":
        raise ValueError("isolation_period: the building needs T_b [s] > 0 (Fig. 11: 0.2-4 s).")
    if isolation_period is not None:
        check_design(structure, {"isolation_period": isolation_period})
    check_design(structure, {"isolation_damping": isolation_damping})
    return structure


def design_ranges(structure: IsolatedStructure) -> dict[str, tuple[float, float]]:
    """Admissible range [low, high] of each design variable (SI): the pressure within the
    Table 1 rows, positive periods, damping in [0, 1), friction constants in their physical
    ranges."""
    pressures = np.asarray(structure.table().pressures)
    return {
        "isolation_period": (1e-3, math.inf),
        "pressure": (float(pressures[0]), float(pressures[-1])),
        "isolation_damping": (0.0, 1.0),
        "f_max": (1e-6, 1.0),
        "delta_f": (0.0, 1.0),
        "rate_a": (0.0, math.inf),
        "breakaway_ratio": (1.0, math.inf),
    }


def check_design(structure: IsolatedStructure, design: Mapping) -> None:
    """`ValueError` naming the variable when a concrete design value is outside its range
    (`design_ranges`), e.g. a pressure outside Table 1's 1000-6500 psi for UF."""
    ranges = design_ranges(structure)
    for name, value in design.items():
        if name not in ranges:
            raise ValueError(
                f"design: unknown variable {name!r}; accepted: {', '.join(DESIGN_VARIABLES)}."
            )
        array = concrete(value)
        if array is None:  # traced: checked by the caller's bounds instead
            continue
        array = array.astype(float)
        lo, hi = ranges[name]
        tolerance = 1e-6 * max(abs(lo), abs(hi) if math.isfinite(hi) else 0.0, 1.0)  # float32 rounding
        bad = ~np.isfinite(array) | (array < lo - tolerance) | (array > hi + tolerance)
        if np.any(bad):
            if name == "pressure":
                text = (
                    f"outside the Table 1 rows of {structure.ptfe}/{structure.direction}, "
                    f"{lo / PSI:.0f}-{hi / PSI:.0f} psi ({lo:.4g}-{hi:.4g} Pa)"
                )
                shown = (array[bad] / PSI).tolist()
                raise ValueError(f"pressure: {text}; got {shown} psi.")
            raise ValueError(
                f"{name}: must lie in [{lo}, {hi}]; got {array[bad].tolist()}."
            )


# --------------------------------------------------------------------------- motions


@dataclasses.dataclass(frozen=True)
class RecordSet:
    """Recorded ground motions on a common sampling grid, zero-padded to a common length.

    **Fields:** `acceleration` (N, nt) [m/s^2]; `time_step` [s]; `names` (N,) labels.
    """

    acceleration: np.ndarray
    time_step: float
    names: tuple[str, ...]

    def __post_init__(self):
        array = np.asarray(self.acceleration, dtype=float)
        if array.ndim != 2 or array.shape[0] < 1 or array.shape[1] < 2:
            raise ValueError(
                f"acceleration: a RecordSet needs an (N >= 1, nt >= 2) array, got shape {array.shape}."
            )
        if not np.all(np.isfinite(array)):
            raise ValueError("acceleration: a RecordSet contains NaN or infinite values.")
        if not self.time_step > 0:
            raise ValueError(f"time_step: must be > 0 s, got {self.time_step}.")
        if len(self.names) != array.shape[0]:
            raise ValueError(f"names: {len(self.names)} labels for {array.shape[0]} records.")
        object.__setattr__(self, "acceleration", array)

    @property
    def duration(self) -> float:
        return (self.acceleration.shape[1] - 1) * self.time_step


def record_set(motions: Sequence, *, duration: float | None = None, scale=1.0) -> RecordSet:
    """Stack `GroundMotion`s (`load_record`, `read_at2`, ...) into a `RecordSet`.

    All motions must share one time step (resample them first with `.resampled`); each is
    multiplied by `scale` (a number or one per motion) and padded with zero acceleration to
    `duration` [s] (default: the longest record). Clocks restart at 0 (windowed records).
    """
    if len(motions) == 0:
        raise ValueError("motions: no ground motions given.")
    steps = {float(m.time_step) for m in motions}
    if len(steps) != 1:
        raise ValueError(
            f"motions: time steps differ ({sorted(steps)} s); resample them to one step with "
            "GroundMotion.resampled first."
        )
    dt = steps.pop()
    scales = np.broadcast_to(np.asarray(scale, dtype=float), (len(motions),))
    longest = max(len(m.acceleration) for m in motions)
    nt = longest if duration is None else int(round(duration / dt)) + 1
    if nt < longest:
        raise ValueError(
            f"duration: {duration} s is shorter than the longest record "
            f"({(longest - 1) * dt} s); records are padded, never cut."
        )
    values = np.zeros((len(motions), nt))
    for i, (motion, factor) in enumerate(zip(motions, scales)):
        values[i, : len(motion.acceleration)] = factor * np.asarray(motion.acceleration)
    return RecordSet(values, dt, tuple(getattr(m, "name", f"record {i}") for i, m in enumerate(motions)))


# --------------------------------------------------------------------------- batch runs


@dataclasses.dataclass
class MonteCarloResult:
    """Peaks of a Monte Carlo run, as NumPy arrays labelled by `dims`.

    - `base_disp` [m], `base_shear_ratio` [-]: shape (N,) or (D, N) with design variants;
    - `smooth_base_disp`, `smooth_base_shear_ratio`: the smooth maxima (same shapes);
    - `converged` (bool, same shape); `pga` (N,) [m/s^2]: peak |a_g| of each motion;
    - `design`: dict name -> (D,) values (empty without variants);
    - `dims`: axis names, ("motion",) or ("design", "motion");
    - `n_devices`, `chunk_size`, `wall_s` (total), `compile_s` (first chunk's compile),
      `memory_estimate_bytes` (one chunk); `attrs`: description of the run.
    """

    base_disp: np.ndarray
    base_shear_ratio: np.ndarray
    smooth_base_disp: np.ndarray
    smooth_base_shear_ratio: np.ndarray
    converged: np.ndarray
    pga: np.ndarray
    design: dict
    dims: tuple
    n_devices: int
    chunk_size: int
    wall_s: float
    compile_s: float
    memory_estimate_bytes: int
    attrs: dict = dataclasses.field(default_factory=dict)

    @property
    def n_motions(self) -> int:
        return int(self.pga.shape[0])

    def percentiles(self, q: Sequence[float] = (5, 16, 50, 84, 95)) -> dict:
        """{"base_disp_m": {"p50": .., "mean": ..}, "base_shear_ratio": {..}} over motions
        (per design variant when there are several: lists)."""
        out = {}
        for key, values in (("base_disp_m", self.base_disp), ("base_shear_ratio", self.base_shear_ratio)):
            stats = {f"p{g:g}": np.percentile(values, g, axis=-1).tolist() for g in q}
            stats["mean"] = np.mean(values, axis=-1).tolist()
            stats["std"] = np.std(values, axis=-1).tolist()
            out[key] = stats
        return out

    def exceedance(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """Empirical exceedance curve of `name` ("base_disp" or "base_shear_ratio"):
        sorted levels x_(k) and P[X > x] estimated as (N - k) / N, k = 1..N (per variant)."""
        if name not in RESPONSE_NAMES:
            raise ValueError(f"name: unknown {name!r}; accepted: {', '.join(RESPONSE_NAMES)}.")
        values = np.sort(getattr(self, name), axis=-1)
        n = values.shape[-1]
        return values, (n - np.arange(1, n + 1)) / n


def available_memory_bytes(device=None) -> int | None:
    """Free memory [bytes] of `device` (its allocator's limit minus use), or for a CPU the
    host's MemAvailable from /proc/meminfo; `None` when unknown."""
    device = jax.devices()[0] if device is None else device
    try:
        stats = device.memory_stats()
    except Exception:  # backends without memory statistics
        stats = None
    if stats and "bytes_limit" in stats:
        return int(stats["bytes_limit"] - stats.get("bytes_in_use", 0))
    try:
        with open("/proc/meminfo") as handle:
            for line in handle:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def bytes_per_motion(record_samples: int, n_dof: int, n_designs: int) -> int:
    """Estimate of the memory one motion of a chunk needs [bytes] (float64): the record and
    the temporaries of its generation (about 8 record-sized arrays), and per design the
    structure's matrices (3 n^2) and scan carry."""
    return 8 * (8 * record_samples + max(n_designs, 1) * (4 * n_dof**2 + 64))


def monte_carlo_motion(model: StochasticGroundMotion, key, index):
    """The `index`-th motion [m/s^2] that `monte_carlo(structure, model, n, key=key)` draws
    (one sample from `jax.random.fold_in(key, index)`), e.g. to run it through another program."""
    return sample(model, jax.random.fold_in(key, index), 1)[0]


class _Source(eqx.Module):
    model: StochasticGroundMotion | None
    key: jax.Array | None
    time_step: float = eqx.field(static=True)
    samples: int = eqx.field(static=True)

    def signal(self, index, values):
        if self.model is not None:
            values = monte_carlo_motion(self.model, self.key, index)
        return uniform_signal(values, self.time_step)


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
) -> MonteCarloResult:
    """Peak responses of `structure` under N ground motions (and D design variants).

    Motion i of a stochastic set is `sample(model, fold_in(key, i), 1)[0]`, so a run's
    numbers do not depend on the chunk size or the number of devices. The batch runs in
    chunks of `chunk_size` motions through one compiled function (vmap over motions and
    design variants, `peak_response` inside); each chunk's batch axis is split over
    `devices` (`shard_map` on a 1-D mesh "batch": every device steps its own motions).
    Multi-host: see the module docstring (`jax.distributed.initialize()` first).

    On a CPU, JAX makes one device of the whole processor, and a batch of small per-motion
    operations then uses about one core. `jax.config.update("jax_num_cpu_devices",
    os.cpu_count())` right after `import jax` (the `teflon-jax` command does this) gives one
    device per core; on 2 cores this ran 2.3x faster (benchmarks B3).

    **Arguments:**

    - `structure`: callable `(ground_acceleration, design) -> StructureOnSliders`, e.g.
      `isolated_structure("building", ...)`; `ground_acceleration` is a uniform `Signal`.
    - `motions`: a `StochasticGroundMotion` (with `n_motions` and `key`) or a `RecordSet`.
    - `n_motions`: N > 0 (stochastic; for a `RecordSet` defaults to all its records).
    - `key`: JAX PRNG key (stochastic motions); default `jax.random.key(0)`.
    - `duration` [s]: default the record length.
    - `design`: dict of `DESIGN_VARIABLES` -> (D,) arrays, run for every motion; or `None`.
    - `chunk_size`: motions per compiled call (rounded up to a multiple of the devices).
    - `devices`: JAX devices to shard over (default all of `jax.devices()`).
    - `progress`: called as `progress(done, total)` after each chunk (e.g. a tqdm update).
    - `disp_width` [m], `shear_width` [-]: widths of the smooth maxima (`peak_response`).
    - `memory_limit_bytes`: memory a chunk may use (default: half of the free memory).

    **Returns:** a `MonteCarloResult`.
    """
    start = time.perf_counter()
    if isinstance(motions, RecordSet):
        n_total = motions.acceleration.shape[0] if n_motions is None else n_motions
        source = _Source(None, None, motions.time_step, motions.acceleration.shape[1])
    elif isinstance(motions, StochasticGroundMotion):
        if n_motions is None:
            raise ValueError("n_motions: give the number of stochastic motions to draw (> 0).")
        n_total = n_motions
        key = jax.random.key(0) if key is None else key
        source = _Source(motions, key, motions.time_step, num_time_steps(motions))
    else:
        raise ValueError(
            f"motions: expected a StochasticGroundMotion or a RecordSet, got {type(motions).__name__}."
        )
    if isinstance(n_total, bool) or not isinstance(n_total, (int, np.integer)) or n_total <= 0:
        raise ValueError(f"n_motions: must be a positive integer, got {n_total!r}.")
    n_total = int(n_total)
    if isinstance(motions, RecordSet) and n_total > motions.acceleration.shape[0]:
        raise ValueError(
            f"n_motions: {n_total} asked for but the RecordSet has {motions.acceleration.shape[0]} records."
        )
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, (int, np.integer)) or chunk_size <= 0:
        raise ValueError(f"chunk_size: must be a positive integer, got {chunk_size!r}.")
    record_duration = (source.samples - 1) * source.time_step
    duration = record_duration if duration is None else float(duration)
    if not duration > 0:
        raise ValueError(f"duration: must be > 0 s, got {duration}.")

    design_arrays = None
    n_designs = 0
    if design:
        design_arrays = {name: jnp.atleast_1d(jnp.asarray(v, dtype=float)) for name, v in design.items()}
        sizes = {v.shape[0] for v in design_arrays.values()}
        if len(sizes) != 1 or any(v.ndim != 1 for v in design_arrays.values()):
            raise ValueError(
                f"design: every variable needs a 1-D array of the same length, got shapes "
                f"{ {k: tuple(v.shape) for k, v in design_arrays.items()} }."
            )
        n_designs = sizes.pop()
        if isinstance(structure, IsolatedStructure):
            check_design(structure, design_arrays)

    devices = list(jax.devices() if devices is None else devices)
    n_devices = len(devices)
    chunk = min(int(chunk_size), n_total)
    chunk = -(-chunk // n_devices) * n_devices
    n_chunks = -(-n_total // chunk)

    # Shapes of one system, without computing it: degrees of freedom for the memory estimate.
    probe_design = None if design_arrays is None else {k: v[0] for k, v in design_arrays.items()}
    probe = jax.eval_shape(
        lambda v: structure(uniform_signal(v, source.time_step), probe_design),
        jax.ShapeDtypeStruct((source.samples,), jnp.result_type(float)),
    )
    n_dof = probe.mass.shape[-1]
    per_motion = bytes_per_motion(source.samples, n_dof, n_designs)
    estimate = chunk * per_motion
    if memory_limit_bytes is None:
        free = available_memory_bytes(devices[0])
        # devices with their own memory (GPUs) each hold 1 / n_devices of a chunk
        own_memory = devices[0].platform != "cpu"
        memory_limit_bytes = None if free is None else free // 2 * (n_devices if own_memory else 1)
    if memory_limit_bytes is not None and estimate > memory_limit_bytes:
        largest = max(memory_limit_bytes // per_motion, 1)
        raise ValueError(
            f"chunk_size: {chunk} motions need about {estimate / 2**20:.0f} MiB "
            f"({per_motion} bytes each) but only {memory_limit_bytes / 2**20:.0f} MiB may be "
            f"used; take chunk_size <= {largest}."
        )

    mesh = jax.sharding.Mesh(np.array(devices), ("batch",))
    batched = jax.sharding.NamedSharding(mesh, jax.sharding.PartitionSpec("batch"))
    replicated = jax.sharding.NamedSharding(mesh, jax.sharding.PartitionSpec())

    def run_chunk(indices, values, design_all):
        def per_motion(index, row):
            signal = source.signal(index, row)

            def one(design_one):
                system = structure(signal, design_one)
                return peak_response(system, duration, disp_width=disp_width, shear_width=shear_width)

            peaks = one(None) if design_all is None else jax.vmap(one)(design_all)
            return peaks, jnp.max(jnp.abs(signal.values))

        return jax.vmap(per_motion)(indices, values)

    # shard_map, not automatic partitioning: every device steps its own motions with its own
    # Newton loops; partitioned automatically, the batched while loop's "any member not
    # converged" test would become a cross-device reduction in every iteration of every step.
    spec = jax.sharding.PartitionSpec
    compiled = jax.jit(
        jax.shard_map(
            run_chunk,
            mesh=mesh,
            in_specs=(spec("batch"), spec("batch"), spec()),
            out_specs=spec("batch"),
            check_vma=False,
        ),
        in_shardings=(batched, batched, replicated),
        out_shardings=batched,
    )
    if design_arrays is not None:
        design_arrays = jax.device_put(design_arrays, replicated)

    outputs = []
    compile_s = 0.0
    pending = None
    for c in range(n_chunks):
        indices = np.arange(c * chunk, (c + 1) * chunk)
        indices = np.minimum(indices, n_total - 1)  # pad the last chunk with copies
        if isinstance(motions, RecordSet):
            values = motions.acceleration[indices]
        else:
            values = np.zeros((chunk, 1))
        args = (_put(indices.astype(np.int32), batched), _put(values, batched), design_arrays)
        if c == 0:
            tic = time.perf_counter()
            compiled = compiled.lower(*args).compile()
            compile_s = time.perf_counter() - tic
        result = compiled(*args)
        if pending is not None:
            outputs.append(_get(pending))
            if progress is not None:
                progress(min(c * chunk, n_total), n_total)
        pending = result
    outputs.append(_get(pending))
    if progress is not None:
        progress(n_total, n_total)

    peaks = jax.tree_util.tree_map(lambda *xs: np.concatenate(xs, axis=0)[:n_total], *outputs)
    peak_response_, pga = peaks

    def arrange(x):
        x = np.asarray(x)
        return x if design_arrays is None else np.moveaxis(x, 0, 1)

    return MonteCarloResult(
        base_disp=arrange(peak_response_.base_disp),
        base_shear_ratio=arrange(peak_response_.base_shear_ratio),
        smooth_base_disp=arrange(peak_response_.smooth_base_disp),
        smooth_base_shear_ratio=arrange(peak_response_.smooth_base_shear_ratio),
        converged=arrange(peak_response_.converged),
        pga=np.asarray(pga),
        design={} if design_arrays is None else {k: np.asarray(v) for k, v in design_arrays.items()},
        dims=("motion",) if design_arrays is None else ("design", "motion"),
        n_devices=n_devices,
        chunk_size=chunk,
        wall_s=time.perf_counter() - start,
        compile_s=compile_s,
        memory_estimate_bytes=int(estimate),
        attrs={"duration_s": duration, "record_time_step_s": source.time_step, "n_dof": int(n_dof)},
    )


# --------------------------------------------------------------------------- output


def save_montecarlo(result: MonteCarloResult, path) -> list:
    """Save `result` as labelled arrays: NetCDF through xarray when `path` ends in ".nc" and
    xarray is installed; otherwise a NumPy ".npz" (arrays plus `dims`, design values and
    attributes as JSON) and, for up to 10,000 rows, a CSV beside it (one row per motion and
    design variant). Returns the paths written."""
    import json
    import pathlib

    path = pathlib.Path(path)
    names = ("base_disp", "base_shear_ratio", "smooth_base_disp", "smooth_base_shear_ratio", "converged")
    written = []
    if path.suffix == ".nc":
        try:
            import xarray
        except ImportError:
            path = path.with_suffix(".npz")
        else:
            coords = {"motion": np.arange(result.n_motions)}
            if result.design:
                coords["design"] = np.arange(len(next(iter(result.design.values()))))
            data = {n: (result.dims, getattr(result, n)) for n in names}
            data["pga"] = (("motion",), result.pga)
            for k, v in result.design.items():
                data[k] = (("design",), v)
            xarray.Dataset(data, coords=coords, attrs={k: str(v) for k, v in result.attrs.items()}).to_netcdf(path)
            return [path]
    if path.suffix != ".npz":
        path = path.with_suffix(".npz")
    meta = {
        "dims": list(result.dims),
        "units": {"base_disp": "m", "base_shear_ratio": "-", "pga": "m/s^2"},
        "n_devices": result.n_devices,
        "attrs": result.attrs,
    }
    arrays = {n: getattr(result, n) for n in names}
    arrays["pga"] = result.pga
    arrays.update({f"design_{k}": v for k, v in result.design.items()})
    np.savez(path, metadata=json.dumps(meta), **arrays)
    written.append(path)
    rows = result.base_disp.size
    if rows <= 10_000:
        csv = path.with_suffix(".csv")
        with open(csv, "w") as handle:
            design_names = list(result.design)
            handle.write(",".join(["design", "motion", *design_names, "pga_m_s2", "base_disp_m",
                                   "base_shear_ratio", "converged"]) + "\n")
            disp = result.base_disp.reshape(-1, result.n_motions)
            shear = result.base_shear_ratio.reshape(-1, result.n_motions)
            ok = result.converged.reshape(-1, result.n_motions)
            for d in range(disp.shape[0]):
                values = [f"{result.design[k][d]:.9g}" for k in design_names]
                for i in range(result.n_motions):
                    handle.write(",".join([str(d), str(i), *values, f"{result.pga[i]:.9g}",
                                           f"{disp[d, i]:.9g}", f"{shear[d, i]:.9g}",
                                           str(bool(ok[d, i]))]) + "\n")
        written.append(csv)
    return written


def plot_montecarlo(result: MonteCarloResult, path, *, title: str = "") -> None:
    """Histogram and exceedance curves of base displacement and base shear ratio (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(10, 7))
    for column, (name, label, factor) in enumerate(
        (("base_disp", "peak base displacement [mm]", 1e3), ("base_shear_ratio", "peak base shear / weight [-]", 1.0))
    ):
        values = getattr(result, name).reshape(-1, result.n_motions) * factor
        levels, probability = result.exceedance(name)
        levels = levels.reshape(-1, result.n_motions) * factor
        for d in range(values.shape[0]):
            axes[0, column].hist(values[d], bins=min(50, max(5, result.n_motions // 10)), alpha=0.6)
            axes[1, column].semilogy(levels[d], np.maximum(probability, 0.5 / result.n_motions))
        for q in (50, 84, 95):
            axes[0, column].axvline(np.percentile(values, q), color="k", lw=0.8, ls="--")
        axes[0, column].set_xlabel(label)
        axes[0, column].set_ylabel("motions")
        axes[1, column].set_xlabel(label)
        axes[1, column].set_ylabel("P[exceedance]")
        axes[1, column].grid(True, which="both", alpha=0.3)
    fig.suptitle(title or f"Monte Carlo, {result.n_motions} motions, {result.n_devices} device(s)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
