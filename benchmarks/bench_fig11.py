"""B2: the whole Fig. 11 set — 2 records x Tb 0.2-4.0 s (step 0.1) x 3 pressures + the linear system.

teflon-jax runs it as vmapped batches (`building_sweep`); OpenSees runs a stated subset of the
sliding cases one by one and its total is extrapolated (labelled as such).
"""

import time

import numpy as np


def run_fig11_benchmark(quick: bool) -> dict:
    import jax

    import teflon_jax as tj
    from teflon_jax.studies import building_sweep

    periods = np.round(np.arange(0.2, 4.0 + 1e-9, 0.1), 10)
    if quick:
        periods = periods[::8]
    records = {
        "elcentro": tj.load_record("elcentro").window(0.0, 40.0),
        "sct": tj.load_record("sct"),
    }
    start = time.perf_counter()
    building_sweep(records=records, periods=periods)
    warm_s = time.perf_counter() - start  # compilation + one run
    start = time.perf_counter()
    sweep = building_sweep(records=records, periods=periods)
    jax.effects_barrier()
    total_s = time.perf_counter() - start
    out_compile = max(warm_s - total_s, 0.0)
    n_sliding = len(records) * 3 * len(periods)
    n_linear = len(records) * len(periods)
    out = {
        "periods": periods.tolist(),
        "n_sliding_cases": n_sliding,
        "n_linear_cases": n_linear,
        "time_step_s": 0.005,
        "teflon_jax": {"first_call_s_incl_compile": warm_s, "total_s": total_s,
                       "compile_s": out_compile,
                       "note": "one vmapped call per system family, after a first (compiling) call of the same size"},
    }
    out["opensees"] = _opensees_subset(records, periods, quick)
    if "s_per_case" in out["opensees"]:
        out["opensees"]["extrapolated_total_s"] = out["opensees"]["s_per_case"] * (n_sliding + n_linear)
        out["speedup"] = out["opensees"]["extrapolated_total_s"] / total_s
    out["summary"] = (
        f"{total_s:.1f} s for {n_sliding + n_linear} cases | "
        + (f"{out['opensees'].get('extrapolated_total_s', float('nan')):.0f} s extrapolated from "
           f"{out['opensees'].get('n_cases', 0)} cases" if "s_per_case" in out["opensees"] else "n/a")
        + " | B2"
    )
    del sweep
    return out


def _opensees_subset(records, periods, quick):
    from _peer import building, load_peer

    try:
        peer = load_peer()
    except ImportError as error:
        return {"skipped": str(error)}
    subset = [("elcentro", 2.0)] if quick else [("elcentro", 1.0), ("elcentro", 3.0), ("sct", 2.0)]
    walls = []
    for name, period in subset:
        motion = records[name]
        result = building(peer, motion.acceleration, float(motion.time_step), period=period)
        walls.append(result["wall_s"])
    return {
        "model": "flatSliderBearing + VelDependent, full 6x6 K and C, Newmark + modified Newton, 5 ms steps",
        "cases": [f"{n} Tb={p}" for n, p in subset],
        "n_cases": len(subset),
        "s_per_case": float(np.mean(walls)),
        "note": "subset run; total extrapolated by the mean time per case",
    }
