"""Benchmark of the bearing-test fit: one 3-cycle record, and a batch of 16 (one per Table 1
interface), compile time reported apart from run time.

Protocol: sine 4 in at 0.6 Hz (test No. 75 of Constantinou, Mokha & Reinhorn 1990), 3 cycles,
started from rest at one end, sampled at 1 kHz (5001 samples; 500 Hz in quick mode), 2 % force
noise; free parameters f_max, delta_f, rate_a, yield_disp, breakaway_ratio.
"""

import platform
import time

import jax
import numpy as np


def _records(quick: bool):
    import teflon_jax as tj
    from teflon_jax.formats import test_record_from_arrays
    from teflon_jax.units import INCH, KIP

    fs = 500.0 if quick else 1000.0
    t = np.arange(0.0, 3 / 0.6 + 1e-9, 1.0 / fs)
    u = 4 * INCH * (1.0 - np.cos(2 * np.pi * 0.6 * t))
    load = 78.5 * KIP
    records = []
    for k, row in enumerate(tj.load_table1()):
        bearing = tj.paper_bearing(tj.FrictionParameters(row.f_max, row.delta_f, row.rate_a),
                                   breakaway_ratio=row.breakaway_ratio)
        f = np.asarray(tj.imposed_path_test(bearing, tj.tabulated_motion(t, u), load).fx)
        f = f + 0.02 * np.sqrt(np.mean(f**2)) * np.random.default_rng(k).standard_normal(f.size)
        records.append(test_record_from_arrays(u, f, time=t, normal_load=load))
    return records


def _timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - start


def run_fit_benchmark(quick: bool) -> dict:
    """Time the fits; returns a dict of seconds, sizes and environment, in the precision the
    caller set (`run.py --float32` or not): "precision" says which ran."""
    from identification import fit_bearing_test, fit_bearing_tests_batch

    records = _records(quick)
    _, single_first = _timed(lambda: fit_bearing_test(records[0]))
    fit, single = _timed(lambda: fit_bearing_test(records[1]))
    _, batch_first = _timed(lambda: fit_bearing_tests_batch(records))
    fits, batch = _timed(lambda: fit_bearing_tests_batch(records[::-1]))
    return {
        "name": "fit",
        "samples_per_record": int(records[0].ux.size),
        "single_record_compile_and_run_s": single_first,
        "single_record_compile_s": max(single_first - single, 0.0),
        "single_record_run_s": single,
        "single_record_starts": fit.n_starts,
        "single_record_solver_steps": fit.n_steps,
        "batch16_compile_and_run_s": batch_first,
        "batch16_compile_s": max(batch_first - batch, 0.0),
        "batch16_run_s": batch,
        "batch16_starts_per_record": fits[0].n_starts,
        "batch16_all_converged": all(f.converged for f in fits),
        "targets": {"single_record_run_s": 5.0, "batch16_run_s": 30.0},
        "precision": "float64" if jax.config.jax_enable_x64 else "float32",
        "jax": jax.__version__,
        "backend": jax.default_backend(),
        "cpu": platform.processor() or platform.machine(),
        "python": platform.python_version(),
    }


if __name__ == "__main__":
    import json
    import sys

    jax.config.update("jax_enable_x64", "--float32" not in sys.argv)
    print(json.dumps(run_fit_benchmark("--quick" in sys.argv), indent=2))
