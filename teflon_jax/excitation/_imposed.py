"""Imposed displacement histories of bearing tests, and time signals (normal load).

Each motion gives the displacement (ux, uy) [m] and velocity [m/s] at time t [s]; all are
pure and jittable, so a batch of tests can share or vmap over them. A motion along x is an
`AbstractUniaxialMotion` (sine, triangle, `TabulatedMotion`), one in the plane an
`AbstractBiaxialMotion` (figure eight, `TabulatedBiaxialMotion`): the bearing test reads the
type to drive Bouc-Wen's Z (Eq. 3) or Park's (Eqs. 8-9).
References: the test protocols of Mokha, Constantinou & Reinhorn (1990, Part I) and the
figure-eight motion of Eq. 16 of Constantinou, Mokha & Reinhorn (1990).
"""

import abc

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import ArrayLike

from ..validation import require_positive


class AbstractMotion(eqx.Module):
    """Imposed displacement u(t) = (ux, uy) [m] and its velocity [m/s].

    A motion is one of two kinds, told apart by its type: `AbstractUniaxialMotion` (along x,
    uy = 0 throughout) or `AbstractBiaxialMotion` (a path in the plane).
    """

    @abc.abstractmethod
    def displacement(self, t) -> jnp.ndarray:
        """(ux, uy) [m] at time t [s]."""

    @abc.abstractmethod
    def velocity(self, t) -> jnp.ndarray:
        """(vx, vy) [m/s] at time t [s]."""

    @property
    @abc.abstractmethod
    def duration(self) -> float:
        """Natural end time [s] of the protocol."""

    def check(self) -> None:
        """Raise `ValueError` naming the parameter for a non-physical (concrete) protocol."""
        for name in ("amplitude", "frequency", "angular_frequency", "cycles"):
            if hasattr(self, name):
                unit = {"amplitude": " [m]", "frequency": " [Hz]", "angular_frequency": " [rad/s]"}
                require_positive(getattr(self, name), name, unit.get(name, ""))

    def reversal_times(self) -> tuple[float, ...]:
        """Times [s] where the x velocity changes sign (steps are aligned to them)."""
        return ()


class AbstractUniaxialMotion(AbstractMotion):
    """A motion along x only: uy = vy = 0 at every time (Bouc-Wen's Z, Eq. 3)."""


class AbstractBiaxialMotion(AbstractMotion):
    """A motion in the plane (ux, uy): Park et al.'s Z (Eqs. 8-9)."""


class SineMotion(AbstractUniaxialMotion):
    """ux(t) = amplitude sin(2 pi frequency t): the paper's tests No. 62, 75 and 191."""

    amplitude: ArrayLike  # [m]
    frequency: ArrayLike  # [Hz]
    cycles: float = eqx.field(static=True, default=3.0)

    def displacement(self, t):
        w = 2 * jnp.pi * self.frequency
        return jnp.stack([self.amplitude * jnp.sin(w * t), jnp.zeros_like(t * w)])

    def velocity(self, t):
        w = 2 * jnp.pi * self.frequency
        return jnp.stack([self.amplitude * w * jnp.cos(w * t), jnp.zeros_like(t * w)])

    @property
    def duration(self):
        return float(self.cycles) / float(self.frequency)


class TriangleMotion(AbstractUniaxialMotion):
    """Constant-velocity test: triangular displacement of `amplitude` [m] at `frequency` [Hz].

    Starts at 0 moving in +x with speed 4 amplitude frequency.
    """

    amplitude: ArrayLike
    frequency: ArrayLike
    cycles: float = eqx.field(static=True, default=3.0)

    def _phase(self, t):
        return jnp.mod(t * self.frequency + 0.25, 1.0)  # 0.25 makes u(0) = 0 rising

    def displacement(self, t):
        p = self._phase(t)
        ux = self.amplitude * jnp.where(p < 0.5, 4 * p - 1, 3 - 4 * p)
        return jnp.stack([ux, jnp.zeros_like(ux)])

    def velocity(self, t):
        p = self._phase(t)
        vx = 4 * self.amplitude * self.frequency * jnp.where(p < 0.5, 1.0, -1.0)
        return jnp.stack([vx, jnp.zeros_like(vx)])

    @property
    def duration(self):
        return float(self.cycles) / float(self.frequency)

    def reversal_times(self):
        f = float(self.frequency)
        n = int(2 * float(self.cycles)) + 1
        return tuple((0.25 + 0.5 * k) / f for k in range(n))


class FigureEightMotion(AbstractBiaxialMotion):
    """Eq. 16: ux = U0 sin(w t), uy = U0 sin(2 w t); `angular_frequency` w in [rad/s]."""

    amplitude: ArrayLike
    angular_frequency: ArrayLike
    cycles: float = eqx.field(static=True, default=2.0)

    def displacement(self, t):
        w = self.angular_frequency
        return self.amplitude * jnp.stack([jnp.sin(w * t), jnp.sin(2 * w * t)])

    def velocity(self, t):
        w = self.angular_frequency
        return self.amplitude * w * jnp.stack([jnp.cos(w * t), 2 * jnp.cos(2 * w * t)])

    @property
    def duration(self):
        return float(self.cycles) * 2 * float(jnp.pi) / float(self.angular_frequency)


def _segment(times, t):
    """Index i of the sample interval [t_i, t_(i+1)] holding t, and its length [s]."""
    i = jnp.clip(jnp.searchsorted(times, t, side="right") - 1, 0, times.shape[0] - 2)
    return i, times[i + 1] - times[i]


class TabulatedMotion(AbstractUniaxialMotion):
    """Any measured or prescribed displacement history along x, linear between samples.

    Velocity is the slope of the current segment (piecewise constant); for smooth protocols
    sampled finely this is the sampled velocity to first order in the sample spacing.
    """

    times: jnp.ndarray  # [s], strictly increasing
    ux: jnp.ndarray  # [m]

    def displacement(self, t):
        ux = jnp.interp(t, self.times, self.ux)
        return jnp.stack([ux, jnp.zeros_like(ux)])

    def velocity(self, t):
        i, h = _segment(self.times, t)
        vx = (self.ux[i + 1] - self.ux[i]) / h
        return jnp.stack([vx, jnp.zeros_like(vx)])

    @property
    def duration(self):
        return float(self.times[-1])


class TabulatedBiaxialMotion(AbstractBiaxialMotion):
    """A measured or prescribed path in the plane (ux, uy), linear between samples; velocity as
    `TabulatedMotion`'s, per component."""

    times: jnp.ndarray  # [s], strictly increasing
    ux: jnp.ndarray  # [m]
    uy: jnp.ndarray  # [m]

    def displacement(self, t):
        return jnp.stack([jnp.interp(t, self.times, self.ux), jnp.interp(t, self.times, self.uy)])

    def velocity(self, t):
        i, h = _segment(self.times, t)
        return jnp.stack([(self.ux[i + 1] - self.ux[i]) / h, (self.uy[i + 1] - self.uy[i]) / h])

    @property
    def duration(self):
        return float(self.times[-1])


def tabulated_motion(times, ux, uy=None) -> TabulatedMotion | TabulatedBiaxialMotion:
    """A `TabulatedMotion` (`uy` not given) or `TabulatedBiaxialMotion` from sample arrays,
    checked (finite, time strictly increasing)."""
    times = jnp.asarray(times, dtype=float)
    ux = jnp.asarray(ux, dtype=float)
    given = {"times": times, "ux": ux} | ({} if uy is None else {"uy": jnp.asarray(uy, dtype=float)})
    if (times.ndim != 1 or times.shape[0] < 2
            or any(arr.shape != times.shape for arr in given.values())):
        raise ValueError("times, ux (and uy): must be 1-D arrays of the same length >= 2.")
    for name, arr in given.items():
        if not bool(jnp.all(jnp.isfinite(arr))):
            raise ValueError(f"{name}: contains NaN or inf at index {int(jnp.argmin(jnp.isfinite(arr)))}.")
    if not bool(jnp.all(jnp.diff(times) > 0)):
        bad = int(jnp.argmin(jnp.diff(times) > 0)) + 1
        raise ValueError(f"times: must be strictly increasing; sample {bad} is not after sample {bad - 1}.")
    return TabulatedMotion(**given) if uy is None else TabulatedBiaxialMotion(**given)
