"""B7: Monte Carlo on single and triple friction pendulums beside flat sliders with springs, in one run.

The same forty-second Clough-Penzien motions (records at 0.01 s, 5 ms structure steps) run
through the rigid mass and the six-storey building twice: on flat sliders with springs of
period T = 2 pi sqrt(R / g) and no viscous damping, and on single friction pendulums of
radius R (its small-rotation restoring force W u / R, the same period), and a third time on
triple friction pendulums (`TRIPLE`: inner effective radius 0.3 m, outer 2.1 m, Eq. 1 on every
surface; the series model's three sliders solved in each step). All are timed alike
(`--motions` motions in chunks of `--chunk` (512, the CPU's default; 65536 on a GPU), the
rate counted after the first chunk, which compiles; alternating the isolators `--repeats`
times); the record rate of each (per second, and per second of the process's CPU time, which other
processes on a shared machine disturb less) and each pendulum's share of the flat slider's are printed and
written as JSON with the machine.

With `--components 2`, `--balances newton secant` times the triple pendulum once per way of
iterating its planar balance (`StructureOnSliders.balance`), alternated with the others.

Usage: `python benchmarks/bench_pendulum.py [--motions 2048] [--repeats 2] [--chunk 512]
[--components 2] [--isolators flat triple-fp] [--balances newton secant] [--structures rigid]
[--json OUT]`.
"""

import argparse
import dataclasses
import functools
import json
import math
import os
import platform
import time

import jax

jax.config.update("jax_enable_x64", True)

from teflon_jax.bearing import BoucWen, FrictionParameters, TriplePendulum  # noqa: E402
from teflon_jax.excitation import StochasticGroundMotion, TwoComponentGroundMotion  # noqa: E402
from teflon_jax.studies import bidirectional_isolated_structure, monte_carlo  # noqa: E402
from teflon_jax.systems import TRIPLE_MONTE_CARLO_TOLERANCE, isolated_structure  # noqa: E402
from teflon_jax.units import INCH, PSI, STANDARD_GRAVITY  # noqa: E402

RADIUS = 39.0 * INCH  # T = 2.0 s
TIME_STEP = 0.005
ISOLATORS = ("flat", "single-fp", "triple-fp")
TRIPLE = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                        bottom_capacity=0.3, top_capacity=0.3,
                        inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                        bottom_friction=FrictionParameters(0.08, 0.03, 20.0),
                        top_friction=FrictionParameters(0.12, 0.05, 20.0), hysteresis=BoucWen(0.005 * INCH))


def _motions(components=1):
    model = StochasticGroundMotion(peak_ground_acceleration=0.3 * STANDARD_GRAVITY, duration=40.0,
                                   time_step=0.01, rise_time=2.0, strong_motion_duration=10.0)
    return model if components == 1 else TwoComponentGroundMotion(model)


def _balanced(structure, balance, grounds, design=None):
    """`structure(grounds, design)` (a `StructureOnSliders` on series pendulums with `ground_y`) iterating its balance by
    `balance`."""
    return dataclasses.replace(structure(grounds, design), balance=balance)


def _structure(kind, isolator, components=1, balance="newton"):
    period = 2 * math.pi * math.sqrt(RADIUS / STANDARD_GRAVITY)
    build = isolated_structure if components == 1 else bidirectional_isolated_structure
    if isolator == "flat":
        return build(kind, time_step=TIME_STEP, pressure=1000 * PSI, isolation_period=period,
                     isolation_damping=0.0)
    if isolator == "triple-fp":
        structure = build(kind, time_step=TIME_STEP, **_isolator_keywords("triple-fp"),
                          newton_tolerance=TRIPLE_MONTE_CARLO_TOLERANCE)
        return structure if balance == "newton" else functools.partial(_balanced, structure, balance)
    return build(kind, time_step=TIME_STEP, pressure=1000 * PSI, **_isolator_keywords("single-fp"))


def _isolator_keywords(name):
    """The isolator of `isolated_structure`: the value (`TRIPLE`, or a concave surface of
    `RADIUS`); under a version whose builders take isolator names, the name and its part, so
    that both versions time the same structure."""
    try:
        from teflon_jax.bearing import concave_surface, one_surface  # noqa: F401
    except ImportError:
        return {"isolator": name, **({"triple": TRIPLE} if name == "triple-fp" else {"radius": RADIUS})}
    return {"isolator": TRIPLE if name == "triple-fp" else concave_surface(RADIUS)}


def _rate(structure, motions, n, chunk):
    """Records per second from the end of the first chunk to the end of the last (as B3
    counts them: each `monte_carlo` call compiles its own program in its first chunk), the
    mean peak, and records per second of this process's CPU time over the same chunks (less
    sensitive to other processes on a shared machine)."""
    marks = []
    result = monte_carlo(structure, motions, n, key=jax.random.key(1), chunk_size=chunk,
                         progress=lambda done, total: marks.append((time.perf_counter(), time.process_time(), done)))
    (start, cpu_start, first), (end, cpu_end, last) = marks[0], marks[-1]
    return (last - first) / (end - start), float(result.base_disp.mean()), (last - first) / (cpu_end - cpu_start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--motions", type=int, default=2048, help="at least two chunks")
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--chunk", type=int, default=512, help="motions per compiled call")
    parser.add_argument("--components", type=int, choices=(1, 2), default=1,
                        help="horizontal ground components (2: the two-component structures, "
                        "resultant peaks) (default 1)")
    parser.add_argument("--isolators", nargs="+", default=list(ISOLATORS), choices=ISOLATORS,
                        help="isolators to time, flat first (default all three)")
    parser.add_argument("--balances", nargs="+", default=["newton"], choices=("newton", "secant"),
                        help="with --components 2: the triple pendulum's planar balance, each timed as an "
                        "isolator 'triple-fp/BALANCE' (default newton, timed as 'triple-fp')")
    parser.add_argument("--structures", nargs="+", default=["rigid", "building"], choices=("rigid", "building"),
                        help="structures to run (default both)")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    if args.motions < 2 * args.chunk:
        parser.error(f"--motions: at least two chunks of --chunk {args.chunk} are needed (the first compiles)")
    if args.isolators[0] != "flat":
        parser.error("--isolators: the shares are of the flat slider's rate; list flat first.")
    if args.balances != ["newton"] and (args.components != 2 or "triple-fp" not in args.isolators):
        parser.error("--balances: applies to the triple pendulum (--isolators ... triple-fp) with --components 2.")
    isolators = [(i, "newton") for i in args.isolators if i != "triple-fp"]
    if "triple-fp" in args.isolators:
        isolators += [("triple-fp", b) for b in args.balances]
    names = {(i, b): i if args.balances == ["newton"] or i != "triple-fp" else f"{i}/{b}" for i, b in isolators}
    motions = _motions(args.components)
    out = {"machine": {"platform": platform.platform(), "processor": platform.processor(),
                       "cpus": os.cpu_count(), "devices": [d.device_kind for d in jax.devices()],
                       "load_average": os.getloadavg()},
           "motions": args.motions, "components": args.components, "chunk": args.chunk, "radius_m": RADIUS, "time_step_s": TIME_STEP, "rates": {}}
    for kind in args.structures:
        rates = {names[i]: [] for i in isolators}
        cpu_rates = {names[i]: [] for i in isolators}
        means = {}
        for _ in range(args.repeats):
            for isolator, balance in isolators:
                rate, mean, cpu_rate = _rate(_structure(kind, isolator, args.components, balance), motions,
                                             args.motions, args.chunk)
                rates[names[isolator, balance]].append(rate)
                cpu_rates[names[isolator, balance]].append(cpu_rate)
                means[names[isolator, balance]] = mean
        shares = {name: max(rates[name]) / max(rates["flat"]) for name in rates if name != "flat"}
        out["rates"][kind] = {"records_per_s": rates, "records_per_cpu_s": cpu_rates,
                              "pendulum_share": shares.get("single-fp"),
                              "triple_share": shares.get("triple-fp"), "shares": shares,
                              "mean_peak_base_disp_m": means}
        print(f"{kind}: " + "; ".join(f"{name} {', '.join(f'{r:.0f}' for r in rates[name])} records/s"
                                      for name in rates)
              + "; shares of flat " + ", ".join(f"{k} {v:.2f}" for k, v in shares.items())
              + "; mean peaks " + ", ".join(f"{k} {v:.4f} m" for k, v in means.items()))
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(out, handle, indent=2)


if __name__ == "__main__":
    main()
