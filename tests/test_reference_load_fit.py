"""Fitting and diagnosing a series pendulum whose surfaces read their contact pressure from a
test under a varying normal load, given the load its pressures are given under
(`reference_load`, `--reference-load`).

A surface's contact pressure (`<slider>_pressure`, an isolator file's `contact_pressure`) is
given under one load, the static weight W the pendulum carries. Under a varying N the test,
as a structure under a vertical record, takes it times N / W. Told W, the fit recovers its
own simulator's record under N = 0.6-1.4 W to rounding, and `diagnose` finds the heating that
record holds; without W both refuse the record by name, and a W that changes nothing (no
surface reads its pressure) or is not positive is refused as well.
Constantinou, Mokha & Reinhorn (1990), Eq. 1; pressure dependence (N / N_ref)^-e.
"""

import dataclasses
import json

import jax.numpy as jnp
import numpy as np
import pytest
from test_double_fit import FITTED, TRUE, _start

from identification.bearing_fit import (
    fit_double_pendulum_test,
    prepare_series_problem,
    series_parameters,
)
from teflon_jax.bearing import FrictionalHeating, PressureDependence, SurfaceParts
from teflon_jax.cli import main
from teflon_jax.formats import (
    isolator_to_dict,
    load_isolator,
    test_record_from_arrays,
    write_test_record,
)
from teflon_jax.systems import imposed_path_test, sampled_path

W = 1e6
"""The static load [N] the surfaces' contact pressures are given under."""

PRESSED = dataclasses.replace(  # the top surface's friction falls with its contact pressure
    TRUE, top_pressure=jnp.asarray(25e6), surface_parts=(None, SurfaceParts(pressure_dependence=PressureDependence(
        exponent=0.3, reference_load=W, contact_area=0.04))))


def _loaded_record(bearing, reference_load=W, n=400):
    """Two cycles of a 0.5 Hz, 0.3 m sine under N = W (1 + 0.4 sin(2 pi t / 0.7)), from the
    series model told `reference_load`."""
    time = np.linspace(0.0, 4.0, n + 1)
    u = 0.3 * np.sin(np.pi * time)
    load = W * (1.0 + 0.4 * np.sin(2 * np.pi * time / 0.7))
    force = np.asarray(imposed_path_test(bearing, sampled_path(time, u, load), reference_load=reference_load).force)
    return test_record_from_arrays(u, force, time=time, normal_load=load)


@pytest.fixture(scope="module")
def pressed_record():
    return _loaded_record(PRESSED)


def test_told_the_static_load_the_fit_recovers_its_own_record_under_a_varying_load(pressed_record):
    """Noise-free, from every constant 8-10 % off: the fitted constants are the truth's to
    rounding. The pressure law matters on this record: the truth told 2 W differs from it by
    more than a percent of its largest force."""
    fit = fit_double_pendulum_test(pressed_record, _start(PRESSED), reference_load=W)
    assert fit.converged and fit.nrmse < 1e-8 and set(fit.free) == set(FITTED)
    truth = series_parameters(PRESSED)
    for name in FITTED:
        assert fit.parameters[name] == pytest.approx(truth[name], rel=1e-6), name
    assert fit.to_json_dict()["reference_load"] == W
    other = _loaded_record(PRESSED, reference_load=2 * W)
    assert np.max(np.abs(other.fx - pressed_record.fx)) > 1e-2 * np.max(np.abs(pressed_record.fx))


def test_the_reference_load_is_refused_where_it_is_missing_changes_nothing_or_is_not_positive(pressed_record):
    with pytest.raises(ValueError, match=r"record 0: its normal load varies .* state that load as reference_load"):
        fit_double_pendulum_test(pressed_record, _start(PRESSED), max_steps=1)
    with pytest.raises(ValueError, match="reference_load: no surface of the double .* leave it out"):
        fit_double_pendulum_test(pressed_record, _start(TRUE), reference_load=W, max_steps=1)
    for bad in (0.0, -W, float("nan"), "1e6", True):
        with pytest.raises(ValueError, match="reference_load: give the positive load"):
            fit_double_pendulum_test(pressed_record, _start(PRESSED), reference_load=bad, max_steps=1)
        with pytest.raises(ValueError, match="reference_load: give the positive load"):
            prepare_series_problem(pressed_record, PRESSED, reference_load=bad)
    with pytest.raises(ValueError, match=r"record 0: heated surfaces .* varies .* reference_load"):
        prepare_series_problem(pressed_record, TRUE)  # the heating candidate reads its pressure


def test_the_heating_candidate_takes_a_stated_contact_area_under_the_reference_load(pressed_record):
    """A record that states its contact area A, under a varying N: the candidate's pressure on
    each surface is W / A, the pressure under the load the test is told (not N at any one
    sample), and the varying load is kept sample by sample."""
    record = dataclasses.replace(pressed_record, metadata={**pressed_record.metadata, "contact_area": 0.05})
    problem = prepare_series_problem(record, TRUE, reference_load=W)
    assert problem.pressures == {"bottom": W / 0.05, "top": W / 0.05} and problem.pressure_assumed == ()
    np.testing.assert_array_equal(problem.load, record.normal_load)


def test_diagnose_finds_the_heating_of_a_record_under_a_varying_load(tmp_path, capsys):
    """Both surfaces heated (30 MPa under W) on a record whose N swings by +-40 %: told W
    (`--reference-load`), the search adds heating, the gap shrinks from percents to the CSV's rounding
    and the heat scale found is the truth's (1)."""
    heat = {f"{s}_heating": FrictionalHeating(contact_area=W / 30e6) for s in ("bottom", "top")}
    heated = dataclasses.replace(TRUE, **heat, bottom_pressure=30e6, top_pressure=30e6)
    write_test_record(tmp_path / "r.csv", _loaded_record(heated, n=800))
    (tmp_path / "start.json").write_text(json.dumps(isolator_to_dict(heated)))
    code = main(["diagnose", str(tmp_path / "r.csv"), "--isolator", "double-fp", "--isolator-file",
                 str(tmp_path / "start.json"), "--candidates", "heating", "--reference-load", "1000kN",
                 "--json", str(tmp_path / "d.json"), "--report", str(tmp_path / "report")])
    assert code == 0, capsys.readouterr().err
    d = json.loads((tmp_path / "d.json").read_text())
    assert d["effects_added"] == ["heating"] and d["reference_load_N"] == pytest.approx(W)
    assert d["nrmse_final"] < 1e-6 and d["nrmse_initial"] > 1e-2  # the CSV holds nine digits
    assert d["parameters"]["heat_scale"] == pytest.approx(1.0, rel=1e-5)


@pytest.fixture
def files(tmp_path, pressed_record):
    (tmp_path / "start.json").write_text(json.dumps(isolator_to_dict(_start(PRESSED))))
    (tmp_path / "plain.json").write_text(json.dumps(isolator_to_dict(_start(TRUE))))
    write_test_record(tmp_path / "r.csv", pressed_record)
    return tmp_path


def test_fit_from_the_command_line_takes_the_reference_load(files, capsys):
    """Through the CSV (nine significant digits) and the fitted isolator file; the JSON report
    states the reference load."""
    code = main(["fit", "--isolator", "double-fp", "--isolator-file", str(files / "start.json"), str(files / "r.csv"),
                 "--reference-load", "1000kN", "--json", str(files / "f.json"),
                 "--save-isolator", str(files / "fitted.json")])
    assert code == 0, capsys.readouterr().err
    report = json.loads((files / "f.json").read_text())
    assert report["converged"] and report["reference_load"] == pytest.approx(W)
    again, truth = series_parameters(load_isolator(files / "fitted.json")), series_parameters(PRESSED)
    for name in FITTED:
        assert again[name] == pytest.approx(truth[name], rel=1e-5), name  # the CSV holds nine digits


@pytest.mark.parametrize("command, extra, message", [
    ("fit", ["--isolator", "double-fp", "--isolator-file", "START"], "its normal load varies"),
    ("fit", ["--isolator", "double-fp", "--isolator-file", "START", "--reference-load", "-1kN"],
     "--reference-load"),
    ("fit", ["--isolator", "double-fp", "--isolator-file", "PLAIN", "--reference-load", "1000kN"],
     "--reference-load: no surface of the double"),
    ("fit", ["--reference-load", "1000kN"], "--reference-load: applies to --isolator triple-fp or double-fp"),
    ("fit", ["--isolator", "single-fp", "--reference-load", "1000kN"], "--reference-load: applies to"),
    ("diagnose", ["--reference-load", "1000kN", "--report", "REPORT"], "--reference-load: applies to"),
    ("diagnose", ["--isolator", "double-fp", "--isolator-file", "PLAIN", "--report", "REPORT"],
     "state the load the contact pressures are given under as --reference-load"),
])
def test_the_commands_refuse_the_reference_load_by_flag(files, capsys, command, extra, message):
    named = {"START": str(files / "start.json"), "PLAIN": str(files / "plain.json"), "REPORT": str(files / "rep")}
    code = main([command, str(files / "r.csv"), *[named.get(e, e) for e in extra], "--json", str(files / "o.json")])
    assert code == 2 and message in capsys.readouterr().err
    assert not (files / "o.json").exists()
