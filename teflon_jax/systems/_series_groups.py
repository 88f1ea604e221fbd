"""The balance of a `BidirectionalStructure` slab (x, y, rotation) on groups of triple or double
friction pendulums (`bearing` a `SeriesPendulum`): its state, its step and its history.

Each group g at plan position P_g (r_g = P_g - C) slides by d_g = B_g q, B_g = [[1, 0, -r_y],
[0, 1, r_x]], and is one multi-surface pendulum of the series model (`_isolator_balance.py`):
S sliders (e) with their own planar displacements, Z and restrainers, all carrying the
group's force F_g, their displacements adding up to d_g. Every slider's force is taken under
the group's normal load N_g = s_g W_g (friction and N_g / R_e alike), the load of a rigid slab
under the overturning moment of its horizontal force, held over each step (`_overturning.py`;
a step on which the slab would tip, its moment beyond what the groups can hold without
tension, is reported as unbalanced); while N_g <= 0 the group carries no shear and its sliders share its motion as R_e
(`uplift_increments`).

Heated surfaces (`SeriesPendulum.heated`) heat with their own group's load: surface e of group
g takes the flux q_ge = mu_ge p_e (N_g / W_g) v_ge (`_slider_forces.heated_step`, p_e its contact
pressure under the static W_g, v_ge the length of its increment over the step times its
velocity factor), none while the group is lifted, and its friction is scaled by k_T at its
own temperature, taken at the step's start and held over the step, as on the rigid mass.

The slab carries a reference spring k_g = W_g / R_ref at each group (R_ref the pendulum's
`reference_radius`), K_ref = sum_g k_g B_g^T B_g, and is advanced by the exact step of
M q'' + K_ref q = -M R a_g - f for the ground and the force f = sum_g B_g^T (F_g - k_g d_g)
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

from ..solver import damped_newton, implicit_root, inverse2
from ..structures import group_factor, overturned_loads, supported_loads
from ._isolator_balance import (
    loaded_blocks,
    pendulum_blocks,
    predicted_increments,
    uplift_increments,
)
from ._response import EngineRun, StructureResponse
from ._slider_forces import (
    balance_forces,
    heated_step,
    initial_history,
    next_history,
    slider_forces,
    slider_lengths,
    step_history,
    surface_temperature_rises,
)


def _overturning(system):
    """`system` with the overturning map L (G, 2) [-] its loads are read with: zeros without
    overturning (N_g = s W_g)."""
    if system.overturning is not None:
        return system
    return dataclasses.replace(system, overturning=jnp.zeros((system.bearing_load.shape[0], 2), system.mass.dtype))


def series_initial_state(system):
    """At rest: x = (q, q') (6,), sliders and Z (G, S, 2), the balance's unknowns of the last
    two steps (2, G, S + 1, 2) (each group's slider increments [m] and its force [N];
    `predicted_increments`), group forces F_g (G, 2) [N], the generalized force beyond the
    springs f (3,) [N, N m], the normal loads N_g (G,) [N], whether the slab tipped on the
    step (`supported_loads`), for heated surfaces the heat states (G, S, K) [W s/m^2], and
    where a surface's part needs it the sliders' history (G, S) (`initial_history`)."""
    groups, sliders = system.bearing_load.shape[0], system.bearing.slider_count
    zeros = jnp.zeros((groups, sliders, 2), system.mass.dtype)
    heat = {} if system.heat_rates is None else {
        "heat": jnp.zeros((groups, sliders, system.heat_rates.shape[0]), system.mass.dtype)}
    history = initial_history(system.bearing, zeros.shape[:2], zeros.dtype)
    if history is not None:
        heat["history"] = history
    return {**heat, "x": jnp.zeros(6, system.mass.dtype), "slider": zeros, "z": zeros,
            "previous": jnp.zeros((2, groups, sliders + 1, 2), system.mass.dtype),
            "force": jnp.zeros((groups, 2), system.mass.dtype), "extra": jnp.zeros(3, system.mass.dtype),
            "normal_load": overturned_loads(_overturning(system), jnp.zeros(2, system.mass.dtype), 0.0),
            "tipped": jnp.zeros((), bool)}


def series_step(system, state, ground0, ground1, t1):
    """One step from `state` (`series_initial_state`) with the ground (2,) at both ends and t1 its
    end [s]: (state at t1, whether the step balanced: the sliders' balance converged and
    the slab rests on its groups, `supported_loads`)."""
    free, start, end = system.step_matrix[:, :6], system.step_matrix[:, 6:11], system.step_matrix[:, 11:]
    q0 = state["x"][:3]
    linear = free @ state["x"] + start @ jnp.concatenate([ground0, state["extra"]]) + end[:, :2] @ ground1
    phi = end[:3, 2:]
    settle = jnp.linalg.inv(jnp.eye(3, dtype=phi.dtype) + phi @ system.stiffness)
    target, compliance = settle @ linear[:3], -settle @ phi  # q1 = D - G_q P
    b = system.bearing_map
    loads, rests = supported_loads(_overturning(system), -jnp.sum(state["force"], axis=0), t1)
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
    extra = total - system.stiffness @ q1
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
    """One sample (no time axis) of the slab's `StructureResponse` at `time` [s] from the step
    state `state` (`series_initial_state`) and the ground (2,) [m/s^2] then; the driver adds
    whether the step balanced and the groups' uplift time."""
    q = state["x"][:3]
    rise = None if system.heat_rates is None else jax.vmap(surface_temperature_rises, in_axes=(0, 0, None))(
        system.bearing, state["heat"], system.heat_weights)
    return StructureResponse(
        time=time, displacement=q, velocity=state["x"][3:], total_acceleration=-(q @ system.stiffness.T + state["extra"]) / system.mass,
        ground=ground, bearing_force=state["force"], slider=state["slider"],
        bearing_displacement=jnp.einsum("gdn,n->gd", system.bearing_map, q), normal_load=state["normal_load"],
        surface_temperature_rise=rise, tipped=state["tipped"])


def series_groups_run(system, n_steps: int) -> EngineRun:
    """The `EngineRun` of the slab on series pendulum groups over `n_steps` steps from rest,
    each sample `series_sample`'s."""
    time = jnp.arange(n_steps + 1) * float(system.time_step)
    ground = jax.vmap(system.ground)(time)

    def step(state, inputs):
        ground0, ground1, time1 = inputs
        new, converged = series_step(system, state, ground0, ground1, time1)
        return new, series_sample(system, time1, new, ground1), converged

    start = series_initial_state(system)
    return EngineRun(start, (ground[:-1], ground[1:], time[1:]), step, series_sample(system, time[0], start, ground[0]))
