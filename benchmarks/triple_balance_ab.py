"""The triple pendulum's planar balance under two versions of its module, alternated in one process.

B7's triple pendulum (`bench_pendulum.TRIPLE`, the rigid mass or the building, 5 ms steps)
runs `biaxial_peaks` of `--lanes` two-component B7 motions over `--duration` seconds in one
`jit(vmap)` call, once with the tree's `teflon_jax/systems/_triple_biaxial.py` and once with
each file given by `--variant PATH[:BALANCE]` (a copy of that module with one change, loaded
in its place; BALANCE one of `BALANCES`, default "newton"), the calls alternated `--repeats`
times after each has compiled. Alternating in one process keeps the machine's load the same
for every version on a shared CPU. Printed: the seconds of each call (least and median), the
rate in forty-second records per second, the largest difference of each peak from the first
version's over its largest value, and whether every step balanced.

Usage: `python benchmarks/triple_balance_ab.py --variant /tmp/copy.py [--variant /tmp/copy.py:secant]
[--lanes 32] [--duration 10] [--structure rigid] [--repeats 8] [--json OUT]`.
"""

import argparse
import importlib.util
import json
import os
import statistics
import time

import jax

jax.config.update("jax_enable_x64", True)

import bench_pendulum as b7  # noqa: E402
import numpy as np  # noqa: E402

from teflon_jax.excitation import sample_two_components, uniform_signal  # noqa: E402

PEAKS = ("base_disp", "base_shear_ratio", "smooth_disp", "smooth_shear")


def _module(path, name):
    """The module at `path`, loaded as a sibling of `teflon_jax.systems._triple_biaxial`."""
    spec = importlib.util.spec_from_file_location(f"teflon_jax.systems._triple_biaxial_{name}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _program(module, balance, structure, duration):
    def one(record):
        system = structure((uniform_signal(record[0], 0.01), uniform_signal(record[1], 0.01)))
        return module.biaxial_peaks(module.BiaxialStructureOnTriple(system.uniaxial, system.ground_y, balance=balance),
                                    duration)

    return jax.jit(jax.vmap(one))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--variant", action="append", required=True, help="PATH[:BALANCE], repeatable")
    parser.add_argument("--lanes", type=int, default=32)
    parser.add_argument("--duration", type=float, default=10.0)
    parser.add_argument("--structure", choices=("rigid", "building"), default="rigid")
    parser.add_argument("--repeats", type=int, default=8)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    tree = os.path.join(os.path.dirname(b7.__file__), "..", "teflon_jax", "systems", "_triple_biaxial.py")
    versions = {"tree": (tree, "newton")}
    for k, variant in enumerate(args.variant):
        path, _, balance = variant.partition(":")
        if not os.path.isfile(path):
            parser.error(f"--variant: no file {path!r}")
        versions[f"{os.path.basename(path)}:{balance or 'newton'}#{k}"] = (path, balance or "newton")
    structure = b7._structure(args.structure, "triple-fp", 2)
    motions = sample_two_components(b7._motions(2), jax.random.key(1), args.lanes)
    programs = {name: _program(_module(path, str(k)), balance, structure, args.duration)
                for k, (name, (path, balance)) in enumerate(versions.items())}
    outs = {name: jax.block_until_ready(run(motions)) for name, run in programs.items()}
    seconds = {name: [] for name in programs}
    for _ in range(args.repeats):
        for name, run in programs.items():
            tic = time.perf_counter()
            jax.block_until_ready(run(motions))
            seconds[name].append(time.perf_counter() - tic)
    first = outs["tree"]
    out = {"structure": args.structure, "lanes": args.lanes, "duration_s": args.duration,
           "load_average_end": os.getloadavg(), "versions": {}}
    for name in programs:
        differences = {peak: float(np.max(np.abs(np.asarray(first[i]) - np.asarray(outs[name][i])))
                                   / np.max(np.abs(np.asarray(first[i])))) for i, peak in enumerate(PEAKS)}
        out["versions"][name] = {"seconds": seconds[name], "least_s": min(seconds[name]),
                                 "median_s": statistics.median(seconds[name]),
                                 "records_per_s_at_median": args.lanes * args.duration / 40.0
                                 / statistics.median(seconds[name]),
                                 "relative_difference": differences, "converged": bool(np.all(outs[name][4]))}
        v = out["versions"][name]
        print(f"{name}: least {v['least_s']:.3f} s, median {v['median_s']:.3f} s, "
              f"{v['records_per_s_at_median']:.1f} records/s; differences "
              + ", ".join(f"{k} {d:.1e}" for k, d in differences.items()) + f"; converged {v['converged']}")
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(out, handle, indent=1)


if __name__ == "__main__":
    main()
