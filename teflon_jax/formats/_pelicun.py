"""Demand samples for a FEMA P-58 loss assessment in pelicun's tabular format.

The file pelicun's `DemandModel.load_sample` reads (SimCenter tabular schema): a header row
of demand labels EVENT-TYPE-LOCATION-DIRECTION, a second row "Units" with each column's unit,
then one row per realisation, the first column its index. Columns a run writes here:

- `1-PFA-0-1`: peak ground acceleration (location 0, the ground);
- `1-PFA-<j+1>-1`: peak total acceleration of level j (j = 0 the base slab on the isolators,
  j >= 1 floor j), so location 1 is the isolation level's slab;
- `1-PID-<j+1>-1`: peak interstorey drift ratio of storey j (from level j-1 to level j), so
  the storey between locations L-1 and L is location L, as in P-58's numbering;
- `1-BRD-1-1`: the isolators' peak displacement as its own demand (pelicun has no isolator
  type; BRD is the library's "Peak Bearing Deformation", a displacement); `1-BRD-1-0` when it
  is the peak of the resultant of two components (non-directional: pelicun multiplies a
  non-directional demand by its NonDirectionalMultipliers, which for BRD should then be 1);
- `1-BRD_<slider>-1-1` (or `-0`, as BRD's direction): a double or triple friction pendulum's
  peak travel of each slider on its surface, the displacement its restrainer limits, one
  column per slider named by the isolator's slider names (`inner`, `bottom`, `top` of the
  triple; `bottom`, `top` of the double): a subtype of BRD in pelicun's TYPE_subtype form
  (as SA_1.0), so it loads as a displacement of its own type and a fragility reaches it by
  the demand type "Peak Bearing Deformation|<slider>"; direction 0 when the travel is the
  resultant of two components (then its NonDirectionalMultipliers entry, `BRD_<slider>` or
  ALL, should be 1);
- `1-ERROR`: 1 for a realisation whose solve failed (its peaks not trusted), else 0; pelicun
  drops those rows on loading, the file keeps them.

Direction 1 is the one horizontal component; with two, PFA and PID are written for directions 1
(x) and 2 (y), the ground's PFA-0 too where the peaks per direction are known (a suite of
record pairs; a two-component Monte Carlo keeps the resultant's only). Units are names of pelicun's unit table ('g',
'mps2', 'in', 'mm', 'm', 'unitless'). Reference: NHERI SimCenter, pelicun documentation
("Demand model", file formats); FEMA P-58-1 (2018), Seismic Performance Assessment of
Buildings, Vol. 1, Ch. 5 (demand parameters by storey and floor).
"""

import pathlib
import re

import numpy as np

from ..units import INCH, MM, STANDARD_GRAVITY

PELICUN_UNITS = {
    "acceleration": {"g": STANDARD_GRAVITY, "mps2": 1.0, "inps2": INCH},
    "length": {"in": INCH, "mm": MM, "m": 1.0},
}
"""Units a demand file may be written in: dimension -> {pelicun's name: SI factor}."""


def _column(values, name: str, rows: int) -> np.ndarray:
    array = np.asarray(values, float)
    if array.shape != (rows,):
        raise ValueError(f"{name}: expected shape {(rows,)} (one row per realisation), got {array.shape}.")
    return array


def _sliders(travel, names, rows: int) -> tuple[list, np.ndarray]:
    """(names, travel (R, S)) of the sliders' columns; `ValueError` naming the argument."""
    array = np.asarray(travel, float)
    if array.ndim != 2 or array.shape[0] != rows or array.shape[1] < 1:
        raise ValueError(f"slider_travel: expected shape ({rows}, S) (one row per realisation, one column per "
                         f"slider), got {array.shape}.")
    names = [str(s + 1) for s in range(array.shape[1])] if names is None else [str(n) for n in names]
    if len(names) != array.shape[1]:
        raise ValueError(f"slider_names: expected {array.shape[1]} names (one per column of slider_travel), "
                         f"got {len(names)}.")
    for name in names:
        if not re.fullmatch(r"[A-Za-z0-9.]+", name):
            raise ValueError(f"slider_names: {name!r} is not a demand subtype pelicun keeps apart; use letters, "
                             "digits and '.' only (no '-', '_', ',' or spaces).")
    if len(set(names)) != len(names):
        raise ValueError(f"slider_names: each slider needs its own name, got {', '.join(names)}.")
    return names, array


def _directions(values, name: str, rows: int) -> np.ndarray:
    """`values` as (R, directions, locations): (R, L) is one direction, (R, 2, L) two."""
    array = np.asarray(values, float)
    if array.ndim == 2:
        array = array[:, None, :]
    if array.ndim != 3 or array.shape[0] != rows or array.shape[1] not in (1, 2):
        raise ValueError(f"{name}: expected shape ({rows}, L) or ({rows}, 2, L) (one row per realisation), "
                         f"got {np.shape(values)}.")
    return array


def pelicun_demand_table(*, base_disp, failed, pga=None, level_acceleration=None, storey_drift=None,
                         base_direction: int = 1, slider_travel=None, slider_names=None,
                         acceleration_unit: str = "g", length_unit: str = "in") -> tuple[list, list, np.ndarray]:
    """(labels, units, values (R, C)) of a demand file (module docstring) from SI peaks.

    **Arguments:** `base_disp` (R,) [m]; `failed` (R,) bool; `pga` (R,) or in x and y (R, 2) [m/s^2];
    `level_acceleration` (R, S + 1) or per direction (R, 2, S + 1) [m/s^2], level 0 the base
    slab; `storey_drift` (R, S) or (R, 2, S) [-]; `base_direction`: 1, or 0 for a resultant
    (the sliders' direction too); `slider_travel` (R, S) [m]: a series pendulum's peak travel
    of each slider (`None`: no slider columns), labelled by `slider_names` (S,) (default
    "1", "2", ...); `acceleration_unit`, `length_unit`: names of `PELICUN_UNITS`.
    """
    for dimension, unit in (("acceleration", acceleration_unit), ("length", length_unit)):
        if unit not in PELICUN_UNITS[dimension]:
            raise ValueError(f"{dimension}_unit: unknown {unit!r}; accepted: {', '.join(PELICUN_UNITS[dimension])}.")
    failed = np.asarray(failed, bool)
    if failed.ndim != 1:
        raise ValueError(f"failed: expected one flag per realisation, got shape {failed.shape}.")
    rows = failed.shape[0]
    to_acc = PELICUN_UNITS["acceleration"][acceleration_unit]
    labels, units, columns = [], [], []
    if pga is not None:  # (R,) one direction, (R, 2) x and y
        ground = _directions(np.asarray(pga, float).reshape(rows, -1, 1) if np.size(pga) in (rows, 2 * rows)
                             else pga, "pga", rows)
        for d in range(ground.shape[1]):
            labels.append(f"1-PFA-0-{d + 1}"), units.append(acceleration_unit)
            columns.append(ground[:, d, 0] / to_acc)
    for name, values, kind, first, unit, scale in (
            ("level_acceleration", level_acceleration, "PFA", 1, acceleration_unit, to_acc),
            ("storey_drift", storey_drift, "PID", 2, "unitless", 1.0)):
        if values is None:
            continue
        array = _directions(values, name, rows)
        for j in range(array.shape[2]):
            for d in range(array.shape[1]):
                labels.append(f"1-{kind}-{j + first}-{d + 1}"), units.append(unit)
                columns.append(array[:, d, j] / scale)
    if base_direction not in (0, 1):
        raise ValueError(f"base_direction: 1, or 0 for a resultant, got {base_direction!r}.")
    labels.append(f"1-BRD-1-{base_direction}"), units.append(length_unit)
    columns.append(_column(base_disp, "base_disp", rows) / PELICUN_UNITS["length"][length_unit])
    if slider_travel is not None:
        names, travel = _sliders(slider_travel, slider_names, rows)
        for s, name in enumerate(names):
            labels.append(f"1-BRD_{name}-1-{base_direction}"), units.append(length_unit)
            columns.append(travel[:, s] / PELICUN_UNITS["length"][length_unit])
    labels.append("1-ERROR"), units.append("")
    columns.append(failed.astype(float))
    return labels, units, np.stack(columns, axis=1)


def write_pelicun_demands(path, **peaks) -> pathlib.Path:
    """Write the demand file of `pelicun_demand_table(**peaks)` to `path` (.csv); every value
    with 10 significant digits, the ERROR flags as 0 / 1. Returns the path."""
    path = pathlib.Path(path)
    labels, units, values = pelicun_demand_table(**peaks)
    error = len(labels) - 1
    lines = ["," + ",".join(labels), "Units," + ",".join(units)]
    for i, row in enumerate(values):
        cells = [str(int(v)) if j == error else f"{v:.10g}" for j, v in enumerate(row)]
        lines.append(f"{i}," + ",".join(cells))
    path.write_text("\n".join(lines) + "\n")
    return path


def check_pelicun_path(path, flag: str = "--pelicun-demands") -> pathlib.Path:
    """`path` once it can be written: a .csv name in an existing, writable folder; else a
    `ValueError` naming `flag`, before any run starts."""
    import os

    path = pathlib.Path(path)
    if path.suffix.lower() != ".csv":
        raise ValueError(f"{flag}: {path}: pelicun's demand file is a .csv; name it e.g. demands.csv.")
    folder = path.parent if str(path.parent) else pathlib.Path(".")
    if not folder.is_dir():
        raise ValueError(f"{flag}: {path}: folder {folder} does not exist.")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ValueError(f"{flag}: {path}: cannot write there (permission denied).")
    return path
