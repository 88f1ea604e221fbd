"""Fitting a double friction pendulum to a bearing test (`fit_double_pendulum_test`,
`fit --isolator double-fp`): the radii and each surface's Eq. 1 friction of a loop drawn from
the closed form of Fenz & Constantinou (2006) (F/W = mu_1 + u / R_1 on surface 1 alone, then
mu_2 + (u - R_1 (mu_2 - mu_1)) / (R_1 + R_2) on both), the series model's own noise-free record
recovered to rounding (also through the CSV and the isolator file), a noisy one within its
standard errors, the two surfaces indistinguishable in series (the mirrored bearing draws the
same loop, and the fit reports the start file's order), and bad inputs refused by name.
Constantinou, Mokha & Reinhorn (1990), Eq. 1: mu(v) = f_max - delta_f exp(-a v).
"""

import dataclasses
import json
import pathlib

import jax.numpy as jnp
import numpy as np
import pytest
from test_triple_fit import W, _friction, simulate_then_fit
from test_triple_fit import _record as sine_record

from identification.bearing_fit import (
    DOUBLE_PARAMETER_NAMES,
    fit_double_pendulum_test,
    series_parameters,
    series_with_parameters,
)
from teflon_jax.bearing import BoucWen, DoublePendulum, coulomb_friction
from teflon_jax.cli import main
from teflon_jax.formats import (
    isolator_from_dict,
    isolator_to_dict,
    load_isolator,
    test_record_from_arrays,
)
from teflon_jax.systems import imposed_path_test, sampled_path

FITTED = [n for n in DOUBLE_PARAMETER_NAMES if not n.endswith("capacity")]
TRIPLE_FILE = pathlib.Path(__file__).parents[1] / "benchmarks" / "triple_isolator.json"


TRUE = DoublePendulum(
    bottom_radius=jnp.asarray(2.0), top_radius=jnp.asarray(2.6), bottom_capacity=jnp.asarray(0.3),
    top_capacity=jnp.asarray(0.3), bottom_friction=_friction(0.05, 0.025, 20.0),
    top_friction=_friction(0.09, 0.04, 20.0), hysteresis=BoucWen(1e-4))


def _mirrored(bearing):
    return dataclasses.replace(
        bearing, bottom_radius=bearing.top_radius, top_radius=bearing.bottom_radius,
        bottom_capacity=bearing.top_capacity, top_capacity=bearing.bottom_capacity,
        bottom_friction=bearing.top_friction, top_friction=bearing.bottom_friction)


def _record(bearing=TRUE, **options):
    """`test_triple_fit._record` of the double pendulum: two cycles of a 0.5 Hz sine (0.3 m),
    speeds up to ~0.9 m/s, where exp(-a v) spans 0-1."""
    return sine_record(bearing, **options)


def _start(bearing=TRUE):
    """Every radius and friction constant 8-10 % off (capacities the true ones)."""
    values = series_parameters(bearing)
    factors = dict(zip(FITTED, (1.1, 0.92, 0.9, 1.08, 1.1, 1.08, 0.92, 0.9)))
    return series_with_parameters(bearing, {n: jnp.asarray(values[n] * factors[n]) for n in FITTED})


@pytest.fixture(scope="module")
def noise_free():
    return fit_double_pendulum_test(_record(), _start())


@pytest.mark.slow
def test_the_closed_form_loading_branch_gives_the_radii_and_friction():
    """A slow push of Coulomb surfaces (Fenz & Constantinou 2006): slope 1 / R_1 from mu_1,
    then 1 / (R_1 + R_2) from mu_2; the fit of that drawn curve finds R_1, R_2, mu_1, mu_2."""
    r1, r2, mu1, mu2 = 1.5, 2.5, 0.04, 0.08
    u = np.linspace(0.0, 0.2, 201)
    both = r1 * (mu2 - mu1)
    force = W * np.where(u < both, mu1 + u / r1, mu2 + (u - both) / (r1 + r2))
    force[0] = 0.0
    record = test_record_from_arrays(u, force, time=np.linspace(0.0, 4.0, u.size), normal_load=np.full(u.size, W))
    start = DoublePendulum(bottom_radius=1.7, top_radius=2.2, bottom_capacity=0.5, top_capacity=0.5,
                           bottom_friction=coulomb_friction(0.045), top_friction=coulomb_friction(0.07),
                           hysteresis=BoucWen(1e-5))
    fit = fit_double_pendulum_test(record, start)
    assert fit.converged and set(fit.free) == {"bottom_radius", "top_radius", "bottom_f_max", "top_f_max"}
    got = fit.parameters
    assert got["bottom_radius"] == pytest.approx(r1, rel=5e-3)
    assert got["top_radius"] == pytest.approx(r2, rel=5e-3)
    assert got["bottom_f_max"] == pytest.approx(mu1, rel=5e-3)
    assert got["top_f_max"] == pytest.approx(mu2, rel=5e-3)


def test_the_series_models_own_record_is_recovered_to_rounding(noise_free):
    assert noise_free.converged and noise_free.nrmse < 1e-8 and not noise_free.swapped
    truth = series_parameters(TRUE)
    assert set(noise_free.free) == set(FITTED)
    for name in FITTED:
        assert noise_free.parameters[name] == pytest.approx(truth[name], rel=1e-6), name
    assert all("capacity" in name for name in noise_free.held)


def test_a_record_under_a_varying_load_at_uneven_steps_is_recovered_to_rounding():
    """Real tests are neither at one load nor at one step: the series model follows N and the
    interval of each sample (`imposed_path_test`), so its own record under a load that swings
    by +-30 % at uneven steps is recovered to rounding as the constant one is."""
    rng = np.random.default_rng(7)
    t = np.concatenate([[0.0], np.cumsum(rng.uniform(0.006, 0.014, 400))])
    u = 0.3 * np.sin(np.pi * t)
    load = W * (1.0 + 0.3 * np.sin(2 * np.pi * t / 1.3))
    force = np.asarray(imposed_path_test(TRUE, sampled_path(t, u, load)).force)
    fit = fit_double_pendulum_test(test_record_from_arrays(u, force, time=t, normal_load=load), _start())
    assert fit.converged and fit.nrmse < 1e-8 and set(fit.free) == set(FITTED)
    truth = series_parameters(TRUE)
    for name in FITTED:
        assert fit.parameters[name] == pytest.approx(truth[name], rel=1e-6), name


def test_the_fitted_isolator_file_reads_back_to_the_same_bearing(noise_free):
    document = json.loads(json.dumps(isolator_to_dict(noise_free.bearing)))
    assert document["isolator"] == "double-fp" and set(document["surfaces"]) == {"bottom", "top"}
    again = isolator_from_dict(document)
    assert isinstance(again, DoublePendulum)
    assert series_parameters(again) == series_parameters(noise_free.bearing)
    assert noise_free.to_json_dict()["isolator"] == "double-fp"


@pytest.mark.slow
def test_with_noise_the_constants_lie_within_their_standard_errors():
    fit = fit_double_pendulum_test(_record(noise=0.01), _start())
    truth = series_parameters(TRUE)
    for name in FITTED:
        error = fit.std_errors[name]
        assert 0 < error < 0.2 * abs(truth[name]), name
        assert abs(fit.parameters[name] - truth[name]) < 4 * error, name


def test_the_surfaces_in_series_are_indistinguishable_and_keep_the_start_files_order():
    """The mirrored bearing (top and bottom exchanged) carries the same force along any path;
    a start ordered the mirrored way is answered in that order."""
    t = np.linspace(0.0, 4.0, 401)
    u = 0.3 * np.sin(np.pi * t)
    np.testing.assert_allclose(imposed_path_test(_mirrored(TRUE), sampled_path(t, u, W)).force,
                               imposed_path_test(TRUE, sampled_path(t, u, W)).force, rtol=1e-9, atol=1e-6 * W)
    fit = fit_double_pendulum_test(_record(), _mirrored(_start()))
    truth = series_parameters(_mirrored(TRUE))
    assert fit.converged and fit.parameters["bottom_f_max"] > fit.parameters["top_f_max"]
    for name in FITTED:
        assert fit.parameters[name] == pytest.approx(truth[name], rel=1e-6), name


@pytest.mark.slow
def test_coulomb_start_and_small_loops_hold_what_the_record_cannot_tell():
    coulomb = dataclasses.replace(TRUE, bottom_friction=coulomb_friction(0.05), top_friction=coulomb_friction(0.09))
    fit = fit_double_pendulum_test(_record(amplitude=0.3), coulomb)
    assert {"bottom_delta_f", "bottom_rate_a", "top_delta_f", "top_rate_a"} <= set(fit.held)
    assert "Coulomb" in fit.held["top_rate_a"]
    # F/W stays below mu_1 + 0.02 / R_1 = 0.06 < mu_2 = 0.09 in a 0.02 m loop: surface 1 alone slides
    small = fit_double_pendulum_test(_record(coulomb, amplitude=0.02, n=200), coulomb)
    assert {"top_radius", "top_f_max"} <= set(small.held) and "does not slide" in small.held["top_radius"]
    assert "bottom_radius" in small.free


def test_bad_starts_and_names_are_refused():
    record = _record(n=100)
    with pytest.raises(ValueError, match="initial: expected a DoublePendulum"):
        fit_double_pendulum_test(record, coulomb_friction(0.1))
    with pytest.raises(ValueError, match="initial: expected a DoublePendulum"):
        fit_double_pendulum_test(record, load_isolator(TRIPLE_FILE))
    alike = dataclasses.replace(TRUE, top_radius=TRUE.bottom_radius, top_friction=TRUE.bottom_friction)
    with pytest.raises(ValueError, match="initial: the bottom and top surfaces have the same"):
        fit_double_pendulum_test(record, alike)
    with pytest.raises(ValueError, match="free: unknown parameter.*inner_radius"):
        fit_double_pendulum_test(record, TRUE, free="inner_radius")
    with pytest.raises(ValueError, match="bottom_radius"):
        isolator_to_dict(dataclasses.replace(TRUE, bottom_radius=-1.0))


@pytest.fixture
def files(tmp_path):
    (tmp_path / "start.json").write_text(json.dumps(isolator_to_dict(_start())))
    (tmp_path / "true.json").write_text(json.dumps(isolator_to_dict(TRUE)))
    (tmp_path / "r.csv").write_text("time [s],ux [m],fx [N],N [N]\n" + "".join(
        f"{0.01 * i},{0.01 * np.sin(i / 5)},{1e4 * np.sin(i / 5)},1e6\n" for i in range(50)))
    return tmp_path


@pytest.mark.parametrize("extra, message", [
    ([], "--isolator-file: --isolator double-fp starts"),
    (["--isolator-file", "TRIPLE"], "holds a triple-fp isolator; fit --isolator double-fp"),
    (["--isolator-file", "START", "--fixed", "f_max=0.1"], "--fixed: not with --isolator double-fp"),
    (["--isolator-file", "START", "--free", "inner_radius"], "--free: free: unknown"),
    (["--isolator-file", "START", "RECORD"], "RECORD: --isolator double-fp fits one record"),
])
def test_the_command_refuses_bad_flags(files, capsys, extra, message):
    named = {"TRIPLE": str(TRIPLE_FILE), "START": str(files / "start.json"), "RECORD": str(files / "r.csv")}
    code = main(["fit", "--isolator", "double-fp", *[named.get(e, e) for e in extra], str(files / "r.csv"),
                 "--json", str(files / "f.json")])
    assert code == 2 and message in capsys.readouterr().err


def test_simulate_then_fit_from_the_command_line(files, capsys):
    """Through the CSV (nine significant digits) and the fitted isolator file."""
    fitted, report = simulate_then_fit(files, "double-fp")
    assert "start file's order of f_max" in capsys.readouterr().err
    assert report["converged"] and report["isolator"] == "double-fp" and not report["bottom_top_swapped"]
    assert report["units"]["top_rate_a"] == "s/m"
    again, truth = series_parameters(load_isolator(fitted)), series_parameters(TRUE)
    for name in FITTED:
        assert again[name] == pytest.approx(truth[name], rel=1e-6), name


def test_a_smoothed_coulomb_loop_is_fitted_with_delta_f_below_f_max_and_saved(tmp_path):
    """`test_diagnose_series`'s sine record (friction 0.06 tanh(20 cos): a smoothed Coulomb
    law), which the fit once matched with delta_f above f_max, a negative friction at rest that
    --save-isolator refused after the JSON was written: every surface keeps
    0 <= delta_f <= f_max, and the saved file loads."""
    from test_diagnose_series import _double, _sine_record, _write

    start = _write(tmp_path / "start.json", _double())
    record = _sine_record(tmp_path / "r.csv")
    fitted = tmp_path / "fitted.json"
    assert main(["fit", "--isolator", "double-fp", "--isolator-file", str(start), str(record),
                 "--json", str(tmp_path / "f.json"), "--save-isolator", str(fitted)]) == 0
    parameters = json.loads((tmp_path / "f.json").read_text())["parameters"]
    loaded = series_parameters(load_isolator(fitted))
    for surface in ("bottom", "top"):
        assert 0 <= parameters[f"{surface}_delta_f"] <= parameters[f"{surface}_f_max"], surface
        assert loaded[f"{surface}_delta_f"] < loaded[f"{surface}_f_max"], surface
