"""Fourier amplitude and linear elastic response spectra of ground motions.

Input processing in NumPy (eager, float64), used to characterise the records the simulator
is driven with, not inside simulations.
"""

import dataclasses
import math

import numpy as np

from ._ground_motion import GroundMotion


def fourier_amplitude(
    signal, time_step: float | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """One-sided Fourier amplitude spectrum of a uniformly sampled signal.

    `A(f_k) = dt |sum_n x_n exp(-2 pi i k n / N)|`, the discrete approximation of the
    continuous transform `|X(f)| = |integral x(t) exp(-2 pi i f t) dt|`, at the frequencies
    `f_k = k / (N dt)`, k = 0 ... N // 2. It is not doubled for negative frequencies and not
    smoothed. For an acceleration in [m/s^2] the amplitude is in [m/s]; a sine of amplitude
    `X` lasting `D` seconds (a whole number of periods) gives a peak `X D / 2`.

    **Arguments:**

    - `signal`: 1-D array of samples (or a `GroundMotion`, whose acceleration and time step are
      used when `time_step` is `None`).
    - `time_step`: sampling interval [s].

    **Returns:** `(frequency [Hz], amplitude [signal unit x s])`, both of length N // 2 + 1.
    """
    if isinstance(signal, GroundMotion):
        if time_step is None:
            time_step = signal.time_step
        signal = signal.acceleration
    values = np.asarray(signal, dtype=np.float64)
    if values.ndim != 1 or values.size < 2:
        raise ValueError(
            "fourier_amplitude: signal must be a 1-D array of at least 2 samples, "
            f"got shape {values.shape}."
        )
    if not np.all(np.isfinite(values)):
        raise ValueError(
            "fourier_amplitude: signal sample "
            f"{int(np.flatnonzero(~np.isfinite(values))[0])} is not finite."
        )
    if time_step is None or not (math.isfinite(time_step) and time_step > 0.0):
        raise ValueError(
            "fourier_amplitude: time_step must be a positive number of seconds, "
            f"got {time_step!r}."
        )
    frequency = np.fft.rfftfreq(values.size, d=time_step)
    amplitude = time_step * np.abs(np.fft.rfft(values))
    return frequency, amplitude


@dataclasses.dataclass(frozen=True, eq=False)
class ResponseSpectrum:
    """Peak responses of damped linear oscillators to a ground motion.

    - `periods`: natural periods T [s].
    - `damping`: damping ratio zeta (fraction of critical).
    - `displacement`: spectral displacement SD = max_t |u(t)| [m], u relative to the ground.
    - `pseudo_acceleration`: PSA = (2 pi / T)^2 SD [m/s^2].
    """

    periods: np.ndarray
    damping: float
    displacement: np.ndarray
    pseudo_acceleration: np.ndarray

    @property
    def pseudo_velocity(self) -> np.ndarray:
        """PSV = (2 pi / T) SD [m/s] (zero at T = 0)."""
        omega = np.divide(
            2.0 * np.pi,
            self.periods,
            out=np.zeros_like(self.periods),
            where=self.periods > 0,
        )
        return omega * self.displacement


def response_spectrum(
    motion: GroundMotion, periods, *, damping: float = 0.05
) -> ResponseSpectrum:
    """Elastic displacement and pseudo-acceleration spectra, computed exactly.

    Each oscillator obeys `u'' + 2 zeta omega u' + omega^2 u = -a_g(t)` from rest, with
    `omega = 2 pi / T` and `u` the displacement relative to the ground. Reading the record as
    piecewise linear between samples, the step from `t_i` to `t_i + dt` has a closed-form
    solution, so the recurrence

        [u, u']_{i+1} = M [u, u']_i + N [a_g,i, a_g,i+1]

    is exact at every step size (Nigam & Jennings 1969, "Calculation of response spectra from
    strong-motion earthquake records", BSSA 59(2); coefficients as in Chopra, "Dynamics of
    Structures", Sec. 5.2). The peak is taken over the samples of the record. The loop runs
    over time steps, vectorised over the periods.

    `T = 0` is allowed and means a rigid oscillator: SD = 0 and PSA = PGA.

    **Arguments:**

    - `motion`: the ground motion.
    - `periods`: natural periods [s], >= 0 (scalar or 1-D).
    - `damping`: damping ratio zeta, 0 <= zeta < 1.

    **Returns:** a `ResponseSpectrum` with `displacement` SD [m] and `pseudo_acceleration`
    PSA = omega^2 SD [m/s^2], one value per period.
    """
    periods = np.atleast_1d(np.asarray(periods, dtype=np.float64))
    if periods.ndim != 1 or periods.size == 0:
        raise ValueError(
            "response_spectrum: periods must be a non-empty 1-D array, "
            f"got shape {periods.shape}."
        )
    if not np.all(np.isfinite(periods) & (periods >= 0.0)):
        raise ValueError("response_spectrum: periods must be finite and >= 0 [s].")
    damping = float(damping)
    if not (0.0 <= damping < 1.0):
        raise ValueError(
            f"response_spectrum: damping ratio must satisfy 0 <= damping < 1, got {damping}."
        )
    rigid = periods == 0.0
    omega = 2.0 * np.pi / np.where(rigid, 1.0, periods)
    peak = np.max(np.abs(_displacements(np.asarray(motion.acceleration), motion.time_step, omega, damping)), axis=0)
    displacement = np.where(rigid, 0.0, peak)
    pseudo_acceleration = np.where(rigid, motion.pga, omega**2 * peak)
    return ResponseSpectrum(
        periods=periods,
        damping=damping,
        displacement=displacement,
        pseudo_acceleration=pseudo_acceleration,
    )


def _displacements(acceleration: np.ndarray, dt: float, omega: np.ndarray, damping: float) -> np.ndarray:
    """u (nt, P) [m] of the oscillators `omega` from rest by the exact recurrence."""
    a, b, c, d, a1, b1, c1, d1 = _nigam_jennings(omega, damping, dt)
    force = -acceleration
    u = np.zeros((force.size, omega.size))
    v = np.zeros_like(omega)
    for i in range(force.size - 1):
        p0, p1 = force[i], force[i + 1]
        u[i + 1], v = a * u[i] + b * v + c * p0 + d * p1, a1 * u[i] + b1 * v + c1 * p0 + d1 * p1
    return u


def oscillator_displacement(acceleration, time_step: float, periods, *, damping: float = 0.05) -> np.ndarray:
    """Displacement histories u(t) [m], relative to the ground, of damped linear oscillators
    of `periods` T > 0 [s] from rest under the ground acceleration `acceleration` (nt,)
    [m/s^2] sampled every `time_step` [s]: u'' + 2 zeta omega u' + omega^2 u = -a_g, by the
    exact piecewise-linear recurrence of `response_spectrum` (Nigam & Jennings 1969).

    **Returns:** u (nt, P), row i at t = i `time_step`; `response_spectrum`'s SD is max_t |u|.
    Oscillators under two components x and y at once move as (u_x(t), u_y(t)), whose largest
    length over t is the RotD100 spectral displacement (Boore 2010, BSSA 100(4)).
    """
    values = np.asarray(acceleration, dtype=np.float64)
    periods = np.atleast_1d(np.asarray(periods, dtype=np.float64))
    if values.ndim != 1 or values.size < 2 or not np.all(np.isfinite(values)):
        raise ValueError(f"acceleration: expected a finite 1-D record of 2 or more samples, got shape {values.shape}.")
    if not (math.isfinite(time_step) and time_step > 0):
        raise ValueError(f"time_step: must be > 0 s, got {time_step!r}.")
    if periods.ndim != 1 or not np.all(np.isfinite(periods) & (periods > 0)):
        raise ValueError(f"periods: must be finite and > 0 s, got {periods.tolist()}.")
    if not 0.0 <= damping < 1.0:
        raise ValueError(f"damping: must satisfy 0 <= damping < 1, got {damping}.")
    return _displacements(values, float(time_step), 2.0 * np.pi / periods, float(damping))


_SERIES_BELOW = 0.1  # omega * dt under which the coefficients come from a power series


_SERIES_TERMS = 20


def _nigam_jennings(omega: np.ndarray, zeta: float, dt: float):
    """Coefficients of the exact step for unit mass, `k = omega^2`, piecewise-linear force.

    u_{i+1}  = A u_i + B v_i + C p_i + D p_{i+1}
    v_{i+1}  = A' u_i + B' v_i + C' p_i + D' p_{i+1}

    For `omega dt >= 0.1` the closed forms of Chopra, Dynamics of Structures, Table 5.2.1. Below
    that, those closed forms lose digits to cancellation (C and D are O(dt^2) differences of
    O(1 / (omega^3 dt)) terms), so the same coefficients are taken from the power series of the
    exponential of the augmented system matrix (state u, v, p, dp/dt), which is exact to
    round-off there.
    """
    closed = _closed_form(omega, zeta, dt)
    small = omega * dt < _SERIES_BELOW
    if not np.any(small):
        return closed
    series = _series(omega, zeta, dt)
    return tuple(np.where(small, s, c) for s, c in zip(series, closed))


def _series(omega: np.ndarray, zeta: float, dt: float):
    count = omega.size
    system = np.zeros((count, 4, 4))
    system[:, 0, 1] = dt
    system[:, 1, 0] = -(omega**2) * dt
    system[:, 1, 1] = -2.0 * zeta * omega * dt
    system[:, 1, 2] = dt
    system[:, 2, 3] = dt
    identity = np.broadcast_to(np.eye(4), system.shape)
    exponential = identity.copy()
    for k in range(_SERIES_TERMS, 0, -1):  # Horner: I + M (I + M/2 (I + M/3 (...)))
        exponential = identity + system @ exponential / k
    e = exponential
    return (
        e[:, 0, 0],
        e[:, 0, 1],
        e[:, 0, 2] - e[:, 0, 3] / dt,
        e[:, 0, 3] / dt,
        e[:, 1, 0],
        e[:, 1, 1],
        e[:, 1, 2] - e[:, 1, 3] / dt,
        e[:, 1, 3] / dt,
    )


def _closed_form(omega: np.ndarray, zeta: float, dt: float):
    k = omega**2
    root = math.sqrt(1.0 - zeta**2)
    omega_d = omega * root
    decay = np.exp(-zeta * omega * dt)
    sin = np.sin(omega_d * dt)
    cos = np.cos(omega_d * dt)
    a = decay * (zeta / root * sin + cos)
    b = decay * sin / omega_d
    c = (
        2.0 * zeta / (omega * dt)
        + decay
        * (
            ((1.0 - 2.0 * zeta**2) / (omega_d * dt) - zeta / root) * sin
            - (1.0 + 2.0 * zeta / (omega * dt)) * cos
        )
    ) / k
    d = (
        1.0
        - 2.0 * zeta / (omega * dt)
        + decay
        * ((2.0 * zeta**2 - 1.0) / (omega_d * dt) * sin + 2.0 * zeta / (omega * dt) * cos)
    ) / k
    a1 = -decay * omega / root * sin
    b1 = decay * (cos - zeta / root * sin)
    c1 = (-1.0 / dt + decay * ((omega / root + zeta / (dt * root)) * sin + cos / dt)) / k
    d1 = (1.0 - decay * (zeta / root * sin + cos)) / (k * dt)
    return a, b, c, d, a1, b1, c1, d1
