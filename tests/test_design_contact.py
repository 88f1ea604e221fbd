"""The gradient check of a single friction pendulum's design where its largest peak just
touches the restrainer (capacity d = P_0, the largest peak without restrainer).

Beyond P_0 the restrainer k_r max(|u| - d, 0) is never reached and every response is the
restrainer-free one, whatever d (its derivative in d is exactly zero); below P_0 it is
reached and the peaks change with d: a kink. A central difference there straddles it; the
one-sided differences from the kink agree with the forward-mode derivative of the side each
enters, and a derivative made wrong on purpose (its chain rule through d scaled) still fails.
Reference: Zayas, Low & Mahin (1990), Earthquake Spectra 6(2).
"""

import json

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
    optimise_design,
    restrainer_contact_check,
)
from teflon_jax.systems import isolated_structure
from teflon_jax.units import PSI

DT = 0.01
RADIUS, WEIGHT = 1.5, 100e3  # m, N (the rigid mass's)
SETTINGS = {"pressure": 1000 * PSI, "time_step": 0.005, "split_at_turn": False, "newton_tolerance": 0.0,
            "linear_rule": "newmark"}
VARIABLES = {"radius": (1.0, 2.5), "capacity": (0.005, 0.1)}
OUTPUTS = ("shear", "disp")


@pytest.fixture(scope="module")
def problem():
    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=3.0, time_step=DT, rise_time=0.5,
                                   strong_motion_duration=1.5)
    records = sample(model, jax.random.key(3), 2)
    surface = concave_surface(RADIUS, displacement_capacity=0.05, restrainer_stiffness=10 * WEIGHT / RADIUS)
    structure = isolated_structure("rigid", isolator=surface, isolation_period=None,
                                   **SETTINGS)
    # the largest peak of the pendulum without any restrainer (an independent structure)
    free = isolated_structure("rigid", isolator=concave_surface(RADIUS), isolation_period=None, **SETTINGS)
    largest = float(expected_response(free, {}, records, DT)["peak_disp_max"])
    return structure, records, design_bounds(structure, VARIABLES), largest


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


def _compiled(response):
    """(value, jacobian) of `restrainer_contact_check`: z -> {output: float}, z -> {output: {name: float}}."""
    keys = ("shear", "disp", "peak_disp_max")
    outputs = jax.jit(lambda z: {k: response(z)[k] for k in keys})
    forward = jax.jit(jax.jacfwd(lambda z: {k: response(z)[k] for k in keys}))

    def value(z):
        return {k: float(v) for k, v in outputs(z).items()}

    def jacobian(z):
        return {k: {n: float(v) for n, v in d.items()} for k, d in forward(z).items()}

    return value, jacobian


@pytest.fixture(scope="module")
def compiled(problem):
    structure, records, _, _ = problem
    return _compiled(_response(structure, records))


def _central(value, x, name, h):
    plus, minus = value(dict(x, **{name: x[name] + h})), value(dict(x, **{name: x[name] - h}))
    return {k: (plus[k] - minus[k]) / (2 * h) for k in ("shear", "disp")}


@pytest.fixture(scope="module")
def kink(problem, compiled):
    """(x, its contact report) with the restrainer barely reached: d = P_0 (1 - 1e-7)."""
    _, _, bounds, largest = problem
    x = {"radius": RADIUS, "capacity": largest * (1 - 1e-7)}
    return x, restrainer_contact_check(*compiled, x, bounds, OUTPUTS)


def test_the_kink_is_found_at_the_largest_peak_without_restrainer(problem, compiled, kink):
    largest = problem[3]
    value, jacobian = compiled
    x, contact = kink
    assert contact["at_contact"] and contact["tolerance"] == CONTACT_TOLERANCE
    assert contact["free_largest_peak"] == pytest.approx(largest, rel=1e-12)
    assert contact["gap"] == pytest.approx(-1e-7, rel=1e-3)  # (d - P_0) / d
    assert x["capacity"] < contact["largest_peak"] < largest  # reached, and pushed back

    # central differences straddle the kink: the two slopes averaged, the old failure
    derivative, central = jacobian(x)["disp"]["capacity"], _central(value, x, "capacity", 1e-5 * x["capacity"])
    assert abs(derivative - central["disp"]) > 0.1 * abs(derivative)

    # one-sided from the kink, each side's derivative agrees
    assert contact["rel_error"] <= GRADIENT_TOLERANCE
    by = {(c["variable"], c["direction"]): c for c in contact["checks"]}
    assert set(by) == {("capacity", "forward"), ("capacity", "backward"), ("radius", "forward"),
                       ("radius", "backward")}
    free, reached = by["capacity", "forward"], by["capacity", "backward"]
    assert (free["side"], reached["side"]) == ("free", "contact")
    # beyond the kink the capacity changes nothing; below it a larger d lets the base travel further
    assert free["derivative"] == {"shear": 0.0, "disp": 0.0}
    assert all(abs(v) < 1e-9 for v in free["one_sided_difference"].values())  # rounding of f(x_0) alone
    assert reached["derivative"]["disp"] > 0 and reached["one_sided_difference"]["disp"] > 0
    # a larger radius softens the pendulum and lets the largest peak grow past d: its forward
    # stencil enters the contact side
    assert by["radius", "forward"]["side"] == "contact" and by["radius", "backward"]["side"] == "free"


def test_away_from_the_kink_there_is_no_contact_and_central_differences_agree(problem, compiled):
    _, _, bounds, largest = problem
    value, jacobian = compiled
    x = {"radius": RADIUS, "capacity": largest * (1 + 3 * CONTACT_TOLERANCE)}
    contact = restrainer_contact_check(value, jacobian, x, bounds, OUTPUTS)
    assert not contact["at_contact"] and "checks" not in contact
    assert contact["largest_peak"] == contact["free_largest_peak"] == pytest.approx(largest, rel=1e-12)
    gradient = jacobian(x)
    for name in VARIABLES:
        central = _central(value, x, name, 1e-5 * x[name])
        for k in OUTPUTS:
            assert gradient[k][name] == pytest.approx(central[k], rel=GRADIENT_TOLERANCE, abs=1e-12), (k, name)
    assert gradient["disp"]["capacity"] == 0.0 and gradient["shear"]["radius"] != 0.0


@pytest.mark.slow
def test_a_wrong_derivative_in_the_capacity_fails_the_one_sided_check(problem):
    """Through `design_gradient_check`, as `optimise_design` calls it."""
    structure, records, bounds, largest = problem
    x = {"radius": RADIUS, "capacity": largest * (1 - 1e-7)}
    check = design_gradient_check(structure, _response(structure, records, scale=1.5), x, bounds)
    assert check["restrainer_contact"]["at_contact"]
    reached = next(c for c in check["restrainer_contact"]["checks"] if c["side"] == "contact"
                   and c["variable"] == "capacity")
    # the derivative 1.5 times the difference: relative error 1 - 1 / 1.5
    assert reached["rel_error"] == pytest.approx(1 / 3, rel=1e-3)
    assert check["rel_error"] == check["restrainer_contact"]["rel_error"] > GRADIENT_TOLERANCE
    assert any("restrainer contact" in m and "one-sided" in m for m in check["messages"])
    assert any("gradient check failed" in m for m in check["messages"])


def test_the_design_summary_reports_the_contact_and_exits_0_when_the_one_sided_check_passes(kink, capsys):
    from types import SimpleNamespace

    from teflon_jax.cli._common import output_units
    from teflon_jax.cli._design import _contact_fields, _verdict
    from teflon_jax.units import INCH

    _, contact = kink
    fields = json.loads(json.dumps(_contact_fields(contact, 0.5, output_units("us"))))
    assert fields["at_contact"] and fields["central_rel_error"] == 0.5
    assert fields["one_sided_rel_error"] == contact["rel_error"] and len(fields["one_sided_checks"]) == 4
    assert fields["free_largest_peak_in"] == pytest.approx(contact["free_largest_peak"] / INCH, rel=1e-12)
    assert fields["relative_gap"] == contact["gap"] and fields["tolerance"] == CONTACT_TOLERANCE
    result = SimpleNamespace(messages=(), at_bounds=(), simulation_converged=True, optimiser_converged=True,
                             n_failed_motions=0, steps=12, limit_met=True, gradient_rel_error=contact["rel_error"])
    assert _verdict(result, None) == 0 and capsys.readouterr().err == ""


@pytest.mark.slow  # BFGS and its checks compile four times: ~30 s CPU, 1.5 min on 2 busy cores
def test_bfgs_started_below_the_kink_ends_on_it_and_the_design_is_accepted(problem):
    """Below P_0 the base shear falls as d grows (the restrainer pushes back less), beyond it
    nothing changes: BFGS started a fraction 1e-6 below the kink ends on it, where central
    differences fail and the one-sided check passes."""
    structure, records, _, largest = problem
    result = optimise_design(structure, records, DT, variables={"capacity": (0.5 * largest, 1.5 * largest)},
                             disp_limit=1.0, start={"capacity": largest * (1 - 1e-6)})
    contact = result.restrainer_contact
    assert contact["at_contact"] and abs(result.optimum["capacity"] / largest - 1) <= CONTACT_TOLERANCE
    assert result.central_rel_error > 0.1 and result.gradient_rel_error == contact["rel_error"]
    assert result.converged and result.gradient_rel_error <= GRADIENT_TOLERANCE, result.messages
    assert any("sits at the restrainer contact" in m for m in result.messages)
