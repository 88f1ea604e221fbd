"""Records per second of `monte_carlo` on the flat rigid mass and the Table 2 building (one
component, the B3 set-up), two trees run alternately on the same machine:

    python benchmarks/bench_peak_driver.py OLD_TREE NEW_TREE [--motions 128] [--rounds 3]

Each run is a fresh process (`PYTHONPATH=<tree>`, one JAX device per core); records/s counts
the motions over the wall time less the compilation (`MonteCarloResult.wall_s - compile_s`).
"""

import json
import os
import subprocess
import sys

RUN = """
import json, jax, os
jax.config.update("jax_enable_x64", True)
jax.config.update("jax_num_cpu_devices", os.cpu_count())
from teflon_jax.excitation import StochasticGroundMotion
from teflon_jax.studies import monte_carlo
from teflon_jax.systems import isolated_structure
out = {}
for kind in ("rigid", "building"):
    result = monte_carlo(isolated_structure(kind), StochasticGroundMotion(peak_ground_acceleration=2.94, duration=20.0, time_step=0.01), MOTIONS,
                         key=jax.random.key(1), chunk_size=MOTIONS)
    out[kind] = MOTIONS / (result.wall_s - result.compile_s)
print(json.dumps(out))
"""


def main(argv):
    old, new = argv[0], argv[1]
    motions = int(argv[argv.index("--motions") + 1]) if "--motions" in argv else 128
    rounds = int(argv[argv.index("--rounds") + 1]) if "--rounds" in argv else 3
    rates = {"old": [], "new": []}
    for _ in range(rounds):
        for name, tree in (("old", old), ("new", new)):
            done = subprocess.run([sys.executable, "-c", RUN.replace("MOTIONS", str(motions))], capture_output=True, text=True,
                                  env=dict(os.environ, PYTHONPATH=tree), cwd=tree, check=True)
            rate = json.loads(done.stdout.strip().splitlines()[-1])
            rates[name].append(rate)
            print(name, {k: round(v, 1) for k, v in rate.items()}, flush=True)
    for kind in ("rigid", "building"):
        o = sorted(r[kind] for r in rates["old"])
        n = sorted(r[kind] for r in rates["new"])
        print(f"{kind}: records/s old {o} new {n}; median new/old {n[len(n) // 2] / o[len(o) // 2]:.3f}")


if __name__ == "__main__":
    main(sys.argv[1:])
