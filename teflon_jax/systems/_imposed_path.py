"""Any isolator driven along a sampled displacement path: the one force model of a test record.

Every consumer that needs the force of an isolator at the samples of a test (the fitters, the
posterior, model discovery, `diagnose`) calls `imposed_path_test` (`_bearing_test`) on a
`SampledPath`, with the same isolator the structures run; its strategies here are

- "sampled", a `SlidingBearing` (flat sliders, the single pendulum's slider): `sliding_along_path`;
- "balanced", a `SeriesPendulum` (single, double, triple): `series_along_path`, the structures' step of
  the isolator (`slider_step`) with the structure replaced by the path, the sliders'
  increments adding up to the path's increment exactly (the limit G -> 0 of an actuator) and
  their forces equal to `TEST_TOLERANCE` W.

**Velocity convention.** The force of a sample at time t_i is mu(v(t_i)) N Z(t_i), with v(t_i)
the velocity *at* the sample: given with the path, or estimated from the samples by
`sample_velocity` (second-order central differences, one-sided second order at both ends). A
forward or backward slope is off by half a sample (1-2 % on fitted constants); the central
difference agrees with a simulated test's own velocity to O(h^2).

**Hysteresis of a sliding bearing.** Uniaxial: the exact Riccati update of Eq. 3 over each
sample interval (`bouc_wen_exact_update`; through a gap with `backlash_update` when the bearing
has `Backlash`). Biaxial: Park et al.'s Eqs. 8-9 along the Hermite path between samples
(`park_path_update`). The running max |Z| switches breakaway (Eq. 17) to Eq. 1.

**Optional parts** (`SlidingBearing.effect_factor`): the normal load of the sample (pressure
dependence), the accumulated travel (wear), Z_x (asymmetry) and the surface temperature rise
(heating: the measured rise if the path carries one, else the semi-infinite-body rise under
the heat flux of the previous sample's friction, advanced as a sum of exponential states,
linear in the number of samples).

References: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 3, 8-9, 17; FORMATS.md; Kumar,
Whittaker & Constantinou (2015); Carslaw & Jaeger (1959); Fenz & Constantinou (2008),
Earthquake Spectra 24(4).
"""

import functools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import (
    DEFAULT_YIELD_DISP,
    SeriesPendulum,
    SlidingBearing,
    backlash_update,
    bouc_wen_exact_update,
)
from ..bearing import heat_kernel_exponentials as _kernel
from ..elements import (
    FRICTION_VELOCITIES,
    TRIPLE_NEWTON_ITERATIONS,
    initial_history,
    isolator_parameters,
    predicted_increments,
    series_heat_kernel,
    slider_step,
)
from ..solver import park_path_update, park_substeps, require_riccati_form
from ._response import BearingTestResult


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
    `imposed_path_test`'s "sampled" strategy):

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


# --------------------------------------------------------------------------- a series pendulum


TEST_TOLERANCE = 1e-12
"""The sliders' force imbalance [-] over W at which a test step stops: a record simulated for
a fit is balanced to rounding, far below the structures' `TRIPLE_TOLERANCE`."""


def _path_step(pendulum, kernel, state, target, load, dt, velocity=None, load_factor=None):
    """One step of the isolator to the path's displacement `target` ((,) or (2,) [m]) from its
    state (`_series.initial_isolator`'s, the force per unit normal load F / N in place of
    the force beyond a reference spring) over `dt` [s], under the path's normal load `load` [N]
    at the step's end: the structures' step of the isolator (`slider_step`) with the sliders'
    increments adding up to D = target - sum(sliders), from the extrapolated increments with
    their misfit to D shared evenly; `velocity` [m/s]: the path's at `target`, for the law
    "end" (one surface), else `None`; `load_factor` N / W_ref [-] at the step's end, on the
    contact pressures of surfaces that read them (`SeriesPendulum.reads_pressure`), as a
    structure's load factor N / W is, or `None` (the pressures as given). The sliders' forces are
    N times their forces under a unit load at that pressure (`slider_forces`), so the balance is
    solved once per unit load, to `TEST_TOLERANCE` [-], and its force scaled by N: the same
    increments, with the balance's work free of N (a load that changes from step to step would
    otherwise be carried through every iteration)."""
    slider, unit = state[0], jnp.ones((), state[0].dtype)
    p = isolator_parameters(pendulum, state, unit, unit, target - jnp.sum(slider, axis=0),
                            heat_weights=None if kernel is None else kernel[1])
    if velocity is not None:
        p["v"] = (velocity, jnp.zeros_like(velocity))
    if load_factor is not None:  # on the pressures of the force law and the heat flux; positive: no uplift
        p["s"] = load_factor
    guess = predicted_increments(state[2])
    guess = guess + (p["D"] - jnp.sum(guess, axis=0)) / pendulum.slider_count
    limit = jnp.maximum(TEST_TOLERANCE, 32 * jnp.finfo(slider.dtype).eps)
    new, converged, force = slider_step(state, p, guess, limit, dt, TRIPLE_NEWTON_ITERATIONS,
                                        heat_rates=None if kernel is None else kernel[0])
    return new, (load * force, new[0], new[1], converged)


def _along_path(pendulum, loads, steps, path, kernel, velocity=None, reference_load=None):
    """Scan `_path_step` along `path` (nt,) or (nt, 2) [m] from rest, under the normal loads
    `loads` (nt,) [N] of its samples, over the steps `steps` (nt - 1,) [s] between them (with
    the path's `velocity`, like it, for the law "end"; with `reference_load` W_ref [N], the
    load factors N / W_ref on the contact pressures): (force, slider, z, converged) of the
    steps after the first sample."""
    shape = (pendulum.slider_count,) + path.shape[1:]
    zeros = jnp.zeros(shape, path.dtype)
    start = (zeros, zeros, jnp.stack([zeros, zeros]), jnp.zeros(path.shape[1:], path.dtype))
    if kernel is not None:
        start = start + (jnp.zeros((pendulum.slider_count, kernel[0].shape[0]), path.dtype),)
    if pendulum.remembers:
        start = start + (initial_history(pendulum, shape[:1], path.dtype),)

    def body(state, inputs):
        target, load, dt, velocity, load_factor = inputs
        return _path_step(pendulum, kernel, state, target, load, dt, velocity, load_factor)

    factors = None if reference_load is None else loads[1:] / reference_load
    inputs = (path[1:], loads[1:], steps, None if velocity is None else velocity[1:], factors)
    return jax.lax.scan(body, start, inputs)[1]


def series_along_path(bearing: SeriesPendulum, path: SampledPath, *, heat_kernel=None,
                      friction_velocity: str = "mean", reference_load=None) -> BearingTestResult:
    """Force of a series pendulum [N] along the imposed displacement of `path` (a
    `SampledPath`: along x, or in the plane), from rest at its first sample, under the path's
    normal load N [N] at each sample (module docstring); `imposed_path_test`'s
    "balanced" strategy. jit-, vmap- and grad-safe once the bearing is checked
    (`check_series_pendulum`). Surfaces that read their contact pressure
    (`SeriesPendulum.reads_pressure`: heating, pressure dependence) take it as given
    (`<slider>_pressure`) times N / `reference_load` [N], the load the pressures are given under
    (a structure's W), as a structure under a vertical record takes it; without
    `reference_load` the pressures hold at the path's N, which must then be constant
    (`normal_load_varies`). A pendulum with heated surfaces scales each surface's friction
    by its temperature (`teflon_jax.elements.heated_step`; in the plane the flux takes the length of
    each surface's increment), with `heat_kernel` (rates, weights) =
    `heat_kernel_exponentials(dt, horizon)`, by default from concrete sample times (the
    shortest step to `HEAT_HORIZON`). `friction_velocity` (`FRICTION_VELOCITIES`): "mean",
    or for a one-surface isolator "end", Eq. 1 at the path's velocity at each sample, as a
    flat bearing's test takes it.

    **Returns:** a `BearingTestResult`: the path (`time`, `ux`, `uy`, `vx`, `vy`),
    `normal_load`, the force `fx`, `fy` [N] (`fy` zeros along one axis), the sliders'
    displacements `slider` and `z`, (nt, S) or (nt, S, 2), in the order of the pendulum's
    `slider_names`, and `converged` (nt,), whether each step's force balance met its tolerance."""
    planar, time = path.planar, path.time
    displacement = jnp.stack([path.ux, path.uy], -1) if planar else path.ux
    kernel = _test_heat_kernel(bearing, time, heat_kernel)
    load = _path_load(bearing, path, reference_load)
    velocity = _path_velocity(bearing, friction_velocity, path)
    reference = None if reference_load is None or not bearing.reads_pressure else reference_load
    force, slider, z, converged = _along_path(bearing, load, jnp.diff(time), displacement, kernel, velocity,
                                              reference)

    def first(rest):
        return jnp.concatenate([jnp.zeros((1,) + rest.shape[1:], rest.dtype), rest])

    force = first(force)
    return BearingTestResult(
        time=time, fx=force[:, 0] if planar else force, fy=force[:, 1] if planar else jnp.zeros_like(force),
        z=first(z), normal_load=load, ux=path.ux, uy=path.uy, vx=path.velocity_x, vy=path.velocity_y,
        slider=first(slider), converged=jnp.concatenate([jnp.array([True]), converged]))


LOAD_SPREAD = 1e-9
"""Largest spread of the normal load [-], over its largest value, that the test of a pendulum
whose surfaces read their contact pressure takes as one load, without a reference load."""


def normal_load_varies(load):
    """Whether the normal loads (nt,) [N] of a path spread by more than `LOAD_SPREAD` of the
    largest: a bool array, of concrete loads or of traced ones."""
    load = jnp.asarray(load)
    return jnp.ptp(load) > LOAD_SPREAD * jnp.max(load)


def _path_load(bearing: SeriesPendulum, path: SampledPath, reference_load=None):
    """The path's normal loads (nt,) [N]; a load that is not positive, or one that varies
    (`normal_load_varies`) under a pendulum whose surfaces read their contact pressure without
    `reference_load`, is refused by name, as is a `reference_load` that is not positive
    (`ValueError` with what is wrong where the loads are concrete, else a runtime error naming
    each check)."""
    load = path.normal_load
    checks = [(jnp.any(jnp.asarray(load) <= 0),
               "path.normal_load: a series pendulum's test needs a positive normal load at every sample.")]
    if reference_load is not None:
        checks.append((~(jnp.asarray(reference_load) > 0),
                       "reference_load: give the positive load [N] the contact pressures are given under."))
    elif bearing.reads_pressure:
        checks.append((normal_load_varies(load),
                       f"path.normal_load: it varies, and the {bearing.description}' surfaces read their contact "
                       "pressure, given under one load: give a constant normal load, or that load as "
                       "reference_load."))
    if any(isinstance(failed, jax.core.Tracer) for failed, _ in checks):  # traced (inside a jit or a sampler)
        bad = functools.reduce(jnp.logical_or, [failed for failed, _ in checks])
        return eqx.error_if(load, bad, " Or: ".join(message for _, message in checks))
    wrong = [message for failed, message in checks if bool(failed)]
    if wrong:
        raise ValueError(" ".join(wrong))
    return load


def _path_velocity(bearing: SeriesPendulum, friction_velocity: str, path: SampledPath):
    """The path's velocity [m/s] (nt,) or (nt, 2) for the law "end", `None` for "mean";
    `ValueError` naming `friction_velocity`."""
    if friction_velocity not in FRICTION_VELOCITIES:
        raise ValueError(f"friction_velocity: unknown {friction_velocity!r}; accepted: {', '.join(FRICTION_VELOCITIES)}.")
    if friction_velocity == "mean":
        return None
    if bearing.slider_count != 1:
        raise ValueError(f"friction_velocity: 'end' needs a one-surface isolator; the {bearing.description} "
                         f"have {bearing.slider_count} sliders.")
    return jnp.stack([path.velocity_x, path.velocity_y], -1) if path.planar else path.velocity_x


def _test_heat_kernel(bearing: SeriesPendulum, time, heat_kernel):
    """(rates, weights) of a heated pendulum's kernel (`series_along_path`), else None."""
    if not bearing.heated:
        return None
    if heat_kernel is not None:
        return tuple(jnp.asarray(a, float) for a in heat_kernel)
    if isinstance(time, jax.core.Tracer):
        raise ValueError("heat_kernel: a heated pendulum under traced sample times needs "
                         "heat_kernel=heat_kernel_exponentials(time_step, horizon) (or concrete times).")
    return series_heat_kernel(bearing, float(np.min(np.diff(np.asarray(time)))))
