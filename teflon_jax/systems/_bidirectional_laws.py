"""The other isolator laws of a structure in two directions: Coulomb friction, no friction,
and a friction pendulum's restrainer and large-displacement force; and the small dense algebra
of the planar solve (vectors over the G bearing groups kept as their x and y parts (G,),
matrices as 2 x 2 blocks of (G, G)).

**Coulomb friction (Eq. 2 in the plane).** Each group g slides at v_g with the force
F_g = mu_g W_g v_g / |v_g|, or sticks (v_g = 0) with |F_g| <= mu_g W_g. Over one Newmark
step the groups' velocities at its end are an affine function of their forces,
v = v* - H F with H = (2 / dt) G_b (G_b = B K_eff^-1 B^T, symmetric positive definite) and v*
the velocities of the step without bearing forces. The law is then the optimality condition
of the convex problem

    F = argmin { F^T H F / 2 - v*^T F :  |F_g| <= mu_g W_g for every g },

(maximum dissipation: v_g lies in the normal cone of the disc at F_g). One group with an
isotropic H = h I has the closed form of the uniaxial rule: stick with F = v* / h while
|v*| / h <= mu W, else slide at F = mu W v* / |v*|. In general the problem is solved by
accelerated projected gradients (Beck & Teboulle 2009, FISTA) from the projected sticking
force, to a fixed-point residual of 1e-12 of the largest capacity. As in one direction, mu is
Eq. 1 at the speed |v*_g| of the step without friction, and Z_g = F_g / (mu_g W_g).

**No friction** ("none"): the groups carry no friction force; the structure is linear.

**The pendulum's surface.** A `ConcaveSurface` with a restrainer or the large-displacement form
adds `ConcaveSurface.extra_force` at each group's displacement d_g (along d_g, under the
group's normal load) to the friction force; its small-rotation part W_g / R is in K.

References: Constantinou, Mokha & Reinhorn (1990), J. Struct. Eng. 116(2), Eq. 2; Moreau
(1988), "Unilateral contact and dry friction in finite freedom dynamics"; Beck & Teboulle
(2009), SIAM J. Imaging Sciences 2(1), 183-202.
"""

import jax
import jax.numpy as jnp

from ..structures import small_dot

FRICTION_MODELS = ("hysteretic", "coulomb", "none")
"""Friction laws of a structure in two directions: Park's biaxial Z, Coulomb, none."""

COULOMB_ITERATIONS = 2000
"""Most projected-gradient iterations of the Coulomb step (a step that needs more is reported
as not converged)."""

COULOMB_TOLERANCE = 1e-12
"""Fixed-point residual of the Coulomb step, relative to the largest capacity mu W."""


def check_planar_law(friction_model, surface, bearing):
    """`ValueError` naming the argument for an unknown friction model, a Coulomb bearing with
    parts beyond Eq. 1, or a restrainer or large-displacement surface without Park's Z."""
    if friction_model not in FRICTION_MODELS:
        raise ValueError(f"friction_model: unknown {friction_model!r}; accepted: {', '.join(FRICTION_MODELS)}.")
    if friction_model == "coulomb" and bearing is not None and bearing.effects:
        raise ValueError(f"bearing: the Coulomb model runs Eq. 1 alone, not its "
                         f"{', '.join(bearing.effects)}; use friction_model='hysteretic'.")
    if surface is not None and not surface.is_linear and friction_model != "hysteretic":
        raise ValueError("surface: its restrainer or large-displacement force is solved with the "
                         f"hysteretic friction model, not {friction_model!r}.")


def surface_forces(system, dx, dy):
    """The surface's force beyond W_g d_g / R (x and y parts, each (G,)) [N] at the groups'
    displacements (dx, dy) [m], under the groups' loads `bearing_load`."""
    force = system.surface.extra_force(jnp.stack([dx, dy], -1), system.bearing_load)
    return force[:, 0], force[:, 1]


def with_surface_forces(system, forces, d):
    """`forces` (x, y parts) [N] plus the surface's at the displacements `d` (x, y parts) [m];
    `forces` themselves without a nonlinear surface (no work added to the flat sliders' step)."""
    if system.surface is None:
        return forces
    extra = surface_forces(system, d[0], d[1])
    return forces[0] + extra[0], forces[1] + extra[1]


def surface_tangent(system, dx, dy):
    """d(surface force)/d(d) per group: ((xx, xy), (yx, yy)), each (G,) [N/m]."""
    def force(dx, dy):
        return surface_forces(system, dx, dy)

    _, column_x = jax.jvp(force, (dx, dy), (jnp.ones_like(dx), jnp.zeros_like(dy)))
    _, column_y = jax.jvp(force, (dx, dy), (jnp.zeros_like(dx), jnp.ones_like(dy)))
    return (column_x[0], column_y[0]), (column_x[1], column_y[1])


def _project(force, capacity):
    """Each group's force (G, 2) pulled back onto its disc |F_g| <= capacity_g."""
    size = jnp.sqrt(jnp.sum(force**2, axis=-1))
    scale = jnp.where(size > capacity, capacity / jnp.where(size > 0, size, 1.0), 1.0)
    return force * scale[:, None]


def coulomb_solve(system, p):
    """Bearing forces (x, y parts), Z (G, 2) and convergence of a Coulomb step (module
    docstring), for the step's parameters `p` of `BidirectionalStructure._update`."""
    dt = system.time_step
    n = p["d0"][0].shape[0]
    compliance = 2 / dt * jnp.block([list(row) for row in p["flexibility"]])  # H (2G, 2G)
    v_star = jnp.concatenate([2 / dt * (p["d_linear"][i] - p["d0"][i]) - p["vb0"][i] for i in range(2)])
    speed = (v_star[:n], v_star[n:])
    capacity = system.bearing.coefficient(speed[0], speed[1], 1.0) * system.bearing_load  # (G,)

    def as_groups(flat):
        return jnp.stack([flat[:n], flat[n:]], -1)

    def flat(groups):
        return jnp.concatenate([groups[:, 0], groups[:, 1]])

    def step(force):
        return flat(_project(as_groups(force - (compliance @ force - v_star) / lipschitz), capacity))

    lipschitz = jnp.max(jnp.sum(jnp.abs(compliance), axis=1))  # >= the largest eigenvalue of H
    tolerance = COULOMB_TOLERANCE * jnp.maximum(jnp.max(capacity), jnp.finfo(v_star.dtype).tiny)
    # the sticking forces of each group alone (H is singular when the groups outnumber the
    # structure's degrees of freedom, as on a slab: the forces are then not unique, the motion is)
    start = flat(_project(as_groups(v_star / jnp.diagonal(compliance)), capacity))

    def residual(force):
        return jnp.max(jnp.abs(step(force) - force))

    def body(carry):
        force, previous, momentum, k = carry
        look = force + (momentum - 1) / (momentum + 2) * (force - previous)
        return step(look), force, momentum + 1, k + 1

    force, *_ = jax.lax.while_loop(
        lambda c: (residual(c[0]) > tolerance) & (c[3] < COULOMB_ITERATIONS), body,
        (start, start, jnp.asarray(1.0, start.dtype), 0))
    converged = residual(force) <= tolerance
    force_g = as_groups(force)
    loaded = capacity > 0  # while uplifted (N = 0) Z points along v*
    direction = as_groups(v_star) / jnp.maximum(jnp.sqrt(jnp.sum(as_groups(v_star) ** 2, -1)),
                                                jnp.finfo(v_star.dtype).tiny)[:, None]
    z = jnp.where(loaded[:, None], force_g / jnp.where(loaded, capacity, 1.0)[:, None], direction)
    return (force_g[:, 0], force_g[:, 1]), z, converged


def no_friction_solve(system, p):
    """No friction: zero forces, Z held, converged."""
    zero = jnp.zeros_like(p["d_linear"][0])
    return (zero, zero), jnp.stack(p["z0"], -1), jnp.asarray(True)


# --------------------------------------------------------------------------- block algebra


def matvec(matrix, vector):
    """matrix (m, G) @ vector (G,), as a product of elements for G = 1 (no dot kernel)."""
    return matrix[:, 0] * vector if matrix.shape[1] == 1 else small_dot(matrix, vector)


def block_matvec(blocks, vector):
    """((xx, xy), (yx, yy)) @ (vx, vy), each block (G, G)."""
    return tuple(matvec(blocks[i][0], vector[0]) + matvec(blocks[i][1], vector[1]) for i in range(2))


def affine(flexibility, forces, d, d_linear):
    """d - d_linear + G_b F, in x and y parts."""
    product = block_matvec(flexibility, forces)
    return tuple(d[i] - d_linear[i] + product[i] for i in range(2))


def solve_blocks(blocks, rhs):
    """((xx, xy), (yx, yy))^-1 (rx, ry): in closed form for one bearing group (2 x 2), by LU
    otherwise."""
    if blocks[0][0].shape == (1, 1):
        (a, b), (c, d) = ((blk[:, 0] for blk in row) for row in blocks)
        det = a * d - b * c
        return (d * rhs[0] - b * rhs[1]) / det, (a * rhs[1] - c * rhs[0]) / det
    full = jnp.block(blocks)
    flat = jnp.linalg.solve(full, jnp.concatenate(rhs))
    n = rhs[0].shape[0]
    return flat[:n], flat[n:]
