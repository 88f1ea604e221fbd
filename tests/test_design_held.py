"""A design variable that BFGS runs onto a bound is held there and BFGS run again over the
others (`studies._design_held`).

Through x = lo + (hi - lo) sigmoid(y), an optimum on a bound sends y to infinity and BFGS spends
its steps there; the README's default `design` (optimum on the lowest pressure) ended with
exit 1 after 200 steps. Here the objectives are quadratics whose minima are known in
closed form; BFGS, the bijection and the held rerun are the design's own."""

import jax
import jax.numpy as jnp
import optimistix as optx
import pytest

from teflon_jax.studies import design_bounds
from teflon_jax.studies._design_held import (
    HELD_LOGIT,
    held_messages,
    minimise_holding_bounds,
)
from teflon_jax.systems import isolated_structure
from teflon_jax.units import PSI


class _Box:
    """The design's sigmoid bijection on [0, 1] for each name (`Bounds`' formula)."""

    def __init__(self, names):
        self.ranges = {n: (0.0, 1.0) for n in names}

    def to_physical(self, y):
        return {n: jax.nn.sigmoid(y[n]) for n in self.ranges}


def _solve(target, start, max_steps=200):
    """min sum_n (x_n - target_n)^2 over [0, 1]^2 from the unconstrained `start`."""
    box = _Box(tuple(target))
    solver = optx.BFGS(rtol=1e-7, atol=1e-9)

    def cost(x, limit):
        return sum((x[n] - t) ** 2 for n, t in target.items()) * limit

    def objective(y, limit):
        return cost(box.to_physical(y), limit)

    def held_objective(y, args):
        return objective({**y, **args[1]}, args[0])

    def minimise(fn, y, args):
        return optx.minimise(fn, solver, y, args=args, max_steps=max_steps, throw=False)

    slope = jax.grad(cost)
    start = {n: jnp.asarray(v, dtype=float) for n, v in start.items()}
    plain = minimise(objective, start, jnp.asarray(1.0))
    return box, plain, minimise_holding_bounds(minimise, objective, held_objective, slope, box, start,
                                               jnp.asarray(1.0))


def test_a_variable_run_onto_its_bound_is_held_and_the_other_converges():
    """Minimum of (a - 0.3)^2 + (b - 2)^2 on the unit box: a = 0.3 inside, b = 1 on its upper
    bound. BFGS alone, given 30 steps, stops short with b's y near 20 (b on its bound) and a
    still moving (it needs 82 steps, most of them spent pushing b's y up to 37); held, b = 1
    and a = 0.3 to the tolerance, converged, the objective rising into the box at b
    (dJ/db = -2 < 0)."""
    box, plain, solution = _solve({"a": 0.3, "b": 2.0}, {"a": 0.0, "b": 0.0}, max_steps=30)
    assert plain.result != optx.RESULTS.successful
    assert solution.result == optx.RESULTS.successful
    assert solution.held == ("b",) and solution.inward == ()
    x = box.to_physical(solution.value)
    assert float(x["b"]) == 1.0 and float(solution.value["b"]) == HELD_LOGIT
    assert float(x["a"]) == pytest.approx(0.3, abs=1e-7)
    assert solution.stats["num_steps"] > plain.stats["num_steps"]
    assert "b onto its bound" in held_messages(solution)[0]


def test_a_held_bound_where_the_objective_falls_into_the_box_is_no_minimum():
    """(x - 0.5)^2 from x = sigmoid(-30) ~ 1e-13, one BFGS step (it cannot converge in one):
    x lies on its lower bound, so it is held, but dJ/dx = -1 there points into the box: named
    in `inward`, and the message says the design is not an optimum."""
    _, plain, solution = _solve({"x": 0.5}, {"x": -30.0}, max_steps=1)
    assert plain.result != optx.RESULTS.successful
    assert solution.held == ("x",) and solution.inward == ("x",)
    assert "not a minimum" in held_messages(solution)[1]


def test_a_design_inside_its_box_is_left_to_bfgs():
    """A minimum inside the box: BFGS converges alone and nothing is held."""
    _, plain, solution = _solve({"a": 0.3, "b": 0.6}, {"a": 0.0, "b": 0.0})
    assert plain.result == optx.RESULTS.successful
    assert solution.held == () and solution.stats["num_steps"] == plain.stats["num_steps"]
    assert held_messages(solution) == []


def test_the_held_logit_is_the_bound_to_rounding_for_the_design_s_pressure():
    """sigmoid(-HELD_LOGIT) on the default pressure range gives the bound itself."""
    bounds = design_bounds(isolated_structure("rigid", pressure=2000 * PSI),
                           {"isolation_period": (1.0, 4.0), "pressure": (1000 * PSI, 3000 * PSI)})
    x = bounds.to_physical({"isolation_period": jnp.asarray(HELD_LOGIT), "pressure": jnp.asarray(-HELD_LOGIT)})
    assert float(x["pressure"]) == 1000 * PSI and float(x["isolation_period"]) == 4.0
