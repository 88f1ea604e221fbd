"""One imposed-path test driver for any isolator (`imposed_path_test`): a flat bearing's test
is solved by diffrax along the motion, a series pendulum's balances its sliders at each sample
with the structures' solve; the solve's options are refused there by name."""

import dataclasses

import jax
import numpy as np
import pytest

from teflon_jax.bearing import BoucWen, DoublePendulum, FrictionParameters, SlidingBearing
from teflon_jax.excitation import SineMotion, uniform_signal
from teflon_jax.systems import imposed_path_test

jax.config.update("jax_enable_x64", True)

W = 1.0e6  # [N]
R_BOTTOM, R_TOP, MU_BOTTOM, MU_TOP = 1.5, 2.5, 0.05, 0.08
DOUBLE = DoublePendulum(bottom_radius=R_BOTTOM, top_radius=R_TOP, bottom_capacity=0.5, top_capacity=0.5,
                        bottom_friction=FrictionParameters(MU_BOTTOM, 0.0, 20.0),  # Coulomb: f_max = f_min
                        top_friction=FrictionParameters(MU_TOP, 0.0, 20.0), hysteresis=BoucWen(1e-4))
MOTION = SineMotion(amplitude=0.3, frequency=0.2, cycles=2)


def test_a_double_pendulums_test_is_the_closed_form_while_both_surfaces_slide():
    """With both surfaces sliding (Coulomb friction, Z = +-1), the force of sliders in series is
    F = W u / (R1 + R2) + W (mu1 R1 + mu2 R2) / (R1 + R2) sgn(v) (Fenz & Constantinou 2006).
    Both slide once the bottom surface (lower friction) has travelled (mu2 - mu1) R1 = 45 mm
    from rest, or 90 mm back after a reversal: kept are |u| < 0.15 m after the first peak."""
    result = imposed_path_test(DOUBLE, MOTION, W, samples_per_cycle=2000)
    assert bool(np.all(result.converged)) and result.slider.shape == (result.time.size, 2)
    t, u, force = (np.asarray(a) for a in (result.time, result.ux, result.fx))
    velocity = np.cos(2 * np.pi * MOTION.frequency * t)
    both = (t > 1.25) & (np.abs(u) < 0.15)
    total = R_BOTTOM + R_TOP
    expected = W * u / total + W * (MU_BOTTOM * R_BOTTOM + MU_TOP * R_TOP) / total * np.sign(velocity)
    assert both.sum() > 1000
    np.testing.assert_allclose(force[both], expected[both], rtol=0, atol=1e-9 * W)


def test_the_flat_bearings_solve_options_are_refused_on_a_series_pendulum_by_name():
    for options, named in (({"solver": object()}, "solver"), ({"steps_per_sample": 2, "rtol": 1e-6},
                                                               "steps_per_sample, rtol")):
        with pytest.raises(ValueError, match=f"^{named}: the double friction pendulums balance their sliders"):
            imposed_path_test(DOUBLE, MOTION, W, **options)
    with pytest.raises(ValueError, match="normal_load: 10 s asked, but the record lasts only 9.9 s"):
        imposed_path_test(DOUBLE, MOTION, uniform_signal(np.full(100, W), 0.1))  # a record, too short
    with pytest.raises(ValueError, match="bottom_radius"):  # checked like a flat bearing's constants
        imposed_path_test(dataclasses.replace(DOUBLE, bottom_radius=-1.5), MOTION, W)


def test_a_flat_bearing_and_a_series_pendulum_give_one_result_type():
    flat = imposed_path_test(SlidingBearing(friction=FrictionParameters(0.1, 0.05, 30.0),
                                                hysteresis=BoucWen(2.5e-4)), MOTION, W, samples_per_cycle=200)
    series = imposed_path_test(DOUBLE, MOTION, W, samples_per_cycle=200)
    assert type(flat) is type(series)
    np.testing.assert_array_equal(np.asarray(flat.time), np.asarray(series.time))
    np.testing.assert_array_equal(np.asarray(flat.ux), np.asarray(series.ux))
