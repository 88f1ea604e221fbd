"""Design of a single friction pendulum's displacement capacity d (where its stiffening
restrainer engages, k_r (|u| - d) beyond it) and the statistic over the motions a
displacement limit applies to (the mean or the 95th percentile of the peaks).

The derivatives of the mean and of the 95th percentile of the smoothed peak base
displacement in d agree with central differences where the restrainer is reached, and vanish
where it is not (the surface is then the linear W u / R one); a design under a limit on the
95th percentile meets it there and is stiffer than the design under the same limit on the
mean; inputs that do not apply are refused by name.
References: Zayas, Low & Mahin (1990), Earthquake Spectra 6(2); Constantinou, Mokha &
Reinhorn (1990), J. Struct. Eng. 116(2).
"""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from teflon_jax.bearing import concave_surface
from teflon_jax.cli import main
from teflon_jax.excitation import StochasticGroundMotion, sample, uniform_signal
from teflon_jax.studies import design_sweep, expected_response, optimise_design
from teflon_jax.systems import isolated_structure, peak_response
from teflon_jax.units import PSI

DT = 0.01
RADIUS = 1.5  # m
WEIGHT = 100e3  # N, the rigid mass's
SETTINGS = {"pressure": 1000 * PSI, "time_step": 0.0025, "split_at_turn": False, "newton_tolerance": 0.0,
            "linear_rule": "newmark"}


@pytest.fixture(scope="module")
def records():
    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=4.0, time_step=DT, rise_time=0.5,
                                   strong_motion_duration=2.0)
    return sample(model, jax.random.key(3), 4)


def _pendulum(capacity):
    surface = concave_surface(RADIUS, displacement_capacity=capacity, restrainer_stiffness=10 * WEIGHT / RADIUS)
    return isolated_structure("rigid", isolator=surface, isolation_period=None, **SETTINGS)


def test_capacity_derivatives_of_the_mean_and_95th_percentile_match_central_differences(records):
    """d/dd of E[D_s], the 95th percentile of D_s (linear interpolation between the two
    largest of four peaks) and E[V_s] at d = 2 cm, which the largest peaks pass (~3 cm
    without restrainer), against (f(d + h) - f(d - h)) / (2 h), h = 1e-5 d."""
    structure = _pendulum(0.05)
    keys = ("disp", "disp_p95", "shear")

    def statistics(d):
        r = expected_response(structure, {"capacity": d}, records, DT)
        return {k: r[k] for k in keys}

    d = 0.02
    jacobian = jax.jit(jax.jacfwd(statistics))
    derivative = jacobian(jnp.asarray(d))
    value = jax.jit(statistics)
    h = 1e-5 * d
    plus, minus = value(jnp.asarray(d + h)), value(jnp.asarray(d - h))
    for k in keys:
        fd = (float(plus[k]) - float(minus[k])) / (2 * h)
        assert float(derivative[k]) == pytest.approx(fd, rel=1e-4), k
    # a larger capacity lets the base travel further before the restrainer pushes back harder
    assert float(derivative["disp"]) > 0 and float(derivative["disp_p95"]) > 0 > float(derivative["shear"])
    assert float(derivative["disp_p95"]) > float(derivative["disp"])  # only the largest peaks reach it

    # beyond every peak the restrainer never engages: the linear pendulum, derivative zero
    free = expected_response(isolated_structure("rigid", isolator=concave_surface(RADIUS),
                                                isolation_period=None, **SETTINGS), {}, records, DT)
    far = value(jnp.asarray(0.2))
    assert float(far["disp"]) == pytest.approx(float(free["disp"]), rel=1e-12)
    assert float(jacobian(jnp.asarray(0.2))["disp_p95"]) == 0.0


def test_the_95th_percentile_is_numpys_linear_interpolation(records):
    """The statistic limited with p95 is numpy's percentile of the motions' true peaks."""
    structure = _pendulum(0.02)
    r = expected_response(structure, {}, records, DT)
    duration = (records.shape[1] - 1) * DT

    def one(values):
        return peak_response(structure(uniform_signal(values, DT)), duration).base_disp

    true = np.asarray(jax.jit(jax.vmap(one))(records))
    assert float(r["peak_disp_p95"]) == pytest.approx(np.percentile(true, 95), rel=1e-12)
    assert float(r["peak_disp"]) == pytest.approx(true.mean(), rel=1e-12)
    assert float(r["peak_disp"]) < float(r["peak_disp_p95"]) <= true.max()


def test_a_capacity_on_a_surface_without_restrainer_or_on_flat_sliders_is_refused():
    plain = isolated_structure("rigid", isolator=concave_surface(RADIUS), isolation_period=None)
    with pytest.raises(ValueError, match="'capacity' needs a surface with a restrainer"):
        plain(jnp.zeros(10), {"capacity": 0.1})
    with pytest.raises(ValueError, match="'capacity' does not apply to the flat isolator"):
        isolated_structure("rigid")(jnp.zeros(10), {"capacity": 0.1})


@pytest.mark.parametrize("flags, message", [
    (["--capacity-range", "1in", "3in"], "--capacity-range: does not apply to --isolator flat"),
    (["--isolator", "single-fp", "--capacity-range", "0in", "3in"], "--capacity-range: must be > 0in"),
    (["--isolator", "single-fp", "--capacity-range", "3in", "1in"], "--capacity-range: LOW must be below HIGH"),
    (["--isolator", "single-fp", "--restrainer-ratio", "5"], "--restrainer-ratio: sets the restrainer"),
    (["--isolator", "triple-fp", "--capacity-range", "1in", "3in", "--capacity-scale-range", "0.5", "1"],
     "--capacity-range: does not apply to --isolator triple-fp"),
    (["--limit-statistic", "p99"], "argument --limit-statistic: invalid choice: 'p99'"),
    (["--penalty", "-1"], "argument --penalty: expected a finite number > 0 (the weight of the displacement limit), "
                          "got -1"),
    (["--penalty", "0"], "argument --penalty: expected a finite number > 0"),
    (["--penalty", "inf"], "argument --penalty: expected a finite number > 0"),
    (["--grid", "1"], "argument --grid: expected an integer >= 2 (the sweep runs from LOW to HIGH of each range), "
                      "got 1"),
])
def test_bad_capacity_and_statistic_flags_are_refused_by_name(flags, message, capsys):
    try:
        code = main(["--no-compile-cache", "design", "--motions", "2", "--no-progress", *flags])
    except SystemExit as stop:  # argparse's own refusal (an unknown choice)
        code = stop.code
    assert code == 2
    assert message in capsys.readouterr().err


def test_the_grid_sweep_penalises_the_chosen_statistic(records):
    """The sweep that starts BFGS: J = E[V_s] + rho max(0, P95[D_s] / D_limit - 1)^2 with p95."""
    structure = isolated_structure("rigid", time_step=DT, pressure=1000 * PSI)
    limit, periods = 0.01, [1.5, 3.0]
    sweep = design_sweep(structure, records, DT, grid={"isolation_period": periods}, disp_limit=limit,
                         limit_statistic="p95", batch_size=2)
    for i, period in enumerate(periods):
        r = expected_response(structure, {"isolation_period": period}, records, DT)
        assert sweep["disp"][i] == pytest.approx(float(r["disp_p95"]), rel=1e-9)
        objective = float(r["shear"]) + 100.0 * max(float(r["disp_p95"]) / limit - 1.0, 0.0) ** 2
        assert sweep["objective"][i] == pytest.approx(objective, rel=1e-9)
    assert sweep["objective"][0] != sweep["objective"][1]


def test_an_unknown_statistic_is_refused_by_the_library(records):
    structure = isolated_structure("rigid", time_step=DT, pressure=1000 * PSI)
    with pytest.raises(ValueError, match="limit_statistic: unknown 'median'; accepted: mean, p95"):
        optimise_design(structure, records, DT, variables={"isolation_period": (1.0, 4.0)}, disp_limit=0.02,
                        limit_statistic="median")


def _flat_design(tmp_path, statistic):
    out = tmp_path / f"{statistic}.json"
    code = main(["--no-compile-cache", "design", "--motions", "8", "--duration", "6s", "--strong-motion", "2s",
                 "--grid", "4", "--pressure", "2000psi", "--disp-limit", "1.4in", "--limit-statistic", statistic,
                 "--json", str(out), "--no-progress"])
    return code, json.loads(out.read_text())


@pytest.mark.slow  # two designs (sweep, BFGS, restarts, gradient checks): ~7 min on 2 busy cores
def test_a_limit_on_the_95th_percentile_is_met_there_and_stiffens_the_design(tmp_path):
    """Flat sliders on springs, the period designed: under the same limit on the 95th
    percentile instead of the mean the optimum is stiffer and its true 95th percentile meets
    the limit (and binds), while the mean-limited design breaks it there."""
    (code_mean, mean), (code_p95, p95) = (_flat_design(tmp_path, s) for s in ("mean", "p95"))
    assert code_mean == 0 and code_p95 == 0
    assert mean["limit_statistic"] == "mean" and p95["limit_statistic"] == "p95"
    m, p = mean["optimum"], p95["optimum"]
    assert (1 - 1e-2) * 1.4 <= p["p95_peak_base_disp_in"] <= 1.4 and p["disp_limit_met"] and p["converged"]
    assert m["mean_peak_base_disp_in"] <= 1.4 < m["p95_peak_base_disp_in"]  # the mean's design breaks it
    assert p["isolation_period_s"] < m["isolation_period_s"]
    assert p["mean_peak_base_disp_in"] < p["p95_peak_base_disp_in"]
    assert p95["gradient_rel_error"] < 1e-4  # the 95th percentile's derivative at the optimum


@pytest.mark.slow  # grid sweep, BFGS and gradient check of two variables: ~3 min on 2 busy cores
def test_design_of_radius_and_capacity_under_a_95th_percentile_limit(tmp_path, capsys):
    out = tmp_path / "design.json"
    code = main(["--no-compile-cache", "design", "--isolator", "single-fp", "--motions", "4", "--duration", "6s",
                 "--strong-motion", "2s", "--radius-range", "20in", "160in", "--capacity-range", "0.5in", "3in",
                 "--pressure", "1000psi", "--grid", "4", "--disp-limit", "1in", "--limit-statistic", "p95",
                 "--json", str(out), "--no-progress"])
    printed = capsys.readouterr()
    summary = json.loads(out.read_text())
    optimum = summary["optimum"]
    assert code == 0, printed.err
    assert summary["limit_statistic"] == "p95" and summary["restrainer_ratio"] == 10.0
    assert 0.99 <= optimum["p95_peak_base_disp_in"] <= 1.0 and optimum["disp_limit_met"]
    assert optimum["mean_peak_base_disp_in"] < optimum["p95_peak_base_disp_in"]
    assert 0.5 <= optimum["capacity_in"] <= 3.0 and summary["gradient_rel_error"] < 1e-4
    assert "95th-percentile peak base displacement" in printed.out
