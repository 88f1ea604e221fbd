"""The gradient check of a design whose central stencil straddles a kink other than the
largest peak's restrainer contact: here the capacity d a fraction 1e-7 below the SMALLER of two
motions' peaks without restrainer, P_1 (Zayas, Low & Mahin 1990, Earthquake Spectra 6(2)).
For d >= P_1 that motion never reaches the restrainer and adds nothing to the derivative in d;
below P_1 it does: the mean response has a kink at d = P_1, and the design, on its contact side,
has the derivative of the piece that extends to smaller d. The kink's place is read from an
independent pendulum without restrainer, motion by motion.
"""

import json
from types import SimpleNamespace

import jax
import numpy as np
import pytest

from teflon_jax.bearing import concave_surface
from teflon_jax.excitation import StochasticGroundMotion, sample
from teflon_jax.studies import (
    CONTACT_TOLERANCE,
    GRADIENT_TOLERANCE,
    design_bounds,
    design_gradient_check,
    expected_response,
    kink_gradient_check,
)
from teflon_jax.systems import isolated_structure
from teflon_jax.units import PSI

DT = 0.01
RADIUS, WEIGHT = 1.5, 100e3  # m, N (the rigid mass's)
SETTINGS = {"pressure": 1000 * PSI, "time_step": 0.005, "split_at_turn": False, "newton_tolerance": 0.0,
            "linear_rule": "newmark"}
VARIABLES = {"radius": (1.0, 2.5), "capacity": (0.005, 0.1)}


@pytest.fixture(scope="module")
def problem():
    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=3.0, time_step=DT, rise_time=0.5,
                                   strong_motion_duration=1.5)
    records = sample(model, jax.random.key(3), 2)
    surface = concave_surface(RADIUS, displacement_capacity=0.05, restrainer_stiffness=10 * WEIGHT / RADIUS)
    structure = isolated_structure("rigid", isolator=surface, isolation_period=None,
                                   **SETTINGS)
    free = isolated_structure("rigid", isolator=concave_surface(RADIUS), isolation_period=None, **SETTINGS)
    peaks = sorted(float(expected_response(free, {}, records[i:i + 1], DT)["peak_disp_max"]) for i in range(2))
    return structure, records, design_bounds(structure, VARIABLES), peaks


def _response(structure, records, scale=None):
    """x -> `expected_response`; with `scale`, the chain rule through the capacity multiplied
    by it (the values untouched): a wrong derivative computed by the simulation itself."""

    @jax.custom_jvp
    def capacity(d):
        return d

    @capacity.defjvp
    def _(primals, tangents):
        return primals[0], scale * tangents[0]

    def response(x):
        if scale is not None:
            x = dict(x, capacity=capacity(x["capacity"]))
        return expected_response(structure, x, records, DT)

    return response


X0, H, JUMP = 1.0, 1e-5, 0.3  # the point, the step and the slope jump of the kinks below


def _kinked(*kinks):
    """z -> {"disp": sin(x) + sum_i s_i JUMP max(s_i (x - a_i), 0)}: a sine with kinks at a_i,
    each raising the slope by JUMP on the side s_i = +1 (right) or -1 (left) of it."""
    def value(z):
        t = z["x"]
        return {"disp": np.sin(t) + sum(JUMP * max(s * (t - a), 0.0) for a, s in kinks)}

    return value


@pytest.mark.parametrize("kinks, side, derivative, within", [
    # a kink just ahead of x: its own piece extends backward, the slope there is cos(x)
    ([(X0 + 0.3 * H, 1)], "backward", np.cos(X0), (X0, X0 + 2 * H)),
    # a kink just behind x: its own piece extends forward, with the raised slope
    ([(X0 - 0.7 * H, 1)], "forward", np.cos(X0) + JUMP, (X0 - 2 * H, X0)),
    # a kink at x itself: forward mode takes either branch
    ([(X0, 1)], "backward", np.cos(X0), (X0, X0)),
    ([(X0, 1)], "forward", np.cos(X0) + JUMP, (X0, X0)),
    # kinks on both sides within the stencil: the step shrinks until none is inside
    ([(X0 + 0.5 * H, 1), (X0 - 0.8 * H, 1)], "central", np.cos(X0) + JUMP, (X0 - 2 * H, X0 + 2 * H)),
])
def test_a_kink_inside_the_stencil_is_found_and_the_derivative_checked_on_its_own_piece(
        kinks, side, derivative, within):
    value = _kinked(*kinks)
    x = {"x": X0}
    central = (value({"x": X0 + H})["disp"] - value({"x": X0 - H})["disp"]) / (2 * H)
    assert abs(central - derivative) > 10 * GRADIENT_TOLERANCE * abs(derivative)  # the central check fails
    report = kink_gradient_check(value, {"disp": derivative}, x, "x", H, GRADIENT_TOLERANCE)
    assert report["kink"] and report["side"] == side
    assert report["rel_error"] <= 1e-6, report
    low, high = report["kink_within"]
    assert within[0] <= low <= high <= within[1]
    assert all(low <= a <= high for a, _ in kinks if abs(a - X0) <= 2 * report["step"])
    # a wrong derivative (1.5 times the piece's, or the average of two slopes as a tie-splitting
    # max would give) agrees with no side
    for wrong in (1.5 * derivative, derivative + 0.5 * JUMP if side == "backward" else derivative - 0.5 * JUMP):
        bad = kink_gradient_check(value, {"disp": wrong}, x, "x", H, GRADIENT_TOLERANCE)
        assert bad["rel_error"] > 100 * GRADIENT_TOLERANCE, (wrong, bad)


def test_without_a_kink_the_central_verdict_stands():
    value = _kinked()
    report = kink_gradient_check(value, {"disp": 1.5 * np.cos(X0)}, {"x": X0}, "x", H, GRADIENT_TOLERANCE)
    assert not report["kink"] and report["rel_error"] is None and report["side"] is None
    assert report["consistent"] == {"forward": True, "backward": True}
    assert report["one_sided_differences"]["forward"]["disp"] == pytest.approx(np.cos(X0), rel=1e-8)


def _capacity_report(check):
    return next(r for r in check["kink_checks"] if r["variable"] == "capacity")


@pytest.mark.slow
def test_a_smaller_peak_touching_the_restrainer_is_found_and_checked_on_the_designs_side(problem):
    structure, records, bounds, (smaller, largest) = problem
    x = {"radius": RADIUS, "capacity": smaller * (1 - 1e-7)}
    assert largest - x["capacity"] > 10 * CONTACT_TOLERANCE * x["capacity"]  # not the largest peak's contact
    check = design_gradient_check(structure, _response(structure, records), x, bounds)
    assert not check["restrainer_contact"]["at_contact"]
    report = _capacity_report(check)
    # the central stencil straddles the kink at P_1, and no derivative agrees with it
    assert report["central_rel_error"] > 10 * GRADIENT_TOLERANCE
    assert report["kink"] and check["check"] == "piecewise"
    # the kink lies ahead of d (at P_1 = d (1 + 1e-7)): the forward stencils straddle it, the
    # backward ones lie on the design's own piece and agree with its forward-mode derivative
    assert report["consistent"] == {"forward": False, "backward": True} and report["side"] == "backward"
    low, high = report["kink_within"]
    assert low == x["capacity"] < smaller <= high
    assert report["rel_error"] <= GRADIENT_TOLERANCE and check["rel_error"] <= GRADIENT_TOLERANCE
    backward = report["one_sided_differences"]["backward"]["disp"]
    assert report["derivative"]["disp"] == pytest.approx(backward, rel=GRADIENT_TOLERANCE)
    # a larger d lets the motion still in contact travel further
    assert backward > 0
    assert any("capacity: central differences miss" in m and "a kink lies between" in m for m in check["messages"])
    assert not any("gradient check failed" in m for m in check["messages"])


@pytest.mark.slow
def test_a_wrong_derivative_at_the_kink_still_fails(problem, capsys):
    structure, records, bounds, (smaller, _) = problem
    x = {"radius": RADIUS, "capacity": smaller * (1 - 1e-7)}
    check = design_gradient_check(structure, _response(structure, records, scale=1.5), x, bounds)
    report = _capacity_report(check)
    assert report["kink"] and report["side"] == "backward"
    # the derivative 1.5 times the difference on its own side: relative error 1 - 1 / 1.5
    assert report["rel_error"] == pytest.approx(1 / 3, rel=1e-3)
    assert check["rel_error"] > GRADIENT_TOLERANCE
    assert any("gradient check failed" in m for m in check["messages"])
    code, err = _exit_status(check, capsys)
    assert code == 1 and "differs from finite differences" in err


def _exit_status(check, capsys):
    """The exit status `teflon-jax design` gives a design with this gradient check (and stderr)."""
    from teflon_jax.cli._design import _verdict

    result = SimpleNamespace(messages=(), at_bounds=(), simulation_converged=True, optimiser_converged=True,
                             n_failed_motions=0, steps=12, limit_met=True, gradient_rel_error=check["rel_error"])
    return _verdict(result, None), capsys.readouterr().err


def test_between_the_peaks_the_central_check_stands(problem):
    structure, records, bounds, (smaller, largest) = problem
    x = {"radius": RADIUS, "capacity": 0.5 * (smaller + largest)}  # one motion in contact, far from both kinks
    check = design_gradient_check(structure, _response(structure, records), x, bounds)
    assert check["check"] == "central" and check["kink_checks"] == ()
    assert check["rel_error"] == check["central_rel_error"] <= GRADIENT_TOLERANCE


@pytest.mark.slow  # two compilations and the kink analysis: ~30 s on 2 busy cores
def test_a_wrong_derivative_between_the_peaks_finds_no_kink_and_fails(problem, capsys):
    structure, records, bounds, (smaller, largest) = problem
    x = {"radius": RADIUS, "capacity": 0.5 * (smaller + largest)}
    wrong = design_gradient_check(structure, _response(structure, records, scale=1.5), x, bounds)
    report = _capacity_report(wrong)
    # the one-sided slopes agree with each other: no kink, so the central verdict stands
    assert not report["kink"] and report["rel_error"] is None and wrong["check"] == "central"
    assert wrong["rel_error"] == pytest.approx(1 / 3, rel=1e-3)
    assert any("no kink within the stencil" in m for m in wrong["messages"])
    code, err = _exit_status(wrong, capsys)
    assert code == 1 and "differs from finite differences" in err


@pytest.mark.slow  # grid sweep, BFGS and the checks of two variables: ~1.5 min on 2 busy cores
def test_a_capacity_design_inside_the_restrainer_contact_ends_on_a_kink_and_is_accepted(tmp_path, capsys):
    """The limit on the 95th percentile binds with d some 9 % below the largest peak, where the
    largest excursions press on the restrainer. BFGS ends on a kink of the percentile in d (its
    one-sided slopes differ by some 4 %; those of the mean base shear do not): central
    differences straddle it (the check failed with 0.019 before); the one-sided differences
    agree with the forward-mode derivative."""
    from teflon_jax.cli import main

    out = tmp_path / "design.json"
    code = main(["--no-compile-cache", "design", "--isolator", "single-fp", "--motions", "4", "--duration", "6s",
                 "--strong-motion", "2s", "--radius-range", "60in", "160in", "--capacity-range", "0.5in", "1.2in",
                 "--pressure", "1000psi", "--grid", "4", "--disp-limit", "1.17in", "--limit-statistic", "p95",
                 "--json", str(out), "--no-progress"])
    printed = capsys.readouterr()
    summary = json.loads(out.read_text())
    assert code == 0, printed.err
    assert summary["optimum"]["converged"] and summary["optimum"]["disp_limit_met"]
    contact = summary["restrainer_contact"]
    assert not contact["at_contact"] and contact["relative_gap"] < -10 * CONTACT_TOLERANCE  # d well below P_0
    assert contact["largest_peak_in"] < contact["free_largest_peak_in"]  # the restrainer pushes back
    assert summary["gradient_check"] == "piecewise"
    assert summary["gradient_rel_error"] <= GRADIENT_TOLERANCE
    assert "gradient check (one-sided on the optimum's side of a kink)" in printed.out
    by = {r["variable"]: r for r in summary["kink_checks"]}
    report = by["capacity"]
    assert report["kink"] and report["central_rel_error"] > 10 * GRADIENT_TOLERANCE
    forward, backward = (report["one_sided_differences"][s] for s in ("forward", "backward"))
    assert abs(forward["disp"] - backward["disp"]) > 10 * GRADIENT_TOLERANCE * abs(forward["disp"])
    assert forward["shear"] == pytest.approx(backward["shear"], rel=GRADIENT_TOLERANCE)
    side = report["one_sided_differences"][report["side"]]
    for k in ("shear", "disp"):
        assert report["derivative"][k] == pytest.approx(side[k], rel=GRADIENT_TOLERANCE)
    assert any("capacity: central differences miss" in m for m in summary["messages"])
