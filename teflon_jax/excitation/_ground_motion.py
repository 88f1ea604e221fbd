"""Ground-motion records: a small container and the peak intensity measures.

This module is input processing, not simulation code: it uses NumPy and runs eagerly.
A `GroundMotion` holds a uniformly sampled horizontal ground acceleration in SI units
([m/s^2], [s]); the readers for the usual text formats live in `_ground_motion_io.py` and
the Fourier and response spectra in `_spectra.py`.
"""

import dataclasses
import math

import numpy as np

_TIME_TOLERANCE = 1.0e-6  # fraction of a time step within which a time is "on" a sample


@dataclasses.dataclass(frozen=True, eq=False, repr=False)
class GroundMotion:
    """A uniformly sampled ground-acceleration record.

    Sample `i` is the acceleration at time `start_time + i * time_step`. Between samples the
    record is understood as piecewise linear (the usual assumption of strong-motion
    processing, and the one made by `response_spectrum`).

    **Arguments:**

    - `time_step`: sampling interval [s], positive.
    - `acceleration`: ground acceleration [m/s^2], a 1-D array of finite values. It is stored
      as a read-only float64 copy.
    - `name`: a short label used in messages and plots (e.g. `"El Centro 1940 N-S"`).
    - `source`: where the record came from (a file path or a description).
    - `start_time`: time of the first sample [s] (0 for most records; 0.02 s for the SCT
      file, whose first row is at t = 0.02 s; the start of the window for a windowed record).
    """

    time_step: float
    acceleration: np.ndarray
    name: str = "ground motion"
    source: str = ""
    start_time: float = 0.0

    def __post_init__(self):
        where = f"GroundMotion '{self.name}'"
        time_step = float(self.time_step)
        if not (math.isfinite(time_step) and time_step > 0.0):
            raise ValueError(
                f"{where}: time_step must be a positive number of seconds, "
                f"got {self.time_step!r}."
            )
        start_time = float(self.start_time)
        if not math.isfinite(start_time):
            raise ValueError(
                f"{where}: start_time must be finite, got {self.start_time!r}."
            )
        acceleration = np.array(self.acceleration, dtype=np.float64)
        if acceleration.ndim != 1:
            raise ValueError(
                f"{where}: acceleration must be a 1-D array of samples, "
                f"got shape {acceleration.shape}."
            )
        if acceleration.size < 2:
            raise ValueError(
                f"{where}: a record needs at least 2 samples, got {acceleration.size}."
            )
        bad = np.flatnonzero(~np.isfinite(acceleration))
        if bad.size:
            raise ValueError(
                f"{where}: acceleration sample {bad[0]} "
                f"(t = {start_time + bad[0] * time_step:g} s) "
                f"is {acceleration[bad[0]]}; {bad.size} sample(s) are not finite."
            )
        acceleration.setflags(write=False)
        object.__setattr__(self, "time_step", time_step)
        object.__setattr__(self, "start_time", start_time)
        object.__setattr__(self, "acceleration", acceleration)
        object.__setattr__(self, "name", str(self.name))
        object.__setattr__(self, "source", str(self.source))

    def __repr__(self) -> str:
        return (
            f"GroundMotion(name={self.name!r}, npts={self.acceleration.size}, "
            f"time_step={self.time_step:g}, start_time={self.start_time:g}, "
            f"duration={self.duration:g}, pga={self.pga:.4g} m/s^2, source={self.source!r})"
        )

    @property
    def time(self) -> np.ndarray:
        """Sample times [s]: `start_time + time_step * arange(npts)`."""
        return self.start_time + self.time_step * np.arange(self.acceleration.size)

    @property
    def end_time(self) -> float:
        """Time of the last sample [s]."""
        return self.start_time + self.time_step * (self.acceleration.size - 1)

    @property
    def duration(self) -> float:
        """Time from the first to the last sample [s], `(npts - 1) * time_step`."""
        return self.time_step * (self.acceleration.size - 1)

    @property
    def pga(self) -> float:
        """Peak ground acceleration, max |acceleration| [m/s^2]."""
        return float(np.max(np.abs(self.acceleration)))

    def window(self, t_start: float, t_end: float) -> "GroundMotion":
        """The samples with `t_start <= t <= t_end` (times in the record's own clock [s]).

        The new record keeps absolute times: its `start_time` is the time of its first sample
        (use `dataclasses.replace(motion, start_time=0.0)` to restart the clock). A time within
        1e-6 of a step of a sample counts as that sample.

        **Raises:** `ValueError` naming the record and its time range when the window is empty,
        reversed, or reaches outside the record.
        """
        t0, t1 = self.start_time, self.end_time
        tol = _TIME_TOLERANCE * self.time_step
        if not (math.isfinite(t_start) and math.isfinite(t_end)) or t_end <= t_start:
            raise ValueError(
                f"window [{t_start}, {t_end}] s of record '{self.name}' ({self.source}): "
                "t_end must be greater than t_start."
            )
        if t_start < t0 - tol or t_end > t1 + tol:
            raise ValueError(
                f"window [{t_start:g}, {t_end:g}] s reaches outside record '{self.name}' "
                f"({self.source}), which runs from {t0:g} s to {t1:g} s; "
                "choose times inside that range."
            )
        first = math.ceil((t_start - t0) / self.time_step - _TIME_TOLERANCE)
        last = math.floor((t_end - t0) / self.time_step + _TIME_TOLERANCE)
        if last - first < 1:
            raise ValueError(
                f"window [{t_start:g}, {t_end:g}] s of record '{self.name}' "
                f"({self.source}) holds "
                f"fewer than 2 samples at time_step {self.time_step:g} s."
            )
        return dataclasses.replace(
            self,
            acceleration=self.acceleration[first : last + 1],
            start_time=t0 + first * self.time_step,
            name=f"{self.name} [{t_start:g}-{t_end:g} s]",
        )

    def scaled(self, factor: float) -> "GroundMotion":
        """The record with every acceleration multiplied by `factor` (dimensionless, finite)."""
        factor = float(factor)
        if not math.isfinite(factor):
            raise ValueError(
                f"scaled: factor for record '{self.name}' must be finite, got {factor}."
            )
        return dataclasses.replace(
            self, acceleration=factor * self.acceleration, name=f"{self.name} x {factor:g}"
        )

    def resampled(self, time_step: float) -> "GroundMotion":
        """The record at a new sampling interval `time_step` [s], by linear interpolation.

        The new samples are at `start_time + k * time_step` for every such time up to the last
        sample of the record. Linear interpolation is exact for the piecewise-linear reading of
        the record, so refining the step changes nothing physical. Coarsening it does no
        anti-alias filtering: content above the new Nyquist frequency `1 / (2 time_step)` is
        folded, and peaks between the new samples are lost. Low-pass filter first if that matters.
        """
        time_step = float(time_step)
        if not (math.isfinite(time_step) and time_step > 0.0):
            raise ValueError(
                f"resampled: time_step for record '{self.name}' must be a positive number of "
                f"seconds, got {time_step!r}."
            )
        count = math.floor(self.duration / time_step + _TIME_TOLERANCE) + 1
        if count < 2:
            raise ValueError(
                f"resampled: time_step {time_step:g} s is longer than record '{self.name}' "
                f"({self.duration:g} s)."
            )
        new_time = self.start_time + time_step * np.arange(count)
        new_time[-1] = min(new_time[-1], self.end_time)
        acceleration = np.interp(new_time, self.time, self.acceleration)
        return dataclasses.replace(self, time_step=time_step, acceleration=acceleration)


@dataclasses.dataclass(frozen=True)
class IntensityMeasures:
    """Peak values of a ground motion.

    - `pga`: peak ground acceleration [m/s^2] (of the record as given, never corrected).
    - `pgv`: peak ground velocity [m/s] after the baseline treatment `baseline`.
    - `pgd`: peak ground displacement [m] after the baseline treatment `baseline`.
    - `baseline`: the treatment used (see `integrate_motion`).
    """

    pga: float
    pgv: float
    pgd: float
    baseline: str


_BASELINES = ("linear_velocity", "none", "highpass")


_HIGHPASS_CORNER = 0.1  # [Hz]


_HIGHPASS_ORDER = 4


_HIGHPASS_PADDING = 20.0  # [s] of zeros on each side


def integrate_motion(
    motion: GroundMotion, *, baseline: str = "linear_velocity"
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Ground velocity and displacement of a record, with a stated baseline treatment.

    Integration is by the trapezoidal rule from rest, `v[0] = 0`, `d[0] = 0` (exact for the
    piecewise-linear reading of the record in velocity; second-order in displacement).

    Baseline treatments (`baseline`):

    - `"linear_velocity"` (default): integrate to velocity, subtract the least-squares straight
      line `c0 + c1 t` from the velocity, integrate the corrected velocity to displacement. This
      removes a constant acceleration offset (`c1`) and an unknown initial velocity (`c0`), the
      usual cause of drift in uncorrected records (e.g. the Caltech Vol. II El Centro).
      The returned acceleration is `acceleration - c1`.
    - `"none"`: plain double integration of the record as given.
    - `"highpass"`: pad 20 s of zeros on both sides, apply a 4th-order Butterworth high-pass
      at 0.1 Hz forwards and backwards (zero phase, `scipy.signal.sosfiltfilt`), integrate the
      filtered acceleration and cut the padding off again. Needs SciPy.

    **Arguments:**

    - `motion`: the record.
    - `baseline`: one of `"linear_velocity"`, `"none"`, `"highpass"`.

    **Returns:** `(acceleration [m/s^2], velocity [m/s], displacement [m])`, arrays on
    `motion.time`, the acceleration being the corrected one the other two integrate.
    """
    if baseline not in _BASELINES:
        raise ValueError(
            f"baseline '{baseline}' for record '{motion.name}' is not known; use one of "
            f"{', '.join(repr(b) for b in _BASELINES)}."
        )
    dt = motion.time_step
    acceleration = np.asarray(motion.acceleration)
    if baseline == "highpass":
        try:
            from scipy import signal
        except ImportError as error:  # pragma: no cover - depends on the environment
            raise ImportError(
                "baseline='highpass' needs SciPy (pip install scipy); "
                "baseline='linear_velocity' works without it."
            ) from error
        nyquist = 0.5 / dt
        if _HIGHPASS_CORNER >= nyquist:
            raise ValueError(
                f"record '{motion.name}': time_step {dt:g} s is too coarse for a "
                f"{_HIGHPASS_CORNER} Hz high-pass filter."
            )
        pad = round(_HIGHPASS_PADDING / dt)
        padded = np.concatenate([np.zeros(pad), acceleration, np.zeros(pad)])
        sos = signal.butter(
            _HIGHPASS_ORDER, _HIGHPASS_CORNER, btype="highpass", fs=1.0 / dt, output="sos"
        )
        filtered = signal.sosfiltfilt(sos, padded)
        velocity = _cumulative_trapezoid(filtered, dt)
        displacement = _cumulative_trapezoid(velocity, dt)
        keep = slice(pad, pad + acceleration.size)
        return filtered[keep], velocity[keep], displacement[keep]
    velocity = _cumulative_trapezoid(acceleration, dt)
    if baseline == "linear_velocity":
        time = dt * np.arange(acceleration.size)
        slope, intercept = np.polyfit(time, velocity, 1)
        velocity = velocity - (intercept + slope * time)
        acceleration = acceleration - slope
    displacement = _cumulative_trapezoid(velocity, dt)
    return acceleration, velocity, displacement


def intensity_measures(
    motion: GroundMotion, *, baseline: str = "linear_velocity"
) -> IntensityMeasures:
    """Peak ground acceleration, velocity and displacement of a record.

    PGA is `max |a|` of the record as given. PGV and PGD are `max |v|` and `max |d|` of the
    velocity and displacement from `integrate_motion(motion, baseline=baseline)`; the
    default `"linear_velocity"` removes the least-squares line from the integrated velocity.

    **Arguments:**

    - `motion`: the record.
    - `baseline`: `"linear_velocity"` (default), `"none"` or `"highpass"` (needs SciPy).

    **Returns:** an `IntensityMeasures` with `pga` [m/s^2], `pgv` [m/s], `pgd` [m].
    """
    _, velocity, displacement = integrate_motion(motion, baseline=baseline)
    return IntensityMeasures(
        pga=motion.pga,
        pgv=float(np.max(np.abs(velocity))),
        pgd=float(np.max(np.abs(displacement))),
        baseline=baseline,
    )


def _cumulative_trapezoid(values: np.ndarray, dt: float) -> np.ndarray:
    out = np.empty_like(values)
    out[0] = 0.0
    np.cumsum(0.5 * dt * (values[1:] + values[:-1]), out=out[1:])
    return out
