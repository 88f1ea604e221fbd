"""The design's smooth peaks and their gradients in one tree, to compare with another's:
`PYTHONPATH=<tree> python benchmarks/design_smooth_numbers.py OUT.json`, then
`python benchmarks/design_smooth_numbers.py compare A.json B.json` (largest relative
difference of each value). `expected_response` (rigid mass and building, flat sliders and a
triple pendulum) and its forward-mode gradient in pressure and isolation period (flat) or
radius scale (triple), and `percentile_disp_gradient_check` on the rigid mass."""

import json
import sys
from pathlib import Path

import jax
import jax.numpy as jnp

jax.config.update("jax_enable_x64", True)

DT = 0.01


def dump(path):
    from teflon_jax.excitation import StochasticGroundMotion, sample
    from teflon_jax.studies import expected_response, percentile_disp_gradient_check
    from teflon_jax.systems import isolated_structure
    from teflon_jax.units import PSI

    model = StochasticGroundMotion(peak_ground_acceleration=2.94, duration=6.0, time_step=DT,
                                    strong_motion_duration=3.0)
    records = sample(model, jax.random.key(7), 3)
    out = {}
    for kind in ("rigid", "building"):
        structure = isolated_structure(kind)
        design = {"pressure": jnp.asarray(2000 * PSI), "isolation_period": jnp.asarray(2.0)}

        def response(x, structure=structure):
            return expected_response(structure, x, records, DT)

        values = jax.jit(response)(design)
        gradient = jax.jit(jax.jacfwd(lambda x, f=response: {k: f(x)[k] for k in ("shear", "disp")}))(design)
        out[kind] = {"values": {k: float(v) for k, v in values.items()},
                     "gradient": {f"{a}/{b}": float(v) for a, row in gradient.items() for b, v in row.items()}}
    check = percentile_disp_gradient_check(isolated_structure("rigid"), {"pressure": 2000 * PSI,
                                                                        "isolation_period": 2.0}, records, DT)
    out["percentile_check"] = {"value": check["value"], **{f"gradient/{k}": v for k, v in check["gradient"].items()}}
    Path(path).write_text(json.dumps(out, indent=1))


def compare(a, b):
    def flat(tree, prefix=""):
        for k, v in tree.items():
            if isinstance(v, dict):
                yield from flat(v, f"{prefix}{k}/")
            else:
                yield f"{prefix}{k}", float(v)

    first, second = dict(flat(json.loads(Path(a).read_text()))), dict(flat(json.loads(Path(b).read_text())))
    for key in first:
        x, y = first[key], second[key]
        print(f"{key}: {x:.15g} {y:.15g} rel {abs(x - y) / max(abs(x), abs(y), 1e-300):.2e}")


if __name__ == "__main__":
    if sys.argv[1] == "compare":
        compare(sys.argv[2], sys.argv[3])
    else:
        dump(sys.argv[1])
