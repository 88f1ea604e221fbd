"""The plan of an isolated structure: where its bearing groups stand under a rigid base and
what they carry. A group at plan position P, arm r = P - C from the centre of mass C, slides by

    d = (u_x - theta r_y, u_y + theta r_x),    i.e. B = [[1, 0, -r_y], [0, 1, r_x]]

for base translations (u_x, u_y) and rotation theta (`plan_bearing_map`, small rotations); the
groups' tributary loads W_g add up to the weight (`check_plan`), each group's bearing constants
are stacked into one `SlidingBearing` of (G,) leaves (`stack_bearings`), and the levels of a
building stand at heights h_i above the sliding surface (`level_heights`).
Reference: plan kinematics as in 3D-BASIS (Nagarajaiah, Reinhorn & Constantinou 1991).
"""

import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import SlidingBearing

LOAD_TOLERANCE = 1e-3
"""Relative mismatch allowed between the sum of the tributary loads and the weight."""


def stack_bearings(bearings) -> SlidingBearing:
    """One `SlidingBearing` whose array leaves hold the constants of every group (G,).

    All groups must agree on the structure: all with or all without breakaway, all isotropic
    or all anisotropic, the same number of interfaces."""
    bearings = list(bearings)
    structures = {jax.tree_util.tree_structure(b) for b in bearings}
    if len(structures) != 1:
        raise ValueError(
            "bearings: the groups differ in kind (breakaway on some, anisotropy or stack height "
            "on others); give every group the same options."
        )
    return jax.tree_util.tree_map(
        lambda *leaves: jnp.stack([jnp.asarray(x, dtype=float) for x in leaves]), *bearings
    )


def check_plan(*, length_x, length_y, weight, centre_of_mass, positions, loads, names=None) -> None:
    """Refuse a plan whose loads do not add up to the weight or whose points lie off the slab.

    `ValueError` naming the group (or the centre of mass) and giving both numbers."""
    positions = np.asarray(positions, dtype=float).reshape(-1, 2)
    loads = np.asarray(loads, dtype=float).reshape(-1)
    names = [f"group {i + 1}" for i in range(len(loads))] if names is None else list(names)
    if not (length_x > 0 and length_y > 0):
        raise ValueError(f"plan: slab dimensions must be > 0 m, got {length_x} x {length_y} m.")
    if not weight > 0:
        raise ValueError(f"plan: weight must be > 0 N, got {weight} N.")
    if positions.shape[0] != loads.shape[0] or positions.shape[0] == 0:
        raise ValueError("plan: give one position and one load per bearing group (at least one group).")
    for name, (x, y) in zip(names + ["centre of mass"], [*positions, centre_of_mass]):
        if not (-1e-9 <= x <= length_x + 1e-9 and -1e-9 <= y <= length_y + 1e-9):
            raise ValueError(
                f"plan: {name} at ({x:g}, {y:g}) m lies outside the slab, which spans "
                f"0-{length_x:g} m in x and 0-{length_y:g} m in y."
            )
    for name, load in zip(names, loads):
        if not load > 0:
            raise ValueError(f"plan: {name} has load {load:g} N; tributary loads must be > 0.")
    total = float(np.sum(loads))
    if abs(total - weight) > LOAD_TOLERANCE * weight:
        raise ValueError(
            f"plan: the tributary loads add up to {total / 1e3:.6g} kN but the slab weighs "
            f"{weight / 1e3:.6g} kN; they must agree within {LOAD_TOLERANCE:.1%}."
        )


def plan_bearing_map(arms, size: int, indices) -> np.ndarray:
    """B (G, 2, `size`) of groups at arms r_g = P_g - C [m] from the centre of a rigid base whose
    x, y translations and rotation theta are the coordinates `indices` = (ix, iy, itheta):
    group g slides by (u_x - theta r_y, u_y + theta r_x)."""
    ix, iy, itheta = indices
    bearing_map = np.zeros((arms.shape[0], 2, size))
    bearing_map[:, 0, ix] = bearing_map[:, 1, iy] = 1.0
    bearing_map[:, 0, itheta] = -arms[:, 1]
    bearing_map[:, 1, itheta] = arms[:, 0]
    return bearing_map


def slab_point_displacement(q, points, centre_of_mass):
    """Displacement (..., P, 2) [m] of plan points (P, 2) [m] for slab coordinates q (..., 3)."""
    r = jnp.asarray(points) - jnp.asarray(centre_of_mass)
    ux, uy, theta = q[..., 0:1], q[..., 1:2], q[..., 2:3]
    return jnp.stack([ux - theta * r[:, 1], uy + theta * r[:, 0]], axis=-1)


def slab_corners(length_x: float, length_y: float) -> np.ndarray:
    """The four corners (4, 2) [m] of the slab, counter-clockwise from the origin."""
    return np.array([[0.0, 0.0], [length_x, 0.0], [length_x, length_y], [0.0, length_y]])


def level_heights(storey_heights, base_height, storeys: int) -> np.ndarray:
    """h_i (storeys + 1,) [m] of the base and the floors above the sliding surface:
    h_0 = `base_height`, h_i = h_0 + sum_{j <= i} `storey_heights`_j (one value, or one per
    storey). `ValueError` naming the argument for a value that is not finite and >= 0."""
    heights = np.asarray(storey_heights, dtype=float)
    if heights.ndim > 1 or (heights.ndim == 1 and heights.shape[0] != storeys):
        raise ValueError(f"storey_heights: one value or one per storey ({storeys}), got {storey_heights}.")
    if not np.all(np.isfinite(heights) & (heights >= 0)):
        raise ValueError(f"storey_heights: must be >= 0 m, got {storey_heights}.")
    base = float(base_height)
    if not (np.isfinite(base) and base >= 0):
        raise ValueError(f"base_height: must be >= 0 m, got {base_height}.")
    return base + np.concatenate([[0.0], np.cumsum(np.broadcast_to(heights, (storeys,)))])
