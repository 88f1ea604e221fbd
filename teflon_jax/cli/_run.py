"""`teflon-jax run`: a user's own ground-motion records (one or two horizontal components, and
a vertical one) through an isolated structure: the rigid mass, the Table 2 building or a rigid
slab on bearing groups, on any isolator (flat sliders, single, triple or double friction
pendulums). One flow for every combination: the isolator and structure flags read and checked
(`_isolator_flags`, `_run_structure`), the records (`_run_records`), the vertical component
composed onto the structure (`_normal_load`), the run and its reduction picked by the type of the
system built (`_run_response`), the outputs (`_run_output`). Peaks in JSON, plots, histories."""

import os
import pathlib
import sys

from ._bearing_flags import add_bearing_flag
from ._common import (
    _NEGATIVE_QUANTITY,
    add_units_flag,
    output_units,
    warn_time_step,
)
from ._isolator_flags import add_isolator_flags, check_combination, read_isolator
from ._normal_load import add_vertical_flag
from ._paths import check_distinct_files
from ._record_checks import RecordFiles, check_record_units
from ._run_stop import stop_entries
from ._run_structure import STRUCTURES
from ._run_suite import add_suite_arguments, check_suite_flags

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
    p.add_argument("--weight", default=None, help="weight of the rigid mass (default 100kN; the building's and "
                   "the slab's are Table 2's and the plan's)")
    p.add_argument("--record-x", default=None, help="x component: PEER .AT2 or a two-column "
                   "(time, acceleration) file with --record-units (required unless --suite)")
    p.add_argument("--suite", default=None, help="CSV of record pairs (record_x, record_y, scale, "
                   "optional name and record_z, a vertical component) run in one call; writes <json stem>.csv "
                   "and .nc (default suite.*)")
    add_suite_arguments(p)
    p.add_argument("--record-y", default=None, help="y component (default: none)")
    add_vertical_flag(p)
    p.add_argument("--record-units", default=None, help="acceleration unit of two-column files: "
                   "g, m/s^2, cm/s^2 or in/s^2 (required for them)")
    p.add_argument("--scale", type=float, default=1.0, help="scale factor on both components, > 0 (default 1)")
    p.add_argument("--start", default="0s", help="start of the window, counted from the record's first "
                   "sample (whatever time the file gives it), e.g. 25s (default 0s)")
    p.add_argument("--duration", default=None, help="length of the window (default: the whole record)")
    p.add_argument("--resample", action="store_true", help="allow components with different time "
                   "steps or lengths: both are interpolated linearly to the finer step and the "
                   "shorter is extended with zeros (reported in the JSON)")
    p.add_argument("--time-step", default=f"{DEFAULT_TIME_STEP}s", help="solver step (default 0.0025s)")
    p.add_argument("--plan", default=None, help="plan of the slab on bearing groups (JSON: length_x, "
                   "length_y, weight, centre_of_mass, optional height_of_centre_of_mass (overturning), groups "
                   "with x, y, load and optional ptfe, pressure, springs, radius (--isolator single-fp), "
                   "isolator_file (--isolator triple-fp or double-fp), vertical_stiffness); with --structure "
                   "building the building's base slab on the groups (any --isolator; weight "
                   "Table 2's 672 kip; the overturning from its levels at Table 2's storey heights, so no "
                   "height_of_centre_of_mass)")
    p.add_argument("--json", default=None, help="write the peaks to this JSON file")
    p.add_argument("--plot", default=None, help="write orbit, x/y loops and histories to this PNG (a single "
                   "record's run)")
    p.add_argument("--histories", default=None, help="write histories to this .nc or .csv file (a single "
                   "record's run)")
    add_bearing_flag(p, replaces="--ptfe, --pressure, --anisotropic, --lay-angle and --breakaway "
                     "(also for every bearing group of a slab)")
    add_units_flag(p)


SMALL_ROTATION_REACH = 0.25
"""Peak base displacement over a single pendulum's radius, u / R, beyond which a run says that the
small-rotation force W u / R departs from the sphere's W u / sqrt(R^2 - u^2) (by 3 % at 0.25)."""


def slope_note(peak_displacement, radius) -> str | None:
    """What a run says of a single pendulum whose peak base displacement `peak_displacement` [m]
    reaches `SMALL_ROTATION_REACH` of its radius `radius` [m] (None: not a single pendulum), or
    passes the radius itself, where no point of the sphere lies; None below."""
    if radius is None or peak_displacement is None or not peak_displacement >= SMALL_ROTATION_REACH * radius:
        return None
    ratio = peak_displacement / radius
    if ratio >= 1:
        return (f"the peak base displacement is {ratio:.3g} times the radius R: no point of the concave surface "
                "lies that far out, so these results are not physical; give the pendulum a larger R or a "
                "displacement capacity (restrainer), or weaken the motion")
    return (f"the peak base displacement is {ratio:.3g} of the radius R, where the sphere's restoring force "
            f"W u / sqrt(R^2 - u^2) is {100 * (1 / (1 - ratio**2) ** 0.5 - 1):.2g} % above the small-rotation "
            "W u / R this run takes")


def run_run(args) -> int:
    """Run `teflon-jax run` (module docstring); returns the exit status (0; 1 when the run
    stopped early, its outputs holding the steps before, `_run_stop`)."""
    check_suite_flags(args)
    isolator = read_isolator(args)  # its flags and files, before the records are read
    check_combination(args, isolator)
    check_record_units(args.record_units, RecordFiles.of(args).named())
    if args.suite is not None:
        if args.record_x is not None or args.record_y is not None or args.record_z is not None:
            raise ValueError("--suite: give the records in the suite file, not with --record-x/--record-y/--record-z.")
        from ._run_suite import run_suite

        return run_suite(args, isolator)
    if args.record_x is None:
        raise ValueError("--record-x: a record is needed (or a --suite file).")
    for horizontal in ("--record-x", "--record-y"):
        check_distinct_files([(horizontal, getattr(args, horizontal[2:].replace("-", "_"))), ("--record-z", args.record_z)],
                             "the vertical component needs its own record")
    if args.resample and args.record_y is None and args.record_z is None:
        raise ValueError("--resample: brings --record-y or --record-z onto the step and length of --record-x, "
                         "and --record-x runs alone here; leave --resample out.")
    if args.histories is not None and pathlib.Path(args.histories).suffix not in (".nc", ".csv"):
        raise ValueError(f"--histories: {args.histories} must end in .nc or .csv.")
    from ..excitation import uniform_signal
    from ..systems import step_count
    from ._normal_load import (
        check_vertical_pressures,
        pressure_law,
        pressure_note,
        with_vertical,
    )
    from ._run_output import write_run_outputs
    from ._run_records import load_components, vertical_component
    from ._run_response import reduce_run, simulate_run
    from ._run_structure import build_structure, read_structure

    flags = read_structure(args, isolator)  # the plan too, before any record
    ax, ay, dt, notes = load_components(args)
    if args.record_y is not None and os.path.samefile(args.record_x, args.record_y):
        notes.append(f"--record-y is the file of --record-x ({args.record_x}): one record along the diagonal, "
                     "sqrt(2) times it in the resultant")
    for note in notes:  # how the records were brought to one window and grid
        print(f"teflon-jax run: {note}", file=sys.stderr)
    system = build_structure(args, isolator, flags, uniform_signal(ax, dt), uniform_signal(ay, dt),
                             two=args.record_y is not None)
    az, law = vertical_component(args, dt, ax.size), pressure_law(args, isolator, flags.plan)
    system = with_vertical(system, az, dt, radius=isolator.radius if flags.plan is None else None,  # a slab's
                           **law)  # groups hold their W_g / R_g
    if az is not None:
        check_vertical_pressures(system, [(f"--record-z {args.record_z}", az)], dt)
    note = pressure_note(law, az)
    if note is not None:
        notes.append(note)
        print(f"teflon-jax run: {note}", file=sys.stderr)
    warn_time_step("run", flags.time_step, args.time_step, dt, f"{dt:g}s of the records")
    duration = (ax.size - 1) * dt
    title = args.structure if isolator.description is None else f"{args.structure} on {isolator.description}"
    print(f"teflon-jax run: {title}, {step_count(flags.time_step, duration)} steps of {args.time_step} over "
          f"{duration:g} s of record (compiling first)...", file=sys.stderr)
    run = simulate_run(system, duration, flags.plan)
    peak, histories, entries, lines = reduce_run(args.structure, system, run, flags.plan, output_units(args.units))
    note = slope_note(peak.get("base_disp_resultant_m"), isolator.radius if flags.plan is None else None)
    if note is not None:
        notes.append(note)
        print(f"teflon-jax run: {note}", file=sys.stderr)
    payload = {
        "structure": args.structure,
        "record_x": str(args.record_x),
        "record_y": None if args.record_y is None else str(args.record_y),
        "record_z": None if args.record_z is None else str(args.record_z),
        "scale": float(args.scale),
        "duration_s": duration,
        "record_time_step_s": dt,
        "solver_time_step_s": flags.time_step,
        "notes": notes,
        **isolator.entries(args),
        "peak": peak,
        **entries,
        **stop_entries(*run.end, ["peak", *entries], beyond_law_s=run.beyond_law_s),
    }
    return write_run_outputs(args, payload, histories, title, lines, run.problem,
                             force_label="friction force" if isolator.pendulum is None else "isolator force")
