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

References: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 3 and 17; Park, Wen & Ang (1986);
Fenz & Constantinou (2006, 2008).
"""

from typing import NamedTuple

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
    costs tens) carried through the rest of the law by forward mode.

    Each slider's force depends on its own increment alone: under two components several
    sliders are evaluated one after the other on their own slices (`_OneSlider`), which gives
    the same numbers to rounding. Under `vmap` every array is then one value per batch member,
    which a CPU vectorises, where the interleaved (S, 2) axes of each member do not (B7's
    triple pendulum under two components on the rigid mass about 1.2x faster; benchmarks/README.md,
    "The sliders one after the other")."""
    count = increment.shape[0]
    if count == 1 or increment.ndim == 1:
        return _balance_forces(p, increment, time_step, blocks)
    columns = zip(*(_balance_forces(_slider_parameters(p, e), increment[e:e + 1], time_step, blocks)
                    for e in range(count)))
    return tuple(jnp.concatenate(column) for column in columns)


def _balance_forces(p, increment, time_step, blocks):
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


def _slider_parameters(p, e: int) -> dict:
    """`p` of slider `e` alone: its pendulum view (`_OneSlider`) and its slices (1[, 2]) of the
    sliders' start, Z, heating factors and history."""
    one = {**p, "pendulum": _OneSlider(p["pendulum"], e), "s0": p["s0"][e:e + 1], "z0": p["z0"][e:e + 1]}
    if p.get("k") is not None:
        one["k"] = p["k"][e:e + 1]
    if p.get("history") is not None:
        one["history"] = {name: values[e:e + 1] for name, values in p["history"].items()}
    return one


class _OneSlider(NamedTuple):
    """Slider `index` of `pendulum` as the force law reads a pendulum (`forces_at_z`): its
    radius, capacity, velocity factor, Eq. 1 constants, surface parts and contact pressure as
    arrays (1,), and the pendulum's Bouc-Wen constants."""

    pendulum: SeriesPendulum
    index: int

    @property
    def hysteresis(self):
        return self.pendulum.hysteresis

    @property
    def has_parts(self) -> bool:
        return self.parts()[0] is not None

    def _one(self, values):
        return values[self.index:self.index + 1]

    def series_radii(self):
        return self._one(self.pendulum.series_radii())

    def series_capacities(self):
        return self._one(self.pendulum.series_capacities())

    def velocity_factors(self):
        return self._one(self.pendulum.velocity_factors())

    def frictions(self):
        return jax.tree_util.tree_map(self._one, self.pendulum.frictions())

    def parts(self) -> tuple:
        return (self.pendulum.parts()[self.index],)

    def contact_pressures(self):
        return self._one(self.pendulum.contact_pressures())


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
