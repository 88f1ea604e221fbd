"""Record sets: recorded ground motions padded to one length for batched runs."""

import dataclasses
from collections.abc import Sequence

import numpy as np

# --------------------------------------------------------------------------- motions


@dataclasses.dataclass(frozen=True)
class RecordSet:
    """Recorded ground motions on a common sampling grid, zero-padded to a common length.

    **Fields:** `acceleration` (N, nt) [m/s^2]; `time_step` [s]; `names` (N,) labels.
    """

    acceleration: np.ndarray
    time_step: float
    names: tuple[str, ...]

    def __post_init__(self):
        array = np.asarray(self.acceleration, dtype=float)
        if array.ndim != 2 or array.shape[0] < 1 or array.shape[1] < 2:
            raise ValueError(
                f"acceleration: a RecordSet needs an (N >= 1, nt >= 2) array, got shape {array.shape}."
            )
        if not np.all(np.isfinite(array)):
            raise ValueError("acceleration: a RecordSet contains NaN or infinite values.")
        if not self.time_step > 0:
            raise ValueError(f"time_step: must be > 0 s, got {self.time_step}.")
        if len(self.names) != array.shape[0]:
            raise ValueError(f"names: {len(self.names)} labels for {array.shape[0]} records.")
        object.__setattr__(self, "acceleration", array)

    @property
    def duration(self) -> float:
        return (self.acceleration.shape[1] - 1) * self.time_step


def record_set(motions: Sequence, *, duration: float | None = None, scale=1.0) -> RecordSet:
    """Stack `GroundMotion`s (`load_record`, `read_at2`, ...) into a `RecordSet`.

    All motions must share one time step (resample them first with `.resampled`); each is
    multiplied by `scale` (a number or one per motion) and padded with zero acceleration to
    `duration` [s] (default: the longest record). Clocks restart at 0 (windowed records).
    """
    if len(motions) == 0:
        raise ValueError("motions: no ground motions given.")
    steps = {float(m.time_step) for m in motions}
    if len(steps) != 1:
        raise ValueError(
            f"motions: time steps differ ({sorted(steps)} s); resample them to one step with "
            "GroundMotion.resampled first."
        )
    dt = steps.pop()
    scales = np.broadcast_to(np.asarray(scale, dtype=float), (len(motions),))
    longest = max(len(m.acceleration) for m in motions)
    nt = longest if duration is None else int(round(duration / dt)) + 1
    if nt < longest:
        raise ValueError(
            f"duration: {duration} s is shorter than the longest record "
            f"({(longest - 1) * dt} s); records are padded, never cut."
        )
    values = np.zeros((len(motions), nt))
    for i, (motion, factor) in enumerate(zip(motions, scales)):
        values[i, : len(motion.acceleration)] = factor * np.asarray(motion.acceleration)
    return RecordSet(values, dt, tuple(getattr(m, "name", f"record {i}") for i, m in enumerate(motions)))
