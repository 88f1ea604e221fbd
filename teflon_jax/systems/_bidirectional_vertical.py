"""The vertical ground acceleration in a structure on bearing groups in two directions.

As in one direction (`_vertical.py`): every group's normal load is s W_g with
s = max(1 + a_v / g, 0), on its friction mu s W_g Z and on a friction pendulum's restoring
force s W_g d_g / R (whose W_g / R is part of the structure's K); at s = 0 the groups carry no
shear. A copy of the structure at one load factor (`loaded_bidirectional`) steps with the
friction under s W_g and the pendulum's change (s - 1) W_g / R d_g moved into the bearings'
equilibrium d = d_lin - G_b (F(d) + A d), A = diag((s - 1) W_g / R):

    d = (I + G_b A)^-1 d_lin - (I + G_b A)^-1 G_b F(d),

the same problem with d_lin and the flexibility G_b replaced (the velocity at the end of
the step is Newmark's 2 (d - d0) / dt - v0 whatever the forces). Reference: Almazan, De la
Llera & Inaudi (1998), Earthquake Eng. Struct. Dyn. 27(8), 845-867.
"""

import dataclasses

import jax.numpy as jnp


def loaded_bidirectional(system, load):
    """`system` (a `BidirectionalStructure`) under the load factor `load` = N / W [-]: its
    groups' loads s W_g, with `load` kept for the pendulum's change (`pendulum_change`)."""
    return dataclasses.replace(system, bearing_load=system.bearing_load * load, load=jnp.asarray(load),
                               vertical_acceleration=None)


def pendulum_change(system):
    """(s - 1) W_g / R (G,) [N/m] of a loaded copy: the change of the pendulum's stiffness
    (zeros for flat sliders)."""
    if system.pendulum_stiffness is None:
        return jnp.zeros_like(system.bearing_load)
    return (system.load - 1) * system.pendulum_stiffness


def loaded_heat(system, coefficient, slide):
    """(mu s, slide) of a loaded copy for the heat flux mu s p |v| and the travel (none while
    uplifted); unchanged for a structure without a load factor."""
    if system.load is None:
        return coefficient, slide
    return coefficient * system.load, jnp.where(system.load > 0, slide, 0.0)


def loaded_solve(system, p):
    """`BidirectionalStructure._solve_bearings` of a loaded copy with the pendulum's change of
    stiffness (module docstring): the total bearing forces F + A d (x, y parts), Z and
    convergence."""
    a = pendulum_change(system)
    n = a.shape[0]
    (xx, xy), (yx, yy) = p["flexibility"]
    flexibility = jnp.block([[xx, xy], [yx, yy]])
    matrix = jnp.eye(2 * n) + flexibility * jnp.concatenate([a, a])[None, :]
    flexibility = jnp.linalg.solve(matrix, flexibility)
    d_linear = jnp.linalg.solve(matrix, jnp.concatenate(p["d_linear"]))
    blocks = ((flexibility[:n, :n], flexibility[:n, n:]), (flexibility[n:, :n], flexibility[n:, n:]))
    (fx, fy), z, converged = system._solve_bearings(
        {**p, "flexibility": blocks, "d_linear": (d_linear[:n], d_linear[n:])})
    d = d_linear - flexibility @ jnp.concatenate([fx, fy])
    return (fx + a * d[:n], fy + a * d[n:]), z, converged
