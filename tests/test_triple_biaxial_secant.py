"""The secant balance of the triple pendulum under two ground components
(`StructureOnSliders.with_y_component(ground_y, balance="secant")`): Broyden's update of the sliders' 2 x 2
blocks, exact identities of the update, the same histories as Newton's iteration to the
balance's tolerance, and the same implicit derivative.

Peers: `balance="newton"` (tests/test_triple_biaxial.py), Broyden (1965)'s secant condition."""

import functools

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from histories import planar_histories

from teflon_jax.bearing import BoucWen, FrictionParameters, TriplePendulum
from teflon_jax.elements import secant_floors
from teflon_jax.excitation import StochasticGroundMotion, sample, uniform_signal
from teflon_jax.solver import broyden_blocks
from teflon_jax.systems import (
    triple_structure,
)
from teflon_jax.units import STANDARD_GRAVITY

TRIPLE = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                        bottom_capacity=0.3, top_capacity=0.3,
                        inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                        bottom_friction=FrictionParameters(0.08, 0.03, 20.0),
                        top_friction=FrictionParameters(0.12, 0.05, 20.0), hysteresis=BoucWen(1.27e-4))
MOTION = StochasticGroundMotion(peak_ground_acceleration=0.4 * STANDARD_GRAVITY, duration=8.0, time_step=0.01,
                                rise_time=1.0, strong_motion_duration=4.0)


@functools.cache
def _records():
    return np.asarray(sample(MOTION, jax.random.key(5), 2))


def _pair(pendulum, balance):
    acc = _records()
    one = triple_structure("rigid", pendulum, uniform_signal(acc[0], 0.01), time_step=0.005)
    return one.with_y_component(uniform_signal(0.8 * acc[1], 0.01), balance=balance)


def test_broyden_update_meets_the_secant_condition_and_keeps_other_directions():
    """K' s = y, and K' v = K v for v orthogonal to s (the update is rank one along s); a step
    within its floor (`secant_floors`) keeps the block."""
    key = jax.random.key(0)
    blocks = jax.random.normal(key, (3, 2, 2)) * 1e6
    step = jax.random.normal(jax.random.fold_in(key, 1), (3, 2)) * 1e-4
    change = jax.random.normal(jax.random.fold_in(key, 2), (3, 2)) * 1e2
    p = {"pendulum": TRIPLE}
    new = broyden_blocks(blocks, step, change, secant_floors(jnp.zeros((3, 2)), p))
    np.testing.assert_allclose(jnp.einsum("eij,ej->ei", new, step), change, rtol=1e-12, atol=1e-12)
    normal = jnp.stack([-step[:, 1], step[:, 0]], -1)
    np.testing.assert_allclose(jnp.einsum("eij,ej->ei", new, normal), jnp.einsum("eij,ej->ei", blocks, normal),
                               rtol=1e-12, atol=1e-6)
    tiny = broyden_blocks(blocks, step * 1e-12, change, secant_floors(jnp.zeros((3, 2)), p))
    np.testing.assert_array_equal(tiny, blocks)


def test_secant_balance_follows_newton_to_the_tolerance():
    """Both balances to the default tolerance (1e-9 W): the histories agree to a displacement
    error far below it would allow at the pendulum's stiffness, every step balanced, and the
    two iterations are different (the secant one ends elsewhere within the tolerance)."""
    histories = jax.jit(planar_histories, static_argnums=1)
    newton = histories(_pair(TRIPLE, "newton"), 8.0)
    secant = histories(_pair(TRIPLE, "secant"), 8.0)
    assert bool(np.all(secant[-1])) and bool(np.all(newton[-1]))
    x_newton, x_secant = np.asarray(newton[1][:, :, 0]), np.asarray(secant[1][:, :, 0])
    assert np.max(np.abs(x_newton)) > 0.02  # the outer surfaces slide
    difference = np.max(np.abs(x_secant - x_newton))
    assert 0 < difference < 1e-8
    np.testing.assert_allclose(np.asarray(secant[3]).sum(axis=1), x_secant, atol=1e-12)


@pytest.mark.slow
def test_secant_balance_has_newtons_implicit_derivative():
    """d(peak |x|)/d(inner f_max) by forward mode: the same under both balances (the root is
    differentiated with exact blocks whichever way it was iterated)."""
    def peak(f_max, balance):
        friction = FrictionParameters(f_max, 0.015, 20.0)
        pendulum = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                                  bottom_capacity=0.3, top_capacity=0.3, inner_friction=friction,
                                  bottom_friction=TRIPLE.bottom_friction, top_friction=TRIPLE.top_friction,
                                  hysteresis=TRIPLE.hysteresis)
        x = planar_histories(_pair(pendulum, balance), 3.0)[1][:, :, 0]
        return jnp.max(jnp.sum(x**2, axis=-1))

    _records()
    derivatives = [jax.jit(lambda f, b=b: jax.jvp(lambda g: peak(g, b), (f,), (1.0,)))(0.03) for b in ("newton", "secant")]
    assert abs(float(derivatives[0][1])) > 0
    np.testing.assert_allclose(float(derivatives[1][1]), float(derivatives[0][1]), rtol=1e-6)


def test_an_unknown_balance_is_refused_by_name():
    with pytest.raises(ValueError, match="balance"):
        _pair(TRIPLE, "broyden")


@pytest.mark.parametrize("secant", [False, True])
def test_the_planar_balance_returns_the_forces_of_its_root_with_their_derivative(secant):
    """The planar balance hands back the sliders' forces and Z of its last evaluation (no
    evaluation after the loop): they are the force law's at the root it returns, and their
    tangent in the linear step's increment D and compliance G is the implicit one (central
    differences of the whole balance)."""
    from teflon_jax.elements import balance, balance_forces

    rng = np.random.default_rng(3)
    weight = 1e6
    start = {"pendulum": TRIPLE, "W": weight, "N": weight, "s0": jnp.asarray(rng.normal(0, 0.02, (3, 2))),
             "z0": jnp.asarray(rng.uniform(-0.6, 0.6, (3, 2)))}
    increment = jnp.array([4e-3, -2.5e-3])

    def solved(theta):
        p = {**start, "D": theta[0] * increment, "G": theta[1] * 2.5e-10}
        return balance(0.005, 60, p, jnp.zeros((3, 2)), 1e-8, secant), p

    theta = jnp.array([1.0, 1.0])
    (d, converged, (force, z)), p = solved(theta)
    assert bool(converged)
    law_force, law_z = balance_forces(p, d, 0.005)
    np.testing.assert_allclose(force, law_force, rtol=1e-13, atol=1e-9 * weight)
    np.testing.assert_allclose(z, law_z, rtol=1e-13, atol=1e-13)
    for axis in range(2):
        tangent = jnp.zeros(2).at[axis].set(1.0)
        _, (d_force, d_z) = jax.jvp(lambda t: solved(t)[0][2], (theta,), (tangent,))
        h = 1e-4
        plus, minus = solved(theta + h * tangent)[0][2], solved(theta - h * tangent)[0][2]
        assert float(jnp.max(jnp.abs(d_force))) > 1.0  # the sliding forces move with D and G
        np.testing.assert_allclose(d_force, (plus[0] - minus[0]) / (2 * h), rtol=1e-4, atol=1e-2)
        np.testing.assert_allclose(d_z, (plus[1] - minus[1]) / (2 * h), rtol=1e-4, atol=1e-7)
