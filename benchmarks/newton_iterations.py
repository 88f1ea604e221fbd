"""Newton steps per time step of the triple pendulum under two components, per motion and per chunk.

A vectorised chunk of motions iterates each step's planar balance as long as its slowest
motion does, so the chunk's rate depends on the largest count across the chunk, not on the
mean. This script runs B7's triple pendulum (`bench_pendulum.TRIPLE`, the rigid mass or the
building, B7's forty-second two-component motions, 5 ms steps) on `--motions` motions in one
vectorised call and reports the mean count per motion and step, the mean over steps of the
largest count across groups of 64, 1,024, 16,384 motions and the whole call, both
histograms, and the seconds of a second call on new motions (the first compiles). The counts
are the line-searched Newton steps of `planar_newton` (each one evaluation of the sliders'
forces with their exact blocks), read by putting them where the step's convergence flag goes;
nothing else changes.

Usage: `python benchmarks/newton_iterations.py [--structure rigid] [--motions 64] [--json OUT]`.
"""

import argparse
import json
import platform
import time

import jax

jax.config.update("jax_enable_x64", True)

import bench_pendulum as b7  # noqa: E402
import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

from teflon_jax.elements import _balance as balance  # noqa: E402
from teflon_jax.excitation import sample_two_components, uniform_signal  # noqa: E402
from teflon_jax.systems import _series as series  # noqa: E402

DURATION = 40.0


def _counting(dt, iterations, p, guess, tolerance, secant=False):
    d, _, taken, evaluation = balance.planar_iteration({**p, "dt": dt}, guess, tolerance, iterations, secant)
    return d, taken, evaluation


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--structure", choices=("rigid", "building"), default="rigid")
    parser.add_argument("--motions", type=int, default=64)
    parser.add_argument("--json", default=None, help="write the figures here")
    args = parser.parse_args()
    balance.balance = _counting
    factory = b7._structure(args.structure, "triple-fp", 2)
    motion = b7._motions(2)
    dt = float(motion.model.time_step)
    n_steps = round(DURATION / b7.TIME_STEP)

    def counts(record):
        system = factory((uniform_signal(record[0], dt), uniform_signal(record[1], dt)))
        ground = jax.vmap(system.ground)(jnp.arange(n_steps + 1) * b7.TIME_STEP)
        matrices = system.step_matrices()

        def body(carry, grounds):
            x1, isolator1, taken, _ = series.series_step(system, *carry, grounds[0], grounds[1], matrices, None)
            return (x1, isolator1), taken.astype(jnp.int16)

        start = (jnp.zeros((2, 2 * system.mass.shape[-1]), system.mass.dtype), series.initial_isolator(system))
        return jax.lax.scan(body, start, (ground[:-1], ground[1:]))[1]

    run = jax.jit(jax.vmap(counts))
    run(sample_two_components(motion, jax.random.key(1), args.motions)).block_until_ready()
    tic = time.perf_counter()
    taken = np.asarray(run(sample_two_components(motion, jax.random.key(2), args.motions)))
    seconds = time.perf_counter() - tic
    groups = [g for g in (64, 1024, 16384) if g < args.motions] + [args.motions]
    largest = {str(g): float(np.mean([taken[i:i + g].max(0).mean() for i in range(0, args.motions - g + 1, g)]))
               for g in groups}
    out = {"machine": platform.machine(), "device": str(jax.devices()[0].device_kind), "structure": args.structure,
           "motions": args.motions, "steps": n_steps, "seconds": seconds,
           "seconds_per_newton_step": seconds / (n_steps * largest[str(args.motions)]),
           "mean_per_motion": float(taken.mean()), "mean_largest_over_group": largest,
           "histogram_per_motion": np.bincount(taken.ravel()).tolist(),
           "histogram_largest_over_call": np.bincount(taken.max(0)).tolist()}
    print(json.dumps({k: v for k, v in out.items() if not k.startswith("histogram")}, indent=1))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
