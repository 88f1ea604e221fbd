"""The design space of each isolator (`teflon_jax.bearing.design_space`): its variables are
exactly those its isolated structure takes, the designed isolator follows each variable's
definition (T_b of the springs, T_b = 2 pi sqrt(R / g) of the surface, Table 1's Eq. 1 at
the pressure, the restrainer's capacity), a box whose low f_max lies below delta_f
(f_min = f_max - delta_f < 0 in Eq. 1) is refused by name, and `teflon-jax design` shows
and names every variable through one table.
References: Constantinou, Mokha & Reinhorn (1990), Eq. 1 and Table 1; Zayas, Low & Mahin (1990).
"""

import math

import jax.numpy as jnp
import pytest
from test_double_design import DOUBLE
from test_triple_design import TRIPLE

from teflon_jax.bearing import (
    DESIGN_SPACES,
    ISOLATORS,
    concave_surface,
    design_space,
    designed_isolator,
)
from teflon_jax.cli._common import output_units
from teflon_jax.cli._design_variables import (
    ISOLATOR_DESIGNS,
    VARIABLE_FLAGS,
    design_fields,
    design_text,
)
from teflon_jax.systems import isolated_structure
from teflon_jax.tables import friction_table
from teflon_jax.units import INCH, PSI, STANDARD_GRAVITY

SAMPLE = {"isolation_period": 3.0, "pressure": 2000 * PSI, "isolation_damping": 0.1, "f_max": 0.12,
          "delta_f": 0.05, "rate_a": 20.0, "breakaway_ratio": 1.2, "radius": 2.5, "capacity": 0.2,
          "outer_radius_scale": 1.2, "inner_f_max": 0.02, "outer_f_max": 0.07, "capacity_scale": 0.8,
          "radius_scale": 1.1, "surface_f_max": 0.04}
"""A value inside the admissible range of each design variable."""


def _structure(isolator):
    return {
        "flat": lambda: isolated_structure("rigid", pressure=1000 * PSI, isolation_period=2.5),
        "single-fp": lambda: isolated_structure("rigid", isolator=concave_surface(
            2.0, displacement_capacity=0.1, restrainer_stiffness=1e6)),
        "triple-fp": lambda: isolated_structure("rigid", isolator=TRIPLE),
        "double-fp": lambda: isolated_structure("rigid", isolator=DOUBLE),
    }[isolator]()


def test_every_isolator_has_one_space():
    assert tuple(DESIGN_SPACES) == tuple(ISOLATORS) == tuple(ISOLATOR_DESIGNS)  # the command's row of each
    with pytest.raises(ValueError, match="isolator: unknown 'quad-fp'; accepted: flat, single-fp"):
        design_space("quad-fp")


@pytest.mark.parametrize("isolator", ISOLATORS)
def test_a_space_holds_exactly_the_variables_its_structure_takes(isolator):
    structure, space = _structure(isolator), design_space(isolator)
    ranges = space.ranges(structure)
    assert tuple(ranges) == space.variables
    ground = jnp.zeros(8)
    for name in space.variables:
        lo, hi = ranges[name]
        assert lo <= SAMPLE[name] <= hi, name
        structure(ground, {name: SAMPLE[name]})  # the structure takes it
        designed_isolator(structure, {name: SAMPLE[name]})
    for name in {n for s in DESIGN_SPACES.values() for n in s.variables} - set(space.variables):
        with pytest.raises(ValueError):
            structure(ground, {name: SAMPLE[name]})
        with pytest.raises(ValueError, match=f"unknown variable '{name}' for the {isolator} isolator"):
            space.check(structure, {name: (SAMPLE[name], 2 * SAMPLE[name])})
        with pytest.raises(ValueError, match=f"unknown variable.*'{name}'"):
            designed_isolator(structure, {name: SAMPLE[name]})


def test_the_designed_sliders_follow_each_variables_definition():
    bearing, period, damping = designed_isolator(_structure("flat"), {
        "isolation_period": 3.0, "pressure": 2000 * PSI, "isolation_damping": 0.1})
    assert (float(period), float(damping)) == (3.0, 0.1)
    table, _ = friction_table("UF", "P").at(2000 * PSI)  # Eq. 1's constants of Table 1 there
    assert float(bearing.friction.f_max) == pytest.approx(float(table.f_max), rel=1e-12)
    assert float(bearing.friction.delta_f) == pytest.approx(float(table.delta_f), rel=1e-12)
    bearing, surface, damping = designed_isolator(_structure("single-fp"), {"radius": 2.5, "capacity": 0.2,
                                                                             "f_max": 0.12})
    assert (float(surface.radius), float(surface.displacement_capacity)) == (2.5, 0.2)
    assert float(surface.isolation_period()) == pytest.approx(2 * math.pi * math.sqrt(2.5 / STANDARD_GRAVITY),
                                                              rel=1e-12)
    assert float(bearing.friction.f_max) == 0.12 and float(damping) == 0.0


def test_a_box_whose_f_max_falls_below_delta_f_is_refused():
    """Eq. 1: f_min = f_max - delta_f must stay >= 0 at every corner of the box."""
    flat, space = _structure("flat"), design_space("flat")
    delta_f = float(designed_isolator(flat, {})[0].friction.delta_f)
    space.check(flat, {"f_max": (delta_f, 0.3)})  # f_min = 0 at the low corner
    with pytest.raises(ValueError, match=r"f_max: the low end .* lies below delta_f = "):
        space.check(flat, {"f_max": (0.999 * delta_f, 0.3)})
    with pytest.raises(ValueError, match="f_max: the low end"):  # delta_f designed up to above it
        space.check(flat, {"f_max": (delta_f, 0.3), "delta_f": (0.0, 1.01 * delta_f)})
    ends = {p: float(designed_isolator(flat, {"pressure": p})[0].friction.delta_f) for p in (1000 * PSI, 2000 * PSI)}
    low_end = min(ends, key=ends.get)  # the structure at the pressure of the smaller delta_f
    assert ends[low_end] < max(ends.values())
    at_low = isolated_structure("rigid", pressure=low_end, isolation_period=2.5)
    with pytest.raises(ValueError, match="f_max: the low end"):  # below delta_f at the box's other pressure
        space.check(at_low, {"f_max": (ends[low_end], 0.3), "pressure": (1000 * PSI, 2000 * PSI)})


def test_each_range_flag_names_the_isolators_whose_space_holds_its_variable():
    owners = {name: [i for i in ISOLATORS if name in design_space(i).variables] for name in VARIABLE_FLAGS}
    for name, spec in VARIABLE_FLAGS.items():
        assert owners[name] and spec.help.startswith(f"--isolator {' or '.join(owners[name])}:"), spec.flag


def test_a_design_point_is_shown_in_the_units_of_each_variable():
    us, si = output_units("us"), output_units("si")
    period = 2 * math.pi * math.sqrt(40 * INCH / STANDARD_GRAVITY)
    assert design_fields({"radius": 40 * INCH, "capacity": 2 * INCH, "f_max": 0.1}, us) == pytest.approx(
        {"radius_in": 40.0, "isolation_period_s": period, "capacity_in": 2.0, "f_max": 0.1}, rel=1e-12)
    assert design_fields({"isolation_period": 2.5, "pressure": 2000 * PSI}, si) == pytest.approx(
        {"isolation_period_s": 2.5, "pressure_MPa": 2000 * PSI / 1e6}, rel=1e-12)
    assert design_text({"radius": 40 * INCH, "capacity": 2 * INCH, "f_max": 0.1}, us) == (
        f"R = 40 in (Tb = {period:.4g} s), d = 2 in, f_max = 0.1")
    assert design_text({"outer_f_max": 0.061234, "capacity_scale": 0.5}, si) == (
        "outer_f_max = 0.061234, capacity_scale = 0.5")
