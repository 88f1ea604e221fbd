"""`teflon-jax design --isolator single-fp`: the radius R of a single friction pendulum as the
isolator's design variable. The derivatives BFGS uses (forward mode through the simulation,
`forward_mode_gradient`) agree with central differences in R and in the friction, the
command picks the R at which the mean peak base displacement meets the limit, reports R and
its period 2 pi sqrt(R / g), and refuses what does not apply to a pendulum."""

import json
import math

import jax
import jax.numpy as jnp
import pytest

from teflon_jax.bearing import concave_surface
from teflon_jax.cli import main
from teflon_jax.excitation import StochasticGroundMotion, sample, uniform_signal
from teflon_jax.studies import expected_response, gradient_check, penalised_objective
from teflon_jax.studies._design import forward_mode_gradient
from teflon_jax.systems import isolated_structure, peak_response
from teflon_jax.units import INCH, PSI, STANDARD_GRAVITY

DT = 0.01
RADIUS = 1.5  # m: T_b = 2.46 s


@pytest.fixture(scope="module")
def problem():
    """Four short motions and the rigid mass on a pendulum, solved as `design` solves it."""
    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=4.0, time_step=DT, rise_time=0.5,
                                   strong_motion_duration=2.0)
    records = sample(model, jax.random.key(3), 4)
    structure = isolated_structure("rigid", isolator=concave_surface(RADIUS), isolation_period=None,
                                   pressure=1000 * PSI, time_step=0.0025, split_at_turn=False,
                                   newton_tolerance=0.0, linear_rule="newmark")
    return structure, records


def _smooth(structure, records):
    """The command's smoothed statistics, their reverse-mode derivative taken in forward mode."""
    def statistics(x):
        r = expected_response(structure, x, records, DT)
        return {"shear": r["shear"], "disp": r["disp"]}

    return forward_mode_gradient(statistics)


@pytest.mark.parametrize("friction", [
    {"pressure": 1500 * PSI},
    # d/dR and d/df_max against central differences: in the fast set by the next test
    pytest.param({"f_max": 0.1}, marks=pytest.mark.slow)])
def test_objective_gradient_in_radius_and_friction_matches_central_differences(problem, friction):
    """J = E[V_s] + rho max(0, E[D_s] / D_limit - 1)^2 with the penalty active, and its two
    parts: d/dR and d/d(friction) against (f(x + h) - f(x - h)) / (2 h), h = 1e-5 |x|."""
    structure, records = problem
    smooth = _smooth(structure, records)
    x = {"radius": RADIUS, **friction}
    limit = 0.9 * float(smooth(x)["disp"])  # the penalty is active: J depends on the displacement too

    def statistics(z):
        parts = smooth(z)
        return {**parts, "objective": penalised_objective(parts, limit, 100.0)}

    jacobian = jax.jit(jax.jacrev(statistics))(x)  # the reverse mode BFGS calls
    value = jax.jit(statistics)
    for name in x:
        h = 1e-5 * abs(x[name])
        plus, minus = value(dict(x, **{name: x[name] + h})), value(dict(x, **{name: x[name] - h}))
        for part in ("objective", "shear", "disp"):
            fd = (float(plus[part]) - float(minus[part])) / (2 * h)
            assert float(jacobian[part][name]) == pytest.approx(fd, rel=1e-4), (name, part)
    # the signs of the physics: a flatter surface (larger R) moves the base further and
    # lowers the restoring force; more friction holds the base back
    assert float(jacobian["disp"]["radius"]) > 0 > float(jacobian["shear"]["radius"])
    if "f_max" in x:
        assert float(jacobian["disp"]["f_max"]) < 0


def test_gradient_of_the_95th_percentile_displacement_matches_central_differences(problem):
    """The 95th percentile over the motions of the smoothed peak base displacement (linear
    interpolation between the two largest of four motions): its derivative in R and f_max."""
    structure, records = problem
    duration = (records.shape[1] - 1) * DT  # as `expected_response`

    def percentile(x):
        def one(values):
            system = structure(uniform_signal(values, DT), x)
            return peak_response(system, duration, disp_width=1e-3, shear_width=1e-3).smooth_base_disp

        return {"p95": jnp.percentile(jax.vmap(one)(records), 95.0)}

    p95 = forward_mode_gradient(percentile)
    gradient, differences, error = gradient_check(lambda z: p95(z)["p95"], {"radius": RADIUS, "f_max": 0.1},
                                                  relative_step=1e-5)
    assert error < 1e-4, (gradient, differences)
    assert gradient["radius"] > 0 > gradient["f_max"]


@pytest.mark.parametrize("flags, message", [
    (["--isolator", "single-fp", "--period-range", "1s", "3s"], "--period-range: does not apply to --isolator single-fp"),
    (["--radius-range", "40in", "80in"], "--radius-range: does not apply to --isolator flat"),
    (["--isolator", "single-fp", "--radius-range", "0in", "80in"], "--radius-range: must be > 0in"),
    (["--isolator", "single-fp", "--radius-range", "80in", "40in"], "--radius-range: LOW must be below HIGH"),
    (["--isolator", "single-fp", "--radius-range", "40", "80in"], "--radius-range"),
    (["--isolator", "single-fp", "--pressure", "1000psi", "--pressure-range", "1000psi", "2000psi"],
     "--pressure: fixes the friction, which --pressure-range designs"),
    (["--isolator", "single-fp", "--f-max-range", "0.1", "0.2", "--pressure-range", "1000psi", "2000psi"],
     "--f-max-range: designs f_max instead of the pressure"),
    (["--isolator", "single-fp", "--f-max-range", "0.05", "0.2"], "--f-max-range: the low end 0.05 lies below delta_f"),
    (["--isolator", "single-fp", "--pressure", "9000psi"], "--pressure: 9000psi is outside Table 1's rows"),
])
def test_bad_design_flags_are_refused_by_name(flags, message, capsys):
    assert main(["--no-compile-cache", "design", "--motions", "2", "--no-progress", *flags]) == 2
    assert message in capsys.readouterr().err


def _design(tmp_path, capsys, limit, grid):
    out = tmp_path / "design.json"
    code = main(["--no-compile-cache", "design", "--isolator", "single-fp", "--motions", "2", "--duration", "6s",
                 "--strong-motion", "2s", "--radius-range", "20in", "160in", "--pressure", "1000psi",
                 "--grid", str(grid), "--disp-limit", limit, "--json", str(out), "--no-progress"])
    captured = capsys.readouterr()
    return code, captured.out + captured.err, json.loads(out.read_text())


@pytest.mark.slow  # grid sweep, BFGS and the gradient check compile: ~60 s on 2 busy cores
def test_design_picks_the_radius_for_a_displacement_limit(tmp_path, capsys):
    code, printed, summary = _design(tmp_path, capsys, "1in", 8)
    assert code == 0, printed
    optimum = summary["optimum"]
    assert summary["isolator"] == "single-fp" and summary["disp_limit_in"] == pytest.approx(1.0)
    radius = optimum["radius_in"] * INCH
    assert 20 * INCH < radius < 160 * INCH and optimum["at_bounds"] == []
    assert optimum["isolation_period_s"] == pytest.approx(2 * math.pi * math.sqrt(radius / STANDARD_GRAVITY),
                                                          rel=1e-12)
    # the limit binds: met on the true mean peak, and not by a needlessly stiff surface
    assert 0.99 <= optimum["mean_peak_base_disp_in"] <= 1.0 and optimum["disp_limit_met"]
    assert optimum["converged"] and summary["gradient_rel_error"] < 1e-4
    assert f"optimum: R = {optimum['radius_in']:.4g} in (Tb = {optimum['isolation_period_s']:.4g} s)" in printed


@pytest.mark.slow  # ~50 s on 2 busy cores
def test_an_unmeetable_limit_exits_1_and_says_so(tmp_path, capsys):
    code, printed, summary = _design(tmp_path, capsys, "0.3in", 3)
    assert code == 1
    assert "breaks --disp-limit 0.3in" in printed and "widen --radius-range" in printed
    assert summary["optimum"]["disp_limit_met"] is False
    assert summary["optimum"]["mean_peak_base_disp_in"] > 0.3
