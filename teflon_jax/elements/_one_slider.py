"""The one slider of a flat-slider or single-pendulum structure, solved for the isolator's
displacement.

A `StructureOnSliders` on a `SlidingBearing` (`bearing_force` to `predicted_root`): its
equilibrium at the end of a step is solved for the isolator's displacement,
x = u_linear - g0 F(x) (Newmark's rule or the exact linear rule,
`structures.newmark_step_matrices`, `structures.exact_step_matrices`), with
F = mu(v) W Z the bearing force at the end of the step, v its velocity there (linear in x,
`isolator_end_velocity`) and Z updated exactly along the step's path (`bearing_force`), by the
bracketed Newton iteration (`solver.bracketed_newton`) with written-out slopes, differentiated
implicitly (`isolator_root`); Eqs. 1, 3 and 17 of Constantinou, Mokha & Reinhorn (1990). The
one-surface isolator of the series engine solves its slider's balance by the same iteration,
its bracket found on the way.

References: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 3 and 17.
"""

import functools

import jax
import jax.numpy as jnp

from ..bearing import bouc_wen_exact_update
from ..solver import bracketed_newton, implicit_root


def bearing_force(x, p, rule):
    """F(x) = mu(v) W Z at the end of the step, for isolator displacement x [m] there.

    Z follows the path of constant acceleration 2 c from (ub0, vb0) to x,
    u(s) = ub0 + vb0 s + c s^2 with c = (x - ub0 - vb0 dt) / dt^2 (Newmark's path; its end
    velocity 2 (x - ub0) / dt - vb0 decides whether the path turns). When it turns, at
    s* = -vb0 / (2 c) and u* = ub0 - vb0^2 / (4 c), Z is updated exactly along both monotone
    pieces, ub0 -> u* and u* -> x (along the net increment it would miss the stretch travelled
    forth and back, an error of Z that grows with the step squared over Y). mu is taken at the
    step's end velocity `isolator_end_velocity(x, p)` (the rule's; Newmark's is the path's), times
    1 + a Z for a bearing with direction asymmetry (`p["asymmetry"]` = a). With a
    friction pendulum's nonlinear surface (`p["surface"]`), F also holds its force beyond
    W x / R, `ConcaveSurface.extra_force` (W x / R itself is in the structure's stiffness).
    """
    z = _z_along_path(x, p, rule)[-1]
    force = p["bearing"].coefficient(isolator_end_velocity(x, p), 0.0, p["z_peak"]) * p["W"] * z
    if "asymmetry" in p:  # mu (1 + a Z): `DirectionAsymmetry`
        force = force * (1 + p["asymmetry"] * z)
    if "surface" in p:
        force = force + p["surface"].extra_force(x, p["W"])
    return force, z


def _z_along_path(x, p, rule):
    """Z along the step's path to isolator displacement x [m] (see `bearing_force`), with what
    its slope needs: (turning, path_velocity, forth, back, z_turn, z), forth = u* - ub0 and
    back = x - u* for a turning path (forth = x - ub0 and back = 0 otherwise)."""
    dt, split_at_turn = rule  # step [s] and `StructureOnSliders.split_at_turn`
    h = p["bearing"].hysteresis
    du = x - p["ub0"]
    vb0 = p["vb0"]
    path_velocity = 2 / dt * du - vb0
    turning = (vb0 * path_velocity < 0) & split_at_turn
    forth = jnp.where(turning, turn_distance(vb0, path_velocity, dt, turning), du)
    back = jnp.where(turning, du - forth, 0.0)
    z_turn = bouc_wen_exact_update(h, p["z0"], forth, p["reversal_length"],
                                   tangent="rational")  # cheaper in batches of structures
    z = bouc_wen_exact_update(h, z_turn, back, tangent="rational")
    return turning, path_velocity, forth, back, z_turn, z


def turn_distance(v0, v1, dt, turning):
    """Distance [m] from the start of the step to the turning point of a path whose velocity
    goes linearly from v0 to v1 [m/s] over dt [s]: v0^2 dt / (2 (v0 - v1)) (where `turning`)."""
    return v0**2 * dt / (2 * jnp.where(turning, v0 - v1, 1.0))


def predicted_root(p, start_factors, lo, hi):
    """First guess [m] of the isolator's displacement at the end of the step, within [lo, hi]:
    one Newton step, from the displacement with the bearing force held at its start value
    F0 = mu0 W z0, on the force linearised about the start state,

        F(x) ~ F0 + mu0 W G(z0) (x - ub0) + z0 d(mu W)/dv (v(x) - vb0),

    G = dZ/du of Eq. 3 in the direction of the held guess and v(x) = `isolator_end_velocity`; the guess
    is then off by the force's second-order change (while sliding at constant Z and speed
    both guesses are exact). `start_factors` = (mu0 W, d(mu W)/dv) at the start
    (`StructureOnSliders.friction_factors`); falls back to the held guess where the linearised
    residual does not increase with x."""
    force_per_z, slope_per_z = start_factors
    z0, ub0, g0 = p["z0"], p["ub0"], p["g0"]
    held = jnp.clip(p["ub_linear"] - g0 * force_per_z * z0, lo, hi)
    z_slope = _bouc_wen_slope(p["bearing"].hysteresis, z0, held - ub0)
    change = force_per_z * z_slope * (held - ub0) + slope_per_z * z0 * (isolator_end_velocity(held, p) - p["vb0"])
    residual = held - p["ub_linear"] + g0 * (force_per_z * z0 + change)
    slope = 1 + g0 * (force_per_z * z_slope + slope_per_z * z0 * p["velocity_gain"])
    return jnp.clip(jnp.where(slope > 0, held - residual / jnp.where(slope > 0, slope, 1.0), held), lo, hi)


def isolator_end_velocity(x, p):
    """The isolator's velocity [m/s] at the end of the step for its displacement x [m] there,
    linear in x: v = vb_linear + velocity_gain (x - ub_linear), with vb_linear [m/s] the
    velocity without the bearing force and velocity_gain [1/s] = dv/dx (Newmark: 2 / dt)."""
    return p["vb_linear"] + p["velocity_gain"] * (x - p["ub_linear"])


def isolator_residual(x, p, rule):
    """Equilibrium at the end of the step for isolator displacement x [m]:
    x - u_linear + g0 F(x) = 0, monotone increasing in x."""
    return x - p["ub_linear"] + p["g0"] * bearing_force(x, p, rule)[0]


def _bouc_wen_slope(h, z, increment):
    """dZ/du [1/m] at Z along a monotone increment of the sign of `increment` (the same sign
    convention as `bouc_wen_exact_update`: + for 0), Eq. 3 with eta = 2:
    Y dZ/du = A - beta Z^2 - gamma sgn(du) Z |Z|."""
    sign = jnp.where(increment >= 0, 1.0, -1.0)
    return (h.A - h.beta * z**2 - h.gamma * sign * z * jnp.abs(z)) / h.yield_disp


def residual_and_slope(x, p, rule):
    """`isolator_residual` and its derivative in x, with the bearing force and Z (see
    `force_and_slopes`): (r, dr/dx, F, Z), dr/dx = 1 + g0 dF/dx."""
    force, z, d_force, _ = force_and_slopes(x, p, rule)
    r = x - p["ub_linear"] + p["g0"] * force
    return r, 1 + p["g0"] * d_force, force, z


def force_and_slopes(x, p, rule):
    """`bearing_force` (F, Z) and their derivatives in x, written out (no automatic
    differentiation, so that Newton's loop costs one evaluation of the exact Z update, and the
    implicit derivative of `isolator_root` none with tangents in x):

        dF/dx = W (mu'(v) dv/dx Z + mu dZ/dx),  dv/dx = `velocity_gain`.

    Bouc-Wen is an autonomous equation in u along a monotone piece, Z' = G(Z), so the end value
    Z(z_a, d) of a piece of length d from z_a has dZ/dd = G(Z) and dZ/dz_a = G(Z) / G(z_a).
    Without a turn Z = Z(z0, du) and dZ/dx = G(Z). With a turn at u* (forth f = u* - ub0,
    df/dx = vb0^2 / (4 c^2 dt^2), see `bearing_force`) and back b = du - f:
        dZ/dx = G_b(Z) / G_b(Z*) G_f(Z*) df/dx + G_b(Z) (1 - df/dx).
    Newton's steps and the implicit derivative of `isolator_root` use these slopes (checked against
    automatic derivatives in the tests)."""
    h = p["bearing"].hysteresis
    vb0 = p["vb0"]
    turning, path_velocity, forth, back, z_turn, z = _z_along_path(x, p, rule)
    slope_forth = _bouc_wen_slope(h, z_turn, forth)
    slope_end = _bouc_wen_slope(h, z, back)
    slope_turn = _bouc_wen_slope(h, z_turn, back)
    change = jnp.where(turning, vb0 - path_velocity, 1.0)
    d_forth = (vb0 / change) ** 2
    ratio = slope_end / jnp.where(slope_turn != 0, slope_turn, 1.0)
    dz = jnp.where(turning, ratio * slope_forth * d_forth + slope_end * (1 - d_forth), slope_forth)
    mu, dmu = p["bearing"].uniaxial_coefficient(isolator_end_velocity(x, p), p["z_peak"])
    W = p["W"]
    force, d_force = mu * W * z, W * (dmu * p["velocity_gain"] * z + mu * dz)
    if "asymmetry" in p:  # F = mu W Z (1 + a Z): dF/dx = W (mu' v' Z (1 + a Z) + mu (1 + 2 a Z) Z')
        a = p["asymmetry"]
        force = force * (1 + a * z)
        d_force = W * (dmu * p["velocity_gain"] * z * (1 + a * z) + mu * (1 + 2 * a * z) * dz)
    if "surface" in p:  # the pendulum's nonlinear force and its stiffness dE/dx
        extra, d_extra = jax.jvp(lambda u: p["surface"].extra_force(u, W), (x,), (jnp.ones_like(x),))
        force, d_force = force + extra, d_force + d_extra
    return force, z, d_force, dz


def isolator_root(rule, iterations, p, x0, lo, hi, tolerance):
    """Root x [m] of `isolator_residual` and the bearing force F [N] and Z [-] there, by
    Newton's method safeguarded by the bracket [lo, hi] (`_bracketed_root`), differentiated
    implicitly (`solver.implicit_root`: dx = -r_p dp / r_x with r_x = 1 + g0 dF/dx from the
    written-out slopes of `force_and_slopes`, and F, Z through `bearing_force` at the root),
    so forward and reverse mode work and cost one evaluation of F with tangents whatever the
    number of iterations. `rule` = (dt, split_at_turn), `iterations` = (unrolled,
    max_iterations), both static."""
    x, (force, z) = implicit_root(functools.partial(_bracketed_root, rule, iterations),
                                  functools.partial(isolator_residual, rule=rule),
                                  functools.partial(_residual_slope_solve, rule), p, x0, lo, hi, tolerance,
                                  outputs=functools.partial(bearing_force, rule=rule))
    return x, force, z


def _residual_slope_solve(rule, x, p, r, dp):
    """r / r_x at the root x, r_x = 1 + g0 dF/dx (`force_and_slopes`): the scalar balance's
    linear solve for `isolator_root` (`dp` unused: the residual holds the whole balance)."""
    return r / (1 + p["g0"] * force_and_slopes(x, p, rule)[2])


def _bracketed_root(rule, iterations, p, x0, lo, hi, tolerance):
    """`solver.bracketed_newton` on `isolator_residual` from x0 in the bracket [lo, hi], with
    `iterations` = (unrolled, max_iterations) and Newton's step r / r_x where the slope r_x is
    positive (a bisection elsewhere). **Returns:** (x, (F, Z)), F and Z those of the last
    iterate (no evaluation after the loop)."""
    unrolled, max_iterations = iterations

    def evaluate(x):
        r, dr, force, z = residual_and_slope(x, p, rule)
        return r, r / jnp.where(dr > 0, dr, jnp.nan), force, z

    x, _, (_, _, force, z) = bracketed_newton(evaluate, x0, tolerance, max_iterations, lower=lo, upper=hi,
                                              unrolled=unrolled)
    return x, (force, z)
