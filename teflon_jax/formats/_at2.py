"""PEER NGA `.AT2` acceleration files (the PEER ground-motion database format)."""

import math
import re

import numpy as np

from ..excitation import GroundMotion
from ..units import unit_factor
from ._text import _NUMBER, _read_lines, _to_float

_AT2_UNITS = {
    "G": "g",
    "G'S": "g",
    "CM/S/S": "cm/s^2",
    "CM/SEC/SEC": "cm/s^2",
    "CM/S^2": "cm/s^2",
    "CM/S2": "cm/s^2",
    "CM/SEC2": "cm/s^2",
    "CM/SEC^2": "cm/s^2",
    "GAL": "cm/s^2",
    "M/S/S": "m/s^2",
    "M/S^2": "m/s^2",
    "M/S2": "m/s^2",
    "IN/S/S": "in/s^2",
    "IN/S^2": "in/s^2",
    "IN/SEC/SEC": "in/s^2",
}


def _acceleration_factor(units: str, where: str) -> float:
    return unit_factor(units, "acceleration", where=where)


def read_at2(path) -> GroundMotion:
    """Read a PEER NGA strong-motion record in AT2 format.

    The format (PEER Ground Motion Database) has four header lines:

    1. the database name; 2. event, date, station, component (used as the record's `name`);
    3. the quantity and units, e.g. `ACCELERATION TIME SERIES IN UNITS OF G`;
    4. `NPTS=   5372, DT=   .0100 SEC` (NGA-West2) or `5372    0.0100    NPTS, DT` (NGA-West1);

    then the `NPTS` accelerations, any number per line (five in PEER files).

    **Arguments:**

    - `path`: the `.AT2` file.

    **Returns:** a `GroundMotion` in [m/s^2] starting at t = 0.

    **Raises:** `ValueError` naming the file and line for a short or malformed header, unknown
    units, a value that is not a finite number, or a value count different from `NPTS`.
    """
    path, lines = _read_lines(path)
    if len(lines) < 4:
        raise ValueError(
            f"{path}, line {len(lines)}: the file ends inside the header; a PEER AT2 file has "
            "4 header lines (database, event/station, units, NPTS and DT)."
        )
    units_line = lines[2]
    match = re.search(r"UNITS\s+OF\s+(\S+)", units_line, flags=re.IGNORECASE)
    if match is None:
        raise ValueError(
            f"{path}, line 3: expected the units, e.g. 'ACCELERATION TIME SERIES IN UNITS OF G', "
            f"got '{units_line.strip()}'."
        )
    unit_text = match.group(1).upper().rstrip(".,")
    if unit_text not in _AT2_UNITS:
        raise ValueError(
            f"{path}, line 3: unknown units '{match.group(1)}'; known: {', '.join(_AT2_UNITS)}."
        )
    factor = _acceleration_factor(_AT2_UNITS[unit_text], f"{path}, line 3")
    if not re.search(r"ACCEL", units_line, flags=re.IGNORECASE):
        raise ValueError(
            f"{path}, line 3: '{units_line.strip()}' does not describe an acceleration record "
            "(velocity and displacement files, .VT2 and .DT2, are not ground accelerations)."
        )
    npts, time_step = _at2_npts_dt(lines[3], path)
    values = []
    for line_no, line in enumerate(lines[4:], start=5):
        for token in line.split():
            values.append(_to_float(token, path, line_no, "acceleration value"))
    if len(values) != npts:
        raise ValueError(
            f"{path}, line 4: the header announces NPTS = {npts} values, but the file holds "
            f"{len(values)} (lines 5 to {len(lines)})."
        )
    return GroundMotion(
        time_step=time_step,
        acceleration=factor * np.asarray(values),
        name=lines[1].strip() or path.stem,
        source=str(path),
    )


def _at2_npts_dt(line: str, path) -> tuple[int, float]:
    npts_match = re.search(r"NPTS\s*=\s*(\S+?)\s*(?:,|\s|$)", line, flags=re.IGNORECASE)
    dt_match = re.search(r"DT\s*=\s*(\S+?)\s*(?:,|\s|SEC|$)", line, flags=re.IGNORECASE)
    if npts_match is not None and dt_match is not None:
        npts_text, dt_text = npts_match.group(1), dt_match.group(1)
    else:
        old = re.match(
            r"^\s*(\S+)\s*,?\s+(\S+)\s*,?\s+NPTS\s*,?\s*DT\b", line, flags=re.IGNORECASE
        )
        if old is None:
            raise ValueError(
                f"{path}, line 4: expected 'NPTS=  <count>, DT=  <step> SEC' or "
                f"'<count>  <step>  NPTS, DT', got '{line.strip()}'."
            )
        npts_text, dt_text = old.group(1), old.group(2)
    if not re.fullmatch(r"\d+", npts_text):
        raise ValueError(f"{path}, line 4: NPTS '{npts_text}' is not a whole number.")
    if not re.fullmatch(_NUMBER, dt_text):
        raise ValueError(f"{path}, line 4: DT '{dt_text}' is not a number of seconds.")
    npts = int(npts_text)
    time_step = float(dt_text.replace("D", "E").replace("d", "e"))
    if npts < 2:
        raise ValueError(
            f"{path}, line 4: NPTS = {npts}; a record needs at least 2 samples."
        )
    if not (math.isfinite(time_step) and time_step > 0.0):
        raise ValueError(
            f"{path}, line 4: DT = {dt_text} must be a positive time step in seconds."
        )
    return npts, time_step
