"""Levenberg-Marquardt with Marquardt's scaled damping, built from optimistix's parts, and
optimistix's own Levenberg-Marquardt with the same end at a minimum of the arithmetic.

optimistix's `LevenbergMarquardt` damps with `lam I`. Marquardt (1963) damps with
`lam diag(J^T J)`, re-scaled at every step, which makes the step independent of how each
parameter is scaled: a parameter whose influence fades (a sigmoid bijection nearing its
bound) still takes steps of order one in u instead of creeping. Here that step is a descent
of optimistix's Gauss-Newton framework, kept in step by its classical trust region
(lam = `INITIAL_DAMPING` / step size; Moré 1978):

    (J^T J + lam diag(J^T J)) du = -J^T r.

References: Marquardt, "An algorithm for least-squares estimation of nonlinear parameters",
J. SIAM 11(2), 1963; Moré, "The Levenberg-Marquardt algorithm: implementation and theory",
Lecture Notes in Mathematics 630, 1978.
"""

from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import lineax as lx
import optimistix as optx

INITIAL_DAMPING = 1e-2
"""lam at the start (the trust region's step size starts at 1, and lam = this / step size)."""

MAX_DAMPING = 1e8
"""lam (relative to diag(J^T J); in `stopping_levenberg_marquardt` to its largest entry) beyond
which the step is zero: the trust region has shrunk through every damping up to this without
lowering the cost, a minimum to the precision of the arithmetic. The trust region accepts the
zero step (`_ZeroStepTrustRegion`) and optimistix's convergence test (no change) ends the solve
there. Without it a solve that lands on such a point refuses every later step and runs to
`max_steps` (optimistix tests for convergence on accepted steps only)."""

MAX_STEP = 4.0
"""Largest change of one unknown in a step: an unconstrained u of order one moves by at most
this, so that one step cannot throw a bounded parameter deep into its sigmoid's flat tail."""

ACCEPT_FRACTION = 1e-4
"""A step is taken when the cost falls by at least this fraction of the decrease the linear
model predicts."""


class _MarquardtState(eqx.Module):
    jacobian: jax.Array
    residual: jax.Array


class _ZeroStepTrustRegion(optx.ClassicalTrustRegion):
    """optimistix's classical trust region that also accepts a step that moves nothing (the
    zero step of `MAX_DAMPING`): evaluated again at the same point, the residuals can differ in
    their last bit (seen: the cost 1 ulp higher), which would refuse it for ever."""

    def step(self, first_step, y, y_eval, f_info, f_eval_info, state):
        step_size, accept, result, state = super().step(first_step, y, y_eval, f_info, f_eval_info, state)
        unmoved = jnp.all(jnp.stack([jnp.all(a == b) for a, b in
                                     zip(jax.tree_util.tree_leaves(y_eval), jax.tree_util.tree_leaves(y))]))
        return step_size, accept | unmoved, result, state


class MarquardtDescent(optx.AbstractDescent):
    """The damped Gauss-Newton step with Marquardt's scaling `diag(J^T J)` (module docstring).

    The unknowns are a one-array tuple `(u,)` of p values, the residuals a 1-D array; a column
    of `J` that is zero (a parameter held fixed) takes no step.
    """

    def init(self, y, f_info_struct):
        p = sum(leaf.size for leaf in jax.tree_util.tree_leaves(y))
        n = f_info_struct.residual.size
        dtype = f_info_struct.residual.dtype
        return _MarquardtState(jnp.zeros((n, p), dtype), jnp.zeros((n,), dtype))

    def query(self, y, f_info, state):
        del y, state
        return _MarquardtState(f_info.jac.as_matrix(), f_info.residual)

    def step(self, step_size, state):
        jac, r = state.jacobian, state.residual
        hess = jac.T @ jac
        diag = jnp.diag(hess)
        scale = jnp.where(diag > 0, diag, 1.0)
        safe = jnp.where(step_size > 0, step_size, 1.0)
        lam = jnp.where(step_size > 0, INITIAL_DAMPING / safe, jnp.finfo(r.dtype).max)
        du = -jnp.linalg.solve(hess + jnp.diag(lam * scale), jac.T @ r)
        ok = jnp.all(jnp.isfinite(du))
        du = jnp.where(ok & (lam < MAX_DAMPING), jnp.clip(du, -MAX_STEP, MAX_STEP), 0.0)
        return (du,), optx.RESULTS.where(ok, optx.RESULTS.successful,
                                         optx.RESULTS.singular)


class TrustRegionGaussNewton(optx.AbstractGaussNewton):
    """optimistix's Gauss-Newton framework with a given descent and trust region, for unknowns
    given as a one-array tuple `(u,)` (`marquardt_levenberg_marquardt`,
    `stopping_levenberg_marquardt`).

    **Arguments:** `rtol`, `atol` and `norm` of optimistix's convergence test, the `descent`
    and the `search`.
    """

    rtol: float
    atol: float
    norm: Callable
    descent: optx.AbstractDescent
    search: optx.AbstractSearch
    verbose: Callable

    def __init__(self, rtol: float, atol: float, norm: Callable, descent, search):
        self.rtol = rtol
        self.atol = atol
        self.norm = norm
        self.descent = descent
        self.search = search
        self.verbose = _quiet


def marquardt_levenberg_marquardt(rtol: float, atol: float, norm: Callable = optx.max_norm):
    """Levenberg-Marquardt with Marquardt's scaled damping (module docstring)."""
    # Any decrease of the cost is accepted and widens the region (lam / 3); a step that
    # does not decrease it is refused and narrows it (lam x 4), as in Marquardt (1963).
    search = _ZeroStepTrustRegion(high_cutoff=ACCEPT_FRACTION, low_cutoff=ACCEPT_FRACTION,
                                  high_constant=3.0, low_constant=0.25)
    return TrustRegionGaussNewton(rtol, atol, norm, MarquardtDescent(), search)


class _StoppingDampedNewtonDescent(optx.DampedNewtonDescent):
    """optimistix's damped Newton step (lam = 1 / step size, damping `lam I`), zero once lam
    exceeds `MAX_DAMPING` times the largest diagonal entry of J^T J."""

    def step(self, step_size, state):
        y_diff, result = super().step(step_size, state)
        jac = state.f_info.jac.as_matrix()
        curvature = jnp.max(jnp.sum(jac**2, axis=0))
        stop = step_size * MAX_DAMPING * curvature < 1
        return jax.tree_util.tree_map(lambda d: jnp.where(stop, jnp.zeros_like(d), d), y_diff), result


def stopping_levenberg_marquardt(rtol: float, atol: float, norm: Callable = optx.max_norm):
    """optimistix's `LevenbergMarquardt` (damping `lam I`, QR, its classical trust region) that
    ends where no damping up to `MAX_DAMPING` lowers the cost (`_StoppingDampedNewtonDescent`);
    every other step is optimistix's."""
    return TrustRegionGaussNewton(rtol, atol, norm, _StoppingDampedNewtonDescent(linear_solver=lx.QR()),
                                  _ZeroStepTrustRegion())


def _quiet(**kwargs):
    del kwargs
