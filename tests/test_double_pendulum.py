"""The double concave friction pendulum as two sliders in series: the backbone of a slow cycle
against the closed forms of Fenz & Constantinou (2006), equal surfaces against a single
pendulum of twice the radius (period and Coulomb decay), two components along a line against
one direction, the gradient in a radius against central differences, bad isolators refused.

Peers: Fenz & Constantinou (2006), Earthquake Engng Struct. Dyn. 35, 1403-1424, for
mu_1 < mu_2: F/W = mu_1 + u / R_1 while surface 1 slides alone, slope 1 / (R_1 + R_2) from
F/W = mu_2 with both sliding, slope 1 / R_2 once surface 1 meets its restrainer at
F/W = mu_1 + d_1 / R_1; a Coulomb oscillator of stiffness W / R_eff and friction mu W,
whose extremes come every half period pi sqrt(R_eff / g) and lose 2 mu R_eff each; under a
vertical ground acceleration a_v the normal load N = W (1 + a_v / g) scales every slider's
force, so a constant a_v is gravity g + a_v (half period pi sqrt(R_eff / (g + a_v)), the same
decay), and N = 0 (uplift) leaves the mass without shear, in free flight.
"""

import dataclasses

import equinox as eqx
import jax
import numpy as np
import pytest
from histories import planar_histories

from teflon_jax.bearing import (
    BoucWen,
    DoublePendulum,
    FrictionParameters,
    check_double_pendulum,
    coulomb_friction,
)
from teflon_jax.excitation import StochasticGroundMotion, sample, uniform_signal
from teflon_jax.systems import (
    imposed_path_test,
    isolated_structure,
    peak_response,
    sampled_path,
    simulate_history,
    triple_structure,
)
from teflon_jax.units import STANDARD_GRAVITY

W = 1e6
R1, R2, D1, D2, MU1, MU2 = 1.5, 2.5, 0.1, 0.2, 0.04, 0.08


def _bearing(**changes):
    values = dict(bottom_radius=R1, top_radius=R2, bottom_capacity=D1, top_capacity=D2,
                  bottom_friction=coulomb_friction(MU1), top_friction=coulomb_friction(MU2),
                  hysteresis=BoucWen(1e-4))
    values.update(changes)
    return DoublePendulum(**values)


def _closed_form(u):
    """F/W of the loading branch (module docstring), and the two transition displacements."""
    both = R1 * (MU2 - MU1)  # surface 2 starts
    ring = MU1 + D1 / R1  # F/W where surface 1 meets its restrainer
    second = D1 + R2 * (ring - MU2)
    force = np.where(u < both, MU1 + u / R1,
                     np.where(u < second, MU2 + (u - both) / (R1 + R2), ring + (u - second) / R2))
    return force, (both, second)


@pytest.fixture(scope="module")
def loading():
    """A slow cycle to 0.29 m (below d_1 + d_2 = 0.3 m), the first quarter: (u, F/W, converged),
    through the bearing test, which balances the sliders by the structures' isolator step."""
    n, period = 4000, 400.0
    t = np.linspace(0, period, n + 1)
    u = 0.29 * np.sin(2 * np.pi * t / period)
    response = jax.jit(imposed_path_test)(_bearing(), sampled_path(t, u, W))
    x, force, ok = u, response.force, response.converged
    quarter = slice(0, n // 4 + 1)
    return np.asarray(x)[quarter], np.asarray(force)[quarter] / W, np.asarray(ok)


def test_the_slow_backbone_is_the_closed_form_of_fenz_and_constantinou(loading):
    """F/W within 1 % of the closed form past the first millimetres (Bouc-Wen's elastic branch),
    and the slope of each regime (fitted on its middle half) within 1 % of 1/R_1, 1/(R_1+R_2)
    and 1/R_2."""
    u, f, ok = loading
    assert ok.all()
    expected, (both, second) = _closed_form(u)
    away = u > 0.005
    np.testing.assert_allclose(f[away], expected[away], rtol=1e-2)
    for start, stop, slope in ((0.0, both, 1 / R1), (both, second, 1 / (R1 + R2)), (second, 0.29, 1 / R2)):
        middle, half = 0.5 * (start + stop), 0.25 * (stop - start)
        inside = (u > middle - half) & (u < middle + half)
        assert np.polyfit(u[inside], f[inside], 1)[0] == pytest.approx(slope, rel=1e-2)


def test_the_transitions_are_where_the_closed_form_puts_them(loading):
    """The line of each regime meets the next at the closed form's displacement within 1 %
    (of the transition) and force within 1 %."""
    u, f, _ = loading
    _, (both, second) = _closed_form(u)
    lines = []
    for start, stop in ((0.0, both), (both, second), (second, 0.29)):
        middle, half = 0.5 * (start + stop), 0.25 * (stop - start)
        inside = (u > middle - half) & (u < middle + half)
        lines.append(np.polyfit(u[inside], f[inside], 1))
    for (a0, b0), (a1, b1), where, force in zip(lines[:-1], lines[1:], (both, second), (MU2, MU1 + D1 / R1)):
        meet = (b1 - b0) / (a0 - a1)
        assert meet == pytest.approx(where, rel=1e-2)
        assert a0 * meet + b0 == pytest.approx(force, rel=1e-2)


RADIUS, MU, DT = 1.0, 0.01, 0.002
TIME = DT * np.arange(4001)


def _swinging(vertical=None):
    """A rigid mass on equal surfaces (R, mu) set swinging by a ground pulse: 8 s of history,
    with the vertical ground acceleration `vertical` (on `TIME`) or none."""
    bearing = _bearing(bottom_radius=RADIUS, top_radius=RADIUS, bottom_capacity=1.0, top_capacity=1.0,
                       bottom_friction=coulomb_friction(MU), top_friction=coulomb_friction(MU))
    pulse = np.where(TIME < 0.5, 0.2 * STANDARD_GRAVITY * np.sin(np.pi * TIME / 0.5), 0.0)
    structure = isolated_structure("rigid", isolator=bearing, time_step=DT)
    system = structure(uniform_signal(pulse, DT))
    if vertical is not None:
        system = dataclasses.replace(system, vertical_acceleration=uniform_signal(vertical, DT))
    response = jax.jit(simulate_history, static_argnums=1)(system, 8.0)
    assert np.asarray(response.converged).all()
    return system, response


def _extremes(u, t, dt):
    """Times and |values| of the extremes of u past the pulse, each refined by a parabola
    through three samples."""
    i = np.arange(1, u.size - 1)
    turns = i[((u[i] - u[i - 1]) * (u[i + 1] - u[i]) <= 0) & (t[i] > 0.5) & (np.abs(u[i]) > 0.1)]
    curvature = u[turns + 1] - 2 * u[turns] + u[turns - 1]
    shift = 0.5 * (u[turns - 1] - u[turns + 1]) / curvature
    return t[turns] + shift * dt, np.abs(u[turns] - 0.25 * (u[turns - 1] - u[turns + 1]) * shift)


def test_equal_surfaces_swing_as_one_pendulum_of_twice_the_radius():
    """R_1 = R_2 = R and mu_1 = mu_2 = mu: the extremes are half a period pi sqrt(2R / g)
    apart within 1 %, and each loses 2 mu (2R) within 1 % (Coulomb decay 4 mu (2R) per cycle);
    the two sliders share the travel equally."""
    _, response = _swinging()
    u, slider = np.asarray(response.displacement[:, 0]), np.asarray(response.slider)
    np.testing.assert_allclose(slider[:, 0], slider[:, 1], rtol=0, atol=1e-12)
    times, peaks = _extremes(u, TIME, DT)
    assert times.size >= 4
    np.testing.assert_allclose(np.diff(times), np.pi * np.sqrt(2 * RADIUS / STANDARD_GRAVITY), rtol=1e-2)
    np.testing.assert_allclose(-np.diff(peaks), 2 * MU * 2 * RADIUS, rtol=1e-2)


def test_a_constant_vertical_acceleration_is_a_stronger_gravity():
    """a_v = 0.2 g throughout: half periods pi sqrt(2R / (1.2 g)) within 1 %, the same decay
    2 mu (2R) per half cycle within 1 %; the peak loop reads the same history."""
    system, response = _swinging(np.full(TIME.size, 0.2 * STANDARD_GRAVITY))
    u = np.asarray(response.displacement[:, 0])
    times, peaks = _extremes(u, TIME, DT)
    assert times.size >= 3 and float(response.uplift_time) == 0.0
    np.testing.assert_allclose(np.diff(times), np.pi * np.sqrt(2 * RADIUS / (1.2 * STANDARD_GRAVITY)), rtol=1e-2)
    np.testing.assert_allclose(-np.diff(peaks), 2 * MU * 2 * RADIUS, rtol=1e-2)
    assert float(peak_response(system, 8.0).base_disp) == pytest.approx(np.abs(u).max(), rel=1e-12)


def test_uplift_leaves_the_mass_without_shear():
    """a_v = -1.5 g over 2-2.5 s: the steps held at N = 0 carry no bearing force and the mass
    flies on at constant velocity (no ground motion then); every step balances."""
    lifted = (TIME > 2.0) & (TIME < 2.5)
    _, response = _swinging(np.where(lifted, -1.5 * STANDARD_GRAVITY, 0.0))
    held = np.concatenate([[False], lifted[:-1]]) & lifted  # steps whose start is lifted too
    force, u = np.asarray(response.bearing_force), np.asarray(response.displacement[:, 0])
    assert held.sum() > 200 and np.all(force[held] == 0.0) and np.abs(force).max() > 1e3
    assert np.abs(np.diff(u[held], 2)).max() < 1e-12
    assert float(response.uplift_time) == pytest.approx(0.5, abs=2 * DT)


MOTION = StochasticGroundMotion(peak_ground_acceleration=0.4 * STANDARD_GRAVITY, duration=10.0, time_step=0.01,
                                rise_time=1.0, strong_motion_duration=5.0)
EQ1 = _bearing(bottom_radius=2.1, top_radius=1.8, bottom_capacity=0.3, top_capacity=0.3,
               bottom_friction=FrictionParameters(0.06, 0.03, 20.0),
               top_friction=FrictionParameters(0.09, 0.04, 20.0), hysteresis=BoucWen(1.27e-4))


def test_two_components_along_a_line_are_the_one_direction_response():
    """A record along a line at 0.6 rad: the one-direction response turned by 0.6 rad (the
    bearing is isotropic), the sliders adding up to the isolator's displacement."""
    acc = np.asarray(sample(MOTION, jax.random.key(3), 1)[0])
    one = triple_structure("rigid", EQ1, uniform_signal(acc, 0.01), time_step=0.005)
    u = np.asarray(jax.jit(simulate_history, static_argnums=1)(one, 10.0).displacement[:, 0])
    assert np.max(np.abs(u)) > 0.05  # both surfaces slide
    c, s = np.cos(0.6), np.sin(0.6)
    turned = triple_structure("rigid", EQ1, uniform_signal(c * acc, 0.01), time_step=0.005)
    turned = turned.with_y_component(uniform_signal(s * acc, 0.01))
    _, x, _, sliders, _, ok = jax.jit(planar_histories, static_argnums=1)(turned, 10.0)
    assert bool(np.all(ok)) and sliders.shape[1:] == (2, 2)
    np.testing.assert_allclose(x[:, 0, 0], c * u, rtol=0, atol=1e-9)
    np.testing.assert_allclose(x[:, 1, 0], s * u, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.asarray(sliders).sum(axis=1), np.asarray(x[:, :, 0]), atol=1e-9)


@pytest.mark.parametrize("uplift", [False, True])
def test_the_peak_is_differentiable_in_the_bottom_radius(uplift):
    """d(smooth peak displacement)/dR_1 by reverse mode against central differences, also
    through 0.4 s of uplift (a_v = -1.5 g)."""
    acc = 2.0 * np.asarray(jax.random.normal(jax.random.key(1), (601,))) * np.sin(np.pi * np.arange(601) / 600)
    system = isolated_structure("rigid", isolator=EQ1)(uniform_signal(acc, 0.01))
    if uplift:
        t = 0.01 * np.arange(601)
        vertical = np.where((t > 2.0) & (t < 2.4), -1.5 * STANDARD_GRAVITY, 0.0)
        system = dataclasses.replace(system, vertical_acceleration=uniform_signal(vertical, 0.01))
        assert float(peak_response(system, 6.0).uplift_time) > 0.3

    def peak(radius):
        moved = eqx.tree_at(lambda s: s.pendulum.bottom_radius, system, radius)
        return peak_response(moved, 6.0).smooth_base_disp

    reverse = float(jax.jit(jax.grad(peak))(2.1))
    h = 1e-4
    central = (float(peak(2.1 + h)) - float(peak(2.1 - h))) / (2 * h)
    assert abs(central) > 1e-3
    assert reverse == pytest.approx(central, rel=1e-4)


@pytest.mark.parametrize("changes, message", [
    (dict(bottom_radius=0.0), "bottom_radius: must be a finite number > 0"),
    (dict(top_radius=-2.0), "top_radius"),
    (dict(top_capacity=0.0), "top_capacity"),
    (dict(bottom_friction=coulomb_friction(-0.01)), "bottom_friction.f_max"),
    (dict(top_friction=FrictionParameters(0.05, 0.06, 0.0)), "top_friction.delta_f: must be smaller than f_max"),
    (dict(top_friction=FrictionParameters(0.05, 0.01, -1.0)), "top_friction.rate_a"),
    (dict(hysteresis=BoucWen(0.0)), "yield_disp"),
])
def test_what_the_model_cannot_take_is_refused_by_name(changes, message):
    with pytest.raises(ValueError, match=message):
        check_double_pendulum(_bearing(**changes))
    with pytest.raises(ValueError, match=message):
        isolated_structure("rigid", isolator=_bearing(**changes))


def test_a_double_pendulum_builds_the_series_structure():
    structure = isolated_structure("building", isolator=_bearing())
    assert structure.isolator == "double-fp" and structure.isolation_period is None
