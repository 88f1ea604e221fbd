"""The cost of one evaluation of B7's triple pendulum sliders' planar forces with their exact
2 x 2 blocks (`teflon_jax.elements.balance_forces(..., blocks=True)`: Park's update and slope
and the force law's forward mode, what each Newton trial of the two-component balance costs),
vmapped over `--members` random states, in this tree.

`python benchmarks/force_evaluation.py [--members 512] [--repeats 9]` prints the best and the
median time of one evaluation [us] over `--repeats` timings of 200 evaluations each (compiled
once). Run it under each version (`PYTHONPATH=/path/to/other/checkout`) alternately; the best
time is the least disturbed by other processes on a shared machine.
"""

import argparse
import os
import sys
import time

import jax
import jax.numpy as jnp

jax.config.update("jax_enable_x64", True)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bench_pendulum as b7  # noqa: E402

from teflon_jax.elements import balance_forces  # noqa: E402

EVALUATIONS = 200


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--members", type=int, default=512)
    parser.add_argument("--repeats", type=int, default=9)
    args = parser.parse_args()
    if args.members < 1 or args.repeats < 1:
        parser.error("--members, --repeats: at least 1.")
    keys = jax.random.split(jax.random.key(0), 3)
    z0 = jax.random.uniform(keys[0], (args.members, 3, 2), minval=-0.7, maxval=0.7)
    increment = jax.random.normal(keys[1], (args.members, 3, 2)) * 2e-4
    start = jax.random.normal(keys[2], (args.members, 3, 2)) * 0.02

    def evaluate(z, s, d):
        p = {"pendulum": b7.TRIPLE, "W": 1e5, "N": 1e5, "s0": s, "z0": z}
        return balance_forces(p, d, b7.TIME_STEP, blocks=True)

    def loop(z, s, d):  # the evaluations in one compiled loop, each depending on the last
        def body(_, carry):
            out = jax.vmap(evaluate)(z, s, d + carry * 1e-30)
            return carry + sum(jnp.sum(o) for o in jax.tree.leaves(out)) * 0
        return jax.lax.fori_loop(0, EVALUATIONS, body, 0.0)

    compiled = jax.jit(loop).lower(z0, start, increment).compile()
    compiled(z0, start, increment).block_until_ready()
    times = []
    for _ in range(args.repeats):
        clock = time.perf_counter()
        compiled(z0, start, increment).block_until_ready()
        times.append((time.perf_counter() - clock) / EVALUATIONS * 1e6)
    print(f"forces with blocks, {args.members} members: best {min(times):.0f} us, median "
          f"{sorted(times)[len(times) // 2]:.0f} us per evaluation (load {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
