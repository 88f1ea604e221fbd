"""Sliding friction laws of PTFE on polished stainless steel.

Reference: Constantinou, Mokha & Reinhorn (1990), J. Struct. Eng. 116(2), Eq. 1 and Sections on
anisotropy and multiple interfaces.
"""

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import ArrayLike


class FrictionParameters(eqx.Module):
    """Constants of the velocity-dependent friction law, Eq. 1.

    mu_s(v) = f_max - delta_f * exp(-rate_a * |v|)

    - `f_max` [-]: coefficient at large sliding velocity (paper: f_max).
    - `delta_f` [-]: f_max minus the coefficient at vanishing velocity (paper: Df).
    - `rate_a` [s/m]: how fast friction rises with velocity (paper: a, tabulated in s/in).

    Constant (Coulomb) friction is `delta_f = 0`; see `coulomb_friction`.
    """

    f_max: ArrayLike
    delta_f: ArrayLike
    rate_a: ArrayLike

    @property
    def f_min(self):
        """Coefficient at vanishing velocity, f_max - delta_f [-]."""
        return self.f_max - self.delta_f

    def scaled(self, factor) -> "FrictionParameters":
        """The constants of `factor` times this friction coefficient at every velocity: f_max
        and delta_f times `factor`, rate_a kept."""
        return FrictionParameters(f_max=factor * self.f_max, delta_f=factor * self.delta_f,
                                  rate_a=self.rate_a)


def coulomb_friction(coefficient: ArrayLike) -> FrictionParameters:
    """Constant friction coefficient [-] as `FrictionParameters` (delta_f = 0)."""
    coefficient = jnp.asarray(coefficient, dtype=float)
    return FrictionParameters(
        f_max=coefficient, delta_f=jnp.zeros_like(coefficient), rate_a=jnp.zeros_like(coefficient)
    )


def sliding_friction(params: FrictionParameters, speed: ArrayLike, n_interfaces: int = 1):
    """Eq. 1 at sliding `speed` [m/s] for a stack of `n_interfaces` sharing the motion.

    Each of n interfaces in series slides at about v / n, so the law is evaluated there
    (Section 5 of MODEL.md; the R-FBI bearing of Fig. 10 has n = 24).

    **Returns:** the friction coefficient mu_s [-].
    """
    speed = jnp.abs(speed) / n_interfaces
    return params.f_max - params.delta_f * jnp.exp(-params.rate_a * speed)


def sliding_angle_weight(velocity_x: ArrayLike, velocity_y: ArrayLike, lay_angle: ArrayLike | None = None):
    """Weight w in [0, 1] of the perpendicular-to-lay constants for a velocity direction.

    w = |theta| / (pi / 2) with theta the angle of the velocity line to the lay, folded into
    [0, pi/2]: 0 when sliding along the lay, 1 across it. The lay is the x axis, or at
    `lay_angle` phi [rad] from x towards y: the velocity is then taken in the lay's axes,
    (v_par, v_perp) = (vx cos phi + vy sin phi, -vx sin phi + vy cos phi). Safe (finite
    gradient) at rest.
    """
    if lay_angle is not None:
        c, s = jnp.cos(lay_angle), jnp.sin(lay_angle)
        velocity_x, velocity_y = c * velocity_x + s * velocity_y, c * velocity_y - s * velocity_x
    ax, ay = jnp.abs(velocity_x), jnp.abs(velocity_y)
    moving = (ax + ay) > 0
    theta = jnp.arctan2(jnp.where(moving, ay, 0.0), jnp.where(moving, ax, 1.0))
    return theta / (jnp.pi / 2)


def anisotropic_friction(
    parallel: FrictionParameters, perpendicular: FrictionParameters, weight: ArrayLike
) -> FrictionParameters:
    """Constants interpolated linearly between sliding parallel (weight 0) and perpendicular
    (weight 1) to the lay of the steel, as assumed in the paper's anisotropic biaxial model."""

    def mix(p, q):
        return (1 - weight) * p + weight * q

    return FrictionParameters(
        f_max=mix(parallel.f_max, perpendicular.f_max),
        delta_f=mix(parallel.delta_f, perpendicular.delta_f),
        rate_a=mix(parallel.rate_a, perpendicular.rate_a),
    )
