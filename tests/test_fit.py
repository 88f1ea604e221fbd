"""Identification: generic least squares, bearing-test fits, real and independent records."""

import argparse
import json

import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import teflon_jax as tj
from identification import fit_least_squares
from identification.bearing_fit import (
    fit_bearing_test,
    fit_bearing_tests_batch,
    parse_free,
    simulate_record_force,
)
from teflon_jax.cli._fit import add_fit_parser
from teflon_jax.formats import read_friction_damper_json, test_record_from_arrays
from teflon_jax.units import INCH, KIP

Y_PAPER = 0.005 * INCH
NORMAL_LOAD = 78.5 * KIP
TOLERANCE = dict(f_max=0.02, delta_f=0.02, rate_a=0.10, breakaway_ratio=0.05, yield_disp=0.25)


def _truth(row, yield_disp=Y_PAPER):
    return dict(f_max=row.f_max, delta_f=row.delta_f, rate_a=row.rate_a,
                yield_disp=yield_disp, breakaway_ratio=row.breakaway_ratio)


def _protocol(fs=1000.0, amplitude=4 * INCH, frequency=0.6, cycles=3):
    """Sine of test No. 75 (4 in, 0.6 Hz, peak 15 in/s), started from rest at one end.

    Sampled at 1 kHz so that the breakaway branch (about 4 Y of travel) holds ~10 samples.
    """
    t = np.arange(0.0, cycles / frequency + 1e-9, 1.0 / fs)
    u = amplitude * (1.0 - np.cos(2 * np.pi * frequency * t))
    return t, u


class _FromRest(tj.AbstractUniaxialMotion):
    """u = amplitude (1 - cos(2 pi frequency t)): the sine of `_protocol` with its exact velocity."""

    amplitude: float
    frequency: float
    cycles: float = 3.0

    def displacement(self, t):
        w = 2 * jnp.pi * self.frequency
        return jnp.stack([self.amplitude * (1.0 - jnp.cos(w * t)), jnp.zeros_like(t)])

    def velocity(self, t):
        w = 2 * jnp.pi * self.frequency
        return jnp.stack([self.amplitude * w * jnp.sin(w * t), jnp.zeros_like(t)])

    @property
    def duration(self):
        return self.cycles / self.frequency


def _synthetic(row, seed, noise=0.02, fs=1000.0, amplitude=4 * INCH, frequency=0.6, cycles=3):
    # The simulator on the analytic motion (as simulate-test runs it), sampled at fs.
    bearing = tj.paper_bearing(
        tj.FrictionParameters(row.f_max, row.delta_f, row.rate_a),
        yield_disp=Y_PAPER, breakaway_ratio=row.breakaway_ratio)
    result = tj.imposed_path_test(bearing, _FromRest(amplitude, frequency, cycles),
                                      NORMAL_LOAD, samples_per_cycle=round(fs / frequency))
    t, u, force = (np.asarray(x) for x in (result.time, result.ux, result.fx))
    rng = np.random.default_rng(seed)
    force = force + noise * np.sqrt(np.mean(force**2)) * rng.standard_normal(force.size)
    return test_record_from_arrays(u, force, time=t, normal_load=NORMAL_LOAD)


def _assert_recovered(fit, truth):
    assert fit.converged, fit.message
    for name in fit.free:
        error = abs(fit.parameters[name] / truth[name] - 1.0)
        assert error < TOLERANCE[name], (name, fit.parameters[name], truth[name])


# ---------------------------------------------------------------------------------------------
# Generic least squares


def _line_residual(params, args):
    x, y = args
    return params["slope"] * x + params["offset"] - y


def test_linear_least_squares_matches_closed_form():
    rng = np.random.default_rng(1)
    x = np.linspace(0.0, 2.0, 40)
    y = 1.7 * x - 0.3 + 0.05 * rng.standard_normal(x.size)
    result = fit_least_squares(_line_residual, {"slope": 1.0, "offset": 0.5},
                               {"slope": (0.0, np.inf)}, args=(x, y))
    design = np.stack([x, np.ones_like(x)], axis=1)
    coef, ssr, *_ = np.linalg.lstsq(design, y, rcond=None)
    cov = ssr[0] / (x.size - 2) * np.linalg.inv(design.T @ design)
    assert result.converged
    assert result.parameters["slope"] == pytest.approx(coef[0], rel=1e-6)
    assert result.parameters["offset"] == pytest.approx(coef[1], rel=1e-6, abs=1e-9)
    assert result.std_errors["slope"] == pytest.approx(np.sqrt(cov[0, 0]), rel=1e-5)
    assert result.correlation[0, 1] == pytest.approx(cov[0, 1] / np.sqrt(cov[0, 0] * cov[1, 1]),
                                                     rel=1e-5)
    assert result.jacobian.shape == (40, 2)


def test_bounds_are_respected_and_checked():
    x = np.linspace(0.0, 1.0, 20)
    y = -2.0 * x  # best slope is negative; bounded below by 0.5
    result = fit_least_squares(_line_residual, {"slope": 1.0, "offset": 0.0},
                               {"slope": (0.5, 3.0)}, args=(x, y))
    assert 0.5 < result.parameters["slope"] < 0.51
    with pytest.raises(ValueError, match="slope"):
        fit_least_squares(_line_residual, {"slope": 4.0, "offset": 0.0},
                          {"slope": (0.5, 3.0)}, args=(x, y))
    with pytest.raises(ValueError, match="offst"):
        fit_least_squares(_line_residual, {"slope": 1.0, "offset": 0.0},
                          {"offst": (0.0, 1.0)}, args=(x, y))


def _exp_residual(params, args):
    t, y = args
    return params["amp"] * jnp.exp(-params["rate"] * t) - y


def test_unconverged_is_reported():
    t = np.linspace(0.0, 5.0, 50)
    y = 3.0 * np.exp(-1.1 * t)
    result = fit_least_squares(_exp_residual, {"amp": 0.1, "rate": 5.0}, {"rate": (0.0, np.inf)},
                               args=(t, y), max_steps=2)
    assert not result.converged
    assert "not converged" in result.message


# ---------------------------------------------------------------------------------------------
# Bearing model used by the fitter


def test_record_force_equals_core_simulator():
    # Same Z update as the simulator; the velocity at a sample from central differences, so
    # the force matches the simulator's (analytic velocity) to O(h^2): 1e-4 of the RMS.
    row = tj.load_table1()[12]
    bearing = tj.paper_bearing(tj.FrictionParameters(row.f_max, row.delta_f, row.rate_a),
                               yield_disp=Y_PAPER, breakaway_ratio=row.breakaway_ratio)
    core = tj.imposed_path_test(bearing, tj.SineMotion(1 * INCH, 0.16, cycles=2),
                                    NORMAL_LOAD, samples_per_cycle=400)
    t, u, f = (np.asarray(x) for x in (core.time, core.ux, core.fx))
    mine = np.asarray(simulate_record_force(_truth(row), t, u, np.full(t.size, NORMAL_LOAD)))
    assert np.sqrt(np.mean((mine - f) ** 2)) < 1e-4 * np.sqrt(np.mean(f**2))


# ---------------------------------------------------------------------------------------------
# Synthetic Table 1 records


@pytest.mark.parametrize("index", [0, 11, 13])
def test_table1_interfaces_recovered(index):
    row = tj.load_table1()[index]
    fit = fit_bearing_test(_synthetic(row, seed=index))
    assert set(fit.free) == {"f_max", "delta_f", "rate_a", "yield_disp", "breakaway_ratio"}
    _assert_recovered(fit, _truth(row))
    assert fit.records[0].nrmse == pytest.approx(0.02, rel=0.15)  # the noise level
    assert not fit.warnings
    # a sine of 4 in at 0.6 Hz slides from 0 to 0.38 m/s: Eq. 1 is separable, nothing reduced
    assert not fit.reduced and fit.full_model is None and fit.clean


def test_standard_errors_cover_truth():
    row = tj.load_table1()[0]
    records = [_synthetic(row, seed=100 + k) for k in range(10)]
    fits = fit_bearing_tests_batch(records, n_starts=1)
    truth = _truth(row)
    for name in ("f_max", "delta_f", "rate_a"):
        inside = [abs(f.parameters[name] - truth[name]) < 2 * f.std_errors[name] for f in fits]
        assert np.mean(inside) >= 0.8, name
    # and the errors are not absurdly pessimistic: the spread matches the mean SE
    estimates = np.array([f.parameters["f_max"] for f in fits])
    se = np.mean([f.std_errors["f_max"] for f in fits])
    assert 0.3 * se < np.std(estimates, ddof=1) < 3.0 * se


@pytest.mark.slow
def test_all_table1_interfaces_in_one_batch():
    rows = tj.load_table1()
    fits = fit_bearing_tests_batch([_synthetic(r, seed=k) for k, r in enumerate(rows)])
    for row, fit in zip(rows, fits):
        _assert_recovered(fit, _truth(row))


@pytest.mark.slow
def test_joint_fit_of_two_protocols():
    row = tj.load_table1()[4]
    fast = _synthetic(row, seed=3)
    slow = _synthetic(row, seed=4, amplitude=1 * INCH, frequency=0.16, fs=100.0, cycles=2)
    fit = fit_bearing_test([fast, slow], n_starts=2)
    _assert_recovered(fit, _truth(row))
    assert len(fit.records) == 2
    assert all(r.nrmse < 0.03 for r in fit.records)


# ---------------------------------------------------------------------------------------------
# Independent integration (scipy, not the project's simulator)


def _independent_record(row, seed, fs=1000.0, amplitude=4 * INCH, frequency=0.6, cycles=3):
    """Bouc-Wen (Eq. 3) + Eq. 1 + Eq. 17 integrated with scipy's Radau, in numpy."""
    w = 2 * np.pi * frequency
    A, beta, gamma, Y = 1.0, 0.1, 0.9, Y_PAPER

    def velocity(t):
        return amplitude * w * np.sin(w * t)

    def rhs(t, y):
        z = y[0]
        v = velocity(t)
        return [(A * v - gamma * abs(v) * z * abs(z) - beta * v * z * z) / Y]

    t = np.arange(0.0, cycles / frequency + 1e-9, 1.0 / fs)
    sol = solve_ivp(rhs, (0.0, t[-1]), [0.0], method="Radau", t_eval=t, rtol=1e-9, atol=1e-12,
                    max_step=2e-3)
    assert sol.success
    z = sol.y[0]
    v = velocity(t)
    mu = row.f_max - row.delta_f * np.exp(-row.rate_a * np.abs(v))
    mu = np.where(np.maximum.accumulate(np.abs(z)) < 0.999, row.breakaway_ratio
                  * (row.f_max - row.delta_f), mu)
    force = mu * NORMAL_LOAD * z
    rng = np.random.default_rng(seed)
    force = force + 0.02 * np.sqrt(np.mean(force**2)) * rng.standard_normal(force.size)
    u = amplitude * (1.0 - np.cos(w * t))
    return test_record_from_arrays(u, force, time=t, normal_load=NORMAL_LOAD)


def test_independent_integration_is_fitted():
    row = tj.load_table1()[1]
    fit = fit_bearing_test(_independent_record(row, seed=7))
    _assert_recovered(fit, _truth(row))


# ---------------------------------------------------------------------------------------------
# The real friction damper


@pytest.mark.external
@pytest.mark.slow
def test_friction_damper_fit_converges_on_the_reduced_law(external_data, tmp_path, capsys):
    path = external_data / "friction_damper_brfd_arts_lab" / "1Hz30lbtension1amplitude.json"
    record = read_friction_damper_json(path)
    with pytest.raises(ValueError, match="normal load"):
        fit_bearing_test(record)
    # The CLI, as a user runs it: the full law converges with rate_a on its lower bound (the
    # friction rises almost linearly over the tested speeds), but f_max, delta_f and rate_a
    # correlate at +-1, so the reduced law the test determines is fitted and said.
    parser = argparse.ArgumentParser()
    add_fit_parser(parser.add_subparsers())
    args = parser.parse_args(["fit", str(path), "--normal-load", "1N", "--json",
                              str(tmp_path / "fit.json"), "--plot", str(tmp_path / "fit.png")])
    assert args.command_function(args) == 0
    console = capsys.readouterr().err
    report = json.loads((tmp_path / "fit.json").read_text())
    assert report["converged"] is True
    assert "reduced model: friction law reduced to mu = f_max, constant" in console
    assert "correlate at +1.0000" in report["reduction"]
    assert "sliding speeds 0.0115 to 0.163 m/s" in report["reduction"]
    assert set(report["reduced"]) == {"delta_f", "rate_a"}
    assert report["free"] == ["f_max", "yield_disp"] and report["parameters"]["delta_f"] == 0.0
    assert report["full_model"]["converged"] is True
    assert report["full_model"]["parameters"]["rate_a"] == pytest.approx(0.005 / INCH, rel=1e-3)
    # Coulomb friction loses nothing the full law had: nrmse within 0.1 % of it.
    assert report["nrmse"] == pytest.approx(report["full_model"]["nrmse"], rel=1e-3)
    # Friction level: SOURCE.md gives the median sliding force as 2.60 kip (+v) and 1.89 kip
    # (-v); the symmetric model must sit between the two directions.
    assert 1.89 < report["parameters"]["f_max"] / KIP < 2.60
    assert report["std_errors"]["f_max"] < 0.01 * report["parameters"]["f_max"]
    # Honest about what is left: the model follows the loop to 26 % RMS, not to the noise,
    # and the misfit differs between the two directions of sliding (a band brake is
    # self-energising one way): the fit converged but is not clean.
    noise = np.std(np.diff(record.fx)) / np.sqrt(2) / np.sqrt(np.mean(record.fx**2))
    assert 5 * noise < report["nrmse"] < 0.30
    assert report["clean"] is False and "converged, not clean" in console
    assert f"`teflon-jax diagnose {path}` looks for the effects the model lacks" in console
    assert any("asymmetric misfit" in w for w in report["warnings"])
    assert any("normal load" in w for w in report["warnings"])
    assert (tmp_path / "fit.png").stat().st_size > 10_000


# ---------------------------------------------------------------------------------------------
# Bad input and identifiability warnings


def test_record_without_sliding_is_rejected():
    row = tj.load_table1()[0]
    t, u = _protocol(amplitude=0.4 * Y_PAPER, fs=100.0)
    bearing = tj.paper_bearing(tj.FrictionParameters(row.f_max, row.delta_f, row.rate_a))
    force = np.asarray(tj.imposed_path_test(bearing, tj.tabulated_motion(t, u), NORMAL_LOAD).fx)
    record = test_record_from_arrays(u, force, time=t, normal_load=NORMAL_LOAD)
    with pytest.raises(ValueError, match="never slides"):
        fit_bearing_test(record)


def test_bad_names_bounds_and_missing_load():
    row = tj.load_table1()[0]
    record = _synthetic(row, seed=0, fs=100.0, cycles=1.5)
    with pytest.raises(ValueError, match="'mu_max'"):
        parse_free("f_max,mu_max")
    with pytest.raises(ValueError, match="'friction'"):
        fit_bearing_test(record, free=["friction"])
    with pytest.raises(ValueError, match="rate_a"):
        fit_bearing_test(record, initial={"rate_a": 50.0}, bounds={"rate_a": (1.0, 10.0)})
    no_load = test_record_from_arrays(record.ux, record.fx, time=record.time)
    with pytest.raises(ValueError, match="normal load"):
        fit_bearing_test(no_load)
    parser = argparse.ArgumentParser()
    add_fit_parser(parser.add_subparsers())
    args = parser.parse_args(["fit", "x.csv", "--free", "f_max,bogus", "--json", "o.json"])
    assert args.command_function(args) == 2


def test_identifiability_warnings():
    row = tj.load_table1()[0]
    # Starts mid-cycle (no first excursion) and coarse sampling (elastic branch unseen).
    t, u = _protocol(fs=25.0)
    bearing = tj.paper_bearing(tj.FrictionParameters(row.f_max, row.delta_f, row.rate_a))
    force = np.asarray(tj.imposed_path_test(bearing, tj.tabulated_motion(t, u), NORMAL_LOAD).fx)
    keep = t > 0.5
    record = test_record_from_arrays(u[keep], force[keep], time=t[keep], normal_load=NORMAL_LOAD)
    fit = fit_bearing_test(record, n_starts=1)
    assert "breakaway_ratio" not in fit.free and "yield_disp" not in fit.free
    assert any(w.startswith("yield_disp") for w in fit.warnings)
    fit = fit_bearing_test(record, free=["f_max", "delta_f", "rate_a", "breakaway_ratio"],
                           fixed={"yield_disp": Y_PAPER}, n_starts=1)
    assert any(w.startswith("breakaway_ratio: not identifiable") for w in fit.warnings)
    # Constant velocity above the plateau: rate_a cannot be seen.
    motion = tj.TriangleMotion(amplitude=4 * INCH, frequency=1.0, cycles=2)
    result = tj.imposed_path_test(bearing, motion, NORMAL_LOAD, samples_per_cycle=800)
    record = test_record_from_arrays(np.asarray(result.ux), np.asarray(result.fx),
                                     time=np.asarray(result.time), normal_load=NORMAL_LOAD)
    fit = fit_bearing_test(record, n_starts=1, reduce=False)
    assert any("rate_a" in w and "identifiable" in w for w in fit.warnings), fit.warnings


@pytest.mark.slow
def test_narrow_speed_range_fits_the_reduced_law():
    # slow: four fits with three free sets (each compiles), about 40 s
    # A triangle of 1 in at 0.4 Hz slides at one speed, v0 = 4 A f = 0.041 m/s: the record
    # shows mu(v0) = f_max - delta_f exp(-a v0) and nothing of how mu changes with speed.
    row = tj.load_table1()[0]
    v0 = 4 * INCH * 0.4
    mu_v0 = row.f_max - row.delta_f * np.exp(-row.rate_a * v0)
    bearing = tj.paper_bearing(tj.FrictionParameters(row.f_max, row.delta_f, row.rate_a),
                               yield_disp=Y_PAPER)
    motion = tj.TriangleMotion(amplitude=1 * INCH, frequency=0.4, cycles=2)
    result = tj.imposed_path_test(bearing, motion, NORMAL_LOAD, samples_per_cycle=400)
    keep = np.asarray(result.time) > 0.7  # steady cycling (no first excursion)
    fx = np.asarray(result.fx)[keep]
    fx = fx + 0.01 * np.sqrt(np.mean(fx**2)) * np.random.default_rng(1).standard_normal(fx.size)
    record = test_record_from_arrays(np.asarray(result.ux)[keep], fx,
                                     time=np.asarray(result.time)[keep], normal_load=NORMAL_LOAD)
    fit = fit_bearing_test(record, n_starts=2)
    assert fit.converged and fit.clean, (fit.message, fit.warnings)
    # Coulomb friction at the one speed the record shows: f_max is mu(v0), not the f_max of
    # Eq. 1 (which is 42 % higher).
    assert fit.free == ("f_max",)  # 0.1 mm per sample: Y (0.13 mm) is held, as the plan says
    assert fit.parameters["delta_f"] == 0.0
    assert fit.parameters["f_max"] == pytest.approx(mu_v0, rel=0.01)
    assert set(fit.reduced) == {"delta_f", "rate_a"}
    assert "sliding speeds 0.04" in fit.reduction and "correlat" in fit.reduction
    assert "condition number" in fit.reduction
    assert fit.full_model["free"] == ["f_max", "delta_f", "rate_a"]
    report = fit.to_json_dict()
    assert report["reduced"] == fit.reduced and report["reduction"] == fit.reduction
    # the same record fitted as asked (reduce=False) is not a clean result
    assert not fit_bearing_test(record, n_starts=2, reduce=False).clean
