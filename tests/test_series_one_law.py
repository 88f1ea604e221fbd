"""A friction pendulum of sliders in series runs one law in its bearing test and in a structure.

The structure's isolator path (a rigid mass on a double or triple pendulum with Eq. 1 friction
that depends on velocity, under a ground motion; one and two components) is imposed on the
bearing test (`imposed_path_test`, which `fit`, Bayes and `diagnose` run): the test's
force must be the structure's bearing force at every step. Velocity-dependent friction is
where the law's reversal rule (f_min while Z still points back) acts; a test that took
W (u / R + mu(|v|) Z) instead misses the structure's force by 6e-4 to 3.4e-3 of the weight
(up to 5 % of the friction force) right after reversals; the two runs here agree to 1e-9 of
the weight (the structure's balance tolerance) and their sliders to 1e-9 m. A double pendulum fitted from its own test then gives the
structure's peaks of the bearing it was fitted from.
"""

import jax
import numpy as np
import pytest
from histories import planar_histories

from identification.bearing_fit import fit_series_pendulum_test
from teflon_jax.bearing import BoucWen, DoublePendulum, FrictionParameters, TriplePendulum
from teflon_jax.excitation import StochasticGroundMotion, sample, uniform_signal
from teflon_jax.formats import test_record_from_arrays
from teflon_jax.systems import (
    imposed_path_test,
    sampled_path,
    simulate_history,
    triple_structure,
)
from teflon_jax.units import STANDARD_GRAVITY

DT = 0.005
DURATION = 8.0

DOUBLE = DoublePendulum(bottom_radius=1.5, top_radius=2.0, bottom_capacity=0.3, top_capacity=0.3,
                        bottom_friction=FrictionParameters(0.06, 0.03, 25.0),
                        top_friction=FrictionParameters(0.09, 0.04, 15.0), hysteresis=BoucWen(2e-4))
TRIPLE = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                        bottom_capacity=0.4, top_capacity=0.4,
                        inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                        bottom_friction=FrictionParameters(0.07, 0.03, 20.0),
                        top_friction=FrictionParameters(0.11, 0.05, 20.0), hysteresis=BoucWen(1e-4))
PENDULUMS = {"double": DOUBLE, "triple": TRIPLE}


def _ground(seed, scale=1.0):
    motion = StochasticGroundMotion(peak_ground_acceleration=0.5 * STANDARD_GRAVITY, duration=DURATION,
                                    time_step=0.01, rise_time=1.0, strong_motion_duration=5.0)
    return scale * np.asarray(sample(motion, jax.random.PRNGKey(seed), 1))[0]


def _structure(pendulum, ground):
    return triple_structure("rigid", pendulum, uniform_signal(ground, 0.01), time_step=DT)


@pytest.mark.parametrize("name", PENDULUMS)
def test_the_test_force_along_the_structures_path_is_the_structures_force(name):
    pendulum = PENDULUMS[name]
    system = _structure(pendulum, _ground(3))
    response = jax.jit(simulate_history, static_argnums=1)(system, DURATION)
    weight = float(system.bearing_load)
    path = np.asarray(response.displacement[:, 0])
    assert np.ptp(path) > 0.05 and bool(np.all(response.converged))  # the outer surfaces slide
    test = jax.jit(imposed_path_test)(pendulum, sampled_path(np.asarray(response.time), path, weight))
    assert bool(np.all(test.converged))
    np.testing.assert_allclose(np.asarray(test.force) / weight, np.asarray(response.bearing_force) / weight,
                               rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.asarray(test.slider), np.asarray(response.slider), rtol=0, atol=1e-9)


def test_the_planar_test_force_along_the_structures_orbit_is_the_structures_force():
    one = _structure(TRIPLE, _ground(5))
    system = one.with_y_component(uniform_signal(_ground(6, 0.8), 0.01))
    time, x, force, sliders, _, converged = jax.jit(planar_histories, static_argnums=1)(system, DURATION)
    weight = float(one.bearing_load)
    orbit = np.asarray(x[:, :, 0])
    assert bool(np.all(converged)) and np.min(np.ptp(orbit, axis=0)) > 0.03
    test = jax.jit(imposed_path_test)(TRIPLE, sampled_path(np.asarray(time), orbit, weight))
    assert bool(np.all(test.converged))
    np.testing.assert_allclose(np.asarray(test.force) / weight, np.asarray(force) / weight, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.asarray(test.slider), np.asarray(sliders), rtol=0, atol=1e-9)


def _peak(pendulum, ground):
    response = jax.jit(simulate_history, static_argnums=1)(_structure(pendulum, ground), DURATION)
    return np.max(np.abs(np.asarray(response.displacement[:, 0]))), np.max(np.abs(np.asarray(response.bearing_force)))


@pytest.mark.slow
def test_a_double_pendulum_fitted_from_its_test_gives_the_structures_peaks():
    weight = 1e6
    t = np.arange(0, 3 * 4.0 + 1e-9, 0.01)
    u = 0.2 * np.sin(2 * np.pi * t / 4.0) * np.minimum(t / 4.0, 1.0)
    force = np.asarray(jax.jit(imposed_path_test)(DOUBLE, sampled_path(t, u, weight)).force)
    record = test_record_from_arrays(u, force, time=t, normal_load=weight)
    start = DoublePendulum(bottom_radius=1.2, top_radius=2.4, bottom_capacity=0.3, top_capacity=0.3,
                           bottom_friction=FrictionParameters(0.05, 0.02, 10.0),
                           top_friction=FrictionParameters(0.1, 0.05, 10.0), hysteresis=BoucWen(2e-4))
    fit = fit_series_pendulum_test(record, start)
    ground = _ground(11)
    truth, fitted = _peak(DOUBLE, ground), _peak(fit.bearing, ground)
    np.testing.assert_allclose(fitted, truth, rtol=1e-4)
