"""A bearing whose friction differs between the two senses of sliding (`DirectionAsymmetry`,
mu (1 + a Z_x)) in the structures, one and two directions.

Peers: the closed form of a rigid mass sliding under a constant ground acceleration (relative
acceleration a_g - mu (1 +/- a) g, by the sense of sliding); the plain bearing at a = 0; the
one-direction structure for two directions under a record along x; the full simulation for the
peak loop.
"""

import dataclasses

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest

import teflon_jax as tj
from teflon_jax.bearing import DirectionAsymmetry
from teflon_jax.units import PSI, STANDARD_GRAVITY

MU = 0.08
UF, UF_B = tj.interface_parameters("UF", 1000 * PSI, "P")


def _asymmetric(bearing, a):
    return eqx.tree_at(lambda b: b.asymmetry, bearing, DirectionAsymmetry(a),
                       is_leaf=lambda x: x is None)


@pytest.mark.parametrize("sense", [1.0, -1.0])
def test_sliding_under_a_constant_ground_acceleration_is_the_closed_form(sense):
    """Ground acceleration -0.3 g sense: the mass slides in the +sense direction with relative
    acceleration sense (0.3 - mu (1 + sense a)) g."""
    a = 0.2
    t = np.array([0.0, 10.0])
    ground = tj.Signal(jnp.asarray(t), jnp.asarray([-sense * 0.3 * STANDARD_GRAVITY] * 2))
    bearing = _asymmetric(tj.paper_bearing(tj.coulomb_friction(MU)), a)
    system = tj.rigid_mass(weight=1e5, bearing=bearing, ground_acceleration=ground, time_step=0.005)
    r = tj.simulate_history(system, 2.0)
    t1, t2 = float(r.time[100]), float(r.time[-1])
    u1, v1, u2 = float(r.displacement[100, 0]), float(r.velocity[100, 0]), float(r.displacement[-1, 0])
    rate = sense * (0.3 - MU * (1 + sense * a)) * STANDARD_GRAVITY
    assert u2 == pytest.approx(u1 + v1 * (t2 - t1) + rate * (t2 - t1) ** 2 / 2, rel=1e-6)


def _signal(duration=8.0, peak=3.0):
    t = np.arange(0, duration, 0.01)
    return tj.uniform_signal(jnp.asarray(peak * np.sin(2 * np.pi * 0.5 * t) * np.exp(-0.2 * t)), 0.01)


def test_no_asymmetry_is_the_plain_bearing_and_the_peak_loop_is_the_simulation():
    from teflon_jax.systems import isolated_structure, peak_response, simulate_history

    plain = tj.paper_bearing(UF, breakaway_ratio=UF_B)
    signal = _signal()
    a = peak_response(isolated_structure("building", bearing=plain)(signal), 7.5)
    neutral = isolated_structure("building", bearing=_asymmetric(plain, 0.0))(signal)
    b = peak_response(neutral, 7.5)
    assert float(b.base_disp) == pytest.approx(float(a.base_disp), rel=1e-12)
    assert float(b.base_shear_ratio) == pytest.approx(float(a.base_shear_ratio), rel=1e-12)
    skewed = isolated_structure("rigid", bearing=_asymmetric(plain, 0.3), isolation_period=2.5)(signal)
    peaks = peak_response(skewed, 7.5)
    full = simulate_history(skewed, 7.5)
    assert float(jnp.max(jnp.abs(full.displacement[:, 0]))) == pytest.approx(float(peaks.base_disp),
                                                                            rel=1e-9)
    # the mass drifts towards the weaker sense (-x for a > 0)
    u = np.asarray(full.displacement[:, 0])
    assert -u.min() > 1.1 * u.max()


@pytest.mark.slow
def test_two_directions_along_x_are_the_one_direction_structure():
    from teflon_jax.systems import (
        rigid_mass,
        simulate_history,
    )

    bearing = _asymmetric(tj.paper_bearing(UF, breakaway_ratio=UF_B), 0.25)
    signal = _signal(6.0)
    one = rigid_mass(weight=1e5, bearing=bearing, ground_acceleration=signal, time_step=0.005,
                     isolation_period=2.5)
    two = rigid_mass(components=2, weight=1e5, bearing=bearing, ground_acceleration=signal, time_step=0.005,
                                   isolation_period=2.5)
    a = simulate_history(dataclasses.replace(one, newton_tolerance=0.0), 5.5)
    b = simulate_history(dataclasses.replace(two, newton_tolerance=0.0), 5.5)
    np.testing.assert_allclose(b.displacement[:, 0], a.displacement[:, 0], rtol=0, atol=1e-10)
    np.testing.assert_allclose(b.friction_force[:, 0, 0], a.friction_force, rtol=1e-7, atol=1e-6)


def test_the_coulomb_model_refuses_parts_it_does_not_run():
    bearing = _asymmetric(tj.paper_bearing(tj.coulomb_friction(MU)), 0.2)
    with pytest.raises(ValueError, match="Coulomb model runs Eq. 1 alone, not its asymmetry"):
        tj.rigid_mass(weight=1e5, bearing=bearing, ground_acceleration=_signal(), time_step=0.005,
                      friction_model="coulomb")
