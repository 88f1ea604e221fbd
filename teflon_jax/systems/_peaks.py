"""Peak responses of an isolated structure along a run (running and smooth maxima)."""

import equinox as eqx
import jax
import jax.numpy as jnp

from ..units import STANDARD_GRAVITY
from ._structure import StructureOnSliders, check_duration, initial_state

RESPONSE_NAMES = ("base_disp", "base_shear_ratio")
"""Peak |base displacement| [m] and peak |base shear| / weight above the isolators [-]."""


class PeakResponse(eqx.Module):
    """Peaks of one response history (scalars, or batched by `monte_carlo`).

    - `base_disp` max_t |u_0(t)| [m]: isolator displacement relative to the ground.
    - `base_shear_ratio` max_t |V(t)| / W_s [-]: V = sum_j m_j a_j^total over the masses
      above the isolators (floors 1.. of a building: the first-storey shear), or m a^total for
      a rigid mass; W_s their weight.
    - `smooth_base_disp`, `smooth_base_shear_ratio`: the same maxima through `smooth_max`
      (differentiable); equal to the peaks' lower bounds when no width is given.
    - `converged`: every step's Newton iteration converged.
    """

    base_disp: jnp.ndarray
    base_shear_ratio: jnp.ndarray
    smooth_base_disp: jnp.ndarray
    smooth_base_shear_ratio: jnp.ndarray
    converged: jnp.ndarray


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


def _shear_ratio(system: StructureOnSliders, relative_acceleration, ground):
    """|V| / W_s for the relative accelerations [m/s^2] under ground acceleration `ground`
    [m/s^2] (see `PeakResponse`)."""
    total = relative_acceleration + ground
    mass = system.mass if system.mass.shape[-1] == 1 else system.mass[1:]
    acc = total if system.mass.shape[-1] == 1 else total[1:]
    return jnp.sum(mass * acc) / (jnp.sum(mass) * STANDARD_GRAVITY)


def peak_response(
    system: StructureOnSliders,
    duration: float,
    *,
    disp_width=None,
    shear_width=None,
    read_every: int = 1,
) -> PeakResponse:
    """Integrate `system` from rest over `duration` [s] and keep only peaks.

    The same `RiccatiNewmark` step as `simulate_structure` (Newmark average acceleration
    with the exact Bouc-Wen update), advanced in a `lax.scan` whose carry holds the state,
    the running maxima and a running log-sum-exp for `smooth_max` (the t = 0 rest state
    included, as in `simulate_structure`'s saved times). jit/vmap/grad-safe.

    **Arguments:**

    - `system`: a `StructureOnSliders` (rigid mass or building; DOF 0 = isolator).
    - `duration` [s]: end time, rounded down to a multiple of `system.time_step`.
    - `disp_width` [m], `shear_width` [-]: widths w of `smooth_max` for the base displacement
      and base shear ratio (default: 1e-3 m and 1e-3).
    - `read_every`: the peaks `base_disp`, `base_shear_ratio` are read every `read_every`
      steps (e.g. at a record's samples, as a program that records at the record step reads
      them; the smooth maxima still see every step).

    **Returns:** a `PeakResponse`.
    """
    dt = float(system.time_step)
    n_steps = check_duration(system, duration)  # at least a step, within the record
    if isinstance(read_every, bool) or not isinstance(read_every, int) or read_every < 1:
        raise ValueError(f"read_every: must be a positive integer number of steps, got {read_every!r}.")
    dtype = system.mass.dtype
    widths = (
        jnp.asarray(1e-3 if disp_width is None else disp_width, dtype),
        jnp.asarray(1e-3 if shear_width is None else shear_width, dtype),
    )

    def lse_update(top, total, x, width):
        new_top = jnp.maximum(top, jax.lax.stop_gradient(jnp.abs(x)))
        total = total * jnp.exp((top - new_top) / width) + 0.5 * (
            jnp.exp((x - new_top) / width) + jnp.exp((-x - new_top) / width)
        )
        return new_top, total

    def body(carry, step_and_ground):
        step, ground1 = step_and_ground
        y, a, peaks, tops, totals, ok = carry
        y1, converged = system.newmark_update(y, a, ground1)
        a1 = system.acceleration_at(ground1, y1)
        values = (y1["u"][0], _shear_ratio(system, a1, ground1))
        read = (step + 1) % read_every == 0
        peaks = tuple(jnp.where(read, jnp.maximum(p, jnp.abs(v)), p) for p, v in zip(peaks, values))
        updated = [lse_update(a, s, v, w) for a, s, v, w in zip(tops, totals, values, widths)]
        tops = tuple(u[0] for u in updated)
        totals = tuple(u[1] for u in updated)
        return (y1, a1, peaks, tops, totals, ok & converged), None

    zero = jnp.zeros((), dtype)
    one = jnp.ones((), dtype)
    y0 = initial_state(system)
    # the record at every step's end, evaluated at once outside the loop
    ground = jax.vmap(system.ground_acceleration)(jnp.arange(n_steps + 1) * dt)
    carry = (y0, system.acceleration_at(ground[0], y0), (zero, zero), (zero, zero), (one, one),
             jnp.array(True))
    (_, _, peaks, tops, totals, ok), _ = jax.lax.scan(body, carry, (jnp.arange(n_steps), ground[1:]))
    smooth = [a + w * jnp.log(s / (n_steps + 1)) for a, s, w in zip(tops, totals, widths)]
    return PeakResponse(
        base_disp=peaks[0],
        base_shear_ratio=peaks[1],
        smooth_base_disp=smooth[0],
        smooth_base_shear_ratio=smooth[1],
        converged=ok,
    )
