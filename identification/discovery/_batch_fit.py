"""Fits of the augmented model for many candidate effects at once (vmapped optimistix
Levenberg-Marquardt)."""

import math

import jax
import jax.numpy as jnp
import numpy as np

from ..least_squares import fit_least_squares_batch
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


FIT_RTOL = 1e-5
"""Relative tolerance of each fit: it has converged when a step changes every residual r by
less than `FIT_ATOL + FIT_RTOL |r|` (optimistix's test on the residuals alone: a parameter
running into a bound of its sigmoid keeps moving in u while the residuals stop), or when no
damping up to `MAX_DAMPING` of `least_squares._marquardt` lowers the cost. The residuals are
forces over their root-mean-square, so this is 1e-5 of the force scale."""

FIT_ATOL = 1e-5
"""Absolute tolerance of each fit (see `FIT_RTOL`)."""


def _free_mask(active) -> np.ndarray:
    """1 for the parameters of the baseline and of the active effects."""
    on = {name: active[i] > 0 for i, name in enumerate(EFFECT_NAMES)}
    return np.array(
        [1.0 if owner == "baseline" or on[owner] else 0.0 for owner in PARAMETER_EFFECT]
    )


def _residual(params, args):
    """Scaled, weighted force residual of one configuration; held parameters at their start."""
    (active, weight, start, free), (data, scale) = args
    values = {name: jnp.where(free[i] > 0, params[name], start[i])
              for i, name in enumerate(PARAMETER_NAMES)}
    sim = simulate_augmented(values, data, active)
    return data.stack(weight * (sim["force"] - data.force) / scale,
                      weight * (sim["force_y"] - data.force_y) / scale)


def fit_batch(starts, free, actives, weights, data, scale, *, max_steps: int = 200):
    """Bounded least-squares fits of B model configurations in one vmapped optimistix call.

    Minimises 0.5 sum((w (F_model - F_meas) / scale)^2) for each configuration with
    `fit_least_squares_batch` (Levenberg-Marquardt with Marquardt's scaled damping), every
    parameter kept inside its search range (`teflon_jax.bearing.PARAMETER_BOUNDS`) by the
    sigmoid bijection, in log x for the log-scaled ones; a parameter where `free` is 0 is held
    at its start (its Jacobian column is zero, so the solver never moves it).

    **Arguments:** `starts`, `free` (B, P) physical start values and 0/1 masks in the order of
    `PARAMETER_NAMES`; `actives` (B, E) effect masks; `weights` (B, n) sample weights (0
    leaves a sample out); `data` (`AugmentedData`); `scale` force scale [N]; `max_steps` the
    solver's step limit.

    **Returns:** `(values, cost, jacobian, converged, n_steps)` as numpy arrays: fitted physical
    parameters (B, P), cost 0.5 sum r^2 (B,), the Jacobian of r in the physical parameters
    (B, n_r, P; zero columns for held ones), whether optimistix reported success (B,) and the
    steps it took (B,).
    """
    starts = np.asarray(starts, float)
    free = np.asarray(free, float)
    fits = fit_least_squares_batch(
        _residual,
        {name: starts[:, i] for i, name in enumerate(PARAMETER_NAMES)},
        {p.name: (p.lower, p.upper) for p in PARAMETERS},
        args=((jnp.asarray(actives), jnp.asarray(weights), jnp.asarray(starts),
               jnp.asarray(free)), (data, jnp.asarray(scale))),
        args_batched=(True, False),
        log_scale=tuple(p.name for p in PARAMETERS if p.log_scale),
        max_steps=max_steps,
        rtol=FIT_RTOL,
        atol=FIT_ATOL,
        solver="levenberg_marquardt_scaled",
        converged_on="residuals",
    )
    values = np.array([[fit.parameters[name] for name in PARAMETER_NAMES] for fit in fits])
    return (
        np.where(free > 0, values, starts),
        np.array([fit.cost for fit in fits]),
        np.stack([fit.jacobian for fit in fits]),
        np.array([fit.converged for fit in fits]),
        np.array([fit.n_steps for fit in fits]),
    )


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
