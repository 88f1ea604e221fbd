"""The Table 2 building on a rigid base slab with a plan: the building on one group in the limit
of a symmetric plan without overturning, the rigid slab in the limit of a rigid frame, and the
groups' normal loads under the moment sum_i h_i F_i of the levels' inertia forces (a rigid slab
on vertical supports that take no tension, the force held from the step's start)."""

import dataclasses

import numpy as np
import pytest

from teflon_jax.bearing import paper_bearing
from teflon_jax.excitation import uniform_signal
from teflon_jax.systems import (
    building_on_plan,
    simulate_history,
    six_storey_building,
    slab_on_bearings,
    with_vertical_motion,
)
from teflon_jax.tables import interface_parameters, load_table2
from teflon_jax.units import FOOT, PSI, STANDARD_GRAVITY

G = STANDARD_GRAVITY
TABLE2 = load_table2()
W = TABLE2.total_weight  # 672 kip
DT, DURATION, STEP, PERIOD = 0.01, 6.0, 0.005, 2.0
TIME = np.arange(0.0, DURATION + DT / 2, DT)
BEARING = paper_bearing(interface_parameters("UF", 1000 * PSI)[0], yield_disp=1e-3)


def _pulse(peak, frequency=0.7, phase=0.0):
    """A ground acceleration [m/s^2]: peak [g] sin(2 pi f t + phase) under a sin^2 window."""
    return peak * G * np.sin(2 * np.pi * frequency * TIME + phase) * np.sin(np.pi * TIME / DURATION) ** 2


def _exact(system):
    """Each step's bearing equilibrium solved to rounding."""
    return dataclasses.replace(system, newton_tolerance=0.0)


def _symmetric(offsets, lx, ly, **options):
    """Equal groups at C + `offsets` on an lx x ly plan with C at its centre."""
    centre = np.array([lx / 2, ly / 2])
    offsets = np.asarray(offsets, float)
    return centre + offsets, building_on_plan(
        length_x=lx, length_y=ly, centre_of_mass=centre, positions=centre + offsets,
        loads=[W / len(offsets)] * len(offsets), bearings=BEARING, time_step=STEP, **options)


def _level_moment(system, response, heights):
    """sum_i h_i F_i (nt, 2) [N m], F_i = m_i (q_i'' + a_g) of the base and floors in x and y,
    written out from the levels' heights `heights` (7,) [m] (q = x: base, floors; y: the same;
    theta)."""
    mass = np.asarray(system.mass)
    total = np.asarray(response.total_acceleration)
    fx = mass[:7] * total[:, :7]
    fy = mass[7:14] * total[:, 7:14]
    return np.stack([fx @ heights, fy @ heights], axis=-1)


CORNERS = [[-6.0, -4.0], [6.0, -4.0], [6.0, 4.0], [-6.0, 4.0]]


@pytest.mark.parametrize("isolator", [pytest.param("flat", marks=pytest.mark.slow), "single-fp"])
def test_symmetric_plan_without_overturning_is_the_building_on_one_group(isolator):
    """Four equal groups at the corners, the centre of mass at the plan's centre, all heights 0:
    along x alone (flat sliders with springs of T_b) and along x and y (single pendulums of
    R = g (T_b / 2 pi)^2, whose W / R is the springs' stiffness), the base and floors follow
    `six_storey_building` on one group of weight W to 1e-6 of the peak (both solved to
    rounding; measured 1.8e-13) and the slab does not turn."""
    radius = G * (PERIOD / (2 * np.pi)) ** 2
    ax, ay = uniform_signal(_pulse(0.4), DT), uniform_signal(_pulse(0.3, 0.5, 1.0), DT)
    ground_y = ay if isolator == "single-fp" else None
    options = dict(isolation_period=PERIOD) if isolator == "flat" else dict(isolator="single-fp", radii=radius)
    _, plan = _symmetric(CORNERS, 16.0, 10.0, ground_acceleration=ax, ground_y=ground_y, storey_heights=0.0, **options)
    assert plan.overturning is None
    one = six_storey_building(components=2, bearing=BEARING, ground_acceleration=ax, ground_y=ground_y, time_step=STEP,
                                 isolation_period=PERIOD)
    q = np.asarray(simulate_history(_exact(plan), DURATION).displacement)
    expected = np.asarray(simulate_history(_exact(one), DURATION).displacement)
    peak = np.max(np.abs(expected[:, [0, 7]]))
    assert peak > 0.1
    assert np.max(np.abs(q[:, :14] - expected)) < 1e-6 * peak
    assert np.max(np.abs(q[:, 14])) < 1e-12


@pytest.mark.slow
def test_rigid_frame_is_the_slab_with_its_centre_of_mass_at_the_building_height():
    """A frame with Table 2's modes at 10^4 times its frequencies on an eccentric plan (centre
    of mass 2 m and 1 m off the plan's centre, four corner groups of unequal load and pressure)
    under two components: the building moves as one rigid body, so it is `slab_on_bearings` of
    weight W with the base slab's rotational inertia and its centre of mass at the
    mass-weighted height h_c = sum m_i h_i / sum m_i of the levels; translation and rotation
    agree to 1e-5 of their peaks (measured 4e-7; 8e-5 at 100 times the frequencies, falling
    as their inverse square) and the groups' loads to 1e-5 W (measured 2.5e-6 W)."""
    stiff = dataclasses.replace(TABLE2, frequencies=1e4 * np.asarray(TABLE2.frequencies))
    lx, ly, centre = 20.0, 12.0, np.array([12.0, 7.0])
    positions = np.array([[1.0, 1.0], [19.0, 1.0], [19.0, 11.0], [1.0, 11.0]])
    loads = W * np.array([0.2, 0.3, 0.3, 0.2])
    bearings = [paper_bearing(interface_parameters("UF", p * PSI)[0], yield_disp=1e-3) for p in (1000, 2000, 3000, 1000)]
    ax, ay = uniform_signal(_pulse(0.15), DT), uniform_signal(_pulse(0.12, 0.5, 1.0), DT)
    common = dict(length_x=lx, length_y=ly, centre_of_mass=centre, positions=positions, loads=loads,
                  bearings=bearings, ground_acceleration=ax, ground_y=ay, time_step=STEP, isolation_period=PERIOD,
                  isolation_damping=0.05)
    base_height, storey = 0.5, 3.0
    heights = base_height + storey * np.arange(7)
    masses = np.concatenate([[TABLE2.base_weight], np.full(6, TABLE2.floor_weight)])
    inertia = TABLE2.base_weight / G * (lx**2 + ly**2) / 12
    building = building_on_plan(**common, building=stiff, storey_heights=storey, base_height=base_height)
    slab = slab_on_bearings(**common, weight=W, rotational_inertia=inertia,
                            height_of_centre_of_mass=masses @ heights / masses.sum())
    b = simulate_history(building, DURATION)
    s = simulate_history(slab, DURATION)
    qb, qs = np.asarray(b.displacement)[:, [0, 7, 14]], np.asarray(s.displacement)
    assert np.max(np.abs(qs[:, 2])) > 1e-3  # the plan's eccentricity turns the slab
    assert np.all(np.max(np.abs(qb - qs), axis=0) < 1e-5 * np.max(np.abs(qs), axis=0))
    assert np.max(np.abs(np.asarray(b.normal_load) - np.asarray(s.normal_load))) < 1e-5 * W


def test_groups_balance_the_moment_of_the_levels_inertia_forces():
    """An eccentric plan of five groups (unequal tributary loads and vertical stiffness) under
    two components and a vertical record, the base 0.5 m and the floors Table 2's 12 ft
    storeys above it (the default): at every step the loads add up to (1 + a_v / g) W and
    their changes dN_g = N_g - (1 + a_v / g) W_g balance the moment of the base's and floors'
    inertia forces at their heights at the step's start, sum_g r_g dN_g = -sum_i h_i F_i, to
    1e-9 W m (measured 7e-14 W m), on the lever rule's steps and on those where the stiff SE
    group lifts and the others take its share; the loads swing from one side of the plan to the
    other."""
    lx, ly, centre = 24.0, 16.0, np.array([13.0, 7.5])
    positions = np.array([[1.0, 1.0], [23.0, 1.0], [23.0, 15.0], [1.0, 15.0], [15.0, 9.0]])
    loads = W * np.array([0.15, 0.2, 0.2, 0.15, 0.3])
    av = uniform_signal(0.2 * G * np.sin(2 * np.pi * 1.3 * TIME), DT)
    system = building_on_plan(
        length_x=lx, length_y=ly, centre_of_mass=centre, positions=positions, loads=loads, bearings=BEARING,
        ground_acceleration=uniform_signal(_pulse(0.15), DT), ground_y=uniform_signal(_pulse(0.12, 0.5, 1.0), DT),
        time_step=STEP, isolation_period=PERIOD, base_height=0.5, vertical_stiffness=[1.0, 2.0, 1.0, 0.5, 3.0])
    response = simulate_history(with_vertical_motion(system, av), DURATION)
    n = np.asarray(response.normal_load)
    factor = 1 + np.asarray(av(response.time)) / G
    assert np.max(np.abs(n.sum(axis=1) - factor * W)) < 1e-9 * W
    change = n - factor[:, None] * loads
    heights = 0.5 + 12 * FOOT * np.arange(7)
    moment = _level_moment(system, response, heights)
    assert np.max(np.abs(change[1:] @ (positions - centre) + moment[:-1])) < 1e-9 * W
    assert np.max(np.abs(moment)) > 1.0 * W  # a moment of a metre times the weight, at least
    assert np.all(n >= 0) and np.any(n == 0)
    east_west = n[:, 1] / loads[1] - n[:, 0] / loads[0]
    assert east_west.max() > 0.3 and east_west.min() < -0.3


@pytest.mark.slow
def test_a_strong_pulse_lifts_either_pair_and_the_base_moves_as_without_overturning():
    """Six equal groups in two rows (x = -9.5, 0, 9.5 m from C, y = +-4 m) under a 0.4 g pulse
    along x, Table 2's storeys: the moment swings past 2/3 W a (the lever rule lifts the outer
    pair, a = 9.5 m) but stays below W a (where the slab would tip about the other outer pair),
    so the west pair and then the east pair lift (N_g = 0, no friction) while the slab rests on
    the other four, the loads adding up to W; the load leaves the side the building leans away
    from (east while the moment is positive); north and south carry the same. Flat sliders
    share the friction mu W Z whatever the loads, so the base and floors move as the building
    on one group to 1e-6 of the peak (both solved to rounding; measured 1.3e-13)."""
    a = 9.5
    offsets = [[-a, -4.0], [0.0, -4.0], [a, -4.0], [-a, 4.0], [0.0, 4.0], [a, 4.0]]
    ax = uniform_signal(_pulse(0.4), DT)
    _, system = _symmetric(offsets, 22.0, 10.0, ground_acceleration=ax, isolation_period=PERIOD)
    response = simulate_history(_exact(system), DURATION)
    n = np.asarray(response.normal_load)
    assert np.max(np.abs(n.sum(axis=1) - W)) < 1e-9 * W
    assert np.max(np.abs(n[:, :3] - n[:, 3:])) < 1e-9 * W
    moment = _level_moment(system, response, 12 * FOOT * np.arange(7))[:, 0]
    assert 2 / 3 * W * a < np.max(np.abs(moment)) < W * a
    west, east = n[:, [0, 3]], n[:, [2, 5]]
    lifted_west, lifted_east = np.all(west == 0, axis=1), np.all(east == 0, axis=1)
    assert lifted_west.any() and lifted_east.any()
    assert np.all(np.asarray(response.friction_force)[n == 0] == 0)
    leaning = np.abs(moment[:-1]) > 0.1 * W
    assert np.all(np.sign(west[1:, 0] - east[1:, 0])[leaning] == np.sign(moment[:-1])[leaning])
    one = six_storey_building(components=2, bearing=BEARING, ground_acceleration=ax, time_step=STEP, isolation_period=PERIOD)
    expected = np.asarray(simulate_history(_exact(one), DURATION).displacement)
    q = np.asarray(response.displacement)
    assert np.max(np.abs(q[:, :14] - expected)) < 1e-6 * np.max(np.abs(expected[:, 0]))


@pytest.mark.parametrize(("change", "message"), [
    (dict(storey_heights=-3.0), "storey_heights: must be >= 0 m"),
    (dict(storey_heights=[3.0] * 5), r"storey_heights: one value or one per storey \(6\)"),
    (dict(base_height=np.nan), "base_height: must be >= 0 m"),
    (dict(isolator="triple-fp"), "pendulums: isolator 'triple-fp' needs its pendulum"),
    (dict(isolation_period=None), "isolation_period: the building's springs need their period"),
    (dict(isolator="single-fp"), "radii: isolator 'single-fp' needs the radius"),
    (dict(loads=[W / 5] * 4), "plan: the tributary loads add up to"),
    (dict(positions=[[2.0, 5.0], [6.0, 5.0], [10.0, 5.0], [14.0, 5.0]]),
     "storey_heights, base_height: the bearing groups lie on one line"),
])
def test_inputs_refused_by_name(change, message):
    """Each wrong input is refused before any work, naming the argument as written."""
    options = dict(length_x=16.0, length_y=10.0, centre_of_mass=[8.0, 5.0], bearings=BEARING,
                   positions=np.array([8.0, 5.0]) + CORNERS, loads=[W / 4] * 4,
                   ground_acceleration=uniform_signal(_pulse(0.1), DT), time_step=STEP, isolation_period=PERIOD)
    if change.get("isolator") == "single-fp":
        options.pop("isolation_period")
    with pytest.raises(ValueError, match=message):
        building_on_plan(**{**options, **change})


def test_groups_on_one_line_without_heights_are_accepted():
    """Heights 0 need no moment balance, so groups on one line make a plan (torsion only)."""
    line = [[2.0, 5.0], [6.0, 5.0], [10.0, 5.0], [14.0, 5.0]]
    system = building_on_plan(length_x=16.0, length_y=10.0, centre_of_mass=[8.0, 5.0], bearings=BEARING,
                              positions=line, loads=[W / 4] * 4, ground_acceleration=uniform_signal(_pulse(0.1), DT),
                              time_step=STEP, isolation_period=PERIOD, storey_heights=0.0)
    assert system.overturning is None and system.mass.shape == (15,)
