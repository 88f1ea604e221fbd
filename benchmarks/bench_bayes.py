"""Benchmark of the Bayesian bearing fit beside the least-squares fit, for one record.

Protocol: sine 4 in at 0.6 Hz (test No. 75 of Constantinou, Mokha & Reinhorn 1990), 3 cycles,
started from rest at one end, sampled at 500 Hz (2501 samples; 200 Hz, 2 cycles in quick
mode), 2 % force noise, interface UF 1000 psi P of Table 1; free parameters f_max, delta_f,
rate_a, yield_disp, breakaway_ratio and the noise level. NUTS: 1,000 warm-up and 1,000 draws
in each of 4 chains (vectorised on one device; 200 + 200 in quick mode).

    python benchmarks/bench_bayes.py [--quick] [--draws N] [--fs HZ] [--cycles C]
                                     [--note TEXT] [--out results/NAME.json]

`--draws`, `--fs`, `--cycles` override the size (e.g. a smaller run on a shared machine;
the JSON records the size that ran). The JSON holds the machine (CPU count, load average
before and after, platform) and `--note` (say there whether the machine was shared).

Times include compilation (each fit compiles once per record shape); the least-squares time
is that of `fit_bearing_test` with its default 8 starts, measured on its own.
"""

import argparse
import os
import platform
import time

import jax
import numpy as np


def _record(fs: float, cycles: float):
    import teflon_jax as tj
    from teflon_jax.formats import test_record_from_arrays
    from teflon_jax.units import INCH, KIP

    t = np.arange(0.0, cycles / 0.6 + 1e-9, 1.0 / fs)
    u = 4 * INCH * (1.0 - np.cos(2 * np.pi * 0.6 * t))
    load = 78.5 * KIP
    row = tj.load_table1()[0]
    bearing = tj.paper_bearing(tj.FrictionParameters(row.f_max, row.delta_f, row.rate_a),
                               breakaway_ratio=row.breakaway_ratio)
    f = np.asarray(tj.imposed_path_test(bearing, tj.tabulated_motion(t, u), load).fx)
    f = f + 0.02 * np.sqrt(np.mean(f**2)) * np.random.default_rng(0).standard_normal(f.size)
    return test_record_from_arrays(u, f, time=t, normal_load=load)


def run_bayes_benchmark(quick: bool, draws=None, fs=None, cycles=None) -> dict:
    """Time the least-squares and the Bayesian fit of one record; returns a dict."""
    jax.config.update("jax_enable_x64", True)
    from identification.bayes import fit_bayes
    from identification.bearing_fit import fit_bearing_test

    fs = fs or (200.0 if quick else 500.0)
    cycles = cycles or (2 if quick else 3)
    draws = draws or (200 if quick else 1000)
    load_before = os.getloadavg()
    record = _record(fs, cycles)
    start, cpu = time.perf_counter(), time.process_time()
    fit = fit_bearing_test(record)
    ls_s, ls_cpu = time.perf_counter() - start, time.process_time() - cpu
    start, cpu = time.perf_counter(), time.process_time()
    result = fit_bayes(record, num_warmup=draws, num_samples=draws, num_chains=4,
                       least_squares=fit)
    bayes_s, bayes_cpu = time.perf_counter() - start, time.process_time() - cpu
    return {
        "name": "bayes",
        "samples_per_record": int(record.ux.size),
        "least_squares_s": ls_s,
        "bayes_total_s": bayes_s,
        "bayes_sampling_s": result.elapsed_s,
        "least_squares_cpu_s": ls_cpu,
        "bayes_total_cpu_s": bayes_cpu,
        "chains": result.num_chains,
        "draws_per_chain": result.num_samples,
        "warmup_per_chain": draws,
        "divergences": result.divergences,
        "converged": result.converged,
        "max_rhat": max(r["rhat"] for r in result.table.values()),
        "min_ess_bulk": min(r["ess_bulk"] for r in result.table.values()),
        "posterior_sd_over_ls_se": result.compare_least_squares(),
        "jax": jax.__version__,
        "backend": jax.default_backend(),
        "cpu": platform.processor() or platform.machine(),
        "python": platform.python_version(),
        "sampling_hz": fs,
        "cycles": cycles,
        "cpu_count": os.cpu_count(),
        "load_average_1_5_15_min_before": list(load_before),
        "load_average_1_5_15_min_after": list(os.getloadavg()),
        "platform": platform.platform(),
        "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }


if __name__ == "__main__":
    import json
    import pathlib

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--draws", type=int, default=None, help="warm-up = draws per chain")
    parser.add_argument("--fs", type=float, default=None, help="sampling frequency [Hz]")
    parser.add_argument("--cycles", type=float, default=None)
    parser.add_argument("--note", default="", help="e.g. whether the machine was shared")
    parser.add_argument("--out", default=None, help="also write the JSON here")
    options = parser.parse_args()
    out = run_bayes_benchmark(options.quick, options.draws, options.fs, options.cycles)
    out["note"] = options.note
    text = json.dumps(out, indent=2)
    print(text)
    if options.out:
        pathlib.Path(options.out).write_text(text + "\n")
