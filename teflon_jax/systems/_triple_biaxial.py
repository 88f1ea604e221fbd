"""Peaks of a structure on friction pendulums of sliders in series under two horizontal ground
components (`StructureOnSeries` with `ground_y`), read along the steps without keeping them:
resultants, as `bidirectional_peak_response` reads them; a building's storey drifts and level
accelerations per direction."""

import jax
import jax.numpy as jnp

from ..units import STANDARD_GRAVITY
from ._structure_build import check_duration, storey_rows
from ._triple_structure import BiaxialStructureOnTriple


def held_loads(structure, n_steps: int):
    """N / W (n_steps,) of each step (at its end) of the structure's vertical record
    (`StructureOnSeries.load_factor`; `check_duration` checked it lasts), or `None`."""
    if structure.vertical_acceleration is None:
        return None
    return jax.vmap(structure.load_factor)(jnp.arange(1, n_steps + 1) * float(structure.time_step))


def biaxial_peaks(system: BiaxialStructureOnTriple, duration: float, widths=(1e-3, 1e-3), read_every: int = 1,
                  storey_height=None):
    """Peaks of the resultant base displacement [m] and of the resultant force on the masses
    above the isolators over their weight (base slab included, as `bidirectional_peak_response`
    reads it), their smooth maxima (widths [m], [-]) and whether every step balanced:
    (base_disp, base_shear_ratio, smooth_disp, smooth_shear, converged); with `storey_height`
    [m] (a building) also the peak |drift ratio| (2, S) [-] of each storey and |total
    acceleration| (2, S + 1) [m/s^2] of each level in x and in y, the maps of `storey_rows`
    applied to each direction's state and its bearing force beyond the reference spring (as
    one direction's `peak_response` reads them). jit/vmap/grad-safe."""
    dt = float(system.time_step)
    n_steps = check_duration(system.uniaxial, duration)
    n = system.mass.shape[-1]
    mass = system.mass
    weight = jnp.sum(mass) * STANDARD_GRAVITY
    linear = system.uniaxial
    matrices = linear.step_matrices()
    rows = None if storey_height is None else storey_rows(linear, storey_height)
    ground = jax.vmap(system.ground)(jnp.arange(n_steps + 1) * dt)
    widths = tuple(jnp.asarray(w, mass.dtype) for w in widths)

    def storeys(x, extra):  # drift ratios (2, S) and total accelerations (2, S + 1), x and y
        if rows is None:
            return ()
        return jnp.abs(x @ rows[0].T), jnp.abs(x @ rows[1].T + extra[:, None] * rows[2])

    def body(carry, step_and_ground):
        step, (ground0, ground1), load = step_and_ground
        x, isolator, peaks, tops, totals, ok = carry
        x1, isolator1, converged, _ = system.step(x, isolator, ground0, ground1, matrices, load)
        inner = x1[:, :n] @ linear.stiffness.T + x1[:, n:] @ linear.damping.T
        force = -(jnp.sum(inner, axis=-1) + isolator1[3])  # sum_j m_j a_j^total in x and y
        now = (jnp.sqrt(jnp.sum(x1[:, 0] ** 2)), jnp.sqrt(jnp.sum(force**2)) / weight) + storeys(x1, isolator1[3])
        read = (step + 1) % read_every == 0
        peaks = tuple(jnp.where(read, jnp.maximum(p, v), p) for p, v in zip(peaks, now))
        new_tops = tuple(jnp.maximum(t, jax.lax.stop_gradient(v)) for t, v in zip(tops, now))  # the first two
        totals = tuple(s * jnp.exp((t - nt) / w) + 0.5 * (jnp.exp((v - nt) / w) + jnp.exp((-v - nt) / w))
                       for s, t, nt, v, w in zip(totals, tops, new_tops, now, widths))
        return (x1, isolator1, peaks, new_tops, totals, ok & converged), None

    zero, one = jnp.zeros((), mass.dtype), jnp.ones((), mass.dtype)
    start = jnp.zeros((2, 2 * n), mass.dtype)
    carry = (start, system.initial_isolator(), (zero, zero) + storeys(start, jnp.zeros(2, mass.dtype)),
             (zero, zero), (one, one), jnp.array(True))
    steps = (jnp.arange(n_steps), (ground[:-1], ground[1:]), held_loads(linear, n_steps))
    (_, _, peaks, tops, totals, ok), _ = jax.lax.scan(body, carry, steps)
    smooth = [t + w * jnp.log(s / (n_steps + 1)) for t, s, w in zip(tops, totals, widths)]
    return (peaks[0], peaks[1], smooth[0], smooth[1], ok) + tuple(peaks[2:])
