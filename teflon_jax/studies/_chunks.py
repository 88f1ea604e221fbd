"""The default number of motions (or records) per compiled call, from the device and its memory."""

import jax

from ._montecarlo import _motion_source, probe_structure
from ._montecarlo_parts import available_memory_bytes, bytes_per_motion

CPU_CHUNK = 512
"""Motions per call on a CPU: past a few hundred the rate (motions per second) no longer grows."""

LARGEST_CHUNK = 65536
"""The most motions per call on an accelerator."""


def default_chunk_size(platform: str, free_bytes: int | None, bytes_per_motion: int, *,
                       cpu: int = CPU_CHUNK) -> int:
    """Motions per compiled call: `cpu` on a CPU (`platform == "cpu"`); on an accelerator
    (GPU, TPU) the largest power of two up to `LARGEST_CHUNK` whose estimated memory,
    `bytes_per_motion * chunk`, fits in half of `free_bytes` (at least 1); `cpu` when the
    free memory is unknown (`None`).

    **Arguments:**

    - `platform`: `jax.Device.platform` ("cpu", "gpu", "cuda", "rocm", "tpu").
    - `free_bytes`: free memory of the devices that share a chunk [bytes], or None.
    - `bytes_per_motion`: estimated memory of one motion of a chunk [bytes]
      (`bytes_per_motion(...)` of the Monte Carlo).
    """
    if platform == "cpu" or free_bytes is None:
        return cpu
    if bytes_per_motion <= 0:
        raise ValueError(f"bytes_per_motion: must be positive, got {bytes_per_motion}.")
    fits = max(int(free_bytes) // 2 // int(bytes_per_motion), 1)
    return min(1 << (fits.bit_length() - 1), LARGEST_CHUNK)


def device_chunk_size(samples: int, n_dof: int, *, devices=None, cpu: int = CPU_CHUNK) -> int:
    """`default_chunk_size` on `devices` (default: all of JAX's) for items (motions, record
    pairs) of `samples` ground-acceleration samples (all components) through a structure of
    `n_dof` degrees of freedom: their platform, their free memory together (each holds its
    share of a chunk) and `bytes_per_motion` of one item."""
    devices = list(jax.devices() if devices is None else devices)
    platform = devices[0].platform
    if platform == "cpu":
        return cpu
    free = available_memory_bytes(devices[0])
    return default_chunk_size(platform, None if free is None else free * len(devices),
                              bytes_per_motion(samples, n_dof, 1), cpu=cpu)


def monte_carlo_chunk_size(structure, motions, *, devices=None, cpu: int = CPU_CHUNK) -> int:
    """`device_chunk_size` for `monte_carlo(structure, motions)` on `devices`."""
    devices = list(jax.devices() if devices is None else devices)
    if devices[0].platform == "cpu":
        return cpu
    source, _ = _motion_source(motions, 1, None)
    n_dof = probe_structure(structure, source, None).mass.shape[-1]
    rows = source.components + source.vertical  # a vertical component is one more record
    return device_chunk_size(rows * source.samples, n_dof, devices=devices, cpu=cpu)
