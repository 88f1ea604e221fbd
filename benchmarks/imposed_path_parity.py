"""The imposed-path test of every isolator before and after one front end: the same numbers.

Runs a fixed set of isolators (flat sliders: hysteretic with breakaway, Coulomb, heated, a
shape that needs a diffrax solve; a single, double and triple friction pendulum) along a sine
motion, the same sine as a `SampledPath`, a figure eight and the displacement of a recorded
test (the friction damper of `../shared/data/external/friction_damper_brfd_arts_lab`), with
`imposed_path_test` where the tree has it, else with the two front ends it replaces
(`simulate_bearing_test`, `respond_along_path`, `force_along_path`), and writes the forces
and Z histories to an `.npz`. Two trees' files are compared with `--compare`:

    PYTHONPATH=/work/main python benchmarks/imposed_path_parity.py --out old.npz
    PYTHONPATH=. python benchmarks/imposed_path_parity.py --out new.npz
    python benchmarks/imposed_path_parity.py --compare old.npz new.npz   # <= 1e-9 relative
"""

import argparse
import json
import pathlib
import sys

import jax

jax.config.update("jax_enable_x64", True)

import diffrax  # noqa: E402
import numpy as np  # noqa: E402

import teflon_jax.systems as systems  # noqa: E402
from teflon_jax.bearing import (  # noqa: E402
    BoucWen,
    FrictionalHeating,
    FrictionParameters,
    SlidingBearing,
    coulomb_friction,
    single_pendulum,
)
from teflon_jax.excitation import FigureEightMotion, SineMotion, tabulated_motion  # noqa: E402
from teflon_jax.formats import load_isolator  # noqa: E402

HERE = pathlib.Path(__file__).resolve().parent
RECORD = (HERE.parents[1] / "shared" / "data" / "external" / "friction_damper_brfd_arts_lab"
          / "1Hz30lbtension1amplitude.json")
INCH = 0.0254
W = 1.0e6  # [N]
TOLERANCE = 1e-9

FLAT = SlidingBearing(friction=FrictionParameters(0.12, 0.07, 25.0), hysteresis=BoucWen(2.5e-4),
                      breakaway_ratio=1.3)
COULOMB = SlidingBearing(friction=coulomb_friction(0.08), hysteresis=BoucWen(2.5e-4))
HEATED = SlidingBearing(friction=FrictionParameters(0.12, 0.07, 25.0), hysteresis=BoucWen(2.5e-4),
                        heating=FrictionalHeating(contact_area=0.01))
ETA3 = SlidingBearing(friction=FrictionParameters(0.12, 0.07, 25.0),
                      hysteresis=BoucWen(2.5e-4, A=1.0, beta=0.1, gamma=0.9, eta=3.0))
SINGLE = single_pendulum(SlidingBearing(friction=FrictionParameters(0.06, 0.03, 20.0),
                                        hysteresis=BoucWen(1e-4)), radius=2.2, capacity=0.4)
DOUBLE = load_isolator(HERE / "double_isolator.json")
TRIPLE = load_isolator(HERE / "triple_isolator.json")
SINE = SineMotion(amplitude=0.2, frequency=0.5, cycles=2)
SMALL_SINE = SineMotion(amplitude=INCH, frequency=1.0, cycles=2)
EIGHT = FigureEightMotion(amplitude=INCH, angular_frequency=2.0)


def recorded():
    """(time [s], displacement [m]) of the friction damper's test, every 4th of its samples."""
    rows = np.asarray(json.loads(RECORD.read_text())["data"])[::4]
    return rows[:, 0] - rows[0, 0], rows[:, 1] * INCH


def sine_samples(n=401):
    time = np.linspace(0.0, SINE.duration, n)
    return time, np.asarray(jax.vmap(SINE.displacement)(time))[:, 0]


def run(isolator, path, normal_load=None, **options):
    """The test by the tree's front end: `imposed_path_test`, or the one it replaces."""
    if hasattr(systems, "imposed_path_test"):
        return systems.imposed_path_test(isolator, path, normal_load, **options)
    if isinstance(path, systems.SampledPath):
        if "solver" in options:
            force, z, _ = systems.force_along_path(isolator, path.time, path.ux, path.normal_load, **options)
            return {"fx": force, "z": z}
        return systems.respond_along_path(isolator, path, **options)
    return systems.simulate_bearing_test(isolator, path, normal_load, **options)


def cases():
    """(name, result) of every isolator on every path."""
    t_rec, u_rec = recorded()
    t_sine, u_sine = sine_samples()
    on_record = systems.sampled_path(t_rec, u_rec, W)
    on_sine = systems.sampled_path(t_sine, u_sine, W)
    record_motion = tabulated_motion(t_rec, u_rec)
    for name, flat in (("flat", FLAT), ("coulomb", COULOMB), ("heated", HEATED)):
        yield f"{name}/sine-motion", run(flat, SMALL_SINE, W, samples_per_cycle=300)
        yield f"{name}/record-motion", run(flat, record_motion, W)
        yield f"{name}/record-path", run(flat, on_record)
    yield "flat/figure-eight", run(FLAT, EIGHT, W, samples_per_cycle=300)
    yield "flat/sine-path-z0", run(FLAT, on_sine, z0=0.5, z_peak0=1.0)
    yield "eta3/sine-motion", run(ETA3, SMALL_SINE, W, samples_per_cycle=300)
    yield "eta3/record-path", run(ETA3, on_record, solver=diffrax.Tsit5())
    for name, series in (("single", SINGLE), ("double", DOUBLE), ("triple", TRIPLE)):
        yield f"{name}/sine-motion", run(series, SINE, W, samples_per_cycle=200)
        yield f"{name}/sine-path", run(series, on_sine)
        yield f"{name}/record-path", run(series, on_record)
    yield "single/record-path-end", run(SINGLE, on_record, friction_velocity="end")


def histories(result) -> dict:
    """Forces and Z of a result, as float arrays."""
    get = result.get if isinstance(result, dict) else lambda key: getattr(result, key, None)
    out = {"fx": get("fx"), "z": get("z")}
    if get("fy") is not None:
        out["fy"] = get("fy")
    return {key: np.asarray(value, dtype=float) for key, value in out.items()}


def compare(old_file, new_file) -> int:
    old, new = np.load(old_file), np.load(new_file)
    worst, failed = 0.0, []
    for key in sorted(old.files):
        a, b = old[key], new[key]
        if a.shape != b.shape and a.size == b.size:
            b = b.reshape(a.shape)
        if a.shape != b.shape:
            a = a[..., 0] if a.ndim > b.ndim else a
            b = b[..., 0] if b.ndim > a.ndim else b
        scale = max(float(np.max(np.abs(a))), 1e-300)
        error = float(np.max(np.abs(a - b))) / scale
        worst = max(worst, error)
        print(f"{key:34s} {a.size:6d} samples  max |new - old| / max |old| = {error:.2e}")
        if not error <= TOLERANCE:
            failed.append(key)
    print(f"{len(old.files)} histories, worst {worst:.2e}; {'FAILED: ' + ', '.join(failed) if failed else 'all <= 1e-9'}")
    return 1 if failed or not set(old.files) <= set(new.files) else 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="write this tree's histories to this .npz")
    parser.add_argument("--compare", nargs=2, metavar=("OLD", "NEW"), help="compare two .npz files")
    args = parser.parse_args(argv)
    if args.compare:
        return compare(*args.compare)
    if not args.out:
        parser.error("give --out FILE or --compare OLD NEW")
    arrays = {f"{name}:{key}": value for name, result in cases() for key, value in histories(result).items()}
    np.savez(args.out, **arrays)
    print(f"wrote {args.out}: {len(arrays)} histories")
    return 0


if __name__ == "__main__":
    sys.exit(main())
