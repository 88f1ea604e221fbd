"""A PTFE sliding bearing: friction law + hysteretic variable + breakaway + anisotropy + stacks.

Reference: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 3, 8-9, 17; MODEL.md Sections 1-5.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..units import INCH
from ..validation import concrete, require, require_positive
from ._effects import (
    Backlash,
    DirectionAsymmetry,
    FrictionalHeating,
    PressureDependence,
    Wear,
)
from ._friction import (
    FrictionParameters,
    anisotropic_friction,
    sliding_angle_weight,
    sliding_friction,
)
from ._hysteresis import BoucWen

EFFECT_FIELDS = ("pressure_dependence", "heating", "wear", "asymmetry", "backlash")
"""Fields of `SlidingBearing` that hold the optional parts beyond the 1990 model."""

BREAKAWAY_THRESHOLD = 0.999
"""|Z| at which the breakaway (static) friction of Eq. 17 gives way to Eq. 1 for good."""

DEFAULT_YIELD_DISP = 0.005 * INCH
"""Y of the paper's simulations [m]."""


class SlidingBearing(eqx.Module):
    """Model of one PTFE bearing (or stack of interfaces) carrying a normal load.

    Friction coefficient (Eq. 1, with Eq. 17 before the first full mobilisation):
        mu = b (f_max - delta_f)                       while max|Z| so far < 0.999
        mu = f_max - delta_f exp(-rate_a |v| / n)       afterwards
    Force: F = mu N Z, with Z from Bouc-Wen (uniaxial) or Park et al. (biaxial).

    **Fields:**

    - `friction`: Eq. 1 constants along x (for anisotropic bearings: parallel to lay).
    - `hysteresis`: `BoucWen` constants (Y, A, beta, gamma, eta).
    - `breakaway_ratio` b [-] of Eq. 17, or `None` for no breakaway.
    - `friction_perpendicular`: Eq. 1 constants for sliding across the lay (along y unless
      `lay_angle` is given), or `None` for an isotropic bearing. Biaxial motion interpolates
      linearly in the angle of the velocity to the lay (`sliding_angle_weight`).
    - `n_interfaces` (static int): number of interfaces in series sharing the motion.
    - `lay_angle` phi [rad]: angle of the lay of the steel from x towards y, for an
      anisotropic bearing; `None` (the default) puts the lay along x. Z (Park's, isotropic)
      does not depend on it.
    - Optional parts beyond the 1990 model, each `None` (absent) by default:
      `pressure_dependence` (`PressureDependence`), `heating` (`FrictionalHeating`), `wear`
      (`Wear`), `asymmetry` (`DirectionAsymmetry`): factors on mu (`effect_factor`);
      `backlash` (`Backlash`): a gap in series with the interface, acting on Z.
    """

    friction: FrictionParameters
    hysteresis: BoucWen
    breakaway_ratio: object = None
    friction_perpendicular: FrictionParameters | None = None
    n_interfaces: int = eqx.field(static=True, default=1)
    lay_angle: object = None
    pressure_dependence: PressureDependence | None = None
    heating: FrictionalHeating | None = None
    wear: Wear | None = None
    asymmetry: DirectionAsymmetry | None = None
    backlash: Backlash | None = None

    @property
    def effects(self) -> tuple[str, ...]:
        """Names of the optional parts this bearing has, in the order of the fields."""
        return tuple(name for name in EFFECT_FIELDS if getattr(self, name) is not None)

    def scaled(self, factor):
        """This bearing with its friction coefficient multiplied by `factor` [-] (f_max and
        delta_f of both directions; breakaway follows, as b (f_max - delta_f)): how a factor
        that does not depend on Z, held over a step, enters a structure's step."""
        perpendicular = self.friction_perpendicular
        return eqx.tree_at(
            lambda b: (b.friction, b.friction_perpendicular), self,
            (self.friction.scaled(factor),
             None if perpendicular is None else perpendicular.scaled(factor)),
            is_leaf=lambda x: x is None)

    def at_contact_pressure(self, pressure):
        """This bearing in a structure whose bearings carry contact pressure p [Pa]: its
        pressure dependence, a constant factor at a constant load, folded into the friction
        (`PressureDependence.factor_at_pressure`) and the part removed; itself without one."""
        if self.pressure_dependence is None:
            return self
        factor = self.pressure_dependence.factor_at_pressure(pressure)
        return eqx.tree_at(lambda b: b.pressure_dependence, self.scaled(factor), None)

    def effect_factor(self, *, normal_load=None, temperature_rise=0.0, travel=0.0, z_x=0.0):
        """Product of the optional factors on mu [-] (1 for a bearing without them).

        **Arguments:** `normal_load` N [N] (pressure dependence), `temperature_rise` the
        unscaled surface temperature rise dT [K] (heating), `travel` accumulated sliding [m]
        (wear), `z_x` [-] the hysteretic variable along x (asymmetry).
        """
        factor = 1.0
        if self.pressure_dependence is not None:
            factor = factor * self.pressure_dependence.factor(normal_load)
        if self.wear is not None:
            factor = factor * self.wear.factor(travel)
        if self.asymmetry is not None:
            factor = factor * self.asymmetry.factor(z_x)
        if self.heating is not None:
            factor = factor * self.heating.factor(temperature_rise)
        return factor

    @property
    def has_history(self) -> bool:
        """True when the friction depends on the bearing's history (heating, wear): a structure
        then carries its surface temperature (heat states) and travel from step to step."""
        return self.heating is not None or self.wear is not None

    def history_factor(self, heat, travel, weights):
        """Factor on mu [-] at heat states `heat` (..., K) [W/m^2 s] and travel [m]; `weights`
        (K,) of the kernel (`heat_kernel_exponentials`)."""
        rise = 0.0 if self.heating is None else self.heating.rise(heat, weights)
        return self.effect_factor(temperature_rise=rise, travel=travel)

    def surface_temperature_rise(self, heat, weights):
        """The surface temperature rise s dT [K] (...) that enters k_T (`FrictionalHeating`,
        heat_scale s) at heat states `heat` (..., K) of the kernel of `weights` (K,)."""
        return self.heating.heat_scale * self.heating.rise(heat, weights)

    def heat_flux(self, coefficient, contact_pressure, speed):
        """q = mu p |v| / n [W/m^2] into the steel of each of the n interfaces of a stack, at
        sliding speed |v| [m/s] of the bearing and contact pressure p [Pa]."""
        return self.heating.flux(coefficient, contact_pressure * self.heating.contact_area,
                                 speed / self.n_interfaces)

    def next_history(self, heat, travel, slide, coefficient, contact_pressure, time_step, rates):
        """Heat states and travel after a step of `time_step` [s] in which the bearing slid
        `slide` [m] (the length of its increment), with the friction coefficient `coefficient`
        [-] of the step's start held over it (flux q = mu p slide / (dt n)); `rates` (K,) [1/s]
        of the kernel (`FrictionalHeating.advance`)."""
        if self.heating is not None:
            flux = self.heat_flux(coefficient, contact_pressure, slide / time_step)
            heat = self.heating.advance(heat, jnp.expand_dims(flux, -1), time_step, rates)
        return heat, travel + slide

    def history_rates(self, heat, coefficient, contact_pressure, speed, rates):
        """(d heat / dt, d travel / dt) = (q - lambda heat, |v|) for an ODE solver."""
        if self.heating is None:
            return jnp.zeros_like(heat), speed
        flux = self.heat_flux(coefficient, contact_pressure, speed)
        return jnp.expand_dims(flux, -1) - rates * heat, speed

    def coefficient(self, velocity_x, velocity_y=0.0, z_peak=1.0):
        """Friction coefficient mu [-] for a sliding velocity [m/s] and the largest |Z| so far."""
        params = self.constants_for(velocity_x, velocity_y)
        mu = sliding_friction(params, sliding_speed(velocity_x, velocity_y), self.n_interfaces)
        if self.breakaway_ratio is None:
            return mu
        return jnp.where(z_peak < BREAKAWAY_THRESHOLD, self.breakaway_ratio * params.f_min, mu)

    def constants_for(self, velocity_x, velocity_y=0.0):
        """Eq. 1 constants for the direction of the velocity: `friction`, or for an anisotropic
        bearing those mixed across the lay (`sliding_angle_weight`)."""
        if self.friction_perpendicular is None:
            return self.friction
        weight = sliding_angle_weight(velocity_x, velocity_y, self.lay_angle)
        return anisotropic_friction(self.friction, self.friction_perpendicular, weight)

    def uniaxial_coefficient(self, velocity, z_peak=1.0):
        """mu [-] and dmu/dv [s/m] for sliding along x at `velocity` [m/s] (the
        `coefficient` with velocity_y = 0): Eq. 1 (`sliding_friction`) and its forward-mode
        derivative in v,

            dmu/dv = (a / n) delta_f exp(-a |v| / n) sgn(v),

        with the constants mixed for the direction as in `coefficient`, held fixed in the
        derivative; during breakaway (Eq. 17) mu = b f_min and dmu/dv = 0. At v = 0 the slope
        is 0, as the derivative of `coefficient` there."""
        params = self.constants_for(velocity, 0.0)
        velocity = jnp.asarray(velocity, dtype=float)
        mu, slope = jax.jvp(lambda v: sliding_friction(params, v, self.n_interfaces), (velocity,),
                            (jnp.ones_like(velocity),))
        slope = jnp.where(velocity == 0, 0.0, slope)  # d|v|/dv taken as 0 at rest
        if self.breakaway_ratio is None:
            return mu, slope
        static = z_peak < BREAKAWAY_THRESHOLD
        return jnp.where(static, self.breakaway_ratio * params.f_min, mu), jnp.where(static, 0.0, slope)


def sliding_speed(velocity_x, velocity_y=0.0):
    """|v| = sqrt(vx^2 + vy^2) [m/s], with a finite derivative (zero) at rest in float32 and
    float64 alike: the square root is taken only of a positive argument (double-where)."""
    square = jnp.asarray(velocity_x) ** 2 + jnp.asarray(velocity_y) ** 2
    moving = square > 0
    return jnp.where(moving, jnp.sqrt(jnp.where(moving, square, 1.0)), 0.0)


def paper_bearing(
    friction: FrictionParameters,
    *,
    yield_disp=DEFAULT_YIELD_DISP,
    breakaway_ratio=None,
    friction_perpendicular: FrictionParameters | None = None,
    n_interfaces: int = 1,
    lay_angle=None,
) -> SlidingBearing:
    """A `SlidingBearing` with the paper's Bouc-Wen constants A = 1, beta = 0.1, gamma = 0.9, eta = 2
    (`lay_angle` [rad]: see `SlidingBearing`; only with `friction_perpendicular`)."""
    if lay_angle is not None and friction_perpendicular is None:
        raise ValueError("lay_angle: the lay of the steel matters only for an anisotropic bearing; "
                         "give friction_perpendicular too (or leave lay_angle out).")
    return SlidingBearing(
        friction=friction,
        hysteresis=BoucWen(yield_disp=jnp.asarray(yield_disp, dtype=float)),
        breakaway_ratio=None if breakaway_ratio is None else jnp.asarray(breakaway_ratio, dtype=float),
        friction_perpendicular=friction_perpendicular,
        n_interfaces=n_interfaces,
        lay_angle=None if lay_angle is None else jnp.asarray(lay_angle, dtype=float),
    )


def check_hysteresis(h: BoucWen) -> None:
    """Raise `ValueError` naming the constant when concrete Bouc-Wen constants are invalid.

    Rules: Y > 0; A > 0; gamma > 0 and -gamma <= beta <= gamma; eta >= 1 -- the range in
    which Eq. 3 is bounded, dissipative and consistent with a hysteretic force (Ikhouane,
    Manosa & Rodellar 2007, with their beta, gamma named gamma, beta here). The paper uses
    A = 1, beta = 0.1, gamma = 0.9, eta = 2. Traced values are not checked here.
    """
    require_positive(h.yield_disp, "yield_disp", " [m] (paper: 0.005 in)")
    require_positive(h.A, "A", " (Bouc-Wen amplitude; paper: 1)")
    require_positive(h.gamma, "gamma", " (Bouc-Wen shape constant; paper: 0.9)")
    require(h.beta, np.isfinite, "beta", "must be finite (Bouc-Wen shape constant; paper: 0.1)")
    beta, gamma = concrete(h.beta), concrete(h.gamma)
    if beta is not None and gamma is not None and not np.all(np.abs(beta) <= gamma):
        raise ValueError(
            "beta: must satisfy -gamma <= beta <= gamma (paper: beta = 0.1, gamma = 0.9); got "
            f"beta = {np.asarray(beta).tolist()}, gamma = {np.asarray(gamma).tolist()}."
        )
    require(h.eta, lambda x: np.isfinite(x) & (x >= 1), "eta", "must be >= 1 (paper: 2)")


def check_bearing(bearing: SlidingBearing) -> None:
    """Raise `ValueError` naming the parameter when a concrete bearing has invalid values.

    Traced values (inside jit/vmap/grad) are not checked here.
    """
    check_eq1(bearing.friction)
    check_hysteresis(bearing.hysteresis)
    if bearing.breakaway_ratio is not None:
        require(
            bearing.breakaway_ratio,
            lambda x: np.isfinite(x) & (x >= 1),
            "breakaway_ratio",
            "must be >= 1 (Table 1: 1.3-4.4), or None for no breakaway",
        )
    if bearing.friction_perpendicular is not None:
        check_eq1(bearing.friction_perpendicular, "friction_perpendicular.")
    if bearing.lay_angle is not None:
        if bearing.friction_perpendicular is None:
            raise ValueError("lay_angle: the lay of the steel matters only for an anisotropic bearing; "
                             "give friction_perpendicular too (or leave lay_angle out).")
        require(bearing.lay_angle, np.isfinite, "lay_angle", "must be finite [rad]")
    _check_parts(bearing)
    if int(bearing.n_interfaces) != bearing.n_interfaces or bearing.n_interfaces < 1:
        raise ValueError(f"n_interfaces: must be an integer >= 1, got {bearing.n_interfaces}.")


def check_eq1(f: FrictionParameters, prefix: str = "", frictionless: bool = False) -> None:
    """`ValueError` naming `prefix` and the constant of Eq. 1 out of range: f_max > 0 (or, with
    `frictionless`, f_max >= 0: a surface without friction has f_max = delta_f = 0),
    0 <= delta_f < f_max (a positive friction at rest), rate_a >= 0 [s/m]."""
    if frictionless:
        require(f.f_max, lambda x: np.isfinite(x) & (x >= 0), f"{prefix}f_max",
                "must be a finite number >= 0 (a friction coefficient; 0 for a frictionless surface)")
    else:
        require_positive(f.f_max, f"{prefix}f_max", " (a friction coefficient, e.g. 0.1193)")
    require(f.delta_f, lambda x: np.isfinite(x) & (x >= 0), f"{prefix}delta_f", "must be >= 0")
    f_max, delta_f = concrete(f.f_max), concrete(f.delta_f)
    if f_max is not None and delta_f is not None and not np.all((delta_f < f_max) | ((delta_f == 0) & (f_max == 0))):
        raise ValueError(f"{prefix}delta_f: must be smaller than f_max ({np.asarray(f_max).tolist()}: Eq. 1 at "
                         f"rest, f_max - delta_f, is positive); got {np.asarray(delta_f).tolist()}.")
    require(f.rate_a, lambda x: np.isfinite(x) & (x >= 0), f"{prefix}rate_a", "must be >= 0 [s/m]")


def check_heating(q: FrictionalHeating, name: str) -> None:
    """`ValueError` naming `name`.<constant> where a `FrictionalHeating`'s constants are out of range."""
    require_positive(q.contact_area, f"{name}.contact_area", " [m^2] (PTFE on the steel)")
    require(q.heat_scale, lambda x: np.isfinite(x) & (x >= 0), f"{name}.heat_scale",
            "must be >= 0 (1: the semi-infinite-body rise)")
    require_positive(q.conductivity, f"{name}.conductivity", " [W/(m K)]")
    require_positive(q.diffusivity, f"{name}.diffusivity", " [m^2/s]")
    require(q.initial_temperature, lambda x: np.isfinite(x) & (x > -273.15),
            f"{name}.initial_temperature", "must be above absolute zero [degC]")


def _check_parts(bearing: SlidingBearing) -> None:
    """The optional parts' constants (concrete values only)."""
    if bearing.pressure_dependence is not None:
        p = bearing.pressure_dependence
        require(p.exponent, np.isfinite, "pressure_dependence.exponent", "must be finite")
        require_positive(p.reference_load, "pressure_dependence.reference_load", " [N]")
        if p.contact_area is not None:
            require_positive(p.contact_area, "pressure_dependence.contact_area",
                             " [m^2] (of the tested bearing)")
    if bearing.heating is not None:
        check_heating(bearing.heating, "heating")
    if bearing.wear is not None:
        require(bearing.wear.change, lambda x: np.isfinite(x) & (x > -1), "wear.change",
                "must be > -1 (friction stays positive)")
        require_positive(bearing.wear.reference_travel, "wear.reference_travel", " [m]")
    if bearing.asymmetry is not None:
        require(bearing.asymmetry.asymmetry, lambda x: np.isfinite(x) & (np.abs(x) < 1),
                "asymmetry.asymmetry", "must be between -1 and 1 (friction stays positive)")
    if bearing.backlash is not None:
        require(bearing.backlash.gap, lambda x: np.isfinite(x) & (x >= 0), "backlash.gap",
                "must be >= 0 [m]")
