"""Checks and small helpers of `monte_carlo`: chunk counts, the run's duration, the peak
readings' interval and the arrangement of the peaks in a `MonteCarloResult`."""

import numpy as np

from ._results import RUN_FLAGS


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
