"""The sliders' balance of a friction pendulum of sliders in series over one step, in one or two
horizontal components: what a structure on the isolator (`teflon_jax.systems`) and the
isolator's bearing test along an imposed path (`teflon_jax.systems.imposed_path_test`) step through.

S sliders carry one force F and their increments d_e add up to the isolator's; slider e
carries F_e(d_e) (`slider_forces`: Eq. 1 at the surface's mean velocity over the step, f_min
while Z still points back after a reversal, the restrainer beyond its capacity), a scalar
under one component and a vector in the plane under two (Park's biaxial Z along the
increment). Each step solves

    F_e(d_e) = F,   F = (D - sum_e d_e) / G,

D the isolator's increment that the linear step leaves without the bearing and G its
compliance over the step (a structure), or with sum_e d_e = D held exactly and F the sliders'
mean force (an imposed path: the limit G -> 0 of an actuator). The iteration is chosen by the
static shape of the unknowns (`teflon_jax.solver`): one slider in one component, a bracketed
scalar Newton (`bracketed_newton`); several, Newton's iteration with a halving line search
and J = diag(k_e) + 1 1^T / G inverted by Sherman-Morrison (`damped_newton`); two
components, the same on the exact 2 x 2 blocks K_e that each evaluation of the forces brings
(Park's slope written out, `balance_forces`), inverted by Woodbury, with an optional Broyden
first stage (`planar_newton`, `BALANCES`). The root is differentiated
implicitly with exact slopes (`implicit_root`). At a normal load N <= 0 (uplift) the sliders
carry nothing and share the isolator's increment as their pendulum stiffnesses W / R_e in
series would (`uplift_increments`).

References: Fenz & Constantinou (2006), Earthquake Engng Struct. Dyn. 35; (2008), Earthquake
Spectra 24(4); Park, Wen & Ang (1986); Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 3.
"""

import functools

import jax
import jax.numpy as jnp

from ..bearing import SeriesPendulum
from ..solver import (
    RESCUE_ITERATIONS,
    bracketed_newton,
    broyden_blocks,
    damped_newton,
    implicit_root,
    inverse2,
    planar_newton,
    sherman_morrison,
    woodbury,
)
from ._sliders import (
    balance_forces,
    floor_stiffnesses,
    heated_step,
    next_history,
    slider_lengths,
    step_history,
)

TRIPLE_NEWTON_ITERATIONS = 60
"""Most evaluations of the sliders' forces per step (Newton iterations and line-search halvings)."""

TRIPLE_TOLERANCE = 1e-9
"""Default `structure_on_isolator(newton_tolerance=...)`: the sliders' force imbalance over the weight W."""

BALANCES = ("newton", "secant")
"""How a step's planar balance is iterated (`StructureOnSliders.balance`, two components):
"newton", the exact 2 x 2 blocks of every point (each evaluation of the forces brings them);
"secant", Broyden's update of the blocks after the first step (the forces alone at each step,
Newton's iteration taking over where it stalls; `planar_newton`). Both balance to the same
tolerance; "newton" along one axis follows the one-component iteration to rounding, "secant"
agrees with it to that tolerance."""

SECANT_FLOOR = 2.0**-26
"""Relative step h / (Y + |d_e|) within which a secant update keeps a slider's block (the
change of its force over so short a step is mostly rounding; `secant_floors`)."""


def isolator_parameters(pendulum: SeriesPendulum, isolator, weight, normal, increment, compliance=None,
                        heat_weights=None):
    """The balance's parameters `p` from the isolator's state (sliders, Z, the last two
    increments, the force beyond the reference spring, then a heated pendulum's heat states and
    a remembering one's history; arrays (S,) or (S, 2)): total normal load W [N], its value N [N] over the step, the isolator's increment
    D [m] and the compliance G [m/N] (`None`: an imposed path), the heat kernel's weights of a
    heated pendulum."""
    slider0, z0 = isolator[:2]
    p = {"pendulum": pendulum, "W": weight, "N": normal, "s0": slider0, "z0": z0, "D": increment}
    if compliance is not None:
        p["G"] = compliance
    if pendulum.heated:
        p["k"] = pendulum.heat_factors(isolator[4], heat_weights)
    if pendulum.remembers:
        p["history"] = step_history(isolator[-1], z0)
    return p


def slider_step(isolator, p, guess, tolerance, dt, iterations: int, *, heat_rates=None, load=None,
                secant: bool = False, reference=None):
    """One step of the isolator: the sliders' increments that balance `p`
    (`isolator_parameters`) from `guess` to `tolerance` [N] (`balance`), over `dt` [s], under
    the load factor `load` N / W at the step's end (`None`: N = W throughout;
    `uplift_increments`), the heat flux at the contact pressure that the load factor `p["s"]`
    scales (the force law's own, 1 without it); `reference`: (k_ref [N/m], the isolator's displacement at the step's
    start [m]) of a structure, whose state keeps the force beyond k_ref u; `None` keeps F.

    **Returns:** (the isolator's state at the end, whether the balance converged, the bearing
    force F [N])."""
    pendulum = p["pendulum"]
    d, converged, evaluation = balance(dt, iterations, p, guess, tolerance, secant)
    if load is not None:
        d, converged = uplift_increments(pendulum, load, p["D"], d, converged)
    if evaluation is None:  # one component: the forces at the increments kept
        force, z1 = balance_forces(p, d, dt)
    elif load is None:
        force, z1 = evaluation
    else:  # the balance's own evaluation, except at uplift, where the increments were shared out again
        again = balance_forces(p, d, dt)
        force, z1 = (jnp.where(load <= 0, a, b) for a, b in zip(again, evaluation))
    bearing = jnp.mean(force, axis=0)  # equal to rounding
    extra = bearing if reference is None else bearing - reference[0] * (reference[1] + jnp.sum(d, axis=0))
    state = (isolator[0] + d, z1, jnp.stack([d, isolator[2][0]]), extra)
    if pendulum.heated:
        slide = jnp.abs(d) if d.ndim == 1 else slider_lengths(d)
        state = state + (heated_step(pendulum, isolator[4], p["k"], slide, dt, heat_rates, p.get("s", 1.0)),)
    if pendulum.remembers:
        state = state + (next_history(pendulum, p["history"], d),)
    return state, converged, bearing


def predicted_increments(previous):
    """The sliders' increments a step's Newton iteration starts from: 2 d_-1 - d_-2, the linear
    extrapolation of the last two steps' increments `previous` (2, ...) [m]. It starts the
    balance closer than d_-1 alone (B7's triple pendulum under two components: 1.47 instead of
    1.84 Newton steps per time step on average; benchmarks/README.md)."""
    return 2 * previous[0] - previous[1]


def uplift_increments(pendulum: SeriesPendulum, load, total, increments, converged):
    """(increments, converged) of a step under the load factor `load`: at `load` <= 0 (uplift)
    the sliders carry no force, the isolator's increment `total` [m] ((,) or (2,)) is theirs
    and they share it as their pendulum stiffnesses W / R_e in series would, d_e = total
    R_e / sum R (a smooth rule where the balance leaves the split open; one surface takes it
    all, also a flat one); else unchanged."""
    radii = pendulum.series_radii()
    share = jnp.ones_like(radii) if pendulum.slider_count == 1 else radii / jnp.sum(radii)
    lifted = load <= 0
    split = share * total if jnp.ndim(total) == 0 else share[:, None] * total
    return jnp.where(lifted, split, increments), converged | lifted


def carried_force(d, force, p):
    """The force the sliders must carry after the increments `d` (S[, 2]) [m], whose own
    forces are `force`: (D - sum d) / G, what the linear step leaves, where `p` holds the
    compliance G [m/N]; else (an imposed path, sum d = D held by the iteration) the mean of
    the sliders' forces."""
    if "G" in p:
        return (p["D"] - jnp.sum(d, axis=0)) / p["G"]
    return jnp.mean(force, axis=0)


def balance_compliance(p):
    """G [m/N] of the balance: the linear step's, or 0 for an imposed path (module docstring)."""
    return p.get("G", jnp.zeros((), p["s0"].dtype))


def balance(dt, iterations: int, p, guess, tolerance, secant: bool = False):
    """The sliders' increments (S,) or (S, 2) [m] that balance their forces with the linear
    step or the imposed path (module docstring) over a step of `dt` [s] (a float, or traced),
    from `guess`, whether |residual| <= `tolerance` [N] was reached, and in two components the
    sliders' (forces, Z) there (`None` in one); the iteration by the shape of `guess` (one
    component: `_iterate_line`; two: `_iterate_plane`, with Broyden's first stage where
    `secant`, whose last evaluation of the forces is the one returned: none is repeated after
    the loop); differentiated implicitly (`solver.implicit_root`) with exact slopes, whichever
    way the root was iterated."""
    if guess.ndim == 1:
        d, converged = implicit_root(functools.partial(_iterate_line, iterations), _balance_residual, _line_solve,
                                     {**p, "dt": dt}, guess, tolerance)
        return d, converged, None
    d, (converged, evaluation) = implicit_root(
        functools.partial(_iterate_plane, iterations, secant), _balance_residual, _plane_solve, {**p, "dt": dt},
        guess, tolerance, outputs=_flagged_forces)
    return d, converged, evaluation


def _flagged_forces(d, p):
    """(a flag, (forces, Z)) at the increments `d`: the planar balance's outputs, the forces
    and Z differentiated along the root's tangent (`implicit_root`; the flag carries none)."""
    return jnp.array(True), balance_forces(p, d, p["dt"])


def _balance_residual(d, p):
    """F_e(d_e) - F(d), F(d) the force the linear step or the imposed path leaves
    (`carried_force`), with the step's length in `p["dt"]`."""
    force, _ = balance_forces(p, d, p["dt"])
    return force - carried_force(d, force, p)


# --------------------------------------------------------------------------- one component


def _residual_and_slopes(d, p):
    """(residual (S,), dF_e/dd_e (S,)): each slider's force depends on its own increment."""
    def forces(x):
        return balance_forces(p, x, p["dt"])[0]

    force, slope = jax.jvp(forces, (d,), (jnp.ones_like(d),))
    return force - carried_force(d, force, p), slope


def _iterate_line(iterations, p, guess, tolerance):
    """One component: one slider's balance bracketed (`bracketed_newton`), several sliders'
    by `damped_newton` with J^-1 r by Sherman-Morrison, the slopes floored by the pendulum's
    own N / R_e under the step's normal load N (W / R_e at uplift, where the increments are
    shared out afterwards: `uplift_increments`). A floor of W / R_e under a light load (N a
    few per cent of W just after landing) shortens every step by N / W and leaves the balance
    unconverged."""
    floor = floor_stiffnesses(p["pendulum"], jnp.where(p["N"] > 0, p["N"], p["W"]))

    def evaluate(d):
        r, k = _residual_and_slopes(d, p)
        return r, jnp.sum(r**2), sherman_morrison(r, jnp.maximum(k, floor), balance_compliance(p))

    if guess.shape[0] == 1 and "G" in p:  # one slider: bracketed (`bracketed_newton`)
        return bracketed_newton(lambda d: evaluate(d)[::2], guess, tolerance, iterations + RESCUE_ITERATIONS)[:2]
    return damped_newton(evaluate, guess, tolerance, iterations)[:2]


def _line_solve(d, p, r, dp):
    """J^-1 r at the root d for J = diag(k_e) + 1 1^T / G (`sherman_morrison`), k_e the
    sliders' exact slopes dF_e/dd_e (several sliders: floored by W / R_e where not positive,
    which happens only at uplift; one slider keeps its slope: G k + 1 > 0 where its balance has
    a root). An imposed path (no G in `p`) holds sum d = D outside the residual: that
    constraint's tangent -dD is shared as the sliders' compliances 1 / k_e (all of it on one
    slider)."""
    _, slope = _residual_and_slopes(d, p)
    if d.shape[0] > 1:
        slope = jnp.where(slope > 0, slope, floor_stiffnesses(p["pendulum"], p["W"]))
    direction = sherman_morrison(r, slope, balance_compliance(p))
    if "G" not in p and d.shape[0] == 1:
        return direction - dp["D"]
    if "G" not in p:
        return direction - dp["D"] / slope / jnp.sum(1.0 / slope)
    return direction


# --------------------------------------------------------------------------- two components


def _exact_blocks(d, p):
    """dF_e/dd_e (S, 2, 2) at the increments `d` (`balance_forces` with `blocks`); the
    pendulum's (W / R_e) I at uplift."""
    return loaded_blocks(balance_forces(p, d, p["dt"], blocks=True)[2], p)


def loaded_blocks(blocks, p):
    """`blocks` where the sliders carry a load, the pendulum's (W / R_e) I at uplift."""
    return jnp.where(p["N"] > 0, blocks, pendulum_blocks(p))


def secant_floors(d, p):
    """h = `SECANT_FLOOR` (Y + max |d_e|) (S,) [m] of each slider."""
    return SECANT_FLOOR * (p["pendulum"].hysteresis.yield_disp + jnp.max(jnp.abs(d), axis=-1))


def pendulum_blocks(p):
    """(W / R_e) I (S, 2, 2): the sliders' pendulum stiffnesses (`floor_stiffnesses`), Newton's
    matrix at uplift."""
    return floor_stiffnesses(p["pendulum"], p["W"])[:, None, None] * jnp.eye(2, dtype=p["s0"].dtype)


def planar_iteration(p, guess, tolerance, iterations: int, secant: bool = False):
    """`planar_newton` on the sliders' planar balance, with the step's length in `p["dt"]`:
    every evaluation of the forces brings their exact 2 x 2 blocks (`balance_forces` with
    `blocks`; the pendulum's own (W / R_e) I where they give no finite direction), J^-1 r by
    Woodbury; with `secant`, the forces alone and Broyden's update of the first blocks
    (`broyden_blocks`, within `secant_floors` of a point a block is kept), the blocks evaluated
    again where Newton's stage takes over.

    **Returns:** (d, converged, the number of Newton steps taken, (forces, Z) at d)."""
    dt = p["dt"]

    def forces(d):  # the secant stage needs the forces alone
        return balance_forces(p, d, dt, blocks=not secant)

    def blocks(d, evaluation):  # the evaluation's own, or (the secant's forces alone) evaluated here
        exact = balance_forces(p, d, dt, blocks=True)[2] if secant else evaluation[2]
        return loaded_blocks(exact, p)

    def residual(d, evaluation):
        return evaluation[0] - carried_force(d, evaluation[0], p)

    def direction(r, blocks):
        found = woodbury(r, blocks, balance_compliance(p))
        fallback = woodbury(r, pendulum_blocks(p), balance_compliance(p))
        return jnp.where(jnp.all(jnp.isfinite(found)), found, fallback)

    def update(blocks, step, change, d):
        return broyden_blocks(blocks, step, change, secant_floors(d, p))

    d, converged, taken, evaluation = planar_newton(
        forces, residual, direction, blocks, guess, tolerance, iterations, secant=update if secant else None)
    return d, converged, taken, evaluation[:2]


def _iterate_plane(iterations, secant, p, guess, tolerance):
    """`planar_iteration`: (d, (converged, (forces, Z) at d))."""
    d, converged, _, evaluation = planar_iteration(p, guess, tolerance, iterations, secant)
    return d, (converged, evaluation)


def _plane_solve(d, p, r, dp):
    """J^-1 r at the root d for J = blockdiag(K_e) + U U^T / G (`woodbury`), K_e the exact
    2 x 2 blocks (`_exact_blocks`). An imposed path (no G in `p`) holds sum d = D outside the
    residual: that constraint's tangent -dD is shared as C_e (sum C)^-1, C_e = K_e^-1 (all of
    it on one slider)."""
    blocks = _exact_blocks(d, p)
    direction = woodbury(r, blocks, balance_compliance(p))
    if "G" not in p and d.shape[0] == 1:
        return direction - dp["D"][None]
    if "G" not in p:
        c = inverse2(blocks)
        return direction - jnp.einsum("eij,j->ei", c, inverse2(jnp.sum(c, 0)) @ dp["D"])
    return direction
