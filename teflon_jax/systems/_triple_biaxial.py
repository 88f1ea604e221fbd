"""A structure on triple or double friction pendulums under two horizontal ground components.

The structure is the same in x and in y (the rigid mass, or the Table 2 building along each
axis), so the linear step of `StructureOnTriple` advances both directions, and the bearings
couple them: each slider's displacement, Z and force are vectors in the plane. Slider e carries

    F_e = W (s_e / R_e + f_min Z_e + (mu_e(v_e) - f_min) <n_e . Z_e>_+ n_e + stop),

with Z_e from Park's biaxial Bouc-Wen model (Eqs. 8-9, updated exactly along the step's
straight increment), n_e the direction of the increment, v_e its mean speed over the step times
the surface's factor, and the restrainer along the slider's displacement beyond its capacity:
one law in one and two components, `_slider_forces.slider_forces`. Each step solves the S sliders'
increments (S, 2) so that every F_e equals F = (D - sum d_e) / G, D the isolator's increment
(2,) without the bearing and G its compliance: Newton's matrix, blockdiag(K_e) + (1/G) U U^T
with 2 x 2 blocks K_e (one-sided differences in the iteration, exact tangents in the
derivative), is inverted by the Woodbury identity, with a halving line search; the root is
differentiated implicitly. Peaks are resultants, as `bidirectional_peak_response`
reads them; a building's storey drifts and level accelerations are kept per direction. The uniaxial structure's vertical record, if any, sets the sliders' normal load
N = s W as in one direction (at s = 0 the sliders share the increment in proportion to R_e,
`uplift_increments`). References:
Fenz & Constantinou (2006, 2008); Park, Wen & Ang (1986).
"""

import functools

import equinox as eqx
import jax
import jax.numpy as jnp

from ..bearing import SeriesPendulum
from ..excitation import Signal
from ..solver import implicit_root
from ._slider_forces import balance_forces, floor_stiffnesses, initial_history
from ._structure_build import check_duration
from ._triple_structure import (
    RESCUE_ITERATIONS,
    StructureOnTriple,
    balance_compliance,
    carried_force,
    isolator_step,
    shortest_fraction,
)

BALANCES = ("newton", "secant")
"""How a step's planar balance is iterated (`BiaxialStructureOnTriple.balance`): "newton",
fresh 2 x 2 blocks by differences at every point (three force evaluations a step); "secant",
Broyden's update of the blocks after the first step (one force evaluation a step, Newton's
iteration taking over where it stalls; `_planar_newton`). Both balance to the same tolerance;
"newton" along one axis follows the one-direction iteration to rounding, "secant" agrees
with it to that tolerance."""


class BiaxialStructureOnTriple(eqx.Module):
    """`StructureOnTriple` (its linear structure in x and in y alike) with the ground's y
    component `ground_y` (module docstring); `balance` (static, `BALANCES`): how each step's
    balance is iterated (`ValueError` naming it if unknown)."""

    uniaxial: StructureOnTriple
    ground_y: Signal
    balance: str = eqx.field(static=True, default="newton")

    def __check_init__(self):
        if self.balance not in BALANCES:
            raise ValueError(f"balance: unknown {self.balance!r}; accepted: {', '.join(BALANCES)}.")

    @property
    def mass(self):
        return self.uniaxial.mass

    @property
    def time_step(self) -> float:
        return self.uniaxial.time_step

    @property
    def pendulum(self) -> SeriesPendulum:
        """The isolator of the one-direction structure."""
        return self.uniaxial.pendulum

    @property
    def triple(self) -> SeriesPendulum:
        """`pendulum`, under the name the triple pendulum gave it first."""
        return self.uniaxial.pendulum

    def ground(self, t):
        """(a_x, a_y) [m/s^2] at time t [s]."""
        return jnp.stack([self.uniaxial.ground_acceleration(t), self.ground_y(t)])

    def initial_isolator(self):
        """(sliders (S, 2) [m], Z (S, 2), the increments of the last two steps (2, S, 2) [m]
        (`predicted_increments`), force beyond the reference spring (2,) [N]), and the heat
        states (S, K) of heated surfaces, and last the sliders' history where a surface's part
        needs it (`initial_history`)."""
        zeros = jnp.zeros((self.pendulum.slider_count, 2), self.mass.dtype)
        state = zeros, zeros, jnp.stack([zeros, zeros]), jnp.zeros(2, self.mass.dtype)
        if self.pendulum.heated:
            state = state + (jnp.zeros((self.pendulum.slider_count, self.uniaxial.heat_rates.shape[0]),
                                       self.mass.dtype),)
        if self.pendulum.remembers:
            state = state + (initial_history(self.pendulum, zeros.shape[:1], zeros.dtype),)
        return state

    def step(self, x0, isolator, ground0, ground1, matrices=None, load=None):
        """One step of both directions: `x0` (2, 2n) = (u, v) in x and in y, the isolator's
        state, the ground (2,) at both ends, the normal load `load` W held over the step
        (`None`: W); returns (x1, isolator, converged, force (2,)). Heated surfaces as in one
        direction (`StructureOnTriple.step`), their flux at the length of their increment."""
        system = self.uniaxial
        step_matrix, force_column = system.step_matrices() if matrices is None else matrices
        w = jnp.concatenate([x0, jnp.stack([ground0, isolator[3], ground1], -1)], -1)
        linear = w @ step_matrix.T
        n = system.mass.shape[-1]
        solve = functools.partial(_balanced, secant=self.balance == "secant")
        state, converged, bearing = isolator_step(system, isolator, linear[:, 0], x0[:, 0], -force_column[0], load,
                                                  solve, (linear[:, n], force_column[n]))
        return linear + state[3][:, None] * force_column, state, converged, bearing


def _residual(d, p, dt):
    force, _ = balance_forces(p, d, dt)
    return force - carried_force(d, force, p)


def _residual_and_blocks(d, p, dt):
    """(residual (S, 2), dF_e/dd_e (S, 2, 2)): a forward pass with the two axes' tangents
    (each slider's force depends on its own increment only)."""
    def forces(x):
        return balance_forces(p, x, dt)[0]

    axes = jnp.broadcast_to(jnp.eye(2, dtype=d.dtype)[:, None, :], (2,) + d.shape)
    force, columns = jax.vmap(lambda t: jax.jvp(forces, (d,), (t,)), out_axes=(None, 0))(axes)
    blocks = jnp.moveaxis(columns, 0, -1)
    return force - carried_force(d, force, p), jnp.where(p["N"] > 0, blocks, _pendulum_blocks(p))


NEWTON_DIFFERENCE_STEP = 2.0**-26
"""Relative step h / (Y + |d_e|) of the one-sided differences that give Newton's 2 x 2 blocks."""


def _differenced_blocks(d, force, p, dt):
    """dF_e/dd_e (S, 2, 2) at the increments `d` (S, 2) whose forces are `force`, from one-sided
    differences along x and y, h = `NEWTON_DIFFERENCE_STEP` (Y + max |d_e|) (relative error
    ~ sqrt(eps)): two evaluations of the forces (each slider's force depends on its own
    increment only). Forward-mode tangents through Park's three segments cost tens of
    evaluations on CPU; Newton's iteration only needs its matrix to about sqrt(eps), the
    balance being judged on the exact residual (the implicit derivative keeps exact blocks)."""
    pendulum = p["pendulum"]
    h = NEWTON_DIFFERENCE_STEP * (pendulum.hysteresis.yield_disp + jnp.max(jnp.abs(d), axis=-1))
    shifted = d + h[:, None]
    steps = shifted - d  # h as the sum represents it
    trials = jnp.stack([jnp.stack([shifted[:, 0], d[:, 1]], -1), jnp.stack([d[:, 0], shifted[:, 1]], -1)])
    forces = jax.vmap(lambda x: balance_forces(p, x, dt)[0])(
        trials)
    blocks = jnp.moveaxis((forces - force) / jnp.moveaxis(steps, -1, 0)[:, :, None], 0, -1)
    return jnp.where(p["N"] > 0, blocks, _pendulum_blocks(p))


def _pendulum_blocks(p):
    """(W / R_e) I (S, 2, 2): the sliders' pendulum stiffnesses (`floor_stiffnesses`), Newton's
    matrix at uplift."""
    return floor_stiffnesses(p["pendulum"], p["W"])[:, None, None] * jnp.eye(2, dtype=p["s0"].dtype)


def _planar_newton(p, dt, guess, tolerance, iterations: int, secant: bool = False):
    """Newton's iteration with step halving on the planar balance: d <- d - f J(d)^-1 r(d),
    J's blocks by differences (`_differenced_blocks`; the pendulum's own (W / R_e) I where they
    give no finite direction), f halved until the merit sum(r^2) falls (or f reaches
    `SMALLEST_STEP`), while max |r| > `tolerance` and fewer than `iterations` steps were
    taken; then, where the balance is still short, at most `RESCUE_ITERATIONS` more steps
    halving f down to `RESCUE_SMALLEST` (as `damped_newton`). Three force evaluations per
    step, one at the start.

    With `secant`, a first stage takes the blocks by differences at `guess` only and after
    each step Broyden's update of each slider's block (`_secant_blocks`): full steps while the
    merit falls, at most min(`SECANT_ITERATIONS`, `iterations`), one force evaluation each;
    Newton's iteration above continues from where it stops short of `tolerance`, counting its
    steps (a vmapped chunk runs it only while one of its lanes needs it).

    **Returns:** (d, whether max |r| <= tolerance, the number of steps taken)."""
    def forces(d):
        return balance_forces(p, d, dt)[0]

    def residual(d, force):
        return force - carried_force(d, force, p)

    def direction_of(r, blocks):
        direction = _woodbury(r, blocks, balance_compliance(p))
        fallback = _woodbury(r, _pendulum_blocks(p), balance_compliance(p))
        return jnp.where(jnp.all(jnp.isfinite(direction)), direction, fallback)

    def trial_of(d, r, merit, step):
        trial = d - step
        force_trial = forces(trial)
        r_trial = residual(trial, force_trial)
        merit_trial = jnp.sum(r_trial**2)
        return merit_trial < merit, (trial, force_trial, r_trial, merit_trial)

    def secant_cond(carry):
        _, _, r, _, _, k, falling = carry
        return falling & (jnp.max(jnp.abs(r)) > tolerance) & (k < min(SECANT_ITERATIONS, iterations))

    def secant_body(carry):
        d, force, r, merit, blocks, k, _ = carry
        lower, new = trial_of(d, r, merit, direction_of(r, blocks))
        blocks = jnp.where(lower, _secant_blocks(blocks, new[0] - d, new[1] - force, d, p), blocks)
        new = tuple(jnp.where(lower, a, b) for a, b in zip(new, (d, force, r, merit)))
        return (*new, blocks, k + 1, lower)

    def cond(carry):
        _, _, r, _, _, k = carry
        return (jnp.max(jnp.abs(r)) > tolerance) & (k < iterations + RESCUE_ITERATIONS)

    def body(carry):
        d, force, r, merit, fraction, k = carry
        lower, new = trial_of(d, r, merit, fraction * direction_of(r, _differenced_blocks(d, force, p, dt)))
        accept = lower | (fraction <= shortest_fraction(k, iterations))
        new = tuple(jnp.where(accept, a, b) for a, b in zip(new, (d, force, r, merit)))
        return (*new, jnp.where(accept, 1.0, 0.5 * fraction), k + 1)

    force = forces(guess)
    r = residual(guess, force)
    d, merit, k = guess, jnp.sum(r**2), 0
    if secant:
        carry = (d, force, r, merit, _differenced_blocks(d, force, p, dt), k, jnp.array(True))
        d, force, r, merit, _, k, _ = jax.lax.while_loop(secant_cond, secant_body, carry)
    d, _, r, _, _, taken = jax.lax.while_loop(cond, body, (d, force, r, merit, jnp.ones((), guess.dtype), k))
    return d, jnp.max(jnp.abs(r)) <= tolerance, taken


SECANT_ITERATIONS = 8
"""Most steps of the secant stage of `_planar_newton` (each one evaluation of the forces)."""


def _secant_blocks(blocks, step, change, d, p):
    """Broyden's update of each slider's block K_e (S, 2, 2) after its increment moved by
    `step` s_e (S, 2) from `d` and its force by `change` y_e (S, 2) (F_e depends on d_e
    alone): K_e + (y_e - K_e s_e) s_e^T / (s_e . s_e), so that K_e s_e = y_e (Broyden 1965);
    a slider whose step is within the differences' own step (`NEWTON_DIFFERENCE_STEP`
    (Y + max |d_e|)), where y_e is mostly rounding, keeps its block."""
    size = jnp.sum(step**2, axis=-1)
    floor = NEWTON_DIFFERENCE_STEP * (p["pendulum"].hysteresis.yield_disp + jnp.max(jnp.abs(d), axis=-1))
    moved = size > floor**2
    miss = change - jnp.einsum("eij,ej->ei", blocks, step)
    update = miss[:, :, None] * step[:, None, :] / jnp.where(moved, size, 1.0)[:, None, None]
    return blocks + jnp.where(moved[:, None, None], update, 0.0)


def _inverse2(m):
    """Inverses of 2 x 2 matrices (..., 2, 2)."""
    det = m[..., 0, 0] * m[..., 1, 1] - m[..., 0, 1] * m[..., 1, 0]
    adjugate = jnp.stack([jnp.stack([m[..., 1, 1], -m[..., 0, 1]], -1),
                          jnp.stack([-m[..., 1, 0], m[..., 0, 0]], -1)], -2)
    return adjugate / det[..., None, None]


def _woodbury(residual, blocks, compliance):
    """J^-1 r for J = blockdiag(K_e) + U U^T / G: C_e (r_e - s), C_e = K_e^-1,
    s = (G I + sum C_e)^-1 sum C_e r_e. One slider: (G K + I)^-1 G r, without the
    cancellation of C (r - s) where K is near singular (a flat slider's along its sliding)."""
    if residual.shape[0] == 1:
        eye = jnp.eye(2, dtype=residual.dtype)
        return jnp.einsum("eij,ej->ei", _inverse2(compliance * blocks + eye), compliance * residual)
    c = _inverse2(blocks)
    cr = jnp.einsum("eij,ej->ei", c, residual)
    s = _inverse2(compliance * jnp.eye(2, dtype=residual.dtype) + jnp.sum(c, 0)) @ jnp.sum(cr, 0)
    return cr - jnp.einsum("eij,j->ei", c, s)


def _balanced(dt, iterations: int, p, guess, tolerance, secant: bool = False):
    """The sliders' increments (S, 2) [m] that balance their forces with the linear step over
    a step of `dt` [s] (a float, or traced), and whether the balance met `tolerance` [N]
    (`_planar_newton`, with its secant stage where `secant`); differentiated implicitly
    (`solver.implicit_root`), with exact blocks, whichever way the root was iterated
    (`_balance_solve`)."""
    return implicit_root(functools.partial(_iterate_balance, iterations, secant), _balance_residual, _balance_solve,
                         {**p, "dt": dt}, guess, tolerance)


def _iterate_balance(iterations, secant, p, guess, tolerance):
    """`_planar_newton` with the step's length in `p["dt"]`: (d, converged)."""
    return _planar_newton(p, p["dt"], guess, tolerance, iterations, secant)[:2]


def _balance_residual(d, p):
    """`_residual` with the step's length in `p["dt"]`."""
    return _residual(d, p, p["dt"])


def _balance_solve(d, p, r, dp):
    """J^-1 r at the root d for J = blockdiag(K_e) + U U^T / G (`_woodbury`), K_e the exact
    2 x 2 blocks (`_residual_and_blocks`). An imposed path (no G in `p`) holds sum d = D
    outside the residual: that constraint's tangent -dD is shared as C_e (sum C)^-1,
    C_e = K_e^-1 (all of it on one slider)."""
    _, blocks = _residual_and_blocks(d, p, p["dt"])
    direction = _woodbury(r, blocks, balance_compliance(p))
    if "G" not in p and d.shape[0] == 1:
        return direction - dp["D"][None]
    if "G" not in p:
        c = _inverse2(blocks)
        return direction - jnp.einsum("eij,j->ei", c, _inverse2(jnp.sum(c, 0)) @ dp["D"])
    return direction


def held_loads(structure, n_steps: int):
    """N / W (n_steps,) of each step (at its end) of the structure's vertical record
    (`StructureOnTriple.load_factor`; `check_duration` checked it lasts), or `None`."""
    if structure.vertical_acceleration is None:
        return None
    return jax.vmap(structure.load_factor)(jnp.arange(1, n_steps + 1) * float(structure.time_step))


def biaxial_histories(system: BiaxialStructureOnTriple, duration: float):
    """Histories from rest over `duration` [s]: (time (nt,), x (nt, 2, 2n) = (u, v) in x and
    y, bearing force (nt, 2) [N], sliders (nt, S, 2) [m], total accelerations (nt, 2, n)
    [m/s^2], converged (nt,)). jit/vmap-safe."""
    dt = float(system.time_step)
    n_steps = check_duration(system.uniaxial, duration)
    n = system.mass.shape[-1]
    time = jnp.arange(n_steps + 1) * dt
    ground = jax.vmap(system.ground)(time)
    matrices = system.uniaxial.step_matrices()
    linear = system.uniaxial

    def acceleration(x, extra):
        force = x[:, :n] @ linear.stiffness.T + x[:, n:] @ linear.damping.T
        return -force.at[:, 0].add(extra) / linear.mass

    def body(carry, grounds):
        x, isolator = carry
        x1, isolator1, ok, force = system.step(x, isolator, grounds[0], grounds[1], matrices, grounds[2])
        return (x1, isolator1), (x1, force, isolator1[0], acceleration(x1, isolator1[3]), ok)

    start = (jnp.zeros((2, 2 * n), system.mass.dtype), system.initial_isolator())
    _, out = jax.lax.scan(body, start, (ground[:-1], ground[1:], held_loads(linear, n_steps)))
    first = (start[0], jnp.zeros(2), jnp.zeros((system.pendulum.slider_count, 2)), jnp.zeros((2, n)), jnp.array(True))
    return (time, *(jnp.concatenate([a[None], b]) for a, b in zip(first, out)))
