"""`teflon-jax simulate-test`: simulate a bearing test and write it as a test-record CSV.

One flow for every isolator: the flags each one refuses or needs are its row of
`_isolator_table.TEST_ROWS`, looked up by `--isolator`. A flat slider or a single friction
pendulum is the bearing of the flags (or of `--bearing`) under the imposed motion, the
pendulum's concave surface adding its restoring force (small rotations, Zayas, Low & Mahin
1990)

    F = N u / R + mu(v) N Z,

to the friction mu N Z of the same liner on a flat surface (Eq. 1 and Bouc-Wen / Park's Z;
Constantinou, Mokha & Reinhorn 1990), in two directions N u / R along each displacement
component; a triple or double friction pendulum is the series model of its `--isolator-file`.
`fit --isolator ...` recovers the constants from such a record.
"""

import pathlib

import numpy as np

from ..units import INCH, STANDARD_GRAVITY, parse_quantity
from ._bearing_flags import add_bearing_flag, read_bearing_flag
from ._common import add_quantity, add_units_flag, check_table1, flags_given, output_units
from ._isolator_flags import add_isolator_flags
from ._isolator_flags import load_isolator_file as _load
from ._isolator_table import TEST_ROWS, refused, required
from ._provenance import record_metadata

DEFAULT_DIAMETER = 10 * INCH  # specimens of the paper's tests: 10 in diameter
MIN_SAMPLES_PER_CYCLE = 8  # fewer cannot show the shape of a loop


HELP = "simulate an imposed-motion bearing test (Table 1 interface) and write the record"
"""The line of this command in `teflon-jax --help`."""


def add_simulate_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "simulate-test",
        help=HELP,
        description=(
            "Simulate a PTFE bearing driven along a prescribed path with the model of "
            "Constantinou, Mokha & Reinhorn (1990): Eq. 1 friction, Bouc-Wen/Park hysteresis, "
            "optional breakaway (Eq. 17), anisotropy and stacks. Values carry units "
            "(e.g. 1000psi, 6.9MPa, 4in, 0.6Hz, 78.5kip). Defaults: test No. 75."
        ),
    )
    p.add_argument("--ptfe", default="UF", help="PTFE type of Table 1: UF, 15GF or 25GF (default UF)")
    add_quantity(p, "--pressure", "pressure", "1000psi", "contact pressure; Table 1 is interpolated "
                 "linearly between 1000, 2000, 3000 and 6500 psi", minimum=0.0)
    p.add_argument("--extrapolate", action="store_true",
                   help="allow pressures outside Table 1's range (extends the nearest segment)")
    p.add_argument("--direction", default="P", help="sliding direction to the lay: P (parallel) or T (default P)")
    p.add_argument("--pattern", default="sine", help="sine, triangle (constant velocity) or eight "
                   "(figure-eight, Eq. 16: ux = U0 sin wt, uy = U0 sin 2wt) (default sine)")
    p.add_argument("--motion-file", default=None, help="CSV with columns 'time [s]', 'ux [unit]' "
                   "(and optionally 'uy [unit]'): any displacement history, saved at its own samples; replaces "
                   "--pattern, --amplitude, --frequency, --cycles and --samples-per-cycle")
    add_quantity(p, "--amplitude", "length", "4in", "displacement amplitude U0 (at most 100in, "
                 "beyond any bearing)", minimum=0.0, maximum=100 * INCH)
    add_quantity(p, "--frequency", "frequency", "0.6Hz", "frequency of the motion (cyclic or "
                 "angular: 0.6Hz = 3.77rad/s)", minimum=0.0)
    p.add_argument("--cycles", type=float, default=3.0, help="number of cycles (default 3)")
    add_quantity(p, "--normal-load", "force", None, "normal load (compression) (default: pressure "
                 "x area of a 10 in diameter contact)", minimum=0.0)
    p.add_argument("--breakaway", default=None, help="breakaway ratio b of Eq. 17 (>= 1), or 'table' "
                   "for Table 1's b (default: no breakaway)")
    p.add_argument("--interfaces-in-series", type=int, default=1,
                   help="number of sliding interfaces stacked in series, sharing the motion (default 1)")
    add_quantity(p, "--yield-disp", "length", "0.005in", "Bouc-Wen yield displacement Y", minimum=0.0)
    p.add_argument("--anisotropic", action="store_true", help="eight pattern: use the T row of "
                   "Table 1 for sliding along y and interpolate in the sliding angle")
    add_bearing_flag(p, replaces="--ptfe, --pressure, --direction, --breakaway, "
                     "--interfaces-in-series, --yield-disp and --anisotropic; give --normal-load")
    add_isolator_flags(
        p, isolator="a flat slider, or a single friction pendulum: the slider on a concave surface of --radius, "
        "force N u / R + friction",
        file="simulate a triple or double friction pendulum whose surfaces (radius, capacity, friction of each) "
        "this isolator file gives, instead of a flat slider; give --normal-load", file_alone=True,
        radius="radius of curvature R of the concave surface, e.g. 88in")
    p.add_argument("--samples-per-cycle", type=int, default=400, help="saved samples per cycle, at "
                   f"least {MIN_SAMPLES_PER_CYCLE} (default 400)")
    p.add_argument("--out", default="test_record.csv", help="output test-record CSV (default test_record.csv)")
    add_units_flag(p)
    p.add_argument("--plot", default=None, help="write the force-displacement loop to this PNG")
    p.set_defaults(_generated_motion={name: p.get_default(name) for name in GENERATED_MOTION_FLAGS})


def build_test(args):
    """Turn parsed options into (bearing, motion, normal_load, metadata); ValueErrors name the option."""
    from ..bearing import paper_bearing
    from ..tables import interface_parameters

    from_file = read_bearing_flag(args)
    if from_file is not None:
        return _from_bearing_file(args, from_file.bearing)
    ptfe = args.ptfe.upper()
    direction = args.direction.upper()
    pressure = args.pressure
    check_table1(args.ptfe, pressure, args.pressure_text, "--pressure", args.direction, args.extrapolate)
    try:
        friction, table_b = interface_parameters(ptfe, pressure, direction, extrapolate=args.extrapolate)
    except ValueError as error:
        raise ValueError(f"--{error}") from None
    perpendicular = None
    if args.anisotropic:
        if args.pattern != "eight":
            raise ValueError("--anisotropic: only meaningful with --pattern eight (biaxial motion).")
        try:
            perpendicular, _ = interface_parameters(ptfe, pressure, "T", extrapolate=args.extrapolate)
        except ValueError as error:
            raise ValueError(f"--anisotropic: {error}") from None
    breakaway = None
    if args.breakaway is not None:
        if args.breakaway == "table":
            breakaway = table_b
        else:
            breakaway = parse_quantity(args.breakaway, "dimensionless", where="--breakaway")
            if not breakaway >= 1:
                raise ValueError(f"--breakaway: must be >= 1 (Table 1: 1.3-4.4), got {args.breakaway}.")
    args.breakaway_shown = None if breakaway is None else (
        f"{float(breakaway):.3g}" + (" (Table 1)" if args.breakaway == "table" else ""))
    yield_disp = args.yield_disp
    if args.motion_file is None and args.samples_per_cycle < MIN_SAMPLES_PER_CYCLE:
        raise ValueError(f"--samples-per-cycle: must be >= {MIN_SAMPLES_PER_CYCLE} (a loop needs "
                         f"them to show its shape), got {args.samples_per_cycle}.")
    if args.interfaces_in_series < 1:
        raise ValueError(f"--interfaces-in-series: must be an integer >= 1, got {args.interfaces_in_series}.")
    bearing = paper_bearing(friction, yield_disp=yield_disp, breakaway_ratio=breakaway,
                               friction_perpendicular=perpendicular, n_interfaces=args.interfaces_in_series)
    area = np.pi * DEFAULT_DIAMETER**2 / 4
    if args.normal_load is None:
        normal_load = pressure * area
    else:
        normal_load = args.normal_load
        area = normal_load / pressure
    motion = _motion(args)
    metadata = {
        "specimen": f"PTFE-steel flat slider, {ptfe} sheet PTFE (simulated by teflon-jax)",
        "ptfe": ptfe,
        "direction": direction,
        "contact_area": area,
        "interfaces_in_series": args.interfaces_in_series,
        "source": "teflon-jax simulate-test; model of Constantinou, Mokha & Reinhorn (1990)",
    }
    return bearing, motion, normal_load, metadata


def _from_bearing_file(args, bearing):
    """(bearing, motion, normal_load, metadata) for `--bearing FILE`."""
    normal_load = args.normal_load
    if normal_load is None and bearing.pressure_dependence is not None:
        normal_load = float(bearing.pressure_dependence.reference_load)
    if normal_load is None:
        raise ValueError(f"--normal-load: give the normal load of the test; the bearing file "
                         f"{args.bearing} states none (e.g. --normal-load 78.5kip).")
    from ..excitation import AbstractBiaxialMotion

    motion = _motion(args)
    if bearing.backlash is not None and isinstance(motion, AbstractBiaxialMotion):
        raise ValueError(f"--pattern: {args.bearing} has a backlash gap, modelled along x only; "
                         "use --pattern sine or triangle.")
    args.breakaway_shown = (None if bearing.breakaway_ratio is None
                            else f"{float(bearing.breakaway_ratio):.3g}")
    metadata = {
        "specimen": f"bearing of {args.bearing} (simulated by teflon-jax)",
        "interfaces_in_series": bearing.n_interfaces,
        "source": f"teflon-jax simulate-test --bearing {args.bearing}",
    }
    if bearing.heating is not None:
        metadata["contact_area"] = float(bearing.heating.contact_area)
    return bearing, motion, normal_load, metadata


GENERATED_MOTION_FLAGS = ("pattern", "amplitude", "frequency", "cycles", "samples_per_cycle")
"""The flags that shape a generated motion, which `--motion-file` replaces (its samples are saved)."""


def _motion(args):
    from ..excitation import FigureEightMotion, SineMotion, TriangleMotion

    if args.motion_file is not None:
        given = flags_given(args, getattr(args, "_generated_motion", {}))
        if given:
            raise ValueError(f"{given[0]}: shapes a generated motion, and --motion-file {args.motion_file} gives "
                             f"the motion, saved at its own samples; leave {given[0]} out.")
        return _read_motion_file(pathlib.Path(args.motion_file))
    amplitude, frequency = args.amplitude, args.frequency
    if not args.cycles > 0:
        raise ValueError(f"--cycles: must be > 0, got {args.cycles}.")
    if args.pattern == "sine":
        return SineMotion(amplitude, frequency, cycles=args.cycles)
    if args.pattern == "triangle":
        return TriangleMotion(amplitude, frequency, cycles=args.cycles)
    if args.pattern == "eight":
        return FigureEightMotion(amplitude, 2 * np.pi * frequency, cycles=args.cycles)
    raise ValueError(f"--pattern: unknown pattern {args.pattern!r}; accepted values: sine, triangle, eight.")


def _read_motion_file(path: pathlib.Path):
    from ..formats import read_motion_record

    if path.is_dir():
        raise ValueError(f"--motion-file: {path} is a folder; give the CSV file of the displacement history.")
    if not path.is_file():
        raise ValueError(f"--motion-file: {path} does not exist.")
    return read_motion_record(path)


def _series_pendulum(args):
    """(isolator, motion, normal load) of `--isolator-file`; the flat slider's flags refused."""
    from ..formats import load_isolator

    given = flags_given(args, getattr(args, "bearing_option_defaults", {}))
    if args.bearing is not None:
        given.append("--bearing")
    if given:
        flag = given[0]
        raise ValueError(f"{flag}: the isolator comes from --isolator-file {args.isolator_file}; "
                         f"leave {flag} out (or edit the isolator file).")
    if args.normal_load is None:
        raise ValueError("--normal-load: give the vertical load of the friction pendulum test "
                         "(e.g. --normal-load 500kip).")
    if args.motion_file is None and args.samples_per_cycle < MIN_SAMPLES_PER_CYCLE:
        raise ValueError(f"--samples-per-cycle: must be >= {MIN_SAMPLES_PER_CYCLE}, got "
                         f"{args.samples_per_cycle}.")
    try:
        isolator = load_isolator(args.isolator_file)
    except ValueError as error:
        raise ValueError(f"--isolator-file {error}") from None
    return isolator, _motion(args), args.normal_load


def _run_series_pendulum(args) -> int:
    """`simulate-test --isolator-file`: the triple or double pendulum's loop as a test record."""
    from ..formats import test_record_from_arrays, write_test_record
    from ..systems import imposed_path_test

    isolator, motion, normal_load = _series_pendulum(args)
    response = imposed_path_test(isolator, motion, normal_load, samples_per_cycle=args.samples_per_cycle)
    time = response.time
    displacement = response.ux if response.uy is None else np.stack([response.ux, response.uy], -1)
    failed = int(np.count_nonzero(~np.asarray(response.converged)))
    if failed:
        raise RuntimeError(f"the sliders' force balance did not converge at {failed} samples; "
                           "use more --samples-per-cycle.")
    u, f = np.asarray(displacement), np.asarray(response.force)
    planar = u.ndim == 2
    record = test_record_from_arrays(
        u[:, 0] if planar else u, f[:, 0] if planar else f, time=np.asarray(time),
        uy=u[:, 1] if planar else None, fy=f[:, 1] if planar else None,
        normal_load=np.full(len(time), float(normal_load)),
        metadata={"specimen": f"{isolator.description[:-1]} of {args.isolator_file} (simulated by "
                              "teflon-jax)",
                  "source": f"teflon-jax simulate-test --isolator-file; {TEST_ROWS[isolator.isolator].model}",
                  **record_metadata()})
    write_test_record(args.out, record, units=None if args.units == "us" else "SI")
    peak = float(np.max(np.abs(f)) / normal_load)
    print(f"wrote {args.out}: {len(record)} samples, peak |F|/N = {peak:.4f} [-]")
    return 0


def run_simulate(args) -> int:
    from ..excitation import AbstractBiaxialMotion
    from ..formats import test_record_from_arrays, write_test_record
    from ..systems import imposed_path_test

    row = TEST_ROWS[args.isolator]
    refused(args, row.refuses)
    required(args, row.requires)
    if row.file_of_it:
        _load(args.isolator_file, args.isolator)  # a file of the other pendulum is refused by name
    if args.isolator_file is not None:  # the flat slider's row takes the pendulum the file holds
        return _run_series_pendulum(args)
    radius = None if args.radius is None else float(args.radius)  # the flat slider's row refused it
    bearing, motion, normal_load, metadata = build_test(args)
    metadata = pendulum_metadata(metadata, radius, args.radius_text)
    result = imposed_path_test(bearing, motion, normal_load,
                                      samples_per_cycle=args.samples_per_cycle, throw=False)
    if not bool(result.succeeded):
        import diffrax

        raise RuntimeError(f"the solver failed: {diffrax.RESULTS[result.result]}")
    result = pendulum_result(result, radius)
    in_plane = ({"uy": np.asarray(result.uy), "fy": np.asarray(result.fy)}
                if isinstance(motion, AbstractBiaxialMotion) else {})
    record = test_record_from_arrays(
        np.asarray(result.ux),
        np.asarray(result.fx),
        time=np.asarray(result.time),
        **in_plane,
        normal_load=np.asarray(result.normal_load),
        metadata={**metadata, **record_metadata()},
    )
    write_test_record(args.out, record, units=None if args.units == "us" else "SI")
    peak = float(np.max(np.abs(np.asarray(result.fx) / np.asarray(result.normal_load))))
    print(f"wrote {args.out}: {len(record)} samples, peak |fx|/N = {peak:.4f} [-]")
    if args.plot:
        units = output_units(args.units)
        load = units.show(normal_load, "force")
        pattern = {"eight": "figure-eight", "sine": "sinusoid", "triangle": "triangle"}.get(args.pattern, args.pattern)
        motion = ("motion from " + args.motion_file if args.motion_file else
                  f"{pattern} {args.amplitude_text} at {args.frequency_text}")
        stamp = f"{_bearing_words(args, metadata)}; {motion}; N = {load}" + (
            f", breakaway b = {args.breakaway_shown}" if args.breakaway_shown else "")
        from ..report import plot_loop

        plot_loop(result, args.plot, title=stamp, length=units.length)
        print(f"wrote {args.plot}")
    return 0


def _bearing_words(args, metadata) -> str:
    """The bearing in the plot's title."""
    if args.bearing is not None:
        return f"bearing {args.bearing}"
    lay = ("parallel to lay along x, perpendicular along y (anisotropic)" if args.anisotropic
           else f"{'parallel' if metadata['direction'] == 'P' else 'perpendicular'} to lay")
    return f"{metadata['ptfe']} PTFE at {args.pressure_text}, {lay}, Y = {args.yield_disp_text}"


def pendulum_result(result, radius: float | None):
    """`result` (a `BearingTestResult`) with the surface's N u / R added to fx and fy
    (unchanged for a flat slider, `radius` None)."""
    import equinox as eqx

    if radius is None:
        return result
    load = result.normal_load
    return eqx.tree_at(lambda r: (r.fx, r.fy), result,
                       (result.fx + load * result.ux / radius, result.fy + load * result.uy / radius))


def pendulum_metadata(metadata: dict, radius: float | None, radius_text) -> dict:
    """The record's metadata of a pendulum test: its specimen and source say so (unchanged for
    a flat slider, `radius` None)."""
    if radius is None:
        return metadata
    period = 2 * np.pi * np.sqrt(radius / STANDARD_GRAVITY)
    return {**metadata,
            "specimen": f"single friction pendulum, R = {radius_text} (T = {period:.4g} s), "
                        + metadata["specimen"].replace("flat slider", "liner"),
            "source": metadata["source"] + "; restoring force N u / R (Zayas, Low & Mahin 1990)"}
