"""Two-component histories as arrays, read from the one history driver's response."""

import jax.numpy as jnp

from teflon_jax.systems import simulate_history


def planar_histories(system, duration: float):
    """(time (nt,), x (nt, 2, 2n) = (u, v) in x and in y, bearing force (nt, 2) [N], sliders
    (nt, S, 2) [m], total accelerations (nt, 2, n) [m/s^2], converged (nt,)) of a structure
    on series pendulums under two components (`simulate_history`). jit/vmap-safe."""
    r = simulate_history(system, duration)
    nt, n = r.time.shape[0], system.mass.shape[-1]
    x = jnp.concatenate([r.displacement.reshape(nt, 2, n), r.velocity.reshape(nt, 2, n)], -1)
    return r.time, x, r.bearing_force, r.slider, r.total_acceleration.reshape(nt, 2, n), r.converged
