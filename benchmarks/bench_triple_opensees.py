"""The triple friction pendulum against OpenSees' `TripleFrictionPendulum` element: the rigid mass
and the Table 2 building under the PEER RSN6 record (El Centro 1940, 180 component, first
30 s; scaled by 1 and 2), one horizontal direction, at a 2.5 ms step on both sides.

Cases (`CASES`):

- "coulomb-0.1mm": constant friction (below) at Y = uy = 0.1 mm, where the element converges
  on this record at x1 only.
- "coulomb": constant friction on every surface (0.02 inner, 0.06 bottom, 0.10 top), the laws
  alike; Y = uy = 0.5 mm. What differs is only the stick-slip corner (Bouc-Wen's rounded one,
  stiffness mu_e W / Y, against the element's elastic-plastic one, 3 mu_inner W / uy).
- "coulomb-1mm": the same at Y = uy = 1 mm, the corner's share of "eq1".
- "eq1": Eq. 1 on every surface (f_max 0.03, 0.08, 0.12; delta_f 0.015, 0.03, 0.05; a = 20 s/m)
  against `VelDependent`, Y = uy = 1 mm (the element does not converge with VelDependent at
  uy = 0.1 or 0.5 mm on this record). The laws differ in form: the element takes mu at the
  slider's mean velocity of its previous iteration, teflon-jax at the step's own, and f_min
  while a slider's Z still points back after a reversal (`_sliders.slider_forces`).

The bearing: inner effective radius 0.3 m, outer 2.1 m (both), capacities 0.05 m and 0.3 m
(the outer ones alike, so that both programs give the inner slider the same travel).

Each case also runs under both components (180 along x, 270 along y, x1): resultant peaks,
the base shear as the resultant force on all masses over W.

Usage: `python benchmarks/bench_triple_opensees.py [--json OUT]`; prints each peak and the
relative difference (teflon-jax over OpenSees, minus 1).
"""

import argparse
import json
import pathlib
import sys

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np  # noqa: E402

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from _opensees_triple import opensees_triple_structure, triple_values  # noqa: E402

from teflon_jax.bearing import BoucWen, FrictionParameters, TriplePendulum, coulomb_friction  # noqa: E402
from teflon_jax.excitation import uniform_signal  # noqa: E402
from teflon_jax.formats import read_at2  # noqa: E402
from teflon_jax.systems import (  # noqa: E402
    peak_response,
    simulate_history,
    triple_structure,
)
from teflon_jax.units import STANDARD_GRAVITY  # noqa: E402

TIME_STEP = 0.0025
DURATION = 30.0
RECORD = pathlib.Path("elcentro1940_peer_nga_rsn6") / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
RECORD_Y = RECORD.with_name("RSN6_IMPVALL.I_I-ELC270-hor2.AT2")
CASES = {"coulomb": ("coulomb", 5e-4), "coulomb-0.1mm": ("coulomb", 1e-4), "coulomb-1mm": ("coulomb", 1e-3), "eq1": ("eq1", 1e-3)}
"""Name: (friction law, Y = uy [m])."""


def bearing(law: str, yield_disp: float) -> TriplePendulum:
    """The compared bearing (module docstring) with the friction `law` "coulomb" or "eq1"."""
    if law == "coulomb":
        friction = [coulomb_friction(mu) for mu in (0.02, 0.06, 0.10)]
    else:
        friction = [FrictionParameters(0.03, 0.015, 20.0), FrictionParameters(0.08, 0.03, 20.0),
                    FrictionParameters(0.12, 0.05, 20.0)]
    return TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                          bottom_capacity=0.3, top_capacity=0.3, inner_friction=friction[0],
                          bottom_friction=friction[1], top_friction=friction[2],
                          hysteresis=BoucWen(yield_disp))


def record(folder: pathlib.Path, scale: float, path=RECORD):
    """(acceleration [m/s^2] of the first `DURATION` s times `scale`, its step [s])."""
    motion = read_at2(folder / path)
    dt = float(motion.time_step)
    return scale * np.asarray(motion.acceleration, float)[:int(round(DURATION / dt)) + 1], dt


def teflon_peaks(kind, triple, acc, dt, weight=1.0e6):
    """(peak |base displacement| [m], peak base shear over the weight above the isolator)."""
    system = triple_structure(kind, triple, uniform_signal(acc, dt), time_step=TIME_STEP, weight=weight)
    response = jax.jit(simulate_history, static_argnums=1)(system, (len(acc) - 1) * dt)
    if not bool(np.all(response.converged)):
        raise RuntimeError("teflon-jax: a step's sliders did not balance.")
    m, a = np.asarray(system.mass), np.asarray(response.total_acceleration)
    above = slice(0, 1) if m.size == 1 else slice(1, None)
    shear = a[:, above] @ m[above] / (m[above].sum() * STANDARD_GRAVITY)
    return float(np.max(np.abs(response.displacement[:, 0]))), float(np.max(np.abs(shear)))


def compare(kind, case, scale, folder):
    """teflon-jax and OpenSees peaks of one case: a dict with both and their differences."""
    law, yield_disp = CASES[case]
    triple = bearing(law, yield_disp)
    acc, dt = record(folder, scale)
    ours = teflon_peaks(kind, triple, acc, dt)
    disp, shear, wall = opensees_triple_structure(kind, acc, dt, triple_values(triple), uy=yield_disp,
                                                  time_step=TIME_STEP)
    return {"kind": kind, "case": case, "scale": scale, "teflon_jax": ours, "opensees": (disp, shear),
            "difference": (ours[0] / disp - 1, ours[1] / shear - 1), "opensees_wall_s": wall}


def teflon_peaks_two(kind, triple, acc, acc_y, dt, weight=1.0e6):
    """Resultant peaks (displacement [m], force on the masses over W) under both components."""
    along_x = triple_structure(kind, triple, uniform_signal(acc, dt), time_step=TIME_STEP, weight=weight)
    system = along_x.with_y_component(uniform_signal(acc_y, dt))
    peaks = jax.jit(peak_response, static_argnums=1)(system, (len(acc) - 1) * dt)
    disp, shear, ok = peaks.base_disp, peaks.base_shear_ratio, peaks.converged
    if not bool(ok):
        raise RuntimeError("teflon-jax: a step's sliders did not balance.")
    return float(disp), float(shear)


def compare_two(kind, case, scale, folder):
    """`compare` under both components of RSN6 (180 along x, 270 along y)."""
    law, yield_disp = CASES[case]
    triple = bearing(law, yield_disp)
    (acc, dt), (acc_y, _) = record(folder, scale), record(folder, scale, RECORD_Y)
    ours = teflon_peaks_two(kind, triple, acc, acc_y, dt)
    disp, shear, wall = opensees_triple_structure(kind, acc, dt, triple_values(triple), uy=yield_disp,
                                                  time_step=TIME_STEP, acc_y=acc_y)
    return {"kind": kind, "case": case, "scale": scale, "components": 2, "teflon_jax": ours,
            "opensees": (disp, shear), "difference": (ours[0] / disp - 1, ours[1] / shear - 1),
            "opensees_wall_s": wall}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", type=pathlib.Path,
                        default=pathlib.Path(__file__).resolve().parents[2] / "shared" / "data" / "external")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    rows = []
    for case in CASES:
        for kind in ("rigid", "building"):
            for scale, two in ((1.0, False), (2.0, False), (1.0, True)):
                try:
                    row = (compare_two if two else compare)(kind, case, scale, args.data)
                except RuntimeError as error:  # the element's steps that do not converge
                    print(f"{case:12s} {kind:8s} x{scale:g}{' x+y' if two else ''}: {error}")
                    continue
                rows.append(row)
                d, s = row["difference"]
                print(f"{case:12s} {kind:8s} x{scale:g}{' x+y' if two else ''}: displacement {row['teflon_jax'][0]:.4f} / "
                      f"{row['opensees'][0]:.4f} m ({100 * d:+.2f} %), base shear {row['teflon_jax'][1]:.4f} / "
                      f"{row['opensees'][1]:.4f} ({100 * s:+.2f} %)")
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(rows, indent=2))


if __name__ == "__main__":
    main()
