"""The command line's one reading of the isolator (`read_isolator`), its one check of what cannot
run together (`check_combination`), the slab groups' isolators (`slab_isolators`), and the one
flow of `run`: every isolator on every structure, under one or two components, builds a system
whose type the response table knows."""

import json
import pathlib
import re

import numpy as np
import pytest

from teflon_jax.bearing import isolator_kind
from teflon_jax.cli._isolator_flags import (
    ISOLATORS,
    check_combination,
    read_isolator,
    slab_isolators,
)
from teflon_jax.cli._main import _parser
from teflon_jax.cli._plan_file import read_plan
from teflon_jax.units import INCH, STANDARD_GRAVITY

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "benchmarks"
FILES = {"triple-fp": EXAMPLES / "triple_isolator.json", "double-fp": EXAMPLES / "double_isolator.json"}
FLAGS = {"flat": [], "single-fp": ["--radius", "88in"],
         **{name: ["--isolator-file", str(path)] for name, path in FILES.items()}}


def _args(command, *flags):
    from teflon_jax.cli._common import read_quantities

    args = _parser(only=command).parse_args([command, *flags])
    read_quantities(args, command)
    return args


def _plan(tmp_path, **group_keys):
    groups = [{"name": n, "x": f"{x}m", "y": f"{y}m", "load": "250kN"}
              for n, (x, y) in zip(("SW", "SE", "NE", "NW"), ((0, 0), (20, 0), (20, 12), (0, 12)))]
    groups[1].update(group_keys)
    path = tmp_path / "plan.json"
    path.write_text(json.dumps({"length_x": "20m", "length_y": "12m", "weight": "1000kN", "groups": groups}))
    return path


@pytest.mark.parametrize("isolator", ISOLATORS)
def test_each_isolator_is_one_value(isolator):
    """The flags become the isolator's geometry and friction: the pendulum's period is 2 pi
    sqrt(R / g), a series pendulum is its file's, and the structure builders' keywords name it."""
    value = read_isolator(_args("run", "--isolator", isolator, *FLAGS[isolator]))
    assert value.name == isolator and value.restores == (isolator != "flat")
    options = value.structure_options()
    assert list(options) == ["isolator"] and isolator_kind(options["isolator"]) == isolator
    if isolator == "single-fp":
        assert value.period == pytest.approx(2 * np.pi * np.sqrt(88 * INCH / STANDARD_GRAVITY), rel=1e-12)
        assert options["isolator"].radius == pytest.approx(88 * INCH, rel=1e-12)
    else:
        assert value.period is None
    if isolator in FILES:
        assert value.pendulum.isolator == isolator and value.file == FILES[isolator]
        assert options["isolator"] is value.pendulum


@pytest.mark.parametrize(("flags", "message"), [
    (["--structure", "building"], "--isolation-period: the building needs its springs"),
    (["--structure", "slab"], "--plan: --structure slab needs a plan file"),
    (["--plan", "plan.json"], "--plan: stands a slab (--structure slab) or the Table 2 building (--structure "
                              "building) on bearing groups; not the rigid mass."),
    (["--structure", "building", "--plan", "plan.json"], "--isolation-period: the building needs its springs"),
])
@pytest.mark.parametrize("isolator", ISOLATORS)
def test_what_cannot_run_is_refused_by_name(isolator, flags, message):
    """Only flat sliders need springs under the building, on a plan too; a plan goes with the slab
    or the building, whatever the isolator."""
    args = _args("run", "--isolator", isolator, *FLAGS[isolator], *flags)
    if message.startswith("--isolation-period") and isolator != "flat":
        check_combination(args, read_isolator(args))  # a pendulum restores the building itself, on a plan too
        return
    with pytest.raises(ValueError, match=re.escape(message)):
        check_combination(args, read_isolator(args))


@pytest.mark.parametrize(("isolator", "components", "message"), [
    ("triple-fp", 1, "--newton-tolerance: is in units of a flat bearing's yield displacement; the triple-fp"),
    ("double-fp", 2, "--newton-tolerance: is in units of a flat bearing's yield displacement; the double-fp"),
])
def test_montecarlo_newton_tolerance_only_where_it_means_something(isolator, components, message):
    args = _args("montecarlo", "--motions", "2", "--isolator", isolator, *FLAGS[isolator],
                 "--components", str(components), "--newton-tolerance", "1e-3")
    with pytest.raises(ValueError, match=re.escape(message)):
        check_combination(args, read_isolator(args))
    for components in ("1", "2"):  # flat sliders, one or two components
        args = _args("montecarlo", "--motions", "2", "--components", components, "--newton-tolerance", "1e-3")
        check_combination(args, read_isolator(args))


@pytest.mark.parametrize(("isolator", "group", "message"), [
    ("flat", {"radius": "60in"}, "SE.radius applies with --isolator single-fp only"),
    ("flat", {"isolator_file": "tfp.json"}, "SE.isolator_file applies with --isolator triple-fp or double-fp only, not flat"),
    ("single-fp", {"springs": 2.0}, "SE.springs conflicts with --isolator single-fp"),
    ("single-fp", {"isolator_file": "tfp.json"}, "not single-fp"),
    ("triple-fp", {"radius": "60in"}, "SE.radius does not apply to --isolator triple-fp"),
    ("double-fp", {"pressure": "2000psi"}, "SE.pressure does not apply to --isolator double-fp"),
])
def test_a_groups_keys_that_its_isolator_does_not_take(tmp_path, isolator, group, message):
    args = _args("run", "--structure", "slab", "--plan", str(_plan(tmp_path, **group)), "--isolator", isolator,
                 *FLAGS[isolator])
    with pytest.raises(ValueError, match=re.escape(message)):
        slab_isolators(args, read_isolator(args), read_plan(args.plan), 2.5)


def test_each_group_takes_its_own_radius_or_isolator_file(tmp_path):
    args = _args("run", "--structure", "slab", "--plan", str(_plan(tmp_path, radius="60in")), "--isolator",
                 "single-fp", "--radius", "88in")
    plan = read_plan(args.plan)
    assert slab_isolators(args, read_isolator(args), plan)["radii"] == pytest.approx(
        [88 * INCH, 60 * INCH, 88 * INCH, 88 * INCH], rel=1e-15)
    (tmp_path / "dfp.json").write_text(FILES["double-fp"].read_text().replace('"value": 2.1', '"value": 2.5'))
    args = _args("run", "--structure", "slab", "--plan", str(_plan(tmp_path, isolator_file="dfp.json")),
                 "--isolator", "double-fp", "--isolator-file", str(FILES["double-fp"]))
    plan = read_plan(args.plan)
    pendulums = slab_isolators(args, read_isolator(args), plan)["pendulums"]
    radii = [float(p.reference_radius()) for p in pendulums]
    assert radii[0] == radii[2] == radii[3] != radii[1]
    assert plan["isolator_files"][1].endswith("dfp.json") and plan["isolator_files"][0] == str(FILES["double-fp"])
    args = _args("run", "--structure", "slab", "--plan", str(_plan(tmp_path)), "--isolation-period", "2.5s")
    assert slab_isolators(args, read_isolator(args), read_plan(args.plan), 2.5) == {
        "isolation_period": 2.5, "spring_shares": [1.0] * 4}


@pytest.mark.parametrize("structure", ("rigid", "building", "slab"))
@pytest.mark.parametrize("isolator", ISOLATORS)
def test_every_combination_runs_through_the_one_flow(tmp_path, isolator, structure):
    """Every isolator on every structure, under one or two components, builds a system whose
    type the one history driver steps (its layout read), and a suite's pair can replace its ground."""
    from teflon_jax.cli._run_structure import build_structure, read_structure
    from teflon_jax.excitation import uniform_signal
    from teflon_jax.systems import (
        StructureOnSliders,
        response_layout,
        under_ground,
    )

    flags = ["--structure", structure, "--isolator", isolator, *FLAGS[isolator]]
    flags += ["--plan", str(_plan(tmp_path))] if structure == "slab" else []
    flags += ["--isolation-period", "2.5s"] if isolator == "flat" else []
    args = _args("run", *flags)
    value = read_isolator(args)
    check_combination(args, value)
    settings = read_structure(args, value)
    ground = uniform_signal(np.zeros(11), 0.01)
    for two in (False, True):
        system = build_structure(args, value, settings, ground, ground, two=two)
        assert isinstance(system, StructureOnSliders)
        response_layout(system)  # a structure the drivers read (TypeError otherwise)
    moved = under_ground(system, uniform_signal(np.ones(11), 0.01), ground)
    assert type(moved) is type(system)
    assert np.asarray(moved.ground(0.05))[0] == 1.0  # the pair's x component, not the built one's
