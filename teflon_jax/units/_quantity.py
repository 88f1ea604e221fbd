"""Named unit constants and a small parser for quantities written with units.

Everything inside teflon-jax is SI (m, s, N, Pa, kg). The paper's inches, kips and psi
appear only at the boundaries (loaders, CLI, reports) and go through these constants.
"""

import re

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

# dimension -> {unit spelling: factor to SI}
UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "cm": CM, "mm": MM, "in": INCH, "ft": FOOT},
    "force": {"N": 1.0, "kN": KN, "kip": KIP, "lbf": LBF, "lb": LBF},
    "pressure": {"Pa": 1.0, "kPa": KPA, "MPa": MPA, "psi": PSI, "ksi": KSI},
    "area": {"m^2": 1.0, "cm^2": CM**2, "mm^2": MM**2, "in^2": INCH**2},
    "time": {"s": 1.0, "ms": 1.0e-3, "min": 60.0},
    "frequency": {"Hz": 1.0, "rad/s": 1.0 / (2.0 * 3.141592653589793)},
    "velocity": {"m/s": 1.0, "cm/s": CM, "mm/s": MM, "in/s": INCH},
    "acceleration": {
        "m/s^2": 1.0,
        "cm/s^2": CM,
        "in/s^2": INCH,
        "g": STANDARD_GRAVITY,
    },
    "temperature": {"degC": 1.0},
    "dimensionless": {"": 1.0},
}

_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")


def unit_factor(unit: str, dimension: str, *, where: str) -> float:
    """Factor that converts `unit` of `dimension` to SI, or a `ValueError` naming `where`."""
    table = UNITS[dimension]
    if unit in table:
        return table[unit]
    for other, other_table in UNITS.items():
        if unit in other_table and other != "dimensionless":
            raise ValueError(
                f"{where}: '{unit}' is a unit of {other}, but a {dimension} is expected; "
                f"use one of {', '.join(u for u in table if u)}."
            )
    raise ValueError(
        f"{where}: unknown {dimension} unit '{unit}'; "
        f"use one of {', '.join(u for u in table if u)}."
    )


def parse_quantity(
    text: str, dimension: str, *, where: str, default_unit: str | None = None
) -> float:
    """Parse a number with a unit, such as `'1000psi'`, `'4 in'` or `'0.6Hz'`, into SI.

    **Arguments:**

    - `text`: the number followed by its unit (a space between them is allowed).
    - `dimension`: one of the keys of `UNITS` ("length", "force", "pressure", ...).
    - `where`: the parameter or file position to name in an error (e.g. `"--amplitude"`).
    - `default_unit`: unit assumed when `text` is a bare number; `None` makes a bare
      number an error (so that `--amplitude 4` cannot be read as 4 m by accident).

    **Returns:** the value in SI units.
    """
    match = _NUMBER.match(str(text))
    if match is None:
        raise ValueError(
            f"{where}: cannot read '{text}' as a number with a unit; write e.g. "
            f"'{_example(dimension)}'."
        )
    number, unit = match.groups()
    if unit == "":
        if default_unit is None and dimension != "dimensionless":
            raise ValueError(
                f"{where}: '{text}' has no unit; write e.g. '{_example(dimension)}' "
                f"(accepted units: {', '.join(u for u in UNITS[dimension] if u)})."
            )
        unit = default_unit or ""
    return float(number) * unit_factor(unit, dimension, where=where)


def _example(dimension: str) -> str:
    return {
        "length": "4in",
        "force": "78.5kip",
        "pressure": "1000psi",
        "frequency": "0.6Hz",
        "time": "20s",
        "area": "78.5in^2",
        "velocity": "15in/s",
        "acceleration": "0.35g",
    }.get(dimension, "1.0")
