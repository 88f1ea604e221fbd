"""Fitting a triple friction pendulum to a bearing test (`fit_triple_pendulum_test`,
`fit --isolator triple-fp`): the series model's own noise-free record recovered to rounding,
a noisy one within its standard errors, and a fit run with the wrong sliding velocity on the
inner surfaces (the pair's, not half of it) that cannot recover the constants: Eq. 1 at the
speed v with rate a equals Eq. 1 at v / 2 with rate 2 a, so that fit lands exactly on half
the inner rate_a (Fenz & Constantinou 2008; Constantinou, Mokha & Reinhorn 1990, Eq. 1).
"""

import json
import pathlib

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from identification.bearing_fit import (
    TRIPLE_PARAMETER_NAMES,
    fit_triple_pendulum_test,
    triple_fit_plan,
    triple_parameters,
    triple_with_parameters,
)
from teflon_jax.bearing import BoucWen, FrictionParameters, TriplePendulum, coulomb_friction
from teflon_jax.cli import main
from teflon_jax.formats import (
    isolator_from_dict,
    isolator_to_dict,
    load_isolator,
    test_record_from_arrays,
)
from teflon_jax.systems import imposed_path_test, sampled_path

W = 1e6
FITTED = [n for n in TRIPLE_PARAMETER_NAMES if not n.endswith("capacity")]


def _friction(f_max, delta_f, rate_a):
    return FrictionParameters(jnp.asarray(f_max), jnp.asarray(delta_f), jnp.asarray(rate_a))


TRUE = TriplePendulum(
    inner_radius=jnp.asarray(0.4), bottom_radius=jnp.asarray(2.2), top_radius=jnp.asarray(2.5),
    inner_capacity=jnp.asarray(0.05), bottom_capacity=jnp.asarray(0.30), top_capacity=jnp.asarray(0.35),
    inner_friction=_friction(0.03, 0.015, 20.0), bottom_friction=_friction(0.06, 0.03, 20.0),
    top_friction=_friction(0.10, 0.04, 20.0), hysteresis=BoucWen(1e-4))


def _record(bearing=TRUE, amplitude=0.3, noise=0.0, n=400):
    """Two cycles of a 0.5 Hz sine (surface speeds up to ~0.5 m/s: exp(-a v) spans 0-1)."""
    t = np.linspace(0.0, 4.0, n + 1)
    u = amplitude * np.sin(np.pi * t)
    force = np.asarray(imposed_path_test(bearing, sampled_path(t, u, W)).force)
    force = force + noise * np.abs(force).max() * np.random.default_rng(1).standard_normal(force.shape)
    return test_record_from_arrays(u, force, time=t, normal_load=np.full(t.size, W))


def _start():
    """Every radius and friction constant 8-10 % off (capacities the true ones)."""
    values = triple_parameters(TRUE)
    return triple_with_parameters(TRUE, {k: values[k] * (1.1 if i % 2 else 0.92)
                                         for i, k in enumerate(FITTED)})


def _relative_errors(fit):
    truth = triple_parameters(TRUE)
    return {k: abs(fit.parameters[k] / truth[k] - 1) for k in FITTED}


@pytest.fixture(scope="module")
def noise_free():
    return fit_triple_pendulum_test(_record(), _start())


def test_the_series_models_own_record_is_recovered_to_rounding(noise_free):
    assert noise_free.converged, noise_free.message
    assert set(noise_free.free) == set(FITTED)  # the loop reaches no restrainer
    assert max(_relative_errors(noise_free).values()) < 1e-6, _relative_errors(noise_free)
    assert noise_free.nrmse < 1e-8


def test_the_fitted_isolator_file_reads_back_to_the_same_bearing(noise_free):
    again = isolator_from_dict(json.loads(json.dumps(isolator_to_dict(noise_free.bearing))))
    assert triple_parameters(again) == pytest.approx(noise_free.parameters, rel=1e-12)


@pytest.mark.slow
def test_with_noise_the_constants_lie_within_their_standard_errors():
    fit = fit_triple_pendulum_test(_record(noise=0.005), _start())
    truth = triple_parameters(TRUE)
    assert fit.converged, fit.message
    for name in FITTED:
        error = fit.std_errors[name]
        assert 0 < error < 0.2 * abs(truth[name]), name
        assert abs(fit.parameters[name] - truth[name]) < 4 * error, name


@pytest.mark.slow
def test_a_fit_with_the_pairs_velocity_on_the_inner_surfaces_misses_the_inner_rate(monkeypatch):
    record, start = _record(), _start()  # recorded with the right law (half the pair's speed)

    def pair_speed(self):
        a, b, c = self.inner_radius, self.bottom_radius, self.top_radius
        return jnp.stack([jnp.ones_like(a), b / (b - a), c / (c - a)])

    monkeypatch.setattr(TriplePendulum, "velocity_factors", pair_speed)
    jax.clear_caches()
    try:
        fit = fit_triple_pendulum_test(record, start)
        from_truth = fit_triple_pendulum_test(record, TRUE)
    finally:
        monkeypatch.undo()
        jax.clear_caches()
    errors = _relative_errors(fit)
    assert errors["inner_rate_a"] > 0.4  # not recovered ...
    # ... but about a / 2 (9.95: from this start the wrong law's fit stops in a local minimum,
    # nrmse 3.6e-5, which a restart keeps), and a / 2 exactly from the true constants, where the
    # wrong law's exact optimum lies (a c v, c the velocity factor, is all Eq. 1 reads)
    assert fit.parameters["inner_rate_a"] == pytest.approx(10.0, rel=1e-2)
    assert from_truth.parameters["inner_rate_a"] == pytest.approx(10.0, rel=1e-9) and from_truth.nrmse < 1e-12


def _plan(bearing, record):
    response = imposed_path_test(bearing, sampled_path(record.time, record.ux, W))
    return triple_fit_plan(bearing, response, record.time)


def test_coulomb_start_and_small_loops_hold_what_the_record_cannot_tell():
    coulomb = triple_with_parameters(TRUE, {"inner_f_max": 0.015, "inner_delta_f": 0.0, "inner_rate_a": 0.0})
    free, held = _plan(coulomb, _record(amplitude=0.005))  # well inside regime I: the pair alone slides
    assert {"inner_delta_f", "inner_rate_a", "bottom_radius", "bottom_f_max", "top_radius",
            "top_f_max"} <= set(held)
    assert set(free) == {"inner_radius", "inner_f_max"}
    slow = _record(n=400)  # the same loop 1000 times slower: exp(-a v) ~ 1 throughout
    slow = test_record_from_arrays(slow.ux, slow.fx, time=1000 * slow.time, normal_load=slow.normal_load)
    free, held = _plan(TRUE, slow)
    assert "does not change over its sliding speeds" in held["top_rate_a"]
    assert {"inner_f_max", "bottom_f_max", "top_f_max"} <= set(free)


def test_a_loop_into_the_restrainers_frees_their_capacities():
    tight = triple_with_parameters(TRUE, {"bottom_capacity": 0.05, "top_capacity": 0.05,
                                          "inner_capacity": 0.01})
    free, held = _plan(tight, _record(tight, n=800))
    assert {"inner_capacity", "bottom_capacity", "top_capacity"} <= set(free)
    assert "capacity" not in " ".join(held)


@pytest.mark.parametrize("change, message", [
    (dict(normal_load=np.linspace(1e6, -1e5, 401)), "positive normal load at every sample"),
    (dict(ux=np.cos(np.linspace(0.0, 4.0, 401))), "starts off the centre"),
])
def test_records_the_fit_cannot_take_are_refused(change, message):
    record = _record()
    values = {"ux": record.ux, "time": record.time, "normal_load": record.normal_load, **change}
    bad = test_record_from_arrays(values.pop("ux"), record.fx, **values)
    with pytest.raises(ValueError, match=message):
        fit_triple_pendulum_test(bad, TRUE)


def test_bad_names_and_starts_are_refused():
    with pytest.raises(ValueError, match="free: unknown parameter"):
        fit_triple_pendulum_test(_record(), TRUE, free="inner_radius,outer_radius")
    with pytest.raises(ValueError, match="initial: expected a TriplePendulum"):
        fit_triple_pendulum_test(_record(), coulomb_friction(0.1))


@pytest.fixture
def files(tmp_path):
    (tmp_path / "start.json").write_text(json.dumps(isolator_to_dict(_start())))
    (tmp_path / "true.json").write_text(json.dumps(isolator_to_dict(TRUE)))
    return tmp_path


@pytest.mark.parametrize("extra, flag", [
    ([], "--isolator-file: --isolator triple-fp starts"),
    (["--isolator-file", "START", "--fixed", "f_max=0.1"], "--fixed: not with --isolator triple-fp"),
    (["--isolator-file", "START", "--save-bearing", "b.json"], "--save-bearing: not with"),
    (["--isolator-file", "START", "--starts", "4"], "--starts: not with --isolator triple-fp"),
    (["--isolator-file", "DOUBLE"], "holds a double-fp isolator"),
    (["--isolator-file", "START", "RECORD"], "RECORD: --isolator triple-fp fits one record"),
    (["--isolator-file", "START", "--free", "inner_radius,spring"], "--free: free: unknown"),
])
def test_the_command_refuses_bad_flags(files, capsys, extra, flag):
    (files / "r.csv").write_text("time [s],ux [m],fx [N],N [N]\n" + "".join(
        f"{0.01 * i},{0.01 * np.sin(i / 5)},{1e4 * np.sin(i / 5)},1e6\n" for i in range(50)))
    double = pathlib.Path(__file__).parents[1] / "benchmarks" / "double_isolator.json"
    extra = [str(double) if e == "DOUBLE" else str(files / "start.json") if e == "START" else str(files / "r.csv") if e == "RECORD" else e
             for e in extra]
    code = main(["fit", "--isolator", "triple-fp", *extra, str(files / "r.csv"), "--json",
                 str(files / "f.json")])
    assert code == 2 and flag in capsys.readouterr().err


def test_the_triple_flags_are_refused_with_other_isolators(files, capsys):
    code = main(["fit", "--isolator-file", str(files / "start.json"), "x.csv", "--json", str(files / "f.json")])
    assert code == 2 and "--isolator-file: applies to --isolator triple-fp or double-fp only" in capsys.readouterr().err


def simulate_then_fit(files, isolator):
    """`simulate-test` of files/true.json (two 0.3 m cycles at 0.5 Hz, 200 samples each, under
    1000 kN) into a CSV, then `fit --isolator isolator` from files/start.json, which must exit
    0: (the fitted isolator file, the JSON report)."""
    record = files / "rec.csv"
    assert main(["simulate-test", "--isolator-file", str(files / "true.json"), "--pattern", "sine",
                 "--amplitude", "0.3m", "--frequency", "0.5Hz", "--cycles", "2", "--samples-per-cycle",
                 "200", "--normal-load", "1000kN", "--out", str(record), "--units", "si"]) == 0
    fitted = files / "fitted.json"
    assert main(["fit", "--isolator", isolator, "--isolator-file", str(files / "start.json"),
                 str(record), "--json", str(files / "fit.json"), "--save-isolator", str(fitted)]) == 0
    return fitted, json.loads((files / "fit.json").read_text())


@pytest.mark.slow
def test_simulate_then_fit_from_the_command_line(files, capsys):
    fitted, report = simulate_then_fit(files, "triple-fp")
    again, truth = triple_parameters(load_isolator(fitted)), triple_parameters(TRUE)
    for name in FITTED:  # the record's nine significant digits (float32 of the file reader aside)
        assert again[name] == pytest.approx(truth[name], rel=1e-5), name
    assert report["converged"] and report["units"]["inner_rate_a"] == "s/m"
