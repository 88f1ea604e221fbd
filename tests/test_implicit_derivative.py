"""The one implicit derivative of a step's balance (`solver.implicit_root`): on a cubic with a
closed-form root derivative, then on each engine that uses it (the flat engine's bracketed
scalar Newton, the series pendulum's Sherman-Morrison in one component, its Woodbury blocks in
two, the slab's group forces, and the imposed path's share of dD), against central
differences of short runs iterated to rounding.

Peers: the implicit function theorem's dx/dp = -r_p / r_x of x^3 + a x - b = 0; central
differences (h and 2 h: their difference bounds the differences' own error)."""

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from histories import planar_histories

from teflon_jax.bearing import (
    BoucWen,
    FrictionParameters,
    TriplePendulum,
    concave_surface,
    single_pendulum,
)
from teflon_jax.excitation import uniform_signal
from teflon_jax.solver import implicit_root
from teflon_jax.studies import bidirectional_isolated_structure
from teflon_jax.systems import (
    imposed_path_test,
    isolated_structure,
    peak_response,
    sampled_path,
    simulate_history,
    slab_on_bearings,
    structure_on_isolator,
)
from teflon_jax.units import STANDARD_GRAVITY

TRIPLE = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                        bottom_capacity=0.3, top_capacity=0.3,
                        inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                        bottom_friction=FrictionParameters(0.08, 0.03, 20.0),
                        top_friction=FrictionParameters(0.12, 0.05, 20.0), hysteresis=BoucWen(1.27e-4))
DT = 0.01
TIME = np.arange(0.0, 1.5 + DT / 2, DT)
PULSE = 0.5 * STANDARD_GRAVITY * np.sin(2 * np.pi * TIME / 0.8) * np.sin(np.pi * TIME / 1.5) ** 2
GX, GY = uniform_signal(PULSE, DT), uniform_signal(0.7 * PULSE[::-1], DT)
PATH = 0.15 * np.sin(2 * np.pi * TIME / 1.0) * np.sin(np.pi * TIME / 1.5)
ORBIT = np.stack([PATH, 0.6 * np.roll(PATH, 20)], -1)
TIGHT = 1e-13
"""The sliders' force imbalance over W at which the series engines stop: the iterates are then
the root to rounding, whose derivative the implicit one is."""


def _cubic_newton(p, guess, steps):
    def body(_, x):
        return x - (x**3 + p["a"] * x - p["b"]) / (3 * x**2 + p["a"])

    x = jax.lax.fori_loop(0, steps, body, guess)
    return x, (p["a"] * x**2, jnp.abs(x**3 + p["a"] * x - p["b"]) < 1e-12)


def _cubic_root(a, b):
    """x^3 + a x - b = 0, with y = a x^2 as a further output and a flag that carries no tangent."""
    x, (y, ok) = implicit_root(lambda p, guess, steps: _cubic_newton(p, guess, 40),
                               lambda x, p: x**3 + p["a"] * x - p["b"],
                               lambda x, p, r, dp: r / (3 * x**2 + p["a"]), {"a": a, "b": b}, jnp.ones(()), 40,
                               outputs=lambda x, p: (p["a"] * x**2, jnp.array(True)))
    return x, y, ok


def test_the_root_and_its_outputs_take_the_implicit_function_theorems_derivative():
    a, b = 2.0, 3.0
    x, y, ok = _cubic_root(a, b)
    assert float(x) == float(_cubic_newton({"a": a, "b": b}, jnp.ones(()), 40)[0])  # the solve's iterate itself
    assert bool(ok)
    slope = 3 * float(x) ** 2 + a  # r_x; r_a = x, r_b = -1
    dx = np.array([-float(x) / slope, 1 / slope])
    dy = np.array([float(x) ** 2, 0.0]) + 2 * a * float(x) * dx
    assert np.allclose(jax.grad(lambda a, b: _cubic_root(a, b)[0], argnums=(0, 1))(a, b), dx, rtol=1e-14)
    assert np.allclose(jax.jacfwd(lambda ab: _cubic_root(*ab)[1])(jnp.array([a, b])), dy, rtol=1e-14)


def _check_derivatives(f, theta, rel=1e-6, forward=True):
    """Reverse (and where `forward`, forward) derivatives of the scalar f at theta against
    central differences (step 1e-5 theta), each entry within `rel` of itself and within 10
    times the differences' own error (their change from the step 2e-5 theta). One compiled
    program for the gradient and the differences (and one for forward mode)."""
    theta = jnp.asarray(theta, float)
    steps = np.diag(1e-5 * np.asarray(theta))
    shifts = np.concatenate([steps, -steps, 2 * steps, -2 * steps])
    reverse, values = jax.jit(lambda t: (jax.grad(f)(t), jax.vmap(f)(t + shifts)))(theta)
    reverse, values = np.asarray(reverse), np.asarray(values).reshape(4, len(theta))
    central = (values[0] - values[1]) / (2 * np.diag(steps))
    wider = (values[2] - values[3]) / (4 * np.diag(steps))
    scale = np.max(np.abs(central))
    assert np.all(np.abs(reverse) > 1e-6 * scale), reverse  # each parameter moves the response
    error = np.abs(reverse - central)
    assert np.all(error <= rel * np.abs(central)), (reverse, central)
    assert np.all(error <= 10 * np.abs(central - wider) + 1e-9 * np.abs(central)), (reverse, central, wider)
    if forward:
        assert np.allclose(jax.jit(jax.jacfwd(f))(theta), reverse, rtol=1e-10, atol=1e-12 * scale)


SINGLE = isolated_structure("rigid", isolator=concave_surface(1.5), time_step=0.005, newton_tolerance=0.0)


def test_the_flat_engines_peak_has_the_implicit_derivative():
    """The bracketed scalar Newton of the flat engine (`isolator_root`): the smooth peak
    displacement of a rigid mass on a single pendulum in f_max and the radius."""
    def peak(theta):
        return peak_response(SINGLE(GX, {"f_max": theta[0], "radius": theta[1]}), 1.5).smooth_base_disp

    _check_derivatives(peak, [0.10, 1.5])


ONE_COMPONENT = isolated_structure("rigid", isolator=TRIPLE, newton_tolerance=TIGHT)(GX)


def _triple(theta):
    pendulum = eqx.tree_at(lambda t: t.top_friction.f_max, TRIPLE, theta[0])
    return eqx.tree_at(lambda t: (t.bottom_radius, t.top_radius), pendulum, (theta[1], theta[1]))


def test_the_series_engines_displacement_has_the_implicit_derivative():
    """Three sliders in one component (Sherman-Morrison): the final displacement in the top
    surface's f_max and the outer radii."""
    def final(theta):
        system = eqx.tree_at(lambda s: s.pendulum, ONE_COMPONENT, _triple(theta))
        return simulate_history(system, 1.5).displacement[-1, 0]

    _check_derivatives(final, [0.12, 2.1])


@pytest.mark.slow
def test_one_slider_on_the_series_engine_has_the_implicit_derivative():
    """One slider's bracketed balance on the series engine: the final displacement in f_max
    and the surface's radius."""
    flat = isolated_structure("rigid", isolator=concave_surface(1.5), split_at_turn=False, time_step=0.005,
                              newton_tolerance=0.0)

    def final(theta):
        linear = flat(GX, {"f_max": theta[0], "radius": theta[1]})
        system = structure_on_isolator(linear, single_pendulum(linear.bearing, radius=theta[1]),
                                       friction_velocity="end", newton_tolerance=TIGHT)
        return simulate_history(system, 1.5).displacement[-1, 0]

    _check_derivatives(final, [0.10, 1.5])


@pytest.mark.parametrize("planar", [False, pytest.param(True, marks=pytest.mark.slow)])
def test_an_imposed_paths_force_has_the_implicit_derivative(planar):
    """Sliders in series along an imposed path, where the iteration holds sum d = D outside
    the residual (the share of dD as the sliders' compliances): the force at the end in the
    top surface's f_max and the path's amplitude."""
    path = ORBIT if planar else PATH

    def force(theta):
        pendulum = eqx.tree_at(lambda t: t.top_friction.f_max, TRIPLE, theta[0])
        traced = sampled_path(TIME, theta[1] * path, 1e6, park_elements=16)  # traced: elements given
        return imposed_path_test(pendulum, traced).fx[-1]

    _check_derivatives(force, [0.12, 1.0], forward=not planar)


# About 37 s: the fast set checks the same two-component balance and its linear solve through the
# imposed planar path (test_an_imposed_paths_force_has_the_implicit_derivative[True]).
@pytest.mark.slow
def test_two_components_displacement_has_the_implicit_derivative():
    """Three sliders in two components (Woodbury's 2 x 2 blocks): the final displacement in
    y in the top surface's f_max and the outer radii."""
    two = bidirectional_isolated_structure("rigid", isolator=TRIPLE, newton_tolerance=TIGHT)((GX, GY))

    def final(theta):
        system = eqx.tree_at(lambda s: s.pendulum, two, _triple(theta))
        return planar_histories(system, 1.0)[1][-1, 1, 0]

    _check_derivatives(final, [0.12, 2.1], forward=False)


@pytest.mark.slow  # about 70 s on a shared 2-core machine: the slab's force law compiled twice
def test_the_slabs_displacement_has_the_implicit_derivative():
    """Four groups of three sliders under a slab (the group forces' system): the final
    rotation in the top surfaces' f_max and their outer radii."""
    corners = np.array([[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]])

    def rotation(theta):
        slab = slab_on_bearings(length_x=20.0, length_y=12.0, weight=1e6, centre_of_mass=np.array([9.0, 6.0]),
                                positions=corners, loads=[0.25e6] * 4, ground_acceleration=GX, ground_y=GY, time_step=DT,
                                isolator=TRIPLE.isolator, pendulums=_triple(theta), height_of_centre_of_mass=3.0)
        return simulate_history(dataclasses.replace(slab, newton_tolerance=TIGHT), 1.0).displacement[-1, 2]

    _check_derivatives(rotation, [0.12, 2.1], forward=False)
