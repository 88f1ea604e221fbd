"""B3 / B5: Monte Carlo throughput and the cost of gradients of Monte Carlo statistics.

B3: records per second for N = 100, 1,000, 10,000 forty-second Clough-Penzien motions on the
rigid mass and the six-storey building (structure step 0.01 s, records at 0.01 s), with the
peak resident memory after each N (flat in N at a fixed chunk size) and the accuracy of the
step against a halved step. B5: wall time of `jax.grad` of the mean smooth peak base shear
over a Monte Carlo set against the forward evaluation (compile times reported apart).

Usage: `python benchmarks/bench_scale.py [--quick]`; `run_scale_benchmark(quick)` returns a dict.
"""

import json
import platform
import resource
import sys
import time

import jax
import numpy as np

from teflon_jax._design import expected_response, forward_mode_gradient
from teflon_jax._montecarlo import isolated_structure, monte_carlo
from teflon_jax._stochastic import StochasticGroundMotion, sample
from teflon_jax._units import PSI, STANDARD_GRAVITY

TIME_STEP = 0.005  # structure step [s]; records are sampled at 0.01 s


def _rss_bytes():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def _motions(duration=40.0):
    strong = min(10.0, 0.5 * duration)
    return StochasticGroundMotion(peak_ground_acceleration=0.3 * STANDARD_GRAVITY,
                                  duration=duration, time_step=0.01, rise_time=min(2.0, 0.1 * duration),
                                  strong_motion_duration=strong)


def _throughput(kind, sizes, chunk_size, time_step):
    structure = isolated_structure(kind, time_step=time_step, pressure=1000 * PSI, isolation_period=2.0)
    rows = []
    for n in sizes:
        before = _rss_bytes()
        result = monte_carlo(structure, _motions(), n, key=jax.random.key(1), chunk_size=chunk_size)
        run = result.wall_s - result.compile_s
        rows.append({
            "n_motions": n,
            "wall_s": result.wall_s,
            "compile_s": result.compile_s,
            "run_s": run,
            "records_per_s": n / run,
            "peak_rss_mb": _rss_bytes() / 2**20,
            "peak_rss_growth_mb": (_rss_bytes() - before) / 2**20,
            "all_converged": bool(result.converged.all()),
            "median_base_disp_m": float(np.median(result.base_disp)),
            "median_base_shear_ratio": float(np.median(result.base_shear_ratio)),
        })
    sizes_arr = np.array([r["n_motions"] for r in rows], float)
    runs = np.array([r["run_s"] for r in rows])
    slope = float(np.polyfit(np.log(sizes_arr), np.log(runs), 1)[0]) if len(rows) > 1 else None
    return {"time_step_s": time_step, "chunk_size": chunk_size, "runs": rows,
            "cost_exponent_in_n": slope}


def _step_accuracy(kind, n, time_step):
    """Peak error of `time_step` against `time_step / 2` over n motions."""
    out = {}
    for dt in (time_step, time_step / 2):
        structure = isolated_structure(kind, time_step=dt, pressure=1000 * PSI, isolation_period=2.0)
        out[dt] = monte_carlo(structure, _motions(), n, key=jax.random.key(1), chunk_size=n)
    coarse, fine = out[time_step], out[time_step / 2]
    err = {}
    for name in ("base_disp", "base_shear_ratio"):
        rel = np.abs(getattr(coarse, name) / getattr(fine, name) - 1)
        err[name] = {"median_rel": float(np.median(rel)), "p95_rel": float(np.percentile(rel, 95)),
                     "max_rel": float(rel.max())}
    return {"time_step_s": time_step, "n_motions": n, "error_vs_half_step": err}


def _gradient_cost(kind, n, duration, time_step):
    structure = isolated_structure(kind, time_step=time_step)
    model = _motions(duration)
    records = sample(model, jax.random.key(4), n)
    x = {"isolation_period": 2.0, "pressure": 1500 * PSI, "isolation_damping": 0.05}

    def statistic(x):
        return expected_response(structure, x, records, 0.01)["shear"]

    out = {"kind": kind, "n_motions": n, "duration_s": duration, "n_variables": len(x)}
    for name, fn in (("forward", jax.jit(statistic)), ("reverse_grad", jax.jit(jax.grad(statistic))),
                     ("forward_mode_grad", jax.jit(jax.grad(forward_mode_gradient(statistic))))):
        tic = time.perf_counter()
        jax.block_until_ready(fn(x))
        first = time.perf_counter() - tic
        times = []
        for _ in range(3):
            tic = time.perf_counter()
            jax.block_until_ready(fn(x))
            times.append(time.perf_counter() - tic)
        out[name] = {"compile_and_first_s": first, "run_s": min(times)}
    out["reverse_over_forward"] = out["reverse_grad"]["run_s"] / out["forward"]["run_s"]
    out["forward_mode_over_forward"] = out["forward_mode_grad"]["run_s"] / out["forward"]["run_s"]
    out["note"] = ("reverse_grad: plain jax.grad through the time stepping; forward_mode_grad: jax.grad "
                   "of forward_mode_gradient(statistic) (custom VJP computed by jacfwd), what the "
                   "design optimiser uses")
    return out


def _opensees_throughput(kind, n, time_step):
    """Records per second of the OpenSees peer on the same stochastic motions (a subset)."""
    from _peer import building, load_peer, rigid_mass

    try:
        peer = load_peer()
    except ImportError as error:
        return {"skipped": str(error)}
    model = _motions()
    records = np.asarray(sample(model, jax.random.key(1), n))
    walls = []
    for acc in records:
        if kind == "rigid":
            r = rigid_mass(peer, acc, model.time_step, time_step=time_step, period=2.0, damping_ratio=0.05)
        else:
            r = building(peer, acc, model.time_step, period=2.0, time_step=time_step)
        walls.append(r["wall_s"])
    return {"n_motions": n, "s_per_record": float(np.mean(walls)), "records_per_s": n / float(np.sum(walls)),
            "time_step_s": time_step, "note": "same stochastic motions (key 1), Newmark + modified Newton"}


def run_scale_benchmark(quick: bool, sizes=None) -> dict:
    """B3 and B5. quick=True: N = 20, 100 and a short gradient case (minutes on 2 CPU cores)."""
    if sizes is None:
        sizes = (20, 100) if quick else (100, 1000, 10000)
    chunk = 50 if quick else 256
    b3 = {kind: _throughput(kind, sizes, chunk, TIME_STEP) for kind in ("rigid", "building")}
    peers = {kind: _opensees_throughput(kind, 2 if quick else 8, TIME_STEP) for kind in ("rigid", "building")}
    for kind, peer in peers.items():
        b3[kind]["opensees"] = peer
        if "records_per_s" in peer:
            at = [r for r in b3[kind]["runs"] if r["n_motions"] == (100 if quick else 1000)]
            if at:
                b3[kind]["speedup_vs_opensees"] = at[0]["records_per_s"] / peer["records_per_s"]
    result = {
        "hardware": {"devices": [str(d) for d in jax.devices()], "platform": platform.platform(),
                     "processor": platform.processor(), "python": sys.version.split()[0],
                     "jax": jax.__version__,
                     "precision": "float64" if jax.config.jax_enable_x64 else "float32"},
        "B3": b3,
        "B3_step_accuracy": {kind: _step_accuracy(kind, 20 if quick else 100, TIME_STEP)
                             for kind in ("rigid", "building")},
        "B5": [_gradient_cost("rigid", 4 if quick else 16, 10.0 if quick else 40.0, TIME_STEP),
               _gradient_cost("building", 4 if quick else 16, 10.0 if quick else 40.0, TIME_STEP)],
    }
    rows = []
    for kind in ("rigid", "building"):
        entry = b3[kind]
        best = max(entry["runs"], key=lambda r: r["n_motions"])
        rows.append(f"{kind} {best['records_per_s']:.0f} rec/s at N={best['n_motions']}"
                    + (f" ({entry['speedup_vs_opensees']:.0f}x OpenSees)" if "speedup_vs_opensees" in entry else ""))
    result["summary"] = "; ".join(rows) + " | B3"
    return result


if __name__ == "__main__":
    jax.config.update("jax_enable_x64", "--float32" not in sys.argv)
    print(json.dumps(run_scale_benchmark("--quick" in sys.argv), indent=1))
