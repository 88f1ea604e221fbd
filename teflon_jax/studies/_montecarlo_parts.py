"""Checks and small helpers of `monte_carlo`: chunk counts and memory, the run's duration, the
peak readings' interval and the arrangement of the peaks in a `MonteCarloResult`, the
surfaces whose peaks a run keeps."""

import os

import jax
import numpy as np

from ._result_variables import RUN_FLAGS, SURFACE_VARIABLES


def _check_chunk_and_first_motion(chunk_size, first_motion) -> None:
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, (int, np.integer)) or chunk_size <= 0:
        raise ValueError(f"chunk_size: must be a positive integer, got {chunk_size!r}.")
    if isinstance(first_motion, bool) or not isinstance(first_motion, (int, np.integer)) or first_motion < 0:
        raise ValueError(f"first_motion: must be an integer >= 0, got {first_motion!r}.")


def _run_duration(source, duration) -> float:
    """The duration to run [s]: default the record length; checked > 0."""
    record_duration = (source.samples - 1) * source.time_step
    duration = record_duration if duration is None else float(duration)
    if not duration > 0:
        raise ValueError(f"duration: must be > 0 s, got {duration}.")
    return duration


def _chunk_counts(chunk_size, n_total, n_devices) -> tuple:
    """(motions per chunk, a multiple of the devices; number of chunks)."""
    chunk = min(int(chunk_size), n_total)
    chunk = -(-chunk // n_devices) * n_devices
    return chunk, -(-n_total // chunk)


def _read_every(peak_interval, time_step) -> int:
    """Steps between peak readings: `peak_interval` over the structure's step (default 1)."""
    if peak_interval is None:
        return 1
    ratio = float(peak_interval) / time_step
    read_every = int(round(ratio))
    if read_every < 1 or abs(ratio - read_every) > 1e-6 * ratio:
        raise ValueError(f"peak_interval: must be a positive multiple of the structure's time step "
                         f"{time_step} s, got {peak_interval}.")
    return read_every


def _peak_fields(peaks, with_designs: bool, with_storeys: bool, vertical: bool = False) -> dict:
    """The peak arrays of a `MonteCarloResult`, (design, motion) when designs were run."""

    def arrange(x):
        x = np.asarray(x)
        return np.moveaxis(x, 0, 1) if with_designs else x

    peaks = flat_peaks(peaks)
    return {
        "base_disp": arrange(peaks["base_disp"]),
        "base_shear_ratio": arrange(peaks["base_shear_ratio"]),
        "smooth_base_disp": arrange(peaks["smooth_base_disp"]),
        "smooth_base_shear_ratio": arrange(peaks["smooth_base_shear_ratio"]),
        "converged": arrange(peaks["converged"]),
        "storey_drift": arrange(peaks["storey_drift"]) if with_storeys else None,
        "floor_acceleration": arrange(peaks["floor_acceleration"]) if with_storeys else None,
        **({"uplift_time": arrange(peaks["uplift_time"])} if vertical else {}),
        **{name: arrange(peaks[name]) for name in RUN_FLAGS if name in peaks},
        **{name: arrange(peaks[name]) for name in GROUP_FIELDS if name in peaks},
        **{name: arrange(peaks[name]) for name in SURFACE_VARIABLES if name in peaks},
    }


def flat_peaks(peaks: dict) -> dict:
    """`peaks` (`peak_arrays`) in the `MonteCarloResult`'s fields: each bearing group's peaks
    of `group_normal_load` as their own entries (`GROUP_FIELDS`), and the runs beyond Table 1's
    pressure law (`within_pressure_law` False) not converged, flagged as `beyond_pressure_law`."""
    out = dict(peaks)
    if "group_normal_load" in out:
        out.update({field: out["group_normal_load"][name] for field, name in GROUP_FIELDS.items()})
    if "within_pressure_law" in out:
        within = np.asarray(out["within_pressure_law"])
        out.update(converged=np.asarray(out["converged"]) & within, beyond_pressure_law=~within)
    return out


GROUP_FIELDS = {"group_peak_load": "peak_N", "group_min_load": "min_N", "group_uplift_time": "uplift_time_s"}
"""The `MonteCarloResult` fields of each bearing group's peaks -> the name of the peak
driver's `group_normal_load` entry."""


def _heated_surfaces(system) -> list:
    """[(index, name)] of the heated surfaces: a series pendulum's sliders whose surface is
    heated, or (0, "surface") of a heated flat slider or single pendulum."""
    pendulum = getattr(system, "pendulum", None)
    if pendulum is None:
        heating = getattr(getattr(system, "bearing", None), "heating", None)
        return [] if heating is None else [(0, "surface")]
    return [(e, name) for e, (name, heating) in enumerate(zip(pendulum.slider_names, pendulum.surface_heatings()))
            if heating is not None]


def surface_axes(system) -> dict:
    """The surfaces whose peaks a run keeps (`SURFACE_VARIABLES`): {"slider": names} of a
    series pendulum's sliders, {"heated_surface": names} of the heated surfaces (`_heated_surfaces`);
    {} for neither."""
    pendulum = getattr(system, "pendulum", None)
    heated = tuple(name for _, name in _heated_surfaces(system))
    return ({} if pendulum is None else {"slider": tuple(pendulum.slider_names)}) | (
        {"heated_surface": heated} if heated else {})


def surface_attributes(system) -> dict:
    """{"<dimension>_names": labels} of `surface_axes`, as a result's attributes."""
    return {f"{dim}_names": list(labels) for dim, labels in surface_axes(system).items()}


def surface_groups(system) -> int:
    """The number G of bearing groups whose surfaces' peaks are kept: a plan's groups, else 1."""
    load = system.bearing_load
    return 1 if np.ndim(load) == 0 else int(np.shape(load)[-1])


def surface_peaks(system, peaks: dict) -> dict:
    """`peaks` (`peak_arrays`) with each surface peak on its (group, surface) axes: the sliders'
    travel (G, S) (one group's (S,) given a group axis) and the heated surfaces' temperature
    rise (G, H), the unheated surfaces (whose rise is 0) left out."""
    out = dict(peaks)
    if "slider_travel" in out:
        travel = out["slider_travel"]
        out["slider_travel"] = travel[None] if travel.ndim == 1 else travel
    if "surface_temperature_rise" in out:
        heated = np.array([e for e, _ in _heated_surfaces(system)])
        out["surface_temperature_rise"] = out["surface_temperature_rise"][..., heated]
    return out


def available_memory_bytes(device=None) -> int | None:
    """Free memory [bytes] of `device` (its allocator's limit minus use), or for a CPU the
    host's MemAvailable from /proc/meminfo; `None` when unknown."""
    device = jax.devices()[0] if device is None else device
    try:
        stats = device.memory_stats()
    except Exception:  # backends without memory statistics
        stats = None
    if stats and "bytes_limit" in stats:
        return int(stats["bytes_limit"] - stats.get("bytes_in_use", 0))
    try:
        with open("/proc/meminfo") as handle:
            for line in handle:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def bytes_per_motion(record_samples: int, n_dof: int, n_designs: int) -> int:
    """Estimate of the memory one motion of a chunk needs [bytes] (float64): the record and
    the temporaries of its generation (about 8 record-sized arrays), and per design the
    structure's matrices (3 n^2) and scan carry."""
    return 8 * (8 * record_samples + max(n_designs, 1) * (4 * n_dof**2 + 64))


def check_chunk_memory(chunk, per_motion, memory_limit_bytes, devices) -> None:
    """Raise when a chunk needs more memory than allowed (default: half of the free memory)."""
    estimate = chunk * per_motion
    n_devices = len(devices)
    if memory_limit_bytes is None:
        free = available_memory_bytes(devices[0])
        # devices with their own memory (GPUs) each hold 1 / n_devices of a chunk
        own_memory = devices[0].platform != "cpu"
        memory_limit_bytes = None if free is None else free // 2 * (n_devices if own_memory else 1)
    if memory_limit_bytes is not None and estimate > memory_limit_bytes:
        largest = max(memory_limit_bytes // per_motion, 1)
        raise ValueError(
            f"chunk_size: {chunk} motions need about {estimate / 2**20:.0f} MiB "
            f"({per_motion} bytes each) but only {memory_limit_bytes / 2**20:.0f} MiB may be "
            f"used; take chunk_size <= {largest}."
        )
