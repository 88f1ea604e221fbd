"""The gradient check of a design whose central stencil straddles a kink other than the
largest peak's restrainer contact: here the capacity d a fraction 1e-7 below the SMALLER of two
motions' peaks without restrainer, P_1 (Zayas, Low & Mahin 1990, Earthquake Spectra 6(2)).
For d >= P_1 that motion never reaches the restrainer and adds nothing to the derivative in d;
below P_1 it does: the mean response has a kink at d = P_1, and the design, on its contact side,
has the derivative of the piece that extends to smaller d. The kink's place is read from an
independent pendulum without restrainer, motion by motion.
"""

import jax
import pytest

from teflon_jax.bearing import concave_surface
from teflon_jax.excitation import StochasticGroundMotion, sample
from teflon_jax.studies import (
    CONTACT_TOLERANCE,
    GRADIENT_TOLERANCE,
    design_bounds,
    design_gradient_check,
    expected_response,
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
    structure = isolated_structure("rigid", isolator="single-fp", surface=surface, isolation_period=None,
                                   **SETTINGS)
    free = isolated_structure("rigid", isolator="single-fp", radius=RADIUS, isolation_period=None, **SETTINGS)
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


def _capacity_report(check):
    return next(r for r in check["kink_checks"] if r["variable"] == "capacity")


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


def test_a_wrong_derivative_at_the_kink_still_fails(problem):
    structure, records, bounds, (smaller, _) = problem
    x = {"radius": RADIUS, "capacity": smaller * (1 - 1e-7)}
    check = design_gradient_check(structure, _response(structure, records, scale=1.5), x, bounds)
    report = _capacity_report(check)
    assert report["kink"] and report["side"] == "backward"
    # the derivative 1.5 times the difference on its own side: relative error 1 - 1 / 1.5
    assert report["rel_error"] == pytest.approx(1 / 3, rel=1e-3)
    assert check["rel_error"] > GRADIENT_TOLERANCE
    assert any("gradient check failed" in m for m in check["messages"])


def test_between_the_peaks_the_central_check_stands_and_catches_a_wrong_derivative(problem):
    structure, records, bounds, (smaller, largest) = problem
    x = {"radius": RADIUS, "capacity": 0.5 * (smaller + largest)}  # one motion in contact, far from both kinks
    check = design_gradient_check(structure, _response(structure, records), x, bounds)
    assert check["check"] == "central" and check["kink_checks"] == ()
    assert check["rel_error"] == check["central_rel_error"] <= GRADIENT_TOLERANCE
    wrong = design_gradient_check(structure, _response(structure, records, scale=1.5), x, bounds)
    report = _capacity_report(wrong)
    # the one-sided slopes agree with each other: no kink, so the central verdict stands
    assert not report["kink"] and report["rel_error"] is None and wrong["check"] == "central"
    assert wrong["rel_error"] == pytest.approx(1 / 3, rel=1e-3)
    assert any("no kink within the stencil" in m for m in wrong["messages"])
