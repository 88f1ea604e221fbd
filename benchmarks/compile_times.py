"""Compile times of the structures' programs: how long XLA takes to compile one run
(`simulate_history`) of flat sliders in two components on the rigid mass and on Table 2's
building on a plan of four groups, and of a triple pendulum in two components, with the size
of each program (its jaxpr's equations, loops included).

    python benchmarks/compile_times.py [--json OUT]

Run it once per tree and per XLA setting to compare them (both sides on one machine, in
separate processes, alternated); e.g. XLA_FLAGS=--xla_cpu_use_fusion_emitters=false for the
CPU compiler's older fusion emitters, and with --xla_backend_optimization_level=0 beside it
(LLVM's optimisation passes off) as the test suite compiles (tests/conftest.py).
"""

import argparse
import json
import os
import platform
import time

import jax
import numpy as np

from teflon_jax.bearing import BoucWen, FrictionParameters, SlidingBearing, TriplePendulum
from teflon_jax.excitation import uniform_signal
from teflon_jax.studies import bidirectional_isolated_structure
from teflon_jax.systems import building_on_plan, simulate_history

jax.config.update("jax_enable_x64", True)

from engine_numbers import x_record  # noqa: E402  (the plan builders' x record on either tree)

STEP, DURATION = 0.01, 1.5
TIME = np.arange(0.0, DURATION + 1e-9, STEP)
GROUND = (4.0 * np.sin(2 * np.pi * TIME), 3.0 * np.cos(2 * np.pi * 1.3 * TIME))
SLIDERS = SlidingBearing(friction=FrictionParameters(0.08, 0.04, 20.0), hysteresis=BoucWen(1.27e-4))
TRIPLE = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                        bottom_capacity=0.4, top_capacity=0.4, inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                        bottom_friction=FrictionParameters(0.07, 0.03, 20.0),
                        top_friction=FrictionParameters(0.11, 0.05, 20.0), hysteresis=BoucWen(1e-4))


def _systems():
    gx, gy = (uniform_signal(a, STEP) for a in GROUND)
    corners = [[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]]
    return {
        "flat, rigid mass, 2 components": bidirectional_isolated_structure("rigid")((gx, gy)),
        "flat, building on a plan of 4 groups": building_on_plan(
            length_x=20.0, length_y=12.0, centre_of_mass=[10.0, 6.0], positions=corners,
            loads=[672 * 4448.2216152605 / 4] * 4, bearings=SLIDERS, **x_record(gx), ground_y=gy, time_step=STEP,
            isolation_period=2.5),
        "triple pendulum, building, 2 components": bidirectional_isolated_structure(
            "building", isolator=TRIPLE)((gx, gy)),
    }


def _equations(jaxpr):
    count = 0
    for eqn in jaxpr.eqns:
        count += 1
        for value in eqn.params.values():
            for inner in value if isinstance(value, (tuple, list)) else [value]:
                inner = getattr(inner, "jaxpr", inner)
                if hasattr(inner, "eqns"):
                    count += _equations(inner)
    return count


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", help="write the figures here")
    args = parser.parse_args(argv)
    rows = {}
    for name, system in _systems().items():
        def run(s):
            return simulate_history(s, DURATION).displacement

        equations = _equations(jax.make_jaxpr(run)(system).jaxpr)
        start = time.perf_counter()
        lowered = jax.jit(run).lower(system)
        traced = time.perf_counter() - start
        start = time.perf_counter()
        lowered.compile()
        compiled = time.perf_counter() - start
        rows[name] = {"equations": equations, "trace_and_lower_s": round(traced, 2), "compile_s": round(compiled, 2)}
        print(f"{name}: {equations} equations, traced and lowered in {traced:.2f} s, compiled in {compiled:.2f} s")
    record = {"machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
              "jax": jax.__version__, "xla_flags": os.environ.get("XLA_FLAGS", ""), "programs": rows}
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(record, handle, indent=1)


if __name__ == "__main__":
    main()
