"""The isolator solve's ingredients: the friction coefficient's written-out slope and the
first guess of the Newton iteration (`predicted_root`)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import teflon_jax as tj
from teflon_jax.elements import isolator_residual, predicted_root
from teflon_jax.units import PSI

PARALLEL, _ = tj.interface_parameters("UF", 1000 * PSI, "P")
ACROSS, _ = tj.interface_parameters("UF", 1000 * PSI, "T")


@pytest.mark.parametrize("bearing", [
    tj.paper_bearing(PARALLEL),
    tj.paper_bearing(PARALLEL, breakaway_ratio=1.6),
    tj.paper_bearing(PARALLEL, n_interfaces=3),
    tj.paper_bearing(PARALLEL, friction_perpendicular=ACROSS, lay_angle=0.4),
], ids=["plain", "breakaway", "stack", "anisotropic"])
def test_uniaxial_coefficient_is_the_coefficient_and_its_derivative(bearing):
    velocity = jnp.array([-0.4, -0.02, -1e-6, 0.0, 1e-6, 0.02, 0.4])
    for z_peak in (0.5, 1.0):
        mu, slope = bearing.uniaxial_coefficient(velocity, z_peak)
        expected, expected_slope = jax.vmap(
            lambda v, z_peak=z_peak: jax.jvp(lambda u: bearing.coefficient(u, 0.0, z_peak), (v,), (1.0,)))(velocity)
        np.testing.assert_array_equal(mu, expected)  # the same arithmetic, bit for bit
        np.testing.assert_allclose(slope, expected_slope, rtol=1e-12, atol=1e-15)
    assert float(bearing.uniaxial_coefficient(0.0, 1.0)[1]) == 0.0  # no slope at rest


def _step_state(dt):
    """A step of `dt` [s] of a bearing sliding at 0.05 m/s in its transition (Z = 0.4, so dZ/du
    is large), accelerating at 2 m/s^2 (no turn): the guess with the force held lands on that
    path, which the isolator's force then changes."""
    bearing = tj.paper_bearing(PARALLEL)
    weight, vb0, z0, acceleration = 1.0e6, 0.05, 0.4, 2.0
    g0 = 6.0e-10 * (dt / 0.005) ** 2  # the isolator's compliance, about dt^2 / (4 m) for a rigid mass
    held_force = float(bearing.coefficient(vb0, 0.0, 1.0)) * weight * z0
    increment, velocity = vb0 * dt + 0.5 * acceleration * dt**2, vb0 + acceleration * dt
    gain = 3.0 / dt  # the exact rule's end-velocity gain for a rigid mass, about 3 / dt
    return {"bearing": bearing, "W": weight, "z0": z0, "z_peak": 1.0, "ub0": 0.0, "vb0": vb0, "g0": g0,
            "ub_linear": increment + g0 * held_force, "vb_linear": velocity + gain * g0 * held_force,
            "velocity_gain": gain, "reversal_length": tj.bouc_wen_reversal_length(bearing.hysteresis, z0)}, bearing, weight


def test_first_guess_is_off_by_second_order_only():
    """Halving the step takes the residual of the guess that holds the force at its start value
    down as the force's first-order change, and that of `predicted_root` (a Newton step on the force linearised about
    the start state: dZ/du of Eq. 3 and dmu/dv of Eq. 1)."""
    held, predicted = [], []
    for dt in (1e-3, 5e-4, 2.5e-4, 1.25e-4):  # du / Y from 0.4 down
        rule = (dt, True)
        p, bearing, weight = _step_state(dt)
        mu, slope = bearing.uniaxial_coefficient(p["vb0"], p["z_peak"])
        factors = (mu * weight, slope * weight)
        wide = 1.0
        guess = predicted_root(p, factors, p["ub_linear"] - wide, p["ub_linear"] + wide)
        held.append(abs(float(isolator_residual(p["ub_linear"] - p["g0"] * factors[0] * p["z0"], p, rule))))
        predicted.append(abs(float(isolator_residual(guess, p, rule))))
    held, predicted = np.array(held), np.array(predicted)
    assert np.all(predicted < 0.25 * held)
    # g0 ~ dt^2: the held force is off by its first-order change (residual ~ dt^3), the
    # linearised one by its second-order change (~ dt^4)
    np.testing.assert_allclose(held[:-1] / held[1:], 8.0, rtol=0.1)
    np.testing.assert_allclose(predicted[:-1] / predicted[1:], 16.0, rtol=0.1)
