"""The one parser for quantities written with units, built on pint.

Everything inside teflon-jax is SI (m, s, N, Pa, kg). The paper's inches, kips and psi
appear only at the boundaries (loaders, command line, reports): there a value is written with
its unit (`'1000psi'`, `'4 in'`, `'0.3g'`, `'2.77rad/s'`, `'5%'`) and read by `parse_quantity`,
which checks its dimension and returns SI. Spellings follow pint's registry, with three
conventions of the trade on top: `g` is standard gravity (9.80665 m/s^2) where an acceleration
is expected, `lb` is a pound-force where a force is expected, and an angular frequency
(`rad/s`, `deg/s`, `rpm`) is turned into a cyclic one [Hz] (divided by 2 pi).
"""

import functools
import math
import re
from tokenize import TokenError  # raised by pint for unbalanced brackets

from ._constants import (
    CM,
    FOOT,
    INCH,
    KIP,
    KN,
    KPA,
    KSI,
    LBF,
    MM,
    MPA,
    PSI,
    STANDARD_GRAVITY,
)

# dimension -> {common unit spelling: factor to SI}; lists what messages suggest and what the
# record writers may emit. Every pint spelling of the right dimension is accepted on input.
UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "cm": CM, "mm": MM, "in": INCH, "ft": FOOT},
    "force": {"N": 1.0, "kN": KN, "kip": KIP, "lbf": LBF, "lb": LBF},
    "pressure": {"Pa": 1.0, "kPa": KPA, "MPa": MPA, "psi": PSI, "ksi": KSI},
    "area": {"m^2": 1.0, "cm^2": CM**2, "mm^2": MM**2, "in^2": INCH**2},
    "time": {"s": 1.0, "ms": 1.0e-3, "min": 60.0},
    "frequency": {"Hz": 1.0, "rad/s": 1.0 / (2.0 * math.pi)},
    "velocity": {"m/s": 1.0, "cm/s": CM, "mm/s": MM, "in/s": INCH},
    "acceleration": {
        "m/s^2": 1.0,
        "cm/s^2": CM,
        "in/s^2": INCH,
        "g": STANDARD_GRAVITY,
    },
    "slowness": {"s/m": 1.0, "s/in": 1.0 / INCH},
    "temperature": {"degC": 1.0},
    "dimensionless": {"": 1.0, "%": 0.01},
    "angle": {"rad": 1.0, "deg": math.pi / 180.0},
}

# dimension -> pint dimensionality string and SI unit
_PINT = {
    "length": ("[length]", "m"),
    "force": ("[force]", "N"),
    "pressure": ("[pressure]", "Pa"),
    "area": ("[area]", "m**2"),
    "time": ("[time]", "s"),
    "frequency": ("[frequency]", "1/s"),
    "velocity": ("[velocity]", "m/s"),
    "acceleration": ("[acceleration]", "m/s**2"),
    "slowness": ("[time]/[length]", "s/m"),
    "dimensionless": ("", ""),
}

_EXAMPLES = {
    "length": "in",
    "force": "kip",
    "pressure": "psi",
    "frequency": "Hz",
    "time": "s",
    "area": "in^2",
    "velocity": "in/s",
    "acceleration": "g",
    "slowness": "s/m",
    "dimensionless": "",
    "angle": "deg",
}

# The words a unit may be built from (pint combines them: 'kN/m^2', 'in/s', 's/in').
_VOCABULARY = {
    "m", "cm", "mm", "km", "meter", "metre", "in", "inch", "ft", "foot", "feet",
    "N", "kN", "MN", "kip", "kips", "lbf", "lb", "lbs", "newton",
    "Pa", "kPa", "MPa", "GPa", "psi", "ksi", "pascal",
    "s", "ms", "min", "h", "sec", "second", "seconds",
    "Hz", "kHz", "rad", "radian", "deg", "degree", "rpm", "cycle", "turn",
    "g", "g_n", "Gal", "%", "percent",
}

_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")


@functools.cache
def _registry():
    import pint

    return pint.UnitRegistry(cache_folder=":auto:")


def _pint_units(unit: str, dimension: str):
    """pint's reading of `unit` (a string) with the trade's spellings, or `None`."""
    import pint

    text = unit.strip().replace("^", "**")
    if not set(re.findall(r"[A-Za-z_%]+", text)) <= _VOCABULARY:
        return None
    if dimension == "acceleration":
        text = re.sub(r"(?<![A-Za-z_])g(?![A-Za-z_0-9])", "g_n", text)
    if dimension == "force":
        text = re.sub(r"(?<![A-Za-z_])lbs?(?![A-Za-z_0-9])", "lbf", text)
    if text == "%":
        text = "percent"
    try:
        return _registry().Quantity(1.0, text)
    except (pint.errors.PintError, AttributeError, TypeError, ValueError, SyntaxError,
            AssertionError, KeyError, TokenError):
        return None


def _dimension_of(quantity) -> str | None:
    for name, (dimensionality, _) in _PINT.items():
        if quantity.check(dimensionality or "[]"):
            return name
    return None


def _accepted(dimension: str) -> str:
    if dimension == "dimensionless":
        return "a plain number or a percentage, e.g. 0.05 or 5%"
    return ", ".join(u for u in UNITS[dimension] if u)


def _use(dimension: str) -> str:
    if dimension == "dimensionless":
        return "write " + _accepted(dimension)
    return "use one of " + _accepted(dimension)


def _a(dimension: str) -> str:
    """The dimension with its article, as a message says it ('an acceleration', 'a ratio')."""
    if dimension == "dimensionless":
        return "a ratio without unit"
    return ("an " if dimension[0] in "aeiou" else "a ") + dimension


def unit_factor(unit: str, dimension: str, *, where: str) -> float:
    """Factor that converts `unit` of `dimension` to SI, or a `ValueError` naming `where`.

    **Arguments:** `unit` (e.g. `'in'`, `'kip'`, `'rad/s'`), `dimension` (a key of `UNITS`),
    `where` (the flag, file position or key to name in an error).

    **Returns:** the SI value of one `unit` (a cyclic frequency [Hz] for angular ones).
    """
    if dimension not in UNITS:
        raise ValueError(f"{where}: unknown dimension '{dimension}'; known: {', '.join(UNITS)}.")
    if unit in UNITS[dimension]:
        return UNITS[dimension][unit]
    if dimension not in _PINT:
        raise ValueError(f"{where}: unknown {dimension} unit '{unit}'; {_use(dimension)}.")
    quantity = _pint_units(unit, dimension)
    if quantity is None:
        raise ValueError(
            f"{where}: unknown {dimension} unit '{unit}'; {_use(dimension)}."
        )
    dimensionality, si = _PINT[dimension]
    if not quantity.check(dimensionality or "[]"):
        other = _dimension_of(quantity)
        kind = f"a unit of {other}" if other else f"a unit of {quantity.dimensionality}"
        raise ValueError(
            f"{where}: '{unit}' is {kind}, but {_a(dimension)} is expected; "
            f"{_use(dimension)}."
        )
    value = float(quantity.to(si).magnitude) if si else float(quantity.to("").magnitude)
    if dimension == "frequency" and dict(quantity.to_root_units().unit_items()).get("radian"):
        value /= 2.0 * math.pi
    return value


def is_unit(text: str) -> bool:
    """Whether `text` reads as a unit of any dimension (`'ms'`, `'g'`, `'cm/s^2'`, `'m'`),
    rather than a word or label (`'N-S'`, `'E-W'`)."""
    return any(_pint_units(text, dimension) is not None for dimension in ("acceleration", "force"))


def parse_quantity(
    text: str, dimension: str, *, where: str, default_unit: str | None = None
) -> float:
    """Parse a number with a unit, such as `'1000psi'`, `'4 in'`, `'0.3g'` or `'0.6Hz'`, into SI.

    **Arguments:**

    - `text`: the number followed by its unit (a space between them is allowed).
    - `dimension`: one of the keys of `UNITS` ("length", "force", "pressure", ...).
    - `where`: the flag or file position to name in an error (e.g. `"--amplitude"`).
    - `default_unit`: unit assumed when `text` is a bare number; `None` makes a bare
      number an error for every dimensional quantity (so that `--amplitude 4` cannot be
      read as 4 m, or 4 in, by accident). A bare number is always fine for a ratio.

    **Returns:** the value in SI units.
    """
    match = _NUMBER.match(str(text))
    if match is None:
        raise ValueError(
            f"{where}: cannot read '{text}' as a number with a unit; write e.g. "
            f"'{example(dimension)}'."
        )
    number, unit = match.groups()
    if unit == "":
        if default_unit is None and dimension != "dimensionless":
            raise ValueError(
                f"{where}: '{text}' has no unit; write e.g. '{number}{_EXAMPLES.get(dimension, '')}' "
                f"(accepted units: {_accepted(dimension)})."
            )
        unit = default_unit or ""
    return float(number) * unit_factor(unit, dimension, where=where)


def example(dimension: str, number: str = "1") -> str:
    """A value of `dimension` written as the parser reads it, e.g. `'1in'`."""
    return f"{number}{_EXAMPLES.get(dimension, '')}"
