"""Peak storey results of a building on sliders: interstorey drift ratio and total floor
acceleration at every floor, with the base peaks of `peak_response`, along one run.

For a building with degrees of freedom 0 = base slab (on the isolators) and 1..n-1 = floors,
displacements u relative to the ground:

    drift_j = |u_j - u_(j-1)| / h_j                       storey j = 1..n-1 [-],
    a_j + a_g = -(C v + K u)_j / m_j                      floor j = 1..n-1 [m/s^2],

the second from the floor's equation of motion m_j (a_j + a_g) + (C v + K u)_j = 0 (no
bearing force acts on a floor), so both are linear in the state (u, v) at each step's end.
Storey 1 lies between the base slab and floor 1, so its drift excludes the isolators'
displacement, which is the base peak `base_disp`. Reference for the building: Constantinou,
Mokha & Reinhorn (1990), J. Struct. Eng. 116(2), Table 2 and Fig. 11.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._block_algebra import small_dot
from ._peaks import step_propagator
from ._structure import WRITTEN_OUT_PRODUCT, StructureOnSliders, check_duration, initial_state


class StoreyPeaks(eqx.Module):
    """Peaks of one run of a building (batched by `monte_carlo(storeys=True)`).

    - `base_disp` [m], `base_shear_ratio` [-], `converged`: as in `PeakResponse`;
    - `storey_drift` (n-1,) [-]: max_t |u_j - u_(j-1)| / h_j, storey 1 (base slab to floor 1) first;
    - `floor_acceleration` (n-1,) [m/s^2]: max_t |a_j + a_g| of floors 1..n-1 (total).
    """

    base_disp: jnp.ndarray
    base_shear_ratio: jnp.ndarray
    storey_drift: jnp.ndarray
    floor_acceleration: jnp.ndarray
    converged: jnp.ndarray


def storey_rows(system: StructureOnSliders, storey_height):
    """(drift rows (n-1, 2n), acceleration rows (n-1, 2n)): the linear maps of the state
    (u, v) to the drift ratios (u_j - u_(j-1)) / h_j and the total floor accelerations
    -(C v + K u)_j / m_j of floors j = 1..n-1 (module docstring). `storey_height` [m]: a
    scalar or (n-1,) > 0."""
    n = system.mass.shape[-1]
    if n < 2:
        raise ValueError("system: storey results need a building (a base and at least one floor), "
                         "not a rigid mass.")
    height = jnp.broadcast_to(jnp.asarray(storey_height, system.mass.dtype), (n - 1,))
    difference = jnp.eye(n)[1:] - jnp.eye(n, k=-1)[1:]
    drift = jnp.concatenate([difference / height[:, None], jnp.zeros((n - 1, n))], axis=1)
    floors = system.mass[1:, None]
    acceleration = -jnp.concatenate([system.stiffness[1:], system.damping[1:]], axis=1) / floors
    return drift, acceleration


def storey_peak_response(system: StructureOnSliders, duration: float, *, storey_height) -> StoreyPeaks:
    """Integrate the building `system` from rest over `duration` [s] with the step of
    `peak_response` (`step_propagator`, `StructureOnSliders.propagated_step`) and keep the
    peak base displacement and base shear ratio and, per storey, the peak drift ratio and
    total floor acceleration (module docstring), all read at every step. jit/vmap-safe.

    **Arguments:** `system`: a `StructureOnSliders` with floors (DOF 0 = base slab);
    `duration` [s]; `storey_height` [m]: scalar or one per storey (n-1,), > 0, not traced (the Table 2
    building: `load_table2().storey_height`).

    **Returns:** a `StoreyPeaks`.
    """
    n_steps = check_duration(system, duration)
    if not np.all(np.asarray(storey_height) > 0):
        raise ValueError(f"storey_height: must be > 0 m, got {storey_height}.")
    drift_rows, acceleration_rows = storey_rows(system, storey_height)
    n = system.mass.shape[-1]
    step_matrix, force_column, shear_row, shear_force = step_propagator(system)

    def body(carry, ground1):
        (x, z, z_peak, start_factors, ground0), peaks, ok = carry
        x1, z1, z_peak1, converged = system.propagated_step(x, z, z_peak, start_factors, ground0, ground1,
                                                            (step_matrix, force_column))
        factors1 = system.friction_factors(x1[n], z_peak1)
        shear = small_dot(shear_row, x1, WRITTEN_OUT_PRODUCT) + shear_force * (factors1[0] * z1)
        now = (jnp.abs(x1[0]), jnp.abs(shear), jnp.abs(drift_rows @ x1), jnp.abs(acceleration_rows @ x1))
        peaks = tuple(jnp.maximum(p, v) for p, v in zip(peaks, now))
        return ((x1, z1, z_peak1, factors1, ground1), peaks, ok & converged), None

    dtype = system.mass.dtype
    y0 = initial_state(system)
    ground = jax.vmap(system.ground_acceleration)(jnp.arange(n_steps + 1) * float(system.time_step))
    start_factors = system.friction_factors(y0["v"][0], y0["z_peak"])
    state = (jnp.concatenate([y0["u"], y0["v"]]), y0["z"], y0["z_peak"], start_factors, ground[0])
    zero, floors = jnp.zeros((), dtype), jnp.zeros((n - 1,), dtype)
    carry = (state, (zero, zero, floors, floors), jnp.array(True))
    (_, peaks, ok), _ = jax.lax.scan(body, carry, ground[1:])
    return StoreyPeaks(base_disp=peaks[0], base_shear_ratio=peaks[1], storey_drift=peaks[2],
                       floor_acceleration=peaks[3], converged=ok)
