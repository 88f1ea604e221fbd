"""BFGS on the design variables, with a variable that runs onto a bound held there.

`optimise_design` maps each variable into its box by x = lo + (hi - lo) sigmoid(y). Where the
optimum lies on a bound, BFGS spends its steps driving y towards infinity (the sigmoid
flattens, the gradient in y fades) before optimistix's test (a step changing every y by less
than atol + rtol |y|) can be met, and may run out of them with the other variables still
moving: it then reports no convergence near a design that is the optimum. When BFGS stops
short with variables on a bound (`bound_side`), they are held there (y = +-
`HELD_LOGIT`, where the sigmoid is 0 or 1 to rounding) and BFGS runs again over the others.

A held bound is a minimum only if the objective rises into the box there (the sign of its
Karush-Kuhn-Tucker multiplier): dJ/dx >= 0 at a lower bound, <= 0 at an upper one, J the
penalised objective. A held variable whose derivative points into the box is named in
`inward` and the solve counts as not converged. Reference: Nocedal & Wright, "Numerical
Optimization", 2nd ed., 2006, Sec. 12.3 (first-order conditions) and 16.7 (active sets).
"""

import dataclasses

import jax.numpy as jnp

from ._design_check import bound_side

HELD_LOGIT = 40.0
"""|y| of a held variable: sigmoid(-40) = 4e-18, the bound itself to double precision for
ranges of up to about 200 times the bound's value."""


@dataclasses.dataclass(frozen=True)
class HeldSolution:
    """The outcome of `minimise_holding_bounds`: `value` (y of every variable), `result`
    (optimistix's code of the last BFGS run), `stats` ({"num_steps": steps of all runs}),
    `held` (names held on a bound) and `inward` (those of them whose derivative points into
    the box: no minimum there)."""

    value: dict
    result: object
    stats: dict
    held: tuple = ()
    inward: tuple = ()


def minimise_holding_bounds(minimise, objective, held_objective, gradient_in_x, bounds, y0: dict,
                            limit) -> HeldSolution:
    """BFGS from `y0`, again over the free variables where it stopped short on a bound.

    **Arguments:** `minimise(fn, y, args)` -> an optimistix `Solution` (BFGS with its
    settings) of `fn(y, args)`; `objective(y, limit)` the penalised objective J of every
    variable and `held_objective(y_free, (limit, y_held))` the same of the free ones (one
    function object each, so their compiled programs are reused); `gradient_in_x(x, limit)`
    -> dJ/dx {name: float}; `bounds`: the design's `Bounds`; `y0`: the unconstrained start;
    `limit` [m]: the limit on the smoothed displacement statistic.
    """
    import optimistix as optx

    first = minimise(objective, y0, limit)
    steps = int(first.stats["num_steps"])
    if first.result == optx.RESULTS.successful:
        return HeldSolution(dict(first.value), first.result, {"num_steps": steps})
    x = bounds.to_physical(first.value)
    sides = {name: bound_side(float(x[name]), lo, hi) for name, (lo, hi) in bounds.ranges.items()}
    sides = {name: side for name, side in sides.items() if side}
    if not sides:
        return HeldSolution(dict(first.value), first.result, {"num_steps": steps})
    held = {n: jnp.asarray(side * HELD_LOGIT, dtype=float) for n, side in sides.items()}
    free = {n: v for n, v in first.value.items() if n not in held}
    if free:
        second = minimise(held_objective, free, (limit, held))
        value, result = {**dict(second.value), **held}, second.result
        steps += int(second.stats["num_steps"])
    else:  # every variable on a bound: the corner is the candidate
        value, result = held, optx.RESULTS.successful
    slope = gradient_in_x(bounds.to_physical(value), limit)
    inward = tuple(n for n, side in sides.items() if side * float(slope[n]) > 0)
    return HeldSolution(value, result, {"num_steps": steps}, tuple(sides), inward)


def held_messages(solution: HeldSolution) -> list:
    """What `minimise_holding_bounds` did with variables that BFGS ran onto a bound."""
    if not solution.held:
        return []
    one = len(solution.held) == 1
    messages = [f"BFGS ran {', '.join(solution.held)} onto {'its bound' if one else 'their bounds'} (where it "
                "cannot meet its tolerance on the unconstrained variable) and was run again with "
                f"{'it' if one else 'them'} held there."]
    for name in solution.inward:
        messages.append(f"{name}: the objective falls into the box from its bound: the held bound is "
                        "not a minimum, so the design is not an optimum.")
    return messages
