"""Command-line layer of the Monte Carlo and design tools (`teflon-jax montecarlo`,
`teflon-jax design`): argument parsing, progress bar, JSON summary, files and plots.

Every quantity on the command line carries its unit (`--pga 0.3g`, `--pressure 1000psi`,
`--duration 40s`), read by the one parser of `teflon_jax.units`; all computation is SI.
"""

import argparse
import math
import pathlib

from ..units import STANDARD_GRAVITY
from ._bearing_flags import add_bearing_flag
from ._bounding import POSTERIOR_WORD
from ._common import (
    _positive_int,
    _write_json,
    add_quantity,
    add_scheduler_flag,
    add_units_flag,
    check_table1,
    motion_bar,
    output_units,
    seed_value,
    warn_time_step,
)
from ._engineering import add_engineering_flags, check_bounding_flags
from ._isolator_flags import add_isolator_flags, check_combination, read_isolator
from ._main import compile_cache_dir
from ._mixture_runs import runner_of
from ._montecarlo_summary import (
    capacity_attributes,
    chunk_marks,
    group_summary,
    report,
    run_attributes,
    stamp,
    statistics,
    summary_payload,
    surface_summary,
)
from ._normal_load import (
    add_vertical_flags,
    check_vertical_flags,
    uplift_message,
    uplift_payload,
    vertical_model,
    vertical_structure,
)
from ._posterior_flags import (
    add_posterior_flags,
    posterior_arguments,
    posterior_attributes,
    posterior_report,
    read_posterior_flags,
    runs_of,
)

HELP = "peak responses under N stochastic ground motions (chunked, sharded over devices)"
"""The line of this command in `teflon-jax --help`."""


def _tolerance(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number >= 0, got {text!r}") from None
    if not value >= 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"expected a finite number >= 0, got {text}")
    return value


def _add_common(parser, *, levels: bool = False, structures=("rigid", "building")):
    parser.add_argument("--structure", choices=structures, default="rigid",
                        help="rigid mass, or the six-storey building of Table 2"
                        + (", or a rigid slab on bearing groups (needs --plan)" if "slab" in structures else "")
                        + " (default rigid)")
    parser.add_argument("--seed", type=seed_value, default=0, help="PRNG seed of the stochastic motions (0 to 4294967295)")
    add_quantity(parser, "--duration", "time", "40s", "length of each motion", minimum=0.0)
    add_quantity(parser, "--record-step", "time", "0.01s", "sampling step of the motions", minimum=0.0)
    add_quantity(parser, "--time-step", "time", None, "step of the structure solver (default 5ms: worst "
                 "peak within 0.2 % of converged ones on 100 test motions, see benchmarks B3; 2.5ms with --components 2 and in design, "
                 "whose gradient check needs the update without the turning-point split"
                 + ("; 2.5ms on a --plan, as run --plan" if "slab" in structures else "") + ")",
                 minimum=0.0)
    add_quantity(parser, "--pga", "acceleration", "0.3g", "expected peak ground acceleration "
                 "(at most 5g, beyond any recorded motion)"
                 + (" or increasing levels 0.1g,0.2g,..., each run with --motions motions "
                    "(fragility curves with --limit)" if levels else ""), minimum=0.0,
                 maximum=5 * STANDARD_GRAVITY, levels=levels)
    add_quantity(parser, "--site-frequency", "frequency", "15.6rad/s", "Kanai-Tajimi site "
                 "frequency omega_g", minimum=0.0)
    add_quantity(parser, "--site-damping", "dimensionless", "0.6", "Kanai-Tajimi site damping "
                 "ratio zeta_g", minimum=0.0)
    add_quantity(parser, "--strong-motion", "time", "10s", "strong-motion duration of the envelope",
                 minimum=0.0)
    parser.add_argument("--ptfe", default="UF", help="PTFE type of Table 1 (UF, 15GF, 25GF) (default UF)")
    parser.add_argument("--json", type=pathlib.Path, help="write the summary JSON here")
    parser.add_argument("--plot", type=pathlib.Path, help="write a PNG plot here")
    add_units_flag(parser)


def add_montecarlo_parser(subparsers) -> argparse.ArgumentParser:
    """`teflon-jax montecarlo --motions N --structure rigid|building [--seed S] [--out FILE]
    --json OUT.json --plot OUT.png`."""
    parser = subparsers.add_parser(
        "montecarlo",
        help=HELP,
        description="Monte Carlo of an isolated structure under Clough-Penzien stochastic "
        "ground motions; the batch is sharded over all JAX devices.",
    )
    parser.add_argument("--motions", type=_positive_int, required=True, help="number of motions N "
                        "(at each --pga level)")
    _add_common(parser, levels=True, structures=("rigid", "building", "slab"))
    parser.add_argument("--plan", default=None, help="plan of bearing groups (JSON, as for `run --plan`): "
                        "the slab (--structure slab) or the Table 2 building's base slab (--structure "
                        "building) on the groups, built once and run under every motion; needs --components 2")
    add_quantity(parser, "--pressure", "pressure", "1000psi", "bearing contact pressure (Table 1 "
                 "row of --ptfe)", minimum=0.0)
    add_quantity(parser, "--isolation-period", "time", None, "isolation period Tb of the "
                 "restoring spring ('none': friction only, rigid structure only) (default 2s on flat "
                 "sliders)", minimum=0.0, none="none")
    add_quantity(parser, "--isolation-damping", "dimensionless", None, "viscous damping ratio "
                 "zeta_b of the isolation system (default 5% on flat sliders, 0 on a friction "
                 "pendulum)", minimum=0.0, strict=False, maximum=1.0)
    add_isolator_flags(parser)
    add_components_flags(parser)
    parser.add_argument("--chunk-size", type=_positive_int, default=None, help="motions per compiled call "
                        "(split over the devices; about 260 kB each for 40 s motions at 0.01 s) (default: "
                        "512 on a CPU; on a GPU the largest power of two up to 65536 whose motions "
                        "fit in half its free memory; with --scheduler local:N at most motions / N, "
                        "so that every worker has a task)")
    parser.add_argument("--out", type=pathlib.Path, help="results file; its suffix picks the format: "
                        ".nc (NetCDF), .zarr, .csv or .npz")
    parser.add_argument("--newton-iterations", type=_positive_int, default=None, metavar="N",
                        help="the most Newton iterations of the bearing's solve per step (default: "
                        "the library's, enough for every step; a step still above --newton-tolerance "
                        "after them fails its run: 1 with --newton-tolerance 0 shows how failures are "
                        "reported)")
    parser.add_argument("--newton-tolerance", type=_tolerance, default=None, metavar="TOL",
                        help="flat sliders and single pendulums: the bearing's equilibrium residual at which "
                        "a step's Newton solve stops, in units of the yield displacement Y (default, one "
                        "component, 1e-3: on the 100 benchmark motions the worst peak error against 0.5 ms "
                        "steps is the same as with 1e-5, 0.1-0.2 %%; two components: the planar solve's "
                        "1e-5; 0 solves to rounding)")
    add_scheduler_flag(parser, "run the chunks as tasks", ", where results stream as chunks finish "
                       "(default: this process)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_engineering_flags(parser)
    add_vertical_flags(parser)
    add_bearing_flag(parser, replaces="--ptfe and --pressure")
    add_posterior_flags(parser)
    parser.set_defaults(command_function=run_montecarlo)
    return parser


def add_components_flags(parser) -> None:
    """--components, --principal-angle and --minor-ratio: the horizontal ground components of
    the stochastic motions (`ground_motion_model`)."""
    parser.add_argument("--components", type=int, choices=(1, 2), default=1,
                        help="horizontal ground components: 1 (along x, the uniaxial structures) or 2 "
                        "(x and y on the bidirectional rigid mass or building: Park's biaxial Z; peaks "
                        "are resultants) (default 1)")
    add_quantity(parser, "--principal-angle", "angle", None, "two components: angle of the major "
                 "principal axis from x towards y (Penzien & Watabe 1975) (default 0deg)")
    add_quantity(parser, "--minor-ratio", "dimensionless", None, "two components: standard deviation "
                 "of the minor component over the major's, in [0, 1] (default 1: two independent, "
                 "equally strong components)", minimum=0.0, strict=False, maximum=1.0)


def ground_motion_model(args, duration=None):
    """The stochastic motions of the flags: `_motion_model`'s, as a `TwoComponentGroundMotion`
    with --principal-angle and --minor-ratio under --components 2."""
    from ..excitation import TwoComponentGroundMotion

    model = _motion_model(args, duration)
    if args.components != 2:
        return model
    return TwoComponentGroundMotion(
        model, principal_angle=0.0 if args.principal_angle is None else args.principal_angle,
        minor_ratio=1.0 if args.minor_ratio is None else args.minor_ratio)


def check_components_flags(args) -> None:
    """`ValueError` naming --principal-angle or --minor-ratio given without --components 2."""
    for flag, value in (("--principal-angle", args.principal_angle), ("--minor-ratio", args.minor_ratio)):
        if value is not None and args.components != 2:
            raise ValueError(f"{flag}: describes the second ground component; add --components 2.")


def _motion_model(args, duration=None):
    from ..excitation import StochasticGroundMotion

    _check_envelope(args, StochasticGroundMotion, args.duration if duration is None else duration)
    return StochasticGroundMotion(
        peak_ground_acceleration=args.pga,
        site_frequency=2 * math.pi * args.site_frequency,
        site_damping=args.site_damping,
        high_pass_frequency=2 * math.pi * args.site_frequency / 10,
        strong_motion_duration=args.strong_motion,
        duration=args.duration if duration is None else duration,
        time_step=args.record_step,
    )


def _check_envelope(args, model_type, duration: float) -> None:
    """`ValueError` naming the flags (--duration, --strong-motion, --record-step,
    --site-frequency) whose values the stochastic motions cannot take: a motion shorter than
    its envelope's rise and strong motion, or than one record step, or not a whole number of
    record steps, and a site frequency above a quarter of the sampling rate."""
    import dataclasses

    rise = next(f.default for f in dataclasses.fields(model_type) if f.name == "rise_time")
    if duration < args.record_step:
        raise ValueError(f"--duration {args.duration_text}: shorter than --record-step {args.record_step_text}; "
                         "lengthen the motions or refine the step.")
    whole = math.floor(duration / args.record_step + 1e-9)  # the motions' steps (`excitation.sample`)
    if duration - whole * args.record_step > 1e-6 * args.record_step:
        raise ValueError(f"--duration {args.duration_text}: not a whole number of --record-step "
                         f"{args.record_step_text}, so the motions would end at {whole * args.record_step:g} s; give "
                         f"--duration {whole * args.record_step:g}s or {(whole + 1) * args.record_step:g}s.")
    if rise + args.strong_motion > duration * (1 + 1e-12):
        raise ValueError(f"--duration {args.duration_text}: shorter than the motions' envelope, its rise of "
                         f"{rise:g} s plus --strong-motion {args.strong_motion_text} ({rise + args.strong_motion:g} s); "
                         f"give --duration {rise + args.strong_motion:g}s or more, or a shorter --strong-motion.")
    if args.site_frequency > 1 / (4 * args.record_step):
        raise ValueError(f"--site-frequency {args.site_frequency_text}: above a quarter of the sampling rate of "
                         f"--record-step {args.record_step_text} ({1 / (4 * args.record_step):g} Hz); give a "
                         "smaller --record-step or a lower --site-frequency.")


def run_montecarlo(args) -> int:
    """Run `teflon-jax montecarlo`; returns the exit status (0; 1 when some run did not
    converge: the results are written all the same, with their `converged` flags, and the
    statistics rest on the converged runs only)."""
    import jax

    from ..report import plot_montecarlo
    from ..studies import monte_carlo, save_montecarlo

    units = output_units(args.units)
    isolator = _check_flags(args)
    bounds = check_bounding_flags(args, isolator)  # --property-factors, --posterior-quantiles: before any work
    posterior = read_posterior_flags(args, isolator)  # the bearing file's draws, or None
    two = args.components == 2
    structure = _structure(args, isolator, two)  # the vertical: a load on it
    if args.time_step is not None:
        warn_time_step("montecarlo", args.time_step, args.time_step_text, args.record_step,
                       f"{args.record_step_text} of --record-step")
    model = ground_motion_model(args)
    horizontal, model = model, vertical_model(args, model)
    # the default fits the device's memory and the workers (--scheduler local:N)
    args.chunk_size = _chunk_size(args, _device_chunk(args, structure, model))
    if args.property_factors is not None:
        from ._bounding import run_bounding

        return run_bounding(args, bounds, structure, model, units)
    if len(args.pga_levels) > 1 or args.limit or args.storeys or args.pelicun_demands is not None:
        from ._levels import run_levels

        return run_levels(args, structure, model, units, statistics, posterior)
    bar = motion_bar(runs_of(args, posterior), args.no_progress)
    progress, marks = chunk_marks(bar)  # (time, runs done) after each chunk: the rate once compiled and warm
    chunk_size = args.chunk_size
    attrs = {**run_attributes(args), **posterior_attributes(posterior), **capacity_attributes(structure)}
    if args.scheduler is None:
        result = runner_of(posterior, monte_carlo)(  # a bearing file's mixture: its compositions
            structure, model, args.motions, key=jax.random.key(args.seed),
            chunk_size=chunk_size, progress=progress, **posterior_arguments(posterior, args.motions),
        )
        result.attrs.update(attrs)
        files = [] if args.out is None else [str(p) for p in save_montecarlo(result, args.out)]
    else:
        from ..studies import monte_carlo_distributed

        result = monte_carlo_distributed(
            structure, model, args.motions, out=args.out, seed=args.seed,
            scheduler=args.scheduler, chunk_size=chunk_size, progress=progress,
            attrs={k: "none" if v is None else v for k, v in attrs.items()},  # as the file written here says None
            compilation_cache=None if args.no_compile_cache else str(compile_cache_dir()),
        )
        files = [str(args.out)]
    bar.close()
    stats = statistics(result, units)
    payload = summary_payload(args, result, structure, horizontal, units, stats, files, marks)
    payload.update(uplift_payload(result, model))
    groups, group_lines = group_summary(result, units)
    if groups:
        payload["groups"], payload["units"]["group_load"] = groups, units.force[0]
    surfaces, surface_lines = surface_summary(result, units)  # the capacities its attributes keep
    if surfaces:
        payload["surfaces"] = surfaces
    posterior_entry, posterior_lines = posterior_report(result, posterior, units)
    payload.update(posterior_entry)
    _write_json(args.json, payload)
    if args.plot is not None:
        plot_montecarlo(result, args.plot, title=stamp(args, horizontal), length=units.length)
    return report(args, result, stats, units, [uplift_message(payload)] * bool(uplift_message(payload))
                  + group_lines + surface_lines + posterior_lines)


def _structure(args, isolator, two: bool):
    """The isolated structure of the flags on `isolator` (`read_isolator`), under one or two
    ground components: flat sliders and single pendulums with --ptfe and --pressure (or
    --bearing) and the isolation system of `_resolve_isolation`, series pendulums with their
    surfaces, each solved to its Monte Carlo tolerance; or the slab or building of --plan on
    its groups of any of them (`built_on_plan`), solved to the same tolerances."""
    from ..studies import bidirectional_isolated_structure
    from ..systems import (
        MONTE_CARLO_NEWTON_TOLERANCE,
        TRIPLE_MONTE_CARLO_TOLERANCE,
        isolated_structure,
    )

    options = isolator.structure_options()
    solver = {} if args.newton_iterations is None else {"newton_iterations": args.newton_iterations}
    if isolator.pendulum is not None:  # its sliders' force imbalance over W, in one and two components
        solver["newton_tolerance"] = TRIPLE_MONTE_CARLO_TOLERANCE
    elif args.newton_tolerance is not None or not two:  # two components: the planar solve's own by default
        solver["newton_tolerance"] = (MONTE_CARLO_NEWTON_TOLERANCE if args.newton_tolerance is None
                                      else args.newton_tolerance)
    if args.plan is not None:  # two components (`_check_plan`), at run --plan's step by default
        from ..systems import BIDIRECTIONAL_TIME_STEP
        from ._run_structure import built_on_plan

        return built_on_plan(args, isolator, time_step=args.time_step or BIDIRECTIONAL_TIME_STEP,
                             period=args.isolation_period, damping=args.isolation_damping,
                             record_step=args.record_step, vertical=args.vertical_ratio is not None, solver=solver)
    if isolator.pendulum is None:
        options.update(ptfe=args.ptfe, pressure=args.pressure, isolation_damping=args.isolation_damping,
                       isolation_period=None if isolator.restores else args.isolation_period)
    return vertical_structure(args, (bidirectional_isolated_structure if two else isolated_structure)(
        args.structure, time_step=args.time_step, **options, **solver))


def _check_flags(args):
    """Before the runs and before any cluster starts: the results file, the isolator
    (`read_isolator`, returned), the Table 1 row, what cannot run together
    (`check_combination`) and the flags that only one or two ground components use."""
    if args.scheduler is not None:
        from ..studies import check_netcdf_output

        if args.out is None:
            raise ValueError("--scheduler: a distributed run streams its results to a file; "
                             "add --out FILE.nc.")
        check_netcdf_output(args.out, "--out")
    elif args.out is not None:
        from ..studies import check_output_path

        check_output_path(args.out)
    isolator = read_isolator(args)
    if args.bearing is None and isolator.pendulum is None:  # else the file's or the surfaces' friction
        check_table1(args.ptfe, args.pressure, args.pressure_text)
    _resolve_isolation(args, isolator)
    check_combination(args, isolator)
    check_vertical_flags(args)
    if args.plan is not None:
        _check_plan(args)
    check_components_flags(args)
    return isolator


def _check_plan(args) -> None:
    """`ValueError` naming the flag that a structure on a plan does not take: one ground
    component (its groups carry the slab in the plane), a bearing posterior's draws and its
    quantiles as bounds, which vary one bearing's constants in a structure rebuilt per run
    (factors, LOWER,UPPER, scale every group's friction)."""
    if args.components != 2:
        raise ValueError("--plan: the groups carry the slab in the plane, under both ground components; "
                         "add --components 2.")
    if args.bearing_draws not in (None, "point"):
        raise ValueError("--bearing-draws: varies the bearings of a structure rebuilt for each run; a structure "
                         "on --plan is built once. Give --bearing-draws point (the file's own constants), run the "
                         "plan once per bearing file, or leave --bearing-draws out.")
    if (args.property_factors or "").strip() == POSTERIOR_WORD:
        raise ValueError(f"--property-factors {POSTERIOR_WORD}: takes each Eq. 1 constant of one bearing from its "
                         "posterior, and the groups of --plan each run their own bearings; give LOWER,UPPER "
                         "factors (every group's friction times them).")


def _resolve_isolation(args, isolator) -> None:
    """The defaults of the isolation system of `isolator` in place: Tb = 2 s and 5 % on flat
    sliders; 2 pi sqrt(R / g) and 0 on a single pendulum; a series pendulum's follow from its
    surfaces."""
    period = isolator.period
    if isolator.pendulum is not None:  # its period and damping follow from its surfaces
        args.isolation_period, args.isolation_period_text = None, f"of {args.isolator_file}"
        args.isolation_damping, args.isolation_damping_text = 0.0, "0"
    elif period is not None:
        args.isolation_period, args.isolation_period_text = period, f"{period:.4g}s (R = {args.radius_text})"
    elif args.isolation_period_text is None:
        args.isolation_period, args.isolation_period_text = 2.0, "2s"
    if args.isolation_damping_text is None:
        damping = 0.05 if period is None else 0.0
        args.isolation_damping, args.isolation_damping_text = damping, f"{damping:.0%}"


def _chunk_size(args, device_default: int = 512) -> int:
    """--chunk-size, or `device_default` (`studies.monte_carlo_chunk_size`: 512 on a CPU, on a
    GPU the largest power of two up to 65536 that fits in half its free memory), with
    --scheduler local:N at most ceil(motions / N): a run of fewer chunks than workers leaves
    workers idle."""
    if args.chunk_size is not None:
        return args.chunk_size
    workers = args.scheduler[len("local:"):] if (args.scheduler or "").startswith("local:") else ""
    if workers.isdigit() and int(workers) > 0:
        return max(1, min(device_default, math.ceil(args.motions / int(workers))))
    return device_default


def _device_chunk(args, structure, model) -> int:
    """The default chunk for the devices of this machine (those of a remote cluster are
    unknown here: 512)."""
    from ..studies import CPU_CHUNK, monte_carlo_chunk_size

    if args.chunk_size is not None or not (args.scheduler or "local:").startswith("local:"):
        return CPU_CHUNK
    return monte_carlo_chunk_size(structure, model)


