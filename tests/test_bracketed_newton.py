"""`solver.bracketed_newton`, the one iteration of a scalar balance (the flat isolator's
displacement, one slider of a series pendulum in one direction): Newton's steps kept inside the
bracket of the iterates' signs. Checked on r(x) = 5 arctan(x - 1), whose plain Newton iteration
diverges from |x - 1| > 1.39 (the slope falls as 1 / x^2), against the root x = 1."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from teflon_jax.solver import bracketed_newton

TOLERANCE = 1e-12


def _evaluate(x):
    r = 5 * jnp.arctan(x - 1)
    slope = 5 / (1 + (x - 1) ** 2)
    return r, r / slope, slope


def test_plain_newton_diverges_where_the_bracketed_one_finds_the_root():
    x = 4.0
    for _ in range(6):
        x = x - float(_evaluate(x)[1])
    assert abs(x) > 1e6  # the unsafeguarded iteration runs away
    for bracket in ({}, {"lower": jnp.asarray(-3.0), "upper": jnp.asarray(4.0)}):
        root, converged, values = bracketed_newton(_evaluate, jnp.asarray(4.0), TOLERANCE, 60, **bracket)
        assert bool(converged) and abs(float(root) - 1.0) < 1e-12
        assert float(values[0]) == float(_evaluate(root)[0])  # the values handed back are the root's


def test_a_step_that_is_not_finite_bisects_the_bracket():
    def no_slope(x):  # no trusted slope: every step bisects the given bracket
        r = 5 * jnp.arctan(x - 1)
        return r, jnp.nan * r

    root, converged, _ = bracketed_newton(no_slope, jnp.asarray(3.0), TOLERANCE, 200, lower=jnp.asarray(0.0),
                                          upper=jnp.asarray(3.0))
    assert bool(converged) and abs(float(root) - 1.0) < 1e-12
    _, short, _ = bracketed_newton(no_slope, jnp.asarray(3.0), TOLERANCE, 5, lower=jnp.asarray(0.0),
                                   upper=jnp.asarray(3.0))
    assert not bool(short)  # five halvings of [0, 3] do not reach 1e-12: reported, not hidden


@pytest.mark.parametrize("unrolled", [1, 3, 8])
def test_iterations_written_out_in_line_follow_the_loop_and_batches_stop_member_by_member(unrolled):
    guesses = jnp.asarray([4.0, -2.0, 1.0 + 1e-14, 1.3])

    def solve(guess, unrolled):
        return bracketed_newton(_evaluate, guess, TOLERANCE, 40, unrolled=unrolled)[0]

    looped = np.asarray([solve(g, 0) for g in guesses])
    np.testing.assert_array_equal(np.asarray(jax.vmap(lambda g: solve(g, unrolled))(guesses)), looped)
    np.testing.assert_array_equal(np.asarray(jax.vmap(lambda g: solve(g, 0))(guesses)), looped)
    assert looped[2] == guesses[2]  # already balanced: no step taken
