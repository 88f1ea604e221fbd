"""The step of a linear structure (`StructureOnSliders`) whose isolator is a friction pendulum
of sliders in series, under one or two horizontal ground components: pure functions of the
structure, which `simulate_history` and `peak_response` choose by the isolator's type.

The bearings are the series model of a `SeriesPendulum`: S sliders carry one force F and their
displacements add up to the isolator's; three for the `TriplePendulum` (the inner pair, the
bottom and the top surface; Fenz & Constantinou 2008), two for the `DoublePendulum` (bottom and
top; Fenz & Constantinou 2006), one for the `SinglePendulum` (a single pendulum, or a flat
slider at R = inf, on any linear structure: `structure_on_isolator`). Slider e carries

    F_e = W (s_e / R_e + mu_e(v_e) Z_e + k_stop <|s_e| - d_e>_+ sgn(s_e) / R_e),

with R_e, d_e its radius and capacity (`series_radii`, `series_capacities`), Z_e from
Bouc-Wen (one component) or Park's biaxial model (two; s_e, Z_e, F_e vectors in the plane)
updated exactly along the step's increment, mu_e from Eq. 1 at the surface's mean velocity
over the step, v_e = |increment| c_e / dt (`velocity_factors`; the velocity OpenSees'
`TripleFrictionPendulum` takes too) where the slider moves the way its Z points, and f_min
(Eq. 1 at rest) while Z still points back after a reversal (`slider_forces`). Without that
exception the force of a slider reversing would fall as its increment grows: the massless
sliders of the series model would have no unique balance. The restrainer of stiffness
`STOP_STIFFNESS_RATIO` W / R_e beyond the capacity.

The number of components C is the shape of the state, not a type: C = 1 with the ground along
x alone, C = 2 with `ground_y` (the structure the same in x and in y, the rigid mass or the
Table 2 building along each axis, the bearings coupling the two). The linear structure carries
a reference spring W / R_ref at the isolator (R_ref = `reference_radius()`: b + c of the
triple, R_1 + R_2 of the double), and each step advances it by its linear rule
(`structures.newmark_step_matrices`, `structures.exact_step_matrices`) with the force beyond
that spring, the sliders' balance (`_isolator_balance.py`) solved in between. With a vertical ground acceleration a_v (up +)
every slider's force is taken under the normal load N = s W, s = max(1 + a_v / g, 0) at the
end of the step; at s = 0 (uplift) the sliders carry nothing and share the isolator's
increment as their pendulum stiffnesses W / R_e in series would. A one-surface isolator may
take Eq. 1 at the isolator's velocity at the step's end, the flat sliders' law
(`friction_velocity="end"`, `FRICTION_VELOCITIES`). References: Fenz & Constantinou (2006,
2008); Park, Wen & Ang (1986).
"""

import dataclasses

import jax
import jax.numpy as jnp

from ..bearing import SeriesPendulum
from ..excitation import Signal
from ..units import STANDARD_GRAVITY
from ._isolator_balance import (
    TRIPLE_NEWTON_ITERATIONS,
    TRIPLE_TOLERANCE,
    isolator_parameters,
    predicted_increments,
    slider_step,
)
from ._response import EngineRun, StructureResponse
from ._slider_forces import (
    FRICTION_VELOCITIES,
    end_velocity,
    initial_history,
    series_heat_kernel,
)
from ._structure import StructureOnSliders
from ._structure_build import rigid_mass, six_storey_building


def initial_isolator(system):
    """The isolator's state at rest: (slider displacements (S[, 2]) [m], Z (S[, 2]), the
    increments of the last two steps (2, S[, 2]) [m] (`predicted_increments`), the force
    beyond the reference spring ((,) or (2,)) [N]), for heated surfaces the heat kernel's
    states (S, K) [W s/m^2], and last, where a surface's part needs it, the sliders'
    history (`initial_history`)."""
    count = system.pendulum.slider_count
    plane = () if system.ground_y is None else (2,)
    zeros = jnp.zeros((count,) + plane, system.mass.dtype)
    state = zeros, zeros, jnp.stack([zeros, zeros]), jnp.zeros(plane, system.mass.dtype)
    if system.pendulum.heated:
        state = state + (jnp.zeros((count, system.heat_rates.shape[0]), system.mass.dtype),)
    if system.pendulum.remembers:  # the sliders' history last (`initial_history`)
        state = state + (initial_history(system.pendulum, (count,), zeros.dtype),)
    return state


def series_step(system, x0, isolator, ground0, ground1, matrices=None, load=None):
    """One step: (u1, v1) ((2n,), or (2, 2n) in x and in y) and the isolator's state at its
    end, from (u0, v0) `x0`, the isolator's state (`initial_isolator`) and the ground
    acceleration [m/s^2] at both ends (scalars or (2,)), under the normal load `load` W
    held over the step (`None`: W); also whether the sliders' balance converged and the
    bearing force F [N]. Heated surfaces take their friction factors at the step's start
    and hold them over it (`heated_step`), their flux at the length of their increment."""
    step_matrix, force_column = system.step_matrices() if matrices is None else matrices
    linear = _apply(step_matrix, jnp.concatenate([x0, jnp.stack([ground0, isolator[3], ground1], -1)], -1))
    n = system.mass.shape[-1]
    state, converged, bearing = _isolator_step(system, isolator, linear[..., 0], x0[..., 0], -force_column[0], load,
                                                    (linear[..., n], force_column[n]))
    return linear + _times(state[3], force_column), state, converged, bearing


def _isolator_step(system, isolator, linear, start, compliance, load, velocity):
    """The isolator's part of a step: the sliders' increments that balance their forces with
    the linear step, whose isolator displacement is `linear` [m] at the end without the
    force beyond the reference spring and `start` at the step's start, with that force's
    compliance `compliance` [m/N]; `load` N / W at the step's end (`None`: W); `velocity`:
    (the isolator's velocity at the end without that force [m/s], its change per unit
    force [m/(N s)]), which the law "end" reads (`end_velocity`). **Returns:** `slider_step`'s."""
    weight, stiffness = system.bearing_load, system.reference_stiffness
    scale = 1 - compliance * stiffness  # the step without the reference spring: x = X - G F
    p = isolator_parameters(system.pendulum, isolator, weight, weight if load is None else load * weight,
                            linear / scale - start, compliance / scale, system.heat_weights)
    if system.friction_velocity == "end":
        p["v"] = end_velocity(*velocity, start, p["D"], p["G"], stiffness)
    if load is not None:
        p["s"] = load
    eps = jnp.finfo(isolator[0].dtype).eps  # F = (D - sum d) / G is known to eps |D| / G at best
    tolerance = jnp.maximum(system.newton_tolerance * weight,
                            32 * eps * (weight + jnp.max(jnp.abs(p["D"])) / p["G"]))
    return slider_step(isolator, p, predicted_increments(isolator[2]), tolerance, system.time_step,
                       system.newton_iterations, heat_rates=system.heat_rates, load=load,
                       secant=system.balance == "secant", reference=(stiffness, start))


def _times(extra, column):
    """The force column (2n + 3,) times the force beyond the reference spring: f F (one
    component), or the rows F_x f, F_y f (two)."""
    return column * extra if extra.ndim == 0 else extra[:, None] * column


def _apply(matrix, x):
    """matrix @ x for one component's vector x, x @ matrix^T for the rows (2, .) of two."""
    return matrix @ x if x.ndim == 1 else x @ matrix.T


def triple_structure(kind: str, pendulum: SeriesPendulum, ground_acceleration: Signal, *, time_step: float,
                     weight=100e3, newton_iterations: int = TRIPLE_NEWTON_ITERATIONS,
                     newton_tolerance: float = TRIPLE_TOLERANCE, friction_velocity: str = "mean",
                     ground_y: Signal | None = None, balance: str = "newton") -> StructureOnSliders:
    """The rigid mass of `weight` W [N] ("rigid") or the Table 2 building ("building", W its
    total weight) on the friction pendulums `pendulum` (a `TriplePendulum`, `DoublePendulum` or
    `SinglePendulum`, to be checked first: `check_series_pendulum`), with no viscous damping
    and no spring at the isolator but the reference spring W / R_ref (none on a flat slider),
    stepped by the exact linear rule at `time_step` [s]; `friction_velocity`, `ground_y`,
    `balance`: `StructureOnSliders`'. A structure with its own springs and dampers at the
    isolator: `structure_on_isolator`."""
    reference = pendulum.reference_radius()
    if kind == "rigid":
        linear = rigid_mass(weight=weight, bearing=None, ground_acceleration=ground_acceleration,
                            time_step=time_step, radius=reference, friction_model="none",
                            linear_rule="exact")
    else:
        period = 2 * jnp.pi * jnp.sqrt(reference / STANDARD_GRAVITY)
        linear = six_storey_building(bearing=None, ground_acceleration=ground_acceleration,
                                     time_step=time_step, isolation_period=period, isolation_damping=0.0,
                                     friction_model="none", linear_rule="exact")
    return structure_on_isolator(linear, pendulum, newton_iterations=newton_iterations,
                                 newton_tolerance=newton_tolerance, friction_velocity=friction_velocity,
                                 ground_y=ground_y, balance=balance)


def structure_on_isolator(linear: StructureOnSliders, pendulum: SeriesPendulum, *,
                          newton_iterations: int = TRIPLE_NEWTON_ITERATIONS, newton_tolerance: float = TRIPLE_TOLERANCE,
                          friction_velocity: str = "mean", ground_y: Signal | None = None,
                          balance: str = "newton") -> StructureOnSliders:
    """The linear structure `linear` (a `StructureOnSliders`, stepped by its `linear_rule`; its
    friction is not read) on the isolator `pendulum`, whose surfaces' forces beyond the
    reference spring W / R_ref (`reference_radius`; 0 on a flat slider) enter each step.
    `linear`'s stiffness at the isolator holds that spring and whatever else acts there (a flat
    slider's restoring springs, a viscous damper), as `rigid_mass` and `six_storey_building`
    build them for the flat sliders and the single pendulum; its vertical record, if any,
    loads the surfaces; `ground_y` a y component (the same structure along y), `balance` its
    planar iteration (`BALANCES`). `friction_velocity` (`FRICTION_VELOCITIES`): "end" needs
    one surface (`ValueError` naming it otherwise)."""
    if friction_velocity not in FRICTION_VELOCITIES:
        raise ValueError(f"friction_velocity: unknown {friction_velocity!r}; accepted: {', '.join(FRICTION_VELOCITIES)}.")
    if friction_velocity == "end" and pendulum.slider_count != 1:
        raise ValueError(f"friction_velocity: 'end' reads the isolator's own velocity, which only a one-surface "
                         f"isolator's slider has; the {pendulum.description} have {pendulum.slider_count} sliders.")
    heat = series_heat_kernel(pendulum, linear.time_step)
    return dataclasses.replace(linear, bearing=pendulum, friction_model="none",
                               reference_stiffness=linear.bearing_load / pendulum.reference_radius(),
                               newton_iterations=int(newton_iterations), newton_tolerance=float(newton_tolerance),
                               heat_rates=heat[0], heat_weights=heat[1], friction_velocity=friction_velocity,
                               ground_y=ground_y, balance=balance)


def total_acceleration(system: StructureOnSliders, x, extra):
    """Total accelerations (n,) or (2, n) [m/s^2] of the masses at state `x` = (u, v) with the
    force `extra` [N] beyond the reference spring at the isolator: -(K u + C v + e0 extra) / m."""
    n = system.mass.shape[-1]
    force = _apply(system.stiffness, x[..., :n]) + _apply(system.damping, x[..., n:])
    return -force.at[..., 0].add(extra) / system.mass


def series_run(system: StructureOnSliders, n_steps: int) -> EngineRun:
    """The `EngineRun` of `system` (a structure on a `SeriesPendulum`, one or two components)
    over `n_steps` steps from rest: each sample's coordinates (n,), or (2n,) the x block then
    the y block; `ground` (C,); the isolator's `bearing_force` [N] ((,) or (2,)), its
    sliders' `slider` and `z` (S[, 2]); with a vertical record `load_factor` (a step holds its
    end's)."""
    dt = float(system.time_step)
    time = jnp.arange(n_steps + 1) * dt
    ground = jax.vmap(system.ground)(time)
    matrices = system.step_matrices()
    loads = None if system.vertical_acceleration is None else jax.vmap(system.load_factor)(time)
    n = system.mass.shape[-1]

    def sample(time1, x, force, isolator, acceleration, ground1, load):
        return StructureResponse(time=time1, displacement=x[..., :n].reshape(-1), velocity=x[..., n:].reshape(-1),
                                 total_acceleration=acceleration.reshape(-1), ground=jnp.reshape(ground1, (-1,)),
                                 bearing_force=force, slider=isolator[0], z=isolator[1], load_factor=load)

    def step(state, inputs):
        x, isolator = state
        time1, ground0, ground1, load1 = inputs
        x1, isolator1, converged, force = series_step(system, x, isolator, ground0, ground1, matrices, load1)
        acceleration = total_acceleration(system, x1, isolator1[3])
        return (x1, isolator1), sample(time1, x1, force, isolator1, acceleration, ground1, load1), converged

    plane = () if system.ground_y is None else (2,)
    x0 = jnp.zeros(plane + (2 * n,), system.mass.dtype)
    start = (x0, initial_isolator(system))
    first = sample(time[0], x0, jnp.zeros(plane), start[1], jnp.zeros(plane + (n,), x0.dtype), ground[0],
                   None if loads is None else loads[0])
    return EngineRun(start, (time[1:], ground[:-1], ground[1:], None if loads is None else loads[1:]), step, first)
