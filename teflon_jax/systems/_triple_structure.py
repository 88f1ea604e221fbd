"""A structure isolated on friction pendulums of sliders in series, in one horizontal direction.

The bearings are the series model of a `SeriesPendulum`: S sliders carry one force F and their
displacements add up to the isolator's; three for the `TriplePendulum` (the inner pair, the
bottom and the top surface; Fenz & Constantinou 2008), two for the `DoublePendulum` (bottom and
top; Fenz & Constantinou 2006), one for the `SinglePendulum` (a single pendulum, or a flat
slider at R = inf, on any linear structure: `structure_on_isolator`). Slider e carries

    F_e = W (s_e / R_e + mu_e(v_e) Z_e + k_stop <|s_e| - d_e>_+ sgn(s_e) / R_e),

with R_e, d_e its radius and capacity (`series_radii`, `series_capacities`), Z_e from
Bouc-Wen updated exactly along the step's increment, mu_e from Eq. 1 at the surface's mean
velocity over the step, v_e = |increment| c_e / dt (`velocity_factors`; the velocity OpenSees'
`TripleFrictionPendulum` takes too) where the slider moves the way its Z points, and f_min
(Eq. 1 at rest) while Z still points back after a reversal (`slider_forces`). Without that
exception the force of a slider reversing would fall as its increment grows (Eq. 1's rise with
|increment| against Z's elastic slope, for steps below a few ms): the massless sliders of the
series model would have no unique balance. The restrainer of stiffness `STOP_STIFFNESS_RATIO`
W / R_e beyond the capacity. The linear structure carries a reference spring W / R_ref at the
isolator (R_ref = `reference_radius()`: b + c of the triple, R_1 + R_2 of the double), and the
step solves for the part of F beyond it. With a vertical ground acceleration a_v (up +) every
slider's force is taken under the normal load N = s W, s = max(1 + a_v / g, 0) at the end of
the step (as the flat sliders, the single pendulum and the slab take it); at s = 0
(uplift) the sliders carry nothing and share the isolator's increment as their pendulum
stiffnesses W / R_e in series would (d_e proportional to R_e), Z following their motion.

Each step solves for the sliders' increments d_e: F_e(d_e) equal to the force the
linear step leaves, F = (D - sum d_e) / G, with D the isolator's increment without the bearing
and G its compliance over the step (the structure's exact step, `_propagators.py`). Newton's
matrix diag(k_e) + 1 1^T / G (k_e = dF_e/dd_e) is inverted in closed form (Sherman-Morrison),
with a halving line search on the force residual, continued with much shorter steps where a
slider's reversal kink makes Newton's step overshoot (`damped_newton`); one slider's balance
is bracketed instead (`bracketed_newton`). The root is differentiated implicitly. A one-surface
isolator may take Eq. 1 at the isolator's velocity at the step's end, the flat sliders' law
(`friction_velocity="end"`, `FRICTION_VELOCITIES`).
"""

import functools

import equinox as eqx
import jax
import jax.numpy as jnp

from ..bearing import SeriesPendulum
from ..excitation import Signal
from ..solver import implicit_root
from ..units import STANDARD_GRAVITY
from ._isolator_solve import bracketed_newton
from ._response import StructureResponse
from ._slider_forces import (
    FRICTION_VELOCITIES,
    balance_forces,
    end_velocity,
    floor_stiffnesses,
    heated_step,
    initial_history,
    next_history,
    series_heat_kernel,
    slider_lengths,
    step_history,
)
from ._structure import StructureOnSliders
from ._structure_build import check_duration, rigid_mass, six_storey_building
from ._vertical import load_factor_at, uplift_steps

TRIPLE_NEWTON_ITERATIONS = 60
"""Most evaluations of the sliders' forces per step (Newton iterations and line-search halvings)."""

TRIPLE_TOLERANCE = 1e-9
"""Default `StructureOnTriple.newton_tolerance`: the sliders' force imbalance over the weight W."""

SMALLEST_STEP = 1.0 / 64
"""Shortest fraction of a Newton step the line search tries; it is then taken as it is."""

RESCUE_ITERATIONS = 120
"""Most further evaluations of the sliders' forces in a step whose balance the first
`newton_iterations` left short (the line search's second stage)."""

RESCUE_SMALLEST = 2.0**-40
"""Shortest fraction of a Newton step the second stage tries before it takes it as it is: where
a slider's force has a kink (Z's elastic slope on a reversal against W / R_e while it slides),
a full Newton step from the sliding side overshoots the root by up to the ratio of the slopes
(mu R_e / Y, ~10^3), and only a short enough one lowers the imbalance."""


class StructureOnTriple(eqx.Module):
    """A linear structure (rigid mass or building; DOF 0 the isolator) on triple or double
    friction pendulums of total normal load W (module docstring), stepped by the exact linear
    rule.

    **Fields:** `linear`: the `StructureOnSliders` without friction whose stiffness holds the
    reference spring W / R_ref at DOF 0 (its `exact_step` the step's matrices); `pendulum`: the
    `SeriesPendulum` (`TriplePendulum` or `DoublePendulum`; also read as `triple`);
    `reference_stiffness` W / R_ref [N/m]; `newton_iterations` (static);
    `newton_tolerance` (static) [-]: the force imbalance at which a step stops, over W;
    `vertical_acceleration`: `Signal` of a_v(t) [m/s^2, up +] or `None` (N = W throughout);
    `heat_rates`, `heat_weights`: the 1/sqrt(t) kernel (`heat_kernel_exponentials`, one step
    to `HEAT_HORIZON`) of a pendulum with heated surfaces (`SeriesPendulum.heated`), else `None`;
    `friction_velocity` (static): the velocity of Eq. 1 (`FRICTION_VELOCITIES`), "mean" or,
    for one surface, "end".
    """

    linear: StructureOnSliders
    pendulum: SeriesPendulum
    reference_stiffness: jnp.ndarray
    newton_iterations: int = eqx.field(static=True, default=TRIPLE_NEWTON_ITERATIONS)
    newton_tolerance: float = eqx.field(static=True, default=TRIPLE_TOLERANCE)
    vertical_acceleration: Signal | None = None
    heat_rates: jnp.ndarray | None = None
    heat_weights: jnp.ndarray | None = None
    friction_velocity: str = eqx.field(static=True, default="mean")

    def load_factor(self, t):
        """N / W = max(1 + a_v(t) / g, 0) at time t [s] (None without a vertical record)."""
        return load_factor_at(self.vertical_acceleration, t)

    @property
    def triple(self) -> SeriesPendulum:
        """The isolator (`pendulum`), under the name the triple pendulum gave it first."""
        return self.pendulum

    @property
    def mass(self):
        return self.linear.mass

    @property
    def stiffness(self):
        return self.linear.stiffness

    @property
    def damping(self):
        return self.linear.damping

    @property
    def time_step(self) -> float:
        return self.linear.time_step

    @property
    def ground_acceleration(self) -> Signal:
        return self.linear.ground_acceleration

    @property
    def bearing_load(self):
        return self.linear.bearing_load

    def step_matrices(self):
        """(R, f) of the linear step (`StructureOnSliders.step_matrices`)."""
        return self.linear.step_matrices()

    def initial_isolator(self):
        """The isolator's state at rest: (slider displacements (S,) [m], Z (S,), the increments
        of the last two steps (2, S) [m] (`predicted_increments`), the force beyond the
        reference spring [N]), for heated surfaces the heat kernel's states (S, K) [W s/m^2],
        and last, where a surface's part needs it, the sliders' history (`initial_history`)."""
        zeros = jnp.zeros(self.pendulum.slider_count, self.mass.dtype)
        state = zeros, zeros, jnp.stack([zeros, zeros]), jnp.zeros((), self.mass.dtype)
        if self.pendulum.heated:
            state = state + (jnp.zeros((self.pendulum.slider_count, self.heat_rates.shape[0]), self.mass.dtype),)
        if self.pendulum.remembers:  # the sliders' history last (`initial_history`)
            state = state + (initial_history(self.pendulum, zeros.shape, zeros.dtype),)
        return state

    def step(self, x0, isolator, ground0, ground1, matrices=None, load=None):
        """One step: (u1, v1) (2n,) and the isolator's state at its end, from (u0, v0) `x0`,
        the isolator's state (`initial_isolator`) and the ground acceleration [m/s^2] at both
        ends, under the normal load `load` W held over the step (`None`: W); also whether the
        sliders' balance converged and the bearing force F [N]. Heated surfaces take their
        friction factors at the step's start and hold them over it (`heated_step`)."""
        step_matrix, force_column = self.step_matrices() if matrices is None else matrices
        linear = step_matrix @ jnp.concatenate([x0, jnp.stack([ground0, isolator[3], ground1])])
        n = self.mass.shape[-1]
        state, converged, bearing = isolator_step(self, isolator, linear[0], x0[0], -force_column[0], load,
                                                  _balanced_increments, (linear[n], force_column[n]))
        return linear + force_column * state[3], state, converged, bearing


def isolator_step(system: StructureOnTriple, isolator, linear, start, compliance, load, solve, velocity=None):
    """The isolator's part of a step in one component (arrays (S,)) or two ((S, 2)): the
    sliders' increments that balance their forces with the linear step, whose isolator
    displacement is `linear` [m] at the end without the force beyond the reference spring and
    `start` at the step's start, with that force's compliance `compliance` [m/N]; `load` N / W
    at the step's end (`None`: W); `solve` the balance (`_balanced_increments` in one
    component, the planar one in two); `velocity`: (the isolator's velocity at the end
    without that force [m/s], its change per unit force [m/(N s)]), which the law "end" reads
    (`end_velocity`).

    **Returns:** (the isolator's state at the end (`initial_isolator`), whether the balance
    converged, the bearing force F [N])."""
    pendulum, weight, dt = system.pendulum, system.bearing_load, system.time_step
    slider0, z0, previous = isolator[:3]
    scale = 1 - compliance * system.reference_stiffness  # the step without the reference spring: x = X - G F
    p = {"pendulum": pendulum, "W": weight, "N": weight if load is None else load * weight, "s0": slider0,
         "z0": z0, "D": linear / scale - start, "G": compliance / scale}
    if system.friction_velocity == "end":
        p["v"] = end_velocity(*velocity, start, p["D"], p["G"], system.reference_stiffness)
    if pendulum.heated:
        p["k"] = pendulum.heat_factors(isolator[4], system.heat_weights)
    if pendulum.remembers:
        p["history"] = step_history(isolator[-1], z0)
    if load is not None:
        p["s"] = load
    eps = jnp.finfo(slider0.dtype).eps  # F = (D - sum d) / G is known to eps |D| / G at best
    tolerance = jnp.maximum(system.newton_tolerance * weight,
                            32 * eps * (weight + jnp.max(jnp.abs(p["D"])) / p["G"]))
    d, converged = solve(dt, system.newton_iterations, p, predicted_increments(previous), tolerance)
    if load is not None:
        d, converged = uplift_increments(pendulum, load, p["D"], d, converged)
    force, z1 = balance_forces(p, d, dt)
    bearing = jnp.mean(force, axis=0)  # equal to rounding
    extra1 = bearing - system.reference_stiffness * (start + jnp.sum(d, axis=0))
    state = (slider0 + d, z1, jnp.stack([d, previous[0]]), extra1)
    if pendulum.heated:
        slide = jnp.abs(d) if d.ndim == 1 else slider_lengths(d)
        state = state + (heated_step(pendulum, isolator[4], p["k"], slide, dt, system.heat_rates,
                                     1.0 if load is None else load),)
    if pendulum.remembers:
        state = state + (next_history(pendulum, p["history"], d),)
    return state, converged, bearing


def triple_structure(kind: str, pendulum: SeriesPendulum, ground_acceleration: Signal, *, time_step: float,
                     weight=100e3, newton_iterations: int = TRIPLE_NEWTON_ITERATIONS,
                     newton_tolerance: float = TRIPLE_TOLERANCE, friction_velocity: str = "mean") -> StructureOnTriple:
    """The rigid mass of `weight` W [N] ("rigid") or the Table 2 building ("building", W its
    total weight) on the friction pendulums `pendulum` (a `TriplePendulum`, `DoublePendulum` or
    `SinglePendulum`, to be checked first: `check_series_pendulum`), with no viscous damping
    and no spring at the isolator but the reference spring W / R_ref (none on a flat slider),
    stepped by the exact linear rule at `time_step` [s]; `friction_velocity`:
    `StructureOnTriple`'s. A structure with its own springs and dampers at the isolator:
    `structure_on_isolator`."""
    reference = pendulum.reference_radius()
    if kind == "rigid":
        linear = rigid_mass(weight=weight, bearing=None, ground_acceleration=ground_acceleration,
                            time_step=time_step, radius=reference, friction_model="none",
                            linear_rule="exact")
    else:
        period = 2 * jnp.pi * jnp.sqrt(reference / STANDARD_GRAVITY)
        linear = six_storey_building(bearing=None, ground_acceleration=ground_acceleration,
                                     time_step=time_step, isolation_period=period, isolation_damping=0.0,
                                     friction_model="none", linear_rule="exact")
    return structure_on_isolator(linear, pendulum, newton_iterations=newton_iterations,
                                 newton_tolerance=newton_tolerance, friction_velocity=friction_velocity)


def structure_on_isolator(linear: StructureOnSliders, pendulum: SeriesPendulum, *,
                          newton_iterations: int = TRIPLE_NEWTON_ITERATIONS, newton_tolerance: float = TRIPLE_TOLERANCE,
                          friction_velocity: str = "mean") -> StructureOnTriple:
    """The linear structure `linear` (a `StructureOnSliders`, stepped by its `linear_rule`; its
    friction is not read) on the isolator `pendulum`, whose surfaces' forces beyond the
    reference spring W / R_ref (`reference_radius`; 0 on a flat slider) enter each step.
    `linear`'s stiffness at the isolator holds that spring and whatever else acts there (a flat
    slider's restoring springs, a viscous damper), as `rigid_mass` and `six_storey_building`
    build them for the flat sliders and the single pendulum; its vertical record, if any,
    loads the surfaces. `friction_velocity` (`FRICTION_VELOCITIES`): "end" needs one surface
    (`ValueError` naming it otherwise)."""
    if friction_velocity not in FRICTION_VELOCITIES:
        raise ValueError(f"friction_velocity: unknown {friction_velocity!r}; accepted: {', '.join(FRICTION_VELOCITIES)}.")
    if friction_velocity == "end" and pendulum.slider_count != 1:
        raise ValueError(f"friction_velocity: 'end' reads the isolator's own velocity, which only a one-surface "
                         f"isolator's slider has; the {pendulum.description} have {pendulum.slider_count} sliders.")
    heat = series_heat_kernel(pendulum, linear.time_step)
    return StructureOnTriple(linear=linear, pendulum=pendulum,
                             reference_stiffness=linear.bearing_load / pendulum.reference_radius(),
                             newton_iterations=int(newton_iterations), newton_tolerance=float(newton_tolerance),
                             vertical_acceleration=linear.vertical_acceleration,
                             heat_rates=heat[0], heat_weights=heat[1], friction_velocity=friction_velocity)


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


def _residual(d, p, dt):
    """F_e(d_e) - F(d), F(d) the force the linear step or the imposed path leaves
    (`carried_force`)."""
    force, _ = balance_forces(p, d, dt)
    return force - carried_force(d, force, p)


def _residual_and_slopes(d, p, dt):
    """(residual (S,), dF_e/dd_e (S,)): each slider's force depends on its own increment."""
    def forces(x):
        return balance_forces(p, x, dt)[0]

    force, slope = jax.jvp(forces, (d,), (jnp.ones_like(d),))
    return force - carried_force(d, force, p), slope


def _newton_direction(residual, slope, compliance):
    """J^-1 r for J = diag(slope) + 1 1^T / G (Sherman-Morrison): c (r - s), c = 1 / slope,
    s = sum(c r) / (G + sum c). At G = 0 (an imposed path) the step keeps sum d. One slider:
    G r / (G k + 1), without the cancellation of c (r - s) where its slope k is small (a flat
    slider sliding)."""
    if residual.shape[0] == 1:
        return compliance * residual / (compliance * slope + 1)
    c = 1.0 / slope
    return c * (residual - jnp.sum(c * residual) / (compliance + jnp.sum(c)))


def _balanced_increments(dt, iterations: int, p, guess, tolerance):
    """The sliders' increments (S,) [m] that balance their forces with the linear step (module
    docstring) over a step of `dt` [s] (a float, or traced), from `guess`, and whether
    |residual| <= `tolerance` [N] was reached; differentiated implicitly
    (`solver.implicit_root`, `_balance_solve`)."""
    return implicit_root(functools.partial(_iterate_balance, iterations), _balance_residual, _balance_solve,
                         {**p, "dt": dt}, guess, tolerance)


def _iterate_balance(iterations, p, guess, tolerance):
    """`_balanced_increments`' iteration, with the step's length in `p["dt"]`: one slider's
    balance bracketed (`bracketed_newton`), several sliders' by `damped_newton`."""
    dt = p["dt"]
    floor = floor_stiffnesses(p["pendulum"], p["W"])  # the pendulum's own stiffness, a floor of the slope

    def evaluate(d):
        r, k = _residual_and_slopes(d, p, dt)
        return r, jnp.sum(r**2), _newton_direction(r, jnp.maximum(k, floor), balance_compliance(p))

    if guess.shape[0] == 1 and "G" in p:  # one slider: bracketed (`bracketed_newton`)
        return bracketed_newton(lambda d: evaluate(d)[::2], guess, tolerance, iterations + RESCUE_ITERATIONS)
    return damped_newton(evaluate, guess, tolerance, iterations)


def _balance_residual(d, p):
    """`_residual` with the step's length in `p["dt"]`."""
    return _residual(d, p, p["dt"])


def _balance_solve(d, p, r, dp):
    """J^-1 r at the root d for J = diag(k_e) + 1 1^T / G (`_newton_direction`), k_e the
    sliders' exact slopes dF_e/dd_e (several sliders: floored by W / R_e where not positive,
    which happens only at uplift; one slider keeps its slope: G k + 1 > 0 where its balance has
    a root). An imposed path (no G in `p`) holds sum d = D outside the residual: that
    constraint's tangent -dD is shared as the sliders' compliances 1 / k_e (all of it on one
    slider)."""
    _, slope = _residual_and_slopes(d, p, p["dt"])
    if d.shape[0] > 1:
        slope = jnp.where(slope > 0, slope, floor_stiffnesses(p["pendulum"], p["W"]))
    direction = _newton_direction(r, slope, balance_compliance(p))
    if "G" not in p and d.shape[0] == 1:
        return direction - dp["D"]
    if "G" not in p:
        return direction - dp["D"] / slope / jnp.sum(1.0 / slope)
    return direction


def damped_newton(evaluate, guess, tolerance, iterations: int, *, finite_direction: bool = False):
    """Newton's iteration with step halving: from `guess`, steps d <- d - f dir with f halved
    until the merit sum(r^2) falls (or f reaches `SMALLEST_STEP`; also until the new direction
    is finite where `finite_direction`), while max |r| > `tolerance` and fewer than `iterations`
    steps were taken. `evaluate(d)` returns (residual r, merit, direction J^-1 r). Where that
    leaves the balance short, at most `RESCUE_ITERATIONS` more steps halve f down to
    `RESCUE_SMALLEST` (`shortest_fraction`); a step balanced within `iterations` is as before.

    **Returns:** (d, whether max |r| <= tolerance)."""
    def cond(carry):
        _, (r, _, _), _, k = carry
        return (jnp.max(jnp.abs(r)) > tolerance) & (k < iterations + RESCUE_ITERATIONS)

    def body(carry):
        d, (r, merit, direction), fraction, k = carry
        trial = d - fraction * direction
        new = evaluate(trial)
        lower = new[1] < merit
        if finite_direction:
            lower = lower & jnp.all(jnp.isfinite(new[2]))
        accept = lower | (fraction <= shortest_fraction(k, iterations))
        d = jnp.where(accept, trial, d)
        values = tuple(jnp.where(accept, a, b) for a, b in zip(new, (r, merit, direction)))
        return d, values, jnp.where(accept, 1.0, 0.5 * fraction), k + 1

    carry = (guess, evaluate(guess), jnp.ones((), guess.dtype), 0)
    d, (r, _, _), _, _ = jax.lax.while_loop(cond, body, carry)
    return d, jnp.max(jnp.abs(r)) <= tolerance


def shortest_fraction(k, iterations: int):
    """The fraction of a Newton step the line search takes as it is at evaluation `k`:
    `SMALLEST_STEP` within the first `iterations`, `RESCUE_SMALLEST` after them."""
    return jnp.where(k < iterations, SMALLEST_STEP, RESCUE_SMALLEST)


def total_acceleration(system: StructureOnTriple, x, extra):
    """Total accelerations (n,) [m/s^2] of the masses at state `x` = (u, v) with the force
    `extra` [N] beyond the reference spring at the isolator: -(K u + C v + e0 extra) / m."""
    n = system.mass.shape[-1]
    force = system.stiffness @ x[:n] + system.damping @ x[n:]
    return -force.at[0].add(extra) / system.mass


def simulate_triple_structure(system: StructureOnTriple, duration: float) -> StructureResponse:
    """Integrate `system` from rest over `duration` [s] (rounded down to whole steps) and keep
    every step. jit/vmap/grad-safe.

    **Returns:** a `StructureResponse` (one ground component): the isolator's `bearing_force`
    (nt,) [N], its sliders' `slider` and `z` (nt, S), `converged` (nt,); with a vertical record
    `load_factor` (nt,) (a step holds its start's) and `uplift_time` [s]."""
    dt = float(system.time_step)
    n_steps = check_duration(system, duration)
    n = system.mass.shape[-1]
    time = jnp.arange(n_steps + 1) * dt
    ground = jax.vmap(system.ground_acceleration)(time)
    matrices = system.step_matrices()
    loads = None if system.vertical_acceleration is None else jax.vmap(system.load_factor)(time)

    def body(carry, grounds):
        x, isolator = carry
        x1, isolator1, converged, force = system.step(x, isolator, grounds[0], grounds[1], matrices, grounds[2])
        out = (x1, force, isolator1[0], isolator1[1], converged,
               total_acceleration(system, x1, isolator1[3]))
        return (x1, isolator1), out

    x0 = jnp.zeros(2 * n, system.mass.dtype)
    start = (x0, system.initial_isolator())
    _, (x, force, slider, z, converged, acc) = jax.lax.scan(
        body, start, (ground[:-1], ground[1:], None if loads is None else loads[1:]))

    def first(a, b):
        return jnp.concatenate([a[None], b])

    zeros_s = jnp.zeros(system.pendulum.slider_count, x0.dtype)
    return StructureResponse(
        time=time, displacement=first(x0[:n], x[:, :n]), velocity=first(x0[n:], x[:, n:]),
        total_acceleration=first(jnp.zeros(n, x0.dtype), acc), ground=ground[:, None],
        bearing_force=first(jnp.zeros(()), force), slider=first(zeros_s, slider), z=first(zeros_s, z),
        converged=first(jnp.array(True), converged), load_factor=loads,
        uplift_time=None if loads is None else uplift_steps(system, n_steps) * dt)
