"""B2-B5 on an accelerator: the same cases as `run.py`, with batch sizes a GPU needs.

    python benchmarks/bench_gpu.py [--parts B3,B5,B4,B2] [--chunk 65536] [--chunks 3] --json OUT.json

B3: records per second of `monte_carlo` on 40 s Clough-Penzien motions (the motions of
`bench_scale.py`, generated on the device) for the rigid mass and the building at their
recommended steps, in chunks of `--chunk` motions; the rate is taken over the chunks after the
first (the first one compiles), wall time, and given per minute too. Accuracy: the peaks of
the first 100 motions at the benchmark step against 0.5 ms steps on the same device
(`bench_scale._peaks`). B5: the gradient cost of `bench_scale._gradient_cost` (16 motions).
B4: `bench_fit.run_fit_benchmark`. B2: `bench_fig11.run_fig11_benchmark` (the OpenSees peer
is reported as skipped where openseespy is not installed). Every part records the device name
(`jax.devices()[0].device_kind`) and the precision (float64 unless `--float32`).
"""

import argparse
import json
import pathlib
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))


def _device() -> dict:
    import jax

    device = jax.devices()[0]
    return {"platform": device.platform, "device_kind": device.device_kind, "n_devices": jax.device_count(),
            "jax": jax.__version__, "precision": "float64" if jax.config.jax_enable_x64 else "float32"}


def throughput(kind: str, chunk: int, chunks: int) -> dict:
    """Records per second of `chunks` chunks of `chunk` motions, over the chunks after the first."""
    import bench_scale
    import jax
    import numpy as np

    from teflon_jax.studies import monte_carlo

    marks = []
    structure = bench_scale._structure(kind, bench_scale.TIME_STEPS[kind])
    result = monte_carlo(structure, bench_scale._motions(), chunk * chunks, key=jax.random.key(bench_scale.MOTION_KEY),
                         chunk_size=chunk, progress=lambda done, total: marks.append(time.perf_counter()))
    rate = (len(marks) - 1) * chunk / (marks[-1] - marks[0])
    return {"time_step_s": bench_scale.TIME_STEPS[kind], "chunk_size": chunk, "n_motions": chunk * chunks,
            "records_per_s_after_first_chunk": rate, "records_per_minute": 60 * rate,
            "wall_s": result.wall_s, "compile_s": result.compile_s,
            "all_converged": bool(np.all(result.converged)),
            "median_base_disp_m": float(np.median(result.base_disp))}


def accuracy(kind: str, n: int = 100) -> dict:
    """Worst peak errors of the first `n` motions at the benchmark step against 0.5 ms steps."""
    import bench_scale

    reference = bench_scale._peaks(kind, n, bench_scale.REFERENCE_STEP)
    errors = bench_scale._errors(bench_scale._peaks(kind, n, bench_scale.TIME_STEPS[kind]), reference)
    return {"reference_step_s": bench_scale.REFERENCE_STEP, "errors": errors,
            "worst_peak_error": max(v["max_rel"] for v in errors.values())}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--parts", default="B3,B5,B4,B2", help="comma-separated parts, in order")
    parser.add_argument("--chunk", type=int, default=65536, help="motions per compiled call (B3)")
    parser.add_argument("--chunks", type=int, default=3, help="chunks per structure (B3; >= 2)")
    parser.add_argument("--kinds", default="building,rigid", help="structures for B3 and B5")
    parser.add_argument("--float32", action="store_true", help="single precision (default double)")
    parser.add_argument("--json", required=True, help="write the results to this JSON file")
    args = parser.parse_args(argv)
    if args.chunks < 2:
        parser.error(f"--chunks: must be >= 2 (the first chunk compiles), got {args.chunks}")
    import jax

    jax.config.update("jax_enable_x64", not args.float32)
    import bench_scale

    out = {"device": _device(), "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
    path = pathlib.Path(args.json)
    path.parent.mkdir(parents=True, exist_ok=True)
    kinds = [k.strip() for k in args.kinds.split(",") if k.strip()]
    for part in [p.strip().upper() for p in args.parts.split(",") if p.strip()]:
        tic = time.perf_counter()
        if part == "B3":
            out["B3"] = {kind: {**throughput(kind, args.chunk, args.chunks), "accuracy": accuracy(kind)}
                         for kind in kinds}
        elif part == "B5":
            out["B5"] = [bench_scale._gradient_cost(kind, 16, 40.0, bench_scale.TIME_STEPS[kind]) for kind in kinds]
        elif part == "B4":
            from bench_fit import run_fit_benchmark

            out["B4"] = run_fit_benchmark(False)
        elif part == "B2":
            from bench_fig11 import run_fig11_benchmark

            out["B2"] = run_fig11_benchmark(False)
        else:
            parser.error(f"--parts: unknown part {part!r}; accepted: B2, B3, B4, B5")
        out.setdefault("part_wall_s", {})[part] = time.perf_counter() - tic
        path.write_text(json.dumps(out, indent=1, default=float))  # what is done so far survives a time-out
        print(f"{part} done in {time.perf_counter() - tic:.0f} s", file=sys.stderr, flush=True)
    print(json.dumps(out, indent=1, default=float))
    return 0


if __name__ == "__main__":
    sys.exit(main())
