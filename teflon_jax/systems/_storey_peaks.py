"""Storey results of a building on sliders: the interstorey drift ratio and total floor
acceleration at every floor as linear maps of the state, whose peaks `peak_response`
keeps when given `storey_height`.

For a building with degrees of freedom 0 = base slab (on the isolators) and 1..n-1 = floors,
displacements u relative to the ground:

    drift_j = |u_j - u_(j-1)| / h_j                       storey j = 1..n-1 [-],
    a_j + a_g = -((C v + K u)_j + delta_j0 F) / m_j       level j = 0..n-1 [m/s^2],

the second from the equations of motion M (u'' + 1 a_g) + C v + K u + e0 F = 0, F the bearing
force on the base slab (level 0); both are linear in the state (u, v) and F at each step's
end. Storey 1 lies between the base slab and floor 1, so its drift excludes the isolators'
displacement, which is the base peak `base_disp`. Reference for the building: Constantinou,
Mokha & Reinhorn (1990), J. Struct. Eng. 116(2), Table 2 and Fig. 11.
"""

import jax.numpy as jnp
import numpy as np

from ._structure import StructureOnSliders


def check_storey_height(n_dof: int, storey_height) -> np.ndarray:
    """`storey_height` [m] as (n_dof - 1,) once checked for a structure of `n_dof` degrees of
    freedom: `ValueError` naming `system` for a rigid mass (no storeys) and `storey_height`
    for a value that is not > 0 or not one per storey."""
    if n_dof < 2:
        raise ValueError("system: storey results need a building (a base and at least one floor), "
                         "not a rigid mass.")
    height = np.asarray(storey_height, float)
    if height.ndim > 1 or (height.ndim == 1 and height.shape[0] != n_dof - 1) or not np.all(height > 0):
        raise ValueError(f"storey_height: must be > 0 m, one value or one per storey ({n_dof - 1}), "
                         f"got {storey_height}.")
    return np.broadcast_to(height, (n_dof - 1,))


def storey_rows(system: StructureOnSliders, storey_height):
    """(drift rows (n-1, 2n), acceleration rows (n, 2n), acceleration force column (n,)):
    the linear maps of the state (u, v) to the drift ratios (u_j - u_(j-1)) / h_j of storeys
    j = 1..n-1, and of the state and the bearing force F [N] to the total accelerations
    -((C v + K u)_j + delta_j0 F) / m_j of levels j = 0 (base slab) ..n-1 (module docstring).

    **Arguments:** `system`: a building (DOF 0 = base slab, 1.. = floors); `storey_height`
    [m]: a scalar or one per storey (n-1,), > 0, not traced (the Table 2 building:
    `load_table2().storey_height`).
    """
    n = system.mass.shape[-1]
    height = jnp.asarray(check_storey_height(n, storey_height), system.mass.dtype)
    difference = jnp.eye(n)[1:] - jnp.eye(n, k=-1)[1:]
    drift = jnp.concatenate([difference / height[:, None], jnp.zeros((n - 1, n))], axis=1)
    acceleration = -jnp.concatenate([system.stiffness, system.damping], axis=1) / system.mass[:, None]
    force = -jnp.eye(n, dtype=system.mass.dtype)[0] / system.mass[0]
    return drift, acceleration, force


def storey_start(rows, dtype) -> tuple:
    """The running peaks of `storey_rows`'s quantities at rest: (drifts (n-1,), accelerations
    (n,)) of zeros, or () without storey results (`rows` None)."""
    if rows is None:
        return ()
    return jnp.zeros(rows[0].shape[0], dtype), jnp.zeros(rows[1].shape[0], dtype)


def directional_storeys(q, total_acceleration, storey_height):
    """Drift ratios (..., 2, S) [-] and total accelerations (..., 2, S + 1) [m/s^2] in x and y
    of the two-direction building (`bidirectional_building`: q = (x: base slab, floors 1..S;
    y: the same), `total_acceleration` the same layout [m/s^2]): (q_j - q_(j-1)) / h_j per
    storey and a_j + a_g per level, level 0 the base slab. jit/vmap-safe in q and the
    accelerations; `storey_height` [m] scalar or (S,), not traced."""
    n = q.shape[-1] // 2
    height = jnp.asarray(check_storey_height(n, storey_height), q.dtype)
    x, y = q[..., :n], q[..., n:]
    drift = jnp.stack([jnp.diff(x, axis=-1), jnp.diff(y, axis=-1)], axis=-2) / height
    acc = jnp.stack([total_acceleration[..., :n], total_acceleration[..., n:]], axis=-2)
    return drift, acc


def bidirectional_storey_peaks(response, system, storey_height) -> dict:
    """Peak storey results of a run of the two-direction building (`bidirectional_building`)
    from its histories (`simulate_bidirectional`), by `directional_storeys`:

    - `storey_drift` (2, S) [-]: max_t |q_j - q_(j-1)| / h_j in x and in y, storey 1 first;
    - `storey_drift_resultant` (S,) [-]: max_t of the drift vector's length over h_j;
    - `level_acceleration` (2, S + 1) [m/s^2]: max_t |a_j + a_g| in x and y, level 0 the base slab;
    - `level_acceleration_resultant` (S + 1,) [m/s^2]: max_t of the total acceleration's length.
    """
    q = jnp.asarray(response.q)
    total = jnp.asarray(response.acceleration) + jnp.asarray(response.ground) @ jnp.asarray(system.influence).T
    drift, acc = (np.asarray(v) for v in directional_storeys(q, total, storey_height))  # (nt, 2, .)
    return {"storey_drift": np.abs(drift).max(axis=0), "storey_drift_resultant": np.hypot(*np.moveaxis(drift, 1, 0)).max(axis=0),
            "level_acceleration": np.abs(acc).max(axis=0),
            "level_acceleration_resultant": np.hypot(*np.moveaxis(acc, 1, 0)).max(axis=0)}
