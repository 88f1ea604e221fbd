"""Scalar time signals (ground acceleration, normal load), linear between samples."""

import equinox as eqx
import jax.numpy as jnp


class Signal(eqx.Module):
    """A scalar time history (ground acceleration [m/s^2], normal load [N], ...), linear
    between samples and held constant outside them.

    With `uniform=True` (equally spaced `times`, as for every ground-motion record) the
    interval is found by division, O(1) per call, instead of a binary search; this matters
    inside the time-stepping loop and under `vmap` over records.
    """

    times: jnp.ndarray
    values: jnp.ndarray
    uniform: bool = eqx.field(static=True, default=False)

    def __call__(self, t):
        if not self.uniform:
            return jnp.interp(t, self.times, self.values)
        start, step = self.times[0], self.times[1] - self.times[0]
        position = (jnp.asarray(t) - start) / step
        last = self.values.shape[-1] - 1
        index = jnp.clip(jnp.floor(position), 0, last - 1).astype(jnp.int32)
        weight = jnp.clip(position - index, 0.0, 1.0)
        return self.values[index] * (1 - weight) + self.values[index + 1] * weight


def uniform_signal(values, time_step: float, start: float = 0.0) -> Signal:
    """A `Signal` sampled every `time_step` [s] from `start` [s]."""
    values = jnp.asarray(values, dtype=float)
    if not time_step > 0:
        raise ValueError(f"time_step: must be > 0 s, got {time_step}.")
    times = start + time_step * jnp.arange(values.shape[-1])
    return Signal(times=times, values=values, uniform=True)


def as_signal(value) -> Signal:
    """A constant (scalar) or an existing `Signal` as a `Signal`."""
    if isinstance(value, Signal):
        return value
    value = jnp.asarray(value, dtype=float)
    return Signal(times=jnp.array([0.0, 1.0]), values=jnp.stack([value, value]), uniform=True)
