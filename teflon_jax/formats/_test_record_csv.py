"""Reading and writing the test-record CSV of FORMATS.md, with file-and-line errors."""

import itertools
import math
import pathlib
import re
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..excitation import TabulatedBiaxialMotion, TabulatedMotion, tabulated_motion
from ..tables import DIRECTIONS, PTFE_TYPES
from ..units import UNITS, parse_quantity, unit_factor
from ._protocol import parse_protocol
from ._record_loads import check_loads_agree, check_loads_as_written, check_written_loads
from ._test_record import (
    _COLUMN_DIMENSIONS,
    _COMMENT_KEY,
    _KEY_ALIASES,
    _METADATA_LINE,
    _QUANTITY_KEYS,
    _REQUIRED_COLUMNS,
    _TEXT_KEYS,
    INTERFACE_KEYS,
    PAPER_UNITS,
    SI_UNITS,
    TestRecord,
    _dimension_of,
    _normal_load_from_metadata,
    _si_unit,
    ambiguous_interfaces_message,
)

_HEADER_CELL = re.compile(r"^\s*(?P<name>[^\[\]]*?)\s*(?:\[(?P<unit>[^\[\]]*)\])?\s*$")

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
            *INTERFACE_KEYS,
            "ptfe",
            "protocol",
        )
    )
    if key == "interfaces":
        raise ValueError(ambiguous_interfaces_message(where))
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
        if value.upper() not in DIRECTIONS:
            raise ValueError(
                f"{where}: metadata 'direction' must be P (sliding parallel to the lay of "
                f"the steel) or T (perpendicular), got '{value}'."
            )
        metadata[key] = value.upper()
    elif key in INTERFACE_KEYS:
        if not re.fullmatch(r"\d+", value) or int(value) < 1:
            raise ValueError(
                f"{where}: metadata '{key}' must be a whole number >= 1, got '{value}'."
            )
        metadata[key] = int(value)
    elif key == "ptfe":
        if value.upper() not in PTFE_TYPES:
            raise ValueError(
                f"{where}: metadata 'ptfe' must be one of {', '.join(PTFE_TYPES)}, "
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


def _read_columns(path, columns_required, digitised_columns, positive=(), only=None):
    """(path, metadata, by_name, extra_units) of a file in the test-record CSV format: the
    metadata in SI, every column in SI by name, the units of the extra columns. A file without
    a `time` column is a digitised loop (needing `digitised_columns` and a protocol) when
    `digitised_columns` is not `None`, otherwise `time` is required like `columns_required`;
    the columns named in `positive` must be > 0 in every row; a column not in `only` (when
    given) is refused."""
    path = pathlib.Path(path)
    with open(path, encoding="utf-8-sig", newline=None) as file:
        lines = file.read().split("\n")
    while lines and not lines[-1].strip():
        lines.pop()
    metadata, header_index = _metadata_and_header(lines, path)
    columns = _parse_header(lines[header_index], f"{path}, line {header_index + 1}")
    names = [name for name, _ in columns]
    digitised = "time" not in names and digitised_columns is not None
    required = digitised_columns if digitised else columns_required
    _check_required_columns(names, required, digitised, metadata, path, header_index)
    _refuse_unread_columns(names, only or names, path, header_index)
    factors, extra_units = _column_factors(columns, path, header_index)
    table = _read_data_rows(lines, header_index, names, factors, path)
    by_name = {name: table[:, i] for i, name in enumerate(names)}
    if not digitised:
        _check_time_increases(by_name["time"], path, header_index)
    check_loads_agree(lines, header_index, metadata, by_name, path)
    for name, unit in columns:
        if name in positive and np.any(by_name[name] <= 0):
            row = int(np.argmax(by_name[name] <= 0))
            cell = lines[header_index + 1 + row].split(",")[names.index(name)].strip()
            raise ValueError(f"{path}, line {header_index + 2 + row}, column '{name}': must be > 0 "
                             f"(compression positive), got {cell} {unit}; repair or remove the sample.")
    return path, metadata, by_name, extra_units


def _metadata_and_header(lines, path) -> tuple:
    """(metadata in SI, index of the header line) of the lines of a test-record file."""
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
    return metadata, header_index


def _check_required_columns(names, required, digitised, metadata, path, header_index):
    """Raise when a required column is missing, or a digitised loop states no protocol."""
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


_MEASURED_COLUMNS = ("fx", "fy", "N", "temperature")  # a test's own file replays its displacement


def _refuse_unread_columns(names, only, path, header_index) -> None:
    """Raise at the first column of `names` neither in `only` nor measured (`_MEASURED_COLUMNS`)."""
    for name in (name for name in names if name not in only and name not in _MEASURED_COLUMNS):
        hint = ", or name it 'uy' if it is the displacement along y" if name in ("y", "dy") else ""
        raise ValueError(f"{path}, line {header_index + 1}, column '{name}': an imposed motion takes only the "
                         f"columns {', '.join(repr(n) for n in only)} ('uy' for a biaxial path), so this one "
                         f"would be left out; remove it{hint}.")


def _column_factors(columns, path, header_index) -> tuple:
    """(SI factor of each column, SI unit of each extra column by name)."""
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
    return factors, extra_units


def _read_data_rows(lines, header_index, names, factors, path) -> np.ndarray:
    """The data rows after the header, in SI, one column per name."""
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
        if len(cells) != len(names):
            raise ValueError(
                f"{where}: {len(cells)} cell(s) but the header (line {header_index + 1}) has {len(names)} "
                f"columns ({', '.join(names)}); make the header and every row hold the same number of cells."
            )
        data.append(
            [
                _parse_number(cell, f"{where}, column '{name}'") * factor
                for cell, name, factor in zip(cells, names, factors)
            ]
        )
    if not data:
        raise ValueError(f"{path}: the file has a header but no data rows.")
    return np.array(data, dtype=float)


def _check_time_increases(time, path, header_index) -> None:
    """Raise at the first sample whose time does not exceed the one before."""
    bad = np.flatnonzero(np.diff(time) <= 0)
    if bad.size:
        row = bad[0] + 1
        raise ValueError(
            f"{path}, line {header_index + 2 + row}, column 'time': time must increase "
            f"strictly, but {time[row]:.9g} s follows {time[row - 1]:.9g} s."
        )


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
    number of cells, time that does not increase strictly, a normal load N <= 0, a missing
    required column, a digitised loop without a protocol, or a `# normal_load` (or a
    `# contact_area` times `# pressure`) that differs from the `N` column (or from
    `# normal_load`) by more than 1e-6 of it. Nothing is dropped or filled in.
    """
    path, metadata, by_name, extra_units = _read_columns(path, _REQUIRED_COLUMNS, ("ux", "fx"), positive=("N",))
    n_rows = by_name["ux"].shape[0]
    normal_load = by_name.get("N")
    if normal_load is None:
        normal_load = _normal_load_from_metadata(metadata, n_rows)
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


def read_motion_record(path) -> TabulatedMotion | TabulatedBiaxialMotion:
    """Read an imposed displacement history in the test-record CSV format (`FORMATS.md`):
    the same metadata lines, header (`name [unit]`) and checks as `read_test_record`, with
    the columns `time` and `ux` required and `uy` optional (a biaxial path); a test's measured
    columns (fx, fy, N, temperature) may stay, and any other (a `y`) is refused, not left out.

    **Returns:** a `TabulatedMotion` (along x) or, with `uy`, a `TabulatedBiaxialMotion` [m]
    (linear between samples); `ValueError` naming the file, line and column for anything `read_test_record` refuses.
    """
    path, _, by_name, _ = _read_columns(path, ("time", "ux"), None, only=("time", "ux", "uy"))
    try:
        return tabulated_motion(by_name["time"], by_name["ux"], by_name.get("uy"))
    except ValueError as error:
        raise ValueError(f"{path}: {error}") from None


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
    significant digits; a record whose normal load, as written to `digits` digits, the file
    would state twice in ways more than 1e-6 apart (`contact_area` times `contact_pressure`
    against `normal_load` or the `N` column) is a `ValueError` naming `digits`, and nothing is
    written. The `N` column is left out when the normal load is the constant that
    the metadata (`normal_load`, or `contact_area` times `contact_pressure`) already states; a
    metadata `normal_load`, or `contact_area` times `contact_pressure`, that the history (or
    `normal_load`) contradicts by more than 1e-6 of it is a `ValueError`.
    """
    if not isinstance(record, TestRecord):
        raise TypeError(f"record: expected a TestRecord, got {type(record).__name__}.")
    chosen = _resolve_units(units)
    check_written_loads(record.metadata, record.normal_load)
    fmt = f"{{:.{digits}g}}".format

    lines = []
    as_written = dict(record.metadata)
    for key, value in record.metadata.items():
        if key == _COMMENT_KEY:
            lines += [f"# {_COMMENT_KEY}: {text}" for text in value.split("\n")]
        elif key in _QUANTITY_KEYS:
            unit = chosen[_QUANTITY_KEYS[key]]
            factor = unit_factor(unit, _QUANTITY_KEYS[key], where=f"metadata '{key}'")
            lines.append(f"# {key} [{unit}]: {fmt(value / factor)}")
            as_written[key] = float(fmt(value / factor)) * factor
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
    factors = []
    for name, unit, values in columns:
        if "," in name or "[" in name or "]" in name:
            raise ValueError(f"record: column name '{name}' cannot hold ',', '[' or ']'.")
        dimension = _COLUMN_DIMENSIONS.get(name) or _dimension_of(unit)
        factor = 1.0 if dimension is None else unit_factor(unit, dimension, where=name)
        header.append(f"{name} [{unit}]")
        scaled.append(values / factor)
        factors.append(factor)
    lines.append(",".join(header))
    text_columns = [[fmt(v) for v in values] for values in scaled]
    if record.time is not None:
        times = [float(t) for t in text_columns[0]]
        if any(b <= a for a, b in itertools.pairwise(times)):
            raise ValueError(
                f"record: time written with {digits} significant digits no longer "
                f"increases strictly; pass a larger `digits`."
            )
    load_column = next((index for index, (name, _, _) in enumerate(columns) if name == "N"), None)
    check_loads_as_written(as_written, None if load_column is None else
                           factors[load_column] * np.array(text_columns[load_column], dtype=float), digits)
    lines += [",".join(row) for row in zip(*text_columns)]
    pathlib.Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")
