"""A bearing driven along a sampled displacement path: the one force model of a test record.

Every consumer that needs the force of a bearing at the samples of a test (the fitter, the
posterior, model discovery, `force_along_path`) calls `respond_along_path` with the same
`SlidingBearing` the structures run; for a `SlidingBearing` that is `sliding_along_path`,
here.

**Velocity convention.** The force of a sample at time t_i is mu(v(t_i)) N Z(t_i), with v(t_i)
the velocity *at* the sample: given with the path, or estimated from the samples by
`sample_velocity` (second-order central differences, one-sided second order at both ends). A
forward or backward slope is off by half a sample (1-2 % on fitted constants); the central
difference agrees with a simulated test's own velocity to O(h^2).

**Hysteresis.** Uniaxial: the exact Riccati update of Eq. 3 over each sample interval
(`bouc_wen_exact_update`; through a gap with `backlash_update` when the bearing has
`Backlash`). Biaxial: Park et al.'s Eqs. 8-9 along the Hermite path between samples
(`park_path_update`). The running max |Z| switches breakaway (Eq. 17) to Eq. 1.

**Optional parts** (`SlidingBearing.effect_factor`): the normal load of the sample (pressure
dependence), the accumulated travel (wear), Z_x (asymmetry) and the surface temperature rise
(heating: the measured rise if the path carries one, else the semi-infinite-body rise under
the heat flux of the previous sample's friction, advanced as a sum of exponential states,
linear in the number of samples).

**The friction's memory in a structure** (`has_history` ... `history_rates`): the surface
temperature of a heating bearing and the travel of a wearing one, carried as state from step
to step (one and two directions alike). The heat flux into the steel is q = mu p |v| / n (p the
contact pressure of the bearing, n the interfaces in series), advanced with the same kernel of
exponential states, so a step costs the same whatever the length of the record; their factor on
mu is taken at the start of each step and held over it.

References: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 3, 8-9, 17; FORMATS.md; Kumar,
Whittaker & Constantinou (2015); Carslaw & Jaeger (1959).
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import (
    DEFAULT_YIELD_DISP,
    SlidingBearing,
    backlash_update,
    bouc_wen_exact_update,
)
from ..bearing import heat_kernel_exponentials as _kernel
from ..solver import park_path_update, park_substeps, require_riccati_form
from ._response import BearingTestResult

HEAT_HORIZON = 3600.0
"""Longest time [s] the heat kernel of a structure represents (the 1/sqrt(t) kernel is
accurate from one time step to this; an earthquake record is far shorter)."""


def sample_velocity(time, u):
    """Velocity [m/s] at the samples of a path: second-order central differences.

    Interior samples: v_i = (h-^2 u_(i+1) - h+^2 u_(i-1) + (h+^2 - h-^2) u_i) / (h- h+ (h- + h+))
    with h- = t_i - t_(i-1), h+ = t_(i+1) - t_i (exact for a quadratic); the end samples use the
    one-sided second-order formula (as `numpy.gradient(u, time, edge_order=2)`). Traceable.

    **Arguments:** `time` [s] (n,), strictly increasing, n >= 3; `u` [m] (n,).

    **Returns:** v [m/s] (n,).
    """
    time, u = jnp.asarray(time), jnp.asarray(u)
    if time.shape[0] < 3:
        raise ValueError(f"time: need at least 3 samples for a velocity, got {time.shape[0]}.")
    return _central_differences(time, u)


@jax.jit
def _central_differences(time, u):
    """`sample_velocity`'s differences, one compiled program per shape."""
    h = jnp.diff(time)
    h1, h2 = h[:-1], h[1:]
    inner = (-h2 / (h1 * (h1 + h2)) * u[:-2] + (h2 - h1) / (h1 * h2) * u[1:-1]
             + h1 / (h2 * (h1 + h2)) * u[2:])
    a, b = h[0], h[1]
    first = (-(2 * a + b) / (a * (a + b)) * u[0] + (a + b) / (a * b) * u[1]
             - a / (b * (a + b)) * u[2])
    a, b = h[-2], h[-1]
    last = (b / (a * (a + b)) * u[-3] - (a + b) / (a * b) * u[-2]
            + (2 * b + a) / (b * (a + b)) * u[-1])
    return jnp.concatenate([first[None], inner, last[None]])


class SampledPath(eqx.Module):
    """Displacement, velocity and normal load at the samples of a path (SI units).

    **Fields:** `time` [s], `ux` [m], `velocity_x` [m/s], `normal_load` N [N] on the bearing
    (n,); `uy`, `velocity_y` (n,) for a path in the plane, `None` along x only;
    `temperature_rise` (n,) measured surface temperature rise [K] or `None`; `heat_rates`
    [1/s], `heat_weights` [s^-1/2] of the 1/sqrt(t) kernel (`heat_kernel_exponentials`) or
    `None`; `park_elements` (static) straight elements per sample interval in the plane.
    """

    time: jnp.ndarray
    ux: jnp.ndarray
    velocity_x: jnp.ndarray
    normal_load: jnp.ndarray
    uy: jnp.ndarray | None = None
    velocity_y: jnp.ndarray | None = None
    temperature_rise: jnp.ndarray | None = None
    heat_rates: jnp.ndarray | None = None
    heat_weights: jnp.ndarray | None = None
    park_elements: int = eqx.field(static=True, default=16)

    @property
    def planar(self) -> bool:
        """True for a path in the plane (Park's Z), False along x (Bouc-Wen)."""
        return self.uy is not None


def sampled_path(time, ux, normal_load, *, uy=None, velocity=None, velocity_y=None,
                 temperature_rise=None, heat_terms_per_decade=3.0, park_elements=None,
                 yield_disp=DEFAULT_YIELD_DISP) -> SampledPath:
    """Build a `SampledPath` from sampled arrays.

    **Arguments:** `time` [s], `ux` [m] (n,), or (n, 2) a path in the plane (its columns x and
    y, without `uy`); `normal_load` [N] scalar or (n,); `uy` [m] for a path in the plane;
    `velocity`, `velocity_y` [m/s] (default `sample_velocity`);
    `temperature_rise` [K] measured (n,) or `None`; the heat kernel is built when `time` is
    concrete (`heat_terms_per_decade`); `park_elements` (default from the longest chord over
    Y / 4, `park_substeps`, with `yield_disp` Y [m]).
    """
    time, ux = jnp.asarray(time), jnp.asarray(ux)
    if ux.ndim == 2:
        if uy is not None or ux.shape[1] != 2:
            raise ValueError(f"ux: a path in the plane is (n, 2) without uy, got {ux.shape}"
                             f"{' and uy' if uy is not None else ''}.")
        ux, uy = ux[:, 0], ux[:, 1]
    load = jnp.broadcast_to(jnp.asarray(normal_load, dtype=ux.dtype), ux.shape)
    velocity = sample_velocity(time, ux) if velocity is None else jnp.asarray(velocity)
    rates = weights = None
    if not isinstance(time, jax.core.Tracer):
        t = np.asarray(time)
        rates, weights = (jnp.asarray(a) for a in _kernel(
            float(np.min(np.diff(t))), float(t[-1] - t[0]), per_decade=heat_terms_per_decade))
    if uy is not None:
        uy = jnp.asarray(uy)
        velocity_y = sample_velocity(time, uy) if velocity_y is None else jnp.asarray(velocity_y)
        if park_elements is None and any(isinstance(a, jax.core.Tracer) for a in (ux, uy)):
            raise ValueError("park_elements: a planar path's elements per sample interval follow from "
                             "concrete displacements; under tracing give park_elements (e.g. 16).")
        if park_elements is None:
            park_elements = park_substeps(ux, uy, yield_disp)
    return SampledPath(time=time, ux=ux, velocity_x=velocity, normal_load=load, uy=uy,
                       velocity_y=velocity_y,
                       temperature_rise=None if temperature_rise is None
                       else jnp.asarray(temperature_rise),
                       heat_rates=rates, heat_weights=weights,
                       park_elements=16 if park_elements is None else int(park_elements))


def _increments(path: SampledPath):
    """Per-sample inputs of the scan; the first sample has a zero increment."""
    time = path.time
    dt = jnp.concatenate([jnp.zeros(1, time.dtype), jnp.diff(time)])
    du_x = jnp.concatenate([jnp.zeros(1, time.dtype), jnp.diff(path.ux)])
    if path.planar:
        du_y = jnp.concatenate([jnp.zeros(1, time.dtype), jnp.diff(path.uy)])
        position = jnp.stack([path.ux, path.uy], axis=-1)
        velocity = jnp.stack([path.velocity_x, path.velocity_y], axis=-1)
        previous = jnp.concatenate([position[:1], position[:-1]])
        previous_velocity = jnp.concatenate([velocity[:1], velocity[:-1]])
        hermite = (previous, position, previous_velocity * dt[:, None], velocity * dt[:, None])
        return hermite, dt, jnp.hypot(du_x, du_y), path.velocity_y
    return du_x, dt, jnp.abs(du_x), jnp.zeros_like(path.ux)


def sliding_along_path(bearing: SlidingBearing, path: SampledPath, *, z0=None,
                       z_peak0=0.0) -> BearingTestResult:
    """Force of `bearing` at the samples of `path` (jit/vmap/grad-safe in the bearing;
    `respond_along_path` for a `SlidingBearing`):

        F = mu(v, theta, max|Z|) k(N, travel, Z_x, dT) N Z       (Eqs. 1, 17; k the optional
                                                                  factors, 1 without them)

    with Z exact between samples (eta = 2, gamma > beta; see the module docstring).

    **Arguments:** `bearing`, `path`; `z0` Z at the first sample (default 0: from rest; (2,)
    in the plane), `z_peak0` the running max |Z| before the first sample (1: already
    mobilised, no breakaway).

    **Returns:** a `BearingTestResult` at the path's samples: the path (`time`, `ux`, `uy`,
    `vx`, `vy`, `normal_load`), `fx`, `fy` [N] (zeros along x only), `z` (n, 2) [-], `z_peak`,
    `coefficient` mu, `temperature_rise` (scaled), `heat_index` and `gap_position`.
    """
    h = require_riccati_form(bearing.hysteresis)
    planar, heating = path.planar, bearing.heating
    measured = path.temperature_rise is not None
    if heating is not None and not measured and path.heat_rates is None:
        raise ValueError("heating: the heat kernel needs concrete sample times; build the path "
                         "with `sampled_path` outside jit.")
    gap = None if bearing.backlash is None else bearing.backlash.gap
    if gap is not None and planar:
        raise ValueError("backlash: the gap is modelled along x only; this path is planar.")
    increments, dt, lengths, velocity_y = _increments(path)
    speed = jnp.where(dt > 0, lengths / jnp.where(dt > 0, dt, 1.0), 0.0) / bearing.n_interfaces
    rise_in = path.temperature_rise if measured else jnp.zeros_like(path.ux)
    use_kernel = heating is not None and not measured
    rates = path.heat_rates if use_kernel else jnp.zeros(1)

    def step(carry, x):
        z, z_peak, heat, mu_prev, gap_position, travel = carry
        du, dt_i, length, speed_i, load, vx, vy, measured_rise = x
        if planar:
            z = park_path_update(h, z, *du, path.park_elements)
        elif gap is not None:
            z, gap_position = backlash_update(h, z, gap_position, du, gap)
        else:
            z = jnp.where(du == 0, z, bouc_wen_exact_update(h, z, du))
        z_peak = jnp.maximum(z_peak, jnp.sqrt(jnp.sum(z**2)) if planar else jnp.abs(z))
        travel = travel + length
        z_x = z[0] if planar else z
        if use_kernel:
            heat = heating.advance(heat, heating.flux(mu_prev, load, speed_i), dt_i, rates)
            heat_index = heating.rise(heat, path.heat_weights)
        else:
            heat_index = measured_rise if heating is not None else jnp.zeros_like(vx)
        factor = bearing.effect_factor(normal_load=load, temperature_rise=heat_index,
                                       travel=travel, z_x=z_x)
        mu = bearing.coefficient(vx, vy, z_peak) * factor
        scaled_rise = heat_index * (heating.heat_scale if heating is not None else 0.0)
        out = (mu * load * z, mu, z, z_peak, scaled_rise, heat_index, gap_position)
        return (z, z_peak, heat, mu, gap_position, travel), out

    dtype = path.ux.dtype
    z_start = jnp.zeros(2 if planar else (), dtype) if z0 is None else jnp.asarray(z0, dtype)
    init = (z_start, jnp.asarray(z_peak0, dtype), jnp.zeros_like(rates), jnp.zeros((), dtype),
            jnp.zeros((), dtype), jnp.zeros((), dtype))
    xs = (increments, dt, lengths, speed, path.normal_load, path.velocity_x, velocity_y, rise_in)
    _, (force, mu, z, z_peak, rise, heat_index, gap_position) = jax.lax.scan(step, init, xs)
    if planar:
        force_x, force_y = force[:, 0], force[:, 1]
    else:
        force_x, force_y, z = force, jnp.zeros_like(force), jnp.stack([z, jnp.zeros_like(z)], axis=-1)
    return BearingTestResult(time=path.time, fx=force_x, fy=force_y, z=z, normal_load=path.normal_load,
                             ux=path.ux, uy=path.uy, vx=path.velocity_x, vy=path.velocity_y, coefficient=mu,
                             z_peak=z_peak, temperature_rise=rise, heat_index=heat_index,
                             gap_position=gap_position)


# --------------------------------------------------------------------------- in a structure


def has_history(bearing: SlidingBearing) -> bool:
    """True when the bearing's friction depends on its history (heating, wear)."""
    return bearing.heating is not None or bearing.wear is not None


def history_factor(bearing: SlidingBearing, heat, travel, weights):
    """Factor on mu [-] at heat states `heat` (..., K) [W/m^2 s] and travel [m]; `weights`
    (K,) of the kernel (`heat_kernel_exponentials`)."""
    heating = bearing.heating
    rise = 0.0 if heating is None else heating.rise(heat, weights)
    return bearing.effect_factor(temperature_rise=rise, travel=travel)


def heat_flux(bearing: SlidingBearing, coefficient, contact_pressure, speed):
    """q = mu p |v| / n [W/m^2] into the steel of each of the n interfaces of a stack, at
    sliding speed |v| [m/s] of the bearing and contact pressure p [Pa]."""
    heating = bearing.heating
    return heating.flux(coefficient, contact_pressure * heating.contact_area,
                        speed / bearing.n_interfaces)


def next_history(bearing: SlidingBearing, heat, travel, slide, coefficient, contact_pressure,
                 time_step, rates):
    """Heat states and travel after a step in which the bearing slid `slide` [m] (the length of
    its increment), with the friction coefficient `coefficient` [-] of the step's start held
    over it (flux q = mu p slide / (dt n)), `rates` (K,) [1/s] of the kernel."""
    heating = bearing.heating
    if heating is not None:
        flux = heat_flux(bearing, coefficient, contact_pressure, slide / time_step)
        heat = heating.advance(heat, jnp.expand_dims(flux, -1), time_step, rates)
    return heat, travel + slide


def history_rates(bearing: SlidingBearing, heat, coefficient, contact_pressure, speed, rates):
    """(d heat / dt, d travel / dt) = (q - lambda heat, |v|) for an ODE solver."""
    if bearing.heating is None:
        return jnp.zeros_like(heat), speed
    flux = heat_flux(bearing, coefficient, contact_pressure, speed)
    return jnp.expand_dims(flux, -1) - rates * heat, speed
