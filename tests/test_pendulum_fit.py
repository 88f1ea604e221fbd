"""A single friction pendulum's test: `simulate-test --isolator single-fp --radius R` writes the
force N u / R + friction (the flat slider's friction plus the surface's restoring force), and
`fit --isolator single-fp` recovers R and the liner's friction constants from it: to rounding
on the simulator's own record, within its standard errors with measurement noise."""

import json
import math
import pathlib

import numpy as np
import pytest
from test_bayes import TRUTH

from identification.bearing_fit import fit_pendulum_test
from teflon_jax.cli import main
from teflon_jax.formats import read_test_record, test_record_from_arrays, write_test_record
from teflon_jax.tables import interface_parameters
from teflon_jax.units import INCH, PSI, STANDARD_GRAVITY

RADIUS = 88 * INCH


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    """The pendulum's test and the flat slider's test of the same liner and motion (UF PTFE
    at 1000 psi, 4 in at 0.6 Hz, test No. 75's defaults)."""
    folder = tmp_path_factory.mktemp("pendulum")
    paths = {}
    for name, extra in (("fp", ["--isolator", "single-fp", "--radius", "88in"]), ("flat", [])):
        paths[name] = folder / f"{name}.csv"
        assert main(["simulate-test", "--out", str(paths[name]), *extra]) == 0
    return paths


def test_pendulum_record_is_the_flat_slider_plus_n_u_over_r(records):
    fp, flat = (read_test_record(records[k]) for k in ("fp", "flat"))
    np.testing.assert_allclose(fp.ux, flat.ux, rtol=1e-12, atol=1e-15)
    restoring = np.asarray(fp.normal_load) * np.asarray(fp.ux) / RADIUS
    # nine significant digits in the file
    np.testing.assert_allclose(np.asarray(fp.fx) - np.asarray(flat.fx), restoring, rtol=0, atol=1e-7 * np.abs(fp.fx).max())
    assert "single friction pendulum, R = 88in" in fp.metadata["specimen"]


def test_fit_recovers_radius_and_friction_from_its_own_record(records, tmp_path, capsys):
    out = tmp_path / "fit.json"
    code = main(["fit", str(records["fp"]), "--isolator", "single-fp", "--json", str(out)])
    err = capsys.readouterr().err
    assert code == 0, err
    report = json.loads(out.read_text())
    table, _ = interface_parameters("UF", 1000 * PSI, "P")
    p = report["parameters"]
    assert report["radius [m]"] == pytest.approx(RADIUS, rel=1e-6)
    assert report["isolation_period [s]"] == pytest.approx(2 * math.pi * math.sqrt(RADIUS / STANDARD_GRAVITY), rel=1e-6)
    # to the nine digits of the file; rate_a to the flat fit's own 3e-5 (velocity at the samples)
    for name, value, rel in (("f_max", table.f_max, 1e-6), ("delta_f", table.delta_f, 1e-6),
                             ("yield_disp", 0.005 * INCH, 1e-6), ("rate_a", table.rate_a, 1e-4)):
        assert p[name] == pytest.approx(float(value), rel=rel), name
    assert report["nrmse"] < 1e-6 and report["pendulum_converged"] is True
    assert "R = 88 in" in err and "(T = 3 s)" in err


@pytest.mark.slow
def test_fit_with_noise_finds_the_radius_within_its_standard_error(records):
    record = read_test_record(records["fp"])
    fx = np.asarray(record.fx)
    noisy = fx + 0.02 * np.sqrt(np.mean(fx**2)) * np.random.default_rng(4).standard_normal(fx.size)
    noisy_record = test_record_from_arrays(np.asarray(record.ux), noisy, time=np.asarray(record.time),
                                           normal_load=np.asarray(record.normal_load), metadata=dict(record.metadata))
    fit = fit_pendulum_test(noisy_record, free=["f_max", "delta_f", "rate_a", "yield_disp"])
    assert fit.converged
    assert 0 < fit.radius_std_error < 0.01 * RADIUS
    assert abs(fit.radius - RADIUS) < 4 * fit.radius_std_error
    assert fit.friction.parameters["f_max"] == pytest.approx(0.1193, rel=0.02)


def test_a_held_radius_fits_the_friction_alone(records):
    fit = fit_pendulum_test(read_test_record(records["fp"]), radius=RADIUS, free=["f_max", "delta_f"],
                            fixed={"rate_a": 0.6 / INCH, "breakaway_ratio": 1.5})
    assert fit.radius == RADIUS and fit.radius_fixed and fit.iterations == 1
    assert fit.friction.parameters["f_max"] == pytest.approx(0.1193, rel=1e-4)


@pytest.mark.parametrize("flags, message", [
    (["--fixed", "radius=0in"], "--fixed radius: must be a positive radius of curvature"),
    (["--fixed", "radius=-88in"], "--fixed radius: must be a positive radius of curvature"),
    (["--fixed", "radius=88"], "--fixed radius"),
    (["--fixed", "radis=88in"], "unknown parameter 'radis'"),
    (["--effects", "temperature"], "--effects: not available with --isolator single-fp"),
])
def test_bad_radius_is_refused_by_name(records, flags, message, tmp_path, capsys):
    code = main(["fit", str(records["fp"]), "--isolator", "single-fp", "--json", str(tmp_path / "f.json"), *flags])
    assert code == 2
    assert message in capsys.readouterr().err


@pytest.mark.parametrize("flags, message", [
    (["--radius", "88in"], "--radius: applies to --isolator single-fp only"),
    (["--isolator", "single-fp"], "--radius: --isolator single-fp needs the radius"),
    (["--isolator", "single-fp", "--radius", "0in"], "--radius: must be > 0in"),
])
def test_simulate_refuses_a_bad_radius_by_name(flags, message, tmp_path, capsys):
    assert main(["simulate-test", "--out", str(tmp_path / "r.csv"), *flags]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "r.csv").exists()


def test_library_refuses_a_bad_radius(records):
    record = read_test_record(records["fp"])
    with pytest.raises(ValueError, match="radius: must be a positive radius"):
        fit_pendulum_test(record, radius=-1.0)
    with pytest.raises(ValueError, match="radius: must be a positive radius"):
        fit_pendulum_test(record, radius=float("nan"))


def test_friction_part_of_a_pendulum_record_is_the_flat_slider(records):
    from identification.bearing_fit import pendulum_friction_record

    fp, flat = (read_test_record(records[k]) for k in ("fp", "flat"))
    friction = pendulum_friction_record(fp, RADIUS)
    np.testing.assert_allclose(friction.fx, flat.fx, rtol=0, atol=1e-7 * np.abs(fp.fx).max())
    assert friction.path == fp.path and friction.metadata == fp.metadata


@pytest.mark.parametrize("flags, message", [
    (["--radius", "88in"], "--radius: applies to --isolator single-fp only"),
    (["--isolator", "single-fp", "--radius", "0in"], "--radius: must be > 0in"),
])
def test_diagnose_refuses_a_bad_radius_by_name(records, flags, message, tmp_path, capsys):
    code = main(["diagnose", str(records["fp"]), "--json", str(tmp_path / "d.json"), "--report",
                 str(tmp_path / "report"), *flags])
    assert code == 2
    assert message in capsys.readouterr().err


@pytest.mark.slow  # the pendulum's fit and a round of candidates: ~60 s on 2 busy cores
def test_diagnose_puts_the_restoring_force_in_the_baseline(records, tmp_path, capsys):
    """On the simulator's own pendulum record (Eq. 1 friction and N u / R, nothing else) the
    search finds no missing effect: the restoring force is not taken for a friction effect."""
    out = tmp_path / "d.json"
    code = main(["diagnose", str(records["fp"]), "--isolator", "single-fp", "--json", str(out),
                 "--report", str(tmp_path / "report")])
    err = capsys.readouterr().err
    assert code == 0, err
    document = json.loads(out.read_text())
    assert document["isolator"] == "single-fp" and document["radius_given"] is False
    assert document["radius_m"] == pytest.approx(RADIUS, rel=1e-6)
    assert document["effects_added"] == [] and document["conclusion"] == "no missing effect"
    assert document["nrmse_initial"] < 1e-5
    assert "single friction pendulum: R = 88 in" in err


def test_radius_refit_beside_the_true_friction_returns_the_true_radius(records):
    """Given the friction the liner really had (the flat slider's record of the same test), the
    least-squares curvature of the record less N u / R' is 1 / R for any starting R'."""
    from identification.bearing_fit import pendulum_friction_record, refit_pendulum_radius
    from identification.discovery import prepare_record

    friction, _ = prepare_record(read_test_record(records["flat"]))
    fp = read_test_record(records["fp"])
    for start in (70 * INCH, 88 * INCH, 120 * INCH):
        data, _ = prepare_record(pendulum_friction_record(fp, start))
        refit = refit_pendulum_radius(data, friction.force, start)
        assert refit == pytest.approx(RADIUS, rel=1e-6), start / INCH


@pytest.mark.slow  # three searches with the heating candidate: ~60 s on 2 cores
def test_diagnose_refits_the_radius_beside_the_effect_it_finds(tmp_path, capsys):
    """A heating pendulum (R = 40 in): the radius fitted with the baseline's Eq. 1 friction
    absorbs part of the friction's decay and is off by about 0.3 %, and the search then also
    takes wear for a missing effect. Refitted beside the heating found, R comes back within
    0.01 % and the search names heating alone."""
    record = tmp_path / "hot.csv"
    assert main(["simulate-test", "--isolator", "single-fp", "--radius", "40in", "--bearing",
                 str(pathlib.Path(__file__).parents[1] / "benchmarks" / "hot_bearing.json"), "--normal-load", "50kip", "--cycles", "5",
                 "--frequency", "0.5Hz", "--amplitude", "6in", "--out", str(record)]) == 0
    out = tmp_path / "d.json"
    code = main(["diagnose", str(record), "--isolator", "single-fp", "--candidates", "heating,wear",
                 "--json", str(out), "--report", str(tmp_path / "report")])
    err = capsys.readouterr().err
    assert code == 0, err
    document = json.loads(out.read_text())
    true_radius = 40 * INCH
    assert abs(document["radius_with_baseline_m"] / true_radius - 1) > 2e-3
    assert document["radius_m"] == pytest.approx(true_radius, rel=1e-4)
    assert document["radius_settled"] is True and document["radius_reruns"] >= 1
    assert document["effects_added"] == ["heating"]
    assert "R refitted beside the effects found" in err


@pytest.mark.slow  # a least-squares fit, NUTS (2 chains x 600 + 600 steps) and a Monte Carlo: 2-3 minutes
def test_the_liners_posterior_travels_from_a_pendulum_test_into_a_monte_carlo(tmp_path, capsys):
    """From a pendulum's test to its Monte Carlo: `fit --isolator single-fp --bayes` samples the
    liner's friction on the record less N u / R at the fitted radius; on a record of known
    constants with 2 % noise the 5-95 % intervals hold the truth and the mean lies within two
    posterior sd of it; the bearing file it saves carries the draws, which `montecarlo
    --isolator single-fp` runs one bearing per motion. Sampled on the whole force instead (N u /
    R left in), the posterior misses the truth (delta_f's 90 % interval ends near half of it)."""
    from test_bayes_cli import _model_record

    from teflon_jax.formats import load_bearing_posterior

    flat = read_test_record(_model_record(tmp_path / "flat.csv", 3))
    fx = np.asarray(flat.fx) + np.asarray(flat.normal_load) * np.asarray(flat.ux) / RADIUS
    record = tmp_path / "fp.csv"
    write_test_record(record, test_record_from_arrays(np.asarray(flat.ux), fx, time=np.asarray(flat.time),
                                                      normal_load=np.asarray(flat.normal_load)))
    bearing = tmp_path / "liner.json"
    code = main(["fit", str(record), "--isolator", "single-fp", "--json", str(tmp_path / "f.json"), "--starts", "2",
                 "--free", "f_max,delta_f,rate_a", "--fixed", "yield_disp=0.005in", "--bayes", str(tmp_path / "post"),
                 "--draws", "600", "--chains", "2", "--no-progress", "--save-bearing", str(bearing),
                 "--posterior-draws", "40"])
    summary = json.loads((tmp_path / "post" / "posterior.json").read_text())
    assert code == 0, summary["messages"]
    fit = json.loads((tmp_path / "f.json").read_text())
    assert fit["radius [m]"] == pytest.approx(RADIUS, rel=0.01)
    for name in ("f_max", "delta_f", "rate_a"):
        row, truth = summary["posterior"][name], TRUTH[name]
        assert row["q05"] <= truth <= row["q95"], (name, row, truth)
        assert abs(row["mean"] - truth) < 2 * row["sd"], (name, row, truth)
    assert summary["posterior"]["f_max"]["sd"] < 0.02 * TRUTH["f_max"]
    assert load_bearing_posterior(bearing).size == 40

    code = main(["montecarlo", "--isolator", "single-fp", "--radius", "88in", "--bearing", str(bearing),
                 "--motions", "4", "--duration", "4s", "--strong-motion", "2s", "--no-progress",
                 "--json", str(tmp_path / "mc.json")])
    assert code == 0, capsys.readouterr().err
    draws = json.loads((tmp_path / "mc.json").read_text())["bearing_posterior"]["bearing_draw"]
    assert len(draws) == 4 and len(set(draws)) > 1
