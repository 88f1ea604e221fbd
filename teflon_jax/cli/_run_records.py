"""The ground-motion records of `teflon-jax run`: the x, y and z (vertical) components read
(PEER AT2, or two-column files with `--record-units`), put on one time grid, windowed by
`--start`/`--duration` and scaled by `--scale`, every error naming the flag."""

import pathlib

import numpy as np

from ..units import parse_quantity
from ._record_checks import RecordFiles, check_peak, check_record_step, check_scaled, is_at2


def read_component(path_text, units, flag):
    """The `GroundMotion` of one record file; `ValueError` naming `flag`."""
    from ..formats import read_at2, read_two_column

    path = pathlib.Path(path_text)
    if not path.is_file():
        raise ValueError(f"{flag}: {path} is not a file.")
    if is_at2(path):
        motion = read_at2(path)
    elif units is None:
        raise ValueError(
            f"{flag}: {path} is a column file, whose acceleration unit is not written in it; "
            "give it with --record-units g (or m/s^2, cm/s^2, in/s^2)."
        )
    else:
        try:
            motion = read_two_column(path, units=units, columns=2)
        except ValueError as error:
            raise ValueError(f"{flag} {error}") from None
    check_peak(motion, flag, path_text, units)
    return motion


def read_once():
    """`read_component` that reads each file once: a file named again (a suite's record in
    several pairs) is the `GroundMotion` read and checked the first time."""
    motions = {}

    def read(path_text, units, flag):
        key = pathlib.Path(path_text).resolve()
        if key not in motions:
            motions[key] = read_component(path_text, units, flag)
        return motions[key]

    return read


def _resample(values, dt, new_dt):
    t = dt * np.arange(values.size)
    t_new = np.arange(0.0, t[-1] + 1e-9 * new_dt, new_dt)
    return np.interp(t_new, t, values)


def load_components(args, files: RecordFiles | None = None, read=read_component):
    """(ax, ay, dt, notes): the windowed, scaled components [m/s^2] on one time grid of `files`
    (default: --record-x, --record-y and --scale), each read by `read` (`read_component`)."""
    files = RecordFiles.of(args) if files is None else files
    x = read(files.x, args.record_units, "--record-x")
    y = None if files.y is None else read(files.y, args.record_units, "--record-y")
    ax, dt = np.asarray(x.acceleration, float), float(x.time_step)
    notes = []
    if y is None:
        ay = np.zeros_like(ax)
    else:
        ay, dty = np.asarray(y.acceleration, float), float(y.time_step)
        if abs(dty - dt) > 1e-9 * dt:
            if not args.resample:
                raise ValueError(
                    f"--record-y: time step {dty:g} s differs from --record-x's {dt:g} s; "
                    "resample one of them, or ask for --resample (linear interpolation to the finer step)."
                )
            new = min(dt, dty)
            ax, ay = _resample(ax, dt, new), _resample(ay, dty, new)
            notes.append(f"resampled from {dt:g} s and {dty:g} s to {new:g} s")
            dt = new
        if ax.size != ay.size:
            length_x, length_y = (ax.size - 1) * dt, (ay.size - 1) * dt
            shorter = min(ax.size, ay.size)
            needed = None if args.duration is None else parse_quantity(args.duration, "time", where="--duration")
            start = parse_quantity(args.start, "time", where="--start")
            if needed is None or start + needed > (shorter - 1) * dt + 1e-9:
                if not args.resample:
                    raise ValueError(
                        f"--record-y: the components last {length_x:g} s (x, {ax.size} samples) and "
                        f"{length_y:g} s (y, {ay.size} samples); choose --duration within the "
                        "shorter, or ask for --resample to extend the shorter with zeros."
                    )
                n = max(ax.size, ay.size)
                ax, ay = np.pad(ax, (0, n - ax.size)), np.pad(ay, (0, n - ay.size))
                notes.append(f"shorter component extended with zeros to {(n - 1) * dt:g} s")
    total = (ax.size - 1) * dt
    start = parse_quantity(args.start, "time", where="--start")
    first = float(x.start_time or 0.0)  # the file's own time of its first sample
    if not 0 <= start < total:
        own = "" if first == 0 else (f", counted from its first sample: the file's times run {first:g} to "
                                     f"{first + total:g} s; file time T is --start (T - {first:g}) s")
        raise ValueError(f"--start: {args.start} is outside the record (0 to {total:g} s{own}).")
    if first != 0 and start > 0:
        notes.append(f"--start {args.start} is counted from the first sample of --record-x, whose file time is "
                     f"{first:g} s: the window begins at file time {first + start:g} s")
    if args.duration is None:
        duration = total - start
    else:
        duration = parse_quantity(args.duration, "time", where="--duration")
        if not duration > 0:
            raise ValueError(f"--duration: must be > 0, got {args.duration}.")
        if start + duration > total + 1e-9:
            raise ValueError(
                f"--duration: {args.duration} from --start {start:g} s runs past the end of the "
                f"record ({total:g} s); the longest window is {total - start:g} s."
            )
    i0 = int(round(start / dt))
    n = int(round(duration / dt)) + 1
    if abs(i0 * dt - start) > 1e-9 * dt or abs((n - 1) * dt - duration) > 1e-9 * dt:
        notes.append(f"the window is {i0 * dt:g} s to {(i0 + n - 1) * dt:g} s, --start and --duration taken to "
                     f"the nearest of the record's samples (step {dt:g} s)")
    scale = float(files.scale)
    if not (np.isfinite(scale) and scale > 0):
        raise ValueError(f"--scale: must be a finite number > 0, got {files.scale:g}.")
    ax, ay = scale * ax[i0:i0 + n], scale * ay[i0:i0 + n]
    check_scaled(ax, ay, scale, f"{files.scale:g}")
    check_record_step(parse_quantity(args.time_step, "time", where="--time-step"), args.time_step, dt,
                      files.named())
    return ax, ay, dt, notes


def vertical_component(args, dt, samples, where: str = "--record-z", files: RecordFiles | None = None,
                       read=read_component):
    """The windowed, scaled vertical component [m/s^2] of `files` (default: --record-z and
    --scale), read by `read` (`read_component`), on the horizontal components' grid (`samples`
    values at step `dt` [s] from --start), or `None` without one; `ValueError` naming `where`
    (--record-z, or a suite pair's record_z) for a step or a length that does not match
    (--resample: interpolated to `dt`, extended with zeros)."""
    files = RecordFiles.of(args) if files is None else files
    if files.z is None:
        return None
    z = read(files.z, args.record_units, where)
    az, dtz = np.asarray(z.acceleration, float), float(z.time_step)
    if abs(dtz - dt) > 1e-9 * dt:
        if not args.resample:
            raise ValueError(f"{where}: time step {dtz:g} s differs from the horizontal components' "
                             f"{dt:g} s; resample it, or ask for --resample (linear interpolation).")
        t = dtz * np.arange(az.size)
        az = np.interp(np.arange(0.0, t[-1] + 1e-9 * dt, dt), t, az)
    i0 = int(round(parse_quantity(args.start, "time", where="--start") / dt))
    window = az[i0:i0 + samples]
    if window.size < samples:
        if not args.resample:
            raise ValueError(f"{where}: lasts {(az.size - 1) * dt:g} s, shorter than the horizontal "
                             f"window ({i0 * dt:g} s + {(samples - 1) * dt:g} s); choose --duration within "
                             "it, or ask for --resample to extend it with zeros.")
        window = np.pad(window, (0, samples - window.size))
    return float(files.scale) * window

