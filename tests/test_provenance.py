"""Results carry their inputs: every JSON, NetCDF and test-record CSV a command writes names the
version, the command line, each input file with the SHA-256 of its bytes, the flags as run (not
those a bearing file replaced), and the NetCDF variables their units."""

import argparse
import hashlib
import json
import os
import time

import numpy as np
import pytest
import xarray
from test_run_cli import _at2 as write_at2

from teflon_jax.bearing import FrictionParameters, paper_bearing
from teflon_jax.cli import main
from teflon_jax.cli._paths import output_flags
from teflon_jax.cli._plan_file import read_plan
from teflon_jax.cli._provenance import (
    clear_arguments,
    run_inputs,
    set_arguments,
    stamp_outputs,
)
from teflon_jax.cli._run_histories import HISTORY_VARIABLES, history_units
from teflon_jax.cli._run_suite import read_suite
from teflon_jax.formats import read_test_record, save_bearing


def _sha(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _at2(path, n=120, dt=0.01, peak=0.3):
    """A PEER AT2 record of a sine of `peak` [g] (`test_run_cli`'s writer)."""
    return write_at2(path, peak * np.sin(2 * np.pi * dt * np.arange(n)), dt)


@pytest.fixture
def bearing_file(tmp_path):
    return save_bearing(tmp_path / "b.json", paper_bearing(FrictionParameters(0.12, 0.06, 20.0)))


def _run(capsys, *argv):
    code = main(["--no-compile-cache", *map(str, argv)])
    capsys.readouterr()
    return code


def test_run_json_and_histories_name_the_files_with_their_hashes_and_the_flags_as_run(tmp_path, capsys,
                                                                                       bearing_file):
    record = _at2(tmp_path / "x.AT2")
    out, histories = tmp_path / "run.json", tmp_path / "h.nc"
    assert _run(capsys, "run", "--record-x", record, "--bearing", bearing_file, "--isolation-period", "2.5s",
                "--isolation-damping", "5%", "--scale", "0.5", "--json", out, "--histories", histories) == 0
    written = json.loads(out.read_text())
    assert list(written)[:3] == ["teflon_jax_version", "command_line", "inputs"]
    inputs = written["inputs"]
    files = {entry["flag"]: entry for entry in inputs["files"]}
    assert files["--record-x"] == {"flag": "--record-x", "path": str(record), "sha256": _sha(record)}
    assert files["--bearing"]["sha256"] == _sha(bearing_file)
    settings = inputs["settings"]
    assert settings["--isolation-period"] == "2.5s" and settings["--isolation-damping"] == "5%"
    assert settings["--scale"] == 0.5 and settings["--structure"] == "rigid" and settings["--isolator"] == "flat"
    for flag in ("--ptfe", "--pressure", "--breakaway"):  # the bearing file's, not run
        assert flag not in settings and inputs["replaced"][flag] == f"--bearing {bearing_file}"
    assert inputs["output_units"] == "us"
    with xarray.open_dataset(histories) as stored:
        assert stored["time"].attrs["units"] == "s"
        for name, variable in stored.data_vars.items():
            assert variable.attrs["units"] == HISTORY_VARIABLES[name][0] and variable.attrs["long_name"], name
        assert stored["ground_x_mps2"].attrs["units"] == "m s-2" and stored["bearing_force_x_N"].attrs["units"] == "N"
        assert stored.attrs["teflon_jax_version"] == written["teflon_jax_version"]
        assert stored.attrs["command_line"] == written["command_line"]
        assert json.loads(stored.attrs["teflon_jax_inputs"]) == inputs


def test_every_history_has_the_unit_its_name_ends_in():
    assert history_units("slider_inner_x_m")[0] == "m" and history_units("temperature_rise_A_bottom_K")[0] == "K"
    assert history_units("ground_y_mps2")[0] == "m s-2" and history_units("rotation_rad")[0] == "rad"
    assert history_units("load_factor")[0] == "1"


def test_montecarlo_results_record_the_bearing_file_and_seed_not_the_flags_it_replaced(tmp_path, capsys,
                                                                                       bearing_file):
    out, summary = tmp_path / "mc.nc", tmp_path / "mc.json"
    assert _run(capsys, "montecarlo", "--motions", "2", "--duration", "6s", "--strong-motion", "2s", "--seed", "7",
                "--bearing", bearing_file, "--no-progress", "--out", out, "--json", summary) == 0
    with xarray.open_dataset(out) as stored:
        attrs = dict(stored.attrs)
        assert stored["base_disp"].attrs["units"] == "m" and stored["pga"].attrs["units"] == "m s-2"
    assert attrs["bearing_file"] == str(bearing_file) and attrs["bearing_file_sha256"] == _sha(bearing_file)
    assert attrs["seed"] == 7 and attrs["isolator"] == "flat" and attrs["isolation_period_s"] == 2.0
    assert "ptfe" not in attrs and "pressure_Pa" not in attrs and "pressure" not in attrs["inputs_as_given"]
    inputs = json.loads(attrs["teflon_jax_inputs"])
    assert inputs["settings"]["--seed"] == 7 and "--ptfe" in inputs["replaced"]
    assert attrs["command_line"].startswith("teflon-jax --no-compile-cache montecarlo --motions 2")
    design = json.loads(summary.read_text())["design"]
    assert design["bearing_file_sha256"] == _sha(bearing_file) and "ptfe" not in design
    assert not any(key.startswith("pressure") for key in design)


def test_montecarlo_without_a_bearing_file_records_its_ptfe_and_pressure(tmp_path, capsys):
    out = tmp_path / "mc.json"
    assert _run(capsys, "montecarlo", "--motions", "2", "--duration", "6s", "--strong-motion", "2s",
                "--pressure", "1500psi", "--ptfe", "15GF", "--no-progress", "--json", out) == 0
    written = json.loads(out.read_text())
    assert written["design"]["ptfe"] == "15GF" and written["design"]["pressure_psi"] == pytest.approx(1500)
    assert written["inputs"]["settings"]["--pressure"] == "1500psi" and written["inputs"]["replaced"] == {}
    assert written["inputs"]["files"] == []


def test_simulate_test_writes_the_version_command_line_and_input_hashes_as_metadata(tmp_path, capsys,
                                                                                   bearing_file):
    out = tmp_path / "t.csv"
    assert _run(capsys, "simulate-test", "--bearing", bearing_file, "--normal-load", "78.5kip",
                "--out", out) == 0
    metadata = read_test_record(out).metadata  # the reader keeps the keys
    assert metadata["teflon_jax_version"] and metadata["command_line"].startswith("teflon-jax --no-compile-cache "
                                                                                  "simulate-test --bearing")
    assert metadata["input_files"] == f"--bearing {bearing_file} sha256 {_sha(bearing_file)}"


def test_an_output_left_by_an_earlier_run_is_not_named_as_an_input(tmp_path, capsys, bearing_file):
    out = tmp_path / "t.csv"
    for _ in range(2):  # the second run finds the first one's record where it writes its own
        assert _run(capsys, "simulate-test", "--bearing", bearing_file, "--normal-load", "78.5kip",
                    "--cycles", "1", "--out", out) == 0
        assert read_test_record(out).metadata["input_files"] == f"--bearing {bearing_file} sha256 {_sha(bearing_file)}"
    for name in ("mc.json", "mc.png", "mc.nc"):
        (tmp_path / name).write_text("an earlier run's")
    args = argparse.Namespace(json=str(tmp_path / "mc.json"), plot=str(tmp_path / "mc.png"),
                              out=str(tmp_path / "mc.nc"), bearing=str(bearing_file))
    set_arguments(args, output_flags("montecarlo"))
    try:
        files = run_inputs()["files"]
    finally:
        clear_arguments()
    assert [entry["flag"] for entry in files] == ["--bearing"]


def test_a_suite_names_each_record_with_its_hash(tmp_path):
    x, y = _at2(tmp_path / "x.AT2"), _at2(tmp_path / "y.AT2", peak=0.2)
    suite = tmp_path / "suite.csv"
    suite.write_text("record_x,record_y,scale,name\nx.AT2,y.AT2,2,one\n")
    set_arguments(argparse.Namespace(suite=str(suite), json=None), output_flags("run"))
    try:
        read_suite(str(suite))
        files = {entry["flag"]: entry for entry in run_inputs()["files"]}
    finally:
        clear_arguments()
    assert files["--suite"]["sha256"] == _sha(suite)
    assert files[f"--suite {suite}: one.record_x"]["sha256"] == _sha(x)
    assert files[f"--suite {suite}: one.record_y"]["sha256"] == _sha(y)
    assert run_inputs() is None  # no command runs now


def test_a_plan_names_each_group_isolator_file_with_its_hash(tmp_path):
    (tmp_path / "iso.json").write_text("{}")  # read by the run, not by the plan reader
    groups = [{"name": n, "x": x, "y": y, "load": "250kN", "isolator_file": "iso.json"}
              for n, x, y in (("SW", "0m", "0m"), ("SE", "20m", "0m"), ("NE", "20m", "12m"), ("NW", "0m", "12m"))]
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"length_x": "20m", "length_y": "12m", "weight": "1000kN", "groups": groups}))
    set_arguments(argparse.Namespace(plan=str(plan), json=None), output_flags("run"))
    try:
        read_plan(str(plan))
        files = {entry["flag"]: entry for entry in run_inputs()["files"]}
    finally:
        clear_arguments()
    assert files["--plan"]["sha256"] == _sha(plan)
    for name in ("SW", "SE", "NE", "NW"):
        assert files[f"--plan {plan}: {name}.isolator_file"]["sha256"] == _sha(tmp_path / "iso.json")


def test_netcdf_outputs_written_by_the_command_are_stamped_and_older_files_are_not(tmp_path):
    fresh, old = tmp_path / "fresh.nc", tmp_path / "old.nc"
    for path in (fresh, old):
        xarray.Dataset({"v": ("t", np.zeros(3), {"units": "m"})}).to_netcdf(path)
    os.utime(old, (time.time() - 3600, time.time() - 3600))
    args = argparse.Namespace(json=None, plot=None, histories=str(fresh), out=str(old), units="si")
    set_arguments(args, output_flags("run"))
    try:
        stamped = stamp_outputs(time.time() - 60)
    finally:
        clear_arguments()
    assert [str(p) for p in stamped] == [str(fresh)]
    with xarray.open_dataset(fresh) as stored:
        assert json.loads(stored.attrs["teflon_jax_inputs"])["output_units"] == "si"
    with xarray.open_dataset(old) as stored:
        assert "teflon_jax_inputs" not in stored.attrs


def test_a_netcdf_file_in_an_output_folder_is_stamped(tmp_path):
    folder = tmp_path / "bayes"
    folder.mkdir()
    xarray.Dataset({"v": ("t", np.zeros(3), {"units": "1"})}).to_netcdf(folder / "posterior.nc")
    args = argparse.Namespace(json=None, plot=None, bayes=str(folder), records=[], units="us")
    set_arguments(args, output_flags("fit"))
    try:
        assert stamp_outputs(time.time() - 60) == [folder / "posterior.nc"]
    finally:
        clear_arguments()
    with xarray.open_dataset(folder / "posterior.nc") as stored:
        assert stored.attrs["teflon_jax_version"] and stored.attrs["command_line"].startswith("teflon-jax")


@pytest.mark.parametrize("command, required", [
    ("reproduce", ["--out", "out"]), ("run", []), ("montecarlo", ["--motions", "8"]), ("design", []),
    ("fit", ["test.csv", "--json", "fit.json"]), ("diagnose", ["test.csv", "--json", "d.json", "--report", "d.md"]),
    ("simulate-test", [])])
def test_the_settings_of_every_command_are_flags_not_code(command, required):
    """Every setting a command records is a flag's value as JSON takes it, never a Python object
    of the parser's (a function's text would differ from run to run)."""
    from teflon_jax.cli._main import _parser

    parser = _parser(command)
    args, _ = parser.parse_known_args([command, *required])
    set_arguments(args, output_flags(command))
    try:
        settings = run_inputs()["settings"]
    finally:
        clear_arguments()
    assert settings and not [flag for flag, value in settings.items() if "<function" in str(value)]
