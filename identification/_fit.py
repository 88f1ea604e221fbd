"""Generic bounded nonlinear least squares with optimistix, and its uncertainty.

Contract (other parts of `identification` build on it):

- `fit_least_squares(residual_fn, initial, bounds, *, args=None, max_steps=200, rtol=1e-8,
  atol=1e-8, solver="levenberg_marquardt") -> LeastSquaresResult`
- `residual_fn(params, args)` takes a dict name -> JAX scalar (physical values) and returns a
  1-D JAX array of residuals, already weighted or scaled by the caller. It must be pure and
  differentiable in forward mode (it is traced once and compiled).
- `bounds` maps a name to `(lower, upper)`; either may be `-inf` / `inf`; a name left out is
  unbounded. The optimiser works on unconstrained values `u` mapped to the physical value `x`
  by a bijection, so `residual_fn` never sees a value outside its bounds:

      (-inf, inf):  x = x0 + s u                       (identity, scaled)
      (lo, inf):    x = lo + s softplus(u)
      (-inf, hi):   x = hi - s softplus(u)
      (lo, hi):     x = lo + (hi - lo) sigmoid(u)

  with the scale `s = |x0 - bound|` (or `|x0|`, or 1) taken from the start `x0`, so every `u`
  is of order one. A start on or outside its bounds raises `ValueError` naming the parameter.
- The solver is optimistix `LevenbergMarquardt` (or `GaussNewton`) with forward-mode
  Jacobians (`options=dict(jac="fwd")`) and `throw=False`; its result code becomes
  `converged` and `message`. An unconverged solve is returned with `converged=False`, never
  presented as converged.
- Uncertainty: with `J` the Jacobian of the residuals in the *physical* parameters at the
  optimum, `n` residuals and `p` parameters, the covariance is
  `sigma^2 (J^T J)^-1` with `sigma^2 = SSR / (n - p)` (the usual asymptotic estimate for
  independent errors of equal variance; Seber & Wild, "Nonlinear Regression", 1989, Ch. 2).
  `std_errors` are the square roots of its diagonal, `correlation` its normalised form. When
  `J^T J` is singular (a parameter has no influence on the residuals) the affected standard
  errors are `inf`, the correlations `nan`, and `message` says which parameters.

`fit_least_squares_batch` solves many independent problems of the same structure in one
vmapped, compiled call (e.g. one record per bearing, or several starts of one problem).
"""

import functools
import math
from collections.abc import Callable, Mapping
from typing import Any, NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx

Bounds = dict[str, tuple[float, float]]
"""Bounds of each parameter: name -> (lower, upper); `-inf` / `inf` for none."""

SOLVERS = ("levenberg_marquardt", "gauss_newton")

_KIND_FREE, _KIND_LOWER, _KIND_UPPER, _KIND_BOTH = 0, 1, 2, 3


class LeastSquaresResult(NamedTuple):
    """Outcome of `fit_least_squares` (numpy / Python values, physical parameters).

    - `parameters`: name -> estimate.
    - `std_errors`: name -> standard error (`inf` when not identifiable from the residuals).
    - `correlation`: (p, p) correlation matrix in the order of `names`.
    - `names`: parameter names, in the order of `correlation` and `jacobian` columns.
    - `residual`: residual vector at the optimum.
    - `cost`: half the sum of squared residuals, `0.5 * sum(residual**2)`.
    - `converged`: whether optimistix reported success.
    - `message`: the solver's status in words (and notes on singular Jacobians).
    - `n_steps`: solver steps taken.
    - `jacobian`: (n, p) Jacobian of the residuals in the physical parameters.
    """

    parameters: dict[str, float]
    std_errors: dict[str, float]
    correlation: np.ndarray
    names: tuple[str, ...]
    residual: np.ndarray
    cost: float
    converged: bool
    message: str
    n_steps: int
    jacobian: np.ndarray


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


@functools.cache
def _make_solver(solver: str, rtol: float, atol: float):
    # Cached: a new solver object would change the compiled function's static key.
    if solver == "levenberg_marquardt":
        return optx.LevenbergMarquardt(rtol=rtol, atol=atol)
    if solver == "gauss_newton":
        return optx.GaussNewton(rtol=rtol, atol=atol)
    raise ValueError(f"solver: unknown '{solver}'; use one of {', '.join(SOLVERS)}.")


def _solve_one(residual_fn, names, kinds, solver, max_steps, u0, lower, upper, scale, origin, args):
    """One optimistix solve in unconstrained space (pure; vmappable)."""

    def physical(u):
        x = _to_physical(u, kinds, lower, upper, scale, origin)
        return {name: x[i] for i, name in enumerate(names)}

    def fn(u, fn_args):
        return residual_fn(physical(u), fn_args)

    solution = optx.least_squares(
        fn,
        solver,
        u0,
        args=args,
        options=dict(jac="fwd"),
        max_steps=max_steps,
        throw=False,
    )
    u = solution.value
    x = _to_physical(u, kinds, lower, upper, scale, origin)
    params = {name: x[i] for i, name in enumerate(names)}
    residual = residual_fn(params, args)
    jacobian = jax.jacfwd(lambda xx: residual_fn({n: xx[i] for i, n in enumerate(names)}, args))(x)
    return x, residual, jacobian, solution.result._value, solution.stats["num_steps"]


@eqx.filter_jit
def _solve_single(residual_fn, names, kinds, solver, max_steps, u0, lower, upper, scale, origin,
                  args):
    return _solve_one(residual_fn, names, kinds, solver, max_steps, u0, lower, upper, scale,
                      origin, args)


@eqx.filter_jit
def _solve_batch(residual_fn, names, kinds, solver, max_steps, args_batched, u0, lower, upper,
                 scale, origin, args):
    def one(u0_, lower_, upper_, scale_, origin_, args_):
        return _solve_one(residual_fn, names, kinds, solver, max_steps, u0_, lower_, upper_,
                          scale_, origin_, args_)

    axes = (0, 0, 0, 0, 0, 0 if args_batched else None)
    return jax.vmap(one, in_axes=axes)(u0, lower, upper, scale, origin, args)


def covariance_from_jacobian(jacobian, residual) -> tuple[np.ndarray, list[str]]:
    """Asymptotic covariance `sigma^2 (J^T J)^-1`, `sigma^2 = SSR / (n - p)`.

    **Arguments:** `jacobian` (n, p) of the residuals in the physical parameters at the
    optimum; `residual` (n,) there.

    **Returns:** `(covariance (p, p), notes)`. Columns of `J` that carry no information (zero,
    or linearly dependent on the others) give `inf` variances and a note naming the index.
    """
    jac = np.asarray(jacobian, dtype=float)
    res = np.asarray(residual, dtype=float)
    n, p = jac.shape
    notes = []
    dof = n - p
    if dof <= 0:
        notes.append(f"only {n} residuals for {p} parameters: no standard errors")
        return np.full((p, p), np.inf), notes
    sigma2 = float(res @ res) / dof
    # Scale columns so that the conditioning test is independent of parameter units.
    norms = np.linalg.norm(jac, axis=0)
    safe = np.where(norms > 0, norms, 1.0)
    scaled = jac / safe
    u, s, vt = np.linalg.svd(scaled, full_matrices=False)
    tol = max(n, p) * np.finfo(float).eps * (s[0] if s.size and s[0] > 0 else 1.0) * 1e3
    good = s > tol
    inv = (vt[good].T / s[good] ** 2) @ vt[good]
    cov = sigma2 * inv / np.outer(safe, safe)
    null = vt[~good]
    involved = np.any(np.abs(null) > 1e-3, axis=0) if null.size else np.zeros(p, dtype=bool)
    bad = np.flatnonzero((norms == 0) | involved)
    for i in bad:
        cov[i, :] = np.inf
        cov[:, i] = np.inf
        notes.append(f"parameter {i} not identifiable (singular Jacobian)")
    return cov, notes


def _correlation(cov):
    d = np.sqrt(np.diag(cov))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(d, d)
    corr[~np.isfinite(corr)] = np.nan
    np.fill_diagonal(corr, np.where(np.isfinite(d), 1.0, np.nan))
    return corr


def summarise(names, x, residual, jacobian, result_code, n_steps) -> LeastSquaresResult:
    """Build a `LeastSquaresResult` from the raw outputs of one solve (numpy)."""
    x = np.asarray(x, dtype=float)
    residual = np.asarray(residual, dtype=float)
    jacobian = np.asarray(jacobian, dtype=float).reshape(residual.size, len(names))
    code = int(result_code)
    converged = code == 0
    message = "converged" if converged else _result_message(code)
    if not np.all(np.isfinite(residual)):
        converged = False
        message = "non-finite residuals at the final parameters"
    cov, notes = covariance_from_jacobian(jacobian, residual)
    notes = [note.replace(f"parameter {i} ", f"{names[i]} ") for note in notes
             for i in range(len(names)) if note.startswith(f"parameter {i} ")] + [
        note for note in notes if not note.startswith("parameter ")]
    if notes:
        message = message + "; " + "; ".join(notes)
    std = np.sqrt(np.abs(np.diag(cov)))
    return LeastSquaresResult(
        parameters={name: float(x[i]) for i, name in enumerate(names)},
        std_errors={name: float(std[i]) for i, name in enumerate(names)},
        correlation=_correlation(cov),
        names=tuple(names),
        residual=residual,
        cost=float(0.5 * residual @ residual),
        converged=converged,
        message=message,
        n_steps=int(n_steps),
        jacobian=jacobian,
    )


def _result_message(code: int) -> str:
    """The optimistix status message of a result code."""
    names = list(optx.RESULTS._name_to_item)
    messages = optx.RESULTS._index_to_message
    if 0 <= code < len(messages):
        text = f"{names[code]}: {messages[code].splitlines()[0]}"
    else:
        text = f"optimistix result code {code}"
    return "not converged (" + text + ")"


def fit_least_squares(
    residual_fn: Callable[[dict, Any], jnp.ndarray],
    initial: Mapping[str, float],
    bounds: Mapping[str, tuple[float, float]] | None,
    *,
    args=None,
    max_steps: int = 200,
    rtol: float = 1e-8,
    atol: float = 1e-8,
    solver: str = "levenberg_marquardt",
) -> LeastSquaresResult:
    """Minimise `sum(residual_fn(params, args)**2)` over bounded parameters.

    **Arguments:**

    - `residual_fn`: `(params: dict[str, scalar], args) -> 1-D array` of weighted residuals.
      Pass a module-level function (not a fresh lambda) to reuse the compiled solve.
    - `initial`: name -> start value (physical units), strictly inside the bounds.
    - `bounds`: name -> `(lower, upper)`, `-inf`/`inf` allowed; missing names are unbounded.
    - `args`: pytree of data passed to `residual_fn`.
    - `max_steps`, `rtol`, `atol`: optimistix settings (tolerances act on the unconstrained
      parameters and on the cost).
    - `solver`: `"levenberg_marquardt"` (default) or `"gauss_newton"`.

    **Returns:** a `LeastSquaresResult`; `converged` is `False` when optimistix did not report
    success (the estimate is still returned, with the reason in `message`).
    """
    names, lower, upper = check_bounds(initial, bounds)
    x0 = np.array([float(initial[n]) for n in names])
    tr = _make_transform(names, lower, upper, x0)
    u0 = _to_unconstrained(x0, tr.kinds, tr.lower, tr.upper, tr.scale, tr.origin)
    out = _solve_single(
        residual_fn, names, tr.kinds, _make_solver(solver, rtol, atol), int(max_steps),
        jnp.asarray(u0), jnp.asarray(tr.lower), jnp.asarray(tr.upper), jnp.asarray(tr.scale),
        jnp.asarray(tr.origin), args,
    )
    x, residual, jacobian, code, n_steps = jax.device_get(out)
    return summarise(names, x, residual, jacobian, code, n_steps)


def fit_least_squares_batch(
    residual_fn: Callable[[dict, Any], jnp.ndarray],
    initial: Mapping[str, Any],
    bounds: Mapping[str, tuple[float, float]] | None,
    *,
    args=None,
    args_batched: bool = True,
    max_steps: int = 200,
    rtol: float = 1e-8,
    atol: float = 1e-8,
    solver: str = "levenberg_marquardt",
) -> list[LeastSquaresResult]:
    """Solve B independent least-squares problems of one structure in one vmapped call.

    **Arguments:** as `fit_least_squares`, except

    - `initial`: name -> array of B start values (one per problem).
    - `args`: pytree whose arrays have a leading batch axis of size B (`args_batched=True`),
      or one pytree shared by all problems (`args_batched=False`, e.g. several starts of one
      problem).

    **Returns:** a list of B `LeastSquaresResult`, each with its own `converged` status.
    """
    names, lower, upper = check_bounds(initial, bounds)
    x0 = np.stack([np.atleast_1d(np.asarray(initial[n], dtype=float)) for n in names], axis=-1)
    tr = _make_transform(names, lower, upper, x0)
    u0 = _to_unconstrained(x0, tr.kinds, tr.lower, tr.upper, tr.scale, tr.origin)
    out = _solve_batch(
        residual_fn, names, tr.kinds, _make_solver(solver, rtol, atol), int(max_steps),
        bool(args_batched), jnp.asarray(u0), jnp.asarray(tr.lower), jnp.asarray(tr.upper),
        jnp.asarray(tr.scale), jnp.asarray(tr.origin), args,
    )
    x, residual, jacobian, code, n_steps = jax.device_get(out)
    return [
        summarise(names, x[b], residual[b], jacobian[b], code[b], n_steps[b])
        for b in range(x.shape[0])
    ]
