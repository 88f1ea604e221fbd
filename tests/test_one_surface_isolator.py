"""One surface as an isolator of sliders in series: the flat slider and the single friction
pendulum run on the series engine with the numbers of the flat sliders' engine.

A `SinglePendulum` (S = 1; R = inf for the flat slider) made of the flat engine's own bearing
(`single_pendulum`: Table 1's UF row with its breakaway, velocity-dependent Eq. 1), on the flat
engine's own linear structure (`structure_on_isolator`: its springs, dampers and W / R stay in
the structure), with the law "end" (Eq. 1 at the isolator's velocity at the step's end, on the
whole of Z) gives the flat engine's histories (Z along the step's net increment,
`split_at_turn=False`; both balances solved to rounding) to 1e-9 of the peak, in one component
(the exact linear step) and in two (Newmark's, the planar engine's), with a vertical record
too. The series law "mean" (Eq. 1 at each surface's mean speed over the step, f_min while Z
points back) is another law: with Coulomb friction, where both laws are f_min Z, it too gives
the flat engine's numbers. Along an imposed path the law "end" is the flat bearing test's
(`imposed_path_test`).
"""

import dataclasses

import jax
import numpy as np
import pytest
from histories import planar_histories

from teflon_jax.bearing import (
    Backlash,
    BoucWen,
    DoublePendulum,
    FrictionParameters,
    SinglePendulum,
    SurfaceParts,
    Wear,
    check_single_pendulum,
    concave_surface,
    coulomb_friction,
    paper_bearing,
    single_pendulum,
)
from teflon_jax.excitation import StochasticGroundMotion, sample, uniform_signal
from teflon_jax.studies import bidirectional_isolated_structure
from teflon_jax.systems import (
    imposed_path_test,
    isolated_structure,
    sampled_path,
    simulate_history,
    structure_on_isolator,
    with_vertical_motion,
)
from teflon_jax.tables import interface_parameters
from teflon_jax.units import PSI, STANDARD_GRAVITY

DURATION = 8.0
RADIUS = 1.5
ISOLATORS = {"flat": np.inf, "single-fp": RADIUS}
"""Each one-surface isolator's radius [m] (flat sliders: R = inf)."""

AGREEMENT = 1e-9
"""Largest difference of the two engines' displacement histories over the peak."""


def _value(isolator, bearing=None):
    """The isolator value of `isolator`: flat sliders or the single pendulum of `bearing`
    (`None`: Table 1's)."""
    if isolator == "flat":
        return bearing
    surface = concave_surface(ISOLATORS[isolator])
    return surface if bearing is None else (bearing, surface)


def _ground(seed, scale=1.0):
    motion = StochasticGroundMotion(peak_ground_acceleration=0.6 * STANDARD_GRAVITY, duration=DURATION,
                                    time_step=0.01, rise_time=1.0, strong_motion_duration=5.0)
    return uniform_signal(scale * np.asarray(sample(motion, jax.random.PRNGKey(seed), 1))[0], 0.01)


def _on_one_surface(flat_builder, isolator, linear, law="end", **surface):
    """The series engine on `linear` with the one-surface isolator of `flat_builder`'s bearing."""
    bearing = flat_builder.isolation()[0]
    pendulum = single_pendulum(bearing, radius=ISOLATORS[isolator], **surface)
    return structure_on_isolator(linear, pendulum, friction_velocity=law, newton_tolerance=1e-13)


def _one_component(isolator, kind, vertical=None, law="end", bearing=None, **options):
    builder = isolated_structure(kind, isolator=_value(isolator, bearing), split_at_turn=False, newton_tolerance=0.0,
                                 time_step=0.005, **options)
    flat = builder(_ground(1))
    series = _on_one_surface(builder, isolator, flat, law)
    if vertical is not None:
        flat, series = with_vertical_motion(flat, vertical), with_vertical_motion(series, vertical)
    flat_run = jax.jit(simulate_history, static_argnums=1)(flat, DURATION)
    series_run = jax.jit(simulate_history, static_argnums=1)(series, DURATION)
    assert bool(np.all(series_run.converged))
    return np.asarray(flat_run.displacement), np.asarray(series_run.displacement)


def _relative(a, b):
    return float(np.max(np.abs(a - b)) / np.max(np.abs(a)))


# each isolator and each structure once in the fast set (each case compiles two programs);
# the other two pairs run with the slow tests
@pytest.mark.parametrize(("isolator", "kind"), [
    ("flat", "rigid"), ("single-fp", "building"),
    pytest.param("flat", "building", marks=pytest.mark.slow),
    pytest.param("single-fp", "rigid", marks=pytest.mark.slow)])
def test_one_surface_in_one_component_gives_the_flat_engines_histories(isolator, kind):
    flat, series = _one_component(isolator, kind)
    assert _relative(flat, series) <= AGREEMENT
    assert np.max(np.abs(flat[:, 0])) > 0.05  # it slides


def test_one_surface_under_a_vertical_record_gives_the_flat_engines_histories():
    # the building at 5 ms: the end-velocity law's balance falls with a reversing speed in some
    # steps (a bracket, not a line search on r^2, finds its root)
    flat, series = _one_component("flat", "building", vertical=_ground(9))
    assert _relative(flat, series) <= AGREEMENT


# each isolator and each structure once in the fast set (each case compiles two programs);
# the other two pairs run with the slow tests
@pytest.mark.parametrize(("isolator", "kind"), [
    ("flat", "rigid"), ("single-fp", "building"),
    pytest.param("flat", "building", marks=pytest.mark.slow),
    pytest.param("single-fp", "rigid", marks=pytest.mark.slow)])
def test_one_surface_in_two_components_gives_the_flat_engines_histories(isolator, kind):
    dt = 0.0025
    ground = (_ground(1), _ground(2, 0.8))
    planar = bidirectional_isolated_structure(kind, isolator=_value(isolator), time_step=dt)
    flat = dataclasses.replace(planar(ground), newton_tolerance=0.0)
    builder = isolated_structure(kind, isolator=_value(isolator), linear_rule="newmark", time_step=dt)
    linear = builder(ground[0])
    series = _on_one_surface(builder, isolator, linear).with_y_component(ground[1])
    q = np.asarray(jax.jit(simulate_history, static_argnums=1)(flat, DURATION).displacement)
    n = linear.mass.shape[0]
    histories = jax.jit(planar_histories, static_argnums=1)(series, DURATION)
    assert bool(np.all(histories[-1]))
    flat_base = np.stack([q[:, 0], q[:, n]], -1)
    assert _relative(flat_base, np.asarray(histories[1])[:, :, 0]) <= AGREEMENT
    assert _relative(q[:, :n], np.asarray(histories[1])[:, 0, :n]) <= AGREEMENT  # every level along x


def test_a_flat_slider_sliding_in_two_components_balances_every_step():
    # along its sliding the flat slider's 2 x 2 slope is near singular (|Z| = 1, no W / R): its
    # Newton step is (G K + I)^-1 G r, which the Woodbury form C (r - s) loses to cancellation
    motion = StochasticGroundMotion(peak_ground_acceleration=0.6 * STANDARD_GRAVITY, duration=12.0,
                                    time_step=0.01)
    ground = [uniform_signal(scale * np.asarray(sample(motion, jax.random.PRNGKey(seed), 1))[0], 0.01)
              for seed, scale in ((1, 1.0), (2, 0.8))]
    builder = isolated_structure("rigid", linear_rule="newmark", time_step=0.0025)
    series = _on_one_surface(builder, "flat", builder(ground[0]), "mean").with_y_component(ground[1])
    series = dataclasses.replace(series, newton_tolerance=1e-9)
    assert bool(np.all(jax.jit(planar_histories, static_argnums=1)(series, 12.0)[-1]))


def test_with_coulomb_friction_the_series_law_is_the_flat_law():
    # f_min = mu at every speed: "mean" and "end" both carry f_min Z
    bearing = paper_bearing(coulomb_friction(0.06))
    flat, series = _one_component("single-fp", "rigid", law="mean", bearing=bearing, pressure=1000 * PSI)
    assert _relative(flat, series) <= AGREEMENT


def test_velocity_dependent_friction_tells_the_laws_apart():
    # the series law at the mean speed (f_min while Z points back) is not the flat engine's
    flat, series = _one_component("flat", "rigid", law="mean")
    assert _relative(flat, series) > 1e-4


def test_the_end_law_needs_one_surface():
    double = DoublePendulum(bottom_radius=1.5, top_radius=2.0, bottom_capacity=0.3, top_capacity=0.3,
                            bottom_friction=FrictionParameters(0.06, 0.03, 25.0),
                            top_friction=FrictionParameters(0.09, 0.04, 15.0), hysteresis=BoucWen(2e-4))
    linear = isolated_structure("rigid", isolator=concave_surface(3.5))(_ground(1))
    with pytest.raises(ValueError, match="friction_velocity"):
        structure_on_isolator(linear, double, friction_velocity="end")
    with pytest.raises(ValueError, match="friction_velocity"):
        imposed_path_test(double, sampled_path(np.arange(3) * 0.01, np.zeros(3), 1e6), friction_velocity="end")
    with pytest.raises(ValueError, match="friction_velocity"):
        structure_on_isolator(linear, double, friction_velocity="start")


@pytest.mark.parametrize("radius", [np.inf, RADIUS])
def test_along_an_imposed_path_the_end_law_is_the_flat_bearing_test(radius):
    params, _ = interface_parameters("UF", 1000 * PSI, "P")
    bearing = paper_bearing(params)
    time = np.arange(0.0, 6.0 + 1e-9, 0.01)
    path = 0.05 * np.sin(2 * np.pi * time / 2.0) * np.minimum(time, 1.0)
    load = 1e6
    series = imposed_path_test(single_pendulum(bearing, radius=radius), sampled_path(time, path, load), friction_velocity="end")
    flat = np.asarray(imposed_path_test(bearing, sampled_path(time, path, load)).fx) + load * path / radius
    assert _relative(flat, np.asarray(series.force)) <= 1e-12
    mean = imposed_path_test(single_pendulum(bearing, radius=radius), sampled_path(time, path, load))
    assert _relative(flat, np.asarray(mean.force)) > 1e-3  # the mean speed lags the path's


def test_a_flat_bearing_becomes_one_surface_with_all_its_parts():
    params, ratio = interface_parameters("UF", 1000 * PSI, "P")
    bearing = dataclasses.replace(paper_bearing(params, breakaway_ratio=ratio), wear=Wear(change=-0.3,
                                                                                          reference_travel=1.0))
    surface = single_pendulum(bearing, radius=2.0, capacity=0.3)
    assert surface.surface_parts == (SurfaceParts(breakaway_ratio=bearing.breakaway_ratio, wear=bearing.wear),)
    assert surface.remembers and surface.slider_count == 1
    assert float(surface.reference_radius()) == 2.0 and float(surface.series_capacities()[0]) == 0.3
    plain = single_pendulum(paper_bearing(params))
    assert plain.surface_parts is None and np.isinf(plain.series_capacities()[0])
    check_single_pendulum(plain)  # R = inf, a flat slider
    with pytest.raises(ValueError, match="n_interfaces"):
        single_pendulum(paper_bearing(params, n_interfaces=2))
    with pytest.raises(ValueError, match="backlash"):
        single_pendulum(dataclasses.replace(paper_bearing(params), backlash=Backlash(gap=1e-3)))
    with pytest.raises(ValueError, match="surface_radius"):
        check_single_pendulum(SinglePendulum(surface_radius=0.0, surface_friction=params,
                                             hysteresis=BoucWen(1e-4)))
    with pytest.raises(ValueError, match="surface_capacity"):
        check_single_pendulum(SinglePendulum(surface_radius=2.0, surface_friction=params,
                                             hysteresis=BoucWen(1e-4), surface_capacity=-0.1))


@pytest.mark.slow
def test_the_one_surface_peak_has_the_flat_engines_gradient():
    # the bracketed balance is differentiated implicitly: d(final displacement)/d(f_max)
    params, _ = interface_parameters("UF", 1000 * PSI, "P")
    builder = isolated_structure("rigid", isolator=concave_surface(RADIUS), split_at_turn=False,
                                 time_step=0.005, newton_tolerance=0.0)
    ground = _ground(4)

    def flat_end(f_max):
        system = builder(ground, {"f_max": f_max})
        return simulate_history(system, 3.0).displacement[-1, 0]

    def series_end(f_max):
        system = builder(ground, {"f_max": f_max})
        series = structure_on_isolator(system, single_pendulum(system.bearing, radius=RADIUS),
                                       friction_velocity="end", newton_tolerance=1e-13)
        return simulate_history(series, 3.0).displacement[-1, 0]

    f_max = float(params.f_max)
    flat_slope = float(jax.grad(flat_end)(f_max))
    series_slope = float(jax.grad(series_end)(f_max))
    assert abs(flat_slope) > 1e-3
    assert abs(series_slope - flat_slope) <= 1e-6 * abs(flat_slope)
