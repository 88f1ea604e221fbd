"""B2: the whole Fig. 11 set — 2 records x Tb 0.2-4.0 s (step 0.1) x 3 pressures + the linear system.

teflon-jax runs it as vmapped batches (`building_sweep`); OpenSees runs a stated subset of the
sliding cases and of the linear cases one by one, and each kind's total is extrapolated from
its own time per case (labelled as such). Breakaway (Eq. 17) is off on both sides: OpenSees'
flatSliderBearing has none.
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
    n_sliding = len(records) * 3 * len(periods)
    n_linear = len(records) * len(periods)

    def timed(include_linear):
        # breakaway off: OpenSees' flatSliderBearing has none (both sides alike)
        def call():
            return building_sweep(records=records, periods=periods, breakaway_ratio=None,
                                  include_linear=include_linear)

        start = time.perf_counter()
        call()
        warm = time.perf_counter() - start  # compilation + one run
        start = time.perf_counter()
        call()
        jax.effects_barrier()
        return warm, time.perf_counter() - start  # one timed run, as for each OpenSees case

    sliding_warm, sliding_s = timed(False)
    all_warm, all_s = timed(True)
    ours = {"sliding_total_s": sliding_s, "all_total_s": all_s,
            "compile_s": max(all_warm - all_s, 0.0), "breakaway": False, "repeats": 1,
            "note": "one vmapped call per system family, timed once after a first (compiling) "
                    "call of the same size: the sliding cases alone, then all cases"}
    out = {"periods": periods.tolist(), "n_sliding_cases": n_sliding, "n_linear_cases": n_linear,
           "time_step_s": 0.005, "teflon_jax": ours}
    peer = _opensees_subset(records, periods, quick)
    out["opensees"] = peer
    if "s_per_sliding_case" in peer:
        peer["extrapolated_sliding_s"] = peer["s_per_sliding_case"] * n_sliding
        peer["extrapolated_linear_s"] = peer["s_per_linear_case"] * n_linear
        peer["extrapolated_total_s"] = peer["extrapolated_sliding_s"] + peer["extrapolated_linear_s"]
        out["speedup_sliding"] = peer["extrapolated_sliding_s"] / sliding_s
        out["speedup"] = peer["extrapolated_total_s"] / all_s
    out["summary"] = (
        f"{all_s:.1f} s for {n_sliding + n_linear} cases ({sliding_s:.1f} s sliding) | "
        + (f"{peer['extrapolated_total_s']:.0f} s extrapolated per case kind "
           f"({peer['extrapolated_sliding_s']:.0f} s sliding from {len(peer['sliding_cases'])} "
           f"cases, {peer['extrapolated_linear_s']:.0f} s linear from {len(peer['linear_cases'])})"
           if "extrapolated_total_s" in peer else "n/a")
        + " | B2, breakaway off on both sides"
    )
    return out


def _opensees_subset(records, periods, quick):
    from _peer import building, load_peer

    try:
        peer = load_peer()
    except ImportError as error:
        return {"skipped": str(error)}
    sliding = [("elcentro", 2.0)] if quick else [("elcentro", 1.0), ("elcentro", 3.0), ("sct", 2.0)]
    linear = [("elcentro", 2.0)] if quick else [("elcentro", 1.0), ("sct", 3.0)]

    def walls(cases, **kwargs):
        return [building(peer, records[n].acceleration, float(records[n].time_step), period=p,
                         **kwargs)["wall_s"] for n, p in cases]

    sliding_walls = walls(sliding)
    linear_walls = walls(linear, slider=False, damping_ratio=0.10)
    return {
        "model": "flatSliderBearing + VelDependent (no breakaway), full 6x6 K and C, Newmark + "
                 "modified Newton, 5 ms steps; linear: the same frame on springs and dashpot only",
        "sliding_cases": [f"{n} Tb={p}" for n, p in sliding],
        "linear_cases": [f"{n} Tb={p}" for n, p in linear],
        "s_per_sliding_case": float(np.mean(sliding_walls)),
        "s_per_linear_case": float(np.mean(linear_walls)),
        "note": "subsets run once each; each kind's total extrapolated by its own mean time per case",
    }
