"""The series groups' engine with one group against the one-isolator engine, under two components.

The rigid mass and the Table 2 building on one triple friction pendulum (`triple_structure`,
the one-isolator planar balance) and the same structures as a plan of one group at the centre
of mass (`slab_on_bearings` of the building's weight, `building_on_plan` without heights: the
groups' balance): the same motions through `peak_response`, vmapped, the two engines alternated
in one process, each timed after its compilation (best of `--repeats`). Prints records/s and
the largest relative difference of the peaks.

    python benchmarks/groups_engine.py --motions 16 --duration 20 --repeats 2
"""

import argparse
import platform
import time

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np  # noqa: E402
from engine_numbers import x_record  # noqa: E402  (the plan builders' x record on either tree)

from teflon_jax.bearing import BoucWen, FrictionParameters, TriplePendulum  # noqa: E402
from teflon_jax.excitation import (  # noqa: E402
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    uniform_signal,
)
from teflon_jax.studies import monte_carlo_motion  # noqa: E402
from teflon_jax.systems import (  # noqa: E402
    building_on_plan,
    peak_response,
    slab_on_bearings,
    triple_structure,
    under_ground,
)
from teflon_jax.tables import load_table2  # noqa: E402

TRIPLE = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                        bottom_capacity=0.3, top_capacity=0.3, inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                        bottom_friction=FrictionParameters(0.08, 0.03, 20.0),
                        top_friction=FrictionParameters(0.12, 0.05, 20.0), hysteresis=BoucWen(1.27e-4))
RECORD_STEP, TIME_STEP = 0.01, 0.005


def structures(kind: str, zero):
    """(one-isolator structure, one-group structure) of `kind` under the record `zero`."""
    weight = load_table2().total_weight
    one = triple_structure(kind, TRIPLE, zero, ground_y=zero, time_step=TIME_STEP, weight=weight)
    plan = dict(length_x=2.0, length_y=2.0, centre_of_mass=[1.0, 1.0], positions=[[1.0, 1.0]], loads=[weight],
                **x_record(zero), ground_y=zero, time_step=TIME_STEP, isolator="triple-fp", pendulums=TRIPLE)
    if kind == "rigid":
        return one, slab_on_bearings(weight=weight, **plan)
    return one, building_on_plan(storey_heights=0.0, **plan)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--motions", type=int, default=16)
    parser.add_argument("--duration", type=float, default=20.0)
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args(argv)
    model = TwoComponentGroundMotion(StochasticGroundMotion(peak_ground_acceleration=3.0, duration=args.duration,
                                                            time_step=RECORD_STEP), minor_ratio=0.7)
    rows = np.stack([np.asarray(monte_carlo_motion(model, jax.random.key(1), i)) for i in range(args.motions)])
    zero = uniform_signal(np.zeros(rows.shape[-1]), RECORD_STEP)
    print(f"{platform.processor() or platform.machine()}, {jax.device_count()} JAX device(s), jax {jax.__version__}, "
          f"{args.motions} motions of {args.duration:g} s at {TIME_STEP:g} s steps")
    for kind in ("rigid", "building"):
        runs = {}
        for name, system in zip(("one isolator", "groups, G = 1"), structures(kind, zero)):
            def peaks(ax, ay, system=system):
                return peak_response(under_ground(system, uniform_signal(ax, RECORD_STEP),
                                                  uniform_signal(ay, RECORD_STEP)), args.duration)

            function = jax.jit(jax.vmap(peaks))
            tic = time.perf_counter()
            out = jax.block_until_ready(function(rows[:, 0], rows[:, 1]))
            compile_s = time.perf_counter() - tic
            times = []
            for _ in range(args.repeats):
                tic = time.perf_counter()
                out = jax.block_until_ready(function(rows[:, 0], rows[:, 1]))
                times.append(time.perf_counter() - tic)
            runs[name] = out
            print(f"{kind:8s} {name:14s} {args.motions / min(times):8.1f} records/s (first call {compile_s:.1f} s), "
                  f"all converged: {bool(np.all(out['converged']))}")
        for key in ("base_disp_resultant", "base_shear_ratio_resultant"):
            a, b = (np.asarray(r[key]) for r in runs.values())
            print(f"{kind:8s} {key}: largest relative difference {np.max(np.abs(b / a - 1)):.2e}")


if __name__ == "__main__":
    main()
