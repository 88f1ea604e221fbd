"""Benchmark: many Bayesian fits in one process, memory and time, with and without the kept
compiled sampler.

Each side runs in a process of its own: N sequential `fit_bayes` calls (least squares with 8
starts, then NUTS) on records of one shape simulated from a known bearing (UF 1000 psi P of
Table 1 of Constantinou, Mokha & Reinhorn 1990, Y = 0.005 in; a sine of 4 in from rest at 0.6
Hz, 2 cycles at 200 Hz: 667 samples), each with its own 2 % force noise and seed. The sides:

- `after`: `fit_bayes(..., reuse_compiled=True)`, the sampler compiled once for the shape;
- `before`: `fit_bayes(..., reuse_compiled=False)`, a numpyro `MCMC` made and compiled per fit.

Printed after every 10 fits and written to the JSON: the resident memory now and at its peak
(`/proc/self/status`, `resource.getrusage`), and the wall time. A side stops early when its
resident memory passes `--max-rss-gb` or its time `--max-minutes` (the JSON says where and why),
so that a side whose memory grows does not take the machine's memory from others.

    python benchmarks/bayes_many_fits.py [--fits 100] [--chains 2] [--draws 100]
        [--sides after,before] [--max-rss-gb 6] [--max-minutes 120] [--note TEXT]
        [--out benchmarks/results/bayes-many-fits-cpu-DATE.json]
"""

import argparse
import json
import os
import pathlib
import platform
import resource
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent


def _rss_mb() -> float:
    with open("/proc/self/status") as handle:
        for line in handle:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _records(fits: int):
    """One noise-free force of the known bearing, and `fits` records with their own noise."""
    import numpy as np

    import teflon_jax as tj
    from teflon_jax.units import INCH, KIP

    row = tj.load_table1()[0]
    bearing = tj.paper_bearing(tj.FrictionParameters(row.f_max, row.delta_f, row.rate_a),
                               yield_disp=0.005 * INCH, breakaway_ratio=row.breakaway_ratio)
    load, fine, fs = 78.5 * KIP, 20, 200.0
    t_fine = np.arange(0.0, 2 / 0.6 + 1e-9, 1.0 / (fine * fs))
    u_fine = 4 * INCH * (1.0 - np.cos(2 * np.pi * 0.6 * t_fine))
    force = np.asarray(tj.imposed_path_test(bearing, tj.tabulated_motion(t_fine, u_fine),
                                                load).fx)[::fine]
    t, u = t_fine[::fine], u_fine[::fine]
    scale = 0.02 * np.sqrt(np.mean(force**2))
    for i in range(fits):
        noise = scale * np.random.default_rng(1000 + i).standard_normal(force.size)
        yield tj.test_record_from_arrays(u, force + noise, time=t, normal_load=load)


def run_side(side: str, fits: int, chains: int, draws: int, max_rss_gb: float,
             max_minutes: float) -> None:
    """The fits of one side in this process; one JSON line per fit on stdout."""
    import jax

    jax.config.update("jax_enable_x64", True)
    from identification.bayes import fit_bayes

    start = time.perf_counter()
    for i, record in enumerate(_records(fits)):
        t0 = time.perf_counter()
        result = fit_bayes(record, num_warmup=draws, num_samples=draws, num_chains=chains,
                           seed=i, reuse_compiled=(side == "after"))
        line = {"fit": i + 1, "wall_s": time.perf_counter() - t0,
                "elapsed_s": time.perf_counter() - start, "rss_mb": _rss_mb(),
                "peak_rss_mb": _peak_mb(), "converged": bool(result.converged)}
        print(json.dumps(line), flush=True)
        if line["rss_mb"] > 1024 * max_rss_gb:
            print(json.dumps({"stopped": f"resident memory {line['rss_mb']:.0f} MB passed "
                              f"--max-rss-gb {max_rss_gb} after {i + 1} fits"}), flush=True)
            return
        if line["elapsed_s"] > 60 * max_minutes:
            print(json.dumps({"stopped": f"time passed --max-minutes {max_minutes} after "
                              f"{i + 1} fits"}), flush=True)
            return


def _summary(side, lines, stopped, wall):
    fits = [x for x in lines]
    rest = sorted(x["wall_s"] for x in fits[1:])
    return {
        "side": side,
        "fits_done": len(fits),
        "stopped": stopped,
        "wall_s": wall,
        "first_fit_s": fits[0]["wall_s"] if fits else None,
        "median_later_fit_s": rest[len(rest) // 2] if rest else None,
        "converged": sum(x["converged"] for x in fits),
        "rss_mb_every_10": {x["fit"]: round(x["rss_mb"], 1) for x in fits
                            if x["fit"] % 10 == 0 or x["fit"] in (1, len(fits))},
        "peak_rss_mb": max((x["peak_rss_mb"] for x in fits), default=None),
        "rss_growth_mb_per_fit_after_first": (
            (fits[-1]["rss_mb"] - fits[0]["rss_mb"]) / (len(fits) - 1) if len(fits) > 1 else None),
        "per_fit": fits,
    }


def _machine(load_before) -> dict:
    import jax
    import numpyro

    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as handle:
            cpu = next(line.split(":", 1)[1].strip() for line in handle
                       if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    with open("/proc/meminfo") as handle:
        memory = int(handle.readline().split()[1]) / 1024**2
    return {"cpu": cpu, "cpu_count": os.cpu_count(), "memory_gb": round(memory, 1),
            "platform": platform.platform(), "python": platform.python_version(),
            "jax": jax.__version__, "numpyro": numpyro.__version__,
            "backend": jax.default_backend(),
            "load_average_1_5_15_min_before": list(load_before),
            "load_average_1_5_15_min_after": list(os.getloadavg())}


def main(options) -> dict:
    out = {"name": "bayes-many-fits", "fits_asked": options.fits, "chains": options.chains,
           "warmup_and_draws_per_chain": options.draws, "samples_per_record": 667,
           "max_rss_gb": options.max_rss_gb, "max_minutes": options.max_minutes,
           "note": options.note, "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
           "command": " ".join([os.path.basename(sys.executable), *sys.argv]), "sides": {}}
    load_before = os.getloadavg()
    for side in options.sides.split(","):
        command = [sys.executable, str(pathlib.Path(__file__).resolve()), "--side", side,
                   "--fits", str(options.fits), "--chains", str(options.chains), "--draws",
                   str(options.draws), "--max-rss-gb", str(options.max_rss_gb),
                   "--max-minutes", str(options.max_minutes)]
        start, lines, stopped = time.perf_counter(), [], None
        errors = tempfile.TemporaryFile("w+")
        with subprocess.Popen(command, stdout=subprocess.PIPE, stderr=errors, text=True,
                              cwd=HERE.parent) as proc:
            for text in proc.stdout:
                item = json.loads(text)
                if "stopped" in item:
                    stopped = item["stopped"]
                    continue
                lines.append(item)
                if item["fit"] % 10 == 0 or item["fit"] == 1:
                    print(f"{side}: fit {item['fit']}: {item['elapsed_s']:.0f} s so far, "
                          f"resident {item['rss_mb']:.0f} MB, peak {item['peak_rss_mb']:.0f} MB",
                          flush=True)
        if proc.returncode:
            errors.seek(0)
            last = [x.strip() for x in errors if x.strip() and "Warning" not in x][-2:]
            stopped = (f"the process ended with status {proc.returncode} after {len(lines)} "
                       f"fits: {' / '.join(last)}")
        out["sides"][side] = _summary(side, lines, stopped, time.perf_counter() - start)
        out["machine"] = _machine(load_before)
        if options.out:
            pathlib.Path(options.out).write_text(json.dumps(out, indent=2) + "\n")
    return out


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fits", type=int, default=100)
    parser.add_argument("--chains", type=int, default=2)
    parser.add_argument("--draws", type=int, default=100, help="warm-up = draws per chain")
    parser.add_argument("--sides", default="after,before")
    parser.add_argument("--side", default=None, help=argparse.SUPPRESS)
    parser.add_argument("--max-rss-gb", type=float, default=6.0)
    parser.add_argument("--max-minutes", type=float, default=120.0)
    parser.add_argument("--note", default="", help="e.g. whether the machine was shared")
    parser.add_argument("--out", default=None, help="the results JSON")
    options = parser.parse_args()
    if options.side is not None:
        run_side(options.side, options.fits, options.chains, options.draws,
                 options.max_rss_gb, options.max_minutes)
    else:
        result = main(options)
        for side in result["sides"].values():
            print(json.dumps({k: v for k, v in side.items() if k != "per_fit"}, indent=2))
