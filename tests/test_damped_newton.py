"""The one damped Newton iteration (`teflon_jax.solver.damped_newton`) on small problems whose
roots are known: the restart that gets a stalled iteration out of a minimum of r^2 with r != 0,
and the direction solved where a step starts, which must give the iterates of the direction
evaluated with each point."""

import jax
import jax.numpy as jnp
import numpy as np

from teflon_jax.solver import damped_newton

jax.config.update("jax_enable_x64", True)


def _cubic(x):
    """r = x^3 - 2 x + 2: Newton's classic trap, whose r^2 has a minimum with r != 0 at
    x = sqrt(2/3); its one real root lies near -1.77."""
    r = x**3 - 2 * x + 2
    return r, jnp.sum(r**2), r / (3 * x**2 - 2)


def test_a_stalled_iteration_restarts_and_finds_the_root():
    root = float(np.real(next(z for z in np.roots([1, 0, -2, 2]) if abs(z.imag) < 1e-12)))
    stalled, converged, _, _ = damped_newton(_cubic, jnp.array([0.0]), 1e-12, 20)
    assert not bool(converged)
    assert abs(float(stalled[0]) - np.sqrt(2 / 3)) < 1e-3  # at the minimum of r^2, r = 0.91
    found, converged, taken, values = damped_newton(_cubic, jnp.array([0.0]), 1e-12, 20, restart=jnp.array([-2.0]))
    assert bool(converged)
    assert abs(float(found[0]) - root) < 1e-12 and abs(float(values[0][0])) <= 1e-12
    assert int(taken) < 20  # counted again from the restart


def _plane(x):
    """Two equations with the root (1, 2): r = (x0^2 + x1 - 3, x0 + x1^3 - 9)."""
    return jnp.stack([x[0] ** 2 + x[1] - 3, x[0] + x[1] ** 3 - 9])


def _jacobian_solve(x, r):
    matrix = jnp.array([[2 * x[0], 1.0], [1.0, 3 * x[1] ** 2]])
    return jnp.linalg.solve(matrix, r)


def test_the_direction_solved_where_a_step_starts_gives_the_same_iterates():
    """The iteration with `direction` (solved at the accepted points only) and without it (solved
    with every evaluation) take the same steps to the same root, counting them alike."""
    def eager(x):
        r = _plane(x)
        return r, jnp.sum(r**2), _jacobian_solve(x, r)

    def lazy(x):
        r = _plane(x)
        return r, jnp.sum(r**2)

    guess = jnp.array([3.0, -1.0])
    a = damped_newton(eager, guess, 1e-13, 40)
    b = damped_newton(lazy, guess, 1e-13, 40, direction=lambda x, values: _jacobian_solve(x, values[0]))
    assert bool(a[1]) and bool(b[1])
    np.testing.assert_allclose(np.asarray(a[0]), [1.0, 2.0], atol=1e-12)
    np.testing.assert_array_equal(np.asarray(a[0]), np.asarray(b[0]))
    assert int(a[2]) == int(b[2]) > 3  # the line search had work to do from this guess
