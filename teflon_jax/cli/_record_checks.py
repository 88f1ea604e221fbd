"""What `teflon-jax run` checks of its records before any work: `--record-units` only where a
two-column file needs it, two columns in a column file, a peak acceleration that a ground
motion can have (after `--scale` too) and a solver step that resolves the records."""

import dataclasses
import pathlib
import sys

import numpy as np

from ..units import STANDARD_GRAVITY
from ._common import check_time_step

MAX_RECORD_PGA = 5 * STANDARD_GRAVITY
"""The largest peak ground acceleration a record may have [m/s^2]: 5 g, beyond any recorded
motion (the bound of `montecarlo --pga`)."""

RARE_RECORD_PGA = 2 * STANDARD_GRAVITY
"""A peak ground acceleration [m/s^2] above which a record is among the few strongest ever
recorded; a column file read in g that peaks above it is reported, in case its unit is wrong."""

RECORD_FLAGS = (("record_x", "--record-x"), ("record_y", "--record-y"), ("record_z", "--record-z"))
"""The record flags of `run`: (attribute, flag)."""


def is_at2(path) -> bool:
    """Whether `path` names a PEER AT2 file (by its suffix, as `run` reads it)."""
    return pathlib.Path(path).suffix.lower() == ".at2"


def check_record_units(units, records) -> None:
    """`ValueError` naming --record-units when it is given but every record of `records`
    ((flag, path) pairs) is a PEER AT2 file, which states its own unit (line 3)."""
    if units is None or not records or not all(is_at2(path) for _, path in records):
        return
    shown = ", ".join(f"{flag} {path}" for flag, path in records)
    kind = "is a PEER AT2 file, which states" if len(records) == 1 else "are PEER AT2 files, which state"
    raise ValueError(f"--record-units {units}: {shown} {kind} the unit of its accelerations on line 3, "
                     "and that unit is used; --record-units is for two-column files only, so leave it out.")


@dataclasses.dataclass(frozen=True)
class RecordFiles:
    """The record files of one run and the factor they are scaled by: --record-x, --record-y,
    --record-z and --scale (`of`), or a suite pair's columns with its scale times --scale."""

    x: str | None
    y: str | None
    z: str | None
    scale: float

    @classmethod
    def of(cls, args) -> "RecordFiles":
        """The records given on `run`'s command line."""
        return cls(args.record_x, args.record_y, args.record_z, args.scale)

    def named(self) -> list[tuple[str, str]]:
        """(flag, path) of the records given."""
        return [(flag, str(path)) for (_, flag), path in zip(RECORD_FLAGS, (self.x, self.y, self.z))
                if path is not None]


def check_peak(motion, flag: str, path, units) -> None:
    """`ValueError` naming `flag` and the file when the record's peak acceleration is above
    `MAX_RECORD_PGA` (for a column file, naming --record-units as read); a warning when a
    column file read in g peaks above `RARE_RECORD_PGA`."""
    acceleration = np.abs(np.asarray(motion.acceleration, float))
    index = int(np.argmax(acceleration))
    peak, when = float(acceleration[index]) / STANDARD_GRAVITY, float(motion.start_time) + index * float(motion.time_step)
    read = ("its line 3's unit" if is_at2(path) else f"--record-units {units}")
    if peak * STANDARD_GRAVITY > MAX_RECORD_PGA:
        fix = ("check the unit on its line 3" if is_at2(path) else
               "are its values in another unit? give that one with --record-units (g, m/s^2, cm/s^2, in/s^2)")
        raise ValueError(f"{flag} {path}: read in {read}, it peaks at {peak:.4g} g (at {when:g} s), beyond "
                         f"any recorded ground motion (at most {MAX_RECORD_PGA / STANDARD_GRAVITY:g} g); {fix}.")
    if not is_at2(path) and units == "g" and peak * STANDARD_GRAVITY > RARE_RECORD_PGA:
        print(f"teflon-jax run: warning: {flag} {path} read in --record-units g peaks at {peak:.4g} g (at "
              f"{when:g} s), stronger than all but a few recorded motions; if its values are in m/s^2, "
              "give --record-units m/s^2.", file=sys.stderr)


def check_scaled(ax, ay, scale: float, scale_text) -> None:
    """`ValueError` naming --scale when the scaled components (ax, ay) [m/s^2] peak above
    `MAX_RECORD_PGA`."""
    peak = max(float(np.max(np.abs(ax), initial=0.0)), float(np.max(np.abs(ay), initial=0.0)))
    if scale != 1 and peak > MAX_RECORD_PGA:
        raise ValueError(f"--scale {scale_text}: the scaled records peak at {peak / STANDARD_GRAVITY:.3g} g, "
                         f"beyond any recorded ground motion (at most {MAX_RECORD_PGA / STANDARD_GRAVITY:g} g); "
                         "give a smaller scale.")


def check_record_step(time_step: float, time_text, dt: float, records) -> None:
    """`check_time_step` of --time-step against the records' step `dt` [s], naming them."""
    if time_step > 0:
        names = " and ".join(f"{flag} {path}" for flag, path in records) or "the suite's records"
        check_time_step(time_step, time_text, dt, f"{dt:g}s of {names}")
