"""Optional parts of a sliding bearing beyond the 1990 model: factors on the friction
coefficient (pressure dependence, frictional heating, wear, direction asymmetry) and a gap in
series with the interface (backlash).

Each part is a final `equinox.Module` whose fields are physical constants (SI); a bearing
composes the parts it has (`SlidingBearing`). Each factor is exactly 1 at its neutral constants
(exponent 0, heat scale 0, wear change 0, asymmetry 0), and a gap of 0 is the plain Bouc-Wen
update, so a model with a part at its neutral value gives the numbers of the model without it.

References: Mokha, Constantinou & Reinhorn (1990), "Teflon bearings in base isolation I:
Testing", J. Struct. Eng. 116(2) (friction falls with contact pressure, changes with travel);
Kumar, Whittaker & Constantinou (2015), "Characterizing friction in sliding isolation
bearings", Earthquake Eng. Struct. Dyn. 44(9) (the factor k_T of temperature); Carslaw &
Jaeger (1959), "Conduction of Heat in Solids", Sec. 2.9 (surface temperature of a
semi-infinite body under a surface heat flux); Krasnosel'skii & Pokrovskii (1989), "Systems
with Hysteresis" (the play operator).
"""

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import ArrayLike

from ._hysteresis import BoucWen, bouc_wen_exact_update, bouc_wen_reversal_length

STEEL_CONDUCTIVITY = 16.2
"""Thermal conductivity of stainless steel (AISI 304/316) near room temperature k [W/(m K)]."""

STEEL_DIFFUSIVITY = 4.4e-6
"""Thermal diffusivity of stainless steel kappa [m^2/s]."""

AMBIENT_TEMPERATURE = 20.0
"""Temperature at which the k_T factor of Kumar et al. (2015) equals 1 [degC]."""


def kumar_temperature_factor(temperature):
    """k_T = 0.79 (0.70^(T/50) + 0.40) of Kumar, Whittaker & Constantinou (2015).

    **Arguments:** `temperature` T of the sliding surface [degC].

    **Returns:** the factor on the friction coefficient [-]; 1.00 at 20 degC.
    """
    return 0.79 * (jnp.power(0.70, temperature / 50.0) + 0.40)


def surface_temperature_coefficient(conductivity=STEEL_CONDUCTIVITY, diffusivity=STEEL_DIFFUSIVITY):
    """C in dT(t) = C int q(s) (t - s)^(-1/2) ds, C = sqrt(kappa / pi) / k [K m^2 / (W s^1/2)].

    Surface temperature rise of a semi-infinite solid heated by a surface flux q(t) [W/m^2]
    (Carslaw & Jaeger 1959, Sec. 2.9). A constant flux q0 gives dT = 2 q0 sqrt(kappa t / pi) / k.
    """
    return jnp.sqrt(diffusivity / jnp.pi) / conductivity


HEAT_HORIZON = 3600.0
"""Longest time [s] the heat kernel of a structure represents (the 1/sqrt(t) kernel is
accurate from one time step to this; an earthquake record is far shorter)."""


def heat_kernel_exponentials(t_min: float, t_max: float, *, per_decade: float = 3.0):
    """Rates and weights of a sum of exponentials approximating 1/sqrt(t) on [t_min, t_max].

    1/sqrt(t) = pi^(-1/2) int_R exp(x/2) exp(-exp(x) t) dx (the Laplace representation with
    s = e^x); the trapezoidal rule on a uniform grid in x converges geometrically, so
        1/sqrt(t) ~ sum_j w_j exp(-lambda_j t),  lambda_j = e^(x_j),  w_j = h e^(x_j/2) / sqrt(pi).
    The grid spans lambda from 1e-6 / t_max (the neglected slow tail adds about
    2 sqrt(lambda_min t / pi) < 1.2e-3 relative error at t_max) to 1e4 / t_min (the fastest
    term resolves the integrable singularity within a step to about 1 %); with 3 nodes per
    decade the quadrature error is of order exp(-pi^2 / h) ~ 1e-5. The convolution with the
    1/sqrt(t) kernel then becomes a set of first-order states: O(n) in the number of steps.

    **Arguments:** `t_min`, `t_max` [s]: shortest (a time step) and longest (the record) time.

    **Returns:** numpy arrays `(rates [1/s], weights [s^-1/2])` with
    `sum(weights * exp(-rates * t))` ~ `t**-0.5` [s^-1/2].
    """
    if not 0 < t_min < t_max:
        raise ValueError(f"heat kernel: need 0 < t_min < t_max, got {t_min}, {t_max}.")
    h = np.log(10.0) / per_decade
    x = np.arange(np.log(1e-6 / t_max), np.log(1e4 / t_min) + h, h)
    return np.exp(x), h * np.exp(x / 2) / np.sqrt(np.pi)


class PressureDependence(eqx.Module):
    """Friction that falls with the normal load (contact pressure):

        mu *= (N / N_ref)^(-exponent)

    **Fields:** `exponent` [-] (0: no dependence), `reference_load` N_ref [N] (the load at
    which the friction constants hold), `contact_area` A [m^2] of the tested bearing, or `None`
    when unknown: with it the factor at a contact pressure p is that at N = p A
    (`factor_at_pressure`), which is how a structure given its bearings' pressure uses it.
    """

    exponent: ArrayLike
    reference_load: ArrayLike
    contact_area: ArrayLike | None = None

    def factor(self, normal_load):
        """The factor [-] at normal load N [N]."""
        return jnp.exp(-self.exponent * jnp.log(normal_load / self.reference_load))

    def factor_at_pressure(self, pressure):
        """The factor [-] at contact pressure p [Pa]: `factor(p A)`; `ValueError` without A."""
        if self.contact_area is None:
            raise ValueError(
                "pressure_dependence: a structure gives its bearings' contact pressure, and the "
                "factor (N / N_ref)^-exponent needs the tested bearing's contact_area to turn it "
                "into a load; add parts.pressure_dependence.contact_area to the bearing file.")
        return self.factor(pressure * self.contact_area)


class Wear(eqx.Module):
    """Friction that changes with accumulated travel (no recovery):

        mu *= 1 + change * travel / reference_travel

    **Fields:** `change` [-] (relative change of mu over `reference_travel`; 0: none),
    `reference_travel` [m].
    """

    change: ArrayLike
    reference_travel: ArrayLike

    def factor(self, travel):
        """The factor [-] after `travel` [m] of sliding."""
        return 1.0 + self.change * (travel / self.reference_travel)


class DirectionAsymmetry(eqx.Module):
    """Friction that differs between the two senses of sliding along x:

        mu *= 1 + asymmetry Z_x

    +asymmetry while sliding in +x (Z_x = 1), -asymmetry in -x; through 1 with Z at a
    reversal, so the force F = mu N Z has no step. Causes: a tilted or misaligned specimen, a
    self-energising band brake.

    **Fields:** `asymmetry` [-] (0: symmetric).
    """

    asymmetry: ArrayLike

    def factor(self, z_x):
        """The factor [-] at the hysteretic variable's x component Z_x [-]."""
        return 1.0 + self.asymmetry * z_x


def advance_heat_states(heat_states, flux, dt, rates):
    """The exponential states s_j [W s/m^2] of the heat kernel (`heat_kernel_exponentials`)
    after `dt` [s] of a constant heat `flux` q [W/m^2]:

        s_j <- e^(-lambda_j dt) s_j + q (1 - e^(-lambda_j dt)) / lambda_j,

    exact for a flux held over the step (rates lambda_j [1/s] along the last axis)."""
    decay = jnp.exp(-rates * dt)
    return decay * heat_states + flux * (1.0 - decay) / rates


class FrictionalHeating(eqx.Module):
    """Friction that falls as the sliding surface heats up (Kumar et al. 2015):

        mu *= k_T(T0 + heat_scale dT) / k_T(T0),   k_T(T) = 0.79 (0.70^(T/50) + 0.40)

    with dT the surface temperature rise of the stainless steel under the heat flux
    q = mu p |v| / n into each of n sliding surfaces of a stack, p = N / contact_area
    (Carslaw & Jaeger: dT = C int q(s) (t - s)^(-1/2) ds, `surface_temperature_coefficient`),
    or the measured rise where a test recorded the temperature.

    **Fields:** `contact_area` [m^2] (of the PTFE on the steel), `heat_scale` [-] (1: the
    semi-infinite-body rise; 0: no heating), `conductivity` [W/(m K)], `diffusivity` [m^2/s]
    of the steel, `initial_temperature` T0 [degC].
    """

    contact_area: ArrayLike
    heat_scale: ArrayLike = 1.0
    conductivity: ArrayLike = STEEL_CONDUCTIVITY
    diffusivity: ArrayLike = STEEL_DIFFUSIVITY
    initial_temperature: ArrayLike = AMBIENT_TEMPERATURE

    def factor(self, temperature_rise):
        """The factor [-] for an unscaled surface temperature rise dT [K]."""
        t0 = self.initial_temperature
        rise = self.heat_scale * temperature_rise
        return kumar_temperature_factor(t0 + rise) / kumar_temperature_factor(t0)

    def flux(self, coefficient, normal_load, speed):
        """Heat flux q = mu p |v| [W/m^2] into the steel at sliding speed |v| [m/s] of one
        surface, p = N / contact_area."""
        return coefficient * (normal_load / self.contact_area) * speed

    def advance(self, heat_states, flux, dt, rates):
        """The exponential states of the heat kernel after `dt` [s] of constant `flux`:
        s_j <- e^(-lambda_j dt) s_j + q (1 - e^(-lambda_j dt)) / lambda_j (exact for a flux
        held over the step)."""
        return advance_heat_states(heat_states, flux, dt, rates)

    def rise(self, heat_states, weights):
        """Unscaled surface temperature rise dT = C sum_j w_j s_j [K] (states along the last
        axis)."""
        coefficient = surface_temperature_coefficient(self.conductivity, self.diffusivity)
        return coefficient * jnp.sum(weights * heat_states, axis=-1)


class Backlash(eqx.Module):
    """A gap in series with the sliding interface (play), as in bolted friction dampers with
    oversized holes: after a reversal Z unloads to 0 along Bouc-Wen, stays 0 (no force) while
    the drive crosses the gap, then loads again (`backlash_update`).

    **Fields:** `gap` g [m] (0: no play).
    """

    gap: ArrayLike


def backlash_update(h: BoucWen, z0, gap_position, displacement_increment, gap):
    """Z and the gap position after a monotone increment of a gap in series with Bouc-Wen.

    The drive moves by du = sigma |du|. After a reversal Z first unloads to 0 along Eq. 3
    (travel Y x0, x0 = `bouc_wen_reversal_length`), then the drive crosses the gap with Z = 0
    (the gap position s [m] moves from -sigma g/2 towards sigma g/2), then Z loads again from
    0 with the travel left. Invariant: s = sign(Z) g/2 whenever Z != 0; a record starts with
    Z = 0 and s = 0 (centred). With g = 0 this is `bouc_wen_exact_update` split at Z = 0. Z
    is continuous in the displacement and in g, so a fit can differentiate in g.

    **Arguments:** `h` Bouc-Wen constants, `z0` [-], `gap_position` s [m],
    `displacement_increment` du [m], `gap` g [m] (>= 0).

    **Returns:** `(z1, s1)`.
    """
    du = displacement_increment
    sigma = jnp.where(du >= 0, 1.0, -1.0)
    travel = jnp.abs(du)
    unloading = sigma * z0 < 0
    to_zero = jnp.where(unloading, bouc_wen_reversal_length(h, z0) * h.yield_disp, 0.0)
    reached = travel >= to_zero
    z_part = bouc_wen_exact_update(h, z0, sigma * jnp.minimum(travel, to_zero))
    left = jnp.maximum(travel - to_zero, 0.0)
    available = jnp.maximum(0.5 * gap - sigma * gap_position, 0.0)
    in_gap = jnp.minimum(left, available)
    s1 = jnp.where(reached, gap_position + sigma * in_gap, gap_position)
    z_start = jnp.where(reached & unloading, 0.0, z_part)
    z1 = jnp.where(reached, bouc_wen_exact_update(h, z_start, sigma * (left - in_gap)), z_part)
    return z1, s1
