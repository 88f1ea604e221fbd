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
from collections.abc import Callable, Mapping
from typing import Any

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx

from ._covariance import SOLVERS, LeastSquaresResult, summarise
from ._transform import _make_transform, _to_physical, _to_unconstrained, check_bounds


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
