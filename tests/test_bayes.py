"""Bayesian identification (NUTS through the fitter's simulator): coverage, convergence, refusals."""

import jax
import numpy as np
import pytest

import teflon_jax as tj
from identification.bayes import fit_bayes
from teflon_jax.formats import test_record_from_arrays
from teflon_jax.units import INCH, KIP

Y_PAPER = 0.005 * INCH
NORMAL_LOAD = 78.5 * KIP
ROW = tj.load_table1()[0]
TRUTH = dict(f_max=ROW.f_max, delta_f=ROW.delta_f, rate_a=ROW.rate_a, yield_disp=Y_PAPER,
             breakaway_ratio=ROW.breakaway_ratio)


def _record(seed, *, fs=200.0, cycles=2, from_rest=True, noise=0.02, n=None, fine=20):
    """A noisy test record of the core simulator, run on a motion tabulated `fine` times
    finer than the record and read at the record's samples, as a test machine samples a
    continuous test. (Run on the record's own samples, the simulator's segment-slope velocity
    is first order in the sample spacing: 1.1 % RMS of the force at 200 Hz away from the
    fitter's second-order sample velocity, enough to bias delta_f and yield_disp by more than
    a standard error at 2 % noise; at 20x finer, 0.1 %.)"""
    t_fine = np.arange(0.0, cycles / 0.6 + 1e-9, 1.0 / (fine * fs))
    phase = 2 * np.pi * 0.6 * t_fine
    u_fine = 4 * INCH * ((1.0 - np.cos(phase)) if from_rest else np.sin(phase))
    bearing = tj.paper_bearing(tj.FrictionParameters(ROW.f_max, ROW.delta_f, ROW.rate_a),
                               yield_disp=Y_PAPER, breakaway_ratio=ROW.breakaway_ratio)
    force = np.asarray(tj.imposed_path_test(bearing, tj.tabulated_motion(t_fine, u_fine),
                                                NORMAL_LOAD).fx)[::fine]
    t, u = t_fine[::fine], u_fine[::fine]
    if n is not None:
        t, u, force = t[:n], u[:n], force[:n]
    rng = np.random.default_rng(seed)
    force = force + noise * np.sqrt(np.mean(force**2)) * rng.standard_normal(force.size)
    return test_record_from_arrays(u, force, time=t, normal_load=NORMAL_LOAD)


def test_bad_input_is_refused_with_the_reason():
    record = _record(0)
    with pytest.raises(ValueError, match="outside the physical range"):
        fit_bayes(record, bounds={"rate_a": (-1.0, 100.0)})
    with pytest.raises(ValueError, match="outside the physical range"):
        fit_bayes(record, bounds={"breakaway_ratio": (0.5, 3.0)})
    with pytest.raises(ValueError, match="finite"):
        fit_bayes(record, bounds={"f_max": (0.01, np.inf)})
    short = _record(0, n=100, from_rest=False)
    with pytest.raises(ValueError, match="need at least 20 per variable"):
        fit_bayes(short, free=("f_max", "delta_f", "rate_a", "yield_disp", "breakaway_ratio"))
    t = np.linspace(0.0, 2.0, 400)
    ramp = test_record_from_arrays(0.05 * t, np.full(t.size, 1e4), time=t, normal_load=1e5)
    with pytest.raises(ValueError, match="never reverses"):
        fit_bayes(ramp)
    with pytest.raises(ValueError, match="2 chains"):
        fit_bayes(record, num_chains=1)


def _check_covers(result, names):
    for name in names:
        row = result.table[name]
        assert row["q05"] < TRUTH[name] < row["q95"], (name, row, TRUTH[name])


@pytest.mark.slow
def test_posterior_covers_truth_converges_and_matches_least_squares(tmp_path):
    result = fit_bayes(_record(3, fs=300.0, cycles=3), num_warmup=500, num_samples=500,
                       num_chains=4, seed=1)
    assert result.converged, result.summary()
    assert result.divergences == 0
    assert all(row["rhat"] < 1.01 for row in result.table.values())
    _check_covers(result, result.free)
    # near-Gaussian posterior: posterior sd and least-squares s.e. agree within 30 %
    for name, ratio in result.compare_least_squares().items():
        assert 0.7 < ratio < 1.3, (name, ratio)
    # noise level: 2 % of the RMS force
    assert all(row["identified"] == "yes" for row in result.table.values())
    result.to_netcdf(tmp_path / "draws.nc")
    result.plot_pairs(tmp_path / "pairs.png")
    import xarray as xr

    with xr.open_dataset(tmp_path / "draws.nc", group="posterior") as ds:
        assert ds["rate_a"].dims == ("chain", "draw")
        assert ds["rate_a"].shape == (4, 500)
    assert (tmp_path / "pairs.png").stat().st_size > 1000
    assert "5 %" in result.summary()


@pytest.mark.slow
def test_parameter_without_information_stays_at_the_prior():
    # steady cycling (no first excursion): Eq. 17 never acts, so b is not identifiable
    record = _record(5, from_rest=False, fs=150.0)
    free = ("f_max", "delta_f", "rate_a", "breakaway_ratio")
    result = fit_bayes(record, free=free, fixed={"yield_disp": Y_PAPER}, num_warmup=300,
                       num_samples=300, num_chains=2, seed=2)
    assert result.table["breakaway_ratio"]["identified"].startswith("no")
    assert any(m.startswith("breakaway_ratio: not identified") for m in result.messages)
    assert result.table["rate_a"]["identified"] == "yes"


def _model_record(seed, *, fs=200.0, cycles=2, noise=0.02):
    """As `_record`, but the force is the fitter's own model (`simulate_record_force`) plus
    noise: coverage then tests the sampler's calibration alone. (On `_record` the fitter's
    model misses the core simulator by 1 % RMS at 200 Hz, noise-free, which biases delta_f
    and yield_disp by 1.2 and 1.6 standard errors at 2 % noise.)"""
    from teflon_jax.systems import sample_velocity

    t = np.arange(0.0, cycles / 0.6 + 1e-9, 1.0 / fs)
    u = 4 * INCH * (1.0 - np.cos(2 * np.pi * 0.6 * t))
    force = np.asarray(_model_force(t, u, np.full(t.size, NORMAL_LOAD), sample_velocity(t, u)))
    rng = np.random.default_rng(seed)
    force = force + noise * np.sqrt(np.mean(force**2)) * rng.standard_normal(force.size)
    return test_record_from_arrays(u, force, time=t, normal_load=NORMAL_LOAD)


@jax.jit
def _model_force(t, u, load, velocity):
    """The fitter's force of the true bearing from rest, compiled once (the record is data)."""
    from identification.bearing_fit import simulate_record_force

    return simulate_record_force(TRUTH, t, u, load, velocity=velocity, z0=0.0, z_peak0=0.0)


def coverage_run(seeds):
    """Fit one noisy record per seed (2 % noise, the fitter's own force model); per seed:
    (seed, converged, divergences, worst R-hat, hits, intervals, summary). 500 warm-up and
    1,000 draws per chain: with 500 draws the R-hat of the noise level reached 1.0106 (seed
    8), with 300 + 300 that of breakaway_ratio 1.0105 (seed 0). All records have one shape,
    so every fit runs on one compiled sampler and the process's memory stays flat."""
    rows = []
    for seed in seeds:
        result = fit_bayes(_model_record(100 + seed), num_warmup=500, num_samples=1000,
                           num_chains=4, seed=seed)
        hits = sum(int(result.table[n]["q05"] < TRUTH[n] < result.table[n]["q95"]) for n in result.free)
        rows.append((seed, bool(result.converged), int(result.divergences),
                     max(row["rhat"] for row in result.table.values()), hits, len(result.free),
                     result.summary()))
    return rows


@pytest.mark.slow
def test_coverage_over_twenty_seeds():
    # 20 noisy records of one interface: every run must converge (no divergence, R-hat < 1.01,
    # enough effective draws) and the 90 % intervals of the five constants must contain the
    # truth 80-100 % of the time.
    from identification.bayes import _sampler

    rows = coverage_run(range(20))
    # one sampler for the 20 fits (records of 667 samples, 4 chains, 500 warm-up steps),
    # compiled once: its initial state and one block length (500 + 1,000 in blocks of 100)
    used = [s for key, s in _sampler._SAMPLERS.items() if key[3:6] == ((667,), 500, 4)]
    assert len(used) == 1 and used[0].runs >= 20 and used[0].compilations() == 2
    for seed, converged, divergences, _, _, _, summary in rows:
        assert converged and divergences == 0, (seed, summary)
    hits, total = sum(r[4] for r in rows), sum(r[5] for r in rows)
    print(f"coverage {hits}/{total} = {hits / total:.0%}; worst R-hat {max(r[3] for r in rows):.4f}")
    assert max(r[3] for r in rows) < 1.01
    assert 0.8 <= hits / total <= 1.0, (hits, total)


def test_draws_file_and_pair_plot(tmp_path):
    import xarray as xr

    from identification.bayes import BayesResult

    rng = np.random.default_rng(0)
    draws = {"f_max": rng.normal(0.12, 1e-3, (2, 50)), "rate_a": rng.normal(23.0, 0.3, (2, 50)),
             "noise_level_0": rng.normal(800.0, 10.0, (2, 50))}
    result = BayesResult(draws=draws, table={}, divergences=0, converged=True, messages=[],
                         least_squares=None, prior="bounds", priors={}, free=("f_max", "rate_a"),
                         num_chains=2, num_samples=50, elapsed_s=0.0,
                         elapsed_least_squares_s=0.0, rhat_max=1.01, ess_min=200.0)
    result._diverging = np.zeros((2, 50), dtype=bool)
    result.to_netcdf(tmp_path / "draws.nc")
    result.plot_pairs(tmp_path / "pairs.png")
    with xr.open_dataset(tmp_path / "draws.nc", group="posterior") as ds:
        assert ds["rate_a"].dims == ("chain", "draw")
        np.testing.assert_allclose(ds["rate_a"].values, draws["rate_a"])
    assert (tmp_path / "pairs.png").stat().st_size > 1000


@pytest.mark.slow
def test_unconverged_run_exits_non_zero(tmp_path, capsys):
    # A real run that cannot converge: 10 warm-up steps (no step-size or mass adaptation to
    # speak of) and 10 draws per chain. The CLI must say so and exit 1.
    import argparse
    import json

    from teflon_jax.cli._fit import add_fit_parser

    tj.write_test_record(tmp_path / "test.csv", _record(4, fs=100.0))
    parser = argparse.ArgumentParser()
    add_fit_parser(parser.add_subparsers())
    args = parser.parse_args(["fit", str(tmp_path / "test.csv"), "--json", str(tmp_path / "f.json"),
                              "--starts", "2", "--bayes", str(tmp_path / "bayes"), "--draws",
                              "10", "--chains", "2", "--save-bearing", str(tmp_path / "b.json")])
    assert args.command_function(args) == 1
    # the bearing file keeps the least-squares bearing, without the unconverged draws
    assert tj.load_bearing(tmp_path / "b.json") is not None
    assert tj.load_bearing_posterior(tmp_path / "b.json") is None
    posterior = json.loads((tmp_path / "bayes" / "posterior.json").read_text())
    assert posterior["converged"] is False
    assert posterior["messages"][0].startswith("NOT converged")
    err = capsys.readouterr().err
    assert "NOT converged" in err
    assert "2 chains x (10 warm-up steps + 10 draws)" in err.split("NOT converged")[0]  # said up front


def interrupted_at_a_block(arguments, cwd):
    """`teflon-jax ARGUMENTS` in a new process, sent a real SIGINT (Ctrl-C) once it says that
    a block of draws is done: (the stderr lines up to then, its exit status, the rest of its
    stderr)."""
    import os
    import signal
    import subprocess
    import sys

    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    proc = subprocess.Popen([sys.executable, "-m", "teflon_jax.cli", *arguments], stderr=subprocess.PIPE,
                            stdout=subprocess.DEVNULL, text=True, env=env, cwd=cwd)
    seen = []
    try:
        for line in proc.stderr:
            seen.append(line)
            if "draws per chain done" in line:
                proc.send_signal(signal.SIGINT)
                break
        rest = proc.communicate(timeout=300)[1]
    finally:
        proc.kill()
    return seen, proc.returncode, rest


@pytest.mark.slow  # a least-squares fit and a NUTS compilation in a new process: 30-60 s
def test_ctrl_c_keeps_the_draws_so_far_and_says_not_converged(tmp_path):
    # A real SIGINT to the command once it has said that a block of draws is done: the draws
    # finished are written (posterior.json, posterior.nc) as not converged, and it exits 130.
    import json

    import xarray as xr

    tj.write_test_record(tmp_path / "test.csv", _record(4, fs=100.0))
    seen, code, rest = interrupted_at_a_block(["fit", str(tmp_path / "test.csv"), "--json", str(tmp_path / "f.json"),
                                               "--starts", "1", "--bayes", str(tmp_path / "bayes"), "--draws", "40",
                                               "--chains", "2"], tmp_path)
    assert any("10 of 40 draws per chain done" in line for line in seen), "".join(seen)
    assert code == 130, rest
    posterior = json.loads((tmp_path / "bayes" / "posterior.json").read_text())
    assert posterior["converged"] is False
    assert posterior["status"].startswith("interrupted after"), posterior["status"]
    assert 10 <= posterior["num_samples"] < 40
    assert posterior["messages"][0].startswith("NOT converged: interrupted after")
    with xr.open_dataset(tmp_path / "bayes" / "posterior.nc", group="posterior") as ds:
        assert ds.sizes["draw"] == posterior["num_samples"]
    assert "interrupted after" in rest and "not converged" in rest


def test_prior_spread_closed_form_matches_the_prior_draws():
    # the spread each posterior is compared with (identification): the closed form of each
    # kind of prior against 200,000 of its draws (relative error of the draws' sd ~ 0.2 %)
    from identification.bayes import ParameterPrior
    from identification.bayes._model import distribution
    from identification.bayes._result import _prior_sd

    priors = [ParameterPrior("f_max", 0.02, 0.5, "log"),                      # uniform
              ParameterPrior("delta_ratio", 0.0, 1.0, "logit"),               # uniform_physical
              ParameterPrior("delta_ratio", 0.0, 1.0, "logit", loc=1.2, sd=0.7),  # normal
              ParameterPrior("f_max", 0.1, 0.5, "log", loc=-2.3, sd=0.4),     # truncated below
              ParameterPrior("f_max", 0.1, 0.5, "log", loc=-1.5, sd=0.6)]     # and above
    assert [p.kind for p in priors] == ["uniform", "uniform_physical", "normal",
                                        "truncated_normal", "truncated_normal"]
    for p in priors:
        draws = np.asarray(distribution(p).sample(jax.random.PRNGKey(1), (200_000,)))
        assert _prior_sd(p) == pytest.approx(float(np.std(draws)), rel=0.01), p


@pytest.mark.slow  # numpyro's MCMC compiled for one fit: 3-5 minutes on 2 cores
def test_a_kept_sampler_repeats_a_fit_and_samples_numpyros_posterior():
    # the compiled sampler kept between fits carries nothing from one fit to the next (the
    # same record and seed after another record give the same draws), and it samples the
    # posterior that numpyro's MCMC, made for the fit alone, samples: means within 4 Monte
    # Carlo standard errors, spreads within 25 %.
    record, other = _model_record(200), _model_record(201)
    settings = dict(num_warmup=300, num_samples=400, num_chains=2)
    first = fit_bayes(record, seed=3, **settings)
    fit_bayes(other, seed=4, **settings)
    again = fit_bayes(record, seed=3, **settings)
    for name in first.draws:
        np.testing.assert_array_equal(first.draws[name], again.draws[name])
    reference = fit_bayes(record, seed=3, reuse_compiled=False, **settings)
    for name in first.free:
        a, b = first.table[name], reference.table[name]
        error = np.hypot(a["sd"] / np.sqrt(a["ess_bulk"]), b["sd"] / np.sqrt(b["ess_bulk"]))
        assert abs(a["mean"] - b["mean"]) < 4 * error, (name, a, b)
        assert 0.8 < a["sd"] / b["sd"] < 1.25, (name, a, b)
