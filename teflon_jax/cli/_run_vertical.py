"""`teflon-jax run --record-z`: the vertical ground component on the isolators' normal load,
N = W max(1 + a_v / g, 0), and the uplift (N <= 0) the run reports."""

import numpy as np

from ..units import parse_quantity


def add_vertical_flag(parser) -> None:
    """`--record-z FILE`: the vertical component (up positive), read and scaled as the others."""
    parser.add_argument("--record-z", default=None, help="vertical component, up positive (PEER .AT2 "
                        "or a two-column file with --record-units; scaled by --scale, windowed by "
                        "--start/--duration): the isolators' normal load becomes W (1 + a_v / g); at "
                        "N <= 0 they carry no shear and the run reports the uplift (default: none)")


def vertical_component(args, read_component, dt, samples):
    """The windowed, scaled vertical component [m/s^2] on the horizontal components' grid
    (`samples` values at step `dt` [s] from --start), or `None` without --record-z;
    `ValueError` naming --record-z for a step or a length that does not match (--resample:
    interpolated to `dt`, extended with zeros)."""
    if args.record_z is None:
        return None
    z = read_component(args.record_z, args.record_units, "--record-z")
    az, dtz = np.asarray(z.acceleration, float), float(z.time_step)
    if abs(dtz - dt) > 1e-9 * dt:
        if not args.resample:
            raise ValueError(f"--record-z: time step {dtz:g} s differs from the horizontal components' "
                             f"{dt:g} s; resample it, or ask for --resample (linear interpolation).")
        t = dtz * np.arange(az.size)
        az = np.interp(np.arange(0.0, t[-1] + 1e-9 * dt, dt), t, az)
    i0 = int(round(parse_quantity(args.start, "time", where="--start") / dt))
    window = az[i0:i0 + samples]
    if window.size < samples:
        if not args.resample:
            raise ValueError(f"--record-z: lasts {(az.size - 1) * dt:g} s, shorter than the horizontal "
                             f"window ({i0 * dt:g} s + {(samples - 1) * dt:g} s); choose --duration within "
                             "it, or ask for --resample to extend it with zeros.")
        window = np.pad(window, (0, samples - window.size))
    return float(args.scale) * window


def with_vertical(args, system, az, dt):
    """`system` with the vertical component `az` [m/s^2] (unchanged for `None`); a friction
    pendulum's W / R scales with the normal load."""
    if az is None:
        return system
    from ..excitation import uniform_signal
    from ..systems import with_vertical_motion

    # a slab on pendulums holds its groups' W_g / R_g already
    radius = args.radius if args.isolator == "single-fp" and system.pendulum_stiffness is None else None
    return with_vertical_motion(system, uniform_signal(az, dt), radius=radius)


def uplift_summary(response) -> dict:
    """The JSON entries of the uplift: whether N <= 0 at any step and for how long [s]."""
    if response.uplift_time is None:
        return {}
    time = float(response.uplift_time)
    loads = np.asarray(response.load_factor)
    return {"uplift": {"occurred": time > 0, "time_s": time, "min_load_factor": float(loads.min()),
                       "max_load_factor": float(loads.max()),
                       "note": "N = W max(1 + a_v / g, 0); while N <= 0 the isolators carry no "
                               "shear (friction and pendulum force zero)"}}


def uplift_line(summary: dict) -> str | None:
    """The printed line of `uplift_summary` (None without a vertical component)."""
    if not summary:
        return None
    u = summary["uplift"]
    if not u["occurred"]:
        return (f"uplift: none (N / W between {u['min_load_factor']:.3g} and "
                f"{u['max_load_factor']:.3g})")
    return f"uplift: N <= 0 during {u['time_s']:.4g} s (isolators carried no shear then)"
