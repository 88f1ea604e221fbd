"""Command-line layer of the Monte Carlo and design tools (`teflon-jax montecarlo`,
`teflon-jax design`): argument parsing, progress bar, JSON summary, files and plots.

Every quantity on the command line carries its unit (`--pga 0.3g`, `--pressure 1000psi`,
`--duration 40s`), read by the one parser of `teflon_jax.units`; all computation is SI.
"""

import argparse
import math
import pathlib
import sys
import time

from ..units import STANDARD_GRAVITY
from ._bearing_flags import add_bearing_flag, read_bearing_flag
from ._common import (
    SERIES_ISOLATORS,
    _positive_int,
    _write_json,
    add_isolator_flags,
    add_quantity,
    add_units_flag,
    check_table1,
    motion_bar,
    output_units,
    pendulum_period,
    warn_time_step,
)
from ._engineering import add_engineering_flags, check_bounding_flags
from ._main import compile_cache_dir
from ._montecarlo_vertical import (
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


def _add_common(parser, *, levels: bool = False):
    parser.add_argument("--structure", choices=("rigid", "building"), default="rigid",
                        help="rigid mass, or the six-storey building of Table 2 (default rigid)")
    parser.add_argument("--seed", type=int, default=0, help="PRNG seed of the stochastic motions")
    add_quantity(parser, "--duration", "time", "40s", "length of each motion", minimum=0.0)
    add_quantity(parser, "--record-step", "time", "0.01s", "sampling step of the motions", minimum=0.0)
    add_quantity(parser, "--time-step", "time", None, "step of the structure solver (default 5ms: worst "
                 "peak within 0.2 % of converged ones on 100 test motions, see benchmarks B3; 2.5ms with --components 2 and in design, "
                 "whose gradient check needs the update without the turning-point split)",
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
    _add_common(parser, levels=True)
    add_quantity(parser, "--pressure", "pressure", "1000psi", "bearing contact pressure (Table 1 "
                 "row of --ptfe)", minimum=0.0)
    add_quantity(parser, "--isolation-period", "time", None, "isolation period Tb of the "
                 "restoring spring ('none': friction only, rigid structure only) (default 2s on flat "
                 "sliders)", minimum=0.0, none="none")
    add_quantity(parser, "--isolation-damping", "dimensionless", None, "viscous damping ratio "
                 "zeta_b of the isolation system (default 5% on flat sliders, 0 on a friction "
                 "pendulum)", minimum=0.0, strict=False, maximum=1.0)
    add_isolator_flags(parser)
    parser.add_argument("--components", type=int, choices=(1, 2), default=1,
                        help="horizontal ground components: 1 (along x, the uniaxial structures) or 2 "
                        "(x and y on the bidirectional rigid mass or building: Park's biaxial Z; peaks "
                        "are resultants) (default 1)")
    add_quantity(parser, "--principal-angle", "angle", None, "two components: angle of the major "
                 "principal axis from x towards y (Penzien & Watabe 1975) (default 0deg)")
    add_quantity(parser, "--minor-ratio", "dimensionless", None, "two components: standard deviation "
                 "of the minor component over the major's, in [0, 1] (default 1: two independent, "
                 "equally strong components)", minimum=0.0, strict=False, maximum=1.0)
    parser.add_argument("--chunk-size", type=_positive_int, default=None, help="motions per compiled call "
                        "(split over the devices; about 260 kB each for 40 s motions at 0.01 s) (default: "
                        "512 on a CPU; on a GPU the largest power of two up to 65536 whose motions "
                        "fit in half its free memory; with --scheduler local:N at most motions / N, "
                        "so that every worker has a task)")
    parser.add_argument("--out", type=pathlib.Path, help="results file; its suffix picks the format: "
                        ".nc (NetCDF), .zarr, .csv or .npz")
    parser.add_argument("--newton-iterations", type=_positive_int, default=None, metavar="N",
                        help="the most Newton iterations of the bearing's solve per step (default: "
                        "the library's, enough for every step; 1 makes runs fail, to see how "
                        "failures are reported)")
    parser.add_argument("--newton-tolerance", type=_tolerance, default=None, metavar="TOL",
                        help="one component: the bearing's equilibrium residual at which a step's "
                        "Newton solve stops, in units of the yield displacement Y (default 1e-3: on the "
                        "100 benchmark motions the worst peak error against 0.5 ms steps is the same as "
                        "with 1e-5, 0.1-0.2 %%; 0 solves to rounding)")
    parser.add_argument("--scheduler", default=None, metavar="local:N|ADDRESS",
                        help="run the chunks as tasks on a Dask cluster: 'local:N' starts N worker "
                        "processes here, an address (tcp://host:8786) uses a running scheduler "
                        "(SLURM/PBS: see docs/distributed.md); needs --out FILE.nc, where results "
                        "stream as chunks finish (default: this process)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_engineering_flags(parser)
    add_vertical_flags(parser)
    add_bearing_flag(parser, replaces="--ptfe and --pressure")
    add_posterior_flags(parser)
    parser.set_defaults(command_function=run_montecarlo)
    return parser


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
    its envelope's rise and strong motion, or than one record step, and a site frequency
    above a quarter of the sampling rate."""
    import dataclasses

    rise = next(f.default for f in dataclasses.fields(model_type) if f.name == "rise_time")
    if duration < args.record_step:
        raise ValueError(f"--duration {args.duration_text}: shorter than --record-step {args.record_step_text}; "
                         "lengthen the motions or refine the step.")
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
    import numpy as np

    from ..excitation import TwoComponentGroundMotion
    from ..report import plot_montecarlo
    from ..studies import monte_carlo, save_montecarlo

    units = output_units(args.units)
    _check_flags(args)
    check_bounding_flags(args)  # --property-factors, --posterior-quantiles: before any work
    posterior = read_posterior_flags(args)  # the bearing file's draws, or None
    two = args.components == 2
    structure = vertical_structure(args, _structure(args, two))
    if args.time_step is not None:
        warn_time_step("montecarlo", args.time_step, args.time_step_text, args.record_step,
                       f"{args.record_step_text} of --record-step")
    model = _motion_model(args)
    if two:
        model = TwoComponentGroundMotion(
            model, principal_angle=0.0 if args.principal_angle is None else args.principal_angle,
            minor_ratio=1.0 if args.minor_ratio is None else args.minor_ratio)
    horizontal, model = model, vertical_model(args, model)
    # the default fits the device's memory and the workers (--scheduler local:N)
    args.chunk_size = _chunk_size(args, _device_chunk(args, structure, model))
    if args.property_factors is not None:
        from ._bounding import run_bounding

        return run_bounding(args, structure, model, units)
    if len(args.pga_levels) > 1 or args.limit or args.storeys or args.pelicun_demands is not None:
        from ._levels import run_levels

        return run_levels(args, structure, model, units, _statistics, posterior)
    bar = motion_bar(runs_of(args, posterior), args.no_progress)
    marks = []  # (time, motions done) after each chunk: the rate once compiled and warm

    def progress(done, total):
        marks.append((time.perf_counter(), done))
        bar.update(done - bar.n)

    chunk_size = args.chunk_size
    attrs = {**_run_attributes(args), **posterior_attributes(posterior)}
    if args.scheduler is None:
        result = monte_carlo(
            structure, model, args.motions, key=jax.random.key(args.seed),
            chunk_size=chunk_size, progress=progress, **posterior_arguments(posterior, args.motions),
        )
        result.attrs.update(attrs)
        files = [] if args.out is None else [str(p) for p in save_montecarlo(result, args.out)]
    else:
        from ..studies import monte_carlo_distributed

        result = monte_carlo_distributed(
            structure, model, args.motions, out=args.out, seed=args.seed,
            scheduler=args.scheduler, chunk_size=chunk_size, progress=progress, attrs=attrs,
            compilation_cache=None if args.no_compile_cache else str(compile_cache_dir()),
        )
        files = [str(args.out)]
    bar.close()
    converged = np.asarray(result.converged, bool).reshape(-1)
    stats = _statistics(result, units)
    length = units.length[0]
    payload = _payload(args, result, structure, horizontal, units, stats, files)
    payload["records_per_s_after_first_chunk"] = _steady_rate(marks)
    payload.update(uplift_payload(result, model))
    posterior_entry, posterior_lines = posterior_report(result, posterior, units)
    payload.update(posterior_entry)
    _write_json(args.json, payload)
    bearing_words = (f"{args.ptfe} PTFE at {args.pressure_text}" if args.bearing is None
                     else f"bearing {args.bearing}")
    stamp = (f"{args.structure}, {bearing_words}, Tb = "
             f"{args.isolation_period_text}, zeta_b = {args.isolation_damping_text}; "
             f"Clough-Penzien motions, PGA {args.pga_text}, {args.duration_text}, seed {args.seed}"
             + (f"; 2 components, major at {math.degrees(float(horizontal.principal_angle)):g} deg, minor "
                f"ratio {float(horizontal.minor_ratio):g}" if two else "")
             + (f"; vertical {args.vertical_ratio:g} x PGA" if args.vertical_ratio is not None else ""))
    if args.plot is not None:
        plot_montecarlo(result, args.plot, title=stamp, length=units.length)
    print(f"{result.n_motions} motions on {result.n_devices} device(s) in {result.wall_s:.1f} s; "
          f"statistics over the {int(converged.sum())} of {converged.size} runs that converged:")
    for name, values in stats.items():
        unit = f" {length}" if name.startswith("base_disp") else ""
        print(f"  {name}: " + ", ".join(f"{k} {v:.4g}{unit}" for k, v in values.items()
                                       if k != "n" and v is not None))
    if uplift_message(payload):
        print(uplift_message(payload))
    for line in posterior_lines:
        print(line)
    failed = np.flatnonzero(~converged)
    if failed.size:
        named = ", ".join(str(i) for i in failed[:20]) + (" ..." if failed.size > 20 else "")
        print(
            f"teflon-jax montecarlo: {failed.size} of {converged.size} runs had a time step whose "
            f"Newton solve did not converge (motion indices {named}); they are left out of the "
            "statistics and flagged in the results ('converged'). "
            + ("Single precision is too coarse for the bearing's Newton solve: drop --float32."
               if getattr(args, "float32", False) else "Try a smaller --time-step."),
            file=sys.stderr,
        )
        return 1
    return 0


def _steady_rate(marks) -> float | None:
    """Motions per second from the end of the first chunk to the end of the last, as B3
    counts them (`benchmarks/bench_gpu.py`): without the compilation and the first chunk's
    start-up on the device; `None` with a single chunk."""
    if len(marks) < 2 or marks[-1][0] <= marks[0][0]:
        return None
    return (marks[-1][1] - marks[0][1]) / (marks[-1][0] - marks[0][0])


def _structure(args, two: bool):
    """The isolated structure of the flags (one or two ground components)."""
    from ..studies import bidirectional_isolated_structure
    from ..systems import MONTE_CARLO_NEWTON_TOLERANCE, isolated_structure

    if args.isolator in SERIES_ISOLATORS:
        from ._triple import triple_montecarlo_structure

        return triple_montecarlo_structure(args)

    solver = {} if args.newton_iterations is None else {"newton_iterations": args.newton_iterations}
    if not two:
        solver["newton_tolerance"] = (MONTE_CARLO_NEWTON_TOLERANCE if args.newton_tolerance is None
                                      else args.newton_tolerance)
    return (bidirectional_isolated_structure if two else isolated_structure)(
        args.structure, ptfe=args.ptfe, pressure=args.pressure,
        isolation_period=None if args.isolator != "flat" else args.isolation_period,
        isolation_damping=args.isolation_damping, time_step=args.time_step,
        bearing=read_bearing_flag(args), isolator=args.isolator, radius=args.radius, **solver)


def _payload(args, result, structure, model, units, stats, files) -> dict:
    """The summary JSON of `teflon-jax montecarlo` (displacements in `units`)."""
    import jax
    import numpy as np

    from ._provenance import isolator_as_run

    converged, two, length = np.asarray(result.converged, bool).reshape(-1), args.components == 2, units.length[0]
    payload = {
        "n_motions": result.n_motions,
        "n_converged": int(converged.sum()),
        "not_converged": np.flatnonzero(~converged).tolist(),
        "structure": args.structure,
        "devices": result.n_devices,
        "device_kind": jax.devices()[0].device_kind,
        "wall_s": result.wall_s,
        "compile_s": result.compile_s,
        "records_per_s": result.n_motions / max(result.wall_s - result.compile_s, 1e-9),
        "chunk_size": result.chunk_size,
        "time_step_s": structure.time_step,
        "all_converged": bool(converged.all()),
        "statistics": stats,
        "design": isolator_as_run(args, units.pressure),
        "motions": {"model": "Clough-Penzien, Jennings-Housner-Tsai envelope",
                    "pga_g": args.pga / STANDARD_GRAVITY, "duration_s": args.duration,
                    "seed": args.seed, "components": args.components},
        "units": {"base_disp": length, "base_shear_ratio": "-", "wall_s": "s"},
        "files": files,
    }
    if two:
        payload["motions"].update({
            "principal_angle_deg": math.degrees(float(model.principal_angle)),
            "minor_ratio": float(model.minor_ratio),
            "peaks": "resultants of the x and y components: |(d_x, d_y)| and |(V_x, V_y)| / W, V the "
                     "force on the structure above the bearings"})
    return payload


def _check_flags(args) -> None:
    """Before the runs and before any cluster starts: the results file, the Table 1 row and
    the flags that only one or two ground components use."""
    if args.scheduler is not None:
        from ..studies import check_netcdf_output

        if args.out is None:
            raise ValueError("--scheduler: a distributed run streams its results to a file; "
                             "add --out FILE.nc.")
        check_netcdf_output(args.out, "--out")
    elif args.out is not None:
        from ..studies import check_output_path

        check_output_path(args.out)
    if args.bearing is None and args.isolator not in SERIES_ISOLATORS:  # else the file's friction
        check_table1(args.ptfe, args.pressure, args.pressure_text)
    _resolve_isolation(args)
    check_vertical_flags(args)
    two = args.components == 2
    for flag, value in (("--principal-angle", args.principal_angle), ("--minor-ratio", args.minor_ratio)):
        if value is not None and not two:
            raise ValueError(f"{flag}: describes the second ground component; add --components 2.")
    if args.newton_tolerance is not None and two:
        raise ValueError("--newton-tolerance: applies to one-component runs (the two-component "
                         "solve has its own); leave it out with --components 2.")


def _resolve_isolation(args) -> None:
    """The isolator's flags checked (`pendulum_period`) and the defaults of the isolation
    system in place: Tb = 2 s and 5 % on flat sliders; 2 pi sqrt(R / g) and 0 on a pendulum."""
    period = pendulum_period(args)
    if args.isolator in SERIES_ISOLATORS:  # its period and damping follow from its surfaces
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


def _run_attributes(args) -> dict:
    """What was run, as the results file's attributes: the structure, the isolator and bearings
    as run (`isolator_as_run`, SI: a bearing or isolator file by its path and SHA-256, not the
    flags it replaced), the motions and their seed, each also as the user typed it, and the
    provenance of every result (`provenance_attributes`: version, command line, inputs)."""
    from ._provenance import isolator_as_run, provenance_attributes, replaced_flags

    replaced = replaced_flags(args)
    typed = [k for k in ("pressure", "isolation_period", "isolation_damping", "pga", "duration")
             if "--" + k.replace("_", "-") not in replaced]
    return {"structure": args.structure, **isolator_as_run(args), "pga_m_s2": args.pga, "duration_s": args.duration,
            "record_step_s": args.record_step, "seed": args.seed, "site_frequency_hz": args.site_frequency,
            "site_damping": args.site_damping, "strong_motion_s": args.strong_motion, "components": args.components,
            "inputs_as_given": " ".join(f"{k}={getattr(args, k + '_text')}" for k in typed),
            **provenance_attributes()}


def _statistics(result, units) -> dict:
    """The converged runs' percentiles, mean and standard deviation (`result.percentiles()`,
    each with the count `n` it rests on), the displacement in the output units."""
    stats = result.percentiles()
    factor = units.length[1]
    disp = {k: (v if k == "n" or v is None else v / factor) for k, v in stats["base_disp_m"].items()}
    return {f"base_disp_{units.length[0]}": disp, "base_shear_ratio": stats["base_shear_ratio"]}
