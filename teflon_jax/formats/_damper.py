"""Reader for the measured banded rotary friction damper tests of the ARTS Laboratory.

The data set (Coble, Huggins, Cao, Ricles & Downey, "Dataset-Friction-Damper-with-
Backlash", GitHub, 2022, CC BY-SA 4.0) holds force-displacement tests of a banded rotary
friction device (BRFD; Downey et al., Engineering Structures 113:287-298, 2016) under
imposed sinusoidal displacement. It is real measured friction with backlash and a strong
asymmetry between the two sliding directions -- a band brake, not a PTFE slider -- so it
serves to try the identification tools on laboratory data, not to obtain PTFE friction
constants.
"""

import math
import pathlib
import re

import numpy as np

from ..units import INCH, unit_factor
from ._protocol import Protocol
from ._test_record import TestRecord
from ._text import read_json_document

DAMPER_SOURCE = (
    "D. Coble, P. Huggins, L. Cao, J. Ricles, A. Downey, 'Dataset-Friction-Damper-with-"
    "Backlash', GitHub (ARTS-Laboratory), 2022, CC BY-SA 4.0; device: Downey et al., Eng. "
    "Struct. 113:287-298 (2016), doi:10.1016/j.engstruct.2016.01.035"
)

DAMPER_NORMAL_LOAD_NOTE = (
    "no normal load: a band brake has no contact force to divide by; fit the force with a "
    "unit normal load (normal_load = 1 N), so that friction coefficients come out in "
    "newtons"
)

# Columns of each row of `data`, in order, and the key of the unit of each.
_ROW = (
    "time",
    "displacement",
    "friction force",
    "velocity",
    "actuator force 1",
    "actuator force 2",
)


_UNIT_KEYS = {
    "time units": "time",
    "displacement units": "length",
    "friction force units": "force",
    "actuator force units": "force",
}


# The repository names the tests '<frequency>Hz<tension>lbtension<amplitude>amplitude.json'.
_FILE_NAME = re.compile(
    r"^(?P<frequency>\d+(?:\.\d+)?)Hz(?P<tension>\d+(?:\.\d+)?)lbtension"
    r"(?P<amplitude>\d+(?:\.\d+)?)amplitude$"
)


def read_friction_damper_json(path) -> TestRecord:
    """Read one test of the banded rotary friction damper data set as a `TestRecord`.

    The JSON object holds `data`, a list of rows `[time, displacement, friction force,
    velocity, actuator force 1, actuator force 2]`, the sampling step `dt` [s], the
    `sampling freq` [Hz], and the units in `time units` (s), `displacement units` (in),
    `friction force units` (kip) and `actuator force units` (lb). The velocity has no unit
    key; it is in displacement units per time unit (in/s), as the repository's README
    states.

    Everything is converted to SI: `ux` [m] is the displacement, `fx` [N] the friction force
    (positive while moving in +x, as the project's format asks; the energy dissipated,
    `integral fx dux`, is positive). The velocity [m/s] and the two actuator forces [N] are
    kept in `extra_columns` as `velocity`, `actuator_force_1` and `actuator_force_2`.

    **Normal load.** A band brake has no normal load to divide the friction force by: the
    band tension sets the friction, and the clamping force along the drum is not measured.
    The record therefore has `normal_load=None`, and `metadata["note"]` says so. To fit a
    friction model to it, pass a unit normal load (1 N) to the fitter: the model's
    `F = mu W Z` then fits the force itself, and the fitted "coefficients" `f_max` and
    `delta_f` are forces in newtons rather than ratios.

    When the file name follows the data set's convention
    (`<f>Hz<T>lbtension<A>amplitude.json`), `metadata["protocol"]` is the sine of amplitude
    `A` [in] and frequency `f` [Hz] and `metadata["band_tension [lbf]"]` the tension `T`.

    **Arguments:**

    - `path`: the JSON file.

    **Returns:** a `TestRecord` (SI). Raises `ValueError` naming the key, row or value that
    is missing or wrong.
    """
    path = pathlib.Path(path)
    content = _load_damper_object(path)
    factors = _unit_factors(content, path)
    sampling, dt_seconds = _sampling(content, factors, path)
    table = _data_table(content, path)
    time = table[:, 0] * factors["time units"]
    _check_time_steps(time, dt_seconds, path)
    length = factors["displacement units"]
    force = factors["actuator force units"]
    return TestRecord(
        time=time,
        ux=table[:, 1] * length,
        fx=table[:, 2] * factors["friction force units"],
        normal_load=None,
        metadata=_damper_metadata(path, sampling),
        extra_columns={
            "velocity": table[:, 3] * length / factors["time units"],
            "actuator_force_1": table[:, 4] * force,
            "actuator_force_2": table[:, 5] * force,
        },
        extra_units={"velocity": "m/s", "actuator_force_1": "N", "actuator_force_2": "N"},
        path=path,
    )


def _load_damper_object(path: pathlib.Path) -> dict:
    """The file's JSON object, checked to hold every key the damper files have."""
    content = read_json_document(path, "friction-damper JSON file")
    if not isinstance(content, dict):
        raise ValueError(f"{path}: expected a JSON object with the key 'data'.")
    for key in ("data", "dt", "sampling freq", *_UNIT_KEYS):
        if key not in content:
            raise ValueError(
                f"{path}: key '{key}' is missing; the damper files have 'data', 'dt', "
                f"'sampling freq' and {', '.join(repr(k) for k in _UNIT_KEYS)}."
            )
    return content


def _unit_factors(content: dict, path: pathlib.Path) -> dict:
    """SI factor of each unit key of the file."""
    factors = {}
    for key, dimension in _UNIT_KEYS.items():
        unit = content[key]
        if not isinstance(unit, str):
            raise ValueError(f"{path}: key '{key}' must be a unit name, got {unit!r}.")
        factors[key] = unit_factor(unit, dimension, where=f"{path}, key '{key}'")
    return factors


def _sampling(content: dict, factors: dict, path: pathlib.Path) -> tuple:
    """(sampling frequency [Hz], time step [s]), checked against each other."""
    dt = _positive_number(content, "dt", path)
    sampling = _positive_number(content, "sampling freq", path)
    dt_seconds = dt * factors["time units"]
    if abs(sampling * dt_seconds - 1.0) > 1e-6:
        raise ValueError(
            f"{path}: key 'sampling freq' ({sampling} Hz) does not match key 'dt' "
            f"({dt} {content['time units']}); the file is inconsistent."
        )
    return sampling, dt_seconds


def _data_table(content: dict, path: pathlib.Path) -> np.ndarray:
    """The rows of key 'data' as a float array, each row checked for six finite numbers."""
    rows = content["data"]
    if not isinstance(rows, list) or not rows:
        raise ValueError(f"{path}: key 'data' must be a non-empty list of rows.")
    for index, row in enumerate(rows):
        if not isinstance(row, list) or len(row) != len(_ROW):
            raise ValueError(
                f"{path}: key 'data', row {index}: expected {len(_ROW)} values "
                f"({', '.join(_ROW)}), got {row!r}."
            )
        for name, value in zip(_ROW, row):
            if not (
                isinstance(value, (int, float))
                and not isinstance(value, bool)
                and math.isfinite(value)
            ):
                raise ValueError(
                    f"{path}: key 'data', row {index}, '{name}': {value!r} is not a finite "
                    f"number."
                )
    return np.array(rows, dtype=float)


def _check_time_steps(time: np.ndarray, dt_seconds: float, path: pathlib.Path) -> None:
    """Raise at the first time step that differs from key 'dt' by more than 0.1 %."""
    steps = np.diff(time)
    if steps.size and np.max(np.abs(steps - dt_seconds)) > 1e-3 * dt_seconds:
        row = int(np.argmax(np.abs(steps - dt_seconds))) + 1
        raise ValueError(
            f"{path}: key 'data', row {row}: time step {steps[row - 1]:.9g} s differs from "
            f"key 'dt' ({dt_seconds:.9g} s)."
        )


def _damper_metadata(path: pathlib.Path, sampling: float) -> dict:
    """Source and note, and the protocol and band tension when the file name states them."""
    metadata = {
        "source": DAMPER_SOURCE,
        "specimen": "banded rotary friction device (BRFD), not PTFE",
        "note": DAMPER_NORMAL_LOAD_NOTE,
        "sampling_frequency [Hz]": f"{sampling:g}",
    }
    match = _FILE_NAME.match(path.stem)
    if match is not None:
        metadata["protocol"] = Protocol(
            "sine",
            amplitude=float(match["amplitude"]) * INCH,
            frequency=float(match["frequency"]),
        )
        metadata["band_tension [lbf]"] = match["tension"]
    return metadata


def _positive_number(content: dict, key: str, path: pathlib.Path) -> float:
    value = content[key]
    if (
        isinstance(value, bool)
        or not isinstance(value, (int, float))
        or not math.isfinite(value)
        or value <= 0
    ):
        raise ValueError(f"{path}: key '{key}' must be a positive number, got {value!r}.")
    return float(value)
