"""`fit --bayes`: the posterior in the bearing file, many records fitted alone (--each), and the
flags refused before any work."""

import argparse
import json

import numpy as np
import pytest
from test_bayes import NORMAL_LOAD, TRUTH

import teflon_jax as tj
from identification.bayes import _sampler
from teflon_jax.cli._fit import add_fit_parser
from teflon_jax.units import INCH


def _run(argv):
    parser = argparse.ArgumentParser()
    add_fit_parser(parser.add_subparsers())
    args = parser.parse_args(["fit", *map(str, argv)])
    return args.command_function(args)


def _model_record(path, seed, *, fs=100.0, cycles=2, noise=0.02):
    """A record of the fitter's own force model (steady cycling, no breakaway) plus 2 % noise."""
    from identification.bearing_fit import simulate_record_force
    from teflon_jax.systems import sample_velocity

    t = np.arange(0.0, cycles / 0.6 + 1e-9, 1.0 / fs)
    u = 4 * INCH * np.sin(2 * np.pi * 0.6 * t)
    truth = {k: v for k, v in TRUTH.items() if k != "breakaway_ratio"}
    force = np.asarray(simulate_record_force(truth, t, u, np.full(t.size, NORMAL_LOAD),
                                             velocity=sample_velocity(t, u), z0=0.0,
                                             z_peak0=1.0))
    rng = np.random.default_rng(seed)
    force = force + noise * np.sqrt(np.mean(force**2)) * rng.standard_normal(force.size)
    tj.write_test_record(path, tj.test_record_from_arrays(u, force, time=t,
                                                          normal_load=NORMAL_LOAD))
    return path


FLAG_ERRORS = [
    (["--each"], "--each: applies with --bayes DIR"),
    (["--posterior-draws", "50"], "--posterior-draws: applies with --bayes DIR"),
    (["--draws", "500"], "--draws: applies with --bayes DIR"),
    (["--chains", "2"], "--chains: applies with --bayes DIR"),
    (["--seed", "0"], "--seed: applies with --bayes DIR"),
    (["--prior", "table1"], "--prior: applies with --bayes DIR"),
    (["--bayes", "B", "--posterior-draws", "50"], "add --save-bearing FILE"),
    (["--bayes", "B", "--save-bearing", "b.json", "--posterior-draws", "0"],
     "--posterior-draws: must be an integer >= 1"),
    (["--bayes", "B", "--each", "--save-bearing", "b.json"],
     "--save-bearing: with --each every record's bearing.json"),
    (["--bayes", "B", "--each", "--plot", "p.png"], "--plot: with --each"),
    (["--bayes", "B", "--each", "--isolator", "single-fp"], "--each: the posterior is sampled"),
]


@pytest.mark.parametrize("extra, message", FLAG_ERRORS)
def test_bayes_file_flags_are_refused_before_any_work(tmp_path, monkeypatch, capsys, extra,
                                                      message):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "r.csv").write_text("not read before the flags are checked\n")
    assert _run(["r.csv", "--json", "f.json", *extra]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "f.json").exists() and not (tmp_path / "B").exists()


def test_each_refuses_two_records_of_one_name(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    for folder in ("a", "b"):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "r.csv").write_text("x\n")
    assert _run(["a/r.csv", "b/r.csv", "--json", "f.json", "--bayes", "B", "--each"]) == 2
    assert "share the name 'r'" in capsys.readouterr().err


@pytest.mark.slow  # a least-squares fit and NUTS: 1-2 minutes on 2 cores
def test_fit_writes_the_posterior_into_the_bearing_file(tmp_path):
    record = _model_record(tmp_path / "test.csv", 1)
    bearing = tmp_path / "bearing.json"
    status = _run([record, "--json", tmp_path / "f.json", "--starts", "2", "--free",
                   "f_max,delta_f,rate_a", "--fixed", "yield_disp=0.005in", "--bayes",
                   tmp_path / "bayes", "--draws", "800", "--chains", "2", "--no-progress",
                   "--save-bearing", bearing, "--posterior-draws", "250"])
    summary = json.loads((tmp_path / "bayes" / "posterior.json").read_text())
    assert status == 0, summary["messages"]
    posterior = tj.load_bearing_posterior(bearing)
    assert posterior.names == ("f_max", "delta_f", "rate_a")
    # 2 chains x 800 draws thinned to at most 250: every 7th, 229 kept
    assert (posterior.draws_before_thinning, posterior.thinning, posterior.size) == (1600, 7, 229)
    assert (posterior.chains, posterior.seed, posterior.method) == (2, 0, "NUTS")
    for name in posterior.names:
        row = summary["posterior"][name]
        assert posterior.effective_sample_size[name] == pytest.approx(row["ess_bulk"])
        # the thinned draws keep the run's centre: within 0.3 posterior sd of its mean
        assert abs(posterior.draws[name].mean() - row["mean"]) < 0.3 * row["sd"]
    point = tj.load_bearing(bearing)
    fit = json.loads((tmp_path / "f.json").read_text())
    assert float(point.friction.rate_a) == pytest.approx(fit["parameters"]["rate_a"])
    assert float(posterior.bearing(point, 7).friction.rate_a) == posterior.draws["rate_a"][7]
    document = json.loads(bearing.read_text())
    assert document["fit"]["bayes"]["converged"] is True


@pytest.mark.slow  # three least-squares fits and two NUTS runs: 2-4 minutes on 2 cores
def test_each_record_is_fitted_alone_with_one_compiled_sampler(tmp_path, capsys):
    # three cycles: a length no other test samples, so that the sampler is made here
    names = [_model_record(tmp_path / f"t{i}.csv", 10 + i, cycles=3) for i in range(2)]
    t = np.arange(0.0, 0.3, 0.01)  # too short for a posterior of three constants and the noise
    tj.write_test_record(tmp_path / "short.csv", tj.test_record_from_arrays(
        4 * INCH * np.sin(2 * np.pi * 3.0 * t), 1e4 * np.cos(2 * np.pi * 3.0 * t), time=t,
        normal_load=NORMAL_LOAD))
    before = set(_sampler._SAMPLERS)
    status = _run([*names, tmp_path / "short.csv", "--json", tmp_path / "each.json", "--starts",
                   "2", "--free", "f_max,delta_f,rate_a", "--fixed", "yield_disp=0.005in",
                   "--bayes", tmp_path / "bayes", "--each", "--draws", "800", "--chains", "2",
                   "--no-progress", "--posterior-draws", "100"])
    rows = {r["record"]: r for r in json.loads((tmp_path / "each.json").read_text())["each"]}
    assert [rows[str(n)]["status"] for n in names] == ["converged", "converged"]
    assert rows[str(tmp_path / "short.csv")]["status"] != "converged"
    assert status in (1, 2)
    assert "short.csv" in capsys.readouterr().err.split("record(s) converged")[-1]
    for i, name in enumerate(names):
        folder = tmp_path / "bayes" / f"t{i}"
        posterior = tj.load_bearing_posterior(folder / "bearing.json")
        assert posterior.size == 100 and posterior.seed == 0
        assert json.loads((folder / "bearing.json").read_text())["sources"] == [str(name)]
        assert (folder / "posterior.nc").is_file() and (folder / "fit.json").is_file()
    draws = [tj.load_bearing_posterior(tmp_path / "bayes" / f"t{i}" / "bearing.json").draws
             for i in range(2)]
    assert not np.array_equal(draws[0]["f_max"], draws[1]["f_max"])  # each its own record
    new = [_sampler._SAMPLERS[k] for k in set(_sampler._SAMPLERS) - before]
    # both records of one length ran on one sampler, compiled once: its initial state and
    # one block length (800 = 10 blocks of 80, warm-up and draws alike)
    assert len(new) == 1 and new[0].runs == 2 and new[0].compilations() == 2
