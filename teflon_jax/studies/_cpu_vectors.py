"""Wide vector code for batched runs on processors with AVX-512.

XLA compiles CPU code for 256-bit vectors unless told otherwise, also on processors that
execute 512-bit ones. A batch of motions is the same arithmetic on every member, so it fills
the wider vectors: the rigid-mass Monte Carlo needed 18 % less CPU per record and the building
15 % on an AMD EPYC with AVX-512 (benchmarks B3), with the same peaks to rounding. The option
has to be in XLA_FLAGS before JAX's first computation, as `jax_num_cpu_devices`; the
`teflon-jax` command and the benchmarks set it.
"""

import os
import pathlib

WIDE_VECTOR_FLAG = "--xla_cpu_prefer_vector_width=512"
"""The XLA option that asks for 512-bit vector code."""


def cpu_has_avx512(cpuinfo: str | os.PathLike = "/proc/cpuinfo") -> bool:
    """Whether the processor executes AVX-512: its `avx512f` flag in `cpuinfo` (Linux); False
    where that file cannot be read (other systems, where the default width is kept)."""
    try:
        text = pathlib.Path(cpuinfo).read_text()
    except OSError:
        return False
    return any(line.startswith("flags") and "avx512f" in line.split() for line in text.splitlines())


def with_wide_vectors(xla_flags: str) -> str:
    """`xla_flags` (an XLA_FLAGS value) with `WIDE_VECTOR_FLAG` added, unless it already sets a
    vector width (the user's choice is kept)."""
    if "xla_cpu_prefer_vector_width" in xla_flags:
        return xla_flags
    return f"{xla_flags} {WIDE_VECTOR_FLAG}".strip()


def prefer_wide_cpu_vectors(cpuinfo: str | os.PathLike = "/proc/cpuinfo") -> bool:
    """Add `WIDE_VECTOR_FLAG` to the XLA_FLAGS of this process (and of the processes it starts,
    e.g. local Dask workers) when the processor has AVX-512 (`cpu_has_avx512`) and XLA_FLAGS
    sets no width. Call it before JAX's first computation (it has no effect after).

    **Returns:** whether XLA_FLAGS now asks for 512-bit vectors.
    """
    flags = os.environ.get("XLA_FLAGS", "")
    if not cpu_has_avx512(cpuinfo):
        return WIDE_VECTOR_FLAG in flags
    os.environ["XLA_FLAGS"] = with_wide_vectors(flags)
    return WIDE_VECTOR_FLAG in os.environ["XLA_FLAGS"]
