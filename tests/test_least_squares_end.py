"""The least-squares solvers end where the arithmetic allows no lower cost.

optimistix tests for convergence only on accepted steps. A solve that lands on a point where
no step lowers the cost (a minimum to the precision of the arithmetic) refuses every later step
and runs to `max_steps`, reported as not converged though it sits on the minimum. Seen on 3 of
120 noisy bearing-test records fitted in one vmapped batch (tests/test_fit_coverage.py): each
converged alone in 21 to 27 steps at the same constants. Two rules end such a solve: past
`MAX_DAMPING` the step is zero, and a step that moves nothing is accepted even where the cost
evaluated again at the same point differs in its last bit.
"""

import jax
import jax.numpy as jnp
import lineax as lx
import numpy as np
import optimistix as optx
import pytest

from identification.least_squares import fit_least_squares
from identification.least_squares._marquardt import (
    MAX_DAMPING,
    _StoppingDampedNewtonDescent,
    _ZeroStepTrustRegion,
)


def _root_two(params, args):
    """r(x) = x^2 - 2: its least-squares minimum sqrt(2) is no float, so near it the cost
    stops falling at rounding level while the gradient is not exactly zero."""
    del args
    return jnp.atleast_1d(params["x"] ** 2 - 2.0)


@pytest.mark.last_bit
@pytest.mark.parametrize("solver", ["levenberg_marquardt", "levenberg_marquardt_scaled"])
def test_a_solve_on_a_minimum_of_the_arithmetic_ends_converged(solver):
    """Tolerances below what the arithmetic can meet by moving (1e-300): only the zero step
    ends the solve, with y and the residuals unchanged. optimistix's own Levenberg-Marquardt,
    with the same tolerances, runs to max_steps there."""
    result = fit_least_squares(_root_two, {"x": 1.0}, {}, max_steps=300, rtol=1e-300, atol=1e-300,
                               solver=solver)
    assert result.converged, result.message
    assert result.n_steps < 120
    assert abs(result.parameters["x"] - np.sqrt(2.0)) <= 2 * np.spacing(np.sqrt(2.0))
    plain = optx.least_squares(lambda y, args: y**2 - 2.0, optx.LevenbergMarquardt(rtol=1e-300, atol=1e-300),
                               jnp.array([1.0]), max_steps=300, throw=False)
    assert plain.result != optx.RESULTS.successful  # the trap the rule removes


def _info(residual, jacobian):
    return optx.FunctionInfo.ResidualJac(jnp.asarray(residual), lx.MatrixLinearOperator(jnp.asarray(jacobian)))


def test_the_damped_step_is_zero_past_max_damping_and_optimistix_s_before():
    """lam = 1 / step size against MAX_DAMPING times the largest column norm^2 of J."""
    jac, r = np.array([[2.0, 0.5], [0.0, 3.0], [1.0, 1.0]]), np.array([0.3, -0.2, 0.1])
    state = _StoppingDampedNewtonDescent(linear_solver=lx.QR()).query(jnp.zeros(2), _info(r, jac), None)
    curvature = np.max(np.sum(jac**2, axis=0))
    for step_size in (1.0, 1e-3, 0.5 / (MAX_DAMPING * curvature), 2.0 / (MAX_DAMPING * curvature)):
        ours, _ = _StoppingDampedNewtonDescent(linear_solver=lx.QR()).step(jnp.asarray(step_size), state)
        theirs, _ = optx.DampedNewtonDescent(linear_solver=lx.QR()).step(jnp.asarray(step_size), state)
        lam = 1 / step_size
        expected = -np.linalg.solve(jac.T @ jac + lam * np.eye(2), jac.T @ r)
        if lam > MAX_DAMPING * curvature:
            assert np.all(np.asarray(ours) == 0.0)
        else:
            np.testing.assert_allclose(ours, theirs, rtol=1e-14, atol=0)
            np.testing.assert_allclose(ours, expected, rtol=1e-9, atol=0)


def test_a_step_that_moves_nothing_is_accepted_whatever_the_last_bit_of_the_cost():
    """Evaluated again at the same y the residuals are one ulp larger: optimistix's trust
    region refuses (and would for ever); ours accepts. A step that moves and raises the cost
    is still refused by both."""
    y = jnp.array([1.0, 2.0])
    jac, r = np.array([[1.0, 0.0], [0.0, 1.0]]), np.array([0.25, 0.5])
    again = _info(np.nextafter(r, 1.0), jac)
    state = optx.ClassicalTrustRegion().init(y, _info(r, jac))
    for search, accepted in ((optx.ClassicalTrustRegion(), False), (_ZeroStepTrustRegion(), True)):
        _, accept, _, _ = search.step(jnp.array(False), y, y, _info(r, jac), again, state)
        assert bool(accept) is accepted
        moved = y + jnp.array([1e-3, 0.0])
        _, accept, _, _ = search.step(jnp.array(False), y, moved, _info(r, jac), _info(r + 0.1, jac), state)
        assert not bool(accept)
    jax.block_until_ready(y)
