"""The flat sliders and the single pendulum on the series engine beside their own engine.

`speed`: the same batch of stochastic motions (Kanai-Tajimi, El Centro-like, 0.6 g) runs
through the rigid mass and the Table 2 building on flat sliders (springs of period 2 s, 5 %
damping) and on single pendulums (R = 1.5 m), in one and two components, by two engines, each
as one compiled `vmap` over the batch, alternated `--repeats` times: the flat engine
(`StructureOnSliders`, its scalar or planar step, Z along the net increment, its Monte Carlo
tolerance 1e-3 Y in one component, the planar solve's 1e-5 Y in two) and the series engine on
the one-surface isolator (`SinglePendulum` of the same bearing, law "end",
`structure_on_isolator`, its Monte Carlo tolerance 1e-7 W, or `--series-tolerance`). It
prints and writes records/s (compile time apart) and how far the two engines' peaks are apart.

`laws`: the rigid mass under one motion by the three laws at steps of 5 ms down to 0.625 ms,
against the law "end" at 0.15625 ms: "mean" (the series law: Eq. 1 at the mean speed over the
step, f_min while Z points back), "end" (Eq. 1 at the end velocity, Z along the net increment)
and "flat-split" (the flat engine's default: Z along the path to the turning point and back).

Usage: `python benchmarks/one_surface_engine.py speed [--motions 32] [--duration 20]
[--repeats 3] --json OUT` and `python benchmarks/one_surface_engine.py laws --json OUT`.
"""

import argparse
import json
import os
import platform
import sys
import time

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

from teflon_jax.bearing import concave_surface, single_pendulum  # noqa: E402
from teflon_jax.excitation import StochasticGroundMotion, sample, uniform_signal  # noqa: E402
from teflon_jax.studies import bidirectional_isolated_structure  # noqa: E402
from teflon_jax.systems import (  # noqa: E402
    MONTE_CARLO_NEWTON_TOLERANCE,
    TRIPLE_MONTE_CARLO_TOLERANCE,
    isolated_structure,
    peak_response,
    simulate_history,
    structure_on_isolator,
)
from teflon_jax.units import STANDARD_GRAVITY  # noqa: E402

RECORD_STEP = 0.01
ISOLATORS = {"flat": None, "single-fp": 1.5}
"""Each isolator's radius [m] (flat sliders: None)."""


def _value(isolator):
    """The isolator value of `isolator` (`ISOLATORS`): Table 1's flat sliders or `concave_surface(R)`."""
    radius = ISOLATORS[isolator]
    return None if radius is None else concave_surface(radius)


def _grounds(count, duration, seed):
    motion = StochasticGroundMotion(peak_ground_acceleration=0.6 * STANDARD_GRAVITY, duration=duration,
                                    time_step=RECORD_STEP, rise_time=min(2.0, duration / 6),
                                    strong_motion_duration=min(10.0, duration / 2))
    return jnp.asarray(sample(motion, jax.random.PRNGKey(seed), count))


def _engines(kind, isolator, components, duration, series_tolerance=TRIPLE_MONTE_CARLO_TOLERANCE):
    """(flat, series): functions of a batch of ground records (M, nt) or ((M, nt), (M, nt))
    to their peak base displacements (M,) and whether every step balanced."""
    radius = np.inf if ISOLATORS[isolator] is None else ISOLATORS[isolator]
    dt = 0.005 if components == 1 else 0.0025
    rule = "exact" if components == 1 else "newmark"
    linear = isolated_structure(kind, isolator=_value(isolator), split_at_turn=False, time_step=dt, linear_rule=rule,
                                newton_tolerance=MONTE_CARLO_NEWTON_TOLERANCE)
    pendulum = single_pendulum(linear.isolation()[0], radius=radius)

    def series_system(ground_x):
        return structure_on_isolator(linear(uniform_signal(ground_x, RECORD_STEP)), pendulum,
                                     friction_velocity="end", newton_tolerance=series_tolerance)

    if components == 1:
        def flat(ground):
            peaks = peak_response(linear(uniform_signal(ground, RECORD_STEP)), duration)
            return peaks.base_disp, peaks.converged

        def series(ground):
            peaks = peak_response(series_system(ground), duration)
            return peaks.base_disp, peaks.converged
    else:
        planar = bidirectional_isolated_structure(kind, isolator=_value(isolator), time_step=dt,
                                                  newton_tolerance=MONTE_CARLO_NEWTON_TOLERANCE)

        def flat(ground):
            system = planar((uniform_signal(ground[0], RECORD_STEP), uniform_signal(ground[1], RECORD_STEP)))
            peaks = peak_response(system, duration)
            return peaks.base_disp, peaks.converged

        def series(ground):
            system = series_system(ground[0]).with_y_component(uniform_signal(ground[1], RECORD_STEP))
            peaks = peak_response(system, duration)
            return peaks.base_disp, peaks.converged
    return jax.jit(jax.vmap(flat)), jax.jit(jax.vmap(series))


def _timed(function, grounds):
    start = time.perf_counter()
    out = jax.block_until_ready(function(grounds))
    return time.perf_counter() - start, out


def speed(args):
    rows = []
    for components in args.components:
        grounds = _grounds(args.motions, args.duration, 1)
        if components == 2:
            grounds = (grounds, 0.8 * _grounds(args.motions, args.duration, 2))
        for kind in args.structures:
            for isolator in args.isolators:
                engines = dict(zip(("flat", "series"), _engines(kind, isolator, components, args.duration,
                                                                args.series_tolerance)))
                compile_s, peaks = {}, {}
                for name, function in engines.items():
                    compile_s[name], peaks[name] = _timed(function, grounds)
                times = {name: [] for name in engines}
                for _ in range(args.repeats):  # alternated: flat, series, flat, series, ...
                    for name, function in engines.items():
                        times[name].append(_timed(function, grounds)[0])
                rates = {name: args.motions / float(np.median(t)) for name, t in times.items()}
                flat_peak, series_peak = (np.asarray(peaks[n][0]) for n in ("flat", "series"))
                row = {"components": components, "structure": kind, "isolator": isolator,
                       "records_per_s": rates, "series_over_flat": rates["series"] / rates["flat"],
                       "first_call_s": compile_s, "run_s": times,
                       "peak_difference_over_peak": float(np.max(np.abs(flat_peak - series_peak) / flat_peak)),
                       "all_converged": {n: bool(np.all(peaks[n][1])) for n in engines}}
                rows.append(row)
                print(f"{components}c {kind:8s} {isolator:9s} flat {rates['flat']:8.2f} rec/s, series "
                      f"{rates['series']:8.2f} rec/s ({row['series_over_flat']:.2f}); peaks apart "
                      f"{row['peak_difference_over_peak']:.1e}", flush=True)
    return {"motions": args.motions, "duration_s": args.duration, "repeats": args.repeats,
            "series_tolerance": args.series_tolerance, "rows": rows}


def _law_run(isolator, dt, law, ground, duration):
    builder = isolated_structure("rigid", isolator=_value(isolator), split_at_turn=law == "flat-split",
                                 newton_tolerance=0.0, time_step=dt)
    flat = builder(ground)
    if law.startswith("flat"):
        response = jax.jit(simulate_history, static_argnums=1)(flat, duration)
    else:
        radius = np.inf if ISOLATORS[isolator] is None else ISOLATORS[isolator]
        pendulum = single_pendulum(builder.isolation()[0], radius=radius)
        system = structure_on_isolator(flat, pendulum, friction_velocity=law, newton_tolerance=1e-13)
        response = jax.jit(simulate_history, static_argnums=1)(system, duration)
    return np.asarray(response.displacement)[:: int(round(RECORD_STEP / dt)), 0]


def laws(args):
    duration = 12.0
    ground = uniform_signal(np.asarray(_grounds(1, duration, 1))[0], RECORD_STEP)
    rows = []
    for isolator in ISOLATORS:
        reference = _law_run(isolator, 0.00015625, "end", ground, duration)
        peak = float(np.max(np.abs(reference)))
        for dt in (0.005, 0.0025, 0.00125, 0.000625):
            for law in ("mean", "end", "flat-split"):
                history = _law_run(isolator, dt, law, ground, duration)
                row = {"isolator": isolator, "time_step_s": dt, "law": law,
                       "peak_error": float(np.max(np.abs(history))) / peak - 1,
                       "history_error": float(np.max(np.abs(history - reference))) / peak}
                rows.append(row)
                print(f"{isolator:9s} {dt * 1e3:7.4f} ms {law:10s} peak {row['peak_error']:+.2e} "
                      f"history {row['history_error']:.2e}", flush=True)
    return {"reference": "law 'end' at 0.15625 ms", "duration_s": duration, "rows": rows}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    timing = sub.add_parser("speed")
    timing.add_argument("--motions", type=int, default=32)
    timing.add_argument("--duration", type=float, default=20.0)
    timing.add_argument("--repeats", type=int, default=3)
    timing.add_argument("--components", type=int, nargs="+", default=[1, 2])
    timing.add_argument("--structures", nargs="+", default=["rigid", "building"])
    timing.add_argument("--isolators", nargs="+", default=list(ISOLATORS))
    timing.add_argument("--series-tolerance", type=float, default=TRIPLE_MONTE_CARLO_TOLERANCE,
                        help="the series balance's force imbalance over W (1e-4 W moves the isolator by about "
                        "the flat engines' tolerances, 1e-3 Y in one component and 1e-5 Y in two)")
    timing.add_argument("--json", required=True)
    study = sub.add_parser("laws")
    study.add_argument("--json", required=True)
    args = parser.parse_args(argv)
    result = speed(args) if args.command == "speed" else laws(args)
    result.update(command=" ".join(sys.argv), machine=platform.platform(), processor=platform.processor(),
                  cpus=os.cpu_count(), jax=jax.__version__, device=str(jax.devices()[0]))
    with open(args.json, "w") as out:
        json.dump(result, out, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
