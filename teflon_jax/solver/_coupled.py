"""Iterations on the balance of G coupled planar unknowns, kept as their x and y parts (G,)
apart (under `vmap` an interleaved (G, 2) layout keeps XLA's CPU loops from vectorising):

    r(d) = d - d_lin + G_b F(d) = 0,     G_b (2G, 2G) = ((xx, xy), (yx, yy)), blocks (G, G),

the bearing groups of a structure in two directions, whose forces F_g couple through the
structure's flexibility G_b (a full matrix, not a block diagonal as in `planar_newton`).

- `coupled_newton`: Broyden's secant iterations from an approximate tangent (a fixed number
  unrolled, the same work for every batch member, then a loop while a member is above
  tolerance), then `damped_newton` on the exact Jacobian from the best iterate seen.
- `coulomb_disc_forces`: the forces of Coulomb friction over one step, the minimiser of
  F^T H F / 2 - v*^T F over the discs |F_g| <= c_g (maximum dissipation), by accelerated
  projected gradients.
- The small block algebra both use (`block_matvec`, `solve_blocks`, `affine`).

References: Broyden (1965), Math. Comp. 19; Dennis & Schnabel (1996), Sec. 6.3 and 8.1;
Moreau (1988), "Unilateral contact and dry friction in finite freedom dynamics"; Beck &
Teboulle (2009), SIAM J. Imaging Sciences 2(1), 183-202.
"""

import jax
import jax.numpy as jnp

from ..structures import small_dot
from ._newton import damped_newton

FIXED_ITERATIONS = 1
"""Newton-Broyden iterations per step, unrolled (the same work for every batch member); from
a force-held predictor one is enough for most members (3 cost the rigid-mass Monte Carlo
~20 % more, measured), the loops after it take the others."""

BROYDEN_ITERATIONS = 8
"""Most further Newton-Broyden iterations per step, in a loop that runs while a member is
above tolerance (before the Newton loop)."""

COULOMB_ITERATIONS = 2000
"""Most projected-gradient iterations of a Coulomb step (a step that needs more is reported
as not converged)."""

COULOMB_TOLERANCE = 1e-12
"""Fixed-point residual of a Coulomb step, relative to the largest capacity."""


def coupled_newton(residual, tangent, guess, tolerance, iterations: int, *, secant: bool = True):
    """The root of a coupled planar balance (module docstring) from `guess` (x, y parts):
    `FIXED_ITERATIONS` Newton-Broyden iterations unrolled from the approximate tangent at the
    guess, up to `BROYDEN_ITERATIONS` more while max |r| > `tolerance`, then Newton's method
    on the exact Jacobian with step halving (`damped_newton`, no rescue steps) from the best
    iterate the secant stage saw; `iterations` caps the steps of all stages together. With
    `secant` False, Newton's stage alone from the guess.

    **Arguments:** `residual(d)` -> (r (x, y parts), evaluation) (the evaluation: whatever the
    caller wants back at the root, such as the forces and Z); `tangent(d, exact)` -> (r,
    Jacobian blocks ((xx, xy), (yx, yy)), evaluation): approximate for `exact` False (the
    secant stage corrects it), dr/dd for True.

    **Returns:** (r at the iterate, flattened (2G,), the evaluation there)."""
    if not secant:
        r, evaluation = residual(guess)
        return _newton_stage(tangent, guess, r, evaluation, 0, tolerance, iterations)
    r, jacobian, evaluation = tangent(guess, False)
    x, r, evaluation, done = _broyden_stage(residual, guess, r, jacobian, evaluation, tolerance, iterations)
    return _newton_stage(tangent, x, r, evaluation, done, tolerance, iterations)


def _largest(r):
    """Largest |r| over the x and y parts of a residual."""
    return jnp.maximum(jnp.max(jnp.abs(r[0])), jnp.max(jnp.abs(r[1])))


def _broyden_update(residual, x, r, jacobian, tolerance):
    """One Newton step with the current Jacobian, then its secant (Broyden) update; a member
    already within tolerance keeps its iterate (no step at round-off)."""
    tiny = jnp.finfo(x[0].dtype).tiny
    off = _largest(r) > tolerance
    step = solve_blocks(jacobian, r)
    finite = jnp.isfinite(step[0]).all() & jnp.isfinite(step[1]).all() & off
    step = tuple(jnp.where(finite, -step[i], jnp.where(off, -r[i], 0.0)) for i in range(2))
    x = (x[0] + step[0], x[1] + step[1])
    r_new, evaluation = residual(x)
    predicted = block_matvec(jacobian, step)
    mismatch = [r_new[i] - r[i] - predicted[i] for i in range(2)]
    norm2 = jnp.maximum(jnp.sum(step[0] ** 2) + jnp.sum(step[1] ** 2), tiny)
    jacobian = [[jacobian[i][j] + jnp.outer(mismatch[i], step[j]) / norm2 for j in range(2)]
                for i in range(2)]
    return x, r_new, jacobian, evaluation


def _broyden_stage(residual, x, r, jacobian, evaluation, tolerance, iterations: int):
    """`FIXED_ITERATIONS` unrolled secant iterations, then more while a member is above
    tolerance; returns the best iterate seen (x, r, evaluation) and the iterations done."""
    fixed = min(FIXED_ITERATIONS, iterations)  # `iterations` bounds them all
    for _ in range(fixed):  # unrolled: the same work for every member
        x, r, jacobian, evaluation = _broyden_update(residual, x, r, jacobian, tolerance)

    def body(carry):
        x, r, jacobian, evaluation, k, best = carry
        x, r, jacobian, evaluation = _broyden_update(residual, x, r, jacobian, tolerance)
        better = _largest(r) < _largest(best[1])
        best = jax.tree.map(lambda new, old: jnp.where(better, new, old), (x, r, evaluation), best)
        return x, r, jacobian, evaluation, k + 1, best

    # more secant iterations, one batch-wide residual each, while a member is off; a secant
    # step can lead away from the root, so Newton's stage starts from the best iterate seen
    limit = fixed + min(BROYDEN_ITERATIONS, iterations - fixed)
    *_, done, (x, r, evaluation) = jax.lax.while_loop(
        lambda c: (_largest(c[1]) > tolerance) & (c[4] < limit), body,
        (x, r, jacobian, evaluation, fixed, (x, r, evaluation)))
    return x, r, evaluation, done


def _newton_stage(tangent, x, r, evaluation, done, tolerance, iterations: int):
    """Newton's method (the exact Jacobian; the residual itself where that gives no finite
    direction) with step halving (`damped_newton`), while a member is above tolerance,
    counting on from the `done` iterations before it; returns (r flat, evaluation)."""
    n = x[0].shape[0]

    def direction(r, jacobian):
        step = jnp.linalg.solve(jnp.block(jacobian), r)
        return jnp.where(jnp.all(jnp.isfinite(step)), step, r)

    def evaluate(flat):
        r, jacobian, evaluation = tangent((flat[:n], flat[n:]), True)
        r = jnp.concatenate(r)
        return r, jnp.sum(r**2), direction(r, jacobian), evaluation

    # the start's direction zero and its merit infinite: the loop's first pass evaluates the
    # start itself (one copy of the exact Jacobian in the compiled step, not two), and is not
    # counted; `iterations` caps the steps of every stage together (no rescue steps)
    r = jnp.concatenate(r)
    start = jnp.concatenate(x)
    first = (r, jnp.asarray(jnp.inf, r.dtype), jnp.zeros_like(r), evaluation)
    *_, (r, _, _, evaluation) = damped_newton(evaluate, start, tolerance, iterations, first=first,
                                              taken=done - 1, rescue=0)
    return r, evaluation


def _project(force, capacity):
    """Each group's force (G, 2) pulled back onto its disc |F_g| <= capacity_g."""
    size = jnp.sqrt(jnp.sum(force**2, axis=-1))
    scale = jnp.where(size > capacity, capacity / jnp.where(size > 0, size, 1.0), 1.0)
    return force * scale[:, None]


def coulomb_disc_forces(compliance, v_star, capacity):
    """Coulomb friction over one step of G groups whose velocities at its end are affine in
    their forces, v = v* - H F (H (2G, 2G) symmetric positive semi-definite, x parts first):

        F = argmin { F^T H F / 2 - v*^T F :  |F_g| <= c_g for every g },

    the optimality condition of which is Coulomb's law (each sliding group's v_g along F_g, each
    sticking group's v_g = 0). Solved by accelerated projected gradients (FISTA, step 1 / L with
    L the largest absolute row sum of H) from each group's sticking force alone projected on
    its disc, to a fixed-point residual of `COULOMB_TOLERANCE` of the largest capacity.

    **Arguments:** `compliance` H; `v_star` (2G,) [m/s] the velocities without friction (x
    parts, then y); `capacity` (G,) [N] the discs' radii mu_g W_g.

    **Returns:** (F (G, 2) [N], whether the residual met the tolerance)."""
    n = capacity.shape[0]

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
    return as_groups(force), residual(force) <= tolerance


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
