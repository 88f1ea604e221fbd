"""B3 / B5: Monte Carlo throughput and the cost of gradients of Monte Carlo statistics.

B3: records per second for N = 100, 1,000, 10,000 forty-second Clough-Penzien motions on the
rigid mass and the six-storey building (records at 0.01 s; structure steps in `TIME_STEPS`,
the largest whose worst peak error over 100 motions is below 0.5 %), with the peak resident
memory after each N (flat in N at a fixed chunk size). The OpenSees peer runs the same motions
(`monte_carlo_motion`) at the same step in one process per core (the headline ratio) and
reports its one-process rate too. Accuracy: the peaks of 100 motions at the benchmark step,
at twice it and at 1 ms, against 0.5 ms steps (the reference; its own convergence is
reported); against the peer, on the same 100 motions with both programs' peaks read at the
record samples, each program's time-step error against its own 0.5 ms run and the
model-form difference (EPP slider vs Bouc-Wen) in separate columns. B5: wall time of `jax.grad` of the mean smooth peak base shear over a
Monte Carlo set against the forward evaluation (compile times reported apart).

Speed against the previous method (`--speed`, `run_speed_comparison`): records/s and process
CPU time per record for both structures with today's step (`TIME_STEPS`, `METHODS["today"]`)
and the previous one (`BASELINE`: 2.5 ms, `METHODS["previous"]`), in the same run, with the worst peak errors of both over 100 motions against
0.5 ms steps and the load average of the machine (shared machines inflate wall times; CPU
time per record is the steadier figure).

Usage: `python benchmarks/bench_scale.py [--quick | --speed]`; `run_scale_benchmark(quick)` and
`run_speed_comparison()` return dicts.
"""

import json
import multiprocessing
import os
import platform
import resource
import sys
import time

import jax
import numpy as np

from teflon_jax.excitation import StochasticGroundMotion, sample
from teflon_jax.studies import (
    expected_response,
    forward_mode_gradient,
    monte_carlo,
    monte_carlo_motion,
    prefer_wide_cpu_vectors,
)
from teflon_jax.systems import (
    MONTE_CARLO_NEWTON_TOLERANCE,
    RECOMMENDED_TIME_STEPS,
    isolated_structure,
)
from teflon_jax.units import PSI, STANDARD_GRAVITY

TIME_STEPS = dict(RECOMMENDED_TIME_STEPS)
"""Structure step [s] per structure, as `teflon-jax montecarlo` uses by default: the largest
divisor of the record step whose worst peak error over 100 motions is below 0.5 % (5 ms for
both; the accuracy section reports twice the step too)."""
BASELINE = {"rigid": 0.0025, "building": 0.0025}
"""The previous method's step [s] (`METHODS["previous"]`)."""
METHODS = {
    "today": {"split_at_turn": True, "linear_rule": "exact", "newton_tolerance": MONTE_CARLO_NEWTON_TOLERANCE},
    "reference": {"split_at_turn": True, "linear_rule": "exact", "newton_tolerance": 1e-5},
    "previous": {"split_at_turn": False, "linear_rule": "newmark", "newton_tolerance": 1e-5},
}
"""The step's options: "today" as `teflon-jax montecarlo` runs (Z split at the turning point,
the exact linear rule, the equilibrium to 1e-3 Y), "reference" for the 0.5 ms runs every error
is measured against (the equilibrium to 1e-5 Y), and "previous", the earlier method
(Z along the net increment, Newmark's rule, 2.5 ms steps)."""
REFERENCE_STEP = 0.0005  # [s] converged reference for the peak errors
RECORD_STEP = 0.01  # [s] sampling of the stochastic motions
MOTION_KEY = 1  # PRNG seed of the benchmark motions (monte_carlo and the peer draw the same)
CHUNK = 500  # motions per compiled call: divides N = 1,000 and 10,000 (no padded motions)


def _rss_bytes():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def _motions(duration=40.0):
    strong = min(10.0, 0.5 * duration)
    return StochasticGroundMotion(peak_ground_acceleration=0.3 * STANDARD_GRAVITY,
                                  duration=duration, time_step=RECORD_STEP,
                                  rise_time=min(2.0, 0.1 * duration), strong_motion_duration=strong)


def _structure(kind, time_step, method="today"):
    return isolated_structure(kind, time_step=time_step, pressure=1000 * PSI, isolation_period=2.0,
                              **METHODS[method])


def _throughput(kind, sizes, chunk_size, time_step, method="today"):
    structure = _structure(kind, time_step, method)
    rows = []
    for n in sizes:
        before = _rss_bytes()
        load = os.getloadavg()[0]
        marks = []  # process CPU time and wall time after each chunk

        def mark(done, total, marks=marks):
            marks.append((time.process_time(), time.perf_counter()))

        result = monte_carlo(structure, _motions(), n, key=jax.random.key(MOTION_KEY), chunk_size=chunk_size,
                             progress=mark)
        run = result.wall_s - result.compile_s
        # CPU and wall time of the chunks after the first (compiled by then), per motion run
        # (the last chunk is padded to full size); None with a single chunk
        after_first = (len(marks) - 1) * result.chunk_size
        rows.append({
            "cpu_s_per_record": (marks[-1][0] - marks[0][0]) / after_first if after_first else None,
            "wall_s_per_record_after_first_chunk": (marks[-1][1] - marks[0][1]) / after_first if after_first else None,
            "load_average_1min": [load, os.getloadavg()[0]],
            "n_motions": n,
            "wall_s": result.wall_s,
            "compile_s": result.compile_s,
            "run_s": run,
            "records_per_s": n / run,
            "n_devices": result.n_devices,
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


def _peaks(kind, n, time_step, at_record_samples=False, method=None):
    """Peaks of the first n benchmark motions at `time_step`, read at every step or, with
    `at_record_samples`, at the record's samples (every 0.01 s, where OpenSees records)."""
    method = ("reference" if time_step == REFERENCE_STEP else "today") if method is None else method
    result = monte_carlo(_structure(kind, time_step, method), _motions(), n, key=jax.random.key(MOTION_KEY),
                         chunk_size=CHUNK, peak_interval=RECORD_STEP if at_record_samples else None)
    if not result.converged.all():
        raise RuntimeError(f"B3 accuracy: {kind} at {time_step} s did not converge on every motion")
    return {"base_disp": result.base_disp, "base_shear_ratio": result.base_shear_ratio}


def _errors(peaks, reference):
    out = {}
    for name in ("base_disp", "base_shear_ratio"):
        rel = np.abs(np.asarray(peaks[name]) / np.asarray(reference[name]) - 1)
        out[name] = {"median_rel": float(np.median(rel)), "p95_rel": float(np.percentile(rel, 95)),
                     "max_rel": float(rel.max()), "n_motions": int(rel.size)}
    return out


def _step_accuracy(kind, n, time_step, peer=None):
    """Peak errors over the first n motions.

    teflon-jax: `2 time_step`, `time_step` and 1 ms against `REFERENCE_STEP`, peaks read at
    every step. Against the peer, on the same motions and with every peak read at the record
    samples (0.01 s) on both sides: each program's time-step error against its own run at
    `REFERENCE_STEP`, and the model-form difference (OpenSees' elastic-perfectly-plastic
    slider against our Bouc-Wen bearing, both at `REFERENCE_STEP`)."""
    reference = _peaks(kind, n, REFERENCE_STEP)
    out = {"time_step_s": time_step, "n_motions": n, "reference_step_s": REFERENCE_STEP,
           "errors": {}}
    for dt in sorted({2 * time_step, time_step, 0.001}, reverse=True):
        out["errors"][f"{dt:g}"] = _errors(_peaks(kind, n, dt), reference)
    out["error_at_benchmark_step"] = out["errors"][f"{time_step:g}"]
    out["reference_convergence"] = ("the 1 ms row is the reference's own step-halving error "
                                    "bound (second order: the reference's error is about 1/3 of it)")
    if peer and "peaks" in peer and "reference_peaks" in peer:
        m = len(peer["peaks"]["base_disp"])
        ours_ref = _peaks(kind, m, REFERENCE_STEP, at_record_samples=True)
        ours = _peaks(kind, m, time_step, at_record_samples=True)
        out["same_instants"] = {
            "n_motions": m,
            "read_at": f"record samples, every {RECORD_STEP} s, on both sides",
            "teflon_jax_step_error": _errors(ours, ours_ref),
            "opensees_step_error": _errors(peer["peaks"], peer["reference_peaks"]),
            "model_form_difference": _errors(peer["reference_peaks"], ours_ref),
            "note": ("step error: each program at the benchmark step against itself at "
                     f"{REFERENCE_STEP} s; model form: OpenSees (EPP slider) against teflon-jax "
                     f"(Bouc-Wen), both at {REFERENCE_STEP} s"),
        }
    return out


def _opensees_throughput(kind, n, time_step):
    """Records per second of the OpenSees peer on the first n benchmark motions at the same
    step, with one process per core running at once (the headline) and in one process (the
    pool's busiest process's analysis time over its motions), with each analysis's peaks;
    and the same motions at `REFERENCE_STEP` (its own converged run)."""
    from _peer import load_peer, peaks_and_wall, ready

    try:
        load_peer()
    except ImportError as error:
        return {"skipped": str(error)}
    key = jax.random.key(MOTION_KEY)
    records = [np.asarray(monte_carlo_motion(_motions(), key, i)) for i in range(n)]
    processes = os.cpu_count() or 1
    context = multiprocessing.get_context("spawn")
    with context.Pool(processes) as pool:
        pool.map(ready, range(processes))  # imports and OpenSees loaded before timing
        runs = pool.map(peaks_and_wall, [(kind, acc, RECORD_STEP, time_step) for acc in records], chunksize=1)
        reference = pool.map(peaks_and_wall, [(kind, acc, RECORD_STEP, REFERENCE_STEP) for acc in records],
                             chunksize=1)
    busy = {}
    for wall, *_, pid in runs:
        busy[pid] = busy.get(pid, 0.0) + wall
    walls = [r[0] for r in runs]
    return {
        "n_motions": n, "time_step_s": time_step, "failed_steps": int(sum(r[3] for r in runs)),
        "s_per_record": float(np.mean(walls)),
        "records_per_s_one_process": 1.0 / float(np.mean(walls)),
        "all_cores": {"processes": processes, "records_per_s": n / max(busy.values()),
                      "note": "one OpenSees process per core running at the same time; time = the "
                              "busiest process's analysis time (model building and process start "
                              "excluded, as for teflon-jax's compile)"},
        "peaks": {"base_disp": [r[1] for r in runs], "base_shear_ratio": [r[2] for r in runs]},
        "reference_peaks": {"base_disp": [r[1] for r in reference],
                            "base_shear_ratio": [r[2] for r in reference]},
        "reference_failed_steps": int(sum(r[3] for r in reference)),
        "note": "the first motions of the B3 set (same seed), Newmark + modified Newton; peaks read "
                "at the record samples",
    }


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


def run_scale_benchmark(quick: bool, sizes=None) -> dict:
    """B3 and B5. quick=True: N = 20, 100 and a short gradient case (minutes on 2 CPU cores)."""
    if sizes is None:
        sizes = (20, 100) if quick else (100, 1000, 10000)
    at = 100 if quick else 1000
    b3 = {kind: _throughput(kind, sizes, 64 if quick else CHUNK, TIME_STEPS[kind]) for kind in TIME_STEPS}
    accuracy_n = 4 if quick else 100  # the same motions for both programs' errors (>= 100)
    peers = {kind: _opensees_throughput(kind, accuracy_n, TIME_STEPS[kind]) for kind in TIME_STEPS}
    for kind, peer in peers.items():
        b3[kind]["opensees"] = {k: v for k, v in peer.items() if k not in ("peaks", "reference_peaks")}
        ours = [r for r in b3[kind]["runs"] if r["n_motions"] == at]
        if "all_cores" in peer and ours:
            # headline: our devices (one per core) against OpenSees on every core
            b3[kind]["speedup_vs_opensees_all_cores"] = (
                ours[0]["records_per_s"] / peer["all_cores"]["records_per_s"])
            b3[kind]["speedup_vs_opensees_one_process"] = (
                ours[0]["records_per_s"] / peer["records_per_s_one_process"])
    result = {
        "hardware": _hardware(),
        "B3": b3,
        "B3_step_accuracy": {kind: _step_accuracy(kind, accuracy_n if quick else 100, TIME_STEPS[kind], peers[kind])
                             for kind in TIME_STEPS},
        "B5": [_gradient_cost(kind, 4 if quick else 16, 10.0 if quick else 40.0, TIME_STEPS[kind])
               for kind in TIME_STEPS],
    }
    result["B3_vs_previous_method"] = run_speed_comparison(at, accuracy_n, 64 if quick else CHUNK)
    rows = []
    for kind in TIME_STEPS:
        entry = b3[kind]
        best = [r for r in entry["runs"] if r["n_motions"] == at] or entry["runs"]
        worst = max(v["max_rel"] for v in result["B3_step_accuracy"][kind]["error_at_benchmark_step"].values())
        text = f"{kind} {best[0]['records_per_s']:.0f} rec/s at N={best[0]['n_motions']}"
        if "speedup_vs_opensees_all_cores" in entry:
            text += (f" ({entry['speedup_vs_opensees_all_cores']:.1f}x OpenSees on all "
                     f"{entry['opensees']['all_cores']['processes']} cores)")
        text += f", worst peak error {100 * worst:.2f} %"
        same = result["B3_step_accuracy"][kind].get("same_instants")
        if same:
            def worst_of(errors):
                return 100 * max(v["max_rel"] for v in errors.values())

            text += (f"; on {same['n_motions']} motions at 0.01 s instants: step error ours "
                     f"{worst_of(same['teflon_jax_step_error']):.2f} %, OpenSees "
                     f"{worst_of(same['opensees_step_error']):.2f} %, model form "
                     f"{worst_of(same['model_form_difference']):.1f} %")
        rows.append(text)
    result["summary"] = "; ".join(rows)
    return result


def run_speed_comparison(n_motions: int = 1024, accuracy_n: int = 100, chunk_size: int = CHUNK) -> dict:
    """Today's update at `TIME_STEPS` beside the previous one at `BASELINE`, in one run: B3
    records/s and CPU s/record on `n_motions` motions, and the worst peak errors of both on the
    first `accuracy_n` (>= 100 for the claim) against today's update at `REFERENCE_STEP`."""
    out = {"hardware": _hardware(), "n_motions": n_motions, "accuracy_n_motions": accuracy_n}
    for kind in TIME_STEPS:
        reference = _peaks(kind, accuracy_n, REFERENCE_STEP)
        previous_reference = _peaks(kind, accuracy_n, REFERENCE_STEP, method="previous")
        entry = {"reference_step_s": REFERENCE_STEP,
                 "references_differ": _errors(previous_reference, reference)}
        for name, step in (("today", TIME_STEPS[kind]), ("previous", BASELINE[kind])):
            speed = _throughput(kind, (n_motions,), chunk_size, step, name)["runs"][0]
            errors = _errors(_peaks(kind, accuracy_n, step, method=name), reference)
            entry[name] = {"time_step_s": step, **METHODS[name], **speed, "errors": errors,
                           "worst_peak_error": max(v["max_rel"] for v in errors.values())}
        entry["speedup_records_per_s"] = entry["today"]["records_per_s"] / entry["previous"]["records_per_s"]
        entry["speedup_cpu_per_record"] = (entry["previous"]["cpu_s_per_record"]
                                           / entry["today"]["cpu_s_per_record"])
        out[kind] = entry
    out["summary"] = "; ".join(
        f"{kind}: {out[kind]['today']['records_per_s']:.0f} rec/s, "
        f"{1e3 * out[kind]['today']['cpu_s_per_record']:.2f} ms CPU/rec at {out[kind]['today']['time_step_s']:.4g} s, "
        f"worst {100 * out[kind]['today']['worst_peak_error']:.2f} % (previous: "
        f"{out[kind]['previous']['records_per_s']:.0f} rec/s, {1e3 * out[kind]['previous']['cpu_s_per_record']:.2f} ms, "
        f"worst {100 * out[kind]['previous']['worst_peak_error']:.2f} %)" for kind in TIME_STEPS)
    return out


def _hardware():
    return {"devices": [str(d) for d in jax.devices()], "platform": platform.platform(),
            "processor": platform.processor(), "cpu_count": os.cpu_count(),
            "python": sys.version.split()[0], "jax": jax.__version__,
            "precision": "float64" if jax.config.jax_enable_x64 else "float32",
            "load_average": list(os.getloadavg())}


if __name__ == "__main__":
    prefer_wide_cpu_vectors()  # as the teflon-jax command does, before JAX's first computation
    jax.config.update("jax_num_cpu_devices", os.cpu_count() or 1)
    jax.config.update("jax_enable_x64", "--float32" not in sys.argv)
    if "--speed" in sys.argv:
        print(json.dumps(run_speed_comparison(), indent=1))
    else:
        print(json.dumps(run_scale_benchmark("--quick" in sys.argv), indent=1))
