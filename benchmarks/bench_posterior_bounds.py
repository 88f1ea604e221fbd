"""Bounding analysis from a posterior beside property modification factors: the Table 2
building under a record suite, `run --suite --property-factors posterior` against
`--property-factors 0.85,1.3`, on the same bearing file.

The bearing file: test No. 75 of Constantinou, Mokha & Reinhorn (1990) simulated (UF PTFE at
1000 psi, sine 4 in at 0.6 Hz, 2 cycles at 200 Hz, 2 % force noise; `bench_bayes._record`),
fitted by least squares (the point estimate) and by NUTS (4 chains x `--draws` warm-up and
draws), the posterior thinned to at most 400 draws and saved beside the point.

The suite: PEER NGA-West2 RSN6 (El Centro 1940, ELC180 and ELC270, 0.01 s, first 40 s) as
recorded, x1.5, with its components swapped, and swapped x1.5 (from ../shared/data/external or
TEFLON_JAX_EXTERNAL_DATA). Both bounding runs are the `teflon-jax run` commands printed in the
markdown, run one after the other in this process's machine.

    python benchmarks/bench_posterior_bounds.py [--draws N] [--note TEXT]
        [--out results/posterior-bounds-NAME]   (writes NAME.json and NAME.md)
"""

import argparse
import json
import os
import pathlib
import platform
import subprocess
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
RSN6 = ("elcentro1940_peer_nga_rsn6", "RSN6_IMPVALL.I_I-ELC180-hor1.AT2", "RSN6_IMPVALL.I_I-ELC270-hor2.AT2")
PAIRS = (("design", 0, 1.0), ("mce", 0, 1.5), ("rotated", 1, 1.0), ("rotated_mce", 1, 1.5))


def posterior_bearing(path: pathlib.Path, draws: int) -> dict:
    """Fit the record by least squares and NUTS and write the bearing file with its posterior."""
    import jax

    jax.config.update("jax_enable_x64", True)
    sys.path.insert(0, str(HERE))
    from bench_bayes import _record

    from identification.bayes import fit_bayes
    from identification.bearing_fit import fit_bearing_test, fitted_bearing
    from teflon_jax.formats import save_bearing, thinned_posterior

    record = _record(200.0, 2)
    start = time.perf_counter()
    fit = fit_bearing_test(record)
    result = fit_bayes(record, num_warmup=draws, num_samples=draws, num_chains=4, least_squares=fit)
    posterior = thinned_posterior({n: result.draws[n] for n in result.free},
                                  {n: result.table[n]["ess_bulk"] for n in result.free},
                                  max_draws=400, chains=result.num_chains, seed=0)
    save_bearing(path, fitted_bearing(fit), sources=["test No. 75, simulated, 2 % noise"], posterior=posterior)
    return {"fit_s": time.perf_counter() - start, "converged": result.converged, "divergences": result.divergences,
            "max_rhat": max(r["rhat"] for r in result.table.values()),
            "min_ess_bulk": min(r["ess_bulk"] for r in result.table.values()),
            "free": list(result.free), "draws_kept": posterior.size,
            "point": {n: float(fit.parameters[n]) for n in ("f_max", "delta_f", "rate_a")},
            "posterior_5_95": {n: [posterior.quantile(n, 0.05), posterior.quantile(n, 0.95)]
                               for n in ("f_max", "delta_f", "rate_a")}}


def suite_file(folder: pathlib.Path) -> pathlib.Path:
    from teflon_jax.formats import external_data_dir

    source = external_data_dir() / RSN6[0]
    records = [source / RSN6[1], source / RSN6[2]]
    rows = [f"{records[i]},{records[1 - i]},{scale},{name}" for name, i, scale in PAIRS]
    path = folder / "suite.csv"
    path.write_text("record_x,record_y,scale,name\n" + "\n".join(rows) + "\n")
    return path


def run(command: list, folder: pathlib.Path) -> tuple[float, str]:
    start = time.perf_counter()
    done = subprocess.run(command, cwd=folder, capture_output=True, text=True)
    if done.returncode not in (0, 1):
        raise RuntimeError(f"{' '.join(command)} exited {done.returncode}:\n{done.stderr}")
    return time.perf_counter() - start, done.stdout


def _table(runs: dict) -> list:
    """Markdown rows: each peak's mean per case in both runs, and the governing case."""
    lines = ["| mean peak over the 4 pairs | bounds | nominal | upper | lower | governs |", "|---|---|---|---|---|---|"]
    first = next(iter(runs.values()))
    for peak in first["governs"]:
        for label, data in runs.items():
            cells = [f"{data['cases'][c]['summary'][peak]['mean']:.4g}" for c in ("nominal", "upper", "lower")]
            lines.append(f"| {peak} | {label} | {' | '.join(cells)} | {data['governs'][peak]['by_mean']} |")
    return lines


def _factors(runs: dict) -> list:
    lines = ["| bounds | case | f_max | delta_f | rate_a | f_min = f_max - delta_f |", "|---|---|---|---|---|---|"]
    for label, data in runs.items():
        table = data["property_factors"]["factors"]
        for case in ("upper", "lower"):
            lines.append(f"| {label} | {case} | " + " | ".join(f"{table[case][k]:.3f}" for k in
                                                                 ("f_max", "delta_f", "rate_a", "f_min")) + " |")
    return lines


def main(options) -> dict:
    folder = pathlib.Path(options.work).resolve()
    folder.mkdir(parents=True, exist_ok=True)
    load_before = os.getloadavg()
    fit = posterior_bearing(folder / "bearing.json", options.draws)
    suite = suite_file(folder)
    exe = str(pathlib.Path(sys.executable).with_name("teflon-jax"))
    common = ["run", "--suite", suite.name, "--structure", "building", "--isolation-period", "2.5s",
              "--duration", "40s", "--bearing", "bearing.json"]
    runs, times, commands = {}, {}, {}
    for label, factors in (("posterior 0.05-0.95", "posterior"), ("factors 0.85,1.3", "0.85,1.3")):
        stem = "posterior" if factors == "posterior" else "factors"
        command = ["teflon-jax", *common, "--property-factors", factors, "--json", f"{stem}.json"]
        times[label], printed = run([exe, *command[1:]], folder)
        commands[label] = " ".join(command)
        runs[label] = json.loads((folder / f"{stem}.json").read_text())
        runs[label]["printed"] = printed
    same_nominal = all(runs["posterior 0.05-0.95"]["cases"]["nominal"]["pairs"][p] ==
                       runs["factors 0.85,1.3"]["cases"]["nominal"]["pairs"][p] for p, _, _ in PAIRS)
    return {"name": "posterior-bounds", "fit": fit, "commands": commands, "wall_s": times,
            "nominal_identical_in_both_runs": same_nominal,
            "runs": {k: {key: v[key] for key in ("property_factors", "cases", "governs")} for k, v in runs.items()},
            "printed": {k: v["printed"] for k, v in runs.items()},
            "markdown": {"peaks": _table(runs), "factors": _factors(runs)},
            "cpu_count": os.cpu_count(), "load_average_1_5_15_min_before": list(load_before),
            "load_average_1_5_15_min_after": list(os.getloadavg()), "platform": platform.platform(),
            "python": platform.python_version(), "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}


def _spread(out: dict, peak: str) -> str:
    """How far each run's bound cases move the mean of `peak` from the nominal's, in %."""
    parts = []
    for label, data in out["runs"].items():
        nominal = data["cases"]["nominal"]["summary"][peak]["mean"]
        moves = [100 * (data["cases"][c]["summary"][peak]["mean"] / nominal - 1) for c in ("upper", "lower")]
        parts.append(f"{label} {moves[0]:+.1f} % (upper) and {moves[1]:+.1f} % (lower)")
    return f"{peak}: " + "; ".join(parts)


def write_markdown(out: dict, path: pathlib.Path, note: str) -> None:
    fit = out["fit"]
    verdict = ("converged by its own criteria" if fit["converged"] else
               f"not marked converged: its largest R-hat, {fit['max_rhat']:.4f}, is above the sampler's 1.01")
    text = [
        "# Bounds from a posterior against property modification factors",
        "",
        f"`benchmarks/bench_posterior_bounds.py`, {out['date_utc']}, {out['platform']}, {out['cpu_count']} CPUs "
        f"({note}). The Table 2 building on a bearing fitted to a simulated test No. 75 (UF, 1000 psi, 2 % noise): "
        f"least squares for the point, NUTS for the posterior (R-hat <= {fit['max_rhat']:.3f}, bulk ESS >= "
        f"{fit['min_ess_bulk']:.0f}, {fit['divergences']} divergences, {fit['draws_kept']} draws kept). Suite: "
        "PEER RSN6 (El Centro 1940, ELC180/ELC270, first 40 s) as recorded, x1.5, components swapped, swapped x1.5.",
        "",
        f"Made by `python benchmarks/bench_posterior_bounds.py --note '{note}' --out benchmarks/results/"
        f"{path.with_suffix('').name}` (the fit, the bearing file and both commands). The two commands, in the "
        "folder it made (`suite.csv`, `bearing.json`):",
        "",
        "```bash",
        *out["commands"].values(),
        "```",
        "",
        "Mean peak over the pairs per case (displacements in m) and the governing case:",
        "",
        *out["markdown"]["peaks"],
        "",
        "The bound cases' Eq. 1 constants over the point estimate's (the posterior's each at its own quantile, "
        "in the direction of more friction for the upper case at every velocity):",
        "",
        *out["markdown"]["factors"],
        "",
        "How far the bound cases move each mean from the nominal's:",
        "",
        *(f"- {_spread(out, peak)}" for peak in ("base_disp_resultant_m", "base_shear_ratio_resultant")),
        "",
        f"The posterior (NUTS, 4 chains, {verdict}) holds what one simulated test says of that "
        "bearing; its bounds move the peaks far less than the factors, which also stand for ageing, "
        "temperature, contamination and the scatter between bearings. Governing case (by the mean) "
        "with each bounds: " + "; ".join(
            f"{peak} " + " / ".join(data["governs"][peak]["by_mean"] for data in out["runs"].values())
            for peak in next(iter(out["runs"].values()))["governs"]) + ".",
        "",
        "Wall time of each command (3 compilations each): "
        + ", ".join(f"{k} {v:.0f} s" for k, v in out["wall_s"].items())
        + f"; nominal peaks identical in both runs: {out['nominal_identical_in_both_runs']}.",
        "",
    ]
    path.write_text("\n".join(text))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--draws", type=int, default=300, help="NUTS warm-up and draws per chain (4 chains)")
    parser.add_argument("--work", default="posterior-bounds-work", help="folder of the bearing, suite and outputs")
    parser.add_argument("--note", default="", help="e.g. whether the machine was shared")
    parser.add_argument("--out", default=None, help="results/NAME: write NAME.json and NAME.md")
    parser.add_argument("--markdown-from", default=None, metavar="NAME.json",
                        help="only rewrite NAME.md from the results NAME.json of an earlier run")
    options = parser.parse_args()
    if options.markdown_from:
        earlier = json.loads(pathlib.Path(options.markdown_from).read_text())
        write_markdown(earlier, pathlib.Path(options.markdown_from).with_suffix(".md"), earlier["note"])
        sys.exit(0)
    out = main(options)
    out["note"] = options.note
    print("\n".join(out["markdown"]["peaks"] + [""] + out["markdown"]["factors"]))
    if options.out:
        stem = pathlib.Path(options.out)
        stem.with_suffix(".json").write_text(json.dumps(out, indent=2) + "\n")
        write_markdown(out, stem.with_suffix(".md"), options.note)
