"""The least-squares solvers end at the minimum of a model that cannot fit its data.

optimistix's convergence test asks every unknown and every residual to change by less than
`atol + rtol |.|` in a step. Where the residuals stay large at the minimum, Gauss-Newton
converges only linearly (Dennis & Schnabel, "Numerical Methods for Unconstrained Optimization
and Nonlinear Equations", 1983, Sec. 10.2), and an unknown pushed against a bound keeps moving
in its unconstrained coordinate: that test is not met within the step budget. The relative
offset of Bates & Watts (1981) ends both at the minimum (`_marquardt.relative_offset`).
"""

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import optimistix as optx
import pytest

from identification.least_squares import fit_least_squares
from identification.least_squares._marquardt import (
    MAX_STEP,
    RELATIVE_OFFSET,
    marquardt_levenberg_marquardt,
    relative_offset,
    stopping_levenberg_marquardt,
)

CURVATURE = 0.95
"""lambda of Dennis & Schnabel's example: Gauss-Newton converges with the linear rate lambda."""


def _large_residual(x, curvature):
    """r(x) = (x + 1, lambda x^2 + x - 1): the minimum is x = 0 (gradient 2 (1 - lambda) x + O(x^2),
    second derivative 2 (1 - lambda) > 0) with residuals (1, -1), cost 1, for 0 < lambda < 1."""
    return jnp.stack([x + 1.0, curvature * x**2 + x - 1.0])


def _solve(make, offset=None, max_steps=200):
    solver = make(1e-8, 1e-8)
    if offset is not None:
        solver = eqx.tree_at(lambda s: s.offset, solver, offset)
    solution = optx.least_squares(lambda y, lam: _large_residual(y[0][0], lam), solver,
                                  (jnp.array([1.0]),), args=CURVATURE, max_steps=max_steps,
                                  throw=False)
    return solution.result == optx.RESULTS.successful, int(solution.stats["num_steps"]), float(solution.value[0][0])


@pytest.mark.parametrize("make", [stopping_levenberg_marquardt, marquardt_levenberg_marquardt])
def test_a_large_residual_minimum_ends_converged_where_optimistix_s_test_runs_out(make):
    # optimistix's test alone (offset 0): linear convergence at the rate 0.95 needs about
    # log(1e-8) / log(0.95) = 360 steps; the budget of 200 runs out.
    converged, steps, _ = _solve(make, offset=0.0)
    assert not converged and steps == 200
    converged, steps, x = _solve(make)
    assert converged and steps < 100
    # At the end the Gauss-Newton step would move x by at most RELATIVE_OFFSET standard errors
    # (sigma / |J| = 1 at x = 0); the Newton step is 1 / (1 - lambda) times the Gauss-Newton one.
    bound = RELATIVE_OFFSET / (1.0 - CURVATURE) * 2.0
    assert abs(x) < bound
    # the cost, 1 + (1 - lambda) x^2 + O(x^3), is the minimum's to a fraction of the scatter
    cost = 0.5 * float(jnp.sum(_large_residual(x, CURVATURE) ** 2))
    assert 1.0 <= cost < 1.0 + (1.0 - CURVATURE) * bound**2


def _beyond_bound(params, args):
    """Residuals x - 2 and x - 2.5: the minimum over 0 < x < 1 is the bound x = 1, cost 1.625."""
    del args
    return jnp.stack([params["x"] - 2.0, params["x"] - 2.5])


def test_a_minimum_on_a_bound_ends_converged():
    # The sigmoid's u runs to infinity while x nears 1, and optimistix's test on the unknowns
    # never passes. Marquardt's scaled damping keeps the steps in u of order one (optimistix's
    # damping lam I creeps: x = 0.99996 after 200 steps); the offset, with the step capped at
    # MAX_STEP in u, ends the solve once x is at the bound to a fraction of its standard error.
    result = fit_least_squares(_beyond_bound, {"x": 0.5}, {"x": (0.0, 1.0)},
                               solver="levenberg_marquardt_scaled")
    assert result.converged, result.message
    assert result.n_steps < 200
    # at the bound to a fraction RELATIVE_OFFSET of a standard error
    assert 0.0 < 1.0 - result.parameters["x"] < RELATIVE_OFFSET * result.std_errors["x"]
    assert 0.0 < result.cost - 1.625 < 2.5 * RELATIVE_OFFSET * result.std_errors["x"]


def _bates_watts(jac, r):
    """|Q1^T r| / sqrt(p) over |Q2^T r| / sqrt(n - p), by a QR decomposition of J."""
    n, p = jac.shape
    q, _ = np.linalg.qr(jac, mode="complete")
    return np.linalg.norm(q[:, :p].T @ r) / np.sqrt(p) / (np.linalg.norm(q[:, p:].T @ r) / np.sqrt(n - p))


def test_the_relative_offset_is_bates_and_watts_with_the_step_capped():
    rng = np.random.default_rng(3)
    n = 40
    jac = rng.standard_normal((n, 3)) * np.array([1.0, 1e-3, 50.0])
    r = rng.standard_normal(n)
    step = np.linalg.lstsq(jac, -r, rcond=None)[0]
    # the weak column asks for a long step: capped, and the other two tested with it held
    pinned = np.abs(step) > MAX_STEP
    assert pinned.tolist() == [False, True, False]
    s = MAX_STEP / np.max(np.abs(step))
    expected = max(s * _bates_watts(jac, r), _bates_watts(jac[:, ~pinned], r))
    assert float(relative_offset(jnp.asarray(r), jnp.asarray(jac))) == pytest.approx(expected, rel=1e-9)
    # a short step is Bates & Watts' offset itself; a zero column (an unknown held) does not count
    small = jac * np.array([1.0, 1e4, 1.0])
    assert np.max(np.abs(np.linalg.lstsq(small, -r, rcond=None)[0])) < MAX_STEP
    plain = _bates_watts(small, r)
    assert float(relative_offset(jnp.asarray(r), jnp.asarray(small))) == pytest.approx(plain, rel=1e-9)
    held = np.concatenate([small, np.zeros((n, 1))], axis=1)
    assert float(relative_offset(jnp.asarray(r), jnp.asarray(held))) == pytest.approx(plain, rel=1e-9)
