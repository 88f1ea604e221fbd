"""`teflon-jax montecarlo --plan FILE`: the slab or the Table 2 building on a plan of bearing
groups, built once and run under every stochastic motion (`studies.BuiltStructure`).

Peers: the rigid mass of the same bearings (a slab whose mass sits over the centre of a
symmetric plan, at no height, moves as the rigid mass: Park's Z and the springs act on the
whole weight alike), and each motion's own run of the building on the plan (`peak_response`)
for the groups' normal loads."""

import csv
import json
import pathlib

import jax
import numpy as np
import pytest

from teflon_jax.cli._main import main
from teflon_jax.excitation import uniform_signal
from teflon_jax.studies import MonteCarloResult, monte_carlo_motion
from teflon_jax.systems import peak_response, under_ground

DOUBLE = pathlib.Path(__file__).resolve().parents[1] / "benchmarks" / "double_isolator.json"
CORNERS = (("SW", "1m", "1m"), ("SE", "19m", "1m"), ("NE", "19m", "11m"), ("NW", "1m", "11m"))
MOTIONS = ("--motions", "3", "--duration", "6s", "--strong-motion", "3s", "--pga", "0.5g", "--seed", "2",
           "--no-progress")


def _plan(path, weight, load, centre=("10m", "6m"), names=None):
    groups = [{"name": n, "x": x, "y": y, "load": load}
              for n, (_, x, y) in zip(names or [c[0] for c in CORNERS], CORNERS)]
    path.write_text(json.dumps({"length_x": "20m", "length_y": "12m", "weight": weight, "centre_of_mass": list(centre),
                                "groups": groups}))
    return path


@pytest.mark.parametrize("isolator", [
    (),
    pytest.param(("--isolator", "double-fp", "--isolator-file", DOUBLE), marks=pytest.mark.slow),
], ids=["flat", "double-fp"])
def test_bound_cases_on_a_symmetric_plan_are_those_of_the_rigid_mass(tmp_path, capsys, isolator):
    """--property-factors on the slab over the centre of a symmetric plan: each case scales every
    group's friction (`BuiltStructure` takes the factor), and each case's peaks equal the rigid
    mass's bound cases, whose bearings take the scaled constants as design variables (flat
    sliders: f_max and delta_f of Table 1's row; a double pendulum: every surface's), to 1e-8,
    at the same step (a plan's default is `run --plan`'s 2.5 ms, a series pendulum's own 5 ms);
    the upper case moves the peaks."""
    common = (*MOTIONS, "--components", "2", "--property-factors", "0.8,1.3", "--time-step", "2.5ms", *isolator)
    springs = () if isolator else ("--isolation-period", "2.5s")
    code, out = _montecarlo(capsys, *common, *springs, "--out", tmp_path / "rigid.nc", "--json", tmp_path / "rigid.json")
    assert code == 0, out.err
    plan = _plan(tmp_path / "slab.json", "1000kN", "250kN")
    code, out = _montecarlo(capsys, *common, *springs, "--structure", "slab", "--plan", plan,
                            "--out", tmp_path / "slab.nc", "--json", tmp_path / "slab.out.json")
    assert code == 0, out.err
    rigid, slab = MonteCarloResult.open(tmp_path / "rigid.nc"), MonteCarloResult.open(tmp_path / "slab.nc")
    assert slab.dims == ("design", "motion") and slab.converged.all()
    for name in ("base_disp", "base_shear_ratio"):
        np.testing.assert_allclose(getattr(slab, name), getattr(rigid, name), rtol=1e-8, err_msg=name)
    assert np.min(np.abs(slab.base_shear_ratio[1] / slab.base_shear_ratio[0] - 1)) > 0.02
    cases = json.loads((tmp_path / "slab.out.json").read_text())["cases"]
    assert [cases[c]["friction_factor"] for c in ("nominal", "upper", "lower")] == [1.0, 1.3, 0.8]


def _montecarlo(capsys, *argv):
    code = main(["montecarlo", *map(str, argv)])
    return code, capsys.readouterr()


def test_a_slab_over_the_centre_of_a_symmetric_plan_is_the_rigid_mass(tmp_path, capsys):
    """Four equal groups at the corners, the mass over the centre and no height: every motion's
    peak displacement and base shear equal the rigid mass's on the same bearings, springs and
    dampers (to 1e-9), and no group load is reported, as the groups share the weight evenly."""
    spring = ("--isolation-period", "2.5s", "--isolation-damping", "3%", "--components", "2")
    code, _ = _montecarlo(capsys, *MOTIONS, *spring, "--out", tmp_path / "rigid.nc")
    assert code == 0
    plan = _plan(tmp_path / "slab.json", "1000kN", "250kN")
    code, out = _montecarlo(capsys, *MOTIONS, *spring, "--structure", "slab", "--plan", plan,
                            "--out", tmp_path / "slab.nc", "--json", tmp_path / "slab.out.json")
    assert code == 0, out.err
    rigid, slab = MonteCarloResult.open(tmp_path / "rigid.nc"), MonteCarloResult.open(tmp_path / "slab.nc")
    assert slab.converged.all() and slab.base_disp.min() > 5e-3
    for name in ("base_disp", "base_shear_ratio", "smooth_base_disp"):
        np.testing.assert_allclose(getattr(slab, name), getattr(rigid, name), rtol=1e-9, err_msg=name)
    assert slab.group_peak_load is None and "groups" not in json.loads((tmp_path / "slab.out.json").read_text())


def test_the_building_on_a_plan_reports_each_groups_loads_as_its_own_run(tmp_path, capsys):
    """The Table 2 building on four corner groups, its mass off the plan's centre: each group's
    largest and least normal load and uplift time in the results file are those of the motion's
    own run of the same building (`peak_response`, to 1e-9), labelled by the plan's names (a
    name with a comma stays one CSV column); the JSON's statistics are those of the file; the
    loads swing about the static shares under the overturning of the levels' inertia forces."""
    names = ["SW", "SE", "NE, tower", "NW"]
    plan = _plan(tmp_path / "plan.json", "672kip", "168kip", centre=("11m", "6.5m"), names=names)
    common = (*MOTIONS, "--structure", "building", "--plan", plan, "--components", "2",
              "--isolation-period", "2.5s")
    code, out = _montecarlo(capsys, *common, "--out", tmp_path / "mc.nc", "--json", tmp_path / "mc.json")
    assert code == 0, out.err
    result = MonteCarloResult.open(tmp_path / "mc.nc")
    assert result.group_names == names and result.converged.all()

    from teflon_jax.cli._common import read_quantities
    from teflon_jax.cli._main import _parser
    from teflon_jax.cli._montecarlo import _check_flags, _motion_model, _structure
    from teflon_jax.excitation import TwoComponentGroundMotion

    args = _parser("montecarlo").parse_args(["montecarlo", *map(str, common)])
    read_quantities(args, "montecarlo")
    structure = _structure(args, _check_flags(args), True)
    model = TwoComponentGroundMotion(_motion_model(args), principal_angle=0.0, minor_ratio=1.0)
    motions = [np.asarray(monte_carlo_motion(model, jax.random.key(2), i)) for i in range(3)]
    for i, (ax, ay) in enumerate(motions):
        run = peak_response(under_ground(structure.system, uniform_signal(ax, 0.01), uniform_signal(ay, 0.01)), 6.0)
        loads = run["group_normal_load"]
        np.testing.assert_allclose(result.group_peak_load[i], loads["peak_N"], rtol=1e-9)
        np.testing.assert_allclose(result.group_min_load[i], loads["min_N"], rtol=1e-9)
        np.testing.assert_allclose(result.base_disp[i], run.base_disp, rtol=1e-9)
    static = 168 * 4448.2216152605
    assert (result.group_peak_load > 1.02 * static).all() and (result.group_min_load < 0.98 * static).all()
    summary = json.loads((tmp_path / "mc.json").read_text())
    tower = summary["groups"]["NE, tower"]
    kip = 4448.2216152605
    assert tower["peak_load"]["max"] == pytest.approx(result.group_peak_load[:, 2].max() / kip, rel=1e-12)
    assert tower["min_load"]["min"] == pytest.approx(result.group_min_load[:, 2].min() / kip, rel=1e-12)
    assert tower["n_uplifted"] == 0 and summary["units"]["group_load"] == "kip"
    result.save(tmp_path / "mc.csv")
    with open(tmp_path / "mc.csv") as handle:
        header = next(csv.reader(handle))
    assert "group_peak_load_N_NE, tower" in header


@pytest.mark.parametrize("flags, message", [
    (("--structure", "slab"), "--plan: the groups carry the slab in the plane, under both ground components; "
                              "add --components 2."),
    (("--structure", "rigid", "--components", "2"), "--plan: stands a slab (--structure slab) or the Table 2 "
                                                    "building (--structure building) on bearing groups; not the rigid"),
    (("--structure", "slab", "--components", "2", "--property-factors", "posterior"),
     "--property-factors posterior: takes each Eq. 1 constant of one bearing from its posterior, and the groups "
     "of --plan each run their own bearings; give LOWER,UPPER factors"),
    (("--structure", "slab", "--components", "2", "--property-factors", "0.9,9"),
     "--property-factors 0.9,9: upper: 9 times the bearings' largest f_max 0.1193 is 1.074, above 1; take "
     "upper <= 8.382."),
    (("--structure", "slab", "--components", "2", "--bearing-draws", "motion"),
     "--bearing-draws: varies the bearings of a structure rebuilt for each run"),
], ids=["one-component", "rigid", "posterior-bounds", "upper", "draws"])
def test_what_a_structure_on_a_plan_cannot_take_is_refused_by_name(tmp_path, capsys, flags, message):
    """Each before any motion is drawn, and nothing is written."""
    plan = _plan(tmp_path / "slab.json", "1000kN", "250kN")
    code, out = _montecarlo(capsys, "--motions", "2", "--plan", plan, *flags, "--json", tmp_path / "out.json")
    assert code == 2 and message in out.err
    assert not (tmp_path / "out.json").exists()


@pytest.mark.slow
def test_bound_cases_of_the_building_on_a_plan_report_each_cases_group_loads(tmp_path, capsys):
    """--property-factors on the building on an eccentric plan: the upper case's peaks and group
    loads are each motion's own run with every group's friction times 1.3
    (`BuiltStructure.with_friction_factor`), and the JSON's groups per case are the file's."""
    plan = _plan(tmp_path / "plan.json", "672kip", "168kip", centre=("11m", "6.5m"))
    common = (*MOTIONS, "--structure", "building", "--plan", plan, "--components", "2",
              "--isolation-period", "2.5s", "--property-factors", "0.8,1.3")
    code, out = _montecarlo(capsys, *common, "--out", tmp_path / "mc.nc", "--json", tmp_path / "mc.json")
    assert code == 0, out.err
    result = MonteCarloResult.open(tmp_path / "mc.nc")

    from teflon_jax.cli._common import read_quantities
    from teflon_jax.cli._main import _parser
    from teflon_jax.cli._montecarlo import _check_flags, _motion_model, _structure
    from teflon_jax.excitation import TwoComponentGroundMotion

    args = _parser("montecarlo").parse_args(["montecarlo", *map(str, common)])
    read_quantities(args, "montecarlo")
    structure = _structure(args, _check_flags(args), True)
    upper = structure.with_friction_factor({"friction_factor": 1.3})
    model = TwoComponentGroundMotion(_motion_model(args), principal_angle=0.0, minor_ratio=1.0)
    for i in range(3):
        ax, ay = np.asarray(monte_carlo_motion(model, jax.random.key(2), i))
        run = peak_response(under_ground(upper, uniform_signal(ax, 0.01), uniform_signal(ay, 0.01)), 6.0)
        np.testing.assert_allclose(result.base_shear_ratio[1, i], run.base_shear_ratio, rtol=1e-9)
        np.testing.assert_allclose(result.group_peak_load[1, i], run["group_normal_load"]["peak_N"], rtol=1e-9)
    cases = json.loads((tmp_path / "mc.json").read_text())["cases"]
    kip = 4448.2216152605
    for index, case in enumerate(("nominal", "upper", "lower")):
        for j, name in enumerate(result.group_names):
            assert cases[case]["groups"][name]["peak_load"]["max"] == pytest.approx(
                result.group_peak_load[index, :, j].max() / kip, rel=1e-12)
            assert cases[case]["groups"][name]["min_load"]["min"] == pytest.approx(
                result.group_min_load[index, :, j].min() / kip, rel=1e-12)


def test_runs_that_tip_a_tall_slab_are_not_sent_to_a_smaller_step(tmp_path, capsys):
    """A 4 m slab whose centre of mass stands 8 m up, under 1.2 g motions: every run tips it.
    The runs are named with the slab's tipping and the plan's height as the way out, not as a
    Newton solve that a smaller --time-step would mend, and the results file flags them
    `tipped`."""
    plan = {"length_x": "4m", "length_y": "4m", "weight": "400kip", "centre_of_mass": ["2m", "2m"],
            "height_of_centre_of_mass": "8m",
            "groups": [{"name": n, "x": x, "y": y, "load": "100kip"}
                       for n, x, y in (("SW", "0m", "0m"), ("SE", "4m", "0m"), ("NE", "4m", "4m"), ("NW", "0m", "4m"))]}
    (tmp_path / "plan.json").write_text(json.dumps(plan))
    code, out = _montecarlo(capsys, "--plan", tmp_path / "plan.json", "--structure", "slab", "--components", "2",
                            "--motions", "2", "--duration", "4s", "--strong-motion", "2s", "--pga", "1.2g",
                            "--isolation-period", "2.5s", "--no-progress", "--json", tmp_path / "mc.json",
                            "--out", tmp_path / "mc.nc")
    assert code == 1
    assert "2 of 2 runs had a time step on which the slab (or the building's base) tipped" in out.err
    assert "lower height_of_centre_of_mass in the plan" in out.err and "Newton" not in out.err
    result = MonteCarloResult.open(tmp_path / "mc.nc")
    assert result.tipped.tolist() == [True, True] and result.converged.tolist() == [False, False]
    assert json.loads((tmp_path / "mc.json").read_text())["not_converged"] == [0, 1]
