"""Bearing test records: the test-record CSV of the project (read, write, build).

A test record is one test of one bearing (or of a stack of sliding interfaces tested
together): the imposed displacement, the measured friction force and, where known, the
normal load. The file format is the one in the project's `FORMATS.md`:

```
# specimen: PTFE-steel flat slider, unfilled sheet PTFE
# contact_area [in^2]: 78.5
# direction: P
time [s],ux [in],fx [kip],N [kip]
0.00,0.0000,0.000,78.5
0.01,0.0025,1.204,78.5
```

Everything in a `TestRecord` is SI (m, s, N, Pa, m^2, degC); the file may use the units
of the paper (in, kip, psi) or any unit listed in `teflon_jax._units.UNITS`. This module
does file I/O and is not meant to be traced by JAX; it returns plain numpy arrays.
"""

import dataclasses
import itertools
import math
import pathlib
import re
from collections.abc import Mapping
from typing import Any

import numpy as np

from ._units import UNITS, parse_quantity, unit_factor

# Columns with a meaning, and the dimension their unit must have.
_COLUMN_DIMENSIONS = {
    "time": "time",
    "ux": "length",
    "fx": "force",
    "uy": "length",
    "fy": "force",
    "N": "force",
    "temperature": "temperature",
}
_REQUIRED_COLUMNS = ("time", "ux", "fx")

# Metadata keys with a meaning. Quantities are stored in SI under these names.
_QUANTITY_KEYS = {
    "contact_area": "area",
    "normal_load": "force",
    "contact_pressure": "pressure",
}
_KEY_ALIASES = {"pressure": "contact_pressure"}
_TEXT_KEYS = ("specimen", "source")
_PTFE_TYPES = ("UF", "15GF", "25GF")
_DIRECTIONS = ("P", "T")
_COMMENT_KEY = "comment"

PROTOCOL_PATTERNS = ("sine", "triangle", "eight")

# Units written by default: those of the paper (Constantinou, Mokha & Reinhorn 1990).
PAPER_UNITS: dict[str, str] = {
    "time": "s",
    "length": "in",
    "force": "kip",
    "area": "in^2",
    "pressure": "psi",
    "temperature": "degC",
    "velocity": "in/s",
    "frequency": "Hz",
}
SI_UNITS: dict[str, str] = {
    "time": "s",
    "length": "m",
    "force": "N",
    "area": "m^2",
    "pressure": "Pa",
    "temperature": "degC",
    "velocity": "m/s",
    "frequency": "Hz",
}

_HEADER_CELL = re.compile(r"^\s*(?P<name>[^\[\]]*?)\s*(?:\[(?P<unit>[^\[\]]*)\])?\s*$")
_METADATA_LINE = re.compile(
    r"^#\s*(?P<key>[^\[\]:]*?)\s*(?:\[(?P<unit>[^\[\]]*)\])?\s*:\s*(?P<value>.*?)\s*$"
)
_METADATA_KEY = re.compile(r"[^\[\]:\n#]*[^\[\]:\n\s#](?: \[[^\[\]:\n]*\])?")
_PROTOCOL_KEY = re.compile(r"(?:^|\s)([A-Za-z_]\w*)\s*=")


def _si_unit(dimension: str) -> str:
    """The SI spelling of `dimension` (the unit whose factor is exactly 1)."""
    return next(unit for unit, factor in UNITS[dimension].items() if factor == 1.0)


def _dimension_of(unit: str) -> str | None:
    """The dimension that lists `unit`, or `None` when no table lists it."""
    for dimension, table in UNITS.items():
        if dimension != "dimensionless" and unit in table:
            return dimension
    return None


@dataclasses.dataclass(frozen=True)
class Protocol:
    """The displacement history imposed in a test, as written on a `# protocol:` line.

    Text form: `<pattern> amplitude=<length> frequency=<frequency> [cycles=<number>]`, for
    example `sine amplitude=1 in frequency=0.16 Hz cycles=3` (test No. 62 of Constantinou,
    Mokha & Reinhorn 1990). Patterns, with `w = 2 pi frequency` and `U0 = amplitude`:

    - `sine`: `ux = U0 sin(w t)`;
    - `triangle`: a triangular wave of the same amplitude and period, starting at zero and
      moving towards +x (constant velocity `4 U0 frequency` between reversals);
    - `eight`: the figure-eight orbit `ux = U0 sin(w t)`, `uy = U0 sin(2 w t)` (Figs. 5-6 of
      the paper).

    **Fields:**

    - `pattern`: one of `"sine"`, `"triangle"`, `"eight"`.
    - `amplitude`: `U0` [m].
    - `frequency`: cycles per second of `ux` [Hz] (`rad/s` is accepted in the text).
    - `cycles`: number of cycles imposed, or `None` when not stated.
    - `extra`: other `key=value` pairs of the line, kept as text.
    """

    pattern: str
    amplitude: float
    frequency: float
    cycles: float | None = None
    extra: dict[str, str] = dataclasses.field(default_factory=dict)

    def __post_init__(self):
        if self.pattern not in PROTOCOL_PATTERNS:
            raise ValueError(
                f"protocol: unknown pattern '{self.pattern}'; use one of "
                f"{', '.join(PROTOCOL_PATTERNS)}."
            )
        for name in ("amplitude", "frequency"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(
                    f"protocol: {name} must be a positive number, got {value!r}."
                )
            object.__setattr__(self, name, float(value))
        if self.cycles is not None:
            if not (
                isinstance(self.cycles, (int, float))
                and math.isfinite(self.cycles)
                and self.cycles > 0
            ):
                raise ValueError(
                    f"protocol: cycles must be a positive number, got {self.cycles!r}."
                )
            object.__setattr__(self, "cycles", float(self.cycles))
        object.__setattr__(self, "extra", {str(k): str(v) for k, v in self.extra.items()})

    @property
    def duration(self) -> float | None:
        """`cycles / frequency` [s], or `None` when the number of cycles is not stated."""
        return None if self.cycles is None else self.cycles / self.frequency

    def displacement(self, time) -> tuple[np.ndarray, np.ndarray | None]:
        """Imposed displacement at `time` [s].

        **Returns:** `(ux, uy)` [m]; `uy` is `None` except for the `eight` pattern.
        """
        t = np.asarray(time, dtype=float)
        omega = 2.0 * np.pi * self.frequency
        if self.pattern == "triangle":
            # Triangle wave of unit amplitude, phase-aligned with sin(w t).
            phase = (self.frequency * t + 0.25) % 1.0
            ux = self.amplitude * (1.0 - 4.0 * np.abs(phase - 0.5))
            return ux, None
        ux = self.amplitude * np.sin(omega * t)
        if self.pattern == "eight":
            return ux, self.amplitude * np.sin(2.0 * omega * t)
        return ux, None

    def to_text(self, length_unit: str = "in", *, digits: int = 9) -> str:
        """The `# protocol:` value, with the amplitude in `length_unit`."""
        factor = unit_factor(length_unit, "length", where="protocol amplitude unit")
        parts = [
            self.pattern,
            f"amplitude={self.amplitude / factor:.{digits}g} {length_unit}",
            f"frequency={self.frequency:.{digits}g} Hz",
        ]
        if self.cycles is not None:
            parts.append(f"cycles={self.cycles:.{digits}g}")
        parts += [f"{key}={value}" for key, value in self.extra.items()]
        return " ".join(parts)


def parse_protocol(text: str, *, where: str = "protocol") -> Protocol:
    """Read a protocol line such as `sine amplitude=1 in frequency=0.16 Hz cycles=3`.

    **Arguments:**

    - `text`: the pattern followed by `key=value` pairs; `amplitude` and `frequency` need a
      unit (`1 in`, `25mm`, `0.16 Hz`, `1 rad/s`).
    - `where`: what to name in an error (the file and line).

    **Returns:** a `Protocol` in SI units.
    """
    text = text.strip()
    pattern, _, rest = text.partition(" ")
    pattern = pattern.lower()
    if pattern not in PROTOCOL_PATTERNS:
        raise ValueError(
            f"{where}: unknown protocol pattern '{pattern}'; start the line with one of "
            f"{', '.join(PROTOCOL_PATTERNS)}, e.g. "
            f"'sine amplitude=1 in frequency=0.16 Hz cycles=3'."
        )
    pieces = _PROTOCOL_KEY.split(" " + rest)
    if pieces[0].strip():
        raise ValueError(
            f"{where}: cannot read '{pieces[0].strip()}' in the protocol; write "
            f"key=value pairs, e.g. 'sine amplitude=1 in frequency=0.16 Hz cycles=3'."
        )
    values: dict[str, str] = {}
    for key, value in zip(pieces[1::2], pieces[2::2]):
        if key in values:
            raise ValueError(f"{where}: protocol key '{key}' is given twice.")
        values[key] = value.strip()
    for key in ("amplitude", "frequency"):
        if key not in values:
            raise ValueError(
                f"{where}: the protocol needs '{key}=' (e.g. "
                f"'sine amplitude=1 in frequency=0.16 Hz cycles=3')."
            )
    amplitude = parse_quantity(
        values.pop("amplitude"), "length", where=f"{where}, protocol amplitude"
    )
    frequency = parse_quantity(
        values.pop("frequency"), "frequency", where=f"{where}, protocol frequency"
    )
    cycles = None
    if "cycles" in values:
        cycles = parse_quantity(
            values.pop("cycles"), "dimensionless", where=f"{where}, protocol cycles"
        )
    try:
        return Protocol(pattern, amplitude, frequency, cycles, values)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None


def _as_array(value, name: str, where: str) -> np.ndarray:
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{where}: '{name}' must be an array of numbers.") from None
    if array.ndim != 1:
        raise ValueError(
            f"{where}: '{name}' must be one-dimensional, got shape {array.shape}."
        )
    bad = np.flatnonzero(~np.isfinite(array))
    if bad.size:
        raise ValueError(
            f"{where}: '{name}' has a non-finite value ({array[bad[0]]}) at index "
            f"{bad[0]}; remove or repair the sample, it is not filled in for you."
        )
    array.setflags(write=False)
    return array


def _check_metadata(metadata: Mapping[str, Any], where: str) -> dict[str, Any]:
    """Validate the known keys of `metadata` (values in SI) and return a copy."""
    checked: dict[str, Any] = {}
    for key, value in metadata.items():
        if not isinstance(key, str) or _METADATA_KEY.fullmatch(key) is None:
            raise ValueError(
                f"{where}: metadata key {key!r} is not a valid key; use a name without "
                f"':', '[', ']' or line breaks, optionally followed by ' [unit]'."
            )
        if key in _QUANTITY_KEYS:
            if not (
                isinstance(value, (int, float, np.floating, np.integer))
                and math.isfinite(value)
                and value > 0
            ):
                raise ValueError(
                    f"{where}: metadata '{key}' must be a positive number in SI "
                    f"({_si_unit(_QUANTITY_KEYS[key])}), got {value!r}."
                )
            value = float(value)
        elif key == "direction":
            if value not in _DIRECTIONS:
                raise ValueError(
                    f"{where}: metadata 'direction' must be 'P' (parallel to the lay of "
                    f"the steel) or 'T' (perpendicular), got {value!r}."
                )
        elif key == "interfaces":
            if (
                isinstance(value, bool)
                or not isinstance(value, (int, np.integer))
                or value < 1
            ):
                raise ValueError(
                    f"{where}: metadata 'interfaces' must be a whole number >= 1, "
                    f"got {value!r}."
                )
            value = int(value)
        elif key == "ptfe":
            if value not in _PTFE_TYPES:
                raise ValueError(
                    f"{where}: metadata 'ptfe' must be one of {', '.join(_PTFE_TYPES)}, "
                    f"got {value!r}."
                )
        elif key == "protocol":
            if not isinstance(value, Protocol):
                raise ValueError(
                    f"{where}: metadata 'protocol' must be a Protocol (see "
                    f"parse_protocol), got {value!r}."
                )
        else:
            if not isinstance(value, str):
                raise ValueError(
                    f"{where}: metadata '{key}' must be text, got {type(value).__name__}; "
                    f"only {', '.join(_QUANTITY_KEYS)}, interfaces and protocol hold "
                    f"other types."
                )
            if "\n" in value and key != _COMMENT_KEY:
                raise ValueError(
                    f"{where}: metadata '{key}' must be a single line of text."
                )
        checked[key] = value
    return checked


def _normal_load_from_metadata(
    metadata: Mapping[str, Any], length: int
) -> np.ndarray | None:
    """Constant normal load [N] from `normal_load` or `contact_area * contact_pressure`."""
    if "normal_load" in metadata:
        value = metadata["normal_load"]
    elif "contact_area" in metadata and "contact_pressure" in metadata:
        value = metadata["contact_area"] * metadata["contact_pressure"]
    else:
        return None
    return np.full(length, float(value))


@dataclasses.dataclass(frozen=True, eq=False)
class TestRecord:
    """One bearing test: imposed displacement, measured friction force and test conditions.

    All arrays are one-dimensional float64 numpy arrays of equal length, in SI units, and
    read-only. Validation happens on construction: equal lengths, finite values, strictly
    increasing time, and the types of the known metadata keys.

    **Fields:**

    - `time`: sample times [s]; `None` for a loop digitised from a figure, whose imposed
      motion is then given by `metadata["protocol"]` (a `Protocol`).
    - `ux`, `fx`: displacement [m] and friction force [N] along x. `fx` is the force the
      bearing resists with, positive while sliding in +x (loops run clockwise).
    - `uy`, `fy`: the same along y for biaxial tests, else `None`.
    - `normal_load`: normal load history [N], positive in compression; from the `N` column,
      or the constant `normal_load` metadata, or `contact_area * contact_pressure`; `None`
      when the record states none of these.
    - `temperature`: temperature history [degC] or `None`.
    - `metadata`: known keys in SI: `contact_area` [m^2], `normal_load` [N],
      `contact_pressure` [Pa] (the file may call it `pressure`), `direction` (`"P"` or
      `"T"`),
      `interfaces` (int), `ptfe` (`"UF"`, `"15GF"`, `"25GF"`), `specimen`, `source` (text),
      `protocol` (`Protocol`), `comment` (text, lines joined by newlines). Unknown keys are
      kept as text; a unit they were written with stays in the key (`"speed [in/s]"`).
    - `extra_columns`: other columns, name -> array; converted to SI when their unit is
      known.
    - `extra_units`: name -> unit of each extra column (the SI unit after conversion, or the
      unit as written when it is not a known one).
    - `path`: the file the record was read from, or `None`.
    """

    __test__ = False  # not a pytest test class, despite the name

    time: np.ndarray | None
    ux: np.ndarray
    fx: np.ndarray
    uy: np.ndarray | None = None
    fy: np.ndarray | None = None
    normal_load: np.ndarray | None = None
    temperature: np.ndarray | None = None
    metadata: dict[str, Any] = dataclasses.field(default_factory=dict)
    extra_columns: dict[str, np.ndarray] = dataclasses.field(default_factory=dict)
    extra_units: dict[str, str] = dataclasses.field(default_factory=dict)
    path: pathlib.Path | None = None

    def __post_init__(self):
        where = str(self.path) if self.path is not None else "TestRecord"
        ux = _as_array(self.ux, "ux", where)
        object.__setattr__(self, "ux", ux)
        for name in ("time", "fx", "uy", "fy", "normal_load", "temperature"):
            value = getattr(self, name)
            if value is None:
                continue
            if name == "normal_load" and np.ndim(value) == 0:
                value = np.full(ux.shape, value, dtype=float)
            array = _as_array(value, name, where)
            if array.shape != ux.shape:
                raise ValueError(
                    f"{where}: '{name}' has {array.size} samples but 'ux' has {ux.size}."
                )
            object.__setattr__(self, name, array)
        if self.fx is None:
            raise ValueError(f"{where}: 'fx' is required.")
        if ux.size == 0:
            raise ValueError(f"{where}: the record has no samples.")
        if self.time is not None:
            steps = np.diff(self.time)
            bad = np.flatnonzero(steps <= 0)
            if bad.size:
                i = bad[0] + 1
                raise ValueError(
                    f"{where}: 'time' must increase strictly, but sample {i} "
                    f"({self.time[i]} s) follows {self.time[i - 1]} s."
                )
        metadata = _check_metadata(self.metadata, where)
        if self.time is None and "protocol" not in metadata:
            raise ValueError(
                f"{where}: a record without 'time' (a digitised loop) needs "
                f"metadata['protocol'] describing the imposed motion, e.g. "
                f"parse_protocol('sine amplitude=1 in frequency=0.16 Hz cycles=3')."
            )
        object.__setattr__(self, "metadata", metadata)
        extra = {}
        for name, value in self.extra_columns.items():
            if name in _COLUMN_DIMENSIONS:
                raise ValueError(
                    f"{where}: extra column '{name}' has the name of a standard column; "
                    f"pass it as the field '{name}' instead."
                )
            if name not in self.extra_units:
                raise ValueError(
                    f"{where}: extra column '{name}' has no unit in extra_units; "
                    f"give one (use '-' for a dimensionless column)."
                )
            array = _as_array(value, name, where)
            if array.shape != ux.shape:
                raise ValueError(
                    f"{where}: '{name}' has {array.size} samples but 'ux' has {ux.size}."
                )
            extra[name] = array
        unused = set(self.extra_units) - set(extra)
        if unused:
            raise ValueError(
                f"{where}: extra_units names {sorted(unused)}, which are not extra columns."
            )
        object.__setattr__(self, "extra_columns", extra)
        object.__setattr__(
            self, "extra_units", {k: str(self.extra_units[k]) for k in extra}
        )
        if self.path is not None:
            object.__setattr__(self, "path", pathlib.Path(self.path))

    @property
    def is_biaxial(self) -> bool:
        """Whether the imposed motion has a y component (`uy` is recorded)."""
        return self.uy is not None

    @property
    def is_digitised(self) -> bool:
        """Whether the record is a loop digitised from a figure (no time column)."""
        return self.time is None

    @property
    def contact_pressure(self) -> np.ndarray | None:
        """Contact pressure history `normal_load / contact_area` [Pa], or `None` when either
        is unknown."""
        if self.normal_load is None or "contact_area" not in self.metadata:
            return None
        return self.normal_load / self.metadata["contact_area"]

    def __len__(self) -> int:
        return self.ux.size


def test_record_from_arrays(
    ux,
    fx,
    *,
    time=None,
    uy=None,
    fy=None,
    normal_load=None,
    temperature=None,
    metadata: Mapping[str, Any] | None = None,
    extra_columns: Mapping[str, Any] | None = None,
    extra_units: Mapping[str, str] | None = None,
) -> TestRecord:
    """Build a `TestRecord` from arrays in SI units, with the same checks as the reader.

    **Arguments:**

    - `ux`, `fx`: displacement [m] and friction force [N] along x.
    - `time`: sample times [s], strictly increasing; `None` for a digitised loop, which then
      needs `metadata["protocol"]`.
    - `uy`, `fy`: displacement [m] and force [N] along y (biaxial tests), optional.
    - `normal_load`: normal load [N], a history or one number (broadcast); when `None` it is
      taken from `metadata["normal_load"]` or `contact_area * contact_pressure` if given.
    - `temperature`: temperature history [degC], optional.
    - `metadata`: see `TestRecord` (known keys in SI).
    - `extra_columns`, `extra_units`: other columns and their units.

    **Returns:** the validated `TestRecord`. Raises `ValueError` naming the argument when
    lengths differ, a value is not finite or time does not increase.
    """
    metadata = dict(metadata or {})
    if normal_load is None:
        normal_load = _normal_load_from_metadata(metadata, np.size(ux))
    return TestRecord(
        time=time,
        ux=ux,
        fx=fx,
        uy=uy,
        fy=fy,
        normal_load=normal_load,
        temperature=temperature,
        metadata=metadata,
        extra_columns=dict(extra_columns or {}),
        extra_units=dict(extra_units or {}),
    )


test_record_from_arrays.__test__ = False  # a constructor, not a pytest test


# ----------------------------------------------------------------------------------------
# Reading


def _parse_metadata_line(line: str, where: str, metadata: dict[str, Any]) -> None:
    """Add the content of one `#` line to `metadata` (known keys converted to SI)."""
    match = _METADATA_LINE.match(line)
    if match is None:
        body = line[1:].strip()
        if ":" in body:
            raise ValueError(
                f"{where}: cannot read the metadata line '{line}'; write "
                f"'# key: value' or '# key [unit]: value'."
            )
        if body:
            _add_comment(metadata, body)
        return
    key, unit, value = match.group("key"), match.group("unit"), match.group("value")
    key = _KEY_ALIASES.get(key, key)
    if key == _COMMENT_KEY and unit is None:
        _add_comment(metadata, value)
        return
    known = (
        key in _QUANTITY_KEYS
        or key in _TEXT_KEYS
        or key
        in (
            "direction",
            "interfaces",
            "ptfe",
            "protocol",
        )
    )
    stored_key = key if known or unit is None else f"{key} [{unit}]"
    if stored_key in metadata:
        raise ValueError(f"{where}: metadata key '{key}' is given twice.")
    if not key:
        raise ValueError(f"{where}: metadata line '{line}' has no key before ':'.")
    if known and unit is not None and key not in _QUANTITY_KEYS:
        raise ValueError(
            f"{where}: metadata '{key}' takes no unit; write '# {key}: {value}'."
        )
    if value == "":
        raise ValueError(f"{where}: metadata '{key}' has no value after ':'.")
    if key in _QUANTITY_KEYS:
        dimension = _QUANTITY_KEYS[key]
        entry = f"{where}, metadata '{key}'"
        if unit is None:
            number = parse_quantity(value, dimension, where=entry)
        else:
            number = _parse_number(value, entry) * unit_factor(unit, dimension, where=entry)
        if not number > 0:
            raise ValueError(f"{entry}: must be positive, got {value}.")
        metadata[key] = number
    elif key == "direction":
        if value.upper() not in _DIRECTIONS:
            raise ValueError(
                f"{where}: metadata 'direction' must be P (sliding parallel to the lay of "
                f"the steel) or T (perpendicular), got '{value}'."
            )
        metadata[key] = value.upper()
    elif key == "interfaces":
        if not re.fullmatch(r"\d+", value) or int(value) < 1:
            raise ValueError(
                f"{where}: metadata 'interfaces' must be a whole number >= 1, "
                f"got '{value}'."
            )
        metadata[key] = int(value)
    elif key == "ptfe":
        if value.upper() not in _PTFE_TYPES:
            raise ValueError(
                f"{where}: metadata 'ptfe' must be one of {', '.join(_PTFE_TYPES)}, "
                f"got '{value}'."
            )
        metadata[key] = value.upper()
    elif key == "protocol":
        metadata[key] = parse_protocol(value, where=where)
    else:
        metadata[stored_key] = value


def _add_comment(metadata: dict[str, Any], text: str) -> None:
    if _COMMENT_KEY in metadata:
        metadata[_COMMENT_KEY] += "\n" + text
    else:
        metadata[_COMMENT_KEY] = text


def _parse_number(text: str, where: str) -> float:
    cell = text.strip()
    if cell == "":
        raise ValueError(f"{where}: empty cell; every cell needs a number.")
    try:
        if "_" in cell:
            raise ValueError
        value = float(cell)
    except ValueError:
        raise ValueError(f"{where}: '{cell}' is not a number.") from None
    if not math.isfinite(value):
        raise ValueError(
            f"{where}: '{cell}' is not a finite number; repair or remove the sample "
            f"(nothing is filled in or dropped for you)."
        )
    return value


def _parse_header(line: str, where: str) -> list[tuple[str, str]]:
    if "," not in line and (";" in line or "\t" in line):
        raise ValueError(
            f"{where}: the header has no commas; the columns must be separated by ','."
        )
    columns = []
    for cell in line.split(","):
        match = _HEADER_CELL.match(cell)
        name = match.group("name") if match else cell.strip()
        if match is None or not name:
            raise ValueError(
                f"{where}: cannot read the column header '{cell.strip()}'; write "
                f"'name [unit]', e.g. 'ux [in]'."
            )
        unit = match.group("unit")
        if unit is None:
            dimension = _COLUMN_DIMENSIONS.get(name)
            hint = (
                f"'{name} [{PAPER_UNITS[dimension]}]'" if dimension else f"'{name} [unit]'"
            )
            raise ValueError(f"{where}: column '{name}' has no unit; write it as {hint}.")
        if any(name == other for other, _ in columns):
            raise ValueError(f"{where}: column '{name}' appears twice.")
        columns.append((name, unit.strip()))
    return columns


def read_test_record(path) -> TestRecord:
    """Read a bearing test record in the project's CSV format (see `FORMATS.md`).

    Metadata lines (`# key: value` or `# key [unit]: value`) come before the header; the
    header names the columns as `name [unit]` in any order; `time`, `ux` and `fx` are
    required, `uy`, `fy`, `N` and `temperature` optional, other columns are kept in
    `extra_columns`. A file without a `time` column is a digitised loop and needs a
    `# protocol:` line (e.g. `# protocol: sine amplitude=1 in frequency=0.16 Hz cycles=3`).

    **Arguments:**

    - `path`: the CSV file.

    **Returns:** a `TestRecord` in SI units. The normal load comes from the `N` column, else
    from `# normal_load`, else from `# contact_area` times `# pressure`; with none of these
    it is `None`.

    Raises `ValueError` naming the file, line and column for: a missing or unknown unit, a
    unit of the wrong dimension, empty cells, NaN or non-numeric cells, rows with the wrong
    number of cells, time that does not increase strictly, a missing required column, or a
    digitised loop without a protocol. Nothing is dropped or filled in.
    """
    path = pathlib.Path(path)
    with open(path, encoding="utf-8-sig", newline=None) as file:
        lines = file.read().split("\n")
    while lines and not lines[-1].strip():
        lines.pop()

    metadata: dict[str, Any] = {}
    header_index = None
    for index, line in enumerate(lines):
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith("#"):
            _parse_metadata_line(stripped, f"{path}, line {index + 1}", metadata)
            continue
        header_index = index
        break
    if header_index is None:
        raise ValueError(
            f"{path}: no header line found; after the '#' metadata lines, write the column "
            f"names, e.g. 'time [s],ux [in],fx [kip]'."
        )
    columns = _parse_header(lines[header_index], f"{path}, line {header_index + 1}")
    names = [name for name, _ in columns]

    digitised = "time" not in names
    required = ("ux", "fx") if digitised else _REQUIRED_COLUMNS
    missing = [name for name in required if name not in names]
    if missing:
        raise ValueError(
            f"{path}, line {header_index + 1}: missing required column(s) "
            f"{', '.join(repr(m) for m in missing)}; the header has "
            f"{', '.join(repr(n) for n in names)}."
        )
    if digitised and "protocol" not in metadata:
        raise ValueError(
            f"{path}: no 'time' column, so the file is read as a digitised loop, which "
            f"needs the imposed motion on a metadata line before the header, e.g. "
            f"'# protocol: sine amplitude=1 in frequency=0.16 Hz cycles=3'; if the test "
            f"has a time history, add a 'time [s]' column instead."
        )

    factors = []
    extra_units: dict[str, str] = {}
    for name, unit in columns:
        where = f"{path}, line {header_index + 1}, column '{name}'"
        if name in _COLUMN_DIMENSIONS:
            factors.append(unit_factor(unit, _COLUMN_DIMENSIONS[name], where=where))
        else:
            dimension = _dimension_of(unit)
            if dimension is None:
                factors.append(1.0)
                extra_units[name] = unit
            else:
                factors.append(UNITS[dimension][unit])
                extra_units[name] = _si_unit(dimension)

    data = []
    for index in range(header_index + 1, len(lines)):
        line = lines[index]
        where = f"{path}, line {index + 1}"
        if line.lstrip().startswith("#"):
            raise ValueError(
                f"{where}: a '#' line after the header; metadata lines must come before "
                f"the header."
            )
        if not line.strip():
            raise ValueError(
                f"{where}: empty line among the data rows; remove it or fill in the sample."
            )
        cells = line.split(",")
        if len(cells) != len(columns):
            raise ValueError(
                f"{where}: {len(cells)} cell(s) but the header has {len(columns)} columns "
                f"({', '.join(names)})."
            )
        data.append(
            [
                _parse_number(cell, f"{where}, column '{name}'") * factor
                for cell, name, factor in zip(cells, names, factors)
            ]
        )
    if not data:
        raise ValueError(f"{path}: the file has a header but no data rows.")
    table = np.array(data, dtype=float)
    by_name = {name: table[:, i] for i, name in enumerate(names)}

    if not digitised:
        time = by_name["time"]
        bad = np.flatnonzero(np.diff(time) <= 0)
        if bad.size:
            row = bad[0] + 1
            raise ValueError(
                f"{path}, line {header_index + 2 + row}, column 'time': time must increase "
                f"strictly, but {time[row]:.9g} s follows {time[row - 1]:.9g} s."
            )

    normal_load = by_name.get("N")
    if normal_load is None:
        normal_load = _normal_load_from_metadata(metadata, table.shape[0])
    return TestRecord(
        time=by_name.get("time"),
        ux=by_name["ux"],
        fx=by_name["fx"],
        uy=by_name.get("uy"),
        fy=by_name.get("fy"),
        normal_load=normal_load,
        temperature=by_name.get("temperature"),
        metadata=metadata,
        extra_columns={name: by_name[name] for name in extra_units},
        extra_units=extra_units,
        path=path,
    )


# ----------------------------------------------------------------------------------------
# Writing


def _resolve_units(units) -> dict[str, str]:
    if units is None or units == "paper":
        return dict(PAPER_UNITS)
    if units == "SI":
        return dict(SI_UNITS)
    if isinstance(units, Mapping):
        chosen = dict(PAPER_UNITS)
        for dimension, unit in units.items():
            if dimension not in UNITS:
                raise ValueError(
                    f"units: unknown dimension '{dimension}'; use one of "
                    f"{', '.join(d for d in UNITS if d != 'dimensionless')}."
                )
            unit_factor(unit, dimension, where=f"units['{dimension}']")
            chosen[dimension] = unit
        return chosen
    raise ValueError(
        f"units: expected None or 'paper' (in, kip, s), 'SI' (m, N, s), or a mapping "
        f"dimension -> unit, got {units!r}."
    )


def write_test_record(path, record: TestRecord, *, units=None, digits: int = 9) -> None:
    """Write `record` in the project's test-record CSV format (see `read_test_record`).

    **Arguments:**

    - `path`: the file to write (overwritten).
    - `record`: a `TestRecord` (SI inside).
    - `units`: `None` or `"paper"` for the units of Constantinou, Mokha & Reinhorn (1990):
      in, kip, s, in^2, psi; `"SI"` for m, N, s, m^2, Pa; or a mapping dimension -> unit
      that overrides the paper's units (e.g. `{"length": "mm", "force": "kN"}`).
    - `digits`: significant digits written for every number (`%.{digits}g`).

    **Returns:** nothing. Reading the file back gives the record again to `digits`
    significant digits. The `N` column is left out when the normal load is the constant that
    the metadata (`normal_load`, or `contact_area` times `contact_pressure`) already states.
    """
    if not isinstance(record, TestRecord):
        raise TypeError(f"record: expected a TestRecord, got {type(record).__name__}.")
    chosen = _resolve_units(units)
    fmt = f"{{:.{digits}g}}".format

    lines = []
    for key, value in record.metadata.items():
        if key == _COMMENT_KEY:
            lines += [f"# {_COMMENT_KEY}: {text}" for text in value.split("\n")]
        elif key in _QUANTITY_KEYS:
            unit = chosen[_QUANTITY_KEYS[key]]
            factor = unit_factor(unit, _QUANTITY_KEYS[key], where=f"metadata '{key}'")
            lines.append(f"# {key} [{unit}]: {fmt(value / factor)}")
        elif key == "protocol":
            lines.append(f"# protocol: {value.to_text(chosen['length'], digits=digits)}")
        else:
            lines.append(f"# {key}: {value}")

    columns: list[tuple[str, str, np.ndarray]] = []
    for name in ("time", "ux", "fx", "uy", "fy", "N", "temperature"):
        values = getattr(record, "normal_load" if name == "N" else name)
        if values is None:
            continue
        if name == "N":
            implied = _normal_load_from_metadata(record.metadata, len(record))
            if implied is not None and np.array_equal(implied, values):
                continue
        columns.append((name, chosen[_COLUMN_DIMENSIONS[name]], values))
    for name, values in record.extra_columns.items():
        unit = record.extra_units[name]
        dimension = _dimension_of(unit)
        if dimension is not None and dimension in chosen and UNITS[dimension][unit] == 1.0:
            unit = chosen[dimension]
        columns.append((name, unit, values))

    header = []
    scaled = []
    for name, unit, values in columns:
        if "," in name or "[" in name or "]" in name:
            raise ValueError(f"record: column name '{name}' cannot hold ',', '[' or ']'.")
        dimension = _COLUMN_DIMENSIONS.get(name) or _dimension_of(unit)
        factor = 1.0 if dimension is None else unit_factor(unit, dimension, where=name)
        header.append(f"{name} [{unit}]")
        scaled.append(values / factor)
    lines.append(",".join(header))
    text_columns = [[fmt(v) for v in values] for values in scaled]
    if record.time is not None:
        times = [float(t) for t in text_columns[0]]
        if any(b <= a for a, b in itertools.pairwise(times)):
            raise ValueError(
                f"record: time written with {digits} significant digits no longer "
                f"increases strictly; pass a larger `digits`."
            )
    lines += [",".join(row) for row in zip(*text_columns)]
    pathlib.Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")
