"""Command-line layer of the Monte Carlo and design tools (`teflon-jax montecarlo`,
`teflon-jax design`): argument parsing, progress bar, JSON summary, files and plots.

Quantities on the command line are in paper units where an engineer expects them (pressure
in psi, displacement limit in inches or with a unit, e.g. "4in", "100mm"); all computation is SI.
"""

import argparse
import json
import math
import pathlib
import sys
import time

from ._units import INCH, PSI, STANDARD_GRAVITY, parse_quantity


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value}")
    return value


def _add_common(parser):
    parser.add_argument("--structure", choices=("rigid", "building"), default="rigid",
                        help="rigid mass, or the six-storey building of Table 2 (default rigid)")
    parser.add_argument("--seed", type=int, default=0, help="PRNG seed of the stochastic motions")
    parser.add_argument("--duration", type=float, default=40.0, help="motion length [s] (default 40)")
    parser.add_argument("--record-step", type=float, default=0.01, help="motion sampling step [s]")
    parser.add_argument("--time-step", type=float, default=None,
                        help="structure step [s] (default 0.0025: peaks within 0.2 %% of "
                        "converged ones on 100 test motions, see benchmarks B3)")
    parser.add_argument("--pga", type=float, default=0.3, help="expected PGA [g] (default 0.3)")
    parser.add_argument("--site-frequency", type=float, default=15.6, help="Kanai-Tajimi omega_g [rad/s]")
    parser.add_argument("--site-damping", type=float, default=0.6, help="Kanai-Tajimi zeta_g [-]")
    parser.add_argument("--strong-motion", type=float, default=10.0, help="strong-motion duration [s]")
    parser.add_argument("--ptfe", default="UF", help="PTFE type of Table 1 (UF, 15GF, 25GF)")
    parser.add_argument("--json", type=pathlib.Path, help="write the summary JSON here")
    parser.add_argument("--plot", type=pathlib.Path, help="write a PNG plot here")


def add_montecarlo_parser(subparsers) -> argparse.ArgumentParser:
    """`teflon-jax montecarlo --motions N --structure rigid|building [--seed S] [--out FILE]
    --json OUT.json --plot OUT.png`."""
    parser = subparsers.add_parser(
        "montecarlo",
        help="peak responses under N stochastic ground motions (chunked, sharded over devices)",
        description="Monte Carlo of an isolated structure under Clough-Penzien stochastic "
        "ground motions; the batch is sharded over all JAX devices.",
    )
    parser.add_argument("--motions", type=_positive_int, required=True, help="number of motions N")
    _add_common(parser)
    parser.add_argument("--pressure", type=float, default=1000.0, help="bearing pressure [psi]")
    parser.add_argument("--isolation-period", type=float, default=2.0, help="T_b [s] (<= 0: none, rigid only)")
    parser.add_argument("--isolation-damping", type=float, default=0.05, help="zeta_b [-]")
    parser.add_argument("--chunk-size", type=_positive_int, default=512, help="motions per compiled call "
                        "(split over the devices; about 260 kB each for 40 s motions at 0.01 s)")
    parser.add_argument("--out", type=pathlib.Path, help="results file (.nc with xarray, else .npz + .csv)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.set_defaults(command_function=run_montecarlo)
    return parser


def _motion_model(args, duration=None):
    from ._stochastic import StochasticGroundMotion

    return StochasticGroundMotion(
        peak_ground_acceleration=args.pga * STANDARD_GRAVITY,
        site_frequency=args.site_frequency,
        site_damping=args.site_damping,
        high_pass_frequency=args.site_frequency / 10,
        strong_motion_duration=args.strong_motion,
        duration=args.duration if duration is None else duration,
        time_step=args.record_step,
    )


def _write_json(path, payload):
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(payload, indent=2))


def run_montecarlo(args) -> int:
    """Run `teflon-jax montecarlo`; returns the exit status (0; 1 when some run did not
    converge: the results are written all the same, with their `converged` flags)."""
    import jax
    import numpy as np
    from tqdm import tqdm

    from ._montecarlo import (
        isolated_structure,
        monte_carlo,
        plot_montecarlo,
        save_montecarlo,
    )

    jax.config.update("jax_enable_x64", not getattr(args, "float32", False))
    period = args.isolation_period if args.isolation_period > 0 else None
    structure = isolated_structure(
        args.structure,
        ptfe=args.ptfe,
        pressure=args.pressure * PSI,
        isolation_period=period,
        isolation_damping=args.isolation_damping,
        time_step=args.time_step,
    )
    model = _motion_model(args)
    bar = tqdm(total=args.motions, unit="motion", disable=args.no_progress)

    def progress(done, total):
        bar.update(done - bar.n)

    result = monte_carlo(
        structure, model, args.motions, key=jax.random.key(args.seed), chunk_size=args.chunk_size,
        progress=progress,
    )
    bar.close()
    files = [] if args.out is None else [str(p) for p in save_montecarlo(result, args.out)]
    payload = {
        "n_motions": result.n_motions,
        "structure": args.structure,
        "devices": result.n_devices,
        "device_kind": jax.devices()[0].device_kind,
        "wall_s": result.wall_s,
        "compile_s": result.compile_s,
        "records_per_s": result.n_motions / max(result.wall_s - result.compile_s, 1e-9),
        "chunk_size": result.chunk_size,
        "time_step_s": structure.time_step,
        "all_converged": bool(result.converged.all()),
        "percentiles": result.percentiles(),
        "design": {"pressure_psi": args.pressure, "isolation_period_s": period,
                   "isolation_damping": args.isolation_damping, "ptfe": args.ptfe},
        "motions": {"model": "Clough-Penzien, Jennings-Housner-Tsai envelope", "pga_g": args.pga,
                    "duration_s": args.duration, "seed": args.seed},
        "files": files,
    }
    _write_json(args.json, payload)
    if args.plot is not None:
        plot_montecarlo(result, args.plot, title=f"{args.structure}: {result.n_motions} motions")
    print(json.dumps({k: payload[k] for k in ("n_motions", "devices", "wall_s", "percentiles")}, indent=1))
    failed = int(np.sum(~np.asarray(result.converged)))
    if failed:
        print(
            f"teflon-jax montecarlo: {failed} of {np.asarray(result.converged).size} runs had a time "
            "step whose Newton solve did not converge; their peaks cannot be trusted (column "
            "'converged' of the results). "
            + ("Single precision is too coarse for the bearing's Newton solve: drop --float32."
               if getattr(args, "float32", False) else "Try a smaller --time-step."),
            file=sys.stderr,
        )
        return 1
    return 0


def add_design_parser(subparsers) -> argparse.ArgumentParser:
    """`teflon-jax design --motions N --structure rigid|building --disp-limit 4in ...
    --json OUT.json --plot OUT.png`: minimise the expected base shear over T_b and pressure
    subject to a base-displacement limit."""
    parser = subparsers.add_parser(
        "design",
        help="gradient-based design: minimise expected base shear under a displacement limit",
        description="BFGS over the isolation period and bearing pressure (bounded), with a "
        "gradient check against central differences and a grid sweep of the same objective.",
    )
    parser.add_argument("--motions", type=_positive_int, default=16, help="motions in the set (default 16)")
    _add_common(parser)
    parser.add_argument("--disp-limit", default="3in", help="limit on mean peak base displacement (e.g. 3in, 80mm)")
    parser.add_argument("--period-range", type=float, nargs=2, default=(1.0, 4.0), metavar=("LOW", "HIGH"),
                        help="T_b bounds [s]")
    parser.add_argument("--pressure-range", type=float, nargs=2, default=(1000.0, 3000.0), metavar=("LOW", "HIGH"),
                        help="pressure bounds [psi] (inside Table 1's rows)")
    parser.add_argument("--isolation-damping", type=float, default=0.05, help="zeta_b [-]")
    parser.add_argument("--penalty", type=float, default=100.0, help="penalty weight rho")
    parser.add_argument("--grid", type=_positive_int, default=7, help="sweep points per variable")
    parser.set_defaults(command_function=run_design)
    return parser


def run_design(args) -> int:
    """Run `teflon-jax design`; returns the exit status (0)."""
    import jax

    from ._design import (
        design_bounds,
        design_sweep,
        expected_response,
        gradient_check,
        optimise_design,
        plot_design,
        sweep_start,
    )
    from ._montecarlo import isolated_structure
    from ._stochastic import sample

    jax.config.update("jax_enable_x64", not getattr(args, "float32", False))
    tic = time.perf_counter()
    disp_limit = parse_quantity(args.disp_limit, "length", where="--disp-limit", default_unit="in")
    low_p, high_p = (p * PSI for p in args.pressure_range)
    structure = isolated_structure(
        args.structure, ptfe=args.ptfe, pressure=low_p, isolation_period=args.period_range[0],
        isolation_damping=args.isolation_damping, time_step=args.time_step,
    )
    variables = {"isolation_period": tuple(args.period_range), "pressure": (low_p, high_p)}
    model = _motion_model(args)
    records = sample(model, jax.random.key(args.seed), args.motions)
    dt = args.record_step
    grid = {"isolation_period": _linspace(*args.period_range, args.grid),
            "pressure": _linspace(low_p, high_p, args.grid)}
    sweep = design_sweep(structure, records, dt, grid=grid, disp_limit=disp_limit, penalty=args.penalty)
    start = sweep_start(sweep, design_bounds(structure, variables))
    result = optimise_design(structure, records, dt, variables=variables, disp_limit=disp_limit,
                             penalty=args.penalty, start=start)

    def shear(x):
        return expected_response(structure, x, records, dt)["shear"]

    # at the optimum; Table 1's interpolation has kinks at its tabulated pressures
    _, _, grad_error = gradient_check(shear, result.optimum)
    best = int(sweep["objective"].argmin())
    payload = {
        "n_motions": args.motions,
        "structure": args.structure,
        "devices": len(jax.devices()),
        "wall_s": time.perf_counter() - tic,
        "optimum": {
            "isolation_period_s": result.optimum["isolation_period"],
            "pressure_psi": result.optimum["pressure"] / PSI,
            "objective": result.objective,
            "mean_smooth_base_shear_ratio": result.mean_shear,
            "mean_smooth_base_disp_m": result.mean_disp,
            "mean_peak_base_shear_ratio": result.peak_shear,
            "mean_peak_base_disp_m": result.peak_disp,
            "bfgs_steps": result.steps,
            "converged": result.converged,
        },
        "disp_limit_m": disp_limit,
        "disp_limit_in": disp_limit / INCH,
        "grad_check_max_rel_err": grad_error,
        "grid_best": {
            "isolation_period_s": float(sweep["grid"]["isolation_period"].reshape(-1)[best]),
            "pressure_psi": float(sweep["grid"]["pressure"].reshape(-1)[best] / PSI),
            "objective": float(sweep["objective"].reshape(-1)[best]),
        },
        "grid_start": start,
        "optimum_beats_grid": bool(result.objective <= sweep["objective"].min() * (1 + 1e-9)),
    }
    _write_json(args.json, payload)
    if args.plot is not None:
        plot_design(sweep, result, args.plot, units={"isolation_period": (1.0, "s"), "pressure": (PSI, "psi")})
    print(json.dumps({k: payload[k] for k in ("optimum", "grad_check_max_rel_err", "wall_s")}, indent=1))
    return 0


def _linspace(low, high, n):
    import numpy as np

    if not (math.isfinite(low) and math.isfinite(high) and low < high):
        raise ValueError(f"range: need finite LOW < HIGH, got ({low}, {high}).")
    return np.linspace(low, high, n)
