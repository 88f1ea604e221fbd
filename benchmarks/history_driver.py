"""The history driver on flat sliders, timed under this checkout (run it under two checkouts to
compare them: `PYTHONPATH=/path/to/other/checkout`).

`simulate_history` of the rigid mass and the Table 2 building on Table 1's flat sliders, under
one and two horizontal components of the same stochastic motions, vmapped over `--motions`
motions of `--duration` s (the suites' shape: every step kept), compiled once, then timed
(best of `--repeats`). Prints one JSON line per case: compile and run seconds, records/s, the
machine, and the histories' checksum (the sum of the base displacements), which two versions
that keep the same numbers share to rounding.

    python benchmarks/history_driver.py --motions 16 --duration 20 --repeats 3
"""

import argparse
import json
import os
import platform
import time

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

import teflon_jax  # noqa: E402
from teflon_jax.excitation import StochasticGroundMotion, sample, uniform_signal  # noqa: E402
from teflon_jax.studies import bidirectional_isolated_structure  # noqa: E402
from teflon_jax.systems import isolated_structure, simulate_history  # noqa: E402
from teflon_jax.units import STANDARD_GRAVITY  # noqa: E402

RECORD_STEP = 0.01


def _records(motions: int, duration: float):
    model = StochasticGroundMotion(peak_ground_acceleration=0.4 * STANDARD_GRAVITY, duration=duration,
                                   time_step=RECORD_STEP)
    x = np.asarray(sample(model, jax.random.PRNGKey(1), motions))
    y = 0.8 * np.asarray(sample(model, jax.random.PRNGKey(2), motions))
    return x, y


def _function(kind: str, components: int, duration: float):
    build = isolated_structure(kind) if components == 1 else bidirectional_isolated_structure(kind)

    def one(ax, ay):
        grounds = uniform_signal(ax, RECORD_STEP), uniform_signal(ay, RECORD_STEP)
        system = build(grounds[0]) if components == 1 else build(grounds)
        response = simulate_history(system, duration, throw=False)
        return jnp.sum(response.displacement[:, 0]), response.succeeded

    return jax.jit(jax.vmap(one))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--motions", type=int, default=16)
    parser.add_argument("--duration", type=float, default=20.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--label", default=os.path.dirname(os.path.dirname(teflon_jax.__file__)))
    args = parser.parse_args(argv)
    x, y = _records(args.motions, args.duration)
    for kind in ("rigid", "building"):
        for components in (1, 2):
            function = _function(kind, components, args.duration)
            start = time.perf_counter()
            checksum, succeeded = jax.block_until_ready(function(x, y))
            compile_s = time.perf_counter() - start
            runs = []
            for _ in range(args.repeats):
                start = time.perf_counter()
                jax.block_until_ready(function(x, y))
                runs.append(time.perf_counter() - start)
            print(json.dumps({"code": args.label, "structure": kind, "components": components,
                              "motions": args.motions, "duration_s": args.duration,
                              "first_call_s": round(compile_s, 2), "run_s": round(min(runs), 3),
                              "records_per_s": round(args.motions / min(runs), 1),
                              "all_balanced": bool(np.all(succeeded)),
                              "checksum_m": float(np.sum(checksum)), "machine": platform.processor() or
                              platform.machine(), "cpus": os.cpu_count(),
                              "load_average": round(os.getloadavg()[0], 1)}), flush=True)


if __name__ == "__main__":
    main()
