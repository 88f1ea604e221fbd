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
import math
import pathlib
import re
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..tables import DIRECTIONS, PTFE_TYPES
from ..units import UNITS
from ._protocol import Protocol

_METADATA_KEY = re.compile(r"[^\[\]:\n#]*[^\[\]:\n\s#](?: \[[^\[\]:\n]*\])?")

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

_METADATA_LINE = re.compile(
    r"^#\s*(?P<key>[^\[\]:]*?)\s*(?:\[(?P<unit>[^\[\]]*)\])?\s*:\s*(?P<value>.*?)\s*$"
)


_TEXT_KEYS = ("specimen", "source")


INTERFACE_KEYS = ("interfaces_in_parallel", "interfaces_in_series")
"""Metadata keys of specimens with several sliding interfaces (FORMATS.md): n identical
interfaces side by side whose forces are recorded together (fx = n mu(v) N Z), or a stack of n
sharing the motion (fx = mu(v / n) N Z). Both default to 1."""


def ambiguous_interfaces_message(where: str) -> str:
    """The error for the bare `interfaces` key, which meant opposite things to different tools."""
    return (
        f"{where}: metadata 'interfaces' is ambiguous and no longer accepted; write "
        f"'interfaces_in_parallel' (n interfaces side by side, forces recorded together: "
        f"fx = n mu(v) N Z, the paper's two-interface rig) or 'interfaces_in_series' (a stack "
        f"of n sharing the motion: fx = mu(v / n) N Z)."
    )


def interface_counts(metadata: Mapping[str, Any]) -> tuple[int, int]:
    """`(interfaces_in_parallel, interfaces_in_series)` of a record's metadata (1 when absent)."""
    return (int(metadata.get("interfaces_in_parallel", 1)),
            int(metadata.get("interfaces_in_series", 1)))


_COMMENT_KEY = "comment"

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


def _si_unit(dimension: str) -> str:
    """The SI spelling of `dimension` (the unit whose factor is exactly 1)."""
    return next(unit for unit, factor in UNITS[dimension].items() if factor == 1.0)


def _dimension_of(unit: str) -> str | None:
    """The dimension that lists `unit`, or `None` when no table lists it."""
    for dimension, table in UNITS.items():
        if dimension != "dimensionless" and unit in table:
            return dimension
    return None


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
            if value not in DIRECTIONS:
                raise ValueError(
                    f"{where}: metadata 'direction' must be 'P' (parallel to the lay of "
                    f"the steel) or 'T' (perpendicular), got {value!r}."
                )
        elif key == "interfaces":
            raise ValueError(ambiguous_interfaces_message(where))
        elif key in INTERFACE_KEYS:
            if (
                isinstance(value, bool)
                or not isinstance(value, (int, np.integer))
                or value < 1
            ):
                raise ValueError(
                    f"{where}: metadata '{key}' must be a whole number >= 1, got {value!r}."
                )
            value = int(value)
        elif key == "ptfe":
            if value not in PTFE_TYPES:
                raise ValueError(
                    f"{where}: metadata 'ptfe' must be one of {', '.join(PTFE_TYPES)}, "
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
                    f"only {', '.join(_QUANTITY_KEYS)}, {', '.join(INTERFACE_KEYS)} and "
                    f"protocol hold "
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
      `interfaces_in_parallel`, `interfaces_in_series` (int; see `INTERFACE_KEYS`; the
      bare `interfaces` is refused as ambiguous), `ptfe` (`"UF"`, `"15GF"`, `"25GF"`), `specimen`, `source` (text),
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
