"""Frictional heating of each sliding surface of a friction pendulum modelled as sliders in
series (`SeriesPendulum`): surface e takes the heat flux q_e = mu_e p_e v_e of its own
friction, contact pressure and sliding speed, its temperature rises as that of a
semi-infinite steel body (Carslaw & Jaeger 1959, Sec. 2.9; the 1/sqrt(t) kernel as a sum of
exponential states, `heat_kernel_exponentials`), and its friction is scaled by k_T of Kumar,
Whittaker & Constantinou (2015) (`FrictionalHeating`), each surface with its own temperature
as in Kim & Constantinou's TripleFrictionPendulumX element of OpenSees. Within a step the
factor is the one at the step's start and the flux is held, as the flat sliders take them.
"""

import jax.numpy as jnp

from ..bearing import (
    SeriesPendulum,
    advance_heat_states,
    heat_kernel_exponentials,
    sliding_friction,
)
from ._structure_build import HEAT_HORIZON


def series_heat_kernel(pendulum: SeriesPendulum, time_step: float):
    """(rates [1/s], weights [s^-1/2]) of the heat kernel from one `time_step` [s] to
    `HEAT_HORIZON` for a pendulum with a heated surface, else (None, None)."""
    if not pendulum.heated:
        return None, None
    return tuple(jnp.asarray(a) for a in heat_kernel_exponentials(float(time_step), HEAT_HORIZON))


def heated_step(pendulum: SeriesPendulum, heat, factors, slide, time_step, rates, load=1.0):
    """Heat states (S, K) [W s/m^2] after a step in which the sliders slid `slide` (S,) [m]
    (the lengths of their increments): each surface's flux q_e = mu_e p_e v_e
    (`SeriesPendulum.heat_fluxes`) at its speed v_e = slide c_e / dt (`velocity_factors`),
    with mu_e Eq. 1 at that speed times the factor `factors` (S,) held over the step; the flux
    is held over the step (`advance_heat_states`, exact for a constant flux) and the
    load factor N / W `load` scales the pressure."""
    speed = slide * pendulum.velocity_factors() / time_step
    mu = sliding_friction(pendulum.frictions().scaled(factors), speed)
    flux = pendulum.heat_fluxes(mu, speed, load)
    return advance_heat_states(heat, flux[:, None], time_step, rates)



def surface_temperature_rises(pendulum: SeriesPendulum, heat, weights):
    """Surface temperature rises s dT_e [K] (S,) at the heat states `heat` (S, K) of the kernel
    of `weights` (K,): the rise that enters k_T (`FrictionalHeating.rise` times its
    `heat_scale` s), 0 where a surface has no heating."""
    return jnp.stack([jnp.zeros((), heat.dtype) if h is None else h.heat_scale * h.rise(heat[e], weights)
                      for e, h in enumerate(pendulum.surface_heatings())])
