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
      (lo, hi), named in `log_scale` (0 < lo, for positive constants spanning decades):
                    x = exp(log lo + (log hi - log lo) sigmoid(u))

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
from collections.abc import Callable, Collection, Mapping
from typing import Any

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx

from ._covariance import SOLVERS, LeastSquaresResult, summarise
from ._marquardt import marquardt_levenberg_marquardt, stopping_levenberg_marquardt
from ._transform import _make_transform, _to_physical, _to_unconstrained, check_bounds

CONVERGENCE_TESTS = ("parameters_and_residuals", "residuals")


def _residuals_only_norm(tree):
    """The solver's norm with the change of the parameters left out of its convergence test:
    they enter it as a tuple `(u,)` (see `_solve_one`), the residuals as an array."""
    if isinstance(tree, tuple):
        return jnp.zeros(())
    return optx.max_norm(tree)


@functools.cache
def _make_solver(solver: str, rtol: float, atol: float, converged_on: str):
    # Cached: a new solver object would change the compiled function's static key.
    if converged_on not in CONVERGENCE_TESTS:
        raise ValueError(f"converged_on: unknown '{converged_on}'; use one of "
                         f"{', '.join(CONVERGENCE_TESTS)}.")
    norm = optx.max_norm if converged_on == "parameters_and_residuals" else _residuals_only_norm
    if solver == "levenberg_marquardt":
        return stopping_levenberg_marquardt(rtol=rtol, atol=atol, norm=norm)
    if solver == "levenberg_marquardt_scaled":
        return marquardt_levenberg_marquardt(rtol=rtol, atol=atol, norm=norm)
    if solver == "gauss_newton":
        return optx.GaussNewton(rtol=rtol, atol=atol, norm=norm)
    raise ValueError(f"solver: unknown '{solver}'; use one of {', '.join(SOLVERS)}.")


@functools.partial(jax.custom_jvp, nondiff_argnums=(0,))
def _dense_jacobian(fn, u, args):
    """`fn(u, args)`, whose derivative in `u` forms the Jacobian once (`jax.jacfwd`) and
    multiplies tangents by it: the solver's linearisation at a point then costs one forward
    pass with p tangents however often the solver applies or factorises it. `args` is data:
    its derivative is taken as zero."""
    return fn(u, args)


@_dense_jacobian.defjvp
def _dense_jacobian_jvp(fn, primals, tangents):
    u, args = primals
    du = tangents[0]

    def with_value(v):
        r = fn(v, args)
        return r, r

    jac, r = jax.jacfwd(with_value, has_aux=True)(u)
    return r, jac @ du


def _solve_one(residual_fn, names, kinds, solver, max_steps, u0, lower, upper, scale, origin, args):
    """One optimistix solve in unconstrained space (pure; vmappable)."""

    def physical(u):
        x = _to_physical(u, kinds, lower, upper, scale, origin)
        return {name: x[i] for i, name in enumerate(names)}

    def residual_fn_u(u, fn_args):
        return residual_fn(physical(u), fn_args)

    def fn(y, fn_args):
        return _dense_jacobian(residual_fn_u, y[0], fn_args)

    solution = optx.least_squares(
        fn,
        solver,
        (u0,),
        args=args,
        options=dict(jac="fwd"),
        max_steps=max_steps,
        throw=False,
    )
    u = solution.value[0]
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

    if isinstance(args_batched, tuple):
        args_axes = tuple(0 if b else None for b in args_batched)
    else:
        args_axes = 0 if args_batched else None
    axes = (0, 0, 0, 0, 0, args_axes)
    return jax.vmap(one, in_axes=axes)(u0, lower, upper, scale, origin, args)


def fit_least_squares(
    residual_fn: Callable[[dict, Any], jnp.ndarray],
    initial: Mapping[str, float],
    bounds: Mapping[str, tuple[float, float]] | None,
    *,
    args=None,
    log_scale: Collection[str] = (),
    max_steps: int = 200,
    rtol: float = 1e-8,
    atol: float = 1e-8,
    solver: str = "levenberg_marquardt",
    converged_on: str = "parameters_and_residuals",
) -> LeastSquaresResult:
    """Minimise `sum(residual_fn(params, args)**2)` over bounded parameters.

    **Arguments:**

    - `residual_fn`: `(params: dict[str, scalar], args) -> 1-D array` of weighted residuals.
      Pass a module-level function (not a fresh lambda) to reuse the compiled solve.
    - `initial`: name -> start value (physical units), strictly inside the bounds.
    - `bounds`: name -> `(lower, upper)`, `-inf`/`inf` allowed; missing names are unbounded.
    - `args`: pytree of data passed to `residual_fn`.
    - `log_scale`: names searched uniformly in log x between finite bounds `0 < lo < hi`.
    - `max_steps`, `rtol`, `atol`: optimistix settings (tolerances act on the unconstrained
      parameters and on the cost).
    - `solver`: `"levenberg_marquardt"` (default; optimistix's, damping `lam I`, ending where
      no damping up to `_marquardt.MAX_DAMPING` lowers the cost),
      `"levenberg_marquardt_scaled"` (Marquardt's damping `lam diag(J^T J)`, `_marquardt.py`:
      for parameters of very different sensitivity) or `"gauss_newton"`.
    - `converged_on`: `"parameters_and_residuals"` (default; optimistix's test: a step changes
      every unconstrained parameter by less than `atol + rtol |u|` and every residual by less
      than `atol + rtol |r|`) or `"residuals"` (the residuals alone: for problems where a
      parameter may run into a bound, where its u keeps drifting while nothing changes).

    **Returns:** a `LeastSquaresResult`; `converged` is `False` when optimistix did not report
    success (the estimate is still returned, with the reason in `message`).
    """
    names, lower, upper = check_bounds(initial, bounds, log_scale)
    x0 = np.array([float(initial[n]) for n in names])
    tr = _make_transform(names, lower, upper, x0, log_scale)
    u0 = _to_unconstrained(x0, tr.kinds, tr.lower, tr.upper, tr.scale, tr.origin)
    out = _solve_single(
        residual_fn, names, tr.kinds, _make_solver(solver, rtol, atol, converged_on), int(max_steps),
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
    args_batched: bool | tuple[bool, ...] = True,
    log_scale: Collection[str] = (),
    max_steps: int = 200,
    rtol: float = 1e-8,
    atol: float = 1e-8,
    solver: str = "levenberg_marquardt",
    converged_on: str = "parameters_and_residuals",
) -> list[LeastSquaresResult]:
    """Solve B independent least-squares problems of one structure in one vmapped call.

    **Arguments:** as `fit_least_squares`, except

    - `initial`: name -> array of B start values (one per problem).
    - `args`: pytree whose arrays have a leading batch axis of size B (`args_batched=True`),
      or one pytree shared by all problems (`args_batched=False`, e.g. several starts of one
      problem); for a tuple `args`, a tuple of such flags, one per element (per-problem
      settings beside data shared by all).

    **Returns:** a list of B `LeastSquaresResult`, each with its own `converged` status.
    """
    names, lower, upper = check_bounds(initial, bounds, log_scale)
    x0 = np.stack([np.atleast_1d(np.asarray(initial[n], dtype=float)) for n in names], axis=-1)
    tr = _make_transform(names, lower, upper, x0, log_scale)
    if isinstance(args_batched, (tuple, list)):
        args_batched = tuple(bool(b) for b in args_batched)
    else:
        args_batched = bool(args_batched)
    u0 = _to_unconstrained(x0, tr.kinds, tr.lower, tr.upper, tr.scale, tr.origin)
    out = _solve_batch(
        residual_fn, names, tr.kinds, _make_solver(solver, rtol, atol, converged_on), int(max_steps),
        args_batched, jnp.asarray(u0), jnp.asarray(tr.lower), jnp.asarray(tr.upper),
        jnp.asarray(tr.scale), jnp.asarray(tr.origin), args,
    )
    x, residual, jacobian, code, n_steps = jax.device_get(out)
    return [
        summarise(names, x[b], residual[b], jacobian[b], code[b], n_steps[b])
        for b in range(x.shape[0])
    ]
