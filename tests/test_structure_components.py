"""One builder per structure for one or two horizontal components: `structure_on_sliders`,
`rigid_mass` and `six_storey_building` take the number of components (an argument, or read
from the influence R (N, C) and bearing map B (G, C, N)) and refuse by name the options the
other count alone takes."""

import jax
import numpy as np
import pytest

from teflon_jax.bearing import paper_bearing
from teflon_jax.excitation import uniform_signal
from teflon_jax.systems import (
    StructureOnSliders,
    rigid_mass,
    six_storey_building,
    structure_on_sliders,
)
from teflon_jax.tables import interface_parameters
from teflon_jax.units import PSI

BEARING = paper_bearing(interface_parameters("UF", 1000 * PSI)[0])
GROUND = uniform_signal(np.sin(np.linspace(0.0, 6.0, 101)), 0.01)
ACROSS = uniform_signal(0.5 * np.cos(np.linspace(0.0, 6.0, 101)), 0.01)


def _leaves_equal(a, b):
    one, two = jax.tree_util.tree_leaves(a), jax.tree_util.tree_leaves(b)
    return len(one) == len(two) and all(np.array_equal(np.asarray(x), np.asarray(y)) for x, y in zip(one, two))


@pytest.mark.parametrize("build", [rigid_mass, six_storey_building])
def test_the_number_of_components_chooses_the_step(build):
    """One component (the default) gives the scalar isolator's system, two (asked for or read
    from a y record) the planar one; a y record is the same as `components=2` with it."""
    common = dict(bearing=BEARING, ground_acceleration=GROUND, time_step=0.005, isolation_period=2.0,
                  **({"weight": 1e5} if build is rigid_mass else {}))
    assert isinstance(build(**common), StructureOnSliders) and not build(**common).planar
    asked = build(**common, components=2, ground_y=ACROSS)
    read = build(**common, ground_y=ACROSS)
    assert asked.planar and asked.mass.shape == (2 * build(**common).mass.shape[0],)
    assert _leaves_equal(asked, read)
    still = build(**common, components=2)  # no y record: the y ground is at rest
    assert np.all(np.asarray(still.ground_y.values) == 0.0)


def test_the_general_builder_reads_two_components_from_the_influence_and_bearing_map():
    """`structure_on_sliders` with R (N, 2) and B (1, 2, N) of the rigid mass in the plane is the
    rigid mass built with `components=2`, leaf for leaf."""
    plane = rigid_mass(weight=1e5, bearing=BEARING, ground_acceleration=GROUND, ground_y=ACROSS, time_step=0.005,
                       isolation_period=2.0)
    built = structure_on_sliders(mass=plane.mass, stiffness=plane.stiffness, damping=plane.damping,
                                 influence=np.eye(2), bearing_map=np.eye(2)[None], bearing=BEARING,
                                 bearing_load=plane.bearing_load, ground_acceleration=GROUND, ground_y=ACROSS,
                                 time_step=0.005)
    assert built.planar
    assert _leaves_equal(built, plane)


@pytest.mark.parametrize(("build", "options", "name"), [
    (rigid_mass, {"components": 1, "ground_y": ACROSS}, "ground_y"),
    (rigid_mass, {"components": 3}, "components"),
    (rigid_mass, {"components": 2, "radius": 2.0}, "radius"),
    (rigid_mass, {"components": 2, "linear_rule": "exact"}, "linear_rule"),
    (six_storey_building, {"isolation_period_y": 2.5}, "isolation_period_y"),
    (six_storey_building, {"ground_y": ACROSS, "linear_rule": "exact"}, "linear_rule"),
])
def test_an_option_of_the_other_count_is_refused_by_name(build, options, name):
    with pytest.raises(ValueError, match=f"^{name}:"):
        build(bearing=BEARING, ground_acceleration=GROUND, time_step=0.005, isolation_period=2.0, **options,
              **({"weight": 1e5} if build is rigid_mass else {}))


@pytest.mark.parametrize(("options", "name"), [
    ({"ground_y": ACROSS}, "ground_y"),
    ({"influence": np.eye(2)}, "bearing_map"),
    ({"influence": np.eye(2), "bearing_map": np.eye(2)[None], "split_at_turn": True}, "split_at_turn"),
])
def test_the_general_builder_refuses_half_a_two_component_structure(options, name):
    with pytest.raises(ValueError, match=f"^{name}:"):
        structure_on_sliders(mass=np.ones(2), stiffness=np.eye(2), damping=np.zeros((2, 2)), bearing=BEARING,
                             bearing_load=1e5, ground_acceleration=GROUND, time_step=0.005, **options)
