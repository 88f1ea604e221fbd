"""The triple friction pendulum (series model) against the closed-form backbone of regimes I-V,
in one direction and along an orbit, and its bad input.

Peers: the force-displacement relation written from the sliding of each surface
(`triple_pendulum_backbone`, Fenz & Constantinou 2008); the one-direction path for an orbit
along x; the restrainers for an orbit beyond the capacity.
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from teflon_jax.bearing import (
    BoucWen,
    TriplePendulum,
    check_triple_pendulum,
    coulomb_friction,
    triple_pendulum_backbone,
)
from teflon_jax.systems import imposed_path_test, sampled_path

W = 1e6


def _bearing(**changes):
    values = dict(inner_radius=0.4, bottom_radius=2.2, top_radius=2.2, inner_capacity=0.05,
                  bottom_capacity=0.30, top_capacity=0.35, inner_friction=coulomb_friction(0.02),
                  bottom_friction=coulomb_friction(0.06), top_friction=coulomb_friction(0.10),
                  hysteresis=BoucWen(1e-4))
    values.update(changes)
    return TriplePendulum(**values)


def _slow_cycle(amplitude, n=8000, period=400.0):
    t = np.linspace(0, period, n + 1)
    return t, amplitude * np.sin(2 * np.pi * t / period)


@pytest.fixture(scope="module")
def loading():
    bearing = _bearing()
    regimes, end = triple_pendulum_backbone(bearing)
    t, u = _slow_cycle(1.02 * end)
    response = jax.jit(imposed_path_test)(bearing, sampled_path(t, u, W))
    quarter = slice(0, len(t) // 4)
    return regimes, end, u[quarter], np.asarray(response.force)[quarter] / W, response


def _fitted_lines(regimes, end, u, f):
    """Slope and intercept of the simulated loop over the middle half of each regime."""
    lines = []
    for (start, _, _), stop in zip(regimes, [r[0] for r in regimes[1:]] + [end]):
        middle, half = 0.5 * (start + stop), 0.25 * (stop - start)
        inside = (u > middle - half) & (u < middle + half)
        lines.append(np.polyfit(u[inside], f[inside], 1))
    return lines


def test_every_step_balances_the_sliders(loading):
    assert bool(np.all(loading[4].converged))


def test_the_slopes_of_regimes_one_to_five_are_the_closed_forms(loading):
    regimes, end, u, f, _ = loading
    for (slope, _), (_, _, closed) in zip(_fitted_lines(regimes, end, u, f), regimes):
        assert slope == pytest.approx(closed, rel=0.01)


def test_the_transition_displacements_are_the_closed_forms(loading):
    """Where two adjacent fitted lines cross: the displacement where the next pair of
    surfaces takes over (u*, u**, u_dr1, u_dr4) within 1 %."""
    regimes, end, u, f, _ = loading
    lines = _fitted_lines(regimes, end, u, f)
    for (k0, c0), (k1, c1), (start, _, _) in zip(lines[:-1], lines[1:], regimes[1:]):
        crossing = (c1 - c0) / (k0 - k1)
        assert crossing == pytest.approx(start, rel=0.01)


def test_the_bearing_stiffens_where_regime_five_ends(loading):
    """On regime V's line just before the inner ring, well above it just after (the ring)."""
    regimes, end, u, f, _ = loading
    start, force0, slope = regimes[-1]

    def line(x):
        return force0 + slope * (x - start)

    before, after = np.interp(0.995 * end, u, f), np.interp(1.015 * end, u, f)
    assert before == pytest.approx(line(0.995 * end), rel=0.01)
    assert after > line(1.015 * end) + 0.02


def test_the_loop_is_symmetric_and_dissipates(loading):
    *_, response = loading
    f = np.asarray(response.force)
    n = len(f)
    # the peak force at +u and at -u of the cycle
    assert np.max(f) == pytest.approx(-np.min(f), rel=1e-3)
    _, u = _slow_cycle(1.02 * loading[1])
    work = np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(u[:n]))
    assert work > 0


@pytest.mark.slow
def test_an_orbit_along_x_is_the_one_direction_path():
    bearing = _bearing()
    t, u = _slow_cycle(0.5, n=2000)
    one = imposed_path_test(bearing, sampled_path(t, u, W))
    two = imposed_path_test(bearing, sampled_path(t, np.stack([u, 0 * u], -1), W))
    np.testing.assert_allclose(two.force[:, 0], one.force, rtol=0, atol=1e-6 * W)
    np.testing.assert_allclose(two.force[:, 1], 0.0, atol=1e-9 * W)


@pytest.mark.slow  # a long planar orbit: about a minute on two cores
def test_an_orbit_at_the_capacity_stays_inside_every_ring():
    """A circular orbit out to the bearing's travel (the end of regime V): every slider meets
    its ring and none passes it (to the give of a stiff restrainer); one 5 % further and the
    restrainers stiffen the bearing."""
    bearing = _bearing()
    _, end = triple_pendulum_backbone(bearing)
    n = 6000
    t = np.linspace(0, 600, n + 1)
    angle = 2 * np.pi * t / 150

    def orbit(scale):
        radius = np.minimum(t / 150, 1.0) * scale * end
        path = np.stack([radius * np.cos(angle), radius * np.sin(angle)], -1)
        return jax.jit(imposed_path_test)(bearing, sampled_path(t, path, W))

    response = orbit(1.0)
    assert bool(np.all(response.converged))
    reach = np.linalg.norm(np.asarray(response.slider), axis=-1)
    capacities = np.asarray(bearing.series_capacities())
    assert np.all(reach <= capacities * 1.01)
    assert np.all(reach.max(axis=0) >= capacities * 0.99)  # every ring was met
    force = np.linalg.norm(np.asarray(response.force), axis=-1).max()
    beyond = np.linalg.norm(np.asarray(orbit(1.05).force), axis=-1).max()
    assert beyond > 2 * force


@pytest.mark.parametrize("changes, message", [
    (dict(inner_radius=-0.4), "inner_radius"),
    (dict(inner_radius=3.0), "bottom_radius: must be larger than inner_radius"),
    (dict(top_capacity=0.0), "top_capacity"),
    (dict(inner_friction=coulomb_friction(0.08)), "inner <= bottom <= top"),
    (dict(top_friction=coulomb_friction(0.05)), "swap bottom and top"),
])
def test_geometry_and_friction_the_series_model_cannot_take_are_refused(changes, message):
    with pytest.raises(ValueError, match=message):
        check_triple_pendulum(_bearing(**changes))


def test_the_backbone_refuses_capacities_out_of_its_order():
    """Surface 1 reaching its ring before surface 4 slides: regime III does not exist."""
    with pytest.raises(ValueError, match="capacities: the closed forms"):
        triple_pendulum_backbone(_bearing(bottom_capacity=0.05))


def test_the_force_is_differentiable_in_the_radii():
    """d(peak force)/d(outer radius) against central differences (design gradients), in
    forward mode (no tape of the Newton loops to keep)."""
    t, u = _slow_cycle(0.3, n=800)

    def peak(radius):
        response = imposed_path_test(_bearing(bottom_radius=radius, top_radius=radius), sampled_path(t, u, W))
        return jnp.max(response.force) / W

    grad = float(jax.jvp(peak, (2.2,), (1.0,))[1])
    h = 1e-4
    central = (float(peak(2.2 + h)) - float(peak(2.2 - h))) / (2 * h)
    assert grad < 0
    assert grad == pytest.approx(central, rel=1e-3)
