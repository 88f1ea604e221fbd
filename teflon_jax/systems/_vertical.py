"""The vertical ground acceleration in a structure on sliders: the isolators' normal load.

With the superstructure rigid in the vertical direction, the normal load on the isolators
follows the vertical ground acceleration a_v(t) [m/s^2, up positive]:

    N(t) = W (1 + a_v(t) / g) = s(t) W,   s = max(1 + a_v / g, 0),

W the weight above the isolators. The friction force mu N Z and a friction pendulum's
restoring force N u / R scale with s; a restoring spring (rubber, carrying no vertical load)
does not. At s = 0 (N <= 0, uplift) the bearing carries no shear: its friction and restoring
forces are exactly zero, Z follows the slider's motion (so that it is the sliding state
again at touchdown) and no heat enters the steel, nor does a wearing bearing count travel.
References: Almazan, De la Llera & Inaudi (1998), Earthquake Eng. Struct. Dyn. 27(8),
845-867 (the friction pendulum's force under a varying normal load); Mokha, Constantinou &
Reinhorn (1990), J. Struct. Eng. 116(2), 438-454 (the normal load's effect on PTFE friction).
"""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np

from ..excitation import Signal
from ..units import STANDARD_GRAVITY


def normal_load_factor(vertical_acceleration):
    """s = N / W = max(1 + a_v / g, 0) [-] at vertical ground acceleration a_v [m/s^2, up +]."""
    return jnp.maximum(1 + jnp.asarray(vertical_acceleration) / STANDARD_GRAVITY, 0.0)


def load_factor_at(vertical_acceleration: Signal | None, t):
    """`normal_load_factor` of the record `vertical_acceleration` at time t [s]; `None`
    without a vertical record (the load is then W throughout)."""
    if vertical_acceleration is None:
        return None
    return normal_load_factor(vertical_acceleration(t))


def uplifted(vertical_acceleration):
    """True where N <= 0, i.e. a_v <= -g [m/s^2]."""
    return 1 + jnp.asarray(vertical_acceleration) / STANDARD_GRAVITY <= 0


def with_vertical_motion(system, vertical_acceleration: Signal, radius=None):
    """`system` (a `StructureOnSliders` or `BidirectionalStructure`) with the vertical ground acceleration
    `vertical_acceleration` [m/s^2, up +] on its isolators' normal load (module docstring).

    `radius` R [m] of a friction pendulum: the part W / R of the isolator's stiffness that the
    normal load carries (scaled by N / W in each step; W / R per group in two directions);
    `None` for flat sliders, whose restoring springs keep their stiffness, and for a system
    that already holds its `pendulum_stiffness` (a slab on friction pendulums), which it keeps.
    """
    if not isinstance(vertical_acceleration, Signal):
        raise ValueError("vertical_acceleration: expected a Signal of the vertical ground "
                         f"acceleration [m/s^2], got {type(vertical_acceleration).__name__}.")
    stiffness = system.pendulum_stiffness
    if radius is not None:
        value = np.asarray(radius) if not isinstance(radius, jax.core.Tracer) else None
        if value is not None and not np.all(np.isfinite(value) & (value > 0)):
            raise ValueError(f"radius: must be > 0 [m] (the pendulum's radius), got {value.tolist()}.")
        stiffness = system.bearing_load / jnp.asarray(radius, float)
    return dataclasses.replace(system, vertical_acceleration=vertical_acceleration,
                               pendulum_stiffness=stiffness)


def loaded_surface_force(system, u0, load):
    """The isolator's force [N] beyond the structure's linear stiffness at displacement u0 [m]
    and load factor s = N / W: the pendulum's (s - 1) W u0 / R (its stiffness W / R is in
    the structure's K) and its surface's large-displacement and restrainer terms under N."""
    u0 = jnp.asarray(u0, dtype=float)
    force = jnp.zeros_like(u0)
    if system.surface is not None:
        force = system.surface.extra_force(u0, load * system.bearing_load)
    if system.pendulum_stiffness is not None:
        force = force + (load - 1) * system.pendulum_stiffness * u0
    return force


def loaded_isolator_force(system, ub_linear, vb_linear, compliance, y0, start_factors, load):
    """`StructureOnSliders.isolator_force` under the normal load s W at the end of the step.

    The total isolator force is F = F_b(x) + a x with F_b the bearing's (friction mu s W Z
    and surface terms under s W) and a = (s - 1) W / R the pendulum's change of stiffness
    (0 for flat sliders). Its equilibrium x = u_lin - g0 (F_b(x) + a x) is the same problem as
    without the load change, x = u_lin / c - (g0 / c) F_b(x) with c = 1 + g0 a, solved by
    the structure at load s W; its velocity stays the same function of x when v_lin becomes
    v_lin - gv a u_lin / c and gv becomes gv / c. At s = 0, F_b = 0 and F = -W x / R cancels
    the pendulum's stiffness: no shear.

    **Returns:** (F [N], Z, running peak of |Z|, converged), as `isolator_force`.
    """
    g0, gv = compliance
    a = 0.0 if system.pendulum_stiffness is None else (load - 1) * system.pendulum_stiffness
    c = 1 + g0 * a
    ub, vb = ub_linear / c, vb_linear - gv * a * ub_linear / c
    loaded = dataclasses.replace(system, bearing_load=load * system.bearing_load,
                                 vertical_acceleration=None, pendulum_stiffness=None)
    force, z1, z_peak1, converged = loaded.isolator_force(ub, y0, vb, (g0 / c, gv / c), start_factors)
    x = ub - g0 / c * force
    return force + a * x, z1, z_peak1, converged


def uplift_steps(system, n_steps: int):
    """Number of the steps 1..n_steps whose end has N <= 0 (0 without a vertical record)."""
    if system.vertical_acceleration is None:
        return None
    times = jnp.arange(1, n_steps + 1) * system.time_step
    return jnp.sum(uplifted(jax.vmap(system.vertical_acceleration)(times)))
