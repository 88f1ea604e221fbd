"""The design's derivatives: `jax.jacfwd` against `forward_jacobian`, in one and two components.

`teflon-jax design` differentiates the mean smoothed peaks over a vmapped set of motions in
each design variable (T_b and the contact pressure here). `jax.jacfwd` pushes both tangents at
once (a second `vmap`); `studies._forward_jacobian.forward_jacobian` takes them one after the
other (`lax.map` of `jax.jvp`). Both are compiled once and timed on a second call, alternated
`--repeats` times, on the design's own structures (`cli._design`'s settings: 2.5 ms steps, the
balance to rounding; one component with Newmark's rule and no turning-point split), on
`--motions` Clough-Penzien motions of `--duration`; the largest difference between the two
Jacobians is printed with the times and written as JSON with the machine.

Usage: `python benchmarks/design_derivatives.py [--motions 2] [--duration 2] [--repeats 1]
[--components 1 2] [--json OUT]`.
"""

import argparse
import json
import os
import platform
import time

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402

from teflon_jax.excitation import (  # noqa: E402
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    sample,
    sample_two_components,
)
from teflon_jax.studies import bidirectional_isolated_structure, expected_response  # noqa: E402
from teflon_jax.studies._forward_jacobian import forward_jacobian  # noqa: E402
from teflon_jax.systems import isolated_structure  # noqa: E402
from teflon_jax.units import PSI, STANDARD_GRAVITY  # noqa: E402

SETTINGS = {"ptfe": "UF", "isolation_damping": 0.05, "pressure": 1000 * PSI, "isolation_period": 2.0,
            "time_step": 0.0025, "newton_tolerance": 0.0}
DESIGN = {"isolation_period": 2.5, "pressure": 1400 * PSI}


def _problem(components, motions, duration):
    model = StochasticGroundMotion(peak_ground_acceleration=0.3 * STANDARD_GRAVITY, duration=duration,
                                   time_step=0.01, rise_time=min(2.0, duration / 4),
                                   strong_motion_duration=duration / 2)
    if components == 2:
        records = sample_two_components(TwoComponentGroundMotion(model), jax.random.key(0), motions)
        return bidirectional_isolated_structure("rigid", **SETTINGS), records
    structure = isolated_structure("rigid", split_at_turn=False, linear_rule="newmark", **SETTINGS)
    return structure, sample(model, jax.random.key(0), motions)


def _timed(function, x):
    """(seconds of compiling, seconds of the second call, its value)."""
    start = time.perf_counter()
    compiled = jax.jit(function).lower(x).compile()
    compiled_at = time.perf_counter()
    jax.block_until_ready(compiled(x))
    again = time.perf_counter()
    value = jax.block_until_ready(compiled(x))
    return compiled_at - start, time.perf_counter() - again, value


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--motions", type=int, default=2)
    parser.add_argument("--duration", type=float, default=2.0, help="seconds of each motion")
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--components", type=int, nargs="+", default=[1, 2], choices=(1, 2))
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    x = {name: jnp.asarray(value) for name, value in DESIGN.items()}
    out = {"machine": {"platform": platform.platform(), "processor": platform.processor(),
                       "cpus": os.cpu_count(), "devices": [d.device_kind for d in jax.devices()],
                       "load_average": os.getloadavg()},
           "motions": args.motions, "duration_s": args.duration, "runs": []}
    for components in args.components:
        structure, records = _problem(components, args.motions, args.duration)

        def response(x, structure=structure, records=records):
            r = expected_response(structure, x, records, 0.01)
            return {"shear": r["shear"], "disp": r["disp"]}

        for _ in range(args.repeats):
            results = {}
            for name, make in (("jacfwd", jax.jacfwd), ("forward_jacobian", forward_jacobian)):
                compile_s, run_s, value = _timed(make(response), x)
                results[name] = value
                out["runs"].append({"components": components, "method": name, "compile_s": compile_s,
                                    "run_s": run_s})
                print(f"{components} component(s), {name}: compile {compile_s:.1f} s, run {run_s:.3f} s", flush=True)
            gap = max(float(abs(results["jacfwd"][k][n] - results["forward_jacobian"][k][n])
                            / abs(results["jacfwd"][k][n])) for k in ("shear", "disp") for n in DESIGN)
            out["runs"][-1]["largest_relative_difference"] = gap
            print(f"{components} component(s): largest relative difference {gap:.2g}")
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(out, handle, indent=2)


if __name__ == "__main__":
    main()
