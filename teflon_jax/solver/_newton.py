"""Newton's iterations on a step's balance r(x) = 0, given as callables: the strategies the
stepped systems choose by the static shape of their unknowns.

- `damped_newton`: x <- x - f J^-1 r with f halved until the merit sum(r^2) falls, then a
  second stage with much shorter steps where the first leaves the balance short (a slider's
  reversal kink: a full step from the sliding side overshoots by the ratio of the slopes);
  J^-1 r comes with each evaluation (`sherman_morrison` for J = diag(k) + 1 1^T / G).
  With a `restart`, the same started once more from a second point where the first run ends
  short (a minimum of sum(r^2) with r != 0).
- `bracketed_newton`: one scalar unknown whose residual changes sign across the root (one
  slider in one direction, the flat isolator's displacement): Newton's steps kept inside the
  bracket of the iterates' signs, bisecting it where a step would leave it.
- `planar_newton` (`_planar.py`): on unknowns with 2 x 2 blocks per element,
  J = blockdiag(K_e) + U U^T / G inverted by the Woodbury identity, an optional secant
  (Broyden) first stage, then `damped_newton`.

Each returns its iterate bit for bit as written here; `implicit_root` differentiates the root.
References: Dennis & Schnabel (1996), Numerical Methods for Unconstrained Optimization,
Sec. 6.3 (line search by backtracking); Sherman & Morrison (1950).
"""

import jax
import jax.numpy as jnp

SMALLEST_STEP = 1.0 / 64
"""Shortest fraction of a Newton step the line search tries; it is then taken as it is."""

RESCUE_ITERATIONS = 120
"""Most further evaluations of the residual in a step whose balance the first `iterations`
left short (the line search's second stage)."""

RESCUE_SMALLEST = 2.0**-40
"""Shortest fraction of a Newton step the second stage tries before it takes it as it is: where
a slider's force has a kink (Z's elastic slope on a reversal against W / R_e while it slides),
a full Newton step from the sliding side overshoots the root by up to the ratio of the slopes
(mu R_e / Y, ~10^3), and only a short enough one lowers the imbalance."""


def shortest_fraction(k, iterations: int):
    """The fraction of a Newton step the line search takes as it is at evaluation `k`:
    `SMALLEST_STEP` within the first `iterations`, `RESCUE_SMALLEST` after them."""
    return jnp.where(k < iterations, SMALLEST_STEP, RESCUE_SMALLEST)


def damped_newton(evaluate, guess, tolerance, iterations: int, *, restart=None, first=None, taken=0,
                  direction=None, rescue: int = RESCUE_ITERATIONS):
    """Newton's iteration with step halving: from `guess`, steps x <- x - f dir with f halved
    until the merit sum(r^2) falls (or f reaches `SMALLEST_STEP`), while max |r| > `tolerance`
    and fewer than `iterations` steps were taken. `evaluate(x)` returns (residual r, merit,
    direction J^-1 r, ...), anything after the direction carried along (such as the forces the
    residual came from). Where that leaves the balance short, at most `rescue` more steps
    (`RESCUE_ITERATIONS` by default; 0 where `iterations` is a hard cap) halve f down to
    `RESCUE_SMALLEST` (`shortest_fraction`); a step balanced within `iterations` is as before.

    **Options:** `restart` (an x like `guess`): where those steps run out short of `tolerance`
    (a minimum of sum(r^2) with r != 0), the same once more from `restart`; `first`:
    `evaluate(guess)` where the caller has it; `taken`: the steps taken before `guess` (a first
    stage's); `direction(x, values)`: J^-1 r from `evaluate`'s values at x, solved where a step
    starts (`evaluate` then returns (r, merit, ...) without it: no solve at the trials the line
    search turns down, nor at the root).

    **Returns:** (x, whether max |r| <= tolerance, the steps taken, `evaluate`'s values at x)."""
    budget = iterations + rescue

    def cond(carry):
        _, values, _, k, restarted = carry
        return (jnp.max(jnp.abs(values[0])) > tolerance) & ((k < budget) | ~restarted)

    def body(carry):
        x, values, fraction, k, restarted = carry
        step = values[2] if direction is None else direction(x, values)
        if restart is None:
            trial = x - fraction * step
        else:
            again = k >= budget  # reached only before the restart
            trial = jnp.where(again, restart, x - fraction * step)
        new = evaluate(trial)
        accept = (new[1] < values[1]) | (fraction <= shortest_fraction(k, iterations))
        if restart is not None:
            accept = accept | again
        x = jnp.where(accept, trial, x)
        values = jax.tree_util.tree_map(lambda a, b: jnp.where(accept, a, b), new, values)
        fraction = jnp.where(accept, 1.0, 0.5 * fraction)
        if restart is None:
            return x, values, fraction, k + 1, restarted
        return x, values, fraction, jnp.where(again, 0, k + 1).astype(k.dtype), restarted | again

    values = evaluate(guess) if first is None else first
    carry = (guess, values, jnp.ones((), guess.dtype), jnp.asarray(taken, jnp.int32),
             jnp.asarray(restart is None))
    x, values, _, k, _ = jax.lax.while_loop(cond, body, carry)
    return x, jnp.max(jnp.abs(values[0])) <= tolerance, k, values


def bracketed_newton(evaluate, guess, tolerance, iterations: int, *, lower=None, upper=None, unrolled: int = 0):
    """Root of a residual r(x) of one unknown (`guess` a scalar or (1,)) whose sign changes
    across it, by Newton's steps x <- x - dir kept inside the bracket (lo, hi) of the iterates'
    signs: a step that is not finite or not strictly inside bisects the bracket. The bracket
    starts at [`lower`, `upper`] where the caller knows one, else open, (-inf, inf), until
    both signs are seen (r tending to -inf and +inf at either end: the balance of one slider,
    whose compliance term outgrows the bounded friction). `evaluate(x)` returns
    (r, dir, *more) with dir = r / J (not finite where no slope is to be trusted), so a step
    goes the way the root lies while the bracket is open; no merit function (r may fall as x
    grows, e.g. while Eq. 1 falls with a reversing speed, where a line search on r^2 stalls).
    Stops when |r| <= `tolerance` or after `iterations` steps; the first `unrolled` of them
    are written out in line (straight-line code that XLA fuses with the rest of the step; a
    member already at tolerance keeps its iterate), the rest run in a `lax.while_loop`. The
    iterates are those of a plain loop that stops at tolerance, whatever `unrolled` is.

    **Returns:** (x, whether |r| <= tolerance, `evaluate`'s values at x: no evaluation after
    the loop)."""
    def short(values):
        return jnp.max(jnp.abs(values[0])) > tolerance

    def cond(carry):
        _, _, _, values, k = carry
        return short(values) & (k < iterations)

    def body(carry):
        x, lo, hi, values, k = carry
        r, direction = values[0], values[1]
        active = short(values)  # always True in the while loop's body
        lo = jnp.where(r < 0, x, lo)
        hi = jnp.where(r > 0, x, hi)
        step = x - direction
        inside = (step > lo) & (step < hi) & jnp.isfinite(step)
        x_new = jnp.where(inside, step, 0.5 * (lo + hi))
        new = evaluate(x_new)
        return (jnp.where(active, x_new, x), lo, hi, tuple(jnp.where(active, a, b) for a, b in zip(new, values)),
                k + 1)

    infinite = jnp.full_like(guess, jnp.inf)
    lo = -infinite if lower is None else lower
    hi = infinite if upper is None else upper
    carry = (guess, lo, hi, evaluate(guess), 0)
    for _ in range(min(unrolled, iterations)):
        carry = body(carry)
    if iterations > unrolled:
        carry = jax.lax.while_loop(cond, body, carry)
    x, _, _, values, _ = carry
    return x, ~short(values), values


def sherman_morrison(residual, slope, compliance):
    """J^-1 r for J = diag(slope) + 1 1^T / G (Sherman-Morrison): c (r - s), c = 1 / slope,
    s = sum(c r) / (G + sum c). At G = 0 (an imposed sum of the unknowns) the step keeps that
    sum. One unknown: G r / (G k + 1), without the cancellation of c (r - s) where its slope k
    is small."""
    if residual.shape[0] == 1:
        return compliance * residual / (compliance * slope + 1)
    c = 1.0 / slope
    return c * (residual - jnp.sum(c * residual) / (compliance + jnp.sum(c)))
