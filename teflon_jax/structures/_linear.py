"""The linear structures of the paper's applications, as matrices: the rigid mass and the
six-storey building of Table 2 over their isolation level, and the ground motion that loads them.

Coordinates relative to the ground, degree of freedom 0 = the isolator / base slab. The
stepped systems (`teflon_jax.systems.rigid_mass`, `six_storey_building`) put the sliders
under these matrices.
Reference: Constantinou, Mokha & Reinhorn (1990), "Teflon bearings in base isolation II:
Modeling", J. Struct. Eng. 116(2), Figs. 7-11 and Table 2 (MODEL.md Section 8).
"""

from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from ..excitation import Signal, uniform_signal
from ..tables import BuildingData, load_table2
from ..units import STANDARD_GRAVITY
from ..validation import concrete, require


class LinearStructure(NamedTuple):
    """The linear part of a structure on sliders: `mass` (n,) [kg], `stiffness` and `damping`
    (n, n) [N/m], [N s/m] relative to the ground, the total normal load W [N] its bearings
    carry (`bearing_load`) and the restoring stiffness W / R [N/m] of a concave sliding surface
    (`pendulum_stiffness`, `None` on flat sliders)."""

    mass: jnp.ndarray
    stiffness: jnp.ndarray
    damping: jnp.ndarray
    bearing_load: jnp.ndarray
    pendulum_stiffness: jnp.ndarray | None = None


def check_finite(value, name: str, rule, text: str) -> None:
    """`require` with the finiteness test every physical input here needs."""
    require(value, lambda x: np.isfinite(x) & rule(x), name, text)


def signal_from_motion(motion) -> Signal:
    """A `GroundMotion` as a `Signal` of ground acceleration [m/s^2] with its clock restarted
    at 0 (a windowed record such as SCT 25-75 s starts at t = 0)."""
    return uniform_signal(np.asarray(motion.acceleration, dtype=float), float(motion.time_step))


def rigid_mass_matrices(*, weight, isolation_period=None, damping_ratio=0.0, radius=None) -> LinearStructure:
    """A rigid mass m = W/g over its isolation (Figs. 7-10 of the paper):

        m u'' + c u' + (k + W/R) u = ...,   k = m (2 pi / T)^2,   c = 2 zeta m omega,

    with omega the frequency of the restoring spring(s). `weight` W [N] (> 0), `isolation_period`
    T [s] (> 0) of a linear spring or `None`, `damping_ratio` zeta [-] (>= 0; needs a restoring
    stiffness when > 0), `radius` R [m] (> 0) of a spherical sliding surface or `None`.
    `ValueError` naming the argument. Returns a 1-degree-of-freedom `LinearStructure`."""
    check_finite(weight, "weight", lambda x: x > 0, "must be > 0 [N]")
    check_finite(damping_ratio, "damping_ratio", lambda x: x >= 0, "must be >= 0")
    mass = jnp.asarray(weight, dtype=float) / STANDARD_GRAVITY
    stiffness = jnp.zeros(())
    if isolation_period is not None:
        check_finite(isolation_period, "isolation_period", lambda x: x > 0, "must be > 0 [s], or None for no spring")
        stiffness = stiffness + mass * (2 * jnp.pi / jnp.asarray(isolation_period, dtype=float)) ** 2
    if radius is not None:
        check_finite(radius, "radius", lambda x: x > 0, "must be > 0 [m], or None for a flat sliding surface")
        stiffness = stiffness + jnp.asarray(weight, dtype=float) / jnp.asarray(radius, dtype=float)
    if isolation_period is None and radius is None:
        zeta = concrete(damping_ratio)
        if zeta is None or np.any(zeta > 0):
            raise ValueError(
                "damping_ratio: the rigid-body mode has no frequency without a restoring spring; "
                "give isolation_period or radius, or damping_ratio=0."
            )
        damping = jnp.zeros(())
    else:
        omega = jnp.sqrt(stiffness / mass)
        damping = 2 * jnp.asarray(damping_ratio, dtype=float) * mass * omega
    return LinearStructure(
        mass=mass[None], stiffness=stiffness.reshape(1, 1), damping=damping.reshape(1, 1),
        bearing_load=jnp.asarray(weight, dtype=float),
        pendulum_stiffness=None if radius is None else jnp.asarray(weight, dtype=float) / jnp.asarray(radius, dtype=float))


def superstructure_matrices(building: BuildingData | None = None):
    """Fixed-base mass, stiffness and damping matrices of the Table 2 frame (6 floors, SI).

    The published mode shapes Phi are rounded to three digits, so they are not exactly
    M-orthogonal (largest off-diagonal of the normalised Phi^T M Phi is about 1e-2). They are
    made M-orthonormal by the symmetric (Lowdin) orthogonalisation
    Phi_o = Phi_n (Phi_n^T M Phi_n)^(-1/2), the M-orthonormal set closest to the published
    one, and then

        K_s = M Phi_o diag(omega^2) Phi_o^T M,   C_s = M Phi_o diag(2 zeta omega) Phi_o^T M,

    whose fixed-base frequencies are exactly Table 2's and whose damping is zeta (2 %) in every
    mode (classical damping).

    **Returns:** `(floor_masses (6,) [kg], K_s (6, 6) [N/m], C_s (6, 6) [N s/m], Phi_o (6, 6))`.
    """
    building = load_table2() if building is None else building
    m = np.full(6, building.floor_weight / STANDARD_GRAVITY)
    M = np.diag(m)
    phi = np.asarray(building.mode_shapes, dtype=float)
    phi_n = phi / np.sqrt(np.einsum("im,i,im->m", phi, m, phi))
    gram = phi_n.T @ M @ phi_n
    values, vectors = np.linalg.eigh(gram)
    phi_o = phi_n @ (vectors @ np.diag(values**-0.5) @ vectors.T)
    omega = 2 * np.pi * np.asarray(building.frequencies, dtype=float)
    zeta = building.modal_damping
    K = M @ phi_o @ np.diag(omega**2) @ phi_o.T @ M
    C = M @ phi_o @ np.diag(2 * zeta * omega) @ phi_o.T @ M
    return m, 0.5 * (K + K.T), 0.5 * (C + C.T), phi_o


def building_matrices(*, isolation_period, isolation_damping=0.05, building: BuildingData | None = None) -> LinearStructure:
    """The six-storey frame of Table 2 over its isolation level (Fig. 11 of the paper).

    Degrees of freedom, relative to the ground: 0 = base, 1-6 = floors. With the fixed-base
    K_s, C_s of `superstructure_matrices` and the vector of ones 1,

        K = [[k_b + 1^T K_s 1, -1^T K_s], [-K_s 1, K_s]],   C likewise with c_b and C_s,
        M = diag(m_b, m_1 ... m_6),   m_b = (W - 6 W_floor) / g (42 kip for W = 672 kip),

    k_b = (W/g)(2 pi / T_b)^2 (rubber springs carrying no vertical load) and
    c_b = 2 zeta_b (2 pi / T_b) W / g (viscous damping zeta_b of the rigid-body mode). The
    bearings carry the total weight W. `isolation_period` T_b [s] (> 0), `isolation_damping`
    zeta_b [-] (>= 0), `building` (default Table 2 from `load_table2()`). Returns a
    7-degree-of-freedom `LinearStructure`.
    """
    check_finite(isolation_period, "isolation_period", lambda x: x > 0, "must be > 0 [s]")
    check_finite(isolation_damping, "isolation_damping", lambda x: x >= 0, "must be >= 0")
    building = load_table2() if building is None else building
    m_floor, K_s, C_s, _ = superstructure_matrices(building)
    total_mass = building.total_weight / STANDARD_GRAVITY
    base_mass = building.base_weight / STANDARD_GRAVITY
    if not base_mass > 0:
        raise ValueError(
            f"building: total_weight must exceed the six floor weights; base weight is "
            f"{building.base_weight} N."
        )
    omega_b = 2 * jnp.pi / jnp.asarray(isolation_period, dtype=float)
    k_b = total_mass * omega_b**2
    c_b = 2 * jnp.asarray(isolation_damping, dtype=float) * omega_b * total_mass

    def assemble(spring, matrix):
        ones = np.ones(6)
        top = np.concatenate([[ones @ matrix @ ones], -(ones @ matrix)])
        full = np.vstack([top, np.column_stack([-(matrix @ ones), matrix])])
        return jnp.asarray(full).at[0, 0].add(spring)

    return LinearStructure(
        mass=jnp.asarray(np.concatenate([[base_mass], m_floor])), stiffness=assemble(k_b, K_s),
        damping=assemble(c_b, C_s), bearing_load=jnp.asarray(building.total_weight, dtype=float))
