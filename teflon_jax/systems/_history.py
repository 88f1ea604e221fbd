"""The friction's memory in a structure: the surface temperature of a heating bearing and the
travel of a wearing one, carried as state from step to step (one and two directions alike).

The heat flux into the steel is q = mu p |v| / n (p the contact pressure of the bearing, n the
interfaces in series); the surface temperature rise is the 1/sqrt(t) kernel of a
semi-infinite body written as a sum of exponential states (`heat_kernel_exponentials`), so a
step costs the same whatever the length of the record. Their factor on mu
(`SlidingBearing.effect_factor`) is taken at the start of each step and held over it.
References: Kumar, Whittaker & Constantinou (2015); Carslaw & Jaeger (1959).
"""

import jax.numpy as jnp

from ..bearing import SlidingBearing


def has_history(bearing: SlidingBearing) -> bool:
    """True when the bearing's friction depends on its history (heating, wear)."""
    return bearing.heating is not None or bearing.wear is not None


def history_factor(bearing: SlidingBearing, heat, travel, weights):
    """Factor on mu [-] at heat states `heat` (..., K) [W/m^2 s] and travel [m]; `weights`
    (K,) of the kernel (`heat_kernel_exponentials`)."""
    heating = bearing.heating
    rise = 0.0 if heating is None else heating.rise(heat, weights)
    return bearing.effect_factor(temperature_rise=rise, travel=travel)


def heat_flux(bearing: SlidingBearing, coefficient, contact_pressure, speed):
    """q = mu p |v| / n [W/m^2] into the steel of each of the n interfaces of a stack, at
    sliding speed |v| [m/s] of the bearing and contact pressure p [Pa]."""
    heating = bearing.heating
    return heating.flux(coefficient, contact_pressure * heating.contact_area,
                        speed / bearing.n_interfaces)


def next_history(bearing: SlidingBearing, heat, travel, slide, coefficient, contact_pressure,
                 time_step, rates):
    """Heat states and travel after a step in which the bearing slid `slide` [m] (the length of
    its increment), with the friction coefficient `coefficient` [-] of the step's start held
    over it (flux q = mu p slide / (dt n)), `rates` (K,) [1/s] of the kernel."""
    heating = bearing.heating
    if heating is not None:
        flux = heat_flux(bearing, coefficient, contact_pressure, slide / time_step)
        heat = heating.advance(heat, jnp.expand_dims(flux, -1), time_step, rates)
    return heat, travel + slide


def history_rates(bearing: SlidingBearing, heat, coefficient, contact_pressure, speed, rates):
    """(d heat / dt, d travel / dt) = (q - lambda heat, |v|) for an ODE solver."""
    if bearing.heating is None:
        return jnp.zeros_like(heat), speed
    flux = heat_flux(bearing, coefficient, contact_pressure, speed)
    return jnp.expand_dims(flux, -1) - rates * heat, speed
