"""Peak responses of an isolated structure along a run (running and smooth maxima)."""

import equinox as eqx
import jax
import jax.numpy as jnp

from ..units import STANDARD_GRAVITY
from ._propagators import small_dot
from ._structure import WRITTEN_OUT_PRODUCT, StructureOnSliders, initial_state
from ._structure_build import check_duration, storey_rows, storey_start
from ._triple_structure import StructureOnTriple
from ._vertical import uplift_steps

STEPS_PER_LOOP_PASS = 2
"""`peak_response(steps_per_pass=...)` of the Monte Carlo runs (`monte_carlo`): two steps
written out in each pass of the peak loop (`lax.scan`'s `unroll`) halve the loop's fixed cost
per step, several per cent of the step for a batch of 250 motions per core; the rigid-mass and
building Monte Carlo needed 5 % and 4 % less CPU (same peaks), four no less than two. Not for
derivatives: forward-mode gradients through the unrolled loop took 8 times as long (B5)."""

RESPONSE_NAMES = ("base_disp", "base_shear_ratio")
"""Peak |base displacement| [m] and peak |base shear| / weight above the isolators [-]."""


class PeakResponse(eqx.Module):
    """Peaks of one run (scalars, or batched by `monte_carlo`), under one ground component
    (`peak_response`) or two (`bidirectional_peak_response`, displacement and shear as
    resultants).

    - `base_disp` max_t |u_0(t)| [m]: isolator displacement relative to the ground.
    - `base_shear_ratio` max_t |V(t)| / W_s [-]: V = sum_j m_j a_j^total over the masses
      above the isolators (floors 1.. of a building: the first-storey shear), or m a^total for
      a rigid mass; W_s their weight (two components: the force on every mass over the
      whole weight).
    - `smooth_base_disp`, `smooth_base_shear_ratio`: the same maxima through `smooth_max`
      (differentiable); equal to the peaks' lower bounds when no width is given.
    - `converged`: every step's Newton iteration converged.
    - `storey_drift` [-]: a building's peak interstorey drift ratio per storey (storey 1 from
      the base slab to floor 1), (n-1,) or (2, n-1) in x and y, and `floor_acceleration`
      [m/s^2] its peak total acceleration per level (0 the base slab on the isolators, 1.. the
      floors), (n,) or (2, n) (`storey_rows`), when given `storey_height`; else `None`.
    - `uplift_time` [s]: with a vertical record, the steps whose end has N <= 0 (the isolators
      uplifted, carrying no shear) times the step (0: no uplift); else `None`.
    """

    base_disp: jnp.ndarray
    base_shear_ratio: jnp.ndarray
    smooth_base_disp: jnp.ndarray
    smooth_base_shear_ratio: jnp.ndarray
    converged: jnp.ndarray
    storey_drift: jnp.ndarray | None = None
    floor_acceleration: jnp.ndarray | None = None
    uplift_time: jnp.ndarray | None = None


def smooth_max(x, width, axis=-1):
    """Smooth maximum of |x| along `axis`: the log-mean-cosh

        M_w(x) = w log( (1/n) sum_t cosh(x_t / w) ),

    with max|x| - w log(2 n) <= M_w(x) <= max|x| and M_w -> max|x| as w -> 0; smooth in x for
    w > 0 (its gradient is a softmax weighting of the samples near the peak).

    **Arguments:** `x` (any shape); `width` w > 0 [units of x]; `axis`: time axis.

    **Returns:** M_w(x) with `axis` removed.
    """
    x = jnp.asarray(x)
    n = x.shape[axis]
    top = jax.lax.stop_gradient(jnp.max(jnp.abs(x), axis=axis, keepdims=True))
    terms = 0.5 * (jnp.exp((x - top) / width) + jnp.exp((-x - top) / width))
    return jnp.squeeze(top, axis) + width * jnp.log(jnp.sum(terms, axis=axis) / n)


def step_propagator(system: StructureOnSliders):
    """One step of `system` (`StructureOnSliders.newmark_update`, by its `linear_rule`) as a
    linear map of w = (u0, v0, g0, F_r0, g1) (2n + 3,) [m, m/s, m/s^2, N, m/s^2]: the
    displacements and velocities at its start, the ground acceleration at its start, the
    bearing force of the start state (`friction_force`) and the ground acceleration at its end;
    and of the bearing force F [N] on the isolator (DOF 0) solved for at its end:

        (u1, v1) = R w + f F

    (`_propagators.py`). One (2n, 2n + 3) product per step; the same step to rounding.

    **Returns:** (R (2n, 2n + 3), f (2n,), shear_row (2n,), shear_force); rows 0 and n of R w
    are the isolator's displacement and velocity without the bearing force that
    `isolator_force` takes, and shear_row . (u1, v1) + shear_force F_r1 the base shear over the
    weight above the isolators (`PeakResponse`), F_r1 the bearing force of the end state: for
    a building the first-storey shear, -sum_{j>=1} (C v + K u)_j / (g sum_{j>=1} m_j) (floors
    carry no friction force, so m_j (a_j + g) = -(C v + K u)_j; shear_force = 0); for a rigid
    mass -(c v + k u + F_r) / (m g).
    """
    m, damping, stiffness = system.mass, system.damping, system.stiffness
    n = m.shape[-1]
    step_matrix, force_column = system.step_matrices()
    if n == 1:  # a rigid mass: m (a + g) = -(c v + k u + F)
        weight = STANDARD_GRAVITY * m[0]
        return step_matrix, force_column, -jnp.concatenate([stiffness[0], damping[0]]) / weight, -1 / weight
    floors = jnp.arange(n) >= 1
    weight = STANDARD_GRAVITY * jnp.sum(jnp.where(floors, m, 0.0))
    shear_row = -jnp.concatenate([floors @ stiffness, floors @ damping]) / weight
    return step_matrix, force_column, shear_row, jnp.zeros((), m.dtype)


def peak_response(
    system: StructureOnSliders,
    duration: float,
    *,
    disp_width=None,
    shear_width=None,
    read_every: int = 1,
    steps_per_pass: int = 1,
    storey_height=None,
) -> PeakResponse:
    """Integrate `system` from rest over `duration` [s] and keep only peaks.

    The same `RiccatiNewmark` step as `simulate_structure` (Newmark average acceleration
    with the exact Bouc-Wen update), advanced in a `lax.scan` whose carry holds the state,
    the running maxima and a running log-sum-exp for `smooth_max` (the t = 0 rest state
    included, as in `simulate_structure`'s saved times); for more than one degree of freedom
    the linear part of the step is one (2n, 2n + 3) product (`step_propagator`).
    jit/vmap/grad-safe.

    **Arguments:**

    - `system`: a `StructureOnSliders` (rigid mass or building; DOF 0 = isolator).
    - `duration` [s]: end time, rounded down to a multiple of `system.time_step`.
    - `disp_width` [m], `shear_width` [-]: widths w of `smooth_max` for the base displacement
      and base shear ratio (default: 1e-3 m and 1e-3).
    - `read_every`: the peaks `base_disp`, `base_shear_ratio` are read every `read_every`
      steps (e.g. at a record's samples, as a program that records at the record step reads
      them; the smooth maxima still see every step).
    - `steps_per_pass`: steps written out in each pass of the loop (the same results; see
      `STEPS_PER_LOOP_PASS`, what `monte_carlo` takes; 1 where the run is differentiated).
    - `storey_height` [m]: also keep a building's storey drifts and level accelerations (`storey_rows`).

    **Returns:** a `PeakResponse`.
    """
    dt = float(system.time_step)
    n_steps = check_duration(system, duration)  # at least a step, within the record
    _check_loop_settings(read_every, steps_per_pass)
    dtype = system.mass.dtype
    widths = (
        jnp.asarray(1e-3 if disp_width is None else disp_width, dtype),
        jnp.asarray(1e-3 if shear_width is None else shear_width, dtype),
    )
    propagator = step_propagator(system)
    rows = None if storey_height is None else storey_rows(system, storey_height)

    def body(carry, step_and_ground):
        step, ground1, load1 = step_and_ground
        state, peaks, tops, totals, ok = carry
        state, base_disp, shear_ratio, converged, force = _advance(system, propagator, state, ground1, load1)
        storeys = () if rows is None else (rows[0] @ state[0], rows[1] @ state[0] + rows[2] * force)
        values = (base_disp, shear_ratio) + storeys  # the smooth maxima below take the first two
        read = (step + 1) % read_every == 0
        peaks = tuple(jnp.where(read, jnp.maximum(p, jnp.abs(v)), p) for p, v in zip(peaks, values))
        updated = [smooth_max_update(a, s, v, w) for a, s, v, w in zip(tops, totals, values, widths)]
        tops = tuple(u[0] for u in updated)
        totals = tuple(u[1] for u in updated)
        return (state, peaks, tops, totals, ok & converged), None

    # the record at every step's end, evaluated at once outside the loop
    times = jnp.arange(n_steps + 1) * dt
    ground = jax.vmap(system.ground_acceleration)(times)
    loads = None if system.vertical_acceleration is None else jax.vmap(system.load_factor)(times)
    carry = _start_carry(system, ground[0], rows, dtype, None if loads is None else loads[0])
    (_, peaks, tops, totals, ok), _ = jax.lax.scan(
        body, carry, (jnp.arange(n_steps), ground[1:], None if loads is None else loads[1:]),
        unroll=steps_per_pass)
    smooth = [smooth_max_value(a, s, n_steps + 1, w) for a, s, w in zip(tops, totals, widths)]
    return PeakResponse(
        base_disp=peaks[0],
        base_shear_ratio=peaks[1],
        smooth_base_disp=smooth[0],
        smooth_base_shear_ratio=smooth[1],
        converged=ok,
        **({} if rows is None else {"storey_drift": peaks[2], "floor_acceleration": peaks[3]}),
        **({} if loads is None else {"uplift_time": uplift_steps(system, n_steps) * dt}),
    )


def _check_loop_settings(read_every, steps_per_pass) -> None:
    if isinstance(read_every, bool) or not isinstance(read_every, int) or read_every < 1:
        raise ValueError(f"read_every: must be a positive integer number of steps, got {read_every!r}.")
    if isinstance(steps_per_pass, bool) or not isinstance(steps_per_pass, int) or steps_per_pass < 1:
        raise ValueError(f"steps_per_pass: must be a positive integer, got {steps_per_pass!r}.")


def smooth_max_update(top, total, x, width):
    """The running (top, total) of `smooth_max` with the sample x added (start: (0, 1) for a
    run from rest, x = 0 at t = 0): top = max |x| so far (no gradient), total = sum_t
    cosh(x_t / w) exp(-top / w) [-]."""
    new_top = jnp.maximum(top, jax.lax.stop_gradient(jnp.abs(x)))
    total = total * jnp.exp((top - new_top) / width) + 0.5 * (
        jnp.exp((x - new_top) / width) + jnp.exp((-x - new_top) / width)
    )
    return new_top, total


def smooth_max_value(top, total, count, width):
    """`smooth_max` M_w = top + w log(total / count) of `count` samples from their running
    (top, total) (`smooth_max_update`)."""
    return top + width * jnp.log(total / count)


def _advance(system, propagator, state, ground1, load1=None):
    """One step of the peak loop: (state, base displacement, base shear ratio, converged,
    isolator force of the stored state: F = mu W Z and the pendulum's force beyond K u).

    The state (u, v), the bearing force per unit Z and its slope of the stored state
    (`friction_factors`) and the ground acceleration at the start of the step, advanced by
    `step_propagator` (one product per step); the same step as `newmark_update` to rounding.
    A bearing with history (heating, wear) steps with its friction at the start of the step
    (`at_history`) and carries its heat states and travel in `history`. With a vertical
    record the state also carries the load factor N / W of its time (`load1` at the end).
    """
    step_matrix, force_column, shear_row, shear_force = propagator
    if isinstance(system, StructureOnTriple):  # the isolator's state in place of Z
        x, isolator, ground0, _ = state  # the load at the step's end
        x1, isolator1, converged, bearing = system.step(x, isolator, ground0, ground1, (step_matrix, force_column),
                                                        load1)
        shear = small_dot(shear_row, x1, WRITTEN_OUT_PRODUCT) + shear_force * isolator1[3]
        return (x1, isolator1, ground1, load1), x1[0], shear, converged, isolator1[3]
    n = system.mass.shape[-1]
    x, z, z_peak, start_factors, ground0, history, load0 = state
    stepped = system
    if history:  # the force at the step's start with the friction of the start's history
        stepped = system.at_history(*history)
        start_factors = stepped.friction_factors(x[n], z_peak, load0)
    x1, z1, z_peak1, converged = stepped.propagated_step(x, z, z_peak, start_factors, ground0, ground1,
                                                         (step_matrix, force_column), load0, load1)
    factors1 = stepped.friction_factors(x1[n], z_peak1, load1)  # of the stored state: F = mu W Z
    friction = factors1[0] * z1 * system.asymmetry_factor(z1)
    bearing_force = friction
    if system.surface is not None or load1 is not None:  # the pendulum's force beyond W u / R
        bearing_force = bearing_force + system.surface_force(x1[0], load1)
    shear = small_dot(shear_row, x1, WRITTEN_OUT_PRODUCT) + shear_force * bearing_force
    if history:
        history = system.next_history(*history, x[0], x1[0], x[n], z_peak, z, load0)
    return (x1, z1, z_peak1, factors1, ground1, history, load1), x1[0], shear, converged, bearing_force


def _start_carry(system, ground0, rows, dtype, load0=None):
    """Carry of the peak loop at rest: (state, peaks, tops, totals, all converged)."""
    zero = jnp.zeros((), dtype)
    one = jnp.ones((), dtype)
    if isinstance(system, StructureOnTriple):
        state = (jnp.zeros(2 * system.mass.shape[-1], dtype), system.initial_isolator(), ground0, load0)
        return (state, (zero, zero) + storey_start(rows, dtype), (zero, zero), (one, one), jnp.array(True))
    y0 = initial_state(system)
    start_factors = system.friction_factors(y0["v"][0], y0["z_peak"], load0)
    history = (y0["heat"], y0["travel"]) if system.history else ()
    state = (jnp.concatenate([y0["u"], y0["v"]]), y0["z"], y0["z_peak"], start_factors, ground0,
             history, load0)
    return (state, (zero, zero) + storey_start(rows, dtype), (zero, zero), (one, one), jnp.array(True))


def series_uplift_time(system, duration: float):
    """Time [s] of the steps 1..n (n = duration / dt, `check_duration`) whose end has N <= 0 in
    a two-direction series-pendulum structure (`BiaxialStructureOnTriple`), as `peak_response`
    counts it in one direction; `None` without a vertical record."""
    uniaxial = system.uniaxial
    if uniaxial.vertical_acceleration is None:
        return None
    n_steps = check_duration(uniaxial, duration)
    return uplift_steps(uniaxial, n_steps) * float(uniaxial.time_step)
