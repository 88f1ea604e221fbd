"""B7's triple pendulum under two ground components, number for number between two versions.

`python benchmarks/triple_numbers.py dump OUT.npz [--motions 32]` runs B7's structures
(`bench_pendulum.py`: the rigid mass and the Table 2 building on `TRIPLE`, two components,
the Monte Carlo tolerance) under B7's own motions: the Monte Carlo's peaks of `--motions`
motions, and the whole history (displacements, velocities, accelerations, bearing force,
sliders, Z) of the first `--histories` of them. Run it under each version
(`PYTHONPATH=/path/to/other/checkout`), then `python benchmarks/triple_numbers.py compare
OLD.npz NEW.npz` prints, per array, the largest difference over the largest value and exits 1
where one exceeds `--tolerance` (1e-9).
"""

import argparse
import os
import sys

import jax
import numpy as np

jax.config.update("jax_enable_x64", True)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bench_pendulum as b7  # noqa: E402

from teflon_jax.excitation import uniform_signal  # noqa: E402
from teflon_jax.studies import monte_carlo, monte_carlo_motion  # noqa: E402
from teflon_jax.systems import simulate_history  # noqa: E402

PEAKS = ("base_disp", "base_shear_ratio", "smooth_base_disp", "smooth_base_shear_ratio", "converged")
HISTORIES = ("displacement", "velocity", "total_acceleration", "bearing_force", "slider", "z")


def dump(path, motions: int, histories: int) -> None:
    model = b7._motions(2)
    out = {}
    for kind in ("rigid", "building"):
        structure = b7._structure(kind, "triple-fp", 2)
        result = monte_carlo(structure, model, motions, key=jax.random.key(1), chunk_size=motions)
        for name in PEAKS:
            out[f"{kind}-peak-{name}"] = np.asarray(getattr(result, name))
        for m in range(histories):  # the Monte Carlo's own motions (x, y)
            ground = np.asarray(monte_carlo_motion(model, jax.random.key(1), m))
            pair = tuple(uniform_signal(ground[c], model.model.time_step) for c in range(2))
            response = jax.jit(simulate_history, static_argnums=1)(structure(pair), 20.0)
            for name in HISTORIES:
                out[f"{kind}-motion{m}-{name}"] = np.asarray(getattr(response, name))
    np.savez(path, **out)
    print(f"{path}: {len(out)} arrays")


def compare(old_path, new_path, tolerance: float) -> int:
    old, new = np.load(old_path), np.load(new_path)
    worst = 0.0
    for key in old.files:
        a, b = old[key].astype(float), new[key].astype(float)
        scale = max(np.max(np.abs(a)), np.finfo(float).tiny)
        difference = np.max(np.abs(a - b)) / scale
        worst = max(worst, difference)
        print(f"{key}: {difference:.2e}{'  EXCEEDS' if difference > tolerance else ''}")
    print(f"largest relative difference {worst:.2e} (tolerance {tolerance:.0e})")
    return int(worst > tolerance or set(old.files) != set(new.files))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    d = commands.add_parser("dump")
    d.add_argument("out")
    d.add_argument("--motions", type=int, default=32)
    d.add_argument("--histories", type=int, default=2)
    c = commands.add_parser("compare")
    c.add_argument("old")
    c.add_argument("new")
    c.add_argument("--tolerance", type=float, default=1e-9)
    args = parser.parse_args()
    if args.command == "dump":
        if args.histories > args.motions or args.motions < 1:
            parser.error("--histories: at most --motions, which is at least 1.")
        dump(args.out, args.motions, args.histories)
    else:
        sys.exit(compare(args.old, args.new, args.tolerance))


if __name__ == "__main__":
    main()
