"""`teflon-jax run`: a user's own ground-motion records (one or two horizontal components)
through an isolated structure on PTFE sliding bearings: rigid mass, Table 2 building or a
rigid slab on bearing groups. Peaks in JSON, plots, histories."""

import pathlib
import sys

import numpy as np

from ..units import parse_quantity
from ._bearing_flags import add_bearing_flag
from ._common import (
    _NEGATIVE_QUANTITY,
    SERIES_ISOLATORS,
    _write_json,
    add_isolator_flags,
    add_units_flag,
    output_units,
    pendulum_period,
    warn_time_step,
)
from ._record_checks import (
    check_peak,
    check_record_step,
    check_record_units,
    check_scaled,
    is_at2,
    run_records,
)
from ._run_bearing import bearing_of_flags as _bearing
from ._run_bearing import fraction as _fraction
from ._run_histories import write_histories
from ._run_slab import build_slab, normal_load_summary, slab_peaks
from ._run_stop import bidirectional_stop, non_finite, stop_entries
from ._run_suite import add_suite_arguments, check_suite_flags
from ._run_vertical import (
    add_vertical_flag,
    uplift_line,
    uplift_summary,
    vertical_component,
    with_vertical,
)

STRUCTURES = ("rigid", "building", "slab")
DEFAULT_TIME_STEP = 0.0025  # [s], systems.BIDIRECTIONAL_TIME_STEP (peaks within 0.5 % of Tsit5)


HELP = "run your own records (x and optional y) through an isolated structure"
"""The line of this command in `teflon-jax --help`."""


def add_run_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "run",
        help=HELP,
        description=(
            "Simulate an isolated structure on PTFE sliding bearings (Constantinou, Mokha & "
            "Reinhorn 1990: Eq. 1 at the resultant sliding speed, Park's biaxial Z, Eq. 17 "
            "breakaway) under one or two horizontal ground components. Values carry units "
            "(1000psi, 2.5s, 5%, 100kN)."
        ),
    )
    p._negative_number_matcher = _NEGATIVE_QUANTITY  # '-1000psi' is a value, refused by its check
    p.add_argument("--structure", default="rigid", choices=STRUCTURES, help="rigid mass, the Table 2 "
                   "building in x and y, or a rigid slab on bearing groups (needs --plan) (default rigid)")
    p.add_argument("--ptfe", default="UF", help="PTFE type of Table 1: UF, 15GF or 25GF (default UF)")
    p.add_argument("--pressure", default="1000psi", help="contact pressure (default 1000psi)")
    p.add_argument("--anisotropic", action="store_true", help="lay of the steel along x (or at --lay-angle) "
                   "(Table 1 P row), y perpendicular (T row), interpolated in the sliding angle")
    p.add_argument("--lay-angle", default=None, help="with --anisotropic: angle of the lay of the steel "
                   "from x towards y, with its unit, e.g. 30deg or 0.5rad (default 0deg: x parallel to "
                   "the lay)")
    p.add_argument("--breakaway", default=None, help="breakaway ratio b of Eq. 17 (>= 1) or 'table' "
                   "(default: no breakaway)")
    p.add_argument("--isolation-period", default=None, help="period of the restoring springs, e.g. "
                   "2.5s (default: none; the building needs it, or --isolator single-fp)")
    add_isolator_flags(p)
    p.add_argument("--isolation-damping", default=None, help="viscous damping of the isolation "
                   "mode, e.g. 5%% (default: none)")
    p.add_argument("--weight", default="100kN", help="weight of the rigid mass (default 100kN)")
    p.add_argument("--record-x", default=None, help="x component: PEER .AT2 or a two-column "
                   "(time, acceleration) file with --record-units (required unless --suite)")
    p.add_argument("--suite", default=None, help="CSV of record pairs (record_x, record_y, scale, "
                   "optional name) run in one call; writes <json stem>.csv and .nc (default suite.*)")
    add_suite_arguments(p)
    p.add_argument("--record-y", default=None, help="y component (default: none)")
    add_vertical_flag(p)
    p.add_argument("--record-units", default=None, help="acceleration unit of two-column files: "
                   "g, m/s^2, cm/s^2 or in/s^2 (required for them)")
    p.add_argument("--scale", type=float, default=1.0, help="scale factor on both components, > 0 (default 1)")
    p.add_argument("--start", default="0s", help="start of the window, e.g. 25s (default 0s)")
    p.add_argument("--duration", default=None, help="length of the window (default: the whole record)")
    p.add_argument("--resample", action="store_true", help="allow components with different time "
                   "steps or lengths: both are interpolated linearly to the finer step and the "
                   "shorter is extended with zeros (reported in the JSON)")
    p.add_argument("--time-step", default=f"{DEFAULT_TIME_STEP}s", help="solver step (default 0.0025s)")
    p.add_argument("--plan", default=None, help="slab plan (JSON: length_x, length_y, weight, "
                   "centre_of_mass, optional height_of_centre_of_mass (overturning), groups with x, "
                   "y, load and optional ptfe, pressure, springs, radius (--isolator single-fp), "
                   "isolator_file (--isolator triple-fp or double-fp), vertical_stiffness)")
    p.add_argument("--json", default=None, help="write the peaks to this JSON file")
    p.add_argument("--plot", default=None, help="write orbit, x/y loops and histories to this PNG")
    p.add_argument("--histories", default=None, help="write histories to this .nc or .csv file")
    add_bearing_flag(p, replaces="--ptfe, --pressure, --anisotropic, --lay-angle and --breakaway "
                     "(also for every bearing group of a slab)")
    add_units_flag(p)


# --------------------------------------------------------------------------- records


def _read_component(path_text, units, flag):
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


def _resample(values, dt, new_dt):
    t = dt * np.arange(values.size)
    t_new = np.arange(0.0, t[-1] + 1e-9 * new_dt, new_dt)
    return np.interp(t_new, t, values)


def load_components(args):
    """(ax, ay, dt, notes): the windowed, scaled components [m/s^2] on one time grid."""
    x = _read_component(args.record_x, args.record_units, "--record-x")
    y = None if args.record_y is None else _read_component(args.record_y, args.record_units, "--record-y")
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
    if not 0 <= start < total:
        raise ValueError(f"--start: {args.start} is outside the record (0 to {total:g} s).")
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
    scale = float(args.scale)
    if not (np.isfinite(scale) and scale > 0):
        raise ValueError(f"--scale: must be a finite number > 0, got {args.scale:g}.")
    ax, ay = scale * ax[i0:i0 + n], scale * ay[i0:i0 + n]
    check_scaled(ax, ay, scale, f"{args.scale:g}")
    check_record_step(parse_quantity(args.time_step, "time", where="--time-step"), args.time_step, dt,
                      run_records(args))
    return ax, ay, dt, notes


# --------------------------------------------------------------------------- structure


def build_structure(args, ax, ay, dt):
    """(system, description) for the parsed options and the components [m/s^2]."""
    from ..excitation import uniform_signal
    from ..systems import bidirectional_building, bidirectional_rigid_mass

    gx, gy = uniform_signal(ax, dt), uniform_signal(ay, dt)
    time_step = parse_quantity(args.time_step, "time", where="--time-step")
    period = pendulum_period(args)
    if args.isolation_period is not None:
        period = parse_quantity(args.isolation_period, "time", where="--isolation-period")
    if period is not None and not period > 0:
        raise ValueError(f"--isolation-period: must be > 0, got {args.isolation_period}.")
    damping = 0.0 if args.isolation_damping is None else _fraction(args.isolation_damping, "--isolation-damping")
    if damping > 0 and period is None:
        raise ValueError("--isolation-damping: dampers need springs; give --isolation-period too.")
    pressure = parse_quantity(args.pressure, "pressure", where="--pressure")  # heating's p
    if args.structure != "slab" and args.plan is not None:
        raise ValueError("--plan: only used with --structure slab.")
    if args.structure == "rigid":
        weight = parse_quantity(args.weight, "force", where="--weight")
        if not weight > 0:
            raise ValueError(f"--weight: must be > 0, got {args.weight}.")
        return bidirectional_rigid_mass(
            weight=weight, bearing=_bearing(args, args.ptfe, args.pressure, "--pressure"),
            ground_x=gx, ground_y=gy, time_step=time_step, isolation_period=period,
            damping_ratio=damping, contact_pressure=pressure), {}
    if args.structure == "building":
        if period is None:
            raise ValueError("--isolation-period: the building needs its springs (Fig. 11: 0.2-4 s), e.g. 2.5s, "
                             "or a friction pendulum (--isolator single-fp --radius 88in).")
        return bidirectional_building(
            bearing=_bearing(args, args.ptfe, args.pressure, "--pressure"), ground_x=gx,
            ground_y=gy, time_step=time_step, isolation_period=period,
            isolation_damping=damping, contact_pressure=pressure), {}
    return build_slab(args, gx, gy, time_step, period, damping)


# --------------------------------------------------------------------------- outputs


def _peak(values):
    return float(np.max(np.abs(values)))


def _resultant(x, y):
    return np.hypot(np.asarray(x), np.asarray(y))


def _storey_ratios(system, response) -> dict:
    """The building's peak drift ratio per storey and total acceleration per level (0 the base
    slab), in x, in y and as resultants (`bidirectional_storey_peaks`)."""
    from ..systems import bidirectional_storey_peaks
    from ..tables import load_table2
    from ..units import STANDARD_GRAVITY

    peaks = bidirectional_storey_peaks(response, system, load_table2().storey_height)
    out = {}
    for key, name, scale in (("storey_drift", "storey_drift_ratio", 1.0),
                             ("level_acceleration", "level_acceleration_g", STANDARD_GRAVITY)):
        for index, axis in enumerate("xy"):
            out[f"{name}_{axis}"] = (peaks[key][index] / scale).tolist()
        out[f"{name}_resultant"] = (peaks[f"{key}_resultant"] / scale).tolist()
    return out


def response_summary(args, system, response, plan):
    """(peak dict, histories dict) in SI from a `BidirectionalResponse`."""
    from ..units import STANDARD_GRAVITY

    q = np.asarray(response.q)
    m, R = np.asarray(system.mass), np.asarray(system.influence)
    total_acc = np.asarray(response.acceleration) + np.asarray(response.ground) @ R.T
    force = np.einsum("tn,n,nd->td", total_acc, m, R)  # on the structure above the bearings
    weight = float(np.sum(m * R[:, 0])) * STANDARD_GRAVITY
    n = q.shape[1] // 2
    ix, iy = (0, 1) if args.structure == "slab" else (0, n)
    base_x, base_y = q[:, ix], q[:, iy]
    bearing_force = -np.asarray(response.friction_force).sum(axis=1)
    peak = {
        "base_disp_resultant_m": float(np.max(_resultant(base_x, base_y))),
        "base_disp_x_m": _peak(base_x),
        "base_disp_y_m": _peak(base_y),
        "base_shear_ratio_resultant": float(np.max(_resultant(force[:, 0], force[:, 1]))) / weight,
        "friction_force_ratio_resultant": float(np.max(_resultant(*bearing_force.T))) / weight,
    }
    if args.structure == "building":
        drift = _resultant(q[:, 1:n] - q[:, 0:n - 1], q[:, n + 1:] - q[:, n:-1])
        floor_acc = _resultant(total_acc[:, 1:n], total_acc[:, n + 1:])
        floors = m[1:n]
        storey = _resultant((floors * total_acc[:, 1:n]).sum(1), (floors * total_acc[:, n + 1:]).sum(1))
        peak["storey_drift_resultant_m"] = [float(v) for v in drift.max(axis=0)]
        peak["floor_acceleration_resultant_g"] = [float(v) for v in floor_acc.max(axis=0) / STANDARD_GRAVITY]
        peak["first_storey_shear_ratio_resultant"] = float(storey.max()) / (float(floors.sum()) * STANDARD_GRAVITY)
        peak.update(_storey_ratios(system, response))
    if args.structure == "slab":
        peak.update(slab_peaks(plan, q, response))
    histories = {
        "time_s": np.asarray(response.time),
        "ground_x_mps2": np.asarray(response.ground)[:, 0],
        "ground_y_mps2": np.asarray(response.ground)[:, 1],
        "base_disp_x_m": base_x,
        "base_disp_y_m": base_y,
        "bearing_force_x_N": bearing_force[:, 0],
        "bearing_force_y_N": bearing_force[:, 1],
        "base_shear_ratio_x": force[:, 0] / weight,
        "base_shear_ratio_y": force[:, 1] / weight,
    }
    if args.structure == "slab":
        histories["rotation_rad"] = q[:, 2]
    return peak, histories


def _shown_peaks(peak: dict, units) -> list:
    """Lines 'name: value unit' of the peaks (SI, keys naming their unit) in the family of
    `--units` (lengths in mm or in; ratios, radians and g as they are)."""
    name, factor = units.length
    lines = []
    for key, value in peak.items():
        label, unit, scale = key, "", 1.0
        if key.endswith("_m"):
            label, unit, scale = key[:-2], f" {name}", factor
        elif key.endswith(("_g", "_rad")):
            label, _, unit = key.rpartition("_")
            unit = f" {unit}"
        if isinstance(value, dict):
            shown = ", ".join(f"{k} {v / scale:.4g}{unit}" for k, v in value.items())
        elif isinstance(value, list):
            shown = ", ".join(f"{v / scale:.4g}" for v in value) + unit
        else:
            shown = f"{value / scale:.4g}{unit}"
        lines.append(f"peak {label.replace('_', ' ')}: {shown}")
    return lines


def plot_run(path, histories, title, *, length=("mm", 1e-3), force=("kN", 1e3),
             force_label="friction force") -> None:
    """Orbit, x and y loops and displacement histories (PNG), in the `length` and `force`
    units given as (name, SI factor); `force_label` names the bearing force of the loops (the
    liner's friction beside springs or a pendulum's N u / R, or a series isolator's whole
    force)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = histories
    (ln, lf), (fn, ff) = length, force
    x, y = h["base_disp_x_m"] / lf, h["base_disp_y_m"] / lf
    fig, axes = plt.subplots(2, 2, figsize=(10, 8))
    axes[0, 0].plot(x, y, lw=0.8)
    axes[0, 0].set(xlabel=f"base displacement x [{ln}]", ylabel=f"base displacement y [{ln}]", title="orbit")
    axes[0, 0].set_aspect("equal", adjustable="datalim")
    for ax, c, u in ((axes[0, 1], "x", x), (axes[1, 0], "y", y)):
        ax.plot(u, h[f"bearing_force_{c}_N"] / ff, lw=0.8)
        ax.set(xlabel=f"base displacement {c} [{ln}]", ylabel=f"{force_label} {c} [{fn}]", title=f"{c} loop")
    t = h["time_s"]
    axes[1, 1].plot(t, x, lw=0.8, label="x")
    axes[1, 1].plot(t, y, lw=0.8, label="y")
    axes[1, 1].plot(t, np.hypot(x, y), lw=0.8, label="resultant")
    axes[1, 1].set(xlabel="time [s]", ylabel=f"base displacement [{ln}]", title="histories")
    axes[1, 1].legend()
    fig.suptitle(title)
    fig.tight_layout()
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def run_run(args) -> int:
    from ..systems import simulate_bidirectional

    check_suite_flags(args)
    pendulum_period(args)  # the isolator's flags, before the records are read
    check_record_units(args.record_units, run_records(args))
    if args.suite is not None:
        if args.record_x is not None or args.record_y is not None or args.record_z is not None:
            raise ValueError("--suite: give the records in the suite file, not with --record-x/--record-y/--record-z.")
        from ._run_suite import run_suite

        return run_suite(args, load_components, build_structure)
    if args.isolator in SERIES_ISOLATORS and args.structure == "slab":  # `_run_slab_series`
        from ._run_slab_series import run_series_slab

        return run_series_slab(args, load_components, write_run_outputs,
                               lambda dt, samples: vertical_component(args, _read_component, dt, samples))
    if args.isolator in SERIES_ISOLATORS:  # triple or double: `_triple.run_triple`
        from ._triple import run_triple

        return run_triple(args, load_components, write_run_outputs,
                          lambda dt, samples: vertical_component(args, _read_component, dt, samples))
    if args.record_x is None:
        raise ValueError("--record-x: a record is needed (or a --suite file).")
    if args.histories is not None and pathlib.Path(args.histories).suffix not in (".nc", ".csv"):
        raise ValueError(f"--histories: {args.histories} must end in .nc or .csv.")
    ax, ay, dt, notes = load_components(args)
    system, plan = build_structure(args, ax, ay, dt)
    system = with_vertical(args, system, vertical_component(args, _read_component, dt, ax.size), dt)
    warn_time_step("run", float(system.time_step), args.time_step, dt, f"{dt:g}s of the records")
    duration = (ax.size - 1) * dt
    print(f"teflon-jax run: {args.structure}, {round(duration / float(system.time_step))} steps of "
          f"{args.time_step} over {duration:g} s of record (compiling first)...", file=sys.stderr)
    response = simulate_bidirectional(system, duration, throw=False)
    problem, end = "", (response.time, np.size(response.time), (), ())
    if not bool(response.succeeded):  # the steps before the failed one, labelled partial
        response, end, problem = bidirectional_stop(system, response)
    peak, histories = response_summary(args, system, response, plan)
    uplift = uplift_summary(response)
    if uplift:
        histories["load_factor"] = np.asarray(response.load_factor)
    lines = [uplift_line(uplift)] * bool(uplift)
    if args.structure == "slab":  # each group's normal load (overturning, vertical record)
        normal, normal_lines = normal_load_summary(plan, system, response, output_units(args.units))
        uplift, lines = {**uplift, **normal}, lines + normal_lines
    payload = {
        "structure": args.structure,
        "record_x": str(args.record_x),
        "record_y": None if args.record_y is None else str(args.record_y),
        "record_z": None if args.record_z is None else str(args.record_z),
        "scale": float(args.scale),
        "duration_s": duration,
        "record_time_step_s": dt,
        "solver_time_step_s": float(system.time_step),
        "notes": notes,
        "isolator": args.isolator,
        "radius_m": args.radius,
        "anisotropic": bool(args.anisotropic),
        "lay_angle_deg": None if args.lay_angle is None else float(
            np.degrees(parse_quantity(args.lay_angle, "angle", where="--lay-angle"))),
        "peak": peak,
        **uplift,
        **stop_entries(*end, ["peak", *uplift]),
    }
    return write_run_outputs(args, payload, histories, args.structure, lines, problem)


def write_run_outputs(args, payload, histories, title, more_lines=(), problem="") -> int:
    """`run`'s outputs: the peaks (and `more_lines`) printed, the JSON `payload` (finite
    numbers only), the histories and the plot (titled `title: records`); returns 0, or 1
    after printing `problem` (why the run stopped early, `_run_stop`) when there is one."""
    units = output_units(args.units)
    bad = non_finite(payload)
    if bad:
        raise ValueError(f"--json: the results {', '.join(bad)} are not finite numbers; nothing was "
                         "written (try a smaller --time-step).")
    for line in _shown_peaks(payload["peak"], units) + list(more_lines):
        print(line)
    _write_json(args.json, payload, allow_nan=False)
    if args.histories is not None:
        write_histories(args.histories, histories)
    if args.plot is not None:
        names = [pathlib.Path(r).name for r in (args.record_x, args.record_y) if r is not None]
        series = getattr(args, "isolator", "flat") not in ("flat", "single-fp")  # its whole force
        plot_run(args.plot, histories, f"{title}: {' + '.join(names)}", length=units.length,
                 force=units.force, force_label="isolator force" if series else "friction force")
    if problem:
        print(f"teflon-jax run: error: {problem}", file=sys.stderr)
        return 1
    return 0
