"""The `teflon-jax montecarlo` outputs of every isolator, structure and component count, dumped
from one tree and compared with another's.

    PYTHONPATH=<tree> python benchmarks/montecarlo_numbers.py dump DIR [--cases flat,...] [--no-csv]
    python benchmarks/montecarlo_numbers.py compare DIR_A DIR_B

Each case writes its summary JSON and its results as .nc and .csv (3 motions of 6 s; files
already there are kept); `compare`
prints, per case and file, the largest relative difference of every number, naming the key
where it exceeds 1e-12.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ISOLATORS = {"flat": [], "single-fp": ["--radius", "2.24m"],
             "double-fp": ["--isolator-file", str(HERE / "double_isolator.json")],
             "triple-fp": ["--isolator-file", str(HERE / "triple_isolator.json")]}
TIMING = ("wall", "compile", "records_per_s", "elapsed", "seconds")
"""Keys of the summary JSON that are timings, not results (left out of `compare`)."""
BASE = ["--motions", "3", "--duration", "6s", "--strong-motion", "3s", "--no-progress", "--seed", "3"]


def cases():
    for isolator, flags in ISOLATORS.items():
        for structure in ("rigid", "building"):
            for components in ("1", "2"):
                extra = ["--storeys"] if structure == "building" else []
                yield (f"{isolator}-{structure}-{components}c", ["--isolator", isolator, *flags, "--structure",
                                                                  structure, "--components", components, *extra])
            yield (f"{isolator}-{structure}-1c-z", ["--isolator", isolator, *flags, "--structure", structure,
                                                    "--vertical-ratio", "1.5"])


def dump(directory, only=None, suffixes=(".nc", ".csv")):
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    for name, flags in cases():
        if only and not any(name.startswith(o) for o in only):
            continue
        for suffix in suffixes:
            if (directory / f"{name}{suffix}").exists():
                continue
            argv = [sys.executable, "-m", "teflon_jax", "montecarlo", *BASE, *flags,
                    "--out", str(directory / f"{name}{suffix}")]
            if suffix == ".nc":
                argv += ["--json", str(directory / f"{name}.json")]
            done = subprocess.run(argv, capture_output=True, text=True, env=os.environ)
            status = "ok" if done.returncode == 0 else f"FAILED {done.returncode}: {done.stderr[-600:]}"
            print(name, suffix, status, flush=True)


def _numbers(tree, prefix=""):
    if isinstance(tree, dict):
        for k, v in tree.items():
            yield from _numbers(v, f"{prefix}/{k}")
    elif isinstance(tree, list):
        for i, v in enumerate(tree):
            yield from _numbers(v, f"{prefix}[{i}]")
    elif isinstance(tree, (int, float)) and not isinstance(tree, bool):
        yield prefix, float(tree)


def _rel(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape:
        return np.inf
    scale = np.maximum(np.abs(a), np.abs(b))
    diff = np.where(scale > 0, np.abs(a - b) / np.where(scale > 0, scale, 1), 0.0)
    return float(np.nanmax(diff)) if diff.size else 0.0


def compare(first, second):
    import xarray as xr

    first, second = Path(first), Path(second)
    for path in sorted(first.glob("*")):
        other = second / path.name
        if not other.exists():
            print(path.name, "missing in", second)
            continue
        worst = {}
        if path.suffix == ".json":
            a = dict(_numbers(json.loads(path.read_text())))
            b = dict(_numbers(json.loads(other.read_text())))
            for key in a.keys() | b.keys():
                if any(word in key for word in TIMING):
                    continue
                worst[key] = np.inf if key not in a or key not in b else _rel(a[key], b[key])
        elif path.suffix == ".nc":
            a, b = xr.open_dataset(path), xr.open_dataset(other)
            for key in set(a.data_vars) | set(b.data_vars):
                worst[key] = np.inf if key not in a or key not in b else _rel(a[key].values, b[key].values)
        elif path.suffix == ".csv":
            import pandas as pd

            a, b = pd.read_csv(path), pd.read_csv(other)
            for key in set(a.columns) | set(b.columns):
                if key not in a or key not in b:
                    worst[key] = np.inf
                elif np.issubdtype(a[key].dtype, np.number):
                    worst[key] = _rel(a[key].values, b[key].values)
        large = {k: v for k, v in worst.items() if v > 1e-12}
        top = max(worst.values(), default=0.0)
        print(f"{path.name}: {len(worst)} fields, largest relative difference {top:.2e}"
              + (f"; over 1e-12: {sorted(large.items())[:8]}" if large else ""))


if __name__ == "__main__":
    if sys.argv[1] == "dump":
        only = sys.argv[sys.argv.index("--cases") + 1].split(",") if "--cases" in sys.argv else None
        dump(sys.argv[2], only, (".nc",) if "--no-csv" in sys.argv else (".nc", ".csv"))
    else:
        compare(sys.argv[2], sys.argv[3])
