"""Newton's iteration on a balance of S elements, each with a planar unknown d_e (S, 2) and a
2 x 2 block K_e = dF_e/dd_e of its own (F_e depends on d_e alone), coupled through one
compliance G: J = blockdiag(K_e) + U U^T / G, inverted by the Woodbury identity
(`woodbury`). `planar_newton` takes the blocks the caller gives at every point, or, with a
secant stage, by Broyden's update of each block after the first (`broyden_blocks`).
References: Woodbury (1950); Broyden (1965), Math. Comp. 19; Dennis & Schnabel (1996),
Sec. 6.3.
"""

import jax
import jax.numpy as jnp

from ._newton import damped_newton

SECANT_ITERATIONS = 8
"""Most steps of the secant stage of `planar_newton` (each one evaluation of the forces)."""


def planar_newton(forces, residual, direction, blocks, guess, tolerance, iterations: int, *, secant=None):
    """Newton's iteration with step halving on a planar balance (`damped_newton`):
    d <- d - f J(d)^-1 r(d), J(d) from the blocks at d, after an optional secant stage.

    **Arguments:** `forces(d)` -> an evaluation (F (S, 2), whatever else the blocks read, such
    as Z), the one costly call; `residual(d, evaluation)` -> r; `direction(r, K)` -> J^-1 r for
    the blocks K (S, 2, 2); `blocks(d, evaluation)` -> K at d (the iteration needs J only to
    about sqrt(eps), the balance being judged on the exact r); `secant`: `None`, or
    `update(K, step, change, d)` -> K after d moved by `step` and F by `change`
    (`broyden_blocks`): a first stage takes `blocks` at `guess` only and then that update,
    full steps while the merit falls, at most min(`SECANT_ITERATIONS`, `iterations`), one
    evaluation each; the Newton stage continues where it stops short, counting its steps.

    **Returns:** (d, whether max |r| <= tolerance, the number of steps taken, the evaluation at
    d)."""
    def choose(keep, new, old):
        return jax.tree_util.tree_map(lambda a, b: jnp.where(keep, a, b), new, old)

    def trial_of(d, r, merit, step):
        trial = d - step
        evaluation = forces(trial)
        r_trial = residual(trial, evaluation)
        merit_trial = jnp.sum(r_trial**2)
        return merit_trial < merit, (trial, evaluation, r_trial, merit_trial)

    def secant_cond(carry):
        _, _, r, _, _, k, falling = carry
        return falling & (jnp.max(jnp.abs(r)) > tolerance) & (k < min(SECANT_ITERATIONS, iterations))

    def secant_body(carry):
        d, evaluation, r, merit, matrix, k, _ = carry
        lower, new = trial_of(d, r, merit, direction(r, matrix))
        matrix = jnp.where(lower, secant(matrix, new[0] - d, new[1][0] - evaluation[0], d), matrix)
        new = choose(lower, new, (d, evaluation, r, merit))
        return (*new, matrix, k + 1, lower)

    def evaluate(d):  # damped_newton's (r, merit, evaluation) at d, its direction where a step starts
        evaluation = forces(d)
        r = residual(d, evaluation)
        return r, jnp.sum(r**2), evaluation

    def newton_direction(d, values):
        return direction(values[0], blocks(d, values[2]))

    evaluation = forces(guess)
    r = residual(guess, evaluation)
    d, merit, k = guess, jnp.sum(r**2), 0
    if secant is not None:
        carry = (d, evaluation, r, merit, blocks(d, evaluation), k, jnp.array(True))
        d, evaluation, r, merit, _, k, _ = jax.lax.while_loop(secant_cond, secant_body, carry)
    d, converged, taken, values = damped_newton(evaluate, d, tolerance, iterations, first=(r, merit, evaluation),
                                                taken=k, direction=newton_direction)
    return d, converged, taken, values[2]


def broyden_blocks(blocks, step, change, floor):
    """Broyden's update of each element's block K_e (S, 2, 2) after its unknown moved by
    `step` s_e (S, 2) and its force by `change` y_e (S, 2) (F_e depends on d_e alone):
    K_e + (y_e - K_e s_e) s_e^T / (s_e . s_e), so that K_e s_e = y_e (Broyden 1965); an
    element whose step is within `floor` (S,) (so short that y_e is mostly rounding) keeps its
    block."""
    size = jnp.sum(step**2, axis=-1)
    moved = size > floor**2
    miss = change - jnp.einsum("eij,ej->ei", blocks, step)
    update = miss[:, :, None] * step[:, None, :] / jnp.where(moved, size, 1.0)[:, None, None]
    return blocks + jnp.where(moved[:, None, None], update, 0.0)


def inverse2(m):
    """Inverses of 2 x 2 matrices (..., 2, 2), by the adjugate."""
    det = m[..., 0, 0] * m[..., 1, 1] - m[..., 0, 1] * m[..., 1, 0]
    adjugate = jnp.stack([jnp.stack([m[..., 1, 1], -m[..., 0, 1]], -1),
                          jnp.stack([-m[..., 1, 0], m[..., 0, 0]], -1)], -2)
    return adjugate / det[..., None, None]


def woodbury(residual, blocks, compliance):
    """J^-1 r for J = blockdiag(K_e) + U U^T / G: C_e (r_e - s), C_e = K_e^-1,
    s = (G I + sum C_e)^-1 sum C_e r_e. One element: (G K + I)^-1 G r, without the
    cancellation of C (r - s) where K is near singular (a flat slider's along its sliding)."""
    if residual.shape[0] == 1:
        eye = jnp.eye(2, dtype=residual.dtype)
        return jnp.einsum("eij,ej->ei", inverse2(compliance * blocks + eye), compliance * residual)
    c = inverse2(blocks)
    cr = jnp.einsum("eij,ej->ei", c, residual)
    s = inverse2(compliance * jnp.eye(2, dtype=residual.dtype) + jnp.sum(c, 0)) @ jnp.sum(cr, 0)
    return cr - jnp.einsum("eij,j->ei", c, s)
