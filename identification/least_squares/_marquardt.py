"""Levenberg-Marquardt with Marquardt's scaled damping, built from optimistix's parts, and
optimistix's own Levenberg-Marquardt with the same end at a minimum of the arithmetic.

optimistix's `LevenbergMarquardt` damps with `lam I`. Marquardt (1963) damps with
`lam diag(J^T J)`, re-scaled at every step, which makes the step independent of how each
parameter is scaled: a parameter whose influence fades (a sigmoid bijection nearing its
bound) still takes steps of order one in u instead of creeping. Here that step is a descent
of optimistix's Gauss-Newton framework, kept in step by its classical trust region
(lam = `INITIAL_DAMPING` / step size; Moré 1978):

    (J^T J + lam diag(J^T J)) du = -J^T r.

Both solvers end at the first of two tests, on an accepted step:

- optimistix's (Cauchy): the step changed every unknown and every residual by less than
  `atol + rtol |.|`. It suits a model that can fit the data to rounding (the residuals go
  to zero and Gauss-Newton converges quadratically), but not a misfit that stays: there
  Gauss-Newton converges linearly, slowly where the residuals are large, and an unknown
  pushed against a bound keeps moving in u (its sigmoid flattens) while nothing changes;
- the relative offset of Bates & Watts (1981), for a misfit that stays: the decrease of the
  cost the linearised model still promises, against the scatter of the residuals about it,

      offset = s sqrt( |P r|^2 / p  /  ((|r|^2 - |P r|^2) / (n - p)) )  <  `RELATIVE_OFFSET`,

  with `P r` the projection of the residuals on the columns of `J` (the Gauss-Newton step's
  decrease) and `s = min(1, MAX_STEP / max |du|)` the fraction of the Gauss-Newton step `du`
  one step may take (`MAX_STEP`), and the same with the unknowns whose step is capped held
  (`relative_offset`). In words: the next step could move the estimate by less than
  `RELATIVE_OFFSET` standard errors, to the minimum or, for an unknown at a bound, to the
  bound (a sigmoid's u nearing its bound reaches it within MAX_STEP). The columns of `J` are
  scaled to unit norm, so the test does not depend on how the unknowns are scaled. On a fit
  of the model's own noise-free data `|r|^2 - |P r|^2` is rounding, so this test waits for
  the offset to reach rounding too, and the Cauchy test ends the solve.

References: Marquardt, "An algorithm for least-squares estimation of nonlinear parameters",
J. SIAM 11(2), 1963; Moré, "The Levenberg-Marquardt algorithm: implementation and theory",
Lecture Notes in Mathematics 630, 1978; Bates & Watts, "A relative offset orthogonality
convergence criterion for nonlinear least squares", Technometrics 23(2), 1981.
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

RELATIVE_OFFSET = 1e-4
"""A solve ends where the Gauss-Newton step (capped at `MAX_STEP`) would move the estimate by
less than this many standard errors (module docstring; Bates & Watts 1981 suggest 1e-3)."""

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


def _offset(residual, jacobian):
    """Bates & Watts' relative offset of `residual` on the non-zero columns of `jacobian`, and
    the Gauss-Newton step in the unknowns."""
    norms = jnp.linalg.norm(jacobian, axis=0)
    live = norms > 0
    safe = jnp.where(live, norms, 1.0)
    scaled = jnp.where(live, jacobian / safe, 0.0)
    step_scaled, *_ = jnp.linalg.lstsq(scaled, -residual)
    step_scaled = jnp.where(live, step_scaled, 0.0)
    projected = jnp.sum((scaled @ step_scaled) ** 2)
    p = jnp.maximum(jnp.sum(live), 1)
    scatter = jnp.maximum(jnp.sum(residual**2) - projected, 0.0) / jnp.maximum(residual.size - p, 1)
    promised = projected / p
    offset = jnp.where(scatter > 0, jnp.sqrt(promised / jnp.where(scatter > 0, scatter, 1.0)),
                       jnp.where(promised > 0, jnp.inf, 0.0))
    return offset, step_scaled / safe


def relative_offset(residual: jax.Array, jacobian: jax.Array) -> jax.Array:
    """The relative offset of Bates & Watts (1981) of the Gauss-Newton step capped at
    `MAX_STEP` (module docstring): at residuals `r` (n,) and Jacobian `J` (n, p) in the
    unknowns u, how many standard errors the next step could still move the estimate.

    The unknowns whose Gauss-Newton step exceeds `MAX_STEP` (at a bound, or running to one)
    move by at most the capped step; the others are tested as by Bates & Watts with those held,
    so that an unknown pinned at a bound cannot hide that the rest are still far from their
    minimum. Columns of `J` that are zero (unknowns held fixed) do not count in p. Infinite
    when the linearised model fits the residuals exactly (nothing is left to measure a scatter
    by)."""
    offset, du = _offset(residual, jacobian)
    largest = jnp.max(jnp.abs(du))
    s = jnp.where(largest > MAX_STEP, MAX_STEP / jnp.where(largest > 0, largest, 1.0), 1.0)
    pinned = jnp.abs(du) > MAX_STEP
    rest, _ = _offset(residual, jnp.where(pinned, 0.0, jacobian))
    return jnp.maximum(s * offset, rest)


class TrustRegionGaussNewton(optx.AbstractGaussNewton):
    """optimistix's Gauss-Newton framework with a given descent and trust region, for unknowns
    given as a one-array tuple `(u,)` (`marquardt_levenberg_marquardt`,
    `stopping_levenberg_marquardt`), that also ends at a small relative offset.

    **Arguments:** `rtol`, `atol` and `norm` of optimistix's convergence test, the `descent`
    and the `search`; `offset`: the relative offset below which an accepted step ends the
    solve (module docstring; 0 leaves optimistix's test alone).
    """

    rtol: float
    atol: float
    norm: Callable
    descent: optx.AbstractDescent
    search: optx.AbstractSearch
    verbose: Callable
    offset: float

    def __init__(self, rtol: float, atol: float, norm: Callable, descent, search,
                 offset: float = RELATIVE_OFFSET):
        self.rtol = rtol
        self.atol = atol
        self.norm = norm
        self.descent = descent
        self.search = search
        self.verbose = _quiet
        self.offset = offset

    def step(self, fn, y, args, options, state, tags):
        y, new_state, aux = super().step(fn, y, args, options, state, tags)
        accepted = new_state.num_steps_since_acceptance == 0
        info = new_state.f_info
        near = relative_offset(info.residual, info.jac.as_matrix()) < self.offset
        terminate = new_state.terminate | (accepted & near & ~state.first_step)
        return y, eqx.tree_at(lambda s: s.terminate, new_state, terminate), aux


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
