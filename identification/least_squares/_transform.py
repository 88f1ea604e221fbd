"""Bijections between bounded physical parameters and the unconstrained space the optimiser sees."""

import math
from collections.abc import Collection, Mapping
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

Bounds = dict[str, tuple[float, float]]
"""Bounds of each parameter: name -> (lower, upper); `-inf` / `inf` for none."""

_KIND_FREE, _KIND_LOWER, _KIND_UPPER, _KIND_BOTH, _KIND_LOG_BOTH = 0, 1, 2, 3, 4


class _Transform(NamedTuple):
    """Bijections of all parameters: kind (static ints), anchors and scales (arrays)."""

    names: tuple[str, ...]
    kinds: tuple[int, ...]
    lower: np.ndarray
    upper: np.ndarray
    scale: np.ndarray
    origin: np.ndarray


def _softplus(u):
    return jnp.logaddexp(u, 0.0)


def _softplus_inverse(x):
    # log(exp(x) - 1), stable for small and large x > 0.
    return np.where(x > 30.0, x, np.log(np.expm1(np.minimum(x, 30.0))))


SIGMOID_LIMIT = 20.0
"""|u| beyond which a bounded parameter sits at its bound to 2e-9 of its range: the sigmoid is
taken of u clipped to this, so there the residual no longer depends on u, the solver's step
in u is zero and its convergence test (on the change of u) can pass at a bound."""


def _sigmoid(u):
    return jax.nn.sigmoid(jnp.clip(u, -SIGMOID_LIMIT, SIGMOID_LIMIT))


def _to_physical(u, kinds, lower, upper, scale, origin):
    """Unconstrained vector u (..., p) -> physical vector x (..., p)."""
    columns = []
    for i, kind in enumerate(kinds):
        ui = u[..., i]
        if kind == _KIND_FREE:
            x = origin[..., i] + scale[..., i] * ui
        elif kind == _KIND_LOWER:
            x = lower[..., i] + scale[..., i] * _softplus(ui)
        elif kind == _KIND_UPPER:
            x = upper[..., i] - scale[..., i] * _softplus(-ui)
        elif kind == _KIND_BOTH:
            x = lower[..., i] + (upper[..., i] - lower[..., i]) * _sigmoid(ui)
        else:
            log_lo = jnp.log(lower[..., i])
            x = jnp.exp(log_lo + (jnp.log(upper[..., i]) - log_lo) * _sigmoid(ui))
        columns.append(x)
    return jnp.stack(columns, axis=-1)


def _to_unconstrained(x, kinds, lower, upper, scale, origin):
    """Inverse of `_to_physical` (numpy, for starts strictly inside the bounds)."""
    u = np.empty_like(x)
    for i, kind in enumerate(kinds):
        xi = x[..., i]
        if kind == _KIND_FREE:
            u[..., i] = (xi - origin[..., i]) / scale[..., i]
        elif kind == _KIND_LOWER:
            u[..., i] = _softplus_inverse((xi - lower[..., i]) / scale[..., i])
        elif kind == _KIND_UPPER:
            u[..., i] = -_softplus_inverse((upper[..., i] - xi) / scale[..., i])
        else:
            if kind == _KIND_BOTH:
                p = (xi - lower[..., i]) / (upper[..., i] - lower[..., i])
            else:
                log_lo = np.log(lower[..., i])
                p = (np.log(xi) - log_lo) / (np.log(upper[..., i]) - log_lo)
            u[..., i] = np.log(p) - np.log1p(-p)
    return u


def check_bounds(initial: Mapping[str, Any], bounds: Mapping[str, tuple[float, float]] | None,
                 log_scale: Collection[str] = ()):
    """Validate names, bounds and starts; returns (names, lower, upper) as numpy arrays.

    Starts may be arrays (a batch); every element must lie strictly inside its bounds, and a
    name in `log_scale` needs finite bounds with `0 < lower`. Raises `ValueError` naming the
    parameter otherwise.
    """
    unknown_log = sorted(set(log_scale) - set(initial))
    if unknown_log:
        raise ValueError(f"log_scale: {', '.join(unknown_log)} not among the fitted parameters.")
    if not initial:
        raise ValueError("initial: give at least one parameter to fit (name -> start value).")
    bounds = dict(bounds or {})
    names = tuple(initial)
    unknown = sorted(set(bounds) - set(names))
    if unknown:
        raise ValueError(
            f"bounds: {', '.join(unknown)} not among the fitted parameters "
            f"({', '.join(names)}); remove them or add a start value."
        )
    lower, upper = [], []
    for name in names:
        pair = bounds.get(name, (-math.inf, math.inf))
        try:
            lo, hi = (float(pair[0]), float(pair[1]))
        except (TypeError, ValueError, IndexError):
            raise ValueError(
                f"bounds['{name}']: must be a pair (lower, upper) of numbers, got {pair!r}."
            ) from None
        if math.isnan(lo) or math.isnan(hi) or not lo < hi:
            raise ValueError(f"bounds['{name}']: need lower < upper, got ({lo}, {hi}).")
        start = np.asarray(initial[name], dtype=float)
        if not np.all(np.isfinite(start)):
            raise ValueError(f"initial['{name}']: start value must be finite, got {start}.")
        if name in log_scale and not (0.0 < lo and math.isfinite(hi)):
            raise ValueError(
                f"bounds['{name}']: a log-scaled parameter needs 0 < lower and a finite upper "
                f"bound, got ({lo}, {hi}).")
        if not (np.all(start > lo) and np.all(start < hi)):
            raise ValueError(
                f"{name}: start value {start.tolist()} is not strictly inside its bounds "
                f"({lo}, {hi}); move the start or widen the bounds."
            )
        lower.append(lo)
        upper.append(hi)
    return names, np.array(lower), np.array(upper)


def _make_transform(names, lower, upper, x0, log_scale: Collection[str] = ()) -> _Transform:
    """Bijection of each parameter, scaled by the distance of the start from its bound
    (bounded ones: the sigmoid of the module docstring, in log x for names in `log_scale`)."""
    kinds, scale, origin = [], np.ones_like(x0), np.array(x0, dtype=float)
    for i, name in enumerate(names):
        lo, hi = np.isfinite(lower[i]), np.isfinite(upper[i])
        xi = x0[..., i]
        if name in log_scale:
            kinds.append(_KIND_LOG_BOTH)
            s = np.ones_like(xi)
        elif lo and hi:
            kinds.append(_KIND_BOTH)
            s = np.ones_like(xi)
        elif lo:
            kinds.append(_KIND_LOWER)
            s = xi - lower[i]
        elif hi:
            kinds.append(_KIND_UPPER)
            s = upper[i] - xi
        else:
            kinds.append(_KIND_FREE)
            s = np.where(np.abs(xi) > 0, np.abs(xi), 1.0)
        scale[..., i] = s
    shape = x0.shape
    return _Transform(
        names=tuple(names),
        kinds=tuple(kinds),
        lower=np.broadcast_to(np.where(np.isfinite(lower), lower, 0.0), shape).copy(),
        upper=np.broadcast_to(np.where(np.isfinite(upper), upper, 0.0), shape).copy(),
        scale=scale,
        origin=origin,
    )
