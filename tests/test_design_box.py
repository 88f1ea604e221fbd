"""BFGS on the unit box (`studies._design_box.minimise_in_box`), the optimiser of `design`,
against quadratics whose minima over the box, with and without a penalised limit, are known in
closed form.

For J(s) = (s - c)^T A (s - c) / 2 with A symmetric positive definite, the minimum over
[0, 1]^2 is c where c lies in the box; with s_1 held on a bound b, the other variable's
minimum is s_2 = c_2 - A_21 (b - c_1) / A_22 (the bound is the minimum when the slope there,
A_11 (b - c_1) + A_12 (s_2 - c_2), points out of the box: the Karush-Kuhn-Tucker condition);
and where both leave the box, a corner."""

import numpy as np
import pytest

from teflon_jax.studies._design_box import _model_step, binding_variables, minimise_in_box

# an ill-scaled, correlated curvature: condition number about 400
A = np.array([[40.0, 6.0], [6.0, 1.0]])


def _quadratic(c, calls=None, limit=None):
    """F = (s - c)^T A (s - c) / 2 and its gradient, with the limit a . s - b <= 0 of
    `limit` = (a, b) (None: no limit, its excess and slope zero)."""
    c = np.asarray(c, dtype=float)
    a, b = (np.zeros(2), 0.0) if limit is None else (np.asarray(limit[0], dtype=float), limit[1])

    def fun(s):
        if calls is not None:
            calls.append(np.array(s))
        r = s - c
        return 0.5 * float(r @ A @ r), A @ r, float(a @ s - b), a

    return fun


def test_interior_minimum_is_found_to_the_tolerance():
    c = np.array([0.3, 0.6])
    solution = minimise_in_box(_quadratic(c), [0.9, 0.1])
    assert solution.converged and solution.binding == ()
    np.testing.assert_allclose(solution.value, c, atol=1e-6)
    assert solution.objective < 1e-12


def test_a_minimum_beyond_one_bound_holds_that_variable_and_minimises_the_other():
    """c = (1.4, -1.9): with s_1 = 1, s_2 = -1.9 - 6 (1 - 1.4) / 1 = 0.5, and the slope of s_1
    there, 40 (1 - 1.4) + 6 (0.5 + 1.9) = -1.6, points out of the box."""
    c = np.array([1.4, -1.9])
    expected = np.array([1.0, c[1] - A[1, 0] * (1.0 - c[0]) / A[1, 1]])
    assert expected[1] == pytest.approx(0.5)
    solution = minimise_in_box(_quadratic(c), [0.5, 0.5])
    assert solution.converged and solution.binding == (0,)
    assert solution.value[0] == 1.0  # on the bound exactly, not a rounding of it
    assert solution.value[1] == pytest.approx(expected[1], abs=1e-6)
    # the first-order condition: the slope on the held bound points out of the box
    assert solution.gradient[0] < 0.0 and abs(solution.gradient[1]) < 1e-5


def test_a_bound_that_is_not_the_minimum_is_left():
    """Started on the lower bound of s_1 with the minimum inside: the slope points into the box,
    so s_1 is free and leaves the bound."""
    c = np.array([0.4, 0.5])
    solution = minimise_in_box(_quadratic(c), [0.0, 0.5])
    assert solution.converged and solution.binding == ()
    np.testing.assert_allclose(solution.value, c, atol=1e-6)


def test_a_corner_minimum_ends_with_both_variables_binding():
    """c = (-1, 2): s_1 = 0 is held (its slope 40 + 6 (s_2 - 2) > 0 for every s_2 in the box), and
    with it s_2's minimum, 2 - 6 (0 + 1) / 1 = -4, lies beyond its lower bound: the corner (0, 0),
    where the slope A (s - c) = (28, 4) points out of the box in both."""
    c = np.array([-1.0, 2.0])
    solution = minimise_in_box(_quadratic(c), [0.7, 0.7])
    assert solution.converged and solution.binding == (0, 1)
    np.testing.assert_array_equal(solution.value, [0.0, 0.0])
    assert solution.gradient[0] > 0.0 and solution.gradient[1] > 0.0


def test_the_iterates_never_leave_the_box():
    calls = []
    minimise_in_box(_quadratic([3.0, -2.0], calls), [0.5, 0.5])
    points = np.array(calls)
    assert points.min() >= 0.0 and points.max() <= 1.0


def test_a_start_outside_the_box_is_projected_onto_it():
    calls = []
    minimise_in_box(_quadratic([0.3, 0.6], calls), [-2.0, 5.0])
    np.testing.assert_array_equal(calls[0], [0.0, 1.0])


def test_the_exact_curvature_given_as_start_reaches_a_quadratic_minimum_at_once():
    """A run started with the Hessian of a previous one: with B = A the first step is Newton's,
    so the interior minimum is reached by the first trial (its Cauchy test needs one more)."""
    c = np.array([0.3, 0.6])
    calls = []
    solution = minimise_in_box(_quadratic(c, calls), [0.9, 0.1], hessian=A)
    np.testing.assert_allclose(calls[1], c, atol=1e-12)
    assert solution.converged and solution.steps <= 3


def test_the_step_budget_is_kept_and_reported():
    solution = minimise_in_box(_quadratic([0.3, 0.6]), [0.9, 0.1], max_steps=3)
    assert solution.steps == 3 and not solution.converged


def test_binding_variables_reads_the_slope_on_each_bound():
    s = np.array([0.0, 0.0, 1.0, 1.0, 0.5])
    g = np.array([1.0, -1.0, -1.0, 1.0, 1.0])
    np.testing.assert_array_equal(binding_variables(s, g), [True, False, True, False, False])


def _penalised_minimum(c, a, b, penalty):
    """The minimum of (s - c)^T A (s - c) / 2 + rho max(0, a . s - b)^2 (inside the box): where
    a . c > b, s = c - A^-1 a l with l = 2 rho (a . c - b) / (1 + 2 rho a^T A^-1 a)."""
    towards = np.linalg.solve(A, a)
    return c - towards * 2 * penalty * (a @ c - b) / (1 + 2 * penalty * a @ towards)


@pytest.mark.parametrize("penalty", [1.0, 100.0, 1e4])
def test_a_penalised_limit_is_met_at_its_closed_form_minimum(penalty):
    """The limit s_1 + s_2 <= 0.7 cuts off the minimum c = (0.5, 0.6): the optimum lies beyond
    the limit by the penalty's closed-form margin, which shrinks as rho grows."""
    c, a, b = np.array([0.5, 0.6]), np.array([1.0, 1.0]), 0.7
    expected = _penalised_minimum(c, a, b, penalty)
    assert np.all((expected > 0) & (expected < 1))
    solution = minimise_in_box(_quadratic(c, limit=(a, b)), [0.1, 0.9], penalty=penalty)
    assert solution.converged and solution.binding == ()
    np.testing.assert_allclose(solution.value, expected, atol=1e-6)
    assert solution.limit == pytest.approx(a @ expected - b, abs=1e-6)


def test_a_penalised_limit_with_a_variable_on_its_bound():
    """F = -s_1 + s_2 / 2 (no curvature) and 100 max(0, s_1 + s_2 - 0.8)^2: s_2 rises into the
    box from 0 (slope 1/2 + 200 max(0, .) > 0), and -1 + 200 (s_1 - 0.8) = 0 gives s_1 = 0.805."""

    def fun(s):
        return -s[0] + 0.5 * s[1], np.array([-1.0, 0.5]), float(s[0] + s[1] - 0.8), np.array([1.0, 1.0])

    solution = minimise_in_box(fun, [0.2, 0.5], penalty=100.0)
    assert solution.converged and solution.binding == (1,)
    assert solution.value[1] == 0.0
    assert solution.value[0] == pytest.approx(0.805, abs=1e-6)


def test_the_model_step_is_the_minimum_of_the_one_sided_penalised_quadratic():
    """The step minimises g . d + d^T A d / 2 + rho max(0, c + a . d)^2: checked against a dense
    search of that model, where the plain step crosses the limit and where it does not."""
    grid = np.stack(np.meshgrid(np.linspace(-3, 3, 1201), np.linspace(-3, 3, 1201)), axis=-1).reshape(-1, 2)
    curvature, gf, gc, rho = np.array([[2.0, 0.5], [0.5, 1.0]]), np.array([-3.0, 1.0]), np.array([1.0, 2.0]), 5.0
    for c in (3.0, -3.0):  # the plain step (2, -2) crosses the limit (l = c - 2), then does not
        model = (grid @ gf + 0.5 * np.einsum("ij,jk,ik->i", grid, curvature, grid)
                 + rho * np.maximum(0, c + grid @ gc) ** 2)
        best = grid[np.argmin(model)]
        np.testing.assert_allclose(_model_step(curvature, gf, c, gc, rho), best, atol=6e-3)


def test_a_variable_next_to_its_bound_with_the_slope_pushing_out_moves_onto_it_at_once():
    """s_2 starts 0.005 above its lower bound and its minimum lies beyond it: the first step puts
    it on the bound exactly (a tiny first step of the others notwithstanding)."""
    calls = []
    solution = minimise_in_box(_quadratic([0.3, -1.0], calls), [0.5, 0.005])
    assert calls[1][1] == 0.0
    assert solution.converged and solution.binding == (1,)


def test_a_strongly_non_quadratic_objective_reaches_its_minimum():
    """J = sum exp(8 (s - c)) - 8 (s - c), whose curvature changes by e^8 across the box, from the
    corner (0, 1): quasi-Newton steps overshoot, the line search holds them, and the minimum c
    is reached with every evaluated point inside the box."""
    c = np.array([0.35, 0.55])

    def fun(s):
        assert np.all((s >= 0.0) & (s <= 1.0))
        e = np.exp(8 * (s - c))
        return float(np.sum(e - 8 * (s - c))), 8 * e - 8, 0.0, np.zeros(2)

    solution = minimise_in_box(fun, [0.0, 1.0])
    assert solution.converged and solution.steps < 60
    np.testing.assert_allclose(solution.value, c, atol=1e-6)
