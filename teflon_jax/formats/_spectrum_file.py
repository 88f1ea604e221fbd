"""Reader of a target spectrum: two columns, period and spectral acceleration, with units.

Format: the first line that is not blank or a `#` comment names the two columns with their
units in brackets, e.g. `period [s], Sa [g]` (separated by a comma or whitespace); then one
row per period, `0.5, 1.05` or `0.5 1.05`, periods strictly increasing and > 0, accelerations
>= 0 and not all 0. Any unit of time and acceleration `teflon_jax.units` reads is accepted.
Every problem is a `ValueError` naming the file, the line (1-based) and the column.
"""

import math
import pathlib
import re

import numpy as np

from ..units import parse_quantity

_UNIT = re.compile(r"\[([^\]]+)\]")
_SPLIT = re.compile(r"\s*,\s*|\s+")


def _header_units(path, number: int, line: str) -> tuple[float, float]:
    units = _UNIT.findall(line)
    if len(units) != 2:
        raise ValueError(f"{path}, line {number}: name the two columns with their units in brackets, e.g. "
                         f"'period [s], Sa [g]'; got {line.strip()!r}.")
    factors = []
    for column, (unit, dimension) in enumerate(zip(units, ("time", "acceleration")), start=1):
        try:
            factors.append(parse_quantity("1" + unit.strip(), dimension, where=f"{path}, line {number}, column {column}"))
        except ValueError as error:
            raise ValueError(f"{error} (the header's units: period [time], spectral acceleration "
                             "[acceleration])") from None
    return factors[0], factors[1]


def read_target_spectrum(path) -> tuple[np.ndarray, np.ndarray]:
    """(periods [s], pseudo-spectral accelerations [m/s^2]) of a target spectrum file (module
    docstring), once checked."""
    path = pathlib.Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such target spectrum file.")
    rows, factors = [], None
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        if factors is None:
            factors = _header_units(path, number, stripped)
            continue
        fields = [f for f in _SPLIT.split(stripped) if f]
        if len(fields) != 2:
            raise ValueError(f"{path}, line {number}: expected two columns (period, acceleration), got "
                             f"{len(fields)}.")
        values = []
        for column, field in enumerate(fields, start=1):
            try:
                value = float(field)
            except ValueError:
                raise ValueError(f"{path}, line {number}, column {column}: {field!r} is not a number.") from None
            if not math.isfinite(value):
                raise ValueError(f"{path}, line {number}, column {column}: {field!r} is not finite.")
            values.append(value)
        if not values[0] > 0:
            raise ValueError(f"{path}, line {number}, column 1: the period must be > 0, got {fields[0]}.")
        if values[1] < 0:
            raise ValueError(f"{path}, line {number}, column 2: the spectral acceleration must be >= 0, "
                             f"got {fields[1]}.")
        if rows and not values[0] > rows[-1][1]:
            raise ValueError(f"{path}, line {number}, column 1: periods must increase; {fields[0]} is not above "
                             f"{rows[-1][2]} (line {rows[-1][0]}). Sort the rows.")
        rows.append((number, values[0], fields[0], values[1]))
    if factors is None or len(rows) < 2:
        raise ValueError(f"{path}: a target spectrum needs a header with units and at least two rows.")
    acceleration = np.array([r[3] for r in rows]) * factors[1]
    if not np.any(acceleration > 0):
        raise ValueError(f"{path}: every spectral acceleration is 0.")
    return np.array([r[1] for r in rows]) * factors[0], acceleration
