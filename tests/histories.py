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


def assert_plane_follows_line(line, plane, duration: float, *, moves: float, without: dict, changes: float):
    """The two-component structure `plane` under a y component of zero follows the
    one-component `line` along x to 1e-9 m over `duration` [s], the base moving by more than
    `moves` [m]; `plane` with the fields `without` replaced (a law switched off) leaves `line`
    by more than `changes` [m], so the agreement rests on that law."""
    import dataclasses

    import numpy as np

    a, b = simulate_history(line, duration), simulate_history(plane, duration)
    assert bool(a.succeeded) and bool(b.succeeded)
    u_line, u_plane = np.asarray(a.displacement[:, 0]), np.asarray(b.displacement[:, 0])
    assert np.max(np.abs(u_line)) > moves
    np.testing.assert_allclose(u_plane, u_line, rtol=0, atol=1e-9)
    held = simulate_history(dataclasses.replace(plane, **without), duration)
    assert np.max(np.abs(np.asarray(held.displacement[:, 0]) - u_line)) > changes
