"""The triple friction pendulum in the structures (one direction): the isolator solve of the
structures against the closed-form backbone of regimes I-V, free vibrations at the period of
the sliding surfaces, peaks converged in the step, Monte Carlo, gradients, bad input.

Peers: `triple_pendulum_backbone` (Fenz & Constantinou 2008); the pendulum period
2 pi sqrt(R / g) of the surfaces that slide (all three sliders in series without friction:
R = 2a + (b - a) + (c - a) = b + c; the inner pair alone below the outer friction: R = 2a);
the same run at a tenth of the step; central differences.
"""

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from teflon_jax.bearing import (
    BoucWen,
    FrictionParameters,
    TriplePendulum,
    coulomb_friction,
    paper_bearing,
    triple_pendulum_backbone,
)
from teflon_jax.excitation import StochasticGroundMotion, sample, uniform_signal
from teflon_jax.studies import monte_carlo
from teflon_jax.systems import (
    imposed_path_test,
    isolated_structure,
    peak_response,
    sampled_path,
    simulate_history,
)
from teflon_jax.units import STANDARD_GRAVITY

W = 1e6


def _bearing(mu=(0.02, 0.06, 0.10), **changes):
    values = dict(inner_radius=0.4, bottom_radius=2.2, top_radius=2.2, inner_capacity=0.05,
                  bottom_capacity=0.30, top_capacity=0.35, inner_friction=coulomb_friction(mu[0]),
                  bottom_friction=coulomb_friction(mu[1]), top_friction=coulomb_friction(mu[2]),
                  hysteresis=BoucWen(1e-4))
    values.update(changes)
    return TriplePendulum(**values)


def _eq1_bearing(radius=2.2):
    return _bearing(bottom_radius=radius, top_radius=radius,
                    inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                    bottom_friction=FrictionParameters(0.07, 0.03, 20.0),
                    top_friction=FrictionParameters(0.11, 0.05, 20.0))


@pytest.fixture(scope="module")
def loading():
    """A slow cycle to 1.02 times the end of regime V, imposed through a stiff actuator on
    the structures' isolator solve; the first quarter (loading)."""
    bearing = _bearing()
    regimes, end = triple_pendulum_backbone(bearing)
    n, period = 8000, 400.0
    t = np.linspace(0, period, n + 1)
    u = 1.02 * end * np.sin(2 * np.pi * t / period)
    response = jax.jit(imposed_path_test)(bearing, sampled_path(t, u, W))
    x, force, converged = u, response.force, response.converged
    quarter = slice(0, n // 4)
    return regimes, end, np.asarray(x)[quarter], np.asarray(force)[quarter] / W, np.asarray(converged)


def _fitted_lines(regimes, end, u, f):
    lines = []
    for (start, _, _), stop in zip(regimes, [r[0] for r in regimes[1:]] + [end]):
        middle, half = 0.5 * (start + stop), 0.25 * (stop - start)
        inside = (u > middle - half) & (u < middle + half)
        lines.append(np.polyfit(u[inside], f[inside], 1))
    return lines


def test_the_structures_isolator_follows_the_backbone_of_regimes_one_to_five(loading):
    """Slopes of regimes I-V and the displacements where the next pair of surfaces takes over
    within 1 % of the closed forms, every step balanced."""
    regimes, end, u, f, converged = loading
    assert converged.all()
    lines = _fitted_lines(regimes, end, u, f)
    for (slope, _), (_, _, closed) in zip(lines, regimes):
        assert slope == pytest.approx(closed, rel=0.01)
    for (k0, c0), (k1, c1), (start, _, _) in zip(lines[:-1], lines[1:], regimes[1:]):
        assert (c1 - c0) / (k0 - k1) == pytest.approx(start, rel=0.01)
    for (start, force0, slope), stop in zip(regimes, [r[0] for r in regimes[1:]] + [end]):
        middle = 0.5 * (start + stop)
        assert np.interp(middle, u, f) == pytest.approx(force0 + slope * (middle - start), rel=0.01)


def _free_vibration(bearing, pulse, duration=30.0, dt=0.01):
    """A rigid mass on `bearing` after a ground pulse of `pulse` [m/s^2] for 0.5 s."""
    t = dt * np.arange(int(round(duration / dt)) + 1)
    ground = uniform_signal(np.where(t < 0.5, pulse, 0.0), dt)
    system = isolated_structure("rigid", isolator=bearing)(ground)
    response = jax.jit(simulate_history, static_argnums=1)(system, duration)
    return np.asarray(response.time), np.asarray(response.displacement[:, 0]), response


def _period(t, u, after=1.0):
    """Mean time between upward zero crossings (linearly interpolated) after `after` [s]."""
    t, u = t[t > after], u[t > after]
    i = np.flatnonzero((u[:-1] < 0) & (u[1:] >= 0))
    crossings = t[i] - u[i] * (t[i + 1] - t[i]) / (u[i + 1] - u[i])
    return np.mean(np.diff(crossings)), len(crossings)


def test_without_friction_the_mass_swings_at_the_period_of_all_surfaces_in_series():
    bearing = _bearing(mu=(0.0, 0.0, 0.0))
    t, u, response = _free_vibration(bearing, 1.0)
    period, count = _period(t, u)
    assert count >= 5 and bool(np.all(response.converged))
    assert period == pytest.approx(2 * math.pi * math.sqrt((2.2 + 2.2) / STANDARD_GRAVITY), rel=2e-3)
    # no friction: the amplitude does not decay
    assert np.max(u[t > 20]) == pytest.approx(np.max(u), rel=1e-3)


def test_below_the_outer_friction_only_the_inner_pair_swings():
    """Inner friction 0.005, outer 0.3 and 0.4: a swing whose force stays below 0.3 W (and
    inside the inner ring) slides on surfaces 2 and 3 only, at 2 pi sqrt(2a / g), decaying
    by 4 mu_2 (2a) a cycle (Coulomb)."""
    bearing = _bearing(mu=(0.005, 0.3, 0.4))
    t, u, response = _free_vibration(bearing, 1.0, duration=12.0)
    period, count = _period(t, u)
    assert count >= 4
    assert period == pytest.approx(2 * math.pi * math.sqrt(0.8 / STANDARD_GRAVITY), rel=5e-3)
    assert np.max(np.abs(np.asarray(response.slider)[:, 1:])) < 1e-4  # the outer sliders stick (< Y)
    peaks = [np.max(u[(t > t0) & (t < t0 + period)]) for t0 in (1.0, 1.0 + period)]
    assert peaks[0] - peaks[1] == pytest.approx(4 * 0.005 * 0.8, rel=0.03)


@pytest.fixture(scope="module")
def record():
    motion = StochasticGroundMotion(peak_ground_acceleration=0.4 * STANDARD_GRAVITY, duration=20.0,
                                    time_step=0.01, rise_time=2.0, strong_motion_duration=8.0)
    return motion, np.asarray(sample(motion, jax.random.key(3), 1)[0])


@pytest.mark.parametrize("kind", ["rigid", "building"])
def test_peaks_converge_in_the_time_step(kind, record):
    """The default 5 ms step within 0.3 % of 0.5 ms (Eq. 1 on every surface)."""
    _, acc = record

    def peaks(step):
        structure = isolated_structure(kind, isolator=_eq1_bearing(), time_step=step)
        p = jax.jit(peak_response, static_argnums=1)(structure(uniform_signal(acc, 0.01)), 20.0)
        assert bool(p.converged)
        return float(p.base_disp), float(p.base_shear_ratio)

    coarse, fine = peaks(0.005), peaks(0.0005)
    assert coarse[0] > 0.05  # the outer surfaces slide
    np.testing.assert_allclose(coarse, fine, rtol=3e-3)


def test_histories_and_the_peak_loop_agree(record):
    _, acc = record
    structure = isolated_structure("building", isolator=_eq1_bearing())
    system = structure(uniform_signal(acc, 0.01))
    p = peak_response(system, 20.0)
    h = simulate_history(system, 20.0)
    assert float(p.base_disp) == pytest.approx(float(np.max(np.abs(h.displacement[:, 0]))), rel=1e-12)
    mass = np.asarray(system.mass)  # the base shear: every mass above the bearings, the base slab's included
    shear = np.abs(np.asarray(h.total_acceleration) @ mass) / (mass.sum() * STANDARD_GRAVITY)
    assert float(p.base_shear_ratio) == pytest.approx(shear.max(), rel=1e-9)
    assert float(np.max(np.abs(h.slider.sum(axis=1) - h.displacement[:, 0]))) < 1e-9  # rounding


@pytest.mark.slow
def test_monte_carlo_runs_the_triple_pendulum(record):
    motion, _ = record
    structure = isolated_structure("rigid", isolator=_eq1_bearing())
    result = monte_carlo(structure, motion, 4, key=jax.random.key(0), chunk_size=2)
    assert result.converged.all()
    one = jax.random.fold_in(jax.random.key(0), 2)
    alone = peak_response(structure(uniform_signal(sample(motion, one, 1)[0], 0.01)), 20.0)
    assert result.base_disp[2] == pytest.approx(float(alone.base_disp), rel=1e-9)


@pytest.mark.slow
def test_the_peak_is_differentiable_in_the_outer_radii():
    """d(smooth peak displacement)/d(b = c) by reverse and forward mode against central
    differences of the peak loop."""
    acc = 2.0 * np.asarray(jax.random.normal(jax.random.key(1), (801,))) * np.sin(np.pi * np.arange(801) / 800)
    system = isolated_structure("rigid", isolator=_eq1_bearing())(uniform_signal(acc, 0.01))

    def peak(radius):
        moved = eqx.tree_at(lambda s: (s.pendulum.bottom_radius, s.pendulum.top_radius), system, (radius, radius))
        return peak_response(moved, 8.0).smooth_base_disp

    reverse = float(jax.jit(jax.grad(peak))(2.2))
    forward = float(jax.jvp(peak, (2.2,), (1.0,))[1])
    h = 1e-4
    central = (float(peak(2.2 + h)) - float(peak(2.2 - h))) / (2 * h)
    assert reverse == pytest.approx(central, rel=1e-5)
    assert forward == pytest.approx(central, rel=1e-5)


@pytest.mark.parametrize("changes, message", [
    (dict(bearing=paper_bearing(coulomb_friction(0.05))), r"bearing: the isolator value \(TriplePendulum\)"),
    (dict(isolation_period=2.0), "isolation_period: does not apply to the triple-fp"),
    (dict(isolation_damping=0.05), "isolation_damping: does not apply"),
    (dict(friction_model="coulomb"), "friction_model: does not apply"),
    (dict(isolator=_bearing(inner_radius=3.0)), "bottom_radius: must be larger"),
    (dict(time_step=0.0), "time_step"),
])
def test_bad_triple_structures_are_refused_by_name(changes, message):
    arguments = {"isolator": _bearing(), **changes}
    with pytest.raises(ValueError, match=message):
        isolated_structure("rigid", **arguments)


def test_a_triple_pendulum_refuses_another_isolators_design():
    structure = isolated_structure("rigid", isolator=_bearing())
    with pytest.raises(ValueError, match=r"design: unknown variable\(s\) \[.radius.\] for the triple-fp isolator"):
        structure(uniform_signal(jnp.zeros(10), 0.01), {"radius": 2.0})


def test_the_inner_surfaces_take_eq1_at_half_the_sliders_speed():
    """Regime I at a constant speed V: only the inner pair slides, each of its two surfaces at
    V / 2, so F / W = u / (2 a) + mu_2(V / 2) with Eq. 1's mu(v) = f_max - delta_f exp(-a v)
    (Fenz & Constantinou 2008). The outer sliders' Bouc-Wen pre-slip (a few Y as their Z nears
    F / (f_min W)) takes up to 3e-4 of F / W; at V itself the friction would be 0.0036 higher."""
    bearing = _eq1_bearing()
    speed, dt = 0.05, 1e-4
    t = np.arange(0.0, 0.4 + dt / 2, dt)
    response = jax.jit(imposed_path_test)(bearing, sampled_path(t, speed * t, W))
    x, force, converged = speed * t, response.force, response.converged
    x, ratio = np.asarray(x), np.asarray(force) / W
    assert np.asarray(converged).all()
    inner = bearing.inner_friction
    mu_half = inner.f_max - inner.delta_f * np.exp(-inner.rate_a * speed / 2)
    # Z saturated, before F / W reaches the bottom surface's f_min = 0.04 (regime II)
    sliding = (x > 0.004) & (x < 0.012)
    closed = x[sliding] / (2 * bearing.inner_radius) + mu_half
    assert np.max(np.abs(ratio[sliding] - closed)) < 6e-4
