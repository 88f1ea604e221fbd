"""Bijections between bounded physical parameters and the unconstrained space the optimiser sees."""

import math
from collections.abc import Mapping
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

Bounds = dict[str, tuple[float, float]]
"""Bounds of each parameter: name -> (lower, upper); `-inf` / `inf` for none."""

_KIND_FREE, _KIND_LOWER, _KIND_UPPER, _KIND_BOTH = 0, 1, 2, 3


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
        else:
            x = lower[..., i] + (upper[..., i] - lower[..., i]) * jax.nn.sigmoid(ui)
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
            p = (xi - lower[..., i]) / (upper[..., i] - lower[..., i])
            u[..., i] = np.log(p) - np.log1p(-p)
    return u


def check_bounds(initial: Mapping[str, Any], bounds: Mapping[str, tuple[float, float]] | None):
    """Validate names, bounds and starts; returns (names, lower, upper) as numpy arrays.

    Starts may be arrays (a batch); every element must lie strictly inside its bounds.
    Raises `ValueError` naming the parameter otherwise.
    """
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
        if not (np.all(start > lo) and np.all(start < hi)):
            raise ValueError(
                f"{name}: start value {start.tolist()} is not strictly inside its bounds "
                f"({lo}, {hi}); move the start or widen the bounds."
            )
        lower.append(lo)
        upper.append(hi)
    return names, np.array(lower), np.array(upper)


def _make_transform(names, lower, upper, x0) -> _Transform:
    """Bijection of each parameter, scaled by the distance of the start from its bound."""
    kinds, scale, origin = [], np.ones_like(x0), np.array(x0, dtype=float)
    for i in range(len(names)):
        lo, hi = np.isfinite(lower[i]), np.isfinite(upper[i])
        xi = x0[..., i]
        if lo and hi:
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
