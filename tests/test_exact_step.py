"""The exact linear rule (`linear_rule="exact"`): exact for inputs linear over the step, so the
storey modes carry no period error and the step is set by the bearing alone."""

import jax
import numpy as np
import pytest

import teflon_jax as tj
from teflon_jax.excitation import uniform_signal
from teflon_jax.units import PSI


def _ramp_oscillator(rule, dt, duration=4.0, rate=0.8, period=1.3, zeta=0.07):
    ground = uniform_signal(rate * np.arange(0.0, duration + 1e-9, 0.5), 0.5)  # a_g = rate t [m/s^2]
    system = tj.rigid_mass(weight=1e5, bearing=None, ground_acceleration=ground, time_step=dt,
                           isolation_period=period, damping_ratio=zeta, friction_model="none", linear_rule=rule)
    return tj.simulate_history(system, duration), rate, 2 * np.pi / period, zeta


@pytest.mark.parametrize("rule", ["exact", "newmark"])
def test_exact_rule_is_the_closed_form_under_a_ramp(rule):
    """u'' + 2 zeta w u' + w^2 u = -r t from rest: u = -r/w^2 (t - 2 zeta/w) plus the free
    response that starts it from rest. The exact rule gives it to rounding at 50 ms steps;
    Newmark's rule, second order, does not (its error is the check that the test can fail)."""
    response, r, w, zeta = _ramp_oscillator(rule, 0.05)
    t = np.asarray(response.time)
    wd = w * np.sqrt(1 - zeta**2)
    u0, v0 = r / w**2 * (-2 * zeta / w), r / w**2  # the free part cancels u_p(0), u_p'(0)
    free = np.exp(-zeta * w * t) * (u0 * np.cos(wd * t) + (v0 + zeta * w * u0) / wd * np.sin(wd * t))
    exact = -r / w**2 * (t - 2 * zeta / w) + free
    error = np.max(np.abs(np.asarray(response.displacement)[:, 0] - exact)) / np.max(np.abs(exact))
    if rule == "exact":
        assert error < 1e-10
    else:
        assert error > 1e-4


def test_exact_rule_does_not_depend_on_the_step_for_a_record_linear_between_samples():
    """The building without friction under a record linear between its 0.01 s samples: the
    exact rule at 10 ms and at 2.5 ms give the same response at the samples (to rounding),
    storey modes included; Newmark's rule does not."""
    rng = np.random.default_rng(3)
    ground = uniform_signal(2.0 * rng.normal(size=301), 0.01)

    def run(rule, dt):
        system = tj.six_storey_building(bearing=None, ground_acceleration=ground, time_step=dt,
                                        isolation_period=2.0, friction_model="none", linear_rule=rule)
        response = tj.simulate_history(system, 3.0)
        every = int(round(0.01 / dt))
        return np.asarray(response.displacement)[::every]

    coarse, fine = run("exact", 0.01), run("exact", 0.0025)
    scale = np.max(np.abs(fine), axis=0)
    assert np.max(np.abs(coarse - fine) / scale) < 1e-9
    newmark = run("newmark", 0.01)
    assert np.max(np.abs(newmark - fine) / scale) > 1e-3


def test_exact_rule_with_friction_converges_on_the_building():
    """With the sliding bearings, the exact rule's peaks at 5 ms lie within 0.2 % of its
    0.5 ms ones, and its base shear, which Newmark's rule misses by its storey modes' period
    error, is closer to that peak than Newmark's at 5 ms."""
    from teflon_jax.excitation import StochasticGroundMotion
    from teflon_jax.studies import monte_carlo_motion
    from teflon_jax.systems import peak_response
    from teflon_jax.units import STANDARD_GRAVITY

    model = StochasticGroundMotion(peak_ground_acceleration=0.3 * STANDARD_GRAVITY, duration=20.0,
                                   time_step=0.01, rise_time=2.0, strong_motion_duration=10.0)
    record = uniform_signal(monte_carlo_motion(model, jax.random.key(4), 0), 0.01)

    def peaks(rule, dt):
        structure = tj.isolated_structure("building", time_step=dt, pressure=1000 * PSI, linear_rule=rule)
        result = jax.jit(lambda: peak_response(structure(record), 20.0))()
        assert bool(result.converged)
        return np.array([result.base_disp, result.base_shear_ratio])

    reference = peaks("exact", 0.0005)
    error = np.abs(peaks("exact", 0.005) / reference - 1)
    newmark_error = np.abs(peaks("newmark", 0.005) / reference - 1)
    assert np.all(error < 2e-3)
    assert error[1] < 0.5 * newmark_error[1]


def test_a_stiff_oscillator_steps_exactly_where_the_exponential_needs_many_halvings():
    """u'' + 2 zeta w u' + w^2 u = 0 at w = 2e4 rad/s over a 5 ms step (w^2 dt = 2e6: more than
    the 16 halvings of A dt `expm` takes by default, which return NaN): the step's free block is
    the closed form e^(-zeta w dt) [[cos + zeta w / w_d sin, sin / w_d], [-w^2 / w_d sin,
    cos - zeta w / w_d sin]] (of w_d dt) to 1e-7 (measured 3e-9), in units of w and 1."""
    w, zeta, dt = 2e4, 0.02, 0.005
    a = np.array([[0.0, 1.0], [-w**2, -2 * zeta * w]])
    free, start, end = tj.structures.first_order_hold(a, np.array([[0.0], [-1.0]]), dt)
    wd = w * np.sqrt(1 - zeta**2)
    decay, c, s = np.exp(-zeta * w * dt), np.cos(wd * dt), np.sin(wd * dt)
    exact = decay * np.array([[c + zeta * w / wd * s, s / wd], [-w**2 / wd * s, c - zeta * w / wd * s]])
    assert np.all(np.isfinite(np.asarray(free))) and np.all(np.isfinite(np.asarray(end)))
    scale = np.array([[1.0, 1 / w], [w, 1.0]])  # displacement and velocity in units of one another
    assert np.max(np.abs((np.asarray(free) - exact) / scale)) < 1e-7
