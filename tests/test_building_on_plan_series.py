"""The Table 2 building on a plan of double or triple friction pendulum groups: each group the
series model with its own sliders, every slider's force under its group's normal load, the
loads moved by the moment of the base's and floors' inertia forces at their heights.

Peers: the building on one pendulum of the building's weight (`triple_structure`, its own tests
against closed forms and OpenSees) in the limit of a symmetric plan without overturning; the
lever rule of the levels' moment; the slab on the same groups in the limit of a rigid frame."""

import dataclasses

import jax
import numpy as np
import pytest
from test_slab_series import DOUBLE, PENDULUMS, TRIPLE

from teflon_jax.excitation import uniform_signal
from teflon_jax.systems import (
    building_on_plan,
    peak_response,
    simulate_history,
    slab_on_bearings,
    triple_structure,
    with_vertical_motion,
)
from teflon_jax.tables import load_table2
from teflon_jax.units import FOOT, STANDARD_GRAVITY

G = STANDARD_GRAVITY
TABLE2 = load_table2()
W = TABLE2.total_weight  # 672 kip
DT, DURATION, STEP = 0.01, 6.0, 0.005
TIME = np.arange(0.0, DURATION + DT / 2, DT)
CORNERS = np.array([[-6.0, -4.0], [6.0, -4.0], [6.0, 4.0], [-6.0, 4.0]])
simulate = jax.jit(simulate_history, static_argnums=1, static_argnames="throw")


def _pulse(peak, frequency=0.7, phase=0.0):
    """A ground acceleration [m/s^2]: peak [g] sin(2 pi f t + phase) under a sin^2 window."""
    return peak * G * np.sin(2 * np.pi * frequency * TIME + phase) * np.sin(np.pi * TIME / DURATION) ** 2


@pytest.mark.parametrize("isolator", [pytest.param("triple-fp", marks=pytest.mark.slow), "double-fp"])
def test_symmetric_plan_without_overturning_is_the_building_on_one_pendulum(isolator):
    """Four equal groups at the corners, the centre of mass at the plan's centre, all heights 0,
    under x and y: every slider's force scales with its group's load W / 4, so the base and the
    floors move as `triple_structure`'s building on one pendulum of weight W (a balance of one
    isolator, not of groups) to 1e-8 of the peak, and the slab does not turn."""
    pendulum = PENDULUMS[isolator]
    ax, ay = uniform_signal(_pulse(0.4), DT), uniform_signal(_pulse(0.3, 0.5, 1.0), DT)
    centre = np.array([8.0, 5.0])
    plan = building_on_plan(length_x=16.0, length_y=10.0, centre_of_mass=centre, positions=centre + CORNERS,
                            loads=[W / 4] * 4, isolator=isolator, pendulums=pendulum, ground_acceleration=ax, ground_y=ay,
                            time_step=STEP, storey_heights=0.0)
    assert plan.overturning is None and plan.mass.shape == (15,)
    one = triple_structure("building", pendulum, ax, ground_y=ay, time_step=STEP)
    response = simulate(plan, DURATION)
    expected = np.asarray(simulate_history(one, DURATION).displacement)
    q = np.asarray(response.displacement)
    peak = np.max(np.abs(expected[:, [0, 7]]))
    assert peak > 0.1  # the outer surfaces slide
    assert bool(np.all(response.converged))
    assert np.max(np.abs(q[:, :14] - expected)) < 1e-8 * peak
    assert np.max(np.abs(q[:, 14])) < 1e-12


def _eccentric(pendulum, **options):
    """Five groups of `pendulum` on an eccentric plan (unequal loads and vertical stiffness),
    the base 0.5 m and the floors Table 2's 12 ft storeys above the sliding surface."""
    lx, ly, centre = 24.0, 16.0, np.array([13.0, 7.5])
    positions = np.array([[1.0, 1.0], [23.0, 1.0], [23.0, 15.0], [1.0, 15.0], [15.0, 9.0]])
    loads = W * np.array([0.15, 0.2, 0.2, 0.15, 0.3])
    system = building_on_plan(
        length_x=lx, length_y=ly, centre_of_mass=centre, positions=positions, loads=loads,
        isolator=pendulum.isolator, pendulums=pendulum, ground_acceleration=uniform_signal(_pulse(0.25), DT),
        ground_y=uniform_signal(_pulse(0.2, 0.5, 1.0), DT), time_step=STEP, vertical_stiffness=[1.0, 2.0, 1.0, 0.5, 3.0],
        **options)
    return system, positions - centre, loads


def test_series_groups_balance_the_moment_of_the_levels_inertia_forces():
    """Five double pendulum groups on an eccentric plan under two components and a vertical
    record of 0.8 g: at every step the loads add up to (1 + a_v / g) W and their changes balance the
    moment of the base's and floors' inertia forces at their heights at the step's start,
    sum_g r_g dN_g = -sum_i h_i F_i, to 1e-9 W m, on the lever rule's steps and on those where
    groups lift and the others take their share; the slab turns."""
    system, arms, loads = _eccentric(DOUBLE, base_height=0.5)
    av = uniform_signal(0.8 * G * np.sin(2 * np.pi * 1.3 * TIME), DT)
    response = simulate_history(with_vertical_motion(system, av), DURATION)
    assert bool(np.all(response.converged))
    n = np.asarray(response.normal_load)
    factor = 1 + np.asarray(av(response.time)) / G
    assert np.max(np.abs(n.sum(axis=1) - factor * W)) < 1e-9 * W
    heights = 0.5 + 12 * FOOT * np.arange(7)
    mass, total = np.asarray(system.mass), np.asarray(response.total_acceleration)
    moment = np.stack([(mass[:7] * total[:, :7]) @ heights, (mass[7:14] * total[:, 7:14]) @ heights], axis=-1)
    change = n - factor[:, None] * loads
    assert np.max(np.abs(change[1:] @ arms + moment[:-1])) < 1e-9 * W
    assert np.max(np.abs(moment)) > 1.0 * W  # a moment of a metre times the weight, at least
    assert np.all(n >= 0) and np.any(n == 0)
    assert np.max(np.abs(np.asarray(response.displacement)[:, 14])) > 1e-4  # the eccentric plan turns it


@pytest.mark.slow
def test_rigid_frame_on_series_groups_is_the_slab_with_its_centre_of_mass_at_the_building_height():
    """A frame with Table 2's modes at 10^3 times its frequencies on the eccentric plan's double
    pendulum groups: the building moves as one rigid body, `slab_on_bearings` of weight W with
    the base slab's rotational inertia and its centre of mass at h_c = sum m_i h_i / sum m_i;
    translation and rotation agree to 1e-5 of their peaks (measured 5.7e-7; 6.4e-5 at 100 times
    the frequencies, falling as their inverse square) and the loads to 1e-5 W (5.7e-7 W)."""
    stiff = dataclasses.replace(TABLE2, frequencies=1e3 * np.asarray(TABLE2.frequencies))
    base_height, storey = 0.5, 3.0
    building, arms, loads = _eccentric(DOUBLE, building=stiff, storey_heights=storey, base_height=base_height)
    heights = base_height + storey * np.arange(7)
    masses = np.concatenate([[TABLE2.base_weight], np.full(6, TABLE2.floor_weight)])
    slab = slab_on_bearings(
        length_x=24.0, length_y=16.0, weight=W, centre_of_mass=[13.0, 7.5], positions=arms + [13.0, 7.5],
        loads=loads, isolator="double-fp", pendulums=DOUBLE, ground_acceleration=building.ground_acceleration, ground_y=building.ground_y,
        time_step=STEP, rotational_inertia=float(building.mass[14]), vertical_stiffness=[1.0, 2.0, 1.0, 0.5, 3.0],
        height_of_centre_of_mass=masses @ heights / masses.sum())
    b, s = simulate(building, DURATION), simulate(slab, DURATION)
    qb, qs = np.asarray(b.displacement)[:, [0, 7, 14]], np.asarray(s.displacement)
    assert np.max(np.abs(qs[:, 2])) > 1e-4
    assert np.all(np.max(np.abs(qb - qs), axis=0) < 1e-5 * np.max(np.abs(qs), axis=0))
    assert np.max(np.abs(np.asarray(b.normal_load) - np.asarray(s.normal_load))) < 1e-5 * W


@pytest.mark.parametrize(("change", "message"), [
    (dict(), "isolation_period: does not apply to isolator 'double-fp'"),
    (dict(isolation_period=None, isolation_damping=0.05), "isolation_damping: does not apply to isolator 'double-fp'"),
    (dict(isolation_period=None, radii=2.0), "radii: does not apply to isolator 'double-fp'"),
    (dict(isolation_period=None, pendulums=TRIPLE), "pendulums: group 1 is a triple-fp, not the double-fp"),
])
def test_series_groups_refuse_the_one_surface_inputs_by_name(change, message):
    """Springs, their damping and radii belong to flat sliders and single pendulums; each given
    with series pendulum groups is refused, naming the argument, before any work."""
    centre = np.array([8.0, 5.0])
    options = dict(length_x=16.0, length_y=10.0, centre_of_mass=centre, positions=centre + CORNERS,
                   loads=[W / 4] * 4, isolator="double-fp", pendulums=DOUBLE, time_step=STEP,
                   ground_acceleration=uniform_signal(_pulse(0.1), DT), isolation_period=2.0)
    with pytest.raises(ValueError, match=message):
        building_on_plan(**{**options, **change})


def test_the_peak_driver_reads_the_groups_vertical_record_as_the_history_does():
    """Under a vertical record of 1.1 g the whole building lifts off its groups at times (and,
    nearly weightless before and after, tips under the levels' inertia forces, which both
    report): the peak driver's uplift time is the history's steps with N <= 0 times the step,
    and each group's largest and least load are the history's."""
    system, _, _ = _eccentric(DOUBLE, base_height=0.5)
    system = with_vertical_motion(system, uniform_signal(1.1 * G * np.sin(2 * np.pi * 1.3 * TIME), DT))
    peaks = peak_response(system, DURATION)
    history = simulate(system, DURATION, throw=False)
    factor = np.asarray(history.load_factor)
    assert bool(peaks.converged) == bool(np.all(history.converged))
    assert float(peaks.uplift_time) == pytest.approx(np.sum(factor[1:] <= 0) * STEP, abs=1e-12)
    assert float(peaks.uplift_time) > 0.05
    loads = np.asarray(history.normal_load)
    np.testing.assert_allclose(peaks["group_normal_load"]["peak_N"], loads.max(axis=0), rtol=1e-12)
    np.testing.assert_allclose(peaks["group_normal_load"]["min_N"], loads.min(axis=0), rtol=1e-12, atol=1e-9)
