"""A `StructureOnSliders` built and run: shapes checked, the step's matrices prefactored, the
optional bearing parts a structure runs (heating, wear) with the heat kernel they need; its
histories over a record (`simulate_history`); and a building's storey results as linear maps
of its state; the paper's two structures on sliders (`rigid_mass`, `six_storey_building`, their
linear parts `teflon_jax.structures.rigid_mass_matrices`, `building_matrices`).

Storey results, for a building with degrees of freedom 0 = base slab (on the isolators) and
1..n-1 = floors, displacements u relative to the ground:

    drift_j = |u_j - u_(j-1)| / h_j                       storey j = 1..n-1 [-],
    a_j + a_g = -((C v + K u)_j + delta_j0 F) / m_j       level j = 0..n-1 [m/s^2],

the second from the equations of motion M (u'' + 1 a_g) + C v + K u + e0 F = 0, F the bearing
force on the base slab (level 0); both are linear in the state (u, v) and F at each step's
end. Storey 1 lies between the base slab and floor 1, so its drift excludes the isolators'
displacement, which is the base peak `base_disp`. Reference for the building: Constantinou,
Mokha & Reinhorn (1990), J. Struct. Eng. 116(2), Table 2 and Fig. 11.
"""

import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import (
    HEAT_HORIZON,
    SeriesPendulum,
    SlidingBearing,
    check_bearing,
    heat_kernel_exponentials,
)
from ..excitation import Signal
from ..structures import (
    LINEAR_RULES,
    building_matrices,
    exact_step_matrices,
    rigid_mass_matrices,
)
from ..tables import BuildingData
from ..units import STANDARD_GRAVITY
from ._response import StructureResponse, uplift_time
from ._structure import (
    FRICTION_MODELS,
    NEWTON_ITERATIONS,
    StructureOnSliders,
)
from ._vertical import step_load_factors


def structure_on_sliders(
    *,
    mass,
    stiffness,
    damping,
    bearing: SlidingBearing | None,
    bearing_load,
    ground_acceleration: Signal,
    time_step: float,
    friction_model: str = "hysteretic",
    newton_iterations: int = NEWTON_ITERATIONS,
    split_at_turn: bool = False,
    linear_rule: str = "newmark",
    contact_pressure=None,
    surface=None,
    pendulum_stiffness=None,
) -> StructureOnSliders:
    """Build a `StructureOnSliders`, checking shapes and prefactoring the step's matrices.

    Newmark (average acceleration): K_eff = K + (2/dt) C + (4/dt^2) M, inverted once for
    `time_step`; with `linear_rule="exact"` also the exact step's matrices (`structures.exact_step_matrices`).
    A bearing with `heating` needs `contact_pressure` [Pa] (its kernel spans one time step to
    `HEAT_HORIZON`); of the optional parts, structures run `STRUCTURE_EFFECTS`. `surface`: a
    friction pendulum's `ConcaveSurface` whose force beyond W u / R the step solves
    (`StructureOnSliders.surface`; W / R itself belongs in `stiffness`). `pendulum_stiffness`
    W / R [N/m]: the part of K[0, 0] a vertical record's normal load scales (`with_vertical_motion`).
    """
    if friction_model not in FRICTION_MODELS:
        raise ValueError(
            f"friction_model: unknown {friction_model!r}; accepted values: {', '.join(FRICTION_MODELS)}."
        )
    if linear_rule not in LINEAR_RULES:
        raise ValueError(f"linear_rule: unknown {linear_rule!r}; accepted values: {', '.join(LINEAR_RULES)}.")
    mass = jnp.atleast_1d(jnp.asarray(mass, dtype=float))
    n = mass.shape[-1]
    stiffness = jnp.asarray(stiffness, dtype=float).reshape(mass.shape[:-1] + (n, n))
    damping = jnp.asarray(damping, dtype=float).reshape(mass.shape[:-1] + (n, n))
    if not time_step > 0:
        raise ValueError(f"time_step: must be > 0 s, got {time_step}.")
    if isinstance(bearing, SeriesPendulum):
        raise ValueError(f"bearing: {bearing.description} balance their sliders at each step; build the linear "
                         "structure with bearing=None, friction_model='none' and put it on them with "
                         "structure_on_isolator(linear, pendulum).")
    if friction_model != "none":
        if bearing is None:
            raise ValueError("bearing: a SlidingBearing is needed unless friction_model='none'.")
        check_bearing(bearing)
    else:
        from ..bearing import coulomb_friction, paper_bearing

        bearing = paper_bearing(coulomb_friction(0.0)) if bearing is None else bearing
    rates, weights = _heat_kernel(bearing, friction_model, contact_pressure, time_step)
    k_eff = stiffness + 2 / time_step * damping + 4 / time_step**2 * jnp.vectorize(
        jnp.diag, signature="(n)->(n,n)"
    )(mass)
    return StructureOnSliders(
        mass=mass,
        stiffness=stiffness,
        damping=damping,
        bearing=bearing,
        bearing_load=jnp.asarray(bearing_load, dtype=float),
        ground_acceleration=ground_acceleration,
        time_step=float(time_step),
        newmark_inverse=jnp.linalg.inv(k_eff),
        friction_model=friction_model,
        newton_iterations=int(newton_iterations),
        split_at_turn=bool(split_at_turn),
        linear_rule=linear_rule,
        exact_step=_exact_step_matrix(mass, stiffness, damping, float(time_step)) if linear_rule == "exact" else None,
        contact_pressure=None if contact_pressure is None else jnp.asarray(contact_pressure, float),
        heat_rates=rates,
        heat_weights=weights,
        surface=surface,
        pendulum_stiffness=pendulum_stiffness,
    )


STRUCTURE_EFFECTS = ("heating", "wear", "asymmetry")
"""Optional bearing parts a structure on sliders runs (besides Eq. 1, breakaway, anisotropy,
stacks): heating and wear, factors on mu held over each step, and the direction asymmetry
1 + a Z, part of the bearing force solved for in each step. Only the hysteretic friction
model runs them."""


def _one_direction_refusal(names: str) -> str:
    return (f"bearing: the structures do not run its {names} (they run Eq. 1, breakaway, anisotropy, "
            f"stacks, {', '.join(STRUCTURE_EFFECTS)}); simulate the bearing test with `simulate-test "
            "--bearing`, or fit without these effects")


def check_structure_parts(bearing: SlidingBearing, refusal=_one_direction_refusal) -> None:
    """`ValueError` naming the optional parts of `bearing` a structure does not run (those
    not in `STRUCTURE_EFFECTS`): `refusal(their names)` and, for pressure dependence,
    `PRESSURE_HINT` (default: the message of the structures in one direction)."""
    other = [name for name in bearing.effects if name not in STRUCTURE_EFFECTS]
    if other:
        raise ValueError(refusal(", ".join(other)) + (PRESSURE_HINT if "pressure_dependence" in other else "."))


PRESSURE_HINT = ("; a pressure dependence is a constant factor at the bearings' contact "
                 "pressure p: give the structure `bearing.at_contact_pressure(p)` (the "
                 "isolated structures and the commands do this with their pressure).")


def _heat_kernel(bearing, friction_model, contact_pressure, time_step):
    """(rates, weights) of the heat kernel for a bearing with heating, else (None, None);
    `ValueError` for parts a structure does not run or a missing contact pressure."""
    if bearing is None:
        return None, None
    if friction_model != "hysteretic":
        if bearing.effects and friction_model == "coulomb":
            raise ValueError(f"bearing: the Coulomb model runs Eq. 1 alone, not its "
                             f"{', '.join(bearing.effects)}; use friction_model='hysteretic'.")
        return None, None
    check_structure_parts(bearing)
    if bearing.heating is None:
        return None, None
    if contact_pressure is None:
        raise ValueError("contact_pressure: a bearing with heating needs the contact pressure "
                         "[Pa] of the bearings (the heat flux is mu p |v|).")
    rates, weights = heat_kernel_exponentials(float(time_step), HEAT_HORIZON)
    return jnp.asarray(rates), jnp.asarray(weights)


def _exact_step_matrix(mass, stiffness, damping, time_step):
    """(R | f) of `structures.exact_step_matrices`, for a structure or a batch of them."""
    def one(m, k, c):
        step, force = exact_step_matrices(m, k, c, time_step)
        return jnp.concatenate([step, force[:, None]], 1)

    return jnp.vectorize(one, signature="(n),(n,n),(n,n)->(m,k)")(mass, stiffness, damping)


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


def check_duration(system: StructureOnSliders, duration: float) -> int:
    """Number of `time_step`s in `duration` [s] (rounded down), after checking that it is at
    least one step and that the ground-acceleration record (and the vertical one) lasts that
    long (`step_count`)."""
    return step_count(system.time_step, duration, records(system))


def records(system: StructureOnSliders) -> tuple:
    """(record, what its length bounds) of the structure's records (`step_count`)."""
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


def _check_friction_model(friction_model: str) -> None:
    if friction_model not in FRICTION_MODELS:
        raise ValueError(
            f"friction_model: unknown {friction_model!r}; accepted values: "
            f"{', '.join(repr(m) for m in FRICTION_MODELS)}."
        )


def rigid_mass(*, weight, bearing: SlidingBearing | None, ground_acceleration: Signal, time_step: float,
               isolation_period=None, damping_ratio=0.0, radius=None, friction_model: str = "hysteretic",
               linear_rule: str = "newmark", contact_pressure=None) -> StructureOnSliders:
    """A rigid mass W/g on sliding bearings (Figs. 7-10 of the paper; TASS-type system):

        m u'' + c u' + (k + W/R) u + mu(u') W Z = -m a_g(t),   m = W/g,

    the linear part `rigid_mass_matrices` (`weight` W [N], `isolation_period` T [s] or `None`,
    `damping_ratio` zeta [-], `radius` R [m] of a spherical sliding surface or `None`) on
    `bearing` (a `SlidingBearing`; `None` allowed with `friction_model="none"`) under the
    `Signal` `ground_acceleration` a_g(t) [m/s^2] (`signal_from_motion`), stepped at
    `time_step` [s] (0.005 s recommended for 0.02 s records). `friction_model`: "hysteretic"
    (the paper's model), "coulomb" (Eq. 2) or "none". Returns a 1-degree-of-freedom
    `StructureOnSliders`."""
    _check_friction_model(friction_model)
    linear = rigid_mass_matrices(weight=weight, isolation_period=isolation_period, damping_ratio=damping_ratio,
                                 radius=radius)
    return structure_on_sliders(**linear._asdict(), bearing=bearing, ground_acceleration=ground_acceleration,
                                time_step=time_step, friction_model=friction_model, linear_rule=linear_rule,
                                contact_pressure=contact_pressure)


def six_storey_building(*, bearing: SlidingBearing | None, ground_acceleration: Signal, time_step: float,
                        isolation_period, isolation_damping=0.05, friction_model: str = "hysteretic",
                        linear_rule: str = "newmark", contact_pressure=None,
                        building: BuildingData | None = None) -> StructureOnSliders:
    """The six-storey frame of Table 2 on an isolation system (Fig. 11 of the paper): the
    linear part `building_matrices` (`isolation_period` T_b [s] > 0, `isolation_damping`
    zeta_b [-] >= 0: 0.05 for the sliding system, 0.10 for the paper's linear high-damping
    rubber system; `building` default Table 2) on `bearing` (paper: UF PTFE parallel to lay at
    1000-3000 psi with breakaway b = 4; `None` allowed with `friction_model="none"`), carrying
    the total weight W, under `ground_acceleration` a_g(t) [m/s^2], stepped at `time_step` [s].
    `friction_model`: "hysteretic", "coulomb", or "none" (linear isolation system). Returns a
    7-degree-of-freedom `StructureOnSliders` (0 = base, 1-6 = floors)."""
    _check_friction_model(friction_model)
    linear = building_matrices(isolation_period=isolation_period, isolation_damping=isolation_damping,
                               building=building)
    return structure_on_sliders(**linear._asdict(), bearing=bearing, ground_acceleration=ground_acceleration,
                                time_step=time_step, friction_model=friction_model, linear_rule=linear_rule,
                                contact_pressure=contact_pressure)


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
