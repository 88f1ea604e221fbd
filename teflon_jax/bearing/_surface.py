"""The interface law of one sliding surface of a friction pendulum, beyond Eq. 1 and heating.

Each surface of a double or triple pendulum is a PTFE-type liner on polished steel, so it takes
every part of the flat bearing's law (`SlidingBearing`): breakaway (Eq. 17), anisotropy across
the lay of the steel, wear, direction asymmetry and pressure dependence, each optional and
each the flat bearing's own formula. `SurfaceParts` holds the parts one surface has;
`surface_coefficients` evaluates the law of every slider of the series model at once.

Reference: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 17 and the section on anisotropy;
MODEL.md Sections 1-5.
"""

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from ..validation import require, require_positive
from ._bearing import BREAKAWAY_THRESHOLD, SlidingBearing, check_eq1
from ._effects import DirectionAsymmetry, PressureDependence, Wear
from ._friction import FrictionParameters, sliding_friction

SURFACE_PARTS = ("breakaway_ratio", "friction_perpendicular", "lay_angle", "pressure_dependence", "wear",
                 "asymmetry")
"""Fields of `SurfaceParts`, in order."""


class SurfaceParts(eqx.Module):
    """Parts of one sliding surface's law beyond Eq. 1 and heating, each `None` (absent) by
    default; each acts as on a flat `SlidingBearing`:

    - `breakaway_ratio` b [-]: mu = b f_min (Eq. 17) until the slider's |Z| first reaches
      `BREAKAWAY_THRESHOLD`;
    - `friction_perpendicular` (`FrictionParameters`): Eq. 1 across the lay of the steel, the
      surface's own constants along it; in two components mixed linearly in the angle of the
      slider's increment to the lay (`sliding_angle_weight`), along the lay in one;
      `lay_angle` [rad]: the lay's angle from x towards y (x when `None`);
    - `pressure_dependence` (`PressureDependence`): mu (p A / N_ref)^-exponent at the surface's
      contact pressure p (the pendulum's `<slider>_pressure` under the static load, times the
      load factor N / W), which it needs, with the tested bearing's contact area A;
    - `wear` (`Wear`): mu (1 + change s / s_ref) after the surface has slid s;
    - `asymmetry` (`DirectionAsymmetry`): mu (1 + a Z_x) with the slider's Z along x.
    """

    breakaway_ratio: object = None
    friction_perpendicular: FrictionParameters | None = None
    lay_angle: object = None
    pressure_dependence: PressureDependence | None = None
    wear: Wear | None = None
    asymmetry: DirectionAsymmetry | None = None

    @property
    def remembers(self) -> bool:
        """Whether the part needs the slider's history (largest |Z|, travel) (static)."""
        return self.breakaway_ratio is not None or self.wear is not None

    def bearing(self, friction: FrictionParameters, hysteresis, heating=None) -> SlidingBearing:
        """The surface's whole interface law as a flat `SlidingBearing`: Eq. 1 `friction`,
        Bouc-Wen `hysteresis`, `heating` and these parts."""
        return SlidingBearing(friction=friction, hysteresis=hysteresis, breakaway_ratio=self.breakaway_ratio,
                              friction_perpendicular=self.friction_perpendicular, lay_angle=self.lay_angle,
                              pressure_dependence=self.pressure_dependence, heating=heating, wear=self.wear,
                              asymmetry=self.asymmetry)


def surface_coefficients(frictions, parts, speed, direction, z, history=None, pressures=None, load_factor=1.0):
    """Coefficients (at rest r (S,), sliding mu (S,)) [-] of the S sliders' surfaces at the
    surface speeds `speed` (S,) [m/s]: Eq. 1 (`sliding_friction`) of the stacked `frictions`,
    r = f_min, each surface with its `parts` (a tuple of `SurfaceParts` or `None`, one per
    slider) applied:

    - anisotropy: the constants for the direction `direction` (S,) (one component: the sign,
      along x) or (S, 2) of each slider's increment;
    - breakaway: r = mu = b f_min while `history["z_peak"]` (S,) < `BREAKAWAY_THRESHOLD`;
    - wear at `history["travel"]` (S,) [m], asymmetry at Z_x of `z` (S,) or (S, 2), pressure
      dependence at `pressures` (S,) [Pa] times `load_factor` N / W: factors on r and mu.
    """
    rest, sliding = [], []
    for e, part in enumerate(parts):
        friction = FrictionParameters(*(getattr(frictions, name)[e] for name in ("f_max", "delta_f", "rate_a")))
        bearing = (SurfaceParts() if part is None else part).bearing(friction, None)
        heading = (direction[e], 0.0) if direction.ndim == 1 else (direction[e, 0], direction[e, 1])
        constants = bearing.constants_for(*heading)
        r, mu = constants.f_min, sliding_friction(constants, speed[e])
        if part is not None and part.breakaway_ratio is not None:
            static = history["z_peak"][e] < BREAKAWAY_THRESHOLD
            r = jnp.where(static, part.breakaway_ratio * r, r)
            mu = jnp.where(static, r, mu)
        factor = _part_factor(part, e, z, history, pressures, load_factor)
        rest.append(factor * r)
        sliding.append(factor * mu)
    return jnp.stack(rest), jnp.stack(sliding)


def _part_factor(part, e, z, history, pressures, load_factor):
    """Product of slider e's wear, asymmetry and pressure-dependence factors [-] (1 without)."""
    factor = 1.0
    if part is None:
        return factor
    if part.wear is not None:
        factor = factor * part.wear.factor(history["travel"][e])
    if part.asymmetry is not None:
        factor = factor * part.asymmetry.factor(z[e] if z.ndim == 1 else z[e, 0])
    if part.pressure_dependence is not None:
        factor = factor * part.pressure_dependence.factor_at_pressure(load_factor * pressures[e])
    return factor


def check_friction(friction: FrictionParameters, name: str) -> None:
    """`ValueError` naming `name`.f_max, .delta_f or .rate_a where Eq. 1 cannot take them:
    f_max >= 0, 0 <= delta_f < f_max (a positive friction at rest) or f_max = delta_f = 0 (a
    frictionless surface), rate_a >= 0 [s/m] (`check_eq1`)."""
    check_eq1(friction, f"{name}.", frictionless=True)


def check_surface_parts(part: SurfaceParts, name: str, pressure=None) -> None:
    """`ValueError` naming `name`.<part> where a surface's part is out of range (the flat
    bearing's rules), or where pressure dependence lacks the surface's contact `pressure` [Pa]
    or the tested bearing's contact area."""
    if part.breakaway_ratio is not None:
        require(part.breakaway_ratio, lambda x: np.isfinite(x) & (x >= 1), f"{name}.breakaway_ratio",
                "must be >= 1 (Table 1: 1.3-4.4)")
    if part.friction_perpendicular is not None:
        check_friction(part.friction_perpendicular, f"{name}.friction_perpendicular")
    if part.lay_angle is not None:
        if part.friction_perpendicular is None:
            raise ValueError(f"{name}.lay_angle: the lay of the steel matters only for an anisotropic surface; "
                             f"give {name}.friction_perpendicular too (or leave lay_angle out).")
        require(part.lay_angle, np.isfinite, f"{name}.lay_angle", "must be finite [rad]")
    if part.wear is not None:
        require(part.wear.change, lambda x: np.isfinite(x) & (x > -1), f"{name}.wear.change",
                "must be > -1 (friction stays positive)")
        require_positive(part.wear.reference_travel, f"{name}.wear.reference_travel", " [m]")
    if part.asymmetry is not None:
        require(part.asymmetry.asymmetry, lambda x: np.isfinite(x) & (np.abs(x) < 1), f"{name}.asymmetry.asymmetry",
                "must be between -1 and 1 (friction stays positive)")
    if part.pressure_dependence is not None:
        p = part.pressure_dependence
        require(p.exponent, np.isfinite, f"{name}.pressure_dependence.exponent", "must be finite")
        require_positive(p.reference_load, f"{name}.pressure_dependence.reference_load", " [N]")
        if p.contact_area is None or pressure is None:
            raise ValueError(f"{name}.pressure_dependence: a surface's friction follows its contact pressure; "
                             "give the tested bearing's contact_area and the surface's contact pressure under "
                             "the static load.")
        require_positive(p.contact_area, f"{name}.pressure_dependence.contact_area", " [m^2]")
