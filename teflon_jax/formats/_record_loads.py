"""The normal load a test record states more than once (an `N` column, `# normal_load`,
`# contact_area` times `# pressure`), checked to agree when read and before it is written."""

import re

import numpy as np

from ..units import unit_factor
from ._test_record import _KEY_ALIASES, _METADATA_LINE

LOAD_TOLERANCE = 1e-6
"""Relative difference [-] beyond which two statements of the normal load contradict."""

_TOLERANCE = f"{LOAD_TOLERANCE:.0e}".replace("e-0", "e-")

_INLINE_UNIT = re.compile(r"^[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\s*(?P<unit>\S.*)$")


def _metadata_line(lines, header_index, key):
    """(1-based line number, `re.Match`) of the metadata line of `key` (after its alias)."""
    return next((index + 1, match) for index, line in enumerate(lines[:header_index])
                if (match := _METADATA_LINE.match(line.strip()))
                and _KEY_ALIASES.get(match.group("key"), match.group("key")) == key)


def _force_unit(match) -> str:
    """The force unit a `# normal_load` line states, in brackets or after its number ('N' if none)."""
    unit = match.group("unit")
    if unit is None and (inline := _INLINE_UNIT.match(match.group("value"))):
        unit = inline.group("unit").strip()
    try:
        unit_factor(unit, "force", where="")
    except (TypeError, ValueError):
        return "N"
    return unit


def check_loads_agree(lines, header_index, metadata, by_name, path) -> None:
    """Raise `ValueError` naming the file and lines when the `# normal_load` line or the product
    `# contact_area` x `# pressure` [N] differs from the `N` column (or from `# normal_load`) by
    more than `LOAD_TOLERANCE` of it: the file would state two loads."""
    column = by_name.get("N")
    if column is not None and "normal_load" in metadata:
        _check_normal_load_line(lines, header_index, metadata["normal_load"], column, path)
    if "contact_area" in metadata and "contact_pressure" in metadata:
        _check_area_times_pressure(lines, header_index, metadata, column, path)


def _check_normal_load_line(lines, header_index, load, column, path) -> None:
    bad = np.flatnonzero(np.abs(column - load) > LOAD_TOLERANCE * load)
    if not bad.size:
        return
    line_no, _ = _metadata_line(lines, header_index, "normal_load")
    cell, unit, row_line = _n_cell(lines, header_index, bad[0])
    raise ValueError(
        f"{path}, line {line_no}: '{lines[line_no - 1].strip()}' contradicts the N column ('{unit}'), "
        f"which holds {cell} on line {row_line}; the N column is the load used, so "
        "remove the metadata line or make the two agree."
    )


def _n_cell(lines, header_index, row):
    """(text of the `N` cell of data row `row`, the N column's header cell, its 1-based line)."""
    header = [cell.strip() for cell in lines[header_index].split(",")]
    index = next(i for i, cell in enumerate(header) if re.fullmatch(r"N\s*(?:\[[^\[\]]*\])?", cell))
    return lines[header_index + 1 + row].split(",")[index].strip(), header[index], header_index + 2 + row


def _check_area_times_pressure(lines, header_index, metadata, column, path) -> None:
    """Raise when `contact_area * contact_pressure` contradicts the `N` column, else `# normal_load`."""
    product = metadata["contact_area"] * metadata["contact_pressure"]
    area_no, _ = _metadata_line(lines, header_index, "contact_area")
    pressure_no, _ = _metadata_line(lines, header_index, "contact_pressure")
    stated = f"'{lines[area_no - 1].strip()}' times '{lines[pressure_no - 1].strip()}'"
    if column is not None:
        bad = np.flatnonzero(np.abs(column - product) > LOAD_TOLERANCE * product)
        if not bad.size:
            return
        cell, header, row_line = _n_cell(lines, header_index, bad[0])
        unit = header[header.index("[") + 1:header.rindex("]")].strip()
        where = f"lines {min(area_no, pressure_no)}, {max(area_no, pressure_no)} and {row_line}"
        used, load = "the N column", f"the N column ('{header}') holds {cell} on line {row_line}"
    else:
        load_value = metadata["normal_load"] if "normal_load" in metadata else None
        if load_value is None or abs(load_value - product) <= LOAD_TOLERANCE * product:
            return
        load_no, match = _metadata_line(lines, header_index, "normal_load")
        unit = _force_unit(match)
        first, second, third = sorted((area_no, pressure_no, load_no))
        where = f"lines {first}, {second} and {third}"
        used, load = "'# normal_load'", f"line {load_no} states '{lines[load_no - 1].strip()}'"
    value = product / unit_factor(unit, "force", where=f"{path}, {where}")
    raise ValueError(
        f"{path}, {where}: {stated} is a normal load of {value:.9g} {unit}, but {load}; the contact area "
        f"times the pressure must equal the normal load to {_TOLERANCE} of it. {used[0].upper()}"
        f"{used[1:]} is the load used, so remove the pressure line (the pressure follows from the load "
        "and the contact area) or correct the contact area or the pressure."
    )


def check_written_loads(metadata, normal_load) -> None:
    """Raise `ValueError` before a record is written whose metadata `normal_load` or
    `contact_area * contact_pressure` [N] contradicts its normal-load history `normal_load`
    (or, for the product, the metadata `normal_load`): a reader would refuse the file."""
    load = metadata.get("normal_load")
    if load is not None and normal_load is not None and np.any(np.abs(normal_load - load) > LOAD_TOLERANCE * load):
        raise ValueError(f"record: metadata 'normal_load' ({load:g} N) contradicts the normal-load "
                         "history (column N), which a reader would refuse; drop one of them.")
    if "contact_area" not in metadata or "contact_pressure" not in metadata:
        return
    area, pressure = metadata["contact_area"], metadata["contact_pressure"]
    product = area * pressure
    for name, values in (("metadata 'normal_load'", load), ("the normal-load history (column N)", normal_load)):
        if values is None:
            continue
        values = np.ravel(values)
        if np.any(np.abs(values - product) > LOAD_TOLERANCE * product):
            worst = float(values[np.argmax(np.abs(values - product))])
            raise ValueError(
                f"record: metadata 'contact_area' ({area:g} m^2) times 'contact_pressure' ({pressure:g} Pa) is "
                f"{product:g} N, but {name} is {worst:g} N, more than {_TOLERANCE} of it apart, so the "
                "file would state two loads, which a reader refuses; drop 'contact_pressure' from the metadata "
                "or make the two agree."
            )


def check_loads_as_written(metadata, normal_load, digits: int) -> None:
    """Raise `ValueError` naming `digits` when the normal load, as a file states it after each
    number is rounded to `digits` significant digits (`metadata` and `normal_load` [N] as read
    back), contradicts itself: the reader would refuse what the writer wrote."""
    try:
        check_written_loads(metadata, normal_load)
    except ValueError as error:
        detail = str(error).removeprefix("record: ").removesuffix(".")
        raise ValueError(f"record: written with {digits} significant digits, {detail}; or pass a "
                         "larger `digits`.") from None
