"""The sliders' forces at the end of a step: each slider of a friction pendulum in the series
model, in one or two horizontal components (the one law that the structures, the slab and the
imposed-path test of a `SeriesPendulum` all run), and the one slider of a flat-slider or
single-pendulum structure, solved for the isolator's displacement.

Slider e, at displacement s_e after the step's increment d_e, carries

    F_e = N (s_e / R_e + f_min Z_e + (mu_e(v_e) - f_min) <n_e . Z_e>_+ n_e
             + k_stop <|s_e| - c_e>_+ s_e / (|s_e| R_e)),

with R_e and c_e its radius and capacity (`series_radii`, `series_capacities`), Z_e from
Bouc-Wen updated exactly along the increment (Park's biaxial model in two components), n_e the
direction of the increment (its sign in one component), mu_e Eq. 1 at the surface's mean
speed over the step v_e = |d_e| c_e / dt (`velocity_factors`; the speed OpenSees'
`TripleFrictionPendulum` takes too), f_min Eq. 1 at rest, and k_stop = `STOP_STIFFNESS_RATIO`.
The friction term is Eq. 1 where the slider moves the way its Z points and f_min while Z still
points back after a reversal (the law "mean" of `FRICTION_VELOCITIES`): without that exception the force of a reversing slider would
fall as its increment grows (Eq. 1's rise with the increment against Z's elastic slope, for
steps below a few ms), and the massless sliders would have no unique balance. A surface with
parts beyond Eq. 1 (`SurfaceParts`: breakaway, anisotropy, wear, direction asymmetry, pressure
dependence) takes its coefficients at rest and sliding from `surface_coefficients`, the flat
bearing's law; breakaway and wear read the slider's history (its largest |Z| up to the
step's start and its surface's travel), which the steppers carry (`initial_history`,
`step_history`, `next_history`). One surface (`SinglePendulum`, S = 1) may take the flat
sliders' law instead, "end": Eq. 1 at the isolator's velocity at the step's end, on the whole
of Z, F = N (s / R + mu(v) Z + stop).

Heating (`series_heat_kernel`, `heated_step`): frictional heating of each sliding surface of a friction pendulum modelled as sliders in
series (`SeriesPendulum`): surface e takes the heat flux q_e = mu_e p_e v_e of its own
friction, contact pressure and sliding speed, its temperature rises as that of a
semi-infinite steel body (Carslaw & Jaeger 1959, Sec. 2.9; the 1/sqrt(t) kernel as a sum of
exponential states, `heat_kernel_exponentials`), and its friction is scaled by k_T of Kumar,
Whittaker & Constantinou (2015) (`FrictionalHeating`), each surface with its own temperature
as in Kim & Constantinou's TripleFrictionPendulumX element of OpenSees. Within a step the
factor is the one at the step's start and the flux is held, as the flat sliders take them.

The one slider of a flat-slider or single-pendulum structure (`StructureOnSliders` with a
`SlidingBearing`; `bearing_force` to `predicted_root`): its equilibrium at the end of a step
is solved for the isolator's displacement, x = u_linear - g0 F(x) (Newmark's rule or the exact
linear rule, `structures.newmark_step_matrices`, `structures.exact_step_matrices`), with
F = mu(v) W Z the bearing force at the end of the step, v its velocity there (linear in x,
`isolator_end_velocity`) and Z updated exactly along the step's path (`bearing_force`), by the
bracketed Newton iteration (`solver.bracketed_newton`) with written-out slopes, differentiated
implicitly (`isolator_root`); Eqs. 1, 3 and 17 of Constantinou, Mokha & Reinhorn (1990). The
one-surface isolator of the series engine solves its slider's balance by the same iteration,
its bracket found on the way.

References: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 3 and 17; Park, Wen & Ang (1986);
Fenz & Constantinou (2006, 2008).
"""

import functools

import jax
import jax.numpy as jnp

from ..bearing import (
    HEAT_HORIZON,
    STOP_STIFFNESS_RATIO,
    SeriesPendulum,
    advance_heat_states,
    bouc_wen_exact_update,
    heat_kernel_exponentials,
    sliding_friction,
    surface_coefficients,
)
from ..solver import (
    bracketed_newton,
    implicit_root,
    park_exact_update,
    park_exact_update_and_slope,
)


def slider_forces(pendulum: SeriesPendulum, load, slider0, z0, increment, time_step, factors=None, history=None,
                  load_factor=1.0, velocity=None):
    """Forces F_e [N] of the sliders after the increments `increment` [m] from displacements
    `slider0` [m] and Z `z0` [-] over a step of `time_step` [s] (module docstring), and their
    Z at the step's end. Arrays (S,) in one component, (S, 2) in two; `load` N [N]; `factors`
    (S,) [-]: each surface's friction scaled by it (heating), or `None`; `history`: the
    sliders' `step_history` where a surface's part needs it; `load_factor` N / W [-] (the
    contact pressure of pressure dependence). `velocity` (S,) or (S, 2) [m/s]: the sliders'
    velocities at the step's end, for the law "end" (`FRICTION_VELOCITIES`: Eq. 1 at the
    surface's speed |v_e| c_e there, anisotropy in the direction of v_e, and mu_e on the whole
    of Z_e, F_e = N (s_e / R_e + mu_e Z_e + stop)); `None`: the law "mean" (module docstring)."""
    z = _z_update(pendulum, z0, increment)
    return forces_at_z(pendulum, load, slider0, z, increment, time_step, factors, history, load_factor,
                       velocity), z


def _z_update(pendulum: SeriesPendulum, z0, increment):
    """The sliders' Z after `increment` (S,) or (S, 2) [m]: Bouc-Wen or Park updated exactly."""
    if increment.ndim == 2:
        return park_exact_update(pendulum.hysteresis, z0, increment)
    return bouc_wen_exact_update(pendulum.hysteresis, z0, increment, tangent="rational")


def forces_at_z(pendulum: SeriesPendulum, load, slider0, z, increment, time_step, factors=None, history=None,
                load_factor=1.0, velocity=None):
    """`slider_forces`' forces (S,) or (S, 2) [N] with the sliders' Z `z` at the step's end given."""
    planar = increment.ndim == 2
    u = slider0 + increment
    if planar:
        radii, capacities = pendulum.series_radii()[:, None], pendulum.series_capacities()[:, None]
    else:
        radii, capacities = pendulum.series_radii(), pendulum.series_capacities()
    slide, direction = _length_and_direction(increment)
    reach, outward = _length_and_direction(u)
    friction = pendulum.frictions() if factors is None else pendulum.frictions().scaled(factors)
    if velocity is None:
        speed, heading = slide * pendulum.velocity_factors() / time_step, direction
    else:
        speed, heading = _length_and_direction(velocity)
        speed = speed * pendulum.velocity_factors()
    if pendulum.has_parts:
        f_min, mu = surface_coefficients(friction, pendulum.parts(), speed, heading, z, history,
                                         pendulum.contact_pressures(), load_factor)
    else:
        f_min, mu = friction.f_max - friction.delta_f, sliding_friction(friction, speed)
    if planar:
        f_min, mu = f_min[:, None], mu[:, None]
        along = jnp.maximum(jnp.sum(direction * z, axis=-1, keepdims=True), 0.0)
        over = jnp.maximum(reach - capacities[:, 0], 0.0)[:, None] * outward
    else:
        along = jnp.maximum(direction * z, 0.0)
        over = jnp.maximum(reach - capacities, 0.0) * outward
    if velocity is None:
        friction_term = f_min * z + (mu - f_min) * along * direction
    else:
        friction_term = mu * z
    return load * (u / radii + friction_term + STOP_STIFFNESS_RATIO * over / radii)


def _length_and_direction(x):
    """(|x| (S,), the unit direction of x) for x (S,) or (S, 2): in one component the sign
    (+1 at 0), in two x / |x| (0 at 0); |x| with a zero derivative at 0."""
    if x.ndim == 1:
        return jnp.abs(x), jnp.where(x >= 0, 1.0, -1.0)
    length = slider_lengths(x)
    return length, x / jnp.where(length > 0, length, 1.0)[:, None]


def slider_lengths(x):
    """|x_e| (S,) of planar vectors x (S, 2), with a zero derivative at 0 instead of NaN."""
    squared = jnp.sum(x**2, axis=-1)
    return jnp.where(squared > 0, jnp.sqrt(jnp.where(squared > 0, squared, 1.0)), 0.0)


def balance_forces(p, increment, time_step, blocks: bool = False):
    """`slider_forces` of a step's balance from its parameters `p` (the pendulum, N, the
    sliders' start, Z, and where present the heating factors "k", the history, the load
    factor "s" and, for the law "end", "v" = (v_free, v_gain): the one slider's velocity at
    the step's end v_free + v_gain d, linear in its increment d, `end_velocity`): (forces, Z).
    With `blocks` (two components), also dF_e/dd_e (S, 2, 2) [N/m], exact: Park's slope written
    out (`park_exact_update_and_slope`, about one more update where forward mode through it
    costs tens) carried through the rest of the law by forward mode."""
    def law(x, z):
        velocity = None if "v" not in p else p["v"][0] + p["v"][1] * x
        return forces_at_z(p["pendulum"], p["N"], p["s0"], z, x, time_step, p.get("k"), p.get("history"),
                           p.get("s", 1.0), velocity)

    if not blocks:
        z = _z_update(p["pendulum"], p["z0"], increment)
        return law(increment, z), z
    z, slope = park_exact_update_and_slope(p["pendulum"].hysteresis, p["z0"], increment)
    axes = jnp.eye(2, dtype=increment.dtype)
    (force, along_x), (_, along_y) = (
        jax.jvp(law, (increment, z), (jnp.broadcast_to(axes[j], increment.shape), slope[..., j])) for j in range(2))
    return force, z, jnp.stack([along_x, along_y], -1)


FRICTION_VELOCITIES = ("mean", "end")
"""The velocity at which a step takes Eq. 1 (`StructureOnSliders.friction_velocity`): "mean",
each surface's mean speed over the step, |d_e| c_e / dt, with f_min while Z_e still points back
(the law of sliders in series, whose massless sliders have no velocity of their own); "end",
the isolator's velocity at the step's end from the structure's linear step, with mu on the
whole of Z (the flat sliders' law, `StructureOnSliders`; one surface only, S = 1, whose slider
is the isolator)."""


def end_velocity(velocity_free, velocity_gain, start, displacement_free, compliance, reference_stiffness):
    """(v_free, v_gain) of the law "end": the isolator's velocity at the step's end
    v = v_free + v_gain d [m/s], linear in the one slider's increment d [m] ((,) or (2,)).

    The linear step gives the isolator's end state x = x_free + g F_r, v = `velocity_free` +
    `velocity_gain` F_r for the force F_r [N] beyond the reference spring k_ref
    (`reference_stiffness`); with the balance's F = (D - d) / G (`displacement_free` D [m],
    `compliance` G [m/N]) and F_r = F - k_ref (`start` + d):
    v_free = v_lin + gain (D / G - k_ref start), v_gain = -gain (1 / G + k_ref)."""
    free = velocity_free + velocity_gain * (displacement_free / compliance - reference_stiffness * start)
    return free, -velocity_gain * (1 / compliance + reference_stiffness)


def initial_history(pendulum: SeriesPendulum, shape, dtype):
    """The sliders' history at rest where a surface's part needs it (`SeriesPendulum.remembers`):
    {"z_peak": largest |Z| so far, "travel": the surface's travel [m]}, each `shape` (S,) or
    (G, S); else `None`."""
    if not pendulum.remembers:
        return None
    return {"z_peak": jnp.zeros(shape, dtype), "travel": jnp.zeros(shape, dtype)}


def step_history(history, z0):
    """The history a step's force reads: the largest |Z| up to the step's start (with Z `z0`
    (S,) or (S, 2) there), so that the force solved for and the force reported are one (as the
    flat bearing's breakaway), and the travel so far; `None` passes through."""
    if history is None:
        return None
    size = jnp.abs(z0) if z0.ndim == history["z_peak"].ndim else slider_lengths(z0)
    return {"z_peak": jnp.maximum(history["z_peak"], size), "travel": history["travel"]}


def next_history(pendulum: SeriesPendulum, history, increment):
    """The history after a step from its `step_history`, the surfaces having slid |increment|
    times their velocity factors; `None` passes through."""
    if history is None:
        return None
    slide = jnp.abs(increment) if increment.ndim == history["travel"].ndim else slider_lengths(increment)
    return {"z_peak": history["z_peak"], "travel": history["travel"] + slide * pendulum.velocity_factors()}


FLOOR_RADIUS = 1e3
"""Radius [m] at which Newton's floor of a slider's slope, its pendulum stiffness W / R_e
(`floor_stiffnesses`), is taken for flatter surfaces (a flat slider's W / R = 0 would leave
Newton's matrix of a sliding slider singular): W / 1000 m is 4e-7 of the rigid mass's
m / dt^2 at 5 ms, so its Newton step is that close to the exact one."""


def floor_stiffnesses(pendulum: SeriesPendulum, load):
    """W / R_e (S,) [N/m] under the load `load` W [N], with R_e at most `FLOOR_RADIUS`: the
    sliders' pendulum stiffnesses, the floor of their slopes in Newton's matrix (exactly
    W / R_e for every surface of a double or triple pendulum)."""
    return load / jnp.minimum(pendulum.series_radii(), FLOOR_RADIUS)


def series_heat_kernel(pendulum: SeriesPendulum, time_step: float):
    """(rates [1/s], weights [s^-1/2]) of the heat kernel from one `time_step` [s] to
    `HEAT_HORIZON` for a pendulum with a heated surface, else (None, None)."""
    if not pendulum.heated:
        return None, None
    return tuple(jnp.asarray(a) for a in heat_kernel_exponentials(float(time_step), HEAT_HORIZON))


def heated_step(pendulum: SeriesPendulum, heat, factors, slide, time_step, rates, load=1.0):
    """Heat states (S, K) [W s/m^2] after a step in which the sliders slid `slide` (S,) [m]
    (the lengths of their increments): each surface's flux q_e = mu_e p_e v_e
    (`SeriesPendulum.heat_fluxes`) at its speed v_e = slide c_e / dt (`velocity_factors`),
    with mu_e Eq. 1 at that speed times the factor `factors` (S,) held over the step; the flux
    is held over the step (`advance_heat_states`, exact for a constant flux) and the
    load factor N / W `load` scales the pressure."""
    speed = slide * pendulum.velocity_factors() / time_step
    mu = sliding_friction(pendulum.frictions().scaled(factors), speed)
    flux = pendulum.heat_fluxes(mu, speed, load)
    return advance_heat_states(heat, flux[:, None], time_step, rates)



def surface_temperature_rises(pendulum: SeriesPendulum, heat, weights):
    """Surface temperature rises s dT_e [K] (S,) at the heat states `heat` (S, K) of the kernel
    of `weights` (K,): the rise that enters k_T (`FrictionalHeating.rise` times its
    `heat_scale` s), 0 where a surface has no heating."""
    return jnp.stack([jnp.zeros((), heat.dtype) if h is None else h.heat_scale * h.rise(heat[e], weights)
                      for e, h in enumerate(pendulum.surface_heatings())])


# --- the one slider of a flat slider or single pendulum, solved for the isolator's displacement ---

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
