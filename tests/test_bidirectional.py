"""Bidirectional structures: Park's biaxial Z updated exactly along straight increments, the
rigid mass and the Table 2 building under two ground components."""

import dataclasses

import diffrax
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from teflon_jax.bearing import BoucWen, paper_bearing, park_rate
from teflon_jax.excitation import uniform_signal
from teflon_jax.solver import park_exact_update
from teflon_jax.systems import (
    rigid_mass,
    simulate_history,
    six_storey_building,
)
from teflon_jax.tables import interface_parameters
from teflon_jax.units import PSI, STANDARD_GRAVITY

G = STANDARD_GRAVITY


def _bearing(breakaway=True):
    params, b = interface_parameters("UF", 1000 * PSI)
    return paper_bearing(params, breakaway_ratio=b if breakaway else None)


def _pulse(duration=6.0, dt=0.01, frequency=1.0, phase=0.0, peak=0.3):
    t = np.arange(0.0, duration + dt / 2, dt)
    return peak * G * np.sin(2 * np.pi * frequency * t + phase) * np.sin(np.pi * t / duration) ** 2


def test_park_update_matches_the_ode_along_straight_increments():
    """The closed form equals Eqs. 8-9 integrated along du (DOP853, rtol 1e-12), including
    increments on which one or both components cross zero (reversals, turns)."""
    h = BoucWen(yield_disp=1.27e-4)
    rng = np.random.default_rng(0)
    worst = 0.0
    rate_jit = jax.jit(lambda z, du: park_rate(h, z, du))
    for trial in range(24):
        z0 = rng.uniform(-1, 1, 2)
        z0 = z0 / max(1.0, 1.01 * np.hypot(*z0))
        du = rng.normal(size=2) * h.yield_disp * rng.choice([0.05, 0.5, 2.0, 10.0])
        if trial % 8 == 0:
            du[1] = 0.0

        def rate(t, z, du=du):
            return np.asarray(rate_jit(z, du))

        reference = solve_ivp(rate, (0, 1), z0, method="DOP853", rtol=1e-12, atol=1e-13).y[:, -1]
        got = np.asarray(park_exact_update(h, jnp.asarray(z0), jnp.asarray(du)))
        worst = max(worst, np.max(np.abs(got - reference)))
    assert worst < 1e-9


@pytest.mark.slow
def test_motion_along_a_line_at_30_degrees_is_the_uniaxial_response():
    """Eqs. 8-9 on an isotropic bearing: ground motion along a line at 30 degrees to x gives
    the uniaxial response along that line, no motion across it, and a friction force along it."""
    angle = np.deg2rad(30.0)
    record = _pulse()
    ground = uniform_signal(record, 0.01)
    bearing = _bearing()
    kwargs = dict(weight=1e5, bearing=bearing, time_step=0.0025, isolation_period=2.5, damping_ratio=0.05)
    plane = rigid_mass(components=2,
        ground_acceleration=uniform_signal(np.cos(angle) * record, 0.01),
        ground_y=uniform_signal(np.sin(angle) * record, 0.01),
        **kwargs,
    )
    line = rigid_mass(ground_acceleration=ground, **kwargs)
    # both equilibria solved to rounding (newton_tolerance 0), so that what is left is the law
    biaxial = simulate_history(dataclasses.replace(plane, newton_tolerance=0.0), 6.0)
    uniaxial = simulate_history(dataclasses.replace(line, newton_tolerance=0.0), 6.0)
    u = np.asarray(uniaxial.displacement[:, 0])
    along = np.cos(angle) * biaxial.displacement[:, 0] + np.sin(angle) * biaxial.displacement[:, 1]
    across = -np.sin(angle) * biaxial.displacement[:, 0] + np.cos(angle) * biaxial.displacement[:, 1]
    peak = np.max(np.abs(u))
    assert peak > 0.01  # it slides
    np.testing.assert_allclose(along, u, rtol=0, atol=1e-6 * peak)
    assert np.max(np.abs(across)) < 1e-6 * peak
    force = np.asarray(biaxial.friction_force[:, 0])
    cross = np.cos(angle) * force[:, 1] - np.sin(angle) * force[:, 0]
    assert np.max(np.abs(cross)) < 1e-6 * np.max(np.abs(force))
    # Z (and the force) agree to rounding accumulated over the run; a wrong coupling of the
    # components shows at the per-cent level.
    np.testing.assert_allclose(
        np.cos(angle) * force[:, 0] + np.sin(angle) * force[:, 1],
        np.asarray(uniaxial.friction_force),
        atol=5e-6 * np.max(np.abs(force)),
    )


@pytest.mark.slow
@pytest.mark.parametrize("structure", ["rigid", "building"])
def test_zero_y_record_gives_the_uniaxial_result_to_rounding(structure):
    """A zero y record: the bidirectional system is the uniaxial one. Converged to rounding
    (`newton_tolerance=0` in both), they agree to ~1e-12 of the peak (measured 7.7e-13 rigid,
    1.5e-12 building); at the default tolerance (|residual| <= 1e-6 Y per step, where the two
    Newton solvers stop at different iterates) only to 2e-10 and 2e-9: the gap is the
    stopping rule, not the model."""
    record = _pulse(duration=4.0)
    bearing = _bearing()
    from teflon_jax.systems import six_storey_building

    if structure == "rigid":
        kwargs = dict(weight=1e5, bearing=bearing, time_step=0.0025, isolation_period=2.5, damping_ratio=0.05)
        plane = rigid_mass(components=2, ground_acceleration=uniform_signal(record, 0.01), **kwargs)
        line = rigid_mass(ground_acceleration=uniform_signal(record, 0.01), **kwargs)
    else:
        kwargs = dict(bearing=bearing, time_step=0.0025, isolation_period=2.0)
        plane = six_storey_building(components=2, ground_acceleration=uniform_signal(record, 0.01), **kwargs)
        line = six_storey_building(ground_acceleration=uniform_signal(record, 0.01), **kwargs)
    n = line.mass.shape[0]
    errors = []
    for tolerance in (1e-6, 0.0):
        biaxial = simulate_history(dataclasses.replace(plane, newton_tolerance=tolerance), 4.0)
        uniaxial = simulate_history(dataclasses.replace(line, newton_tolerance=tolerance), 4.0)
        peak = np.max(np.abs(uniaxial.displacement))
        assert np.max(np.abs(biaxial.displacement[:, n:])) == 0.0  # nothing moves across
        errors.append(np.max(np.abs(biaxial.displacement[:, :n] - uniaxial.displacement)) / peak)
    assert errors[1] < 1e-11, errors
    assert errors[0] < 1e-6, errors


def energy_terms(system, response):
    """Input, kinetic, strain, damping and friction energies [J] by the trapezoidal rule."""
    t = np.asarray(response.time)
    q, v = np.asarray(response.displacement), np.asarray(response.velocity)
    m, K, C = np.asarray(system.mass), np.asarray(system.stiffness), np.asarray(system.damping)
    R = np.asarray(system.influence)
    ag = np.asarray(response.ground)
    power_in = -np.einsum("tn,n,nd,td->t", v, m, R, ag)
    bearing_v = np.einsum("gdn,tn->tgd", np.asarray(system.bearing_map), v)
    power_friction = np.einsum("tgd,tgd->t", np.asarray(response.friction_force), bearing_v)
    power_damping = np.einsum("tn,nk,tk->t", v, C, v)

    def integral(p):
        return float(np.sum(0.5 * (p[1:] + p[:-1]) * np.diff(t)))

    kinetic = 0.5 * float(np.sum(m * v[-1] ** 2))
    strain = 0.5 * float(q[-1] @ K @ q[-1])
    return integral(power_in), kinetic, strain, integral(power_damping), integral(power_friction)


def test_energy_balance_of_a_bidirectional_run():
    """Input = kinetic + strain + damping + friction work within 1 % (building, two components)."""
    system = six_storey_building(components=2,
        bearing=_bearing(),
        ground_acceleration=uniform_signal(_pulse(frequency=0.8), 0.01),
        ground_y=uniform_signal(_pulse(frequency=0.55, phase=1.0, peak=0.25), 0.01),
        time_step=0.0025,
        isolation_period=2.5,
    )
    response = simulate_history(system, 6.0)
    e_in, kinetic, strain, damping, friction = energy_terms(system, response)
    assert friction > 0.2 * e_in  # the bearings do work in this run
    assert abs(e_in - (kinetic + strain + damping + friction)) < 0.01 * e_in


@pytest.mark.slow
def test_fast_solver_matches_tsit5_on_a_short_pair():
    """RiccatiNewmark at 2.5 ms against Tsit5 (rtol 1e-9): peak resultant displacement within 0.5 %."""
    system = rigid_mass(components=2,
        weight=1e5,
        bearing=_bearing(),
        ground_acceleration=uniform_signal(_pulse(frequency=0.8), 0.01),
        ground_y=uniform_signal(_pulse(frequency=0.55, phase=1.0, peak=0.25), 0.01),
        time_step=0.0025,
    )
    fast = simulate_history(system, 6.0)
    reference = simulate_history(system, 6.0, solver=diffrax.Tsit5(), rtol=1e-9, atol=1e-12)
    peaks = [float(np.max(np.hypot(r.displacement[:, 0], r.displacement[:, 1]))) for r in (fast, reference)]
    assert abs(peaks[0] - peaks[1]) < 5e-3 * peaks[1]
