"""Batched parameter sweeps of isolated structures as single vmapped calls.

A sweep over isolation periods T_b, bearing pressures and ground motions builds the systems
inside `jax.vmap` (the builders are trace-safe) and integrates them together with
`RiccatiNewmark`, returning only peak responses as NumPy arrays labelled by their axes.

Records of unequal length: every record of a batch is padded with zero acceleration (on its
own sampling grid) to the longest one, and all members are integrated over the longest
duration; the peaks of each member are taken only over its own record's duration, through a
mask on the time steps. The free vibration after a shorter record ends is therefore computed
but never reported. A batch shares the structure's time step (`time_step` is a static field
of `StructureOnSliders`), so records are grouped by the time step asked for.
Reference: Constantinou, Mokha & Reinhorn (1990), Fig. 11.
"""

import dataclasses
import functools
from collections.abc import Mapping, Sequence

import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import FrictionParameters, paper_bearing
from ..excitation import Signal
from ..structures import signal_from_motion
from ..systems import (
    StructureOnSliders,
    building_response_quantities,
    simulate_history,
    six_storey_building,
)
from ..tables import friction_table
from ..units import PSI

PEAK_NAMES = (
    "base_disp",
    "base_shear_ratio",
    "max_drift",
    "max_floor_acc",
    "max_friction_ratio",
)
"""Peak quantities of a building sweep: base displacement [m], first-storey shear /
superstructure weight [-], largest storey drift [m], largest floor total acceleration
[m/s^2], largest friction force / bearing load [-]."""


def stack_systems(systems: Sequence[StructureOnSliders]) -> StructureOnSliders:
    """Stack systems of identical structure (same static fields) along a new leading axis."""
    systems = list(systems)
    if not systems:
        raise ValueError("systems: give at least one system to stack.")
    structures = {jax.tree_util.tree_structure(s) for s in systems}
    if len(structures) != 1:
        raise ValueError(
            "systems: all must share time_step, friction_model, breakaway (None or a value) and "
            "n_interfaces to run in one batch; group them by these settings."
        )
    return jax.tree_util.tree_map(lambda *xs: jnp.stack([jnp.asarray(x) for x in xs]), *systems)


def pad_signals(signals: Sequence[Signal], duration: float | None = None) -> tuple[Signal, np.ndarray]:
    """Pad ground-acceleration signals with zeros, each on its own uniform grid, to a common
    number of samples that covers `duration` [s] (default: the longest signal).

    **Returns:** `(batched Signal (n_records, n_samples), own durations [s] (n_records,))`.
    """
    signals = list(signals)
    if not signals:
        raise ValueError("signals: give at least one record.")
    ends = np.array([float(s.times[-1] - s.times[0]) for s in signals])
    target = float(ends.max()) if duration is None else float(duration)
    grids = []
    for index, s in enumerate(signals):
        times = np.asarray(s.times, dtype=float)
        steps = np.diff(times)
        if not np.all(steps > 0):
            raise ValueError(f"signals[{index}]: times must be strictly increasing.")
        grids.append((times, np.asarray(s.values, dtype=float), float(np.median(steps))))
    lengths = [len(t) + max(0, int(np.ceil((target - (t[-1] - t[0])) / dt - 1e-9))) + 1 for t, _, dt in grids]
    n = max(lengths)
    times_out, values_out = [], []
    for times, values, dt in grids:
        extra = n - len(times)
        times_out.append(np.concatenate([times, times[-1] + dt * np.arange(1, extra + 1)]))
        values_out.append(np.concatenate([values, np.zeros(extra)]))
    batched = Signal(
        times=jnp.asarray(np.stack(times_out)), values=jnp.asarray(np.stack(values_out)), uniform=True
    )
    return batched, ends


def simulate_batch(systems: StructureOnSliders, duration: float, **kwargs):
    """`simulate_history` vmapped over a stacked batch of systems (see `stack_systems`).

    Steps that do not balance do not raise; check `response.succeeded` per member (each
    step's in `response.converged`).
    """
    kwargs.setdefault("throw", False)
    return jax.jit(jax.vmap(lambda s: simulate_history(s, duration, **kwargs)))(systems)


def _masked_peak(values, mask):
    values = jnp.abs(values)
    if values.ndim > mask.ndim:
        values = jnp.max(values, axis=tuple(range(mask.ndim, values.ndim)))
    return jnp.max(jnp.where(mask, values, 0.0))


def building_peaks(system: StructureOnSliders, duration: float, own_duration):
    """Peak responses of a building over its record's own duration (trace-safe).

    **Returns:** dict of `PEAK_NAMES` -> scalar and `"succeeded"` -> bool.
    """
    response = simulate_history(system, duration, throw=False)
    quantities = building_response_quantities(system, response)
    mask = response.time <= own_duration + 1e-9
    return {
        "base_disp": _masked_peak(quantities["base_displacement"], mask),
        "base_shear_ratio": _masked_peak(quantities["base_shear_ratio"], mask),
        "max_drift": _masked_peak(quantities["storey_drifts"], mask),
        "max_floor_acc": _masked_peak(quantities["floor_accelerations"], mask),
        "max_friction_ratio": _masked_peak(quantities["friction_force"], mask) / system.bearing_load,
        "succeeded": response.succeeded,
    }


@functools.lru_cache(maxsize=8)
def _sweep_functions(duration, time_step, breakaway_ratio, isolation_damping, linear_damping):
    """Jitted, vmapped peak functions of the sweep, compiled once per set of settings."""

    def peaks(times, values, own_duration, period, bearing, damping, friction_model):
        """`building_peaks` of the Table 2 building on `bearing` (T_b `period`, zeta_b `damping`)."""
        system = six_storey_building(bearing=bearing, ground_acceleration=Signal(times, values, uniform=True),
                                     time_step=time_step, isolation_period=period, isolation_damping=damping,
                                     friction_model=friction_model)
        return building_peaks(system, duration, own_duration)

    def sliding(times, values, own_duration, friction, period):
        bearing = paper_bearing(friction, breakaway_ratio=breakaway_ratio)
        return peaks(times, values, own_duration, period, bearing, isolation_damping, "hysteretic")

    def linear(times, values, own_duration, period):
        return peaks(times, values, own_duration, period, None, linear_damping, "none")

    return jax.jit(jax.vmap(sliding)), jax.jit(jax.vmap(linear))


@dataclasses.dataclass(frozen=True)
class SweepResult:
    """Peaks of a building sweep on the grid (record, system, period).

    - `records`: record labels; `systems`: e.g. "sliding_1000psi", "linear";
      `periods` T_b [s]; `pressures` [Pa] per system (NaN for the linear system);
    - `peaks`: dict name -> array (n_records, n_systems, n_periods) (see `PEAK_NAMES`), SI;
    - `succeeded`: bool array of the same shape (solver status).
    """

    records: tuple[str, ...]
    systems: tuple[str, ...]
    periods: np.ndarray
    pressures: np.ndarray
    peaks: dict
    succeeded: np.ndarray

    def rows(self):
        """One dict per grid point, for CSV output."""
        out = []
        for i, record in enumerate(self.records):
            for j, system in enumerate(self.systems):
                for k, period in enumerate(self.periods):
                    row = {"record": record, "system": system, "Tb_s": float(period)}
                    row.update({name: float(self.peaks[name][i, j, k]) for name in PEAK_NAMES})
                    row["succeeded"] = bool(self.succeeded[i, j, k])
                    out.append(row)
        return out


def building_sweep(
    *,
    records: Mapping[str, object],
    periods,
    pressures=(1000 * PSI, 2000 * PSI, 3000 * PSI),
    breakaway_ratio=4.0,
    isolation_damping=0.05,
    linear_damping=0.10,
    include_linear: bool = True,
    ptfe: str = "UF",
    direction: str = "P",
    time_step: float = 0.005,
) -> SweepResult:
    """Peak responses of the Table 2 building over T_b x pressure x record (Fig. 11).

    The sliding systems (bearings of `ptfe`/`direction` with Table 1 constants at each
    pressure, breakaway `breakaway_ratio`, rubber springs of period T_b with
    `isolation_damping`) run as one vmapped call over all (record, pressure, T_b); the linear
    systems (period T_b, damping `linear_damping`, no friction) as a second one.

    **Arguments:**

    - `records`: label -> `GroundMotion` (or `Signal` of a_g [m/s^2] starting at 0).
    - `periods` T_b [s] (> 0); `pressures` [Pa] (within Table 1's range).
    - `time_step` [s]: structure step shared by the batch.

    **Returns:** a `SweepResult` on (record, system, period).
    """
    periods = np.atleast_1d(np.asarray(periods, dtype=float))
    if periods.ndim != 1 or not np.all(periods > 0):
        raise ValueError(f"periods: must be a 1-D array of T_b > 0 [s], got {periods}.")
    pressures = np.atleast_1d(np.asarray(pressures, dtype=float))
    if not records:
        raise ValueError("records: give at least one ground motion.")
    labels = tuple(records)
    signals = [r if isinstance(r, Signal) else signal_from_motion(r) for r in records.values()]
    batched, own = pad_signals(signals)
    duration = float(own.max())
    table = friction_table(ptfe, direction)
    lo, hi = float(table.pressures[0]), float(table.pressures[-1])
    for p in pressures:
        if not lo * (1 - 1e-9) <= p <= hi * (1 + 1e-9):
            raise ValueError(
                f"pressures: {p / PSI:.0f} psi is outside Table 1's range for {ptfe}/{direction} "
                f"({lo / PSI:.0f}-{hi / PSI:.0f} psi)."
            )

    # Table 1 constants at each pressure, evaluated eagerly (FrictionTable.at formats its range
    # check message with float() of the table, which fails under jit in jax 0.10).
    frictions = [table.at(float(p))[0] for p in pressures]
    f_max = np.array([float(f.f_max) for f in frictions])
    delta_f = np.array([float(f.delta_f) for f in frictions])
    rate_a = np.array([float(f.rate_a) for f in frictions])

    sliding, linear = _sweep_functions(
        float(duration), float(time_step), breakaway_ratio, isolation_damping, linear_damping
    )

    n_r, n_p, n_t = len(labels), len(pressures), len(periods)
    grid_r, grid_p, grid_t = np.meshgrid(np.arange(n_r), np.arange(n_p), np.arange(n_t), indexing="ij")
    grid_r, grid_p, grid_t = grid_r.ravel(), grid_p.ravel(), grid_t.ravel()
    out = sliding(
        batched.times[grid_r],
        batched.values[grid_r],
        jnp.asarray(own[grid_r]),
        FrictionParameters(
            f_max=jnp.asarray(f_max[grid_p]),
            delta_f=jnp.asarray(delta_f[grid_p]),
            rate_a=jnp.asarray(rate_a[grid_p]),
        ),
        jnp.asarray(periods[grid_t]),
    )
    peaks = {name: np.asarray(out[name]).reshape(n_r, n_p, n_t) for name in PEAK_NAMES}
    succeeded = np.asarray(out["succeeded"]).reshape(n_r, n_p, n_t)
    systems = tuple(f"sliding_{p / PSI:.0f}psi" for p in pressures)
    pressure_axis = list(pressures)
    if include_linear:
        lr, lt = np.meshgrid(np.arange(n_r), np.arange(n_t), indexing="ij")
        lr, lt = lr.ravel(), lt.ravel()
        lin = linear(
            batched.times[lr], batched.values[lr], jnp.asarray(own[lr]), jnp.asarray(periods[lt])
        )
        for name in PEAK_NAMES:
            peaks[name] = np.concatenate([peaks[name], np.asarray(lin[name]).reshape(n_r, 1, n_t)], axis=1)
        succeeded = np.concatenate([succeeded, np.asarray(lin["succeeded"]).reshape(n_r, 1, n_t)], axis=1)
        systems = systems + ("linear",)
        pressure_axis.append(np.nan)
    return SweepResult(
        records=labels,
        systems=systems,
        periods=periods,
        pressures=np.asarray(pressure_axis),
        peaks=peaks,
        succeeded=succeeded,
    )
