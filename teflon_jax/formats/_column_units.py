"""The units a two-column record's text header states in brackets (`time [ms]`, `acc (g)`) or
after an underscore (`time_ms`, `acc_g`), checked against the units the reader is given."""

import math
import re

from ..units import is_unit, unit_factor

_BRACKETED = re.compile(r"\[([^\[\]]*)\]|\(([^()]*)\)")
_FIELD_SPLIT = re.compile(r"\s*,\s*|\s+")
_WHITESPACE_CELL = re.compile(r"[^\s,()\[\]]+(?:\s*(?:\[[^\[\]]*\]|\([^()]*\)))*|\[[^\[\]]*\]|\([^()]*\)")


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _header_cells(line: str) -> list[str]:
    """The cells of a header line: split at commas, else at spaces outside brackets."""
    if "," in line:
        return [cell.strip() for cell in line.split(",")]
    return _WHITESPACE_CELL.findall(line)


def _suffix_unit(cell: str, dimension: str) -> str | None:
    """The longest text after an underscore in `cell` that is a unit of `dimension` (`time_ms`,
    `acc_g`, `acc_g_n`), or None: a name that merely holds an underscore (`ground_acc`,
    `time_step`) states no unit."""
    parts = cell.split("_")
    for start in range(1, len(parts)):
        suffix = "_".join(parts[start:])
        try:
            unit_factor(suffix, dimension, where=cell)
        except ValueError:
            continue
        return suffix
    return None


def _header_unit(cell: str, dimension: str) -> str | None:
    """The last bracketed text of `cell` that reads as a unit (`(N-S)` is a label), else the
    unit of `dimension` after an underscore, or None."""
    units = [a or b for a, b in _BRACKETED.findall(cell) if is_unit((a or b).strip())]
    if units:
        return units[-1].strip()
    return _suffix_unit(_BRACKETED.sub("", cell).strip(), dimension)


def header_time_factor(lines, first_data_line, width, path, time_column, acceleration_column,
                       units) -> float:
    """The factor [s] of the time column's unit in the header (1 without one), after checking
    the acceleration column's unit, where the header states it, against `units`.

    The header is the last line before `first_data_line` (1-based) that is neither blank nor a
    `#` comment. `ValueError` naming the file, line and column for a unit of the wrong dimension,
    or an acceleration unit other than `units`; naming the file and line for a header whose
    number of cells differs from the rows' `width` (a line holding a number is no header, but a
    line skipped by `skip_header`, and is left alone)."""
    header = next(((number, line.strip()) for number, line in
                   reversed(list(enumerate(lines[:first_data_line - 1], start=1)))
                   if line.strip() and not line.strip().startswith("#")), None)
    if header is None:
        return 1.0
    line_no, text = header
    cells = _header_cells(text)
    if len(cells) != width:
        if any(_is_number(field) for field in _FIELD_SPLIT.split(text)):
            return 1.0
        raise ValueError(
            f"{path}, line {line_no}: the header '{text}' has {len(cells)} cell(s), but the data rows "
            f"(from line {first_data_line}) have {width}, so its names and units cannot be matched to "
            f"the columns; make them match, one name per column (e.g. 'time [s],acc [g]'), or turn "
            "the line into a '#' comment."
        )
    time_unit = _header_unit(cells[time_column], "time")
    acceleration_unit = _header_unit(cells[acceleration_column], "acceleration")
    where = f"{path}, line {line_no}, column {{}} ('{{}}')"
    if acceleration_unit is not None:
        stated = unit_factor(acceleration_unit, "acceleration",
                             where=where.format(acceleration_column + 1, cells[acceleration_column]))
        if not math.isclose(stated, unit_factor(units, "acceleration", where=f"{path}: units"),
                            rel_tol=1e-9):
            raise ValueError(
                f"{where.format(acceleration_column + 1, cells[acceleration_column])}: the header gives "
                f"the acceleration in {acceleration_unit}, but the record is read in {units}; fix the "
                f"header, or read the record in {acceleration_unit} (--record-units {acceleration_unit})."
            )
    if time_unit is None:
        return 1.0
    return unit_factor(time_unit, "time", where=where.format(time_column + 1, cells[time_column]))
