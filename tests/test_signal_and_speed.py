"""A record is zero past its end and simulations refuse to run past it; the sliding speed and
its derivative are finite at rest in float32 and float64."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import teflon_jax as tj
from teflon_jax.systems import peak_response, rigid_mass
from teflon_jax.units import INCH, PSI

FRICTION, _ = tj.interface_parameters("UF", 1000 * PSI, "P")


@pytest.mark.parametrize("uniform", [True, False])
def test_signal_is_zero_outside_its_record_and_exact_at_its_ends(uniform):
    values = jnp.asarray([1.0, 2.0, -3.0, 4.0, 5.0])
    signal = tj.Signal(0.02 * jnp.arange(5.0), values, uniform=uniform)
    end = float(signal.times[-1])
    assert float(signal(end)) == 5.0 and float(signal(0.0)) == 1.0
    assert float(signal(0.05)) == pytest.approx(0.5, abs=1e-12)
    for t in (end + 1e-4, end + 1.0, -1e-4):
        assert float(signal(t)) == 0.0  # no held last value: the ground is at rest after the record


def test_simulations_refuse_a_duration_longer_than_the_record():
    ground = tj.uniform_signal(np.sin(np.arange(501) * 0.01), 0.01)  # 5 s
    system = rigid_mass(weight=1e5, bearing=tj.paper_bearing(FRICTION), ground_acceleration=ground,
                        time_step=0.01)
    with pytest.raises(ValueError, match=r"duration: 6 s asked, but the record lasts only 5 s"):
        tj.simulate_history(system, 6.0)
    with pytest.raises(ValueError, match=r"duration: 6 s asked, but the record lasts only 5 s"):
        peak_response(system, 6.0)
    assert bool(tj.simulate_history(system, 5.0).succeeded)  # the whole record is fine
    load = tj.uniform_signal(np.full(11, 1e5), 0.1)  # 1 s of normal load
    with pytest.raises(ValueError, match=r"normal_load: 2 s asked, but the record lasts only 1 s"):
        tj.imposed_path_test(tj.paper_bearing(FRICTION), tj.SineMotion(INCH, 0.5, cycles=1), load)
    with pytest.raises(ValueError, match="duration"):
        tj.as_signal(1.0)


@pytest.mark.parametrize("dtype", [jnp.float32, jnp.float64])
def test_speed_and_friction_gradients_are_finite_at_rest(dtype):
    friction = tj.FrictionParameters(*(jnp.asarray(x, dtype) for x in (0.1193, 0.0927, 23.6)))
    for perpendicular in (None, friction):
        bearing = tj.paper_bearing(friction, friction_perpendicular=perpendicular,
                                   breakaway_ratio=jnp.asarray(2.0, dtype))
        zero = jnp.zeros((), dtype)
        for z_peak in (0.0, 1.0):
            gx, gy = jax.grad(bearing.coefficient, argnums=(0, 1))(zero, zero, z_peak)
            assert np.isfinite(float(gx)) and np.isfinite(float(gy))
        mu, slope = jax.jvp(lambda v, b=bearing: b.coefficient(v, 0.0, 1.0), (zero,), (jnp.ones((), dtype),))
        assert float(mu) == pytest.approx(0.1193 - 0.0927, rel=1e-6)  # Eq. 1 at rest
        assert np.isfinite(float(slope))
    speed_grad = jax.grad(lambda v: tj.bearing.sliding_speed(v[0], v[1]))(jnp.zeros(2, dtype))
    np.testing.assert_array_equal(np.asarray(speed_grad), 0.0)
    # Z at rest (Z = 0) in the biaxial vector field: finite Jacobian
    motion = tj.FigureEightMotion(jnp.asarray(INCH, dtype), jnp.asarray(1.0, dtype))
    system = tj.BearingTestSystem(bearing=tj.paper_bearing(friction, yield_disp=jnp.asarray(1e-4, dtype)),
                                  motion=motion)
    y = {"z": jnp.zeros(2, dtype), "z_peak": jnp.zeros((), dtype)}
    jac = jax.jacfwd(lambda y: system(jnp.asarray(0.5, dtype), y, None))(y)
    assert all(np.all(np.isfinite(np.asarray(x))) for x in jax.tree.leaves(jac))
    rev = jax.grad(lambda z: jnp.sum(system(jnp.asarray(0.5, dtype), {"z": z, "z_peak": y["z_peak"]}, None)["z_peak"]))(y["z"])
    assert np.all(np.isfinite(np.asarray(rev)))
