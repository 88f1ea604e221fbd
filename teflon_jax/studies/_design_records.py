"""The motions of a design: one record set for one or two horizontal ground components."""

import jax.numpy as jnp

from ..excitation import uniform_signal


def records_array(records, time_step, components: int = 1):
    """`records` as an array (N, nt) for one horizontal component, (N, 2, nt) for two (x, y),
    or a `ValueError` naming the shape and what it should be."""
    array = jnp.asarray(records, dtype=float)
    wanted = "(N >= 1, nt)" if components == 1 else "(N >= 1, 2, nt): x and y"
    if array.ndim != components + 1 or array.shape[0] < 1 or (components == 2 and array.shape[1] != 2):
        raise ValueError(f"records: need an {wanted} array of ground accelerations [m/s^2] for a structure of "
                         f"{components} horizontal component(s), got shape {array.shape}.")
    if not time_step > 0:
        raise ValueError(f"record_time_step: must be > 0 s, got {time_step}.")
    return array


def components_of(structure) -> int:
    """The horizontal ground components `structure` takes (`IsolatedStructure.components`; 1
    for a factory without it)."""
    return getattr(structure, "components", 1)


def record_ground(values, time_step: float):
    """The ground motion a structure takes from one record's samples: a `Signal` of `values`
    (nt,), or the (x, y) pair of `values` (2, nt) [m/s^2] sampled every `time_step` [s]."""
    if values.ndim == 1:
        return uniform_signal(values, time_step)
    return uniform_signal(values[0], time_step), uniform_signal(values[1], time_step)


def record_duration(records, time_step: float) -> float:
    """The length [s] of `records` (..., nt) sampled every `time_step` [s]."""
    return (records.shape[-1] - 1) * time_step
