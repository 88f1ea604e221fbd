"""Command-line layer of the Monte Carlo and design tools (`teflon-jax montecarlo`,
`teflon-jax design`): argument parsing, progress bar, JSON summary, files and plots.

Quantities on the command line are in paper units where an engineer expects them (pressure
in psi, displacement limit in inches or with a unit, e.g. "4in", "100mm"); all computation is SI.
"""

import argparse
import json
import pathlib
import sys

from ..units import PSI, STANDARD_GRAVITY
from ._common import _positive_int, _write_json


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
    from ..excitation import StochasticGroundMotion

    return StochasticGroundMotion(
        peak_ground_acceleration=args.pga * STANDARD_GRAVITY,
        site_frequency=args.site_frequency,
        site_damping=args.site_damping,
        high_pass_frequency=args.site_frequency / 10,
        strong_motion_duration=args.strong_motion,
        duration=args.duration if duration is None else duration,
        time_step=args.record_step,
    )


def run_montecarlo(args) -> int:
    """Run `teflon-jax montecarlo`; returns the exit status (0; 1 when some run did not
    converge: the results are written all the same, with their `converged` flags)."""
    import jax
    import numpy as np
    from tqdm import tqdm

    from ..report import plot_montecarlo
    from ..studies import monte_carlo, save_montecarlo
    from ..systems import isolated_structure

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
