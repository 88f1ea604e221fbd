"""The one quantity parser (`teflon_jax.units.parse_quantity`, on pint) and the rule every
quantity flag of the command line follows: a unit is required, defaults carry one, and errors
name the flag and echo the value as typed."""

import math
import re

import pytest

from teflon_jax.cli._common import QUANTITY_FLAGS, read_quantities
from teflon_jax.cli._main import _parser
from teflon_jax.units import INCH, KIP, PSI, STANDARD_GRAVITY, parse_quantity, unit_factor


@pytest.mark.parametrize("text, dimension, si", [
    ("4in", "length", 4 * 0.0254),
    ("100 mm", "length", 0.1),
    ("1000psi", "pressure", 1000 * 4.4482216152605 / 0.0254**2),
    ("6.9MPa", "pressure", 6.9e6),
    ("78.5kip", "force", 78.5e3 * 4.4482216152605),
    ("10lb", "force", 10 * 4.4482216152605),           # lb is a pound-force where a force is asked
    ("0.3g", "acceleration", 0.3 * 9.80665),          # g is standard gravity, not a gram
    ("0.6Hz", "frequency", 0.6),
    ("2.77rad/s", "frequency", 2.77 / (2 * math.pi)),   # angular -> cyclic
    ("60rpm", "frequency", 1.0),
    ("2.5ms", "time", 2.5e-3),
    ("5%", "dimensionless", 0.05),
    ("0.05", "dimensionless", 0.05),                   # a ratio needs no unit
    ("0.6s/in", "slowness", 0.6 / 0.0254),
    ("15 in/s", "velocity", 15 * 0.0254),
])
def test_values_with_units_are_read_into_si(text, dimension, si):
    assert parse_quantity(text, dimension, where="--x") == pytest.approx(si, rel=1e-12)


def test_named_constants_agree_with_the_parser():
    assert parse_quantity("1in", "length", where="x") == INCH
    assert parse_quantity("1kip", "force", where="x") == pytest.approx(KIP, rel=1e-12)
    assert parse_quantity("1psi", "pressure", where="x") == pytest.approx(PSI, rel=1e-12)
    assert parse_quantity("1g", "acceleration", where="x") == pytest.approx(STANDARD_GRAVITY, rel=1e-12)
    assert unit_factor("ksi", "pressure", where="x") == pytest.approx(1000 * PSI, rel=1e-12)


@pytest.mark.parametrize("text, dimension, message", [
    ("4", "length", "--x: '4' has no unit; write e.g. '4in'"),
    ("0.3", "acceleration", "--x: '0.3' has no unit; write e.g. '0.3g'"),
    ("4Hz", "length", "--x: 'Hz' is a unit of frequency, but a length is expected"),
    ("3in", "acceleration", "--x: 'in' is a unit of length, but an acceleration is expected"),
    ("4 furlong", "length", "--x: unknown length unit 'furlong'"),
    ("abc", "pressure", "--x: cannot read 'abc' as a number with a unit; write e.g. '1psi'"),
    ("5in", "dimensionless", "a ratio without unit is expected"),
])
def test_bad_values_are_refused_naming_the_place(text, dimension, message):
    with pytest.raises(ValueError) as error:
        parse_quantity(text, dimension, where="--x")
    assert message in str(error.value)


COMMANDS = ("simulate-test", "fit", "montecarlo", "design")


def _flags():
    _parser()
    return [q for q in QUANTITY_FLAGS if q.command in COMMANDS]


def test_every_quantity_flag_shows_its_default_with_a_unit_in_help():
    parser = _parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    flags = _flags()
    assert {q.flag for q in flags} >= {"--pressure", "--amplitude", "--frequency", "--pga", "--disp-limit",
                                       "--isolation-period", "--isolation-damping", "--period-range",
                                       "--pressure-range", "--duration", "--time-step", "--normal-load"}
    for q in flags:
        text = " ".join(sub.choices[q.command].format_help().split())
        if q.default is None:
            continue
        shown = " ".join(q.default) if isinstance(q.default, tuple) else q.default
        assert f"(default {shown})" in text, (q.command, q.flag)
        for value in ([shown] if q.nargs is None else shown.split()):
            parse_quantity(value, q.dimension, where=q.flag)
            if q.dimension != "dimensionless":
                assert re.search(r"\d\s*[A-Za-z]", value), (q.flag, value)  # written with its unit


@pytest.mark.parametrize("argv, message", [
    (["montecarlo", "--motions", "2", "--pga", "-0.3g"], "--pga: must be > 0g, got -0.3g."),
    (["montecarlo", "--motions", "2", "--pga", "0.3"], "--pga: '0.3' has no unit; write e.g. '0.3g'"),
    (["montecarlo", "--motions", "2", "--pressure", "1000"], "--pressure: '1000' has no unit"),
    (["montecarlo", "--motions", "2", "--isolation-period", "-2s"], "--isolation-period: must be > 0s"),
    (["montecarlo", "--motions", "2", "--duration", "40"], "--duration: '40' has no unit; write e.g. '40s'"),
    (["design", "--disp-limit", "3"], "--disp-limit: '3' has no unit; write e.g. '3in'"),
    (["design", "--disp-limit", "-80mm"], "--disp-limit: must be > 0mm, got -80mm."),
    (["design", "--period-range", "4s", "1s"], "--period-range: LOW must be below HIGH, got 4s 1s."),
    (["design", "--pressure-range", "1000", "3000psi"], "--pressure-range: '1000' has no unit"),
    (["simulate-test", "--amplitude", "4"], "--amplitude: '4' has no unit; write e.g. '4in'"),
])
def test_flag_errors_name_the_flag_and_echo_the_value(argv, message):
    args = _parser().parse_args(argv)
    with pytest.raises(ValueError) as error:
        read_quantities(args, args.command)
    assert message in str(error.value)


def test_flags_are_read_in_the_users_units():
    args = _parser().parse_args(["montecarlo", "--motions", "2", "--pressure", "6.9MPa", "--pga", "0.3g",
                                 "--isolation-period", "2.5s", "--isolation-damping", "5%",
                                 "--site-frequency", "2.5Hz", "--time-step", "2.5ms"])
    read_quantities(args, "montecarlo")
    assert (args.pressure, args.isolation_period, args.isolation_damping) == (6.9e6, 2.5, 0.05)
    assert args.pga == pytest.approx(0.3 * 9.80665)
    assert (args.site_frequency, args.time_step) == (2.5, 2.5e-3)
    assert args.pga_text == "0.3g"
    args = _parser().parse_args(["montecarlo", "--motions", "2", "--isolation-period", "none"])
    read_quantities(args, "montecarlo")
    assert args.isolation_period is None
    args = _parser().parse_args(["design", "--disp-limit", "80mm", "--period-range", "1.5s", "3s",
                                 "--pressure-range", "1000psi", "2ksi"])
    read_quantities(args, "design")
    assert args.disp_limit == pytest.approx(0.08)
    assert args.period_range == (1.5, 3.0)
    assert args.pressure_range == pytest.approx((1000 * PSI, 2000 * PSI))


def test_fixed_fit_parameters_take_units():
    from teflon_jax.cli._isolator_table import _parse_fixed

    fixed = _parse_fixed("yield_disp=0.005in,rate_a=0.6s/in,breakaway_ratio=1.5")
    assert fixed == pytest.approx({"yield_disp": 0.005 * INCH, "rate_a": 0.6 / INCH, "breakaway_ratio": 1.5})
    with pytest.raises(ValueError, match="--fixed yield_disp: '0.005' has no unit; write e.g. '0.005in'"):
        _parse_fixed("yield_disp=0.005")
    with pytest.raises(ValueError, match="--fixed rate_a: 'in' is a unit of length"):
        _parse_fixed("rate_a=0.6in")
