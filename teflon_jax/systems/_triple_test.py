"""A triple or double friction pendulum driven along an imposed displacement: the S sliders
of the series model (`SeriesPendulum`: three of the `TriplePendulum`, two of the
`DoublePendulum`) carry one force, and their displacements add up to the bearing's.

Each slider e carries F = W (u_e / R_e + mu_e(v_e) Z_e) + its restrainer beyond its capacity
(stiffness `STOP_STIFFNESS_RATIO` W / R_e), with Z_e updated exactly along the step
(Bouc-Wen's exact update along one axis, Park's along two) and mu_e from Eq. 1 at its
surface's velocity. Each step solves for the sliders' increments (S - 1 unknowns, each with one
or two components; the last closes the sum) by Newton's method on the differences of their
forces. References: Fenz & Constantinou (2006), Earthquake Engng Struct. Dyn. 35; (2008),
Earthquake Spectra 24(4);
Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 3.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import (
    STOP_STIFFNESS_RATIO,
    SeriesPendulum,
    bouc_wen_exact_update,
    sliding_friction,
)
from ..excitation import AbstractBiaxialMotion
from ..solver import park_exact_update
from ._bearing_test import save_times
from ._series_heat import heated_step, series_heat_kernel

NEWTON_STEPS = 30
"""Newton iterations per step of the series solve (fixed; the step reports convergence)."""

STEP_FRACTIONS = np.array([1.0, 0.5, 0.25, 0.125])
"""Fractions of a Newton step tried; the one with the smallest imbalance is taken."""

RESCUE_STEPS = 16
"""Newton iterations of the second stage, run only on a step the first `NEWTON_STEPS` left
unbalanced (`_rescue`)."""

RESCUE_FRACTIONS = 2.0 ** -np.arange(41)
"""Fractions of a Newton step the second stage tries (1 down to 2^-40)."""

MIN_SHARE = 1e-3
"""Smallest share of a step's increment a slider is first guessed to take."""


class TripleResponse(eqx.Module):
    """Response of a `SeriesPendulum` along an imposed path (SI): `force` (nt,) or (nt, 2)
    [N], `slider` (nt, S) or (nt, S, 2) displacements of the sliders of the series model (in
    the order of the pendulum's `slider_names`) [m], `z` like `slider` [-], `converged` (nt,) whether each
    step's force balance met its tolerance."""

    force: jnp.ndarray
    slider: jnp.ndarray
    z: jnp.ndarray
    converged: jnp.ndarray


def slider_forces(bearing: SeriesPendulum, normal_load, u, z, velocity, factors=None):
    """Force [N] of each slider at displacements `u` (S, k) [m], Z (S, k) and slider
    velocities (S, k) [m/s], k = 1 or 2 components: W (u / R + mu(|v|) Z) plus the
    restrainer beyond the capacity, along the slider's displacement; each surface's friction
    times `factors` (S,) [-] (heating) where given."""
    radii, capacities = bearing.series_radii()[:, None], bearing.series_capacities()[:, None]
    speed = _length(velocity)[:, 0] * bearing.velocity_factors()
    friction = bearing.frictions() if factors is None else bearing.frictions().scaled(factors)
    mu = sliding_friction(friction, speed)[:, None]
    reach = _length(u)
    direction = u / jnp.where(reach > 0, reach, 1.0)
    over = jnp.maximum(reach - capacities, 0.0) * direction
    return normal_load * (u / radii + mu * z + STOP_STIFFNESS_RATIO * over / radii)


def _length(x):
    """|x| along the last axis (kept), with a zero derivative at 0 instead of NaN."""
    squared = jnp.sum(x**2, axis=-1, keepdims=True)
    return jnp.where(squared > 0, jnp.sqrt(jnp.where(squared > 0, squared, 1.0)), 0.0)


def _z_update(h, z0, du):
    """Z after the increments du (S, k): Bouc-Wen along one axis, Park's model along two."""
    if du.shape[-1] == 1:
        return bouc_wen_exact_update(h, z0[:, 0], du[:, 0])[:, None]
    return park_exact_update(h, z0, du)


def _step(bearing, normal_load, dt, state, increment, kernel=None):
    """One step of the bearing by `increment` (k,) [m]: the sliders' increments that balance
    their forces, from the start state `state` = (u (S, k), z (S, k), previous increments
    (S, k), share (S,)[, heat states (S, K) of a heated pendulum, with `kernel` its (rates,
    weights)]). First guess: the previous step's increments, with what the step adds
    to them shared as the sliders last shared their travel; then Newton's method, each step
    shortened (to 1/2, 1/4 or 1/8) where that lowers the force imbalance more, and where the
    balance is still short a second stage with much shorter steps (`_rescue`)."""
    u0, z0, previous, share = state[:4]
    factors = None if kernel is None else bearing.heat_factors(state[4], kernel[1])
    k = increment.shape[-1]
    free = u0.shape[0] - 1  # the last slider closes the sum

    def forces(x):
        x = x.reshape(free, k)
        last = increment
        for row in x:
            last = last - row
        du = jnp.concatenate([x, last[None]])
        z = _z_update(bearing.hysteresis, z0, du)
        return slider_forces(bearing, normal_load, u0 + du, z, du / dt, factors), z, du

    def residual(x):
        f = forces(x)[0]
        return (f[:-1] - f[-1]).reshape(-1)

    def newton(_, x):
        return _newton_trial(residual, x, STEP_FRACTIONS)[0]

    def balanced(values):
        f = values[0]
        return jnp.max(jnp.abs(f[:-1] - f[-1])) <= 1e-8 * normal_load * jnp.max(bearing.frictions().f_max)

    guess = previous[:-1] + share[:-1, None] * (increment - jnp.sum(previous, axis=0))
    x = jax.lax.fori_loop(0, NEWTON_STEPS, newton, guess.reshape(-1))
    values = forces(x)
    f, z, du = jax.lax.cond(balanced(values), lambda: values, lambda: forces(_rescue(residual, x)))
    converged = balanced((f, z, du))
    length = _length(du)[:, 0]
    total = jnp.sum(length)
    # a floor keeps every first guess off zero: Park's update has no slope at a zero increment
    new_share = jnp.where(total > 0, jnp.maximum(length / jnp.where(total > 0, total, 1.0),
                                                 MIN_SHARE), share)
    new_state = (u0 + du, z, du, new_share)
    if kernel is not None:
        new_state = new_state + (heated_step(bearing, state[4], factors, length, dt, kernel[0]),)
    return new_state, (f[-1], u0 + du, z, converged)


def _rescue(residual, x):
    """The second stage of a step's Newton iteration: `RESCUE_STEPS` steps from `x`, each the
    fraction of `RESCUE_FRACTIONS` that lowers the imbalance sum(r^2) most, none where no
    fraction lowers it. Where a slider reverses, its force has a kink (Z's elastic slope
    against W / R while it slides): a Newton step from the sliding side overshoots the root by
    up to the ratio of the slopes, more than the first stage's shortest fraction corrects."""
    def body(_, x):
        trial, size, r = _newton_trial(residual, x, RESCUE_FRACTIONS)
        return jnp.where(size < jnp.sum(r**2), trial, x)

    return jax.lax.fori_loop(0, RESCUE_STEPS, body, x)


def _newton_trial(residual, x, fractions):
    """(the trial x - c s with the least imbalance sum(r^2) over the `fractions` c of the
    Newton step s = J^-1 r (s = 0 where it is not finite), that imbalance, r at `x`)."""
    r = residual(x)
    step = jnp.linalg.solve(jax.jacfwd(residual)(x), r)
    step = jnp.where(jnp.all(jnp.isfinite(step)), step, 0.0)
    trials = x - fractions[:, None] * step
    sizes = jax.vmap(lambda y: jnp.sum(residual(y) ** 2))(trials)
    sizes = jnp.where(jnp.isfinite(sizes), sizes, jnp.inf)
    best = jnp.argmin(sizes)
    return trials[best], sizes[best], r


def simulate_triple_test(bearing: SeriesPendulum, time, displacement, normal_load, *,
                         heat_kernel=None) -> TripleResponse:
    """Force of a triple or double pendulum bearing [N] along an imposed displacement [m] at the sample
    times [s] (uniform), under normal load W [N]: `displacement` (nt,) along one axis or
    (nt, 2) in the plane (an orbit); the path starts at rest at its first sample. jit- and
    vmap-safe once the bearing is checked (`check_triple_pendulum`, `check_double_pendulum`).
    A pendulum with heated surfaces (`SeriesPendulum.heated`; contact pressures at this W)
    scales each surface's friction by its temperature (`_series_heat.py`; in the plane the
    flux takes the length of each surface's increment), with `heat_kernel`
    (rates, weights) = `heat_kernel_exponentials(dt, horizon)`, by default from concrete
    `time` (one step to `HEAT_HORIZON`)."""
    time = jnp.asarray(time, float)
    displacement = jnp.asarray(displacement, float)
    planar = displacement.ndim == 2
    path = displacement if planar else displacement[:, None]
    k = path.shape[-1]
    dt = time[1] - time[0]
    n = bearing.slider_count
    start = (jnp.zeros((n, k)), jnp.zeros((n, k)), jnp.zeros((n, k)),
             jnp.array([1.0] + [MIN_SHARE] * (n - 1)))
    kernel = _test_heat_kernel(bearing, time, heat_kernel)
    if kernel is not None:
        start = start + (jnp.zeros((n, kernel[0].shape[0])),)

    def body(state, increment):
        return _step(bearing, normal_load, dt, state, increment, kernel)

    _, (force, slider, z, converged) = jax.lax.scan(body, start, jnp.diff(path, axis=0))
    force = jnp.concatenate([jnp.zeros((1, k)), force])
    slider = jnp.concatenate([jnp.zeros((1, n, k)), slider])
    z = jnp.concatenate([jnp.zeros((1, n, k)), z])
    if not planar:
        force, slider, z = force[:, 0], slider[..., 0], z[..., 0]
    return TripleResponse(force=force, slider=slider, z=z,
                          converged=jnp.concatenate([jnp.array([True]), converged]))


def _test_heat_kernel(bearing: SeriesPendulum, time, heat_kernel):
    """(rates, weights) of a heated pendulum's kernel (`simulate_triple_test`), else None."""
    if not bearing.heated:
        return None
    if heat_kernel is not None:
        return tuple(jnp.asarray(a, float) for a in heat_kernel)
    if isinstance(time, jax.core.Tracer):
        raise ValueError("heat_kernel: a heated pendulum under traced sample times needs "
                         "heat_kernel=heat_kernel_exponentials(time_step, horizon) (or concrete times).")
    return series_heat_kernel(bearing, float(np.min(np.diff(np.asarray(time)))))


def triple_pendulum_test(bearing: SeriesPendulum, motion, normal_load, *,
                         samples_per_cycle: int = 400):
    """A bearing test of a triple or double pendulum: the imposed `motion` (`AbstractMotion`: sine,
    triangle, figure-eight or tabulated) sampled `samples_per_cycle` times a cycle (a tabulated
    motion at its own samples), under the constant normal load [N].

    **Returns:** (time (nt,) [s], displacement (nt,) or (nt, 2) [m], `TripleResponse`).
    """
    time = save_times(motion, motion.duration, samples_per_cycle)
    path = jax.vmap(motion.displacement)(time)
    displacement = path if isinstance(motion, AbstractBiaxialMotion) else path[:, 0]
    return time, displacement, simulate_triple_test(bearing, time, displacement, normal_load)
