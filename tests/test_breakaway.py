"""Breakaway acts once (Eq. 17 then Eq. 1 for good), in bearing tests and in structures, and
anisotropy at 45 degrees (constants halfway between parallel and perpendicular to lay)."""

import jax.numpy as jnp
import numpy as np
import pytest

import teflon_jax as tj
from teflon_jax.systems import rigid_mass
from teflon_jax.units import INCH, KIP, PSI, STANDARD_GRAVITY

# Test No. 191 (MODEL.md Section 7): UF, 1000 psi, perpendicular to lay, b = 3, 78.5 kip.
UF_T_1000, _ = tj.interface_parameters("UF", 1000 * PSI, "T")
B_191, LOAD_191 = 3.0, 78.5 * KIP
F_MAX_T, DELTA_F_T, RATE_A_T = 0.1420, 0.1181, 0.45 / INCH  # Table 1, UF 1000 psi T
F_MAX_P, DELTA_F_P, RATE_A_P = 0.1193, 0.0927, 0.60 / INCH  # Table 1, UF 1000 psi P
THRESHOLD = 0.999  # |Z| that ends breakaway for good (MODEL.md Section 3)


def eq1(speed, f_max=F_MAX_T, delta_f=DELTA_F_T, rate_a=RATE_A_T):
    return f_max - delta_f * np.exp(-rate_a * np.abs(speed))


def half_cycles(velocity):
    """Index of the half-cycle (run of one velocity sign) of each sample."""
    return np.concatenate([[0], np.cumsum(np.diff(np.sign(velocity)) != 0)])


def test_191_breakaway_then_eq1_on_every_half_cycle():
    bearing = tj.paper_bearing(UF_T_1000, breakaway_ratio=B_191)
    r = tj.imposed_path_test(bearing, tj.SineMotion(0.5 * INCH, 0.03, cycles=2.5), LOAD_191)
    mu = np.asarray(r.fx) / LOAD_191
    z, v, z_peak = np.asarray(r.z[:, 0]), np.asarray(r.vx), np.asarray(r.z_peak)
    broken = z_peak >= THRESHOLD
    assert broken.any() and not broken[0]
    # before the first slide: the static coefficient b (f_max - delta_f) of Eq. 17
    np.testing.assert_allclose(mu[~broken], B_191 * (F_MAX_T - DELTA_F_T) * z[~broken], rtol=1e-9)
    # after it: Eq. 1 at the sliding velocity, on every half-cycle that follows
    sliding = broken & (np.abs(z) > THRESHOLD)
    np.testing.assert_allclose(mu[broken], eq1(v[broken]) * z[broken], rtol=1e-9)
    halves = set(half_cycles(v)[sliding])
    assert len(halves) >= 5
    for k in halves:
        assert np.max(np.abs(mu[sliding & (half_cycles(v) == k)])) < F_MAX_T  # no second breakaway


def test_breakaway_acts_once_in_a_structure():
    """A rigid mass on the test-191 bearing, shaken at 0.25 g: Eq. 17 until |Z| first reaches
    0.999, Eq. 1 at the sliding velocity on every later half-cycle, and the force that moved
    the mass (Newmark's equilibrium) is the force reported at every step, the switch included."""
    dt, duration, omega = 1e-3, 4.0, 3.14
    times = np.arange(0.0, duration + dt / 2, dt)
    ground = tj.Signal(jnp.asarray(times), jnp.asarray(0.25 * STANDARD_GRAVITY * np.sin(omega * times)))
    weight = 1.0e5
    bearing = tj.paper_bearing(UF_T_1000, breakaway_ratio=B_191)
    system = rigid_mass(weight=weight, bearing=bearing, ground_acceleration=ground, time_step=dt)
    r = tj.simulate_history(system, duration)
    assert bool(r.succeeded)
    mu = np.asarray(r.friction_force) / weight
    z, v, z_peak = np.asarray(r.z), np.asarray(r.velocity[:, 0]), np.asarray(r.z_peak)
    broken = z_peak >= THRESHOLD
    assert broken.any() and not broken[0]
    np.testing.assert_allclose(mu[~broken], B_191 * (F_MAX_T - DELTA_F_T) * z[~broken], rtol=1e-9)
    np.testing.assert_allclose(mu[broken], eq1(v[broken]) * z[broken], rtol=1e-9)
    sliding = broken & (np.abs(z) > THRESHOLD) & (np.abs(v) > 1e-4)
    assert len(set(half_cycles(v)[sliding])) >= 4
    # Newmark's average-acceleration relations with the reported accelerations, at every step
    u = np.asarray(r.displacement[:, 0])
    a = np.asarray(r.total_acceleration[:, 0]) - np.asarray(r.ground[:, 0])
    velocity_error = v[1:] - v[:-1] - dt / 2 * (a[1:] + a[:-1])
    displacement_error = u[1:] - u[:-1] - dt * v[:-1] - dt**2 / 4 * (a[1:] + a[:-1])
    # as accelerations: within the Newton tolerance (~1e-6 m/s^2); a force switched between the
    # equilibrium and the report would leave (b f_min - Eq. 1) g ~ 0.4 m/s^2 at one step
    tolerance = 1e-4 * np.max(np.abs(a))
    assert np.max(np.abs(velocity_error)) * 2 / dt < tolerance
    assert np.max(np.abs(displacement_error)) * 4 / dt**2 < tolerance


def test_anisotropy_at_45_degrees_is_the_mean_of_the_two_laws():
    """Sliding at 45 degrees to the lay: constants halfway between P and T (MODEL.md Section 4);
    at high speed mu = (0.1193 + 0.1420) / 2 = 0.13065."""
    parallel, _ = tj.interface_parameters("UF", 1000 * PSI, "P")
    bearing = tj.paper_bearing(parallel, friction_perpendicular=UF_T_1000)
    t = np.linspace(0.0, 2 / 0.6, 1601)
    u = 4 * INCH * np.sin(2 * np.pi * 0.6 * t)
    mean = dict(f_max=(F_MAX_P + F_MAX_T) / 2, delta_f=(DELTA_F_P + DELTA_F_T) / 2,
                rate_a=(RATE_A_P + RATE_A_T) / 2)
    for sign in (1.0, -1.0):  # along (1, 1) and (1, -1)
        r = tj.imposed_path_test(bearing, tj.tabulated_motion(t, u, sign * u), LOAD_191)
        speed = np.hypot(np.asarray(r.vx), np.asarray(r.vy))
        sliding = np.hypot(np.asarray(r.z[:, 0]), np.asarray(r.z[:, 1])) > 0.9999
        mu = np.asarray(r.coefficient)
        np.testing.assert_allclose(mu[sliding], eq1(speed[sliding], **mean), rtol=1e-6)
        assert np.max(mu) == pytest.approx(0.13065, rel=1e-4)
    # the coefficient itself, at 45 degrees in each quadrant and high speed
    for vx, vy in ((1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)):
        assert float(bearing.coefficient(vx, vy)) == pytest.approx(0.13065, rel=1e-9)
