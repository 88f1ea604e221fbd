"""`teflon-jax run --structure building --plan FILE`: the Table 2 building on its base slab over
the plan's bearing groups (`building_on_plan`; flat sliders, single, double or triple pendulums). On a plan symmetric about its centre of mass
under one component the groups slide as one and the slab does not turn, so the base, storeys
and floors are those of the building on one group (`run --structure building`), while the
groups' loads swing with the overturning moment of the levels' inertia forces; and what the
building on a plan cannot take is refused by name before any record is read."""

import json
import pathlib

import numpy as np
import pytest
from test_run_cli import _at2

from teflon_jax.cli import main
from teflon_jax.systems import building_centre_height
from teflon_jax.tables import load_table2

W = load_table2().total_weight
TRIPLE = pathlib.Path(__file__).parents[1] / "benchmarks" / "triple_isolator.json"
CORNERS = (("SW", "1m", "1m"), ("SE", "19m", "1m"), ("NE", "19m", "11m"), ("NW", "1m", "11m"))


def _plan(path, centre=("10m", "6m"), weight="672kip", **extra):
    groups = [{"name": n, "x": x, "y": y, "load": "168kip"} for n, x, y in CORNERS]
    path.write_text(json.dumps({"length_x": "20m", "length_y": "12m", "weight": weight, "centre_of_mass": centre,
                                "groups": groups, **extra}))
    return path


def _record(tmp_path):
    t = 0.01 * np.arange(401)
    return _at2(tmp_path / "x.AT2", 0.35 * np.sin(2 * np.pi * 0.8 * t) * np.sin(np.pi * t / t[-1]) ** 2)


def _run(capsys, *argv):
    code = main(["run", *map(str, argv)])
    return code, capsys.readouterr()


def _without_and_with_plan(tmp_path, capsys, *flags):
    """(peaks of `run --structure building` on the isolator of `flags`, the JSON written with
    the symmetric `_plan` of four corner groups), each run checked to succeed."""
    common = ["--structure", "building", "--record-x", _record(tmp_path), *flags]
    code, out = _run(capsys, *common, "--json", tmp_path / "one.json")
    assert code == 0, out.err
    code, out = _run(capsys, *common, "--plan", _plan(tmp_path / "plan.json"), "--json", tmp_path / "plan.out.json")
    assert code == 0, out.err
    return json.loads((tmp_path / "one.json").read_text())["peak"], json.loads((tmp_path / "plan.out.json").read_text())


def test_a_symmetric_plan_is_the_building_on_one_group_and_its_groups_carry_the_overturning(tmp_path, capsys):
    one, written = _without_and_with_plan(tmp_path, capsys, "--isolation-period", "2.5s", "--isolation-damping", "5%")
    on_plan = written["peak"]
    assert one["base_disp_x_m"] > 0.02
    for key in ("base_disp_x_m", "base_shear_ratio_resultant"):
        assert on_plan[key] == pytest.approx(one[key], rel=1e-6), key
    for key in ("storey_drift_ratio_x", "level_acceleration_g_x"):
        np.testing.assert_allclose(on_plan[key], one[key], rtol=1e-6, err_msg=key)
    assert on_plan["base_disp_y_m"] < 1e-9 and on_plan["rotation_rad"] < 1e-9
    np.testing.assert_allclose(on_plan["corner_disp_resultant_m"], [one["base_disp_x_m"]] * 4, rtol=1e-6)
    np.testing.assert_allclose(list(on_plan["group_disp_resultant_m"].values()), [one["base_disp_x_m"]] * 4, rtol=1e-6)
    normal = written["normal_load"]
    assert normal["height_of_centre_of_mass_m"] == pytest.approx(building_centre_height())
    assert 0 < normal["height_of_centre_of_mass_m"] < 6 * 12 * 0.3048
    groups = normal["groups"]
    for name in ("SW", "SE", "NE", "NW"):  # the loads swing by the moment h_c H over the 18 m lever
        assert groups[name]["static_N"] == pytest.approx(W / 4)
        assert groups[name]["min_N"] < 0.9 * W / 4 and groups[name]["peak_N"] > 1.1 * W / 4
    for a, b in (("SW", "NW"), ("SE", "NE")):  # the plan's symmetry about y = 6 m
        assert groups[a]["peak_N"] == pytest.approx(groups[b]["peak_N"], rel=1e-9)


def test_a_symmetric_plan_of_triple_pendulums_is_the_building_on_one_pendulum(tmp_path, capsys):
    """The same symmetric plan on triple pendulum groups (`--isolator-file`): each group balances
    its own sliders under its own load, and the building moves as on one pendulum of its weight
    (`run --structure building --isolator triple-fp`) to 1e-6; the groups' loads swing."""
    one, written = _without_and_with_plan(tmp_path, capsys, "--isolator", "triple-fp", "--isolator-file", TRIPLE)
    assert one["base_disp_x_m"] > 0.01
    for key in ("base_disp_x_m", "base_shear_ratio_resultant", "bearing_force_ratio_resultant"):
        assert written["peak"][key] == pytest.approx(one[key], rel=1e-6), key
    np.testing.assert_allclose(written["peak"]["storey_drift_ratio_x"], one["storey_drift_ratio_x"], rtol=1e-6)
    assert written["peak"]["rotation_rad"] < 1e-9
    for group in written["normal_load"]["groups"].values():
        assert group["min_N"] < 0.95 * W / 4 < 1.05 * W / 4 < group["peak_N"]


@pytest.mark.parametrize("flags, message", [
    (["--plan", "{plan}"], "--plan: stands a slab (--structure slab) or the Table 2 building (--structure building) "
                           "on bearing groups; not the rigid mass"),
    (["--structure", "building", "--plan", "{high}"], "--plan: {high}: height_of_centre_of_mass is the building's"),
    (["--structure", "building", "--plan", "{light}"], "--plan: {light}: weight is 600kip, and the building on the "
                                                       "plan weighs 2989.2 kN (Table 2: 672 kip)"),
    (["--structure", "building", "--weight", "200kN"], "--weight: is the rigid mass's; the building's weight is "
                                                       "Table 2's (672 kip); leave --weight out."),
    (["--structure", "slab", "--plan", "{plan}", "--weight", "200kN"], "--weight: is the rigid mass's; the slab's "
                                                                      "weight is the plan's weight"),
], ids=["rigid", "height", "weight", "building-weight", "slab-weight"])
def test_what_the_building_or_a_plan_cannot_take_is_refused_by_name(tmp_path, capsys, flags, message):
    """Each refused before the record is read (it does not exist)."""
    files = {"plan": _plan(tmp_path / "plan.json"), "high": _plan(tmp_path / "high.json", height_of_centre_of_mass="9m"),
             "light": _plan(tmp_path / "light.json", weight="600kip"), "triple": TRIPLE}
    flags = [f.format(**files) for f in flags]
    springs = [] if "triple-fp" in flags else ["--isolation-period", "2.5s"]
    code, out = _run(capsys, "--record-x", tmp_path / "not-read.AT2", *springs, *flags, "--json", tmp_path / "out.json")
    assert code == 2
    assert message.format(**files) in out.err
    assert not (tmp_path / "out.json").exists()


@pytest.mark.parametrize("isolator", [["--isolation-period", "2.5s"], ["--isolator", "triple-fp", "--isolator-file", TRIPLE]],
                         ids=["flat", "triple-fp"])
def test_a_building_that_tips_on_a_narrow_plan_stops_saying_why(tmp_path, capsys, isolator):
    """Groups 1.8 m apart under a centre of mass 12 m up: the moment of the levels' inertia
    forces outgrows what the weight holds back, the run stops (exit 1) at the first step it
    cannot balance and says so in the building's terms (no plan height to lower), on flat
    sliders and on triple pendulum groups alike."""
    plan = tmp_path / "narrow.json"
    groups = [{"name": n, "x": x, "y": y, "load": "168kip"}
              for n, x, y in (("SW", "0.1m", "0.1m"), ("SE", "1.9m", "0.1m"), ("NE", "1.9m", "1.9m"), ("NW", "0.1m", "1.9m"))]
    plan.write_text(json.dumps({"length_x": "2m", "length_y": "2m", "weight": "672kip", "groups": groups}))
    code, out = _run(capsys, "--structure", "building", "--plan", plan, "--record-x", _record(tmp_path),
                     *isolator, "--json", tmp_path / "out.json")
    assert code == 1
    assert "the building tips " in out.err and "spread the groups or give a weaker record" in out.err
    assert "height_of_centre_of_mass" not in out.err and "slab tips" not in out.err
    written = json.loads((tmp_path / "out.json").read_text())
    assert written["complete"] is False and written["tipped_steps"] >= 1
