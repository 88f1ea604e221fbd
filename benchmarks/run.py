"""teflon-jax benchmarks, side by side with OpenSees, in one run on one machine.

    python benchmarks/run.py [--quick] [--json OUT.json] [--skip B3,B4]

B1  one rigid mass on UF/1000 psi bearings under El Centro (40 s): seconds per record for
    teflon-jax (RiccatiNewmark, 5 ms steps) and OpenSees (flatSliderBearing + VelDependent,
    Newmark + modified Newton, the same 5 ms steps), and each one's peak-displacement error
    against a converged reference (diffrax Tsit5, rtol 1e-10, on the same Bouc-Wen model).
B2  the whole Fig. 11 set (2 records x Tb 0.2-4.0 s x 3 pressures + the linear system);
    the comparison with OpenSees per case kind (sliding: both without breakaway; linear).
B3  Monte Carlo throughput of stochastic 40 s motions (benchmarks/bench_scale.py), sharded
    over one JAX CPU device per core (`--cpu-devices`), against OpenSees in one process and in
    one process per core.
B4  fit time of one record and of a batch of 16 (benchmarks/bench_fit.py).
B5  gradient cost relative to the forward run (benchmarks/bench_scale.py).

Compile time and run time are reported separately; run times are the best of the same
number of repeats on both sides (after compilation for teflon-jax, with `block_until_ready`).
"""

import argparse
import datetime
import importlib.util
import json
import os
import pathlib
import platform
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))  # the benchmark helpers (_peer, bench_*) sit beside this file


def _load(name):
    spec = importlib.util.spec_from_file_location(name, HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _cpu_model() -> str | None:
    """The processor's model name from /proc/cpuinfo (Linux), else None."""
    try:
        for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        return None
    return None


def machine_info() -> dict:
    import jax

    info = {
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "cpu_model": _cpu_model(),
        "cpu_count": os.cpu_count(),
        "python": platform.python_version(),
        "jax": jax.__version__,
        "devices": [str(d) for d in jax.devices()],
        "device_kind": jax.devices()[0].device_kind,
        "xla_flags": os.environ.get("XLA_FLAGS", ""),
    }
    for package in ("diffrax", "optimistix", "equinox", "numpy", "openseespy"):
        try:
            info[package] = __import__(package).__version__
        except Exception:  # not installed or no version attribute
            try:
                from importlib.metadata import version

                info[package] = version(package)
            except Exception:
                info[package] = None
    return info


def _best_of(fn, repeats):
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def bench_b1(quick: bool) -> dict:
    import diffrax
    import jax
    import jax.numpy as jnp
    import numpy as np

    import teflon_jax as tj
    from teflon_jax.units import INCH, PSI, STANDARD_GRAVITY

    motion = tj.load_record("elcentro").window(0.0, 40.0)
    ag = np.asarray(motion.acceleration)
    ground = tj.Signal(jnp.asarray(motion.time - motion.start_time), jnp.asarray(ag))
    friction, _ = tj.interface_parameters("UF", 1000 * PSI, "P")
    weight = 1.0e6
    mass = weight / STANDARD_GRAVITY
    step = 0.005
    duration = 40.0

    def system(dt):
        return tj.structure_on_sliders(
            mass=[mass], stiffness=[[0.0]], damping=[[0.0]], bearing=tj.paper_bearing(friction),
            bearing_load=weight, ground_acceleration=ground, time_step=dt,
        )

    @jax.jit
    def peak(s):
        r = tj.simulate_history(s, duration, throw=False)
        return jnp.max(jnp.abs(r.displacement[:, 0])), r.result

    sys_step = system(step)
    start = time.perf_counter()
    jax.block_until_ready(peak(sys_step))
    compile_s = time.perf_counter() - start
    repeats = 3 if quick else 5  # the same number of timed repeats on both sides
    run_s = _best_of(lambda: jax.block_until_ready(peak(sys_step)), repeats)
    ours, result = peak(sys_step)

    start = time.perf_counter()
    reference = tj.simulate_history(system(step), duration, solver=diffrax.Tsit5(),
                                      rtol=1e-10, atol=1e-12, save_every=1)
    reference_s = time.perf_counter() - start
    ref_peak = float(jnp.max(jnp.abs(reference.displacement[:, 0])))

    out = {
        "case": "rigid mass, UF 1000 psi P, El Centro 1940 S00E (Caltech), 40 s",
        "time_step_s": step,
        "reference": {"solver": "diffrax Tsit5 rtol 1e-10 atol 1e-12", "peak_disp_in": ref_peak / INCH,
                      "wall_s": reference_s},
        "teflon_jax": {
            "compile_s": compile_s,
            "run_s_per_record": run_s,
            "peak_disp_in": float(ours) / INCH,
            "peak_error_pct": 100 * (float(ours) - ref_peak) / ref_peak,
            "solver_ok": bool(result == diffrax.RESULTS.successful),
            "repeats": repeats,
        },
    }
    try:
        from _peer import load_peer, rigid_mass

        peer = load_peer()
        runs = [rigid_mass(peer, ag, float(motion.time_step), time_step=step, weight=weight)
                for _ in range(repeats)]
        best = min(runs, key=lambda r: r["wall_s"])
        n = int(round(duration / float(motion.time_step))) + 1
        os_peak = float(np.max(np.abs(best["displacement"][:n])))
        out["opensees"] = {
            "model": "flatSliderBearing + VelDependent (elastic-perfectly-plastic, k0 = mu(0) W / Y)",
            "build_s": best["build_s"],
            "run_s_per_record": best["wall_s"] * duration / (len(best["displacement"]) * float(motion.time_step)),
            "peak_disp_in": os_peak / INCH,
            "peak_error_pct": 100 * (os_peak - ref_peak) / ref_peak,
            "failed_steps": int(best["n_failed"]),
            "repeats": repeats,
        }
        out["speedup"] = out["opensees"]["run_s_per_record"] / run_s
    except ImportError as error:
        out["opensees"] = {"skipped": str(error)}
    return out


def _table(results: dict) -> str:
    lines = ["case | teflon-jax | OpenSees | note", "---|---|---|---"]
    b1 = results.get("B1")
    if b1 and "teflon_jax" in b1:
        tjx, ops = b1["teflon_jax"], b1.get("opensees", {})
        lines.append(
            f"B1 s/record (40 s El Centro) | {tjx['run_s_per_record']:.4f} "
            f"(err {tjx['peak_error_pct']:+.2f} %) | "
            + (f"{ops['run_s_per_record']:.4f} (err {ops['peak_error_pct']:+.2f} %)" if "run_s_per_record" in ops else "n/a")
            + f" | compile {tjx['compile_s']:.1f} s"
        )
    for key in ("B2", "B3", "B4", "B5"):
        if key in results and "summary" in results[key]:
            lines.append(f"{key} | {results[key]['summary']}")
    return "\n".join(lines)


CASES = {
    "B1": lambda quick: bench_b1(quick),
    "B2": lambda quick: _load("bench_fig11").run_fig11_benchmark(quick),
    "B3": lambda quick: _load("bench_scale").run_scale_benchmark(quick),
    "B4": lambda quick: _load("bench_fit").run_fit_benchmark(quick),
}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="small sizes, few repeats")
    parser.add_argument("--json", default=None, help="write all results to this JSON file")
    parser.add_argument("--skip", default="", help="comma-separated cases to skip, e.g. B3,B4")
    parser.add_argument("--float32", action="store_true", help="single precision (default double)")
    parser.add_argument("--cpu-devices", type=int, default=os.cpu_count() or 1,
                        help="JAX CPU devices to split the processor into (default: one per core); "
                             "Monte Carlo shards its motions over them")
    args = parser.parse_args(argv)
    if args.cpu_devices < 1:
        parser.error(f"--cpu-devices: must be >= 1, got {args.cpu_devices}")
    import jax

    from teflon_jax.studies import prefer_wide_cpu_vectors

    prefer_wide_cpu_vectors()  # as the teflon-jax command does, before JAX's first computation
    jax.config.update("jax_num_cpu_devices", args.cpu_devices)
    jax.config.update("jax_enable_x64", not args.float32)
    skip = {s.strip().upper() for s in args.skip.split(",") if s.strip()}
    results = {"machine": machine_info(), "quick": args.quick,
               "precision": "float32" if args.float32 else "float64"}
    for name, case in CASES.items():
        if name in skip:
            continue
        print(f"running {name} ...", file=sys.stderr, flush=True)
        start = time.perf_counter()
        try:
            results[name] = case(args.quick)
        except FileNotFoundError as error:
            results[name] = {"skipped": str(error)}
        results[name]["benchmark_wall_s"] = time.perf_counter() - start
    print(_table(results))
    if args.json:
        pathlib.Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        pathlib.Path(args.json).write_text(json.dumps(results, indent=2, default=float))
        print(f"wrote {args.json}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
