"""One isolator value picks the structure's engine: its type says the isolator
(`isolator_kind`), one surface (flat sliders, the single friction pendulum, a `SinglePendulum`)
runs on the flat sliders' engine and S > 1 sliders in series on the series engine
(`runs_in_series`). The rigid mass and the building hold the value's parts; a plan's values
build the same structure, leaf for leaf, as the isolator named with its parts apart, for the
slab and the building on a plan; what contradicts the value is refused by name."""

import pathlib

import jax
import numpy as np
import pytest

from teflon_jax.bearing import (
    FrictionParameters,
    concave_surface,
    isolator_kind,
    one_surface,
    paper_bearing,
    runs_in_series,
    single_pendulum,
)
from teflon_jax.cli._isolator_flags import Isolator
from teflon_jax.excitation import uniform_signal
from teflon_jax.formats import load_isolator
from teflon_jax.studies import bidirectional_isolated_structure
from teflon_jax.systems import (
    IsolatedStructure,
    building_on_plan,
    isolated_structure,
    simulate_history,
    slab_on_bearings,
)
from teflon_jax.tables import interface_parameters, load_table2
from teflon_jax.units import PSI, STANDARD_GRAVITY

REPO = pathlib.Path(__file__).resolve().parent.parent

TRIPLE = load_isolator(REPO / "benchmarks" / "triple_isolator.json")
DOUBLE = load_isolator(REPO / "benchmarks" / "double_isolator.json")
BEARING = paper_bearing(interface_parameters("UF", 1000 * PSI)[0], breakaway_ratio=1.4)
RADIUS = 2.2
TIME = np.arange(0.0, 4.0 + 1e-9, 0.01)
GROUND = uniform_signal(0.4 * STANDARD_GRAVITY * np.sin(2 * np.pi * 0.6 * TIME) * np.sin(np.pi * TIME / 4.0), 0.01)


def _same(a, b) -> bool:
    """Whether two pytrees have one structure and bit-identical leaves."""
    if jax.tree_util.tree_structure(a) != jax.tree_util.tree_structure(b):
        return False
    return all(np.array_equal(np.asarray(x), np.asarray(y))
               for x, y in zip(jax.tree_util.tree_leaves(a), jax.tree_util.tree_leaves(b)))


def test_the_type_of_the_value_names_the_isolator_and_its_engine():
    surface = concave_surface(RADIUS)
    cases = [(None, "flat", False), (BEARING, "flat", False), (surface, "single-fp", False),
             ((BEARING, surface), "single-fp", False), (single_pendulum(BEARING), "flat", False),
             (single_pendulum(BEARING, radius=RADIUS), "single-fp", False),
             (TRIPLE, "triple-fp", True), (DOUBLE, "double-fp", True)]
    for value, name, series in cases:
        assert isolator_kind(value) == name and runs_in_series(value) == series
    for wrong in ("flat", 2.0, (surface, BEARING), [BEARING]):
        with pytest.raises(ValueError, match="isolator: expected None .*, a SlidingBearing"):
            isolator_kind(wrong)


@pytest.mark.parametrize("kind", ["rigid", "building"])
def test_the_structure_holds_the_values_parts_on_its_engine(kind):
    surface = concave_surface(RADIUS)
    for value, parts in ((None, (None, None)), (BEARING, (BEARING, None)), (surface, (None, surface)),
                         ((BEARING, surface), (BEARING, surface))):
        built = isolated_structure(kind, isolator=value)
        assert type(built) is IsolatedStructure and _same((built.bearing, built.surface), parts), value
        assert built.isolator == isolator_kind(value)
    assert _same(isolated_structure(kind, bearing=BEARING), isolated_structure(kind, isolator=BEARING))
    for step in (0.0, True):  # one time-step check for every isolator
        for value in (None, TRIPLE):
            with pytest.raises(ValueError, match="time_step: must be a positive number"):
                isolated_structure(kind, isolator=value, time_step=step)
    for pendulum in (TRIPLE, DOUBLE):
        for build, components in ((isolated_structure, 1), (bidirectional_isolated_structure, 2)):
            built = build(kind, isolator=pendulum)
            assert type(built) is IsolatedStructure and built.pendulum is pendulum
            assert built.components == components and built.isolator == isolator_kind(pendulum)
        for bad in ({"newton_iterations": 0}, {"newton_tolerance": -1.0},  # checked as on flat sliders
                    {"pressure": 2e7}, {"ptfe": "PTFE"}, {"breakaway": False}, {"linear_rule": "newmark"}):  # refused
            with pytest.raises(ValueError, match=next(iter(bad))):
                isolated_structure(kind, isolator=pendulum, **bad)


def test_a_single_pendulum_runs_on_the_flat_engine_with_its_bearings_numbers():
    """`single_pendulum(bearing, radius=R)` is (bearing, concave_surface(R)) on the flat
    sliders' engine: the same structure and the same history, bit for bit (R = inf: flat)."""
    for radius, alone in ((RADIUS, (BEARING, concave_surface(RADIUS))), (np.inf, BEARING)):
        options = dict(isolation_period=None) if np.isfinite(radius) else {}
        structure = isolated_structure("rigid", isolator=single_pendulum(BEARING, radius=radius), **options)
        assert type(structure) is IsolatedStructure
        expected = isolated_structure("rigid", isolator=alone, **options)
        assert _same(structure, expected)
        history = simulate_history(structure(GROUND), 4.0).displacement
        assert np.array_equal(history, simulate_history(expected(GROUND), 4.0).displacement)
        assert np.max(np.abs(history)) > 1e-3  # it slides
    assert _same(one_surface(single_pendulum(BEARING, radius=RADIUS))[0], BEARING)


@pytest.mark.parametrize(("options", "message"), [
    (dict(isolator=TRIPLE, bearing=BEARING), r"bearing: the isolator value \(TriplePendulum\) carries the whole isolator"),
    (dict(isolator=BEARING, bearing=BEARING), r"bearing: the isolator value \(SlidingBearing\)"),
    (dict(bearing=TRIPLE), "bearing: expected a SlidingBearing, got a TriplePendulum"),
    (dict(isolator=DOUBLE, isolation_period=2.5), r"isolation_period: does not apply to the double-fp isolator"),
    (dict(isolator=TRIPLE, friction_model="coulomb"), r"friction_model: does not apply to the triple-fp isolator"),
    (dict(isolator=concave_surface(RADIUS), isolation_period=2.5), "isolation_period: the single-fp isolator's period"),
    (dict(isolator=single_pendulum(BEARING, radius=RADIUS, capacity=0.2)), "isolator: the SinglePendulum's surface_capacity"),
    (dict(isolator=3.0), "isolator: expected None"),
    (dict(isolator="single-fp"), "isolator: expected None .*; got 'single-fp'"),
])
def test_what_contradicts_the_isolator_is_refused_by_name(options, message):
    with pytest.raises(ValueError, match=message):
        isolated_structure("rigid", **options)


@pytest.mark.parametrize(("options", "named"), [
    (dict(split_at_turn=False), "split_at_turn"),
    (dict(linear_rule="newmark"), "linear_rule"),
    (dict(isolator=concave_surface(RADIUS), split_at_turn=False, linear_rule="newmark"), "split_at_turn, linear_rule"),
])
def test_settings_of_one_component_are_refused_under_two_by_name(options, named):
    assert isolated_structure("rigid", **options)(GROUND) is not None  # one component takes them
    with pytest.raises(ValueError, match=f"^{named}: a setting of one horizontal component"):
        bidirectional_isolated_structure("rigid", **options)
    series = bidirectional_isolated_structure("rigid", isolator=DOUBLE)  # refused there under one already
    assert series.components == 2 and series.split_at_turn


def _plan(build, **isolator):
    """The slab (with overturning) or the building on four groups at the corners of a plan."""
    corners = np.array([[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]])
    if build is slab_on_bearings:
        size = dict(weight=1e6, loads=[2.6e5, 2.4e5, 2.4e5, 2.6e5], height_of_centre_of_mass=3.0)
    else:
        size = dict(loads=[float(load_table2().total_weight) / 4] * 4)
    return build(length_x=20.0, length_y=12.0, centre_of_mass=(10.0, 6.0), positions=corners, ground_acceleration=GROUND,
                 ground_y=GROUND, time_step=0.005, **size, **isolator)


@pytest.mark.parametrize("build", [slab_on_bearings, building_on_plan])
def test_a_plans_values_build_the_named_isolators_structure(build):
    other = paper_bearing(FrictionParameters(0.1, 0.05, 25.0), yield_disp=2e-4, breakaway_ratio=1.2)
    groups = [BEARING, other, BEARING, other]
    radii = [2.0, 2.5, 2.0, 3.0]
    pairs = [(dict(isolator=groups, isolation_period=2.5), dict(bearings=groups, isolation_period=2.5)),
             (dict(isolator=BEARING, isolation_period=2.5), dict(isolator="flat", bearings=BEARING, isolation_period=2.5)),
             (dict(isolator=[(b, concave_surface(r)) for b, r in zip(groups, radii)]),
              dict(isolator="single-fp", bearings=groups, radii=radii))]
    pairs.append((dict(isolator=TRIPLE), dict(isolator="triple-fp", pendulums=TRIPLE)))
    for value, named in pairs:
        assert _same(_plan(build, **value), _plan(build, **named)), (value, named)


def test_a_plans_bad_isolator_is_refused_by_name():
    with pytest.raises(ValueError, match=r"isolator: the groups stand on one isolator, got flat, single-fp"):
        _plan(slab_on_bearings, isolator=[BEARING, BEARING, (BEARING, concave_surface(2.0)), BEARING])
    with pytest.raises(ValueError, match=r"isolator: 2 given for 4 groups"):
        _plan(slab_on_bearings, isolator=[BEARING, BEARING], isolation_period=2.5)
    with pytest.raises(ValueError, match=r"radii: the isolator value carries the groups' isolators"):
        _plan(slab_on_bearings, isolator=BEARING, radii=2.0)
    with pytest.raises(ValueError, match=r"isolator \(group 1\): a plan's pendulums restore with W_g / R_g"):
        _plan(slab_on_bearings, isolator=(BEARING, concave_surface(2.0, displacement_capacity=0.2,
                                                                      restrainer_stiffness=1e6)))
    with pytest.raises(ValueError, match=r"isolation_period: does not apply to isolator 'double-fp'"):
        _plan(building_on_plan, isolator=DOUBLE, isolation_period=2.5)


def test_the_command_lines_isolator_hands_over_its_value():
    surface = concave_surface(RADIUS)
    assert Isolator("flat").structure_options() == {"isolator": None}
    assert Isolator("flat", bearing=BEARING).value is BEARING
    assert _same(Isolator("single-fp", radius=RADIUS).value, surface)
    assert _same(Isolator("single-fp", radius=RADIUS, bearing=BEARING).value, (BEARING, surface))
    assert Isolator("triple-fp", pendulum=TRIPLE).value is TRIPLE
    assert Isolator("double-fp", pendulum=DOUBLE).structure_options() == {"isolator": DOUBLE}
