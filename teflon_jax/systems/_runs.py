"""A built structure run over its records, in one or two horizontal components: how many
steps its records cover (`step_count`, `time_grid`), its state at rest, the response of an
adaptive diffrax solution (`solved_structure_response`, `solved_planar_response`), the stepped
run of a structure on sliding bearing groups (`planar_run`), and a building's storey results
as linear maps of its state (one component: `storey_rows`; two: `directional_storeys`).

Storey results, for a building with degrees of freedom 0 = base slab (on the isolators) and
1..n-1 = floors, displacements u relative to the ground:

    drift_j = |u_j - u_(j-1)| / h_j                       storey j = 1..n-1 [-],
    a_j + a_g = -((C v + K u)_j + delta_j0 F) / m_j       level j = 0..n-1 [m/s^2],

the second from the equations of motion M (u'' + 1 a_g) + C v + K u + e0 F = 0, F the bearing
force on the base slab (level 0); both are linear in the state (u, v) and F at each step's
end. Storey 1 lies between the base slab and floor 1, so its drift excludes the isolators'
displacement, which is the base peak `base_disp`. Two components: the equations of motion and
the step are `_planar_step.py`'s. Reference: Constantinou, Mokha & Reinhorn (1990), J.
Struct. Eng. 116(2), Eqs. 1, 8-9, 17, Figs. 7-11, Table 2 (MODEL.md Sections 4 and 8).
"""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np

from ..units import STANDARD_GRAVITY
from ._planar_step import overturning_step
from ._response import EngineRun, StructureResponse, uplift_time
from ._structure import StructureOnSliders, initial_state
from ._vertical import step_load_factors


def step_count(time_step: float, duration: float, records=()) -> int:
    """Number n of steps `time_step` dt [s] in `duration` [s], n = floor(duration / dt) (up to
    1e-9 of a step of rounding), after checking that it is at least one step and that each (`Signal` or
    `None`, name in the message) of `records` lasts n dt (a `Signal` is zero past its last
    sample; ask for a shorter duration or append zeros on purpose)."""
    dt = float(time_step)
    n_steps = int(duration / dt + 1e-9)
    if n_steps < 1:
        raise ValueError(f"duration: must be at least one time step ({dt} s), got {duration}.")
    for record, name in records:
        if record is not None:
            record.require_covers(n_steps * dt, name)
    return n_steps


def time_grid(time_step: float, duration: float, save_every: int, records=()):
    """(n, t (n + 1,), saved t (every `save_every`-th)) [s] of the fixed steps t_k = k dt over
    `duration`, n and `records` checked by `step_count`."""
    n_steps = step_count(time_step, duration, records)
    steps = jnp.arange(n_steps + 1) * float(time_step)
    return n_steps, steps, steps[::save_every]


def check_duration(system, duration: float) -> int:
    """Number of `time_step`s in `duration` [s] (rounded down), after checking that it is at
    least one step and that the structure's records (x, y where it has one, vertical where it
    has one) last that long (`step_count`)."""
    return step_count(system.time_step, duration, records(system))


def records(system) -> tuple:
    """(record, what its length bounds) of a structure's records (`step_count`), in one or two
    components: the x and y ground records and the vertical one (`None` where it has none; a
    `Signal` is zero past its end, so a run longer than a record is refused by name, not padded)."""
    return ((system.ground_acceleration, "duration"), (system.ground_y, "duration (y record)"),
            (system.vertical_acceleration, "duration (vertical record)"))


def solved_structure_response(system: StructureOnSliders, save_times, solution, n_steps: int) -> StructureResponse:
    """The `StructureResponse` (one ground component) of a flat-slider or single-pendulum
    structure from its diffrax `solution` saved at `save_times` [s] over `n_steps` steps
    (`simulate_history`): the states, the total accelerations of the equation of motion, the
    friction force mu W Z, a heated bearing's surface temperature rise and, with a vertical
    record, the load factor and the uplift time."""
    ys = solution.ys
    ag = jax.vmap(system.ground_acceleration)(save_times)
    relative = jax.vmap(system._acceleration)(save_times, ys)
    loads = None if system.vertical_acceleration is None else jax.vmap(system.load_factor)(save_times)
    friction = jax.vmap(lambda y, s: system.at_state(y).friction_force(y["v"][0], y["z"], y["z_peak"], s))(
        ys, loads)
    rise = None
    if system.bearing.heating is not None:  # (nt, 1, 1): one group, one surface
        rise = system.bearing.surface_temperature_rise(ys["heat"], system.heat_weights)[:, None, None]
    return StructureResponse(
        time=save_times,
        displacement=ys["u"],
        velocity=ys["v"],
        total_acceleration=relative + ag[:, None],
        ground=ag[:, None],
        friction_force=friction,
        z=ys["z"],
        z_peak=ys["z_peak"],
        surface_temperature_rise=rise,
        result=solution.result,
        load_factor=loads,
        uplift_time=None if loads is None else uplift_time(step_load_factors(system, n_steps),
                                                           float(system.time_step)),
    )


def check_storey_height(n_dof: int, storey_height) -> np.ndarray:
    """`storey_height` [m] as (n_dof - 1,) once checked for a structure of `n_dof` degrees of
    freedom: `ValueError` naming `system` for a rigid mass (no storeys) and `storey_height`
    for a value that is not > 0 or not one per storey."""
    if n_dof < 2:
        raise ValueError("system: storey results need a building (a base and at least one floor), "
                         "not a rigid mass.")
    height = np.asarray(storey_height, float)
    if height.ndim > 1 or (height.ndim == 1 and height.shape[0] != n_dof - 1) or not np.all(height > 0):
        raise ValueError(f"storey_height: must be > 0 m, one value or one per storey ({n_dof - 1}), "
                         f"got {storey_height}.")
    return np.broadcast_to(height, (n_dof - 1,))


def storey_rows(system: StructureOnSliders, storey_height):
    """(drift rows (n-1, 2n), acceleration rows (n, 2n), acceleration force column (n,)):
    the linear maps of the state (u, v) to the drift ratios (u_j - u_(j-1)) / h_j of storeys
    j = 1..n-1, and of the state and the bearing force F [N] to the total accelerations
    -((C v + K u)_j + delta_j0 F) / m_j of levels j = 0 (base slab) ..n-1 (module docstring).

    **Arguments:** `system`: a building (DOF 0 = base slab, 1.. = floors); `storey_height`
    [m]: a scalar or one per storey (n-1,), > 0, not traced (the Table 2 building:
    `load_table2().storey_height`).
    """
    n = system.mass.shape[-1]
    height = jnp.asarray(check_storey_height(n, storey_height), system.mass.dtype)
    difference = jnp.eye(n)[1:] - jnp.eye(n, k=-1)[1:]
    drift = jnp.concatenate([difference / height[:, None], jnp.zeros((n - 1, n))], axis=1)
    acceleration = -jnp.concatenate([system.stiffness, system.damping], axis=1) / system.mass[:, None]
    force = -jnp.eye(n, dtype=system.mass.dtype)[0] / system.mass[0]
    return drift, acceleration, force


def storey_start(rows, dtype) -> tuple:
    """The running peaks of `storey_rows`'s quantities at rest: (drifts (n-1,), accelerations
    (n,)) of zeros, or () without storey results (`rows` None)."""
    if rows is None:
        return ()
    return jnp.zeros(rows[0].shape[0], dtype), jnp.zeros(rows[1].shape[0], dtype)


def building_response_quantities(system: StructureOnSliders, response: StructureResponse) -> dict:
    """Engineering quantities of a building's history (SI; time along the first axis), for any
    `StructureOnSliders` whose DOF 0 is the base and DOFs 1.. are floors stacked from the base
    up (e.g. `six_storey_building`). jit/vmap-safe.

    **Returns:** a dict of

    - `time` [s]; `base_displacement` (nt,) [m] relative to the ground;
    - `storey_drifts` (nt, n - 1) [m]: floor j minus floor j-1 (floor 0 = base);
    - `floor_accelerations` (nt, n - 1) [m/s^2]: total accelerations of floors 1..;
    - `base_shear_ratio` (nt,) [-]: first-storey shear / superstructure weight, with the
      first-storey shear V_1 = sum_j m_j a_j^total over the floors (the inertia force of the
      superstructure; positive when the floors accelerate in +x, so V_1 is the force the
      first storey applies to the floors above with its sign reversed);
    - `friction_force` (nt,) [N]; `z` (nt,) [-].
    """
    floor_masses = system.mass[..., 1:]
    floors = response.displacement[..., 1:]
    below = response.displacement[..., :-1]
    accelerations = response.total_acceleration[..., 1:]
    shear = jnp.sum(floor_masses[..., None, :] * accelerations, axis=-1)
    weight = jnp.sum(floor_masses, axis=-1)[..., None] * STANDARD_GRAVITY
    return {
        "time": response.time,
        "base_displacement": response.displacement[..., 0],
        "storey_drifts": floors - below,
        "floor_accelerations": accelerations,
        "base_shear_ratio": shear / weight,
        "friction_force": response.friction_force,
        "z": response.z,
    }


def solved_planar_response(system: StructureOnSliders, save_times, solution, n_steps: int) -> StructureResponse:
    """The `StructureResponse` (two ground components) of a structure on sliding bearing groups
    from an adaptive diffrax `solution` saved at `save_times` [s] over `n_steps` steps
    (`simulate_history`; no overturning loads, which only the fixed steps carry): at each saved
    time the sample of `planar_run`, under the load factor there."""
    loads = None if system.vertical_acceleration is None else jax.vmap(system.load_factor)(save_times)

    def sample(time, y, load):
        return _planar_sample(system.at_load(load), time, y, system._acceleration(time, y), system.ground(time),
                              load, None)

    response = jax.vmap(sample)(save_times, solution.ys, loads)
    dt = float(system.time_step)
    return dataclasses.replace(response, result=solution.result, uplift_time=None if loads is None else uplift_time(
        step_load_factors(system, n_steps), dt))


def directional_storeys(q, total_acceleration, storey_height):
    """Drift ratios (..., 2, S) [-] and total accelerations (..., 2, S + 1) [m/s^2] in x and y
    of the two-direction building (`six_storey_building(components=2)`: q = (x: base slab, floors 1..S;
    y: the same); `building_on_plan`: the same and the slab's rotation last),
    `total_acceleration` the same layout [m/s^2]: (q_j - q_(j-1)) / h_j per storey and
    a_j + a_g per level, level 0 the base slab. jit/vmap-safe in q and the accelerations;
    `storey_height` [m] scalar or (S,), not traced."""
    n = q.shape[-1] // 2
    height = jnp.asarray(check_storey_height(n, storey_height), q.dtype)
    x, y = q[..., :n], q[..., n:2 * n]
    drift = jnp.stack([jnp.diff(x, axis=-1), jnp.diff(y, axis=-1)], axis=-2) / height
    acc = jnp.stack([total_acceleration[..., :n], total_acceleration[..., n:2 * n]], axis=-2)
    return drift, acc


def bidirectional_storey_peaks(response, system, storey_height) -> dict:
    """Peak storey results of a run of the two-direction building (`six_storey_building(components=2)`)
    from its histories (`simulate_history`), by `directional_storeys`:

    - `storey_drift` (2, S) [-]: max_t |q_j - q_(j-1)| / h_j in x and in y, storey 1 first;
    - `storey_drift_resultant` (S,) [-]: max_t of the drift vector's length over h_j;
    - `level_acceleration` (2, S + 1) [m/s^2]: max_t |a_j + a_g| in x and y, level 0 the base slab;
    - `level_acceleration_resultant` (S + 1,) [m/s^2]: max_t of the total acceleration's length.
    """
    q = jnp.asarray(response.displacement)
    total = jnp.asarray(response.total_acceleration)
    drift, acc = (np.asarray(v) for v in directional_storeys(q, total, storey_height))  # (nt, 2, .)
    return {"storey_drift": np.abs(drift).max(axis=0), "storey_drift_resultant": np.hypot(*np.moveaxis(drift, 1, 0)).max(axis=0),
            "level_acceleration": np.abs(acc).max(axis=0),
            "level_acceleration_resultant": np.hypot(*np.moveaxis(acc, 1, 0)).max(axis=0)}


def planar_run(system: StructureOnSliders, n_steps) -> EngineRun:
    """Flat sliders or single pendulums under two components, each step as the history's
    (`newmark_update` under the load factor of the step's end; with a slab's overturning,
    `overturning_step`: the groups' loads from the horizontal force at the step's start and
    the vertical record at its end, held over the step, a step on which the slab tips not
    converged), the accelerations the equation of motion's at each step's end."""
    dt = float(system.time_step)
    times = jnp.arange(n_steps + 1) * dt
    ground = jax.vmap(system.ground)(times)
    loads = None if system.vertical_acceleration is None else jax.vmap(system.load_factor)(times)
    overturning = system.overturning is not None
    y0 = initial_state(system)
    load0 = system.load_at(times[0], y0) if overturning else None if loads is None else loads[0]
    a0 = system.at_load(load0).acceleration_at(ground[0], y0)

    def step(state, inputs):
        y, a = state
        time0, time1, ground1, load1 = inputs
        tipped = None
        if overturning:
            y1, converged, tipped = overturning_step(system, time0, time1, y, a)
            loaded = system.at_load(system.load_at(time1, y1))  # the groups' loads kept in the state
        else:
            loaded = system.at_load(load1)  # the normal load at the step's end (vertical record)
            y1, converged = loaded.newmark_update(y, a, ground1)
        a1 = loaded.acceleration_at(ground1, y1)
        sample = _planar_sample(loaded, time1, y1, a1, ground1, load1, tipped)
        return (y1, a1), sample, converged

    inputs = (times[:-1], times[1:], ground[1:], None if loads is None else loads[1:])
    first = _planar_sample(system.at_load(load0), times[0], y0, a0, ground[0], None if loads is None else loads[0],
                           jnp.array(False) if overturning else None)
    return EngineRun((y0, a0), inputs, step, first)


def _planar_sample(loaded, time, y, acceleration, ground, load, tipped):
    """One sample of a planar `StructureOnSliders`' run: its coordinates, total accelerations,
    the groups' bearing displacements, friction forces (under the step's normal loads), Z,
    running peak of |Z|, heated bearings' surface temperature rise (G, 1) and, with
    overturning loads, the groups' loads and whether the slab tipped on the step."""
    rise = None
    if loaded.bearing.heating is not None:
        rise = loaded.bearing.surface_temperature_rise(y["heat"], loaded.heat_weights)[:, None]
    return StructureResponse(time=time, displacement=y["u"], velocity=y["v"],
                             total_acceleration=acceleration + loaded.influence @ ground, ground=ground,
                             friction_force=loaded.bearing_forces(y), z=y["z"], z_peak=y["z_peak"],
                             bearing_displacement=loaded.bearing_motion(y["u"]),
                             normal_load=y.get("normal_load"), surface_temperature_rise=rise, tipped=tipped,
                             load_factor=load)
