"""The steps of structures on friction pendulums of sliders in series: a linear structure
(`StructureOnSliders`) on one such isolator, under one or two horizontal ground components,
and a slab on groups of them; pure functions of the structure, which `simulate_history` and
`peak_response` choose by the isolator's type.

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
that spring, the sliders' balance (`teflon_jax.elements`) solved in between. With a vertical ground acceleration a_v (up +)
every slider's force is taken under the normal load N = s W, s = max(1 + a_v / g, 0) at the
end of the step; at s = 0 (uplift) the sliders carry nothing and share the isolator's
increment as their pendulum stiffnesses W / R_e in series would. A one-surface isolator may
take Eq. 1 at the isolator's velocity at the step's end, the flat sliders' law
(`friction_velocity="end"`, `FRICTION_VELOCITIES`). References: Fenz & Constantinou (2006,
2008); Park, Wen & Ang (1986).

A planar `StructureOnSliders` on groups of triple or double friction pendulums (`bearing` a
`SeriesPendulum`; `series_initial_state` to `series_groups_run`), the slab (x, y, rotation) or
the Table 2 building on a plan (x block, y block, the slab's rotation): its state, its step and
its history.

Each group g at plan position P_g (r_g = P_g - C) slides by d_g = B_g q, B_g = [[1, 0, -r_y],
[0, 1, r_x]], and is one multi-surface pendulum of the series model (`teflon_jax.elements`):
S sliders (e) with their own planar displacements, Z and restrainers, all carrying the
group's force F_g, their displacements adding up to d_g. Every slider's force is taken under
the group's normal load N_g = s_g W_g (friction and N_g / R_e alike), the load of a rigid slab
under the overturning moment of its horizontal force (of the levels' inertia forces at their
heights under a building), held over each step (`_overturning.py`;
a step on which the slab would tip, its moment beyond what the groups can hold without
tension, is reported as unbalanced); while N_g <= 0 the group carries no shear and its sliders share its motion as R_e
(`uplift_increments`).

Heated surfaces (`SeriesPendulum.heated`) heat with their own group's load: surface e of group
g takes the flux q_ge = mu_ge p_e (N_g / W_g) v_ge (`teflon_jax.elements.heated_step`, p_e its contact
pressure under the static W_g, v_ge the length of its increment over the step times its
velocity factor), none while the group is lifted, and its friction is scaled by k_T at its
own temperature, taken at the step's start and held over the step, as on the rigid mass.

The structure carries a reference spring k_g = W_g / R_ref at each group (R_ref the pendulum's
`reference_radius`), K_ref = sum_g k_g B_g^T B_g (`reference_stiffness`), and is advanced by the
exact step of M q'' + C q' + K q = -M R a_g - f (K holding K_ref and a building's frame, C the
frame's damping) for the ground and the force f = sum_g B_g^T (F_g - k_g d_g)
varying linearly over the step (Van Loan 1978), as the rigid mass on one such pendulum is.
That step gives q1 = D - G_q sum_g B_g^T F_g at its end. The unknowns of a step are the
sliders' increments d_ge (G, S, 2) and the group forces F_g (G, 2), with

    F_ge(d_ge) - F_g = 0,     k_g (sum_e d_ge + sum_h B_g G_q B_h^T F_h - (B_g D - d_g0)) = 0;

Newton's matrix [[blockdiag K_ge, -U], [k U^T, k B G_q B^T]] is solved by eliminating the
increments (a 2G x 2G system in the forces), with the halving line search of the single
isolator (`damped_newton`) and the implicit derivative of the root.
References: Fenz & Constantinou (2006, 2008) (series model); Nagarajaiah, Reinhorn &
Constantinou (1991), 3D-BASIS (rigid slab on bearing groups).
"""
import dataclasses
import functools

import jax
import jax.numpy as jnp

from ..bearing import SeriesPendulum
from ..elements import (
    FRICTION_VELOCITIES,
    TRIPLE_NEWTON_ITERATIONS,
    TRIPLE_TOLERANCE,
    balance_forces,
    end_velocity,
    heated_step,
    initial_history,
    isolator_parameters,
    loaded_blocks,
    next_history,
    pendulum_blocks,
    predicted_increments,
    series_heat_kernel,
    slider_forces,
    slider_lengths,
    slider_step,
    step_history,
    surface_temperature_rises,
    uplift_increments,
)
from ..excitation import Signal
from ..solver import damped_newton, implicit_root, inverse2
from ..structures import group_factor, overturned_loads, supported_loads
from ..units import STANDARD_GRAVITY
from ._response import EngineRun, StructureResponse
from ._structure import StructureOnSliders
from ._structure_build import rigid_mass, six_storey_building
from ._vertical import load_factor_at


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
    sliders' `slider` and `z` (S[, 2]); heated surfaces' `surface_temperature_rise` (1, S)
    [K]; with a vertical record `load_factor` (a step holds its end's)."""
    dt = float(system.time_step)
    time = jnp.arange(n_steps + 1) * dt
    ground = jax.vmap(system.ground)(time)
    matrices = system.step_matrices()
    loads = None if system.vertical_acceleration is None else jax.vmap(system.load_factor)(time)
    n = system.mass.shape[-1]

    def sample(time1, x, force, isolator, acceleration, ground1, load):
        rise = None
        if system.pendulum.heated:  # (1, S): the one isolator's surfaces
            rise = surface_temperature_rises(system.pendulum, isolator[4], system.heat_weights)[None]
        return StructureResponse(time=time1, displacement=x[..., :n].reshape(-1), velocity=x[..., n:].reshape(-1),
                                 total_acceleration=acceleration.reshape(-1), ground=jnp.reshape(ground1, (-1,)),
                                 bearing_force=force, slider=isolator[0], z=isolator[1],
                                 surface_temperature_rise=rise, load_factor=load)

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


# --- a slab (x, y, rotation) on groups of series pendulums ---------------------------------------

def _overturning(system):
    """`system` with the overturning map L (G, 2) [-] its loads are read with: zeros without
    overturning (N_g = s W_g)."""
    if system.overturning is not None:
        return system
    return dataclasses.replace(system, overturning=jnp.zeros((system.bearing_load.shape[0], 2), system.mass.dtype))


def series_initial_state(system):
    """At rest: x = (q, q') (2N,), sliders and Z (G, S, 2), the balance's unknowns of the last
    two steps (2, G, S + 1, 2) (each group's slider increments [m] and its force [N];
    `predicted_increments`), group forces F_g (G, 2) [N], the generalized force beyond the
    springs f (N,) [N, N m], the normal loads N_g (G,) [N], whether the slab tipped on the
    step (`supported_loads`), for heated surfaces the heat states (G, S, K) [W s/m^2], and
    where a surface's part needs it the sliders' history (G, S) (`initial_history`)."""
    groups, sliders = system.bearing_load.shape[0], system.bearing.slider_count
    count, dtype = system.mass.shape[0], system.mass.dtype
    zeros = jnp.zeros((groups, sliders, 2), dtype)
    heat = {} if system.heat_rates is None else {
        "heat": jnp.zeros((groups, sliders, system.heat_rates.shape[0]), dtype)}
    history = initial_history(system.bearing, zeros.shape[:2], zeros.dtype)
    if history is not None:
        heat["history"] = history
    return {**heat, "x": jnp.zeros(2 * count, dtype), "slider": zeros, "z": zeros,
            "previous": jnp.zeros((2, groups, sliders + 1, 2), dtype),
            "force": jnp.zeros((groups, 2), dtype), "extra": jnp.zeros(count, dtype),
            "normal_load": overturned_loads(_overturning(system), jnp.zeros(2, dtype), 0.0),
            "tipped": jnp.zeros((), bool)}


def _groups_total_acceleration(system, state):
    """q'' + R a_g = -M^-1 (K q + C q' + f) (N,) [m/s^2, rad/s^2] of the step state `state`:
    the structure's acceleration in space (`stiffness` K and `damping` C hold the reference
    springs and the structure's own)."""
    count = system.mass.shape[0]
    q, v = state["x"][:count], state["x"][count:]
    return -(q @ system.stiffness.T + v @ system.damping.T + state["extra"]) / system.mass


def _groups_overturning_force(system, state):
    """The horizontal force (2,) [N] whose moment loads the groups at the step's start: the
    groups' force on the structure, -sum_g F_g, for masses at one height (a slab), or H_h of
    the levels' inertia forces at their heights (`structures.overturning_force`: the building
    on a plan)."""
    if system.supports is None or system.supports.levels is None:
        return -jnp.sum(state["force"], axis=0)
    total = _groups_total_acceleration(system, state)
    return (system.supports.levels * system.mass * total) @ system.influence


def groups_series_step(system, state, ground0, ground1, t1):
    """One step from `state` (`series_initial_state`) with the ground (2,) at both ends and t1 its
    end [s]: (state at t1, whether the step balanced: the sliders' balance converged and
    the slab rests on its groups, `supported_loads`)."""
    n = system.mass.shape[0]
    free, start, end = jnp.split(system.step_matrix, [2 * n, 3 * n + 2], axis=1)
    q0 = state["x"][:n]
    linear = free @ state["x"] + start @ jnp.concatenate([ground0, state["extra"]]) + end[:, :2] @ ground1
    phi = end[:n, 2:]
    settle = jnp.linalg.inv(jnp.eye(n, dtype=phi.dtype) + phi @ system.reference_stiffness)
    target, compliance = settle @ linear[:n], -settle @ phi  # q1 = D - G_q P
    b = system.bearing_map
    loads, rests = supported_loads(_overturning(system), _groups_overturning_force(system, state), t1)
    factor = group_factor(system, loads)  # N_g / W_g, 0 while lifted
    normal = factor * system.bearing_load
    flex = jnp.einsum("gin,nm,hjm->gihj", b, compliance, b)
    own = jnp.einsum("gigi->gi", flex)  # each group's own compliance; its inverse scales the misfit
    p = {"pendulum": system.bearing, "W": system.bearing_load, "N": normal, "s0": state["slider"],
         "z0": state["z"], "stiffness": 2 / jnp.sum(own, axis=-1),
         "E": jnp.einsum("gin,n->gi", b, target - q0), "flex": flex, "s": factor}
    if "history" in state:
        p["history"] = jax.vmap(step_history)(state["history"], state["z"])
    if system.heat_rates is not None:  # each surface's factor at the step's start, held over it
        p["k"] = jax.vmap(lambda pendulum, heat: pendulum.heat_factors(heat, system.heat_weights))(
            system.bearing, state["heat"])
    eps = jnp.finfo(linear.dtype).eps
    tolerance = jnp.maximum(system.newton_tolerance * jnp.min(system.bearing_load),
                            32 * eps * jnp.max(system.bearing_load + jnp.abs(p["E"]).max(-1) * p["stiffness"]))
    guess = predicted_increments(state["previous"])
    x, converged = _balanced(system.time_step, system.newton_iterations, p, guess, tolerance)
    d = x[:, :-1]
    d, _ = jax.vmap(uplift_increments)(system.bearing, normal, jnp.sum(d, axis=1), d,
                                       jnp.zeros(normal.shape, bool))
    forces, z1 = _group_forces(p, d, system.time_step)
    force = jnp.mean(forces, axis=1)
    total = jnp.einsum("gin,gi->n", b, force)
    q1 = target - compliance @ total
    extra = total - system.reference_stiffness @ q1
    x1 = linear + end[:, 2:] @ extra
    new = {"x": x1, "slider": state["slider"] + d, "z": z1, "force": force,
           "previous": jnp.stack([jnp.concatenate([d, force[:, None]], axis=1), state["previous"][0]]),
           "extra": extra, "normal_load": loads, "tipped": ~rests}
    if system.heat_rates is not None:  # the flux under the group's own N_g / W_g (0 lifted)
        new["heat"] = jax.vmap(heated_step, in_axes=(0, 0, 0, 0, None, None, 0))(
            system.bearing, state["heat"], p["k"], slider_lengths(d), system.time_step, system.heat_rates,
            factor)
    if "history" in state:
        new["history"] = jax.vmap(next_history)(system.bearing, p["history"], d)
    return new, converged & rests


def _group_forces(p, d, dt):
    """Slider forces (G, S, 2) [N] and Z of every group after the increments d (G, S, 2),
    each surface's friction times its heating factor `p["k"]` (G, S) where given, its parts
    reading the history `p["history"]` and the load factor `p["s"]` (G,)."""
    return jax.vmap(slider_forces, in_axes=(0, 0, 0, 0, 0, None, 0, 0, 0))(
        p["pendulum"], p["N"], p["s0"], p["z0"], d, dt, p.get("k"), p.get("history"), p["s"])


def _residual(x, p, dt):
    """(G, S + 1, 2) [N]: F_ge - F_g for the sliders, then k_g times the misfit of the
    group's displacement (module docstring)."""
    d, force = x[:, :-1], x[:, -1]
    sliders, _ = _group_forces(p, d, dt)
    misfit = jnp.sum(d, axis=1) - p["E"] + jnp.einsum("gihj,hj->gi", p["flex"], force)
    return jnp.concatenate([sliders - force[:, None], (p["stiffness"][:, None] * misfit)[:, None]], axis=1)


def _group_parameters(p):
    """The per-group part of `p` as one isolator's sliders read it (`isolator_parameters`) (to vmap over G)."""
    return {key: p[key] for key in ("pendulum", "W", "N", "s0", "z0")}


def _direction(r, blocks, p):
    """J^-1 r for Newton's matrix of the module docstring with the sliders' 2 x 2 blocks
    (G, S, 2, 2): the forces' change solves (blockdiag sum_e C_ge + B G_q B^T) dF
    = r2 / k - sum_e C_ge r1_ge (C = blocks^-1), then dd_ge = C_ge (r1_ge + dF_g)."""
    groups = r.shape[0]
    c = inverse2(blocks)
    cr = jnp.einsum("gsij,gsj->gsi", c, r[:, :-1])
    diagonal = jnp.einsum("gij,gh->gihj", jnp.sum(c, axis=1), jnp.eye(groups, dtype=r.dtype))
    matrix = (diagonal + p["flex"]).reshape(2 * groups, 2 * groups)
    rhs = r[:, -1] / p["stiffness"][:, None] - jnp.sum(cr, axis=1)
    change = jnp.linalg.solve(matrix, rhs.reshape(-1)).reshape(groups, 2)
    return jnp.concatenate([cr + jnp.einsum("gsij,gj->gsi", c, change), change[:, None]], axis=1)


def _evaluate(x, p, dt):
    """(residual, merit sum(r^2), Newton's direction) at x, with the sliders' exact 2 x 2
    blocks (`_forces_and_blocks`); the pendulums' own W / R_e blocks where a group carries no
    load or the blocks give no finite direction."""
    force = x[:, -1]
    forces, blocks = _forces_and_blocks(x, p, dt)
    misfit = jnp.sum(x[:, :-1], axis=1) - p["E"] + jnp.einsum("gihj,hj->gi", p["flex"], force)
    r = jnp.concatenate([forces - force[:, None], (p["stiffness"][:, None] * misfit)[:, None]], axis=1)
    direction = _direction(r, blocks, p)
    fallback = _direction(r, jax.vmap(pendulum_blocks)(_group_parameters(p)), p)
    return r, jnp.sum(r**2), jnp.where(jnp.all(jnp.isfinite(direction)), direction, fallback)


def _forces_and_blocks(x, p, dt):
    """The sliders' forces (G, S, 2) [N] at the increments of x and their exact blocks
    dF_ge/dd_ge (G, S, 2, 2) (`balance_forces` with `blocks`, each group under its own load,
    heating factors and history); the pendulums' W / R_e where a group carries no load."""
    groups = {key: p[key] for key in ("pendulum", "W", "N", "s0", "z0", "k", "history", "s") if key in p}

    def group(q, d):
        forces, _, blocks = balance_forces(q, d, dt, blocks=True)
        return forces, loaded_blocks(blocks, q)

    return jax.vmap(group)(groups, x[:, :-1])


def _balanced(dt, iterations, p, guess, tolerance):
    """The sliders' increments and the group forces (G, S + 1, 2) that balance the step, and
    whether they met `tolerance` [N] (`_iterate_balance`), over a step of `dt` [s] (a float);
    differentiated implicitly (`solver.implicit_root`) with exact blocks (`_balance_solve`)."""
    return implicit_root(functools.partial(_iterate_balance, dt, iterations), functools.partial(_residual, dt=dt),
                         functools.partial(_balance_solve, dt), p, guess, tolerance)


def _iterate_balance(dt, iterations, p, guess, tolerance):
    """Newton's iteration on the step's balance from `guess` (the increments and forces
    extrapolated from the last two steps, `predicted_increments`); where it stalls there (at a
    minimum of sum(r^2) with r != 0: the line search, which asks that sum to fall, ends where
    the sliders' kinked friction turns Newton's direction away from descent, as a slider
    reverses under a two-component impact), it starts once more from each group's increment
    d_g = B_g D - d_g0 shared evenly among its S sliders, the forces those of `guess`
    (`damped_newton` with its `restart`). A step balanced from `guess` is as before."""
    even = jnp.broadcast_to(p["E"][:, None] / (guess.shape[1] - 1), guess[:, :-1].shape)
    restart = jnp.concatenate([even, guess[:, -1:]], axis=1)
    return damped_newton(lambda x: _evaluate(x, p, dt), guess, tolerance, iterations, restart=restart)[:2]


def _balance_solve(dt, x, p, r, dp):
    """J^-1 r at the root x (`_direction`) with the sliders' exact blocks (`_forces_and_blocks`)
    (`dp` unused: the residual holds the whole balance)."""
    return _direction(r, _forces_and_blocks(x, p, dt)[1], p)


def series_sample(system, time, state, ground) -> StructureResponse:
    """One sample (no time axis) of the groups' structure's `StructureResponse` at `time` [s]
    from the step state `state` (`series_initial_state`) and the ground (2,) [m/s^2] then, with
    a vertical record its load factor s = max(1 + a_v / g, 0) (`load_factor_at`); the driver
    adds whether the step balanced and the groups' uplift time."""
    n = system.mass.shape[0]
    q = state["x"][:n]
    rise = None if system.heat_rates is None else jax.vmap(surface_temperature_rises, in_axes=(0, 0, None))(
        system.bearing, state["heat"], system.heat_weights)
    return StructureResponse(
        time=time, displacement=q, velocity=state["x"][n:], total_acceleration=_groups_total_acceleration(system, state),
        ground=ground, bearing_force=state["force"], slider=state["slider"],
        bearing_displacement=jnp.einsum("gdn,n->gd", system.bearing_map, q), normal_load=state["normal_load"],
        surface_temperature_rise=rise, tipped=state["tipped"],
        load_factor=load_factor_at(system.vertical_acceleration, time))


def series_groups_run(system, n_steps: int) -> EngineRun:
    """The `EngineRun` of the slab on series pendulum groups over `n_steps` steps from rest,
    each sample `series_sample`'s."""
    time = jnp.arange(n_steps + 1) * float(system.time_step)
    ground = jax.vmap(system.ground)(time)

    def step(state, inputs):
        ground0, ground1, time1 = inputs
        new, converged = groups_series_step(system, state, ground0, ground1, time1)
        return new, series_sample(system, time1, new, ground1), converged

    start = series_initial_state(system)
    return EngineRun(start, (ground[:-1], ground[1:], time[1:]), step, series_sample(system, time[0], start, ground[0]))
