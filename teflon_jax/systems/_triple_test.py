"""A triple or double friction pendulum driven along an imposed displacement: the bearing
test of a `SeriesPendulum` (three sliders of the `TriplePendulum`, two of the
`DoublePendulum`), run as the structures run the isolator.

Each step solves the balance of `StructureOnTriple.step` (one component) and
`BiaxialStructureOnTriple.step` (two) with the same slider forces (`slider_forces`: Eq. 1
where a slider moves the way its Z points, f_min while Z still points back after a reversal),
the same damped Newton iteration and the same implicit derivative, with the structure replaced
by the imposed path: the sliders' increments add up to the path's increment D exactly (the
limit of an actuator of vanishing compliance, G = 0 in the structures' Newton matrix), and
their forces are equal to `TEST_TOLERANCE` W. References: Fenz & Constantinou (2006),
Earthquake Engng Struct. Dyn. 35; (2008), Earthquake Spectra 24(4); Constantinou, Mokha &
Reinhorn (1990), Eqs. 1, 3.
"""

import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import SeriesPendulum
from ..excitation import AbstractBiaxialMotion
from ._bearing_test import save_times
from ._response import BearingTestResult
from ._sampled_path import sample_velocity
from ._slider_forces import (
    FRICTION_VELOCITIES,
    balance_forces,
    heated_step,
    initial_history,
    next_history,
    series_heat_kernel,
    slider_lengths,
    step_history,
)
from ._triple_biaxial import _balanced as _balanced_planar
from ._triple_structure import (
    TRIPLE_NEWTON_ITERATIONS,
    _balanced_increments,
    predicted_increments,
)

TEST_TOLERANCE = 1e-12
"""The sliders' force imbalance [-] over W at which a test step stops: a record simulated for
a fit is balanced to rounding, far below the structures' `TRIPLE_TOLERANCE`."""


def _path_step(pendulum, load, dt, kernel, state, target, velocity=None, *, tolerance=TEST_TOLERANCE,
               iterations: int = TRIPLE_NEWTON_ITERATIONS):
    """One step of the isolator to the path's displacement `target` ((,) or (2,) [m]) from the
    state (sliders (S[, 2]), Z, the last two increments[, heat states][, the sliders'
    history]): the structures' balance (`_balanced_increments` in one component,
    `_balanced_planar` in two) with the sliders' increments adding up to
    D = target - sum(sliders), from the extrapolated increments with their misfit to D shared
    evenly; `velocity` [m/s]: the path's at `target`, for the law "end" (one surface), else
    `None`."""
    slider, z, previous = state[:3]
    p = {"pendulum": pendulum, "W": load, "N": load, "s0": slider, "z0": z, "D": target - jnp.sum(slider, axis=0)}
    if velocity is not None:
        p["v"] = (velocity, jnp.zeros_like(velocity))
    if kernel is not None:
        p["k"] = pendulum.heat_factors(state[3], kernel[1])
    if pendulum.remembers:
        p["history"] = step_history(state[-1], z)
    guess = predicted_increments(previous)
    guess = guess + (p["D"] - jnp.sum(guess, axis=0)) / pendulum.slider_count
    limit = jnp.maximum(tolerance, 32 * jnp.finfo(slider.dtype).eps) * load
    solve = _balanced_planar if slider.ndim == 2 else _balanced_increments
    d, converged = solve(dt, iterations, p, guess, limit)
    force, z1 = balance_forces(p, d, dt)
    new = (slider + d, z1, jnp.stack([d, previous[0]]))
    if kernel is not None:
        slide = slider_lengths(d) if d.ndim == 2 else jnp.abs(d)
        new = new + (heated_step(pendulum, state[3], p["k"], slide, dt, kernel[0]),)
    if pendulum.remembers:
        new = new + (next_history(pendulum, p["history"], d),)
    return new, (jnp.mean(force, axis=0), slider + d, z1, converged)


def _along_path(pendulum, load, time_step, path, kernel, velocity=None, **solve):
    """Scan `_path_step` along `path` (nt,) or (nt, 2) [m] from rest (with the path's
    `velocity`, like it, for the law "end"): (force, slider, z, converged) of the steps after
    the first sample."""
    shape = (pendulum.slider_count,) + path.shape[1:]
    zeros = jnp.zeros(shape, path.dtype)
    start = (zeros, zeros, jnp.stack([zeros, zeros]))
    if kernel is not None:
        start = start + (jnp.zeros((pendulum.slider_count, kernel[0].shape[0]), path.dtype),)
    if pendulum.remembers:
        start = start + (initial_history(pendulum, shape[:1], path.dtype),)

    def body(state, inputs):
        return _path_step(pendulum, load, time_step, kernel, state, *inputs, **solve)

    return jax.lax.scan(body, start, (path[1:],) if velocity is None else (path[1:], velocity[1:]))[1]


def simulate_triple_test(bearing: SeriesPendulum, time, displacement, normal_load, *,
                         heat_kernel=None, friction_velocity: str = "mean", velocity=None) -> BearingTestResult:
    """Force of a triple or double pendulum bearing [N] along an imposed displacement [m] at the
    sample times [s] (uniform), under normal load W [N]: `displacement` (nt,) along one axis or
    (nt, 2) in the plane (an orbit); the path starts at rest at its first sample (module
    docstring). jit-, vmap- and grad-safe once the bearing is checked
    (`check_triple_pendulum`, `check_double_pendulum`). A pendulum with heated surfaces
    (`SeriesPendulum.heated`; contact pressures at this W) scales each surface's friction by
    its temperature (`_slider_forces.heated_step`; in the plane the flux takes the length of each
    surface's increment), with `heat_kernel` (rates, weights) =
    `heat_kernel_exponentials(dt, horizon)`, by default from concrete `time` (one step to
    `HEAT_HORIZON`). `friction_velocity` (`FRICTION_VELOCITIES`): "mean", or for a one-surface
    isolator "end", Eq. 1 at the path's velocity at each sample, `velocity` [m/s] like
    `displacement` (default: `sample_velocity`, central differences), as a flat bearing's
    test (`respond_along_path`) takes it.

    **Returns:** a `BearingTestResult`: the path (`time`, `ux`, `uy`; `vx`, `vy` for the law
    "end"), `normal_load`, the force `fx`, `fy` [N] (`fy` zeros along one axis), the sliders'
    displacements `slider` and `z`, (nt, S) or (nt, S, 2), in the order of the pendulum's
    `slider_names`, and `converged` (nt,), whether each step's force balance met its tolerance."""
    time = jnp.asarray(time, float)
    path = jnp.asarray(displacement, float)
    kernel = _test_heat_kernel(bearing, time, heat_kernel)
    load = jnp.asarray(normal_load, float)
    velocity = _path_velocity(bearing, friction_velocity, time, path, velocity)
    force, slider, z, converged = _along_path(bearing, load, time[1] - time[0], path, kernel, velocity)

    def first(rest):
        return jnp.concatenate([jnp.zeros((1,) + rest.shape[1:], rest.dtype), rest])

    force, planar = first(force), path.ndim == 2
    vx, vy = (None, None) if velocity is None else ((velocity[:, 0], velocity[:, 1]) if planar else (velocity, None))
    return BearingTestResult(
        time=time, fx=force[:, 0] if planar else force, fy=force[:, 1] if planar else jnp.zeros_like(force),
        z=first(z), normal_load=jnp.broadcast_to(load, time.shape), ux=path[:, 0] if planar else path,
        uy=path[:, 1] if planar else None, vx=vx, vy=vy, slider=first(slider),
        converged=jnp.concatenate([jnp.array([True]), converged]))


def _path_velocity(bearing: SeriesPendulum, friction_velocity: str, time, path, velocity):
    """The path's velocity [m/s] for the law "end" (given, or `sample_velocity` of each
    component), `None` for "mean"; `ValueError` naming `friction_velocity` or `velocity`."""
    if friction_velocity not in FRICTION_VELOCITIES:
        raise ValueError(f"friction_velocity: unknown {friction_velocity!r}; accepted: {', '.join(FRICTION_VELOCITIES)}.")
    if friction_velocity == "mean":
        if velocity is not None:
            raise ValueError("velocity: the law 'mean' takes each surface's mean speed over a step; "
                             "give friction_velocity='end' to use the path's velocity.")
        return None
    if bearing.slider_count != 1:
        raise ValueError(f"friction_velocity: 'end' needs a one-surface isolator; the {bearing.description} "
                         f"have {bearing.slider_count} sliders.")
    if velocity is None:
        columns = path[:, None] if path.ndim == 1 else path
        velocity = jnp.stack([sample_velocity(time, c) for c in columns.T], -1).reshape(path.shape)
    velocity = jnp.asarray(velocity, float)
    if velocity.shape != path.shape:
        raise ValueError(f"velocity: one per sample like the displacement {path.shape}, got {velocity.shape}.")
    return velocity


def imposed_isolator_force(pendulum: SeriesPendulum, load, displacement, time_step: float, *,
                           newton_iterations: int = TRIPLE_NEWTON_ITERATIONS,
                           tolerance: float = TEST_TOLERANCE):
    """The structures' isolator solve driven along a displacement path (nt,) [m] sampled at
    `time_step` [s], under normal load W [N] (the bearing test, `simulate_triple_test`, with
    the balance's settings: `newton_iterations`, `tolerance` [-] over W).

    **Returns:** (isolator displacement (nt,) [m], force (nt,) [N], converged (nt,))."""
    load = jnp.asarray(load, float)
    force, slider, _, ok = _along_path(pendulum, load, float(time_step), jnp.asarray(displacement, float), None,
                                       tolerance=tolerance, iterations=newton_iterations)
    at_rest = jnp.zeros(1, force.dtype)
    return (jnp.concatenate([at_rest, jnp.sum(slider, axis=1)]), jnp.concatenate([at_rest, force]),
            jnp.concatenate([jnp.ones(1, bool), ok]))


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

    **Returns:** (time (nt,) [s], displacement (nt,) or (nt, 2) [m], `BearingTestResult`).
    """
    time = save_times(motion, motion.duration, samples_per_cycle)
    path = jax.vmap(motion.displacement)(time)
    displacement = path if isinstance(motion, AbstractBiaxialMotion) else path[:, 0]
    return time, displacement, simulate_triple_test(bearing, time, displacement, normal_load)
