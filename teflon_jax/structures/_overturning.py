"""Overturning of a rigid slab: the normal load of each bearing group under the moment of the
lateral inertia force, held over each step.

The mass above the sliding surface has its centre at the height h above it. The isolation
pushes the slab with the horizontal force H = R^T M (q'' + R a_g) (m times the total
acceleration, for a slab); the inertia force -H acts at the centre of mass, so the vertical reactions of the
groups must take the couple h H. With the slab rigid and the groups on vertical supports of
stiffness k_g (equal unless given), their changes dN_g = k_g (w0 + a rx_g + b ry_g) follow a
plane, and the moment balance about the centre of mass C (r_g = P_g - C) reads

    sum_g dN_g = 0,   sum_g rx_g dN_g = -h H_x,   sum_g ry_g dN_g = -h H_y,

a 3 x 3 system A c = (0, -h H_x, -h H_y), A = sum_g k_g p_g p_g^T, p_g = (1, rx_g, ry_g), so
dN = L H with L (G, 2) fixed by the plan (three groups: statics alone; more: the lever rule
of the supports' stiffness). The normal load of group g is

    N_g = (1 + a_v / g) W_g + dN_g    (N_g = (1 + a_v / g) W_g while a_v <= -g),

on its friction mu N_g Z_g and its pendulum's N_g / R_g d_g (the factor s_g = max(N_g / W_g, 0)
of the vertical record's load, one per group). The equilibrium of the step needs H at its
end, which needs the loads: H is taken at the start of the step (the isolation's force of the
step before) and held over it, as the vertical record's load is held; the lag is one step,
an error of order dt (it vanishes under a steady ground acceleration). The supports take no
tension: when the lever rule leaves a group with N_g <= 0 the slab rests on the others, which
take its share, the plane of the remaining supports solved again with the same total load and
moment (`redistributed_loads`, removing the groups that lift until none is left in tension);
the lifted group has N_g = 0 and carries no shear. Where fewer than three groups off one line
remain, the slab cannot rest on them: the resultant of the vertical reactions would have to act
at C - h H / N (N = sum_g N_g) outside the groups' support, i.e. the moment h H exceeds what
the weight can hold back about the leaning edge, and a rigid slab on supports that take no
tension tips. The model has no rocking, so such a step cannot be balanced: it is reported
(`supported_loads`' flag, folded into each structure's convergence flag) and the loads keep
vertical equilibrium, the lever rule's positive loads scaled to sum to (1 + a_v / g) W, so the
run stays finite (a lever rule with the tension clipped would load the groups with more than
the weight, which under a restrainer's force feeds back on H from step to step).

Masses at several heights (a building on the slab): the inertia force F_i = m_i (q_i'' + R_i a_g)
of degree of freedom i acts at its own height h_i, and the couple is sum_i h_i F_i. Written at
one reference height h (the height of the whole mass's centre, so that H_h = H while every
level accelerates alike) it is h H_h with

    H_h = R^T diag(h_i / h) M (q'' + R a_g)      (`overturning_force`),

which takes the place of H in the lever rule and in the redistribution above, with L and the
`SupportPlan` of that h; the ratios h_i / h are the plan's `levels`. The rigid slab is the case
of one height (no `levels`: H_h = H).
References: Nagarajaiah, Reinhorn & Constantinou (1991), 3D-BASIS, NCEER-91-0005 (rigid slab
on bearings with normal loads from overturning); Almazan, De la Llera & Inaudi (1998),
Earthquake Eng. Struct. Dyn. 27(8), 845-867 (friction pendulum under a varying normal load).
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..units import STANDARD_GRAVITY


def overturning_map(positions, centre_of_mass, height, vertical_stiffness=None, names=None, *,
                    height_name="height_of_centre_of_mass") -> np.ndarray:
    """L (G, 2) [-] with dN = L H (module docstring) for groups at `positions` (G, 2) [m],
    the centre of mass (x, y) [m] at `height` h [m] above the sliding surface and the groups'
    relative vertical stiffness (G,) (default equal). `ValueError` for groups on one line
    (they cannot balance a moment about it; the message names `height_name`, the caller's
    argument for the height) or a stiffness share <= 0."""
    positions = np.asarray(positions, dtype=float).reshape(-1, 2)
    groups = positions.shape[0]
    k = np.ones(groups) if vertical_stiffness is None else np.asarray(vertical_stiffness, float).reshape(-1)
    names = [f"group {i + 1}" for i in range(groups)] if names is None else list(names)
    if k.shape != (groups,):
        raise ValueError(f"vertical_stiffness: one value per group ({groups}), got {k.size}.")
    for name, value in zip(names, k):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"vertical_stiffness: {name} has {value:g}; give a relative stiffness > 0.")
    r = positions - np.asarray(centre_of_mass, dtype=float).reshape(2)
    p = np.column_stack([np.ones(groups), r])  # (G, 3)
    a = np.einsum("g,gi,gj->ij", k, p, p)
    length = max(float(np.max(np.abs(r))), 1e-300)
    spread = np.linalg.svd(p / np.array([1.0, length, length]) * np.sqrt(k / k.max())[:, None],
                           compute_uv=False)
    if groups < 3 or spread[-1] < 1e-9 * spread[0]:
        raise ValueError(
            f"{height_name}: the bearing groups lie on one line, so a rigid slab on "
            "them cannot balance the overturning moment about it; add a group off that line, or "
            "give height 0 (no overturning).")
    columns = np.linalg.solve(a, np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]))  # (3, 2)
    return -float(height) * k[:, None] * (p @ columns)


class SupportPlan(eqx.Module):
    """The vertical supports of the groups, for the loads while some lift (module docstring):
    relative stiffness k_g (G,) [-], p_g = (1, rx_g / l, ry_g / l) (G, 3) [-] and h / l [-],
    with l the largest arm [m] (numbers of order one); `levels` h_i / h (N,) [-] of masses at
    several heights (`overturning_force`), `None` for all at h (the rigid slab)."""

    stiffness: jnp.ndarray
    arms: jnp.ndarray
    height: jnp.ndarray
    levels: jnp.ndarray | None = None


def support_plan(positions, centre_of_mass, height, vertical_stiffness=None, levels=None) -> SupportPlan:
    """The `SupportPlan` of groups at `positions` (G, 2) [m] (checked by `overturning_map`);
    `levels` (N,) [-]: the degrees of freedom's heights over `height` (`overturning_force`),
    `None` for all at `height`."""
    positions = np.asarray(positions, dtype=float).reshape(-1, 2)
    groups = positions.shape[0]
    k = np.ones(groups) if vertical_stiffness is None else np.asarray(vertical_stiffness, float).reshape(-1)
    r = positions - np.asarray(centre_of_mass, dtype=float).reshape(2)
    length = max(float(np.max(np.abs(r))), 1e-300)
    return SupportPlan(stiffness=jnp.asarray(k / k.max()),
                       arms=jnp.asarray(np.column_stack([np.ones(groups), r / length])),
                       height=jnp.asarray(float(height) / length),
                       levels=None if levels is None else jnp.asarray(levels, dtype=float))


def redistributed_loads(supports: SupportPlan, static, linear, force, vertical=1.0):
    """N_g (G,) [N] of a slab on supports that take no tension (`resting_loads`' loads)."""
    return resting_loads(supports, static, linear, force, vertical)[0]


def resting_loads(supports: SupportPlan, static, linear, force, vertical=1.0):
    """(N_g (G,) [N], whether the slab rests) on supports that take no tension: from the lever
    rule's loads `linear` (G,), the groups with N_g <= 0 are removed and the plane of the others
    solved again for the same resultant (sum_g N_g = sum_g `static`, the moments of `static` and
    of -h H, H = `force` (2,) [N], counted while `vertical` > 0), until none is in tension (at
    most G rounds). `linear` itself where no group lifts (or nothing presses, sum `static` <= 0);
    where fewer than three groups off one line remain the slab tips (module docstring): it does
    not rest, and the loads are max(`linear`, 0) scaled to sum to sum `static`."""
    k, p = supports.stiffness, supports.arms
    moment = jnp.concatenate([jnp.zeros(1, static.dtype), -supports.height * force]) * (vertical > 0)
    target = p.T @ static + moment

    def loads(active):
        a = active.astype(static.dtype)
        matrix = jnp.einsum("g,g,gi,gj->ij", a, k, p, p)
        ok = jnp.abs(jnp.linalg.det(matrix)) > 1e-9 * jnp.sum(a * k) ** 3
        c = jnp.linalg.solve(jnp.where(ok, matrix, jnp.eye(3, dtype=matrix.dtype)), target - p.T @ (a * static))
        return a * (static + k * (p @ c)), ok

    def remove(_, active):
        n, ok = loads(active)
        return jnp.where(ok, active & (n > 0), active)

    n, ok = loads(jax.lax.fori_loop(0, static.shape[0], remove, linear > 0))
    lifts, total = jnp.any(linear <= 0), jnp.sum(static)
    rests = ok | ~lifts | (total <= 0)
    pressed = jnp.maximum(linear, 0.0)
    pressed_sum = jnp.sum(pressed)
    tipped = pressed * total / jnp.where(pressed_sum > 0, pressed_sum, 1.0)
    return jnp.where(ok & lifts, n, jnp.where(rests, linear, tipped)), rests


def inertia_force(system, acceleration, ground):
    """H = R^T M (q'' + R a_g) (2,) [N]: the horizontal force of the isolation on the
    structure at relative acceleration `acceleration` (N,) and ground acceleration (2,)."""
    total = acceleration + system.influence @ ground
    return (system.mass * total) @ system.influence


def overturning_force(system, acceleration, ground):
    """H_h = R^T diag(h_i / h) M (q'' + R a_g) (2,) [N]: the force at the reference height h
    whose moment h H_h is that of the inertia forces at their own heights h_i (module
    docstring; the `levels` h_i / h of `system.supports`); `inertia_force` H where there are no
    levels (all masses at h, the rigid slab)."""
    levels = None if system.supports is None else system.supports.levels
    if levels is None:
        return inertia_force(system, acceleration, ground)
    total = acceleration + system.influence @ ground
    return (levels * system.mass * total) @ system.influence


def overturned_loads(system, force, t):
    """N_g (G,) [N] under the vertical record at t [s] and the horizontal force `force` H (2,) [N]
    (`supported_loads`' loads); the factor on W_g is `group_factor`."""
    return supported_loads(system, force, t)[0]


def supported_loads(system, force, t):
    """(N_g (G,) [N], whether the slab rests) under the vertical record at t [s] and the
    horizontal force `force` H (2,) [N] (module docstring), redistributed while groups lift
    where `system.supports` is given (`resting_loads`)."""
    vertical = 1.0 if system.vertical_acceleration is None else 1 + system.vertical_acceleration(t) / STANDARD_GRAVITY
    static = vertical * system.bearing_load
    linear = static + (vertical > 0) * (system.overturning @ force)
    if system.supports is None:
        return linear, jnp.ones((), bool)
    return resting_loads(system.supports, static, linear, force, vertical)


def group_factor(system, normal_load):
    """s_g = max(N_g / W_g, 0) (G,) [-]: the load factor of each group (0 while lifted)."""
    return jnp.maximum(normal_load, 0.0) / system.bearing_load


def initial_normal_load(system):
    """N_g (G,) [N] at rest at t = 0 (no inertia force yet)."""
    return overturned_loads(system, np.zeros(2), 0.0)
