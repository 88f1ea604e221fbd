"""Scalar time signals (ground acceleration, normal load), linear between samples and zero
outside them."""

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from ..validation import concrete


class Signal(eqx.Module):
    """A scalar time history (ground acceleration [m/s^2], normal load [N], ...), linear
    between samples and zero before the first and after the last sample.

    Zero outside the record is what a ground-motion record means (the ground is at rest
    before and after it); nothing is held or extrapolated. Simulations that would run past
    the end refuse to (see `require_covers`) unless the caller appends zeros on purpose.
    A time within a millionth of a sample interval (plus round-off) of either end counts as
    inside, so a simulation that stops at the last sample sees its value.

    With `uniform=True` (equally spaced `times`, as for every ground-motion record) the
    interval is found by division, O(1) per call, instead of a binary search; this matters
    inside the time-stepping loop and under `vmap` over records.
    """

    times: jnp.ndarray
    values: jnp.ndarray
    uniform: bool = eqx.field(static=True, default=False)

    def __call__(self, t):
        t = jnp.asarray(t)
        last = self.values.shape[-1] - 1
        eps = jnp.finfo(jnp.result_type(t, self.times, float)).eps
        if self.uniform:
            start, step = self.times[0], self.times[1] - self.times[0]
            position = (t - start) / step
            slack = 1e-6 + 64 * eps * last
            index = jnp.clip(jnp.floor(position), 0, last - 1).astype(jnp.int32)
            weight = jnp.clip(position - index, 0.0, 1.0)
            value = self.values[index] * (1 - weight) + self.values[index + 1] * weight
            inside = (position >= -slack) & (position <= last + slack)
        else:
            value = jnp.interp(t, self.times, self.values)
            first, end = self.times[0], self.times[-1]
            slack_start = 1e-6 * (self.times[1] - first) + 64 * eps * jnp.abs(first)
            slack_end = 1e-6 * (end - self.times[-2]) + 64 * eps * jnp.abs(end)
            inside = (t >= first - slack_start) & (t <= end + slack_end)
        return jnp.where(inside, value, 0.0)

    def require_covers(self, duration: float, name: str = "duration") -> None:
        """Raise `ValueError` when concrete sample times end before `duration` [s] (the
        simulated span from t = 0); traced times are not checked (the signal is then zero
        past its end)."""
        times = concrete(self.times)
        if times is None:
            return
        ends = np.atleast_1d(times[..., -1])
        step = np.atleast_1d(times[..., -1] - times[..., -2])
        end = float(np.min(ends))
        if not np.all(float(duration) <= ends + 1e-6 * step + 64 * np.finfo(float).eps * np.abs(ends)):
            raise ValueError(
                f"{name}: {float(duration):.6g} s asked, but the record lasts only {end:.6g} s and "
                "is not extended past its last sample (no held value); ask for at most "
                f"{end:.6g} s, or append zeros to the record to follow the motion after it."
            )


def uniform_signal(values, time_step: float, start: float = 0.0) -> Signal:
    """A `Signal` sampled every `time_step` [s] from `start` [s]."""
    values = jnp.asarray(values, dtype=float)
    if not time_step > 0:
        raise ValueError(f"time_step: must be > 0 s, got {time_step}.")
    times = start + time_step * jnp.arange(values.shape[-1])
    return Signal(times=times, values=values, uniform=True)


def as_signal(value, *, duration: float | None = None) -> Signal:
    """An existing `Signal` as is, or a constant (scalar) as a `Signal` from 0 to duration [s]."""
    if isinstance(value, Signal):
        return value
    if duration is None or not float(duration) > 0:
        raise ValueError(
            f"duration: a constant becomes a Signal over [0, duration]; give duration > 0 s, got "
            f"{duration}."
        )
    value = jnp.asarray(value, dtype=float)
    return Signal(
        times=jnp.array([0.0, float(duration)]), values=jnp.stack([value, value]), uniform=True
    )
