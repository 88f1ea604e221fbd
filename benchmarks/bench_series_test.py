"""The imposed-path test of a triple friction pendulum (`imposed_path_test`), the model the
series fit and diagnose evaluate at every residual: its run time along one axis and in the plane,
under a constant normal load and under one that swings +-30 % at every sample.

Path: 4,001 samples at 5 ms of a sine of amplitude 0.2 m and period 4 s, ramped in over its
first period (in the plane, y = 0.6 x shifted by 1 s). Each case is compiled once, then timed
as the least of `--repeats` calls (the path a jit argument, as in the fit's residual, where
the record travels in the solver's arguments); the cases are alternated `--rounds` times and
the least of each is printed and written as JSON with the machine.

Usage: `python benchmarks/bench_series_test.py [--rounds 3] [--repeats 5] [--json OUT]`.
"""

import argparse
import json
import os
import platform
import time

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np  # noqa: E402

from teflon_jax.bearing import BoucWen, FrictionParameters, TriplePendulum  # noqa: E402
from teflon_jax.systems import imposed_path_test, sampled_path  # noqa: E402

TRIPLE = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                        bottom_capacity=0.4, top_capacity=0.4,
                        inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                        bottom_friction=FrictionParameters(0.07, 0.03, 20.0),
                        top_friction=FrictionParameters(0.11, 0.05, 20.0), hysteresis=BoucWen(1e-4))
WEIGHT = 1e6  # N


def _paths():
    time_ = np.arange(0.0, 20.0 + 1e-9, 0.005)
    x = 0.2 * np.sin(2 * np.pi * time_ / 4.0) * np.minimum(time_ / 4.0, 1.0)
    swinging = WEIGHT * (1.0 + 0.3 * np.sin(2 * np.pi * time_ / 0.7))
    out = {}
    for load_name, load in (("constant N", np.full_like(time_, WEIGHT)), ("N +-30 %", swinging)):
        out[f"1 component, {load_name}"] = sampled_path(time_, x, load)
        out[f"2 components, {load_name}"] = sampled_path(time_, x, load, uy=0.6 * np.roll(x, 200))
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--json", default=None)
    args = parser.parse_args(argv)
    run = jax.jit(imposed_path_test)
    paths = _paths()
    for path in paths.values():  # compile each shape once
        jax.block_until_ready(run(TRIPLE, path).fx)
    best = {name: float("inf") for name in paths}
    for _ in range(args.rounds):
        for name, path in paths.items():
            for _ in range(args.repeats):
                start = time.perf_counter()
                jax.block_until_ready(run(TRIPLE, path).fx)
                best[name] = min(best[name], time.perf_counter() - start)
    machine = {"platform": platform.platform(), "processor": platform.processor() or platform.machine(),
               "cpus": os.cpu_count(), "device": str(jax.devices()[0]), "jax": jax.__version__}
    print(f"triple pendulum, imposed path of 4,001 samples ({machine['device']}, {machine['cpus']} CPUs):")
    for name, seconds in best.items():
        print(f"  {name:28s} {1e3 * seconds:8.1f} ms")
    if args.json:
        with open(args.json, "w") as handle:
            json.dump({"machine": machine, "milliseconds": {k: 1e3 * v for k, v in best.items()}}, handle, indent=1)


if __name__ == "__main__":
    main()
