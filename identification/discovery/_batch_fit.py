"""Fits of the augmented model for many candidate effects at once (vmapped optimistix
Levenberg-Marquardt).

Inside the optimiser each delta_f of Eq. 1 (and its perpendicular twin) is its ratio to f_max in
(0, 1), as in the single flat fit and the series fits (`identification.bearing_fit._ratio`), so
that no fit ends with delta_f > f_max, a negative friction at rest f_max - delta_f."""

import math

import jax
import jax.numpy as jnp
import numpy as np

from ..bearing_fit import (
    RATIO_BOUNDS,
    RATIO_PAIRS,
    deltas_of,
    ratio_bounds,
    result_from_ratios,
    to_ratios,
)
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


def _physical(params, start, free) -> dict:
    """The augmented model's parameters of the optimiser's `params` (each delta_f as its ratio to
    f_max): held parameters (`free` 0) at their `start`, a free delta_f the ratio times f_max."""
    index = {name: i for i, name in enumerate(PARAMETER_NAMES)}
    values = {name: jnp.where(free[i] > 0, params[name], start[i])
              for i, name in enumerate(PARAMETER_NAMES) if name in params}
    deltas = deltas_of({**values, **{k: v for k, v in params.items() if k not in index}}, RATIO_PAIRS)
    values.update({name: jnp.where(free[index[name]] > 0, value, start[index[name]])
                   for name, value in deltas.items()})
    return {name: values[name] for name in PARAMETER_NAMES}


def _residual(params, args):
    """Scaled, weighted force residual of one configuration; held parameters at their start."""
    (active, weight, start, free), (data, scale) = args
    sim = simulate_augmented(_physical(params, start, free), data, active)
    return data.stack(weight * (sim["force"] - data.force) / scale,
                      weight * (sim["force_y"] - data.force_y) / scale)


def fit_batch(starts, free, actives, weights, data, scale, *, max_steps: int = 200):
    """Bounded least-squares fits of B model configurations in one vmapped optimistix call.

    Minimises 0.5 sum((w (F_model - F_meas) / scale)^2) for each configuration with
    `fit_least_squares_batch` (Levenberg-Marquardt with Marquardt's scaled damping), every
    parameter kept inside its search range (`teflon_jax.bearing.PARAMETER_BOUNDS`) by the
    sigmoid bijection, in log x for the log-scaled ones, and each delta_f as its ratio to f_max
    in (0, 1) (module docstring); a parameter where `free` is 0 is held at its start (its
    Jacobian column is zero, so the solver never moves it).

    **Arguments:** `starts`, `free` (B, P) physical start values and 0/1 masks in the order of
    `PARAMETER_NAMES`; `actives` (B, E) effect masks; `weights` (B, n) sample weights (0
    leaves a sample out); `data` (`AugmentedData`); `scale` force scale [N]; `max_steps` the
    solver's step limit.

    **Returns:** `(values, cost, jacobian, converged, n_steps)` as numpy arrays: fitted physical
    parameters (B, P), cost 0.5 sum r^2 (B,), the Jacobian of r in the physical parameters
    (B, n_r, P; zero columns for held ones), whether optimistix reported success (B,) and the
    steps it took (B,).
    """
    free = np.asarray(free, float)
    starts, bounds = _ratio_search(np.asarray(starts, float), free, actives)
    fits = fit_least_squares_batch(
        _residual,
        _ratio_starts(starts),
        bounds,
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
    values = np.array([[float(v) for v in _physical(fit.parameters, starts[b], free[b]).values()]
                       for b, fit in enumerate(fits)])
    jacobians = np.stack([result_from_ratios(fit, RATIO_PAIRS).jacobian for fit in fits])
    return (
        np.where(free > 0, values, starts),
        np.array([fit.cost for fit in fits]),
        jacobians * free[:, None, :],
        np.array([fit.converged for fit in fits]),
        np.array([fit.n_steps for fit in fits]),
    )


RATIO_MARGIN = 1e-4
"""How far a ratio's start is kept inside its bounds (0, 1), as `_rounds._inside` keeps the
other starts: a held delta_f's ratio is never used, a free one starts where it was."""


def _ratio_starts(starts: np.ndarray) -> dict:
    """The optimiser's starts (B each) of physical `starts` (B, P): each delta_f as its ratio
    to f_max (`to_ratios`), kept `RATIO_MARGIN` inside (0, 1)."""
    inner = to_ratios({name: starts[:, i] for i, name in enumerate(PARAMETER_NAMES)}, RATIO_PAIRS)
    lo, hi = RATIO_BOUNDS
    ratios = {ratio for _, _, ratio in RATIO_PAIRS}
    return {k: np.clip(v, lo + RATIO_MARGIN, hi - RATIO_MARGIN) if k in ratios else v for k, v in inner.items()}


def _ratio_search(starts: np.ndarray, free: np.ndarray, actives) -> tuple[np.ndarray, dict]:
    """(starts, bounds) in which the fits search: the search ranges in the optimiser's names
    (`ratio_bounds`). Where a member holds delta_f at a known value while Eq. 1 is on and its
    f_max is fitted, f_max is bounded below by that value instead (every member's f_max start
    kept above it), so that f_max - delta_f stays positive there too."""
    bounds = {p.name: (p.lower, p.upper) for p in PARAMETERS}
    starts = starts.copy()
    for delta, f_max, _ in RATIO_PAIRS:
        i, j = PARAMETER_NAMES.index(delta), PARAMETER_NAMES.index(f_max)
        on = np.asarray(actives)[:, EFFECT_NAMES.index(PARAMETER_EFFECT[i])] > 0
        known = on & (free[:, i] == 0) & (free[:, j] > 0)
        if known.any():
            lower, upper = bounds[f_max]
            bounds[f_max] = (max(lower, float(np.max(starts[known, i]))), upper)
            floor = bounds[f_max][0] + RATIO_MARGIN * (upper - bounds[f_max][0])
            starts[:, j] = np.where(free[:, j] > 0, np.maximum(starts[:, j], floor), starts[:, j])
    return starts, ratio_bounds(bounds, RATIO_PAIRS)


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
