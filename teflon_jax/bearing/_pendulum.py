"""The concave sliding surface of a single friction pendulum (FP) bearing.

A slider on a spherical surface of radius R carrying the normal load N is pulled back toward
the centre by the horizontal component of N. In the small-rotation form (Zayas, Low & Mahin
1990; OpenSees `singleFPBearing`) the restoring force is linear,

    F_r = N u / R,                         period of a rigid mass 2 pi sqrt(R / g),

and in the large-displacement form, at the same vertical load N, it is the horizontal
component of the normal reaction on the sphere,

    F_r = N u / sqrt(R^2 - |u|^2).

A stiffening restrainer (the rim) beyond the displacement capacity d adds
k_r (|u| - d) along u for |u| > d. In two directions the force acts along the displacement
vector u. The liner's friction is a `SlidingBearing` (Eq. 1 of Constantinou, Mokha &
Reinhorn 1990 at the liner's contact pressure), composed beside this part, at the vertical
load N in both forms (the normal reaction N / cos(theta) exceeds it by about (u / R)^2 / 2).

References: Zayas, Low & Mahin (1990), "A simple pendulum technique for achieving seismic
isolation", Earthquake Spectra 6(2); Constantinou, Mokha & Reinhorn (1990), J. Struct. Eng.
116(2), Eq. 1.
"""

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from ..units import STANDARD_GRAVITY
from ..validation import concrete, require


class ConcaveSurface(eqx.Module):
    """A spherical sliding surface (single friction pendulum).

    **Fields:**

    - `radius` R [m] (> 0): radius of curvature of the surface (the effective radius of the
      pendulum, surface radius less the slider's height).
    - `displacement_capacity` d [m] (> 0) or `None`: where the restrainer engages (no
      restrainer when `None`).
    - `restrainer_stiffness` k_r [N/m] (>= 0): stiffness of the restrainer beyond d.
    - `large_displacement` (static): `N u / sqrt(R^2 - |u|^2)` instead of `N u / R`.
    """

    radius: jnp.ndarray
    displacement_capacity: jnp.ndarray | None = None
    restrainer_stiffness: jnp.ndarray = eqx.field(default_factory=lambda: jnp.zeros(()))
    large_displacement: bool = eqx.field(static=True, default=False)

    @property
    def is_linear(self) -> bool:
        """True when the force is N u / R alone (small rotation, no restrainer)."""
        return not self.large_displacement and self.displacement_capacity is None

    def stiffness(self, normal_load):
        """N / R [N/m]: the small-rotation restoring stiffness under the normal load N [N]."""
        return normal_load / self.radius

    def isolation_period(self):
        """2 pi sqrt(R / g) [s]: the period of a rigid mass on the surface (small rotation)."""
        return 2 * jnp.pi * jnp.sqrt(self.radius / STANDARD_GRAVITY)

    def restoring_force(self, displacement, normal_load):
        """Restoring force [N] of the surface (and restrainer) at the slider's displacement
        u [m] from the centre, (..., ) in one direction or (..., 2) in two, under normal
        load N [N]; in two directions along u. Opposes the motion when subtracted:
        the bearing applies -F_r to the structure."""
        u = jnp.asarray(displacement)
        return self._along(u, self._magnitude(_norm_of(u), normal_load))

    def extra_force(self, displacement, normal_load):
        """`restoring_force` less the linear part N u / R [N]: the large-displacement and
        restrainer terms (zero for a small-rotation surface without restrainer)."""
        u = jnp.asarray(displacement)
        r = _norm_of(u)
        return self._along(u, self._magnitude(r, normal_load) - normal_load * r / self.radius)

    def _magnitude(self, r, normal_load):
        """|F_r| [N] at distance r = |u| [m]: N r / R (or N r / sqrt(R^2 - r^2)) plus the
        restrainer k_r max(r - d, 0)."""
        if self.large_displacement:
            gap = jnp.maximum(self.radius**2 - r**2, (1e-6 * self.radius) ** 2)
            force = normal_load * r / jnp.sqrt(gap)
        else:
            force = normal_load * r / self.radius
        if self.displacement_capacity is not None:
            force = force + self.restrainer_stiffness * jnp.maximum(r - self.displacement_capacity, 0.0)
        return force

    def _along(self, u, magnitude):
        if u.ndim >= 1 and u.shape[-1] == 2:
            r = _norm_of(u)
            direction = u / jnp.where(r > 0, r, 1.0)[..., None]
            return direction * magnitude[..., None]
        return jnp.sign(u) * magnitude


def _norm_of(u):
    """|u| [m]: the absolute value in one direction, the length of the last axis in two
    (the gradient at u = 0 kept finite)."""
    if u.ndim >= 1 and u.shape[-1] == 2:
        square = jnp.sum(u**2, axis=-1)
        safe = jnp.where(square > 0, square, 1.0)
        return jnp.where(square > 0, jnp.sqrt(safe), 0.0)
    return jnp.abs(u)


def concave_surface(radius, *, displacement_capacity=None, restrainer_stiffness=0.0,
                    large_displacement: bool = False) -> ConcaveSurface:
    """A `ConcaveSurface` with its inputs checked (`ValueError` naming the parameter):
    `radius` [m] > 0, `displacement_capacity` [m] > 0 (or `None`, below R for the
    large-displacement form), `restrainer_stiffness` [N/m] >= 0."""
    require(radius, lambda x: np.isfinite(x) & (x > 0), "radius", "must be > 0 [m]")
    require(restrainer_stiffness, lambda x: np.isfinite(x) & (x >= 0), "restrainer_stiffness",
            "must be >= 0 [N/m]")
    if displacement_capacity is not None:
        require(displacement_capacity, lambda x: np.isfinite(x) & (x > 0), "displacement_capacity",
                "must be > 0 [m], or None for no restrainer")
        radius_value, capacity = concrete(radius), concrete(displacement_capacity)
        if large_displacement and radius_value is not None and capacity is not None:
            require(capacity, lambda x: x < radius_value, "displacement_capacity",
                    "must be below the radius for the large-displacement form")
    return ConcaveSurface(
        radius=jnp.asarray(radius, dtype=float),
        displacement_capacity=None if displacement_capacity is None else jnp.asarray(displacement_capacity, float),
        restrainer_stiffness=jnp.asarray(restrainer_stiffness, dtype=float),
        large_displacement=bool(large_displacement),
    )
