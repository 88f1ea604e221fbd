"""`diagnose --isolator triple-fp|double-fp --isolator-file START.json RECORD.csv`: the series
fit as baseline and the surfaces' frictional heating as candidate.

Peers: the constant-flux surface temperature rise of Carslaw & Jaeger (1959, Sec. 2.9),
dT = 2 q sqrt(kappa t / pi) / k, and k_T(T) = 0.79 (0.70^(T/50) + 0.40) of Kumar, Whittaker &
Constantinou (2015), written out here; records simulated by `simulate-test` from an isolator
file with a hidden `heating` entry (30 MPa on each surface), with 1 % (RMS) noise added to the
force. The start files hold no heating and the records state no contact pressure, so the
candidate takes 1000 psi and its heat_scale must come out as 30 MPa / 1000 psi = 4.351.
"""

import copy
import json

import numpy as np
import pytest

from identification.bearing_fit import heated_pendulum, prepare_series_problem
from identification.discovery import SERIES_EFFECTS
from teflon_jax.bearing import STEEL_CONDUCTIVITY, STEEL_DIFFUSIVITY
from teflon_jax.cli import main
from teflon_jax.formats import (
    isolator_from_dict,
    load_isolator,
    read_test_record,
    test_record_from_arrays,
    write_test_record,
)
from teflon_jax.systems import imposed_path_test, sampled_path

PRESSURE = 30e6
"""Contact pressure of the hidden heating [Pa]."""

NOMINAL = 1000 * 6894.757293168
"""1000 psi [Pa], the pressure the candidate takes when none is stated."""


def _friction(f_max, delta_f=0.0, rate_a=0.0):
    return {"f_max": {"value": f_max, "unit": "1"}, "delta_f": {"value": delta_f, "unit": "1"},
            "rate_a": {"value": rate_a, "unit": "s/m"}}


def _surface(radius, friction, capacity=0.3):
    return {"radius": {"value": radius, "unit": "m"}, "capacity": {"value": capacity, "unit": "m"},
            "friction": friction}


HEATING = {"contact_area": {"value": 0.05, "unit": "m^2"},
           "contact_pressure": {"value": PRESSURE / 1e6, "unit": "MPa"},
           "heat_scale": {"value": 1, "unit": "1"},
           "conductivity": {"value": 16.2, "unit": "W/(m K)"},
           "diffusivity": {"value": 4.4, "unit": "mm^2/s"},
           "initial_temperature": {"value": 20, "unit": "degC"}}


def _double(bottom=(2.1, 0.06, 0.03), top=(2.1, 0.09, 0.04), heated=False):
    surfaces = {name: _surface(r, _friction(f, d, 20.0)) for name, (r, f, d) in
                (("bottom", bottom), ("top", top))}
    if heated:
        for surface in surfaces.values():
            surface["heating"] = copy.deepcopy(HEATING)
    return {"format": "teflon-jax isolator", "format_version": 1, "isolator": "double-fp",
            "surfaces": surfaces, "yield_disp": {"value": 0.005, "unit": "in"}}


def _triple(heated=False, scale=1.0):
    surfaces = {"inner": _surface(0.3 * scale, _friction(0.03 * scale, 0.015 * scale, 20.0), 0.05),
                "bottom": _surface(2.1 * scale, _friction(0.08 * scale, 0.03 * scale, 20.0)),
                "top": _surface(2.1 * scale, _friction(0.12 * scale, 0.05 * scale, 20.0))}
    if heated:
        for surface in surfaces.values():
            surface["heating"] = copy.deepcopy(HEATING)
    return {"format": "teflon-jax isolator", "format_version": 1, "isolator": "triple-fp",
            "surfaces": surfaces, "yield_disp": {"value": 0.005, "unit": "in"}}


def _write(path, document):
    path.write_text(json.dumps(document))
    return path


def _kumar(temperature):
    return 0.79 * (0.70 ** (temperature / 50.0) + 0.40)


def test_the_candidate_heats_each_surface_by_the_constant_flux_rise_at_1000_psi():
    """A double pendulum whose top surface never slides, driven at constant speed v: under the
    candidate at heat_scale s the bottom surface's friction falls as
    k_T(20 + s dT) / k_T(20) with dT = 2 mu p v sqrt(kappa t / pi) / k at p = 1000 psi (the
    record states none); at s = 0 the model is the series fit's, to round-off."""
    mu, radius, load, speed = 0.06, 1.5, 1e6, 0.05
    start = isolator_from_dict(_double(bottom=(radius, mu, 0.0), top=(2.0, 0.5, 0.0)))
    time = np.linspace(0.0, 2.0, 401)
    unheated = imposed_path_test(start, sampled_path(time, speed * time, load))
    record = test_record_from_arrays(speed * time, np.asarray(unheated.force), time=time,
                                     normal_load=np.full(time.size, load))
    problem = prepare_series_problem(record, start)
    assert problem.pressures == {"bottom": pytest.approx(NOMINAL), "top": pytest.approx(NOMINAL)}
    for s in (0.0, 2.0):
        bearing = heated_pendulum(problem.start, problem.heating, problem.pressures, s)
        response = imposed_path_test(bearing, sampled_path(time, speed * time, load), heat_kernel=problem.kernel)
        assert bool(np.all(response.converged))
        if s == 0.0:
            np.testing.assert_allclose(np.asarray(response.force), np.asarray(unheated.force), rtol=1e-12)
            continue
        friction = np.asarray(response.force) / load - np.asarray(response.slider[:, 0]) / radius
        coefficient = np.sqrt(STEEL_DIFFUSIVITY / np.pi) / STEEL_CONDUCTIVITY
        rise = s * 2 * mu * NOMINAL * speed * coefficient * np.sqrt(time)
        expected = mu * _kumar(20.0 + rise) / _kumar(20.0)
        later = time > 0.2
        assert mu - friction[-1] > 5e-3 * mu * s
        np.testing.assert_allclose(mu - friction[later], mu - expected[later], rtol=5e-2)


def _sine_record(path, biaxial=False, varying_load=False):
    time = np.linspace(0.0, 4.0, 201)
    u = 0.3 * np.sin(np.pi * time)
    f = 1e6 * (u / 2.1 + 0.06 * np.tanh(np.cos(np.pi * time) * 20))
    extra = {"uy": 0.5 * u, "fy": 0.5 * f} if biaxial else {}
    load = 1e6 * (1.0 + (0.2 * np.sin(time) if varying_load else 0.0 * time))
    write_test_record(path, test_record_from_arrays(u, f, time=time, normal_load=load, **extra), units="SI")
    return path


@pytest.mark.parametrize("flags, message", [
    (["--isolator", "triple-fp"], "--isolator-file: .* holds a double-fp isolator; diagnose --isolator triple-fp"),
    (["--isolator", "double-fp", "--isolator-file", None], "--isolator-file: --isolator double-fp starts"),
    (["--radius", "2m"], "--radius: not with --isolator double-fp"),
    (["--baseline", "coulomb"], "--baseline: not with --isolator double-fp"),
    (["--known", "rate_a=0.6s/in"], "--known: not with --isolator double-fp"),
    (["--save-bearing", "b.json"], "--save-bearing: not with --isolator double-fp"),
    (["--isolator", "single-fp"], "--isolator-file: applies to --isolator triple-fp or double-fp only"),
    (["--isolator", "flat", "--isolator-file", None, "--save-isolator", "x.json"],
     "--save-isolator: applies to --isolator triple-fp or double-fp only"),
    (["--candidates", "wear,breakaway"], r"--candidates: the series pendulums take velocity_dependence, "
     r"heating; not wear \(not among the series search's candidates; a surface of the start file may "
     r"carry it \(its \"wear\" entry\)"),
    (["--candidates", "heating,grip"], r"--candidates heating,grip: unknown effect grip; choose among "
                                       r"velocity_dependence, breakaway"),
    (["--biaxial"], "runs in the plane .* along one axis"),
    (["--varying-load"], "heated surfaces take their contact pressures at one load; .* as --reference-load"),
])
def test_what_the_series_diagnose_cannot_take_is_refused_by_name(tmp_path, capsys, flags, message):
    start = _write(tmp_path / "start.json", _double())
    flags = list(flags)
    biaxial, varying_load = "--biaxial" in flags, "--varying-load" in flags
    flags = [f for f in flags if f not in ("--biaxial", "--varying-load")]
    if "--isolator" not in flags:
        flags = ["--isolator", "double-fp"] + flags
    if "--isolator-file" in flags:
        i = flags.index("--isolator-file")
        del flags[i:i + 2]
    else:
        flags += ["--isolator-file", str(start)]
    record = _sine_record(tmp_path / "r.csv", biaxial=biaxial, varying_load=varying_load)
    code = main(["diagnose", str(record), "--json", str(tmp_path / "d.json"), "--report",
                 str(tmp_path / "rep"), "--quiet", *flags])
    assert code == 2
    assert __import__("re").search(message, capsys.readouterr().err)
    assert not (tmp_path / "d.json").exists()


def _noisy_record(tmp_path, document, name, extra=()):
    isolator = _write(tmp_path / f"{name}.json", document)
    clean = tmp_path / f"{name}-clean.csv"
    assert main(["simulate-test", "--isolator-file", str(isolator), "--pattern", "sine",
                 "--amplitude", "0.3m", "--frequency", "0.5Hz", "--cycles", "2",
                 "--samples-per-cycle", "100", "--normal-load", "1000kN", "--out", str(clean),
                 "--units", "si", *extra]) == 0
    record = read_test_record(clean)
    force = np.asarray(record.fx)
    noise = np.random.default_rng(7).normal(0.0, 0.01 * np.sqrt(np.mean(force**2)), force.size)
    path = tmp_path / f"{name}.csv"
    write_test_record(path, test_record_from_arrays(record.ux, force + noise, time=record.time,
                                                    normal_load=record.normal_load), units="SI")
    return path


def _diagnose(tmp_path, isolator, start, record, *flags):
    out = tmp_path / "diagnosis.json"
    code = main(["diagnose", "--isolator", isolator, "--isolator-file", str(start), str(record),
                 "--json", str(out), "--report", str(tmp_path / "report"), "--quiet", *flags])
    assert code == 0
    return json.loads(out.read_text())


@pytest.mark.slow
def test_hidden_heating_of_a_double_pendulum_is_named_and_the_gap_shrinks(tmp_path):
    record = _noisy_record(tmp_path, _double(heated=True), "heated")
    start = _write(tmp_path / "start.json", _double((2.268, 0.0552, 0.03), (2.268, 0.0828, 0.04)))
    fitted = tmp_path / "fitted.json"
    d = _diagnose(tmp_path, "double-fp", start, record, "--save-isolator", str(fitted))
    assert d["isolator"] == "double-fp" and d["baseline"] == "series"
    assert d["effects_added"] == ["heating"] and d["conclusion"] == "added: heating"
    step = d["steps"][0]
    assert step["evidence"]["delta_bic"] > 10 and step["evidence"]["holdout_gain"] > 0
    # the gap shrinks to the noise (1 % of the RMS force), from several times it
    assert d["nrmse_initial"] > 4 * 0.01
    assert 0.006 < d["nrmse_final"] < 0.012  # the noise: 1 % of the RMS force
    scale, error = d["parameters"]["heat_scale"], d["std_errors"]["heat_scale"]
    assert abs(scale - PRESSURE / NOMINAL) < max(3 * error, 0.03 * PRESSURE / NOMINAL)
    assert d["parameters"]["bottom_radius"] == pytest.approx(2.1, rel=0.02)
    assert d["skipped_candidates"]["breakaway"].startswith("not among the series search's candidates; a surface")
    assert d["skipped_candidates"]["backlash"] == "the series model has no backlash gap (a flat bearing's part)"
    assert (tmp_path / "report" / "report.md").read_text().count("heating") >= 2
    saved = json.loads(fitted.read_text())["surfaces"]["bottom"]["heating"]
    assert saved["heat_scale"]["value"] == pytest.approx(scale)


@pytest.mark.slow
def test_a_double_pendulum_without_a_hidden_effect_names_nothing(tmp_path):
    record = _noisy_record(tmp_path, _double(), "plain")
    start = _write(tmp_path / "start.json", _double((2.268, 0.0552, 0.03), (2.268, 0.0828, 0.04)))
    d = _diagnose(tmp_path, "double-fp", start, record)
    assert d["effects_added"] == [] and d["conclusion"] == "no missing effect"
    refused = d["refused_candidates"]["heating"]
    assert refused["delta_bic"] <= 10 or refused["holdout_gain"] <= 0
    assert 0.006 < d["nrmse_initial"] < 0.012
    assert d["nrmse_final"] == d["nrmse_initial"]


@pytest.mark.slow
def test_rate_dependence_hidden_from_a_coulomb_start_is_named(tmp_path):
    """The record's surfaces follow Eq. 1 (rate_a 20 s/m); the start file gives the bottom one
    Coulomb friction, which the series fit holds: velocity dependence is named, and Eq. 1's
    constants of that surface come back."""
    record = _noisy_record(tmp_path, _double(), "rate")
    start = _write(tmp_path / "start.json", _double((2.268, 0.0552, 0.0), (2.268, 0.0828, 0.04)))
    d = _diagnose(tmp_path, "double-fp", start, record, "--candidates", "velocity_dependence")
    assert d["effects_added"] == ["velocity_dependence"]
    assert d["nrmse_initial"] > 2 * d["nrmse_final"]
    assert 0.006 < d["nrmse_final"] < 0.012  # the noise: 1 % of the RMS force
    assert d["parameters"]["bottom_rate_a"] == pytest.approx(20.0, rel=0.25)
    assert d["parameters"]["bottom_f_max"] == pytest.approx(0.06, rel=0.05)
    assert "bottom_rate_a" in d["std_errors"] and "bottom_rate_a" not in d["held"]


@pytest.mark.slow
def test_hidden_heating_of_a_triple_pendulum_is_named(tmp_path):
    record = _noisy_record(tmp_path, _triple(heated=True), "triple")
    start = _write(tmp_path / "start.json", _triple(scale=1.05))
    d = _diagnose(tmp_path, "triple-fp", start, record)
    assert d["isolator"] == "triple-fp" and d["effects_added"] == ["heating"]
    assert d["nrmse_initial"] > 3 * d["nrmse_final"]
    assert 0.006 < d["nrmse_final"] < 0.012
    assert d["parameters"]["heat_scale"] == pytest.approx(PRESSURE / NOMINAL, rel=0.1)


def test_heating_and_velocity_dependence_are_the_series_candidates():
    assert set(SERIES_EFFECTS) == {"heating", "velocity_dependence"}


def test_velocity_dependence_is_a_candidate_on_the_sliding_surfaces_with_coulomb_friction(tmp_path):
    """The series fit holds delta_f and rate_a of a surface the start gives Coulomb friction:
    those surfaces (and only those) take the velocity-dependence candidate."""
    record = read_test_record(_sine_record(tmp_path / "r.csv"))
    coulomb = prepare_series_problem(record, isolator_from_dict(_double((2.1, 0.06, 0.0), (2.1, 0.09, 0.04))))
    assert coulomb.rate_surfaces == ("bottom",)
    assert coulomb.effect_keys("velocity_dependence") == ("bottom_delta_f", "bottom_rate_a")
    assert "bottom_delta_f" in coulomb.held and "top_delta_f" in coulomb.free
    assert prepare_series_problem(record, isolator_from_dict(_double())).rate_surfaces == ()


@pytest.mark.slow
def test_the_sine_records_fitted_pendulum_keeps_delta_f_below_f_max_and_is_saved(tmp_path):
    """The sine record's friction is a smoothed Coulomb one, which the series fit once matched
    with delta_f above f_max (a negative friction at rest, which no isolator file may hold), so
    that --save-isolator failed after the JSON and the report were written: the fit keeps
    0 <= delta_f <= f_max on every surface and the saved file loads."""
    start = _write(tmp_path / "start.json", _double())
    record = _sine_record(tmp_path / "r.csv")
    fitted = tmp_path / "fitted.json"
    d = _diagnose(tmp_path, "double-fp", start, record, "--candidates", "heating", "--max-effects", "1",
                  "--save-isolator", str(fitted))
    for surface in ("bottom", "top"):
        assert 0 <= d["parameters"][f"{surface}_delta_f"] <= d["parameters"][f"{surface}_f_max"], surface
    saved = json.loads(fitted.read_text())["surfaces"]
    loaded = load_isolator(fitted)
    for surface in ("bottom", "top"):
        friction = getattr(loaded, f"{surface}_friction")
        assert float(friction.delta_f) < float(friction.f_max), surface
        assert saved[surface]["friction"]["f_max"]["value"] == pytest.approx(d["parameters"][f"{surface}_f_max"])
