"""Readers for ground-motion files and the shared records used by the tests and benchmarks.

Formats:

- PEER NGA AT2 (PEER Ground Motion Database, NGA-West1 and NGA-West2 flat files): four header
  lines (database, event/station/component, `... IN UNITS OF G`, `NPTS=..., DT=...`), then the
  accelerations, several values per line.
- Time and acceleration columns, separated by whitespace or commas.
- One acceleration value per line at a known time step.

Every problem with a file is a `ValueError` that names the file and the line (1-based).
"""

import math

import numpy as np

from ..excitation import GroundMotion
from ._at2 import _acceleration_factor
from ._column_units import _FIELD_SPLIT, _is_number, header_time_factor
from ._text import _read_lines, _to_float


def _split_fields(line: str) -> list[str]:
    return _FIELD_SPLIT.split(line.strip())


def _data_rows(path, lines, skip_header):
    """(line number, fields) of the data rows, after the header, blank lines and `#` comments."""
    if skip_header is None:
        start = 0
        while start < len(lines):
            stripped = lines[start].strip()
            if (
                stripped
                and not stripped.startswith("#")
                and any(_is_number(f) for f in _split_fields(stripped))
            ):
                break
            start += 1
    else:
        if not (isinstance(skip_header, int) and skip_header >= 0):
            raise ValueError(
                f"{path}: skip_header must be a whole number >= 0, got {skip_header!r}."
            )
        start = skip_header
    rows = []
    for line_no, line in enumerate(lines[start:], start=start + 1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        rows.append((line_no, _split_fields(stripped)))
    if not rows:
        raise ValueError(
            f"{path}, line {len(lines)}: no data rows after {start} header line(s)."
        )
    first_line, first_fields = rows[0]
    if not any(_is_number(field) for field in first_fields):
        raise ValueError(
            f"{path}, line {first_line}: '{lines[first_line - 1].strip()}' holds no "
            "number; if it "
            f"is a header, skip it with skip_header={first_line} (or skip_header=None)."
        )
    width = len(rows[0][1])
    for line_no, fields in rows:
        if len(fields) != width:
            raise ValueError(
                f"{path}, line {line_no}: {len(fields)} column(s), but the first data row "
                f"(line {rows[0][0]}) has {width}; rows must all have the same columns."
            )
        for column, field in enumerate(fields):
            if field == "":
                raise ValueError(f"{path}, line {line_no}: column {column} is empty.")
    return rows, width


def read_two_column(
    path,
    *,
    units: str,
    time_column: int = 0,
    acceleration_column: int = 1,
    skip_header: int | None = None,
    time_tolerance: float = 1.0e-3,
    columns: int | None = None,
) -> GroundMotion:
    """Read a record stored as columns of time and acceleration.

    Columns are separated by whitespace or by commas. Blank lines and lines starting with `#`
    are skipped. The time must increase strictly and be uniformly sampled: each step must lie
    within `time_tolerance * dt` of the median step, and each time within `time_tolerance * dt`
    of the straight line through the first and last times (so that round-off in the written
    times, such as 0.01999 / 0.02001 in the SCT file, is accepted but a missing sample is not).
    The time step is `(t_last - t_first) / (npts - 1)` rounded to 12 significant digits, and the
    first time becomes `start_time`. Other columns than the two selected are read and checked
    for shape but not used, so a 4-column file (time, N-S, E-W, vertical) can be read one
    component at a time (the unused columns are not checked). A unit in brackets in a text
    header (`time [ms]`, `acc (g)`) is read: a time unit converts the times to seconds, and an
    acceleration unit must be `units`; bracketed text that is no unit (`(N-S)`) is a label.

    **Arguments:**

    - `path`: the text file.
    - `units`: units of the acceleration column: `"g"`, `"m/s^2"`, `"cm/s^2"` or `"in/s^2"`.
    - `time_column`, `acceleration_column`: 0-based column indices.
    - `skip_header`: number of lines to skip before the data; `None` skips the leading lines
      in which no field is a number (a text header such as `time,acc (g)`).
    - `time_tolerance`: allowed jitter of the times as a fraction of the time step.
    - `columns`: the number of columns the rows must have (None: any), so that a column that
      would not be read is refused rather than passed over.

    **Returns:** a `GroundMotion` in [m/s^2].

    **Raises:** `ValueError` naming the file and line for an empty file, ragged rows, a value
    that is not a finite number, a time that does not increase, non-uniform sampling, or a
    number of columns other than `columns`, or a header unit of the wrong dimension or, for
    the acceleration, other than `units`.
    """
    factor = _acceleration_factor(units, f"{path}: units")
    path, lines = _read_lines(path)
    rows, width = _data_rows(path, lines, skip_header)
    if columns is not None and width != columns:
        raise ValueError(
            f"{path}, line {rows[0][0]}: {width} column(s), but {columns} are read: time in column "
            f"{time_column + 1} and acceleration in column {acceleration_column + 1}"
            + (", so the others would be left out; give each component a file of its own."
               if width > columns else ".")
        )
    for label, column in (
        ("time_column", time_column),
        ("acceleration_column", acceleration_column),
    ):
        if not (isinstance(column, int) and 0 <= column < width):
            raise ValueError(
                f"{path}, line {rows[0][0]}: {label} = {column!r}, but the rows have {width} "
                f"column(s) (0 to {width - 1})."
            )
    if time_column == acceleration_column:
        raise ValueError(
            f"{path}: time_column and acceleration_column are both {time_column}."
        )
    time_factor = header_time_factor(lines, rows[0][0], width, path, time_column,
                                     acceleration_column, units)
    line_numbers = [line_no for line_no, _ in rows]
    time = time_factor * np.array(
        [
            _to_float(f[time_column], path, n, f"time (column {time_column + 1})")
            for n, f in rows
        ]
    )
    acceleration = np.array(
        [
            _to_float(
                f[acceleration_column],
                path,
                n,
                f"acceleration (column {acceleration_column + 1})",
            )
            for n, f in rows
        ]
    )
    time_step = _uniform_time_step(time, line_numbers, path, time_tolerance)
    return GroundMotion(
        time_step=time_step,
        acceleration=factor * acceleration,
        name=path.stem,
        source=f"{path} (column {acceleration_column + 1} counting from 1, {units})",
        start_time=float(time[0]),
    )


def _uniform_time_step(time, line_numbers, path, tolerance) -> float:
    if time.size < 2:
        raise ValueError(
            f"{path}, line {line_numbers[0]}: a record needs at least 2 samples."
        )
    steps = np.diff(time)
    bad = np.flatnonzero(steps <= 0.0)
    if bad.size:
        i = bad[0] + 1
        raise ValueError(
            f"{path}, line {line_numbers[i]}: time {time[i]:g} s does not increase "
            f"(previous row, line {line_numbers[i - 1]}, has {time[i - 1]:g} s); times must "
            "increase strictly."
        )
    median = float(np.median(steps))
    bad = np.flatnonzero(np.abs(steps - median) > tolerance * median)
    if bad.size:
        i = bad[0] + 1
        raise ValueError(
            f"{path}, line {line_numbers[i]}: time step {steps[i - 1]:g} s differs from the "
            f"record's step {median:g} s by more than {tolerance:g} of a step; "
            "the record must be "
            "uniformly sampled (resample it first)."
        )
    time_step = float((time[-1] - time[0]) / (time.size - 1))
    drift = time - (time[0] + time_step * np.arange(time.size))
    bad = np.flatnonzero(np.abs(drift) > tolerance * time_step)
    if bad.size:
        i = bad[0]
        raise ValueError(
            f"{path}, line {line_numbers[i]}: time {time[i]:g} s is {drift[i]:+.3g} s off the "
            f"uniform grid of step {time_step:g} s; the record must be uniformly sampled."
        )
    return float(f"{time_step:.12g}")


def read_single_column(
    path,
    *,
    time_step: float,
    units: str,
    start_time: float = 0.0,
    skip_header: int | None = None,
) -> GroundMotion:
    """Read a record stored as one acceleration value per line.

    **Arguments:**

    - `path`: the text file. Blank lines and lines starting with `#` are skipped.
    - `time_step`: sampling interval [s].
    - `units`: units of the values: `"g"`, `"m/s^2"`, `"cm/s^2"` or `"in/s^2"`.
    - `start_time`: time of the first value [s].
    - `skip_header`: lines to skip first; `None` skips leading lines that hold no number.

    **Returns:** a `GroundMotion` in [m/s^2].

    **Raises:** `ValueError` naming the file and line for an empty file, a row with more than
    one value, or a value that is not a finite number.
    """
    factor = _acceleration_factor(units, f"{path}: units")
    if not (
        isinstance(time_step, (int, float)) and math.isfinite(time_step) and time_step > 0
    ):
        raise ValueError(
            f"{path}: time_step must be a positive number of seconds, got {time_step!r}."
        )
    path, lines = _read_lines(path)
    rows, width = _data_rows(path, lines, skip_header)
    if width != 1:
        raise ValueError(
            f"{path}, line {rows[0][0]}: {width} columns, but a single-column record has one "
            "value per line (use read_two_column for time and acceleration columns)."
        )
    acceleration = np.array([_to_float(f[0], path, n, "acceleration") for n, f in rows])
    if acceleration.size < 2:
        raise ValueError(f"{path}, line {rows[0][0]}: a record needs at least 2 samples.")
    return GroundMotion(
        time_step=float(time_step),
        acceleration=factor * acceleration,
        name=path.stem,
        source=f"{path} ({units})",
        start_time=start_time,
    )
