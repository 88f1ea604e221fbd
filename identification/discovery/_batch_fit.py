"""Fits of the augmented model for many candidate effects at once (vmapped Gauss-Newton)."""

import functools
import math

import jax
import jax.numpy as jnp
import numpy as np

from ._augmented import PARAMETER_EFFECT, PARAMETER_NAMES, PARAMETERS, simulate_augmented
from ._effects import EFFECT_NAMES


def _finite_or_null(value):
    if isinstance(value, dict):
        return {k: _finite_or_null(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite_or_null(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


_LOWER = np.array([p.lower for p in PARAMETERS])


_UPPER = np.array([p.upper for p in PARAMETERS])


_LOG = np.array([p.log_scale for p in PARAMETERS])


_LO = np.array([math.log(p.lower) if p.log_scale else p.lower for p in PARAMETERS])


_HI = np.array([math.log(p.upper) if p.log_scale else p.upper for p in PARAMETERS])


def to_physical(u):
    """Unconstrained vector -> physical parameters: x = lo + (hi - lo) sigmoid(u), in log
    space for the parameters marked `log_scale` (bounds are never left)."""
    y = _LO + (_HI - _LO) * jax.nn.sigmoid(u)
    return jnp.where(_LOG, jnp.exp(y), y)


def to_unconstrained(x) -> np.ndarray:
    """Inverse of `to_physical` (numpy; x strictly inside the bounds)."""
    x = np.asarray(x, float)
    y = np.where(_LOG, np.log(np.maximum(x, 1e-300)), x)
    p = np.clip((y - _LO) / (_HI - _LO), 1e-9, 1 - 1e-9)
    return np.log(p) - np.log1p(-p)


def _free_mask(active) -> np.ndarray:
    """1 for the parameters of the baseline and of the active effects."""
    on = {name: active[i] > 0 for i, name in enumerate(EFFECT_NAMES)}
    return np.array(
        [1.0 if owner == "baseline" or on[owner] else 0.0 for owner in PARAMETER_EFFECT]
    )


FIT_RTOL = 1e-9
"""A fit has converged when an accepted Levenberg-Marquardt step lowers the cost by less than
this fraction of it, or when no step of any damping up to 1e8 lowers it (a minimum to the
precision of the arithmetic)."""


@functools.partial(jax.jit, static_argnames=("n_iter",))
def fit_batch(u0, free, actives, weights, data, scale, *, n_iter: int = 200):
    """Masked, bounded Levenberg-Marquardt fits of B model configurations in one call.

    Minimises sum((w (F_model - F_meas) / scale)^2) over the unconstrained parameters u
    (`to_physical`), with the parameters where `free` is 0 held at their start. Steps:
    (J^T J + lam diag(J^T J)) du = -J^T r (Marquardt 1963), lam divided by 3 after a success
    and multiplied by 4 after a failure; iterations until converged (`FIT_RTOL`) or `n_iter`.

    **Arguments:** `u0`, `free` (B, P); `actives` (B, E) effect masks; `weights` (B, n) sample
    weights (0 leaves a sample out); `data` (`AugmentedData`); `scale` force scale [N].

    **Returns:** `(u, cost, jacobian, converged, n_steps)`: final unconstrained parameters
    (B, P), cost 0.5 sum r^2 (B,), the Jacobian of r in u at the end (B, n, P), whether each
    fit met the convergence test (B,) and the iterations it took (B,).
    """

    def one(u_start, free_i, active, weight):
        def residual(u):
            params = {name: x for name, x in zip(PARAMETER_NAMES, to_physical(u))}
            sim = simulate_augmented(params, data, active)
            r = weight * (sim["force"] - data.force) / scale
            if data.biaxial:
                r = jnp.concatenate([r, weight * (sim["force_y"] - data.force_y) / scale])
            return r, r

        def cost_of(u):
            return 0.5 * jnp.sum(residual(u)[0] ** 2)

        def body(carry):
            i, u, lam, cost, _ = carry
            jac, r = jax.jacfwd(residual, has_aux=True)(u)
            jac = jac * free_i
            grad = jac.T @ r
            hess = jac.T @ jac
            diag = jnp.diag(hess)
            system = hess + jnp.diag(lam * (diag + 1e-12) + (1.0 - free_i))
            step = -jnp.linalg.solve(system, grad) * free_i
            trial = u + jnp.clip(step, -4.0, 4.0)
            trial_cost = cost_of(trial)
            better = jnp.isfinite(trial_cost) & (trial_cost < cost)
            small = better & (cost - trial_cost <= FIT_RTOL * cost)
            stuck = (~better) & (lam >= 1e8)
            u = jnp.where(better, trial, u)
            new_cost = jnp.where(better, trial_cost, cost)
            lam = jnp.clip(jnp.where(better, lam / 3.0, lam * 4.0), 1e-9, 1e9)
            return i + 1, u, lam, new_cost, small | stuck | (new_cost == 0.0)

        def cond(carry):
            i, *_, done = carry
            return (i < n_iter) & ~done

        init = (0, u_start, 1e-2, cost_of(u_start), False)
        n, u, _, cost, done = jax.lax.while_loop(cond, body, init)
        jac = jax.jacfwd(lambda v: residual(v)[0])(u) * free_i
        return u, cost, jac, done, n

    return jax.vmap(one)(u0, free, actives, weights)


@jax.jit
def _simulate_batch(values, data, actives):
    def one(v, active):
        params = {name: v[i] for i, name in enumerate(PARAMETER_NAMES)}
        return simulate_augmented(params, data, active)

    return jax.vmap(one)(values, actives)


def _fold_weights(n: int, hc) -> tuple[np.ndarray, np.ndarray]:
    """Two complementary 0/1 masks over the samples: alternate cycles.

    A cycle here is a pair of consecutive strokes (half-cycles 1-2, 3-4, ...; the stroke from
    rest, 0, is a cycle of its own), so each fold holds sliding in both directions and an
    effect that differs between them (asymmetry) stays identifiable in every fold. Records
    with fewer than two cycles are split into alternate eighths of their length instead.
    """
    cycle = (np.asarray(hc) + 1) // 2
    if cycle.max() >= 2:
        a = (cycle % 2 == 0).astype(float)
    else:
        a = ((np.arange(n) * 8 // n) % 2 == 0).astype(float)
    return a, 1.0 - a


def _stacked(x, y, biaxial: bool):
    """x and y components one after the other along the last axis (biaxial), else x."""
    return np.concatenate([x, y], axis=-1) if biaxial else x
