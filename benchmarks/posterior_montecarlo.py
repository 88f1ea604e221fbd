"""Monte Carlo over a bearing posterior and ground motions together: its cost, and how the
bearing's share of the peak variance falls as the test record grows.

(a) Records per second of one compiled chunk of motions with a posterior's bearings (one draw
per motion, `monte_carlo(bearings=..., bearing_draw=...)`: the friction constants traced
values gathered per run) against the same chunk with the point bearing as a constant of the
program, on the same motions, on the rigid mass and on the six-storey building of Table 2.
Each side is compiled once (compile times reported apart); then the timed calls alternate,
one bearing, posterior, one bearing, posterior, ... `REPEATS` times each, every call waited for
(`block_until_ready`). Target: the posterior's rate at least 80 % of the one bearing's.

(b) The variance split of the building's peaks (law of total variance, `variance_split`) for
posteriors of a Bayesian fit (`identification.bayes.fit_bayes`, NUTS) of a record of a test
of the same bearing of 3 cycles and of one of 10 cycles: sine of 4 in at 0.6 Hz from rest
at one end, interface UF 1000 psi P of Table 1 (the truth), 5 % force noise, sampled at
200 Hz; the sampled constants f_max, delta_f, rate_a (Y and b held at the truth). Each
posterior's K draws run on the same M motions (`nested=True`); the bearing share must fall
with the longer record. The 95th-percentile base displacement gets its band over the K
draws; the true bearing runs on the same motions for comparison. Figure:
`results/posterior-montecarlo-<tag>.png`.

    python benchmarks/posterior_montecarlo.py [--quick] [--tag NAME] [--note TEXT]

Writes `results/posterior-montecarlo-<tag>.json` and `.md` (machine, versions, load average
before and after, every number). `--quick` runs tiny sizes to check the script. Short NUTS
chains (`CHAINS` x (`WARMUP` + `DRAWS`)) keep the fits within minutes on a shared 2-core
machine; their convergence diagnostics are reported with them.
"""

import argparse
import json
import os
import pathlib
import platform
import sys
import tempfile
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
REPEATS = 3
CHAINS, WARMUP, DRAWS = 4, 150, 100
NOISE, SAMPLING_HZ, FREQUENCY_HZ = 0.05, 200.0, 0.6
SIZES = {"full": {"throughput": {"rigid": 512, "building": 128}, "duration": 20.0, "bearings": 32, "motions": 96},
         "quick": {"throughput": {"rigid": 8, "building": 4}, "duration": 6.0, "bearings": 3, "motions": 4}}


def _setup_jax():
    """JAX as the `teflon-jax` command sets it up: one CPU device per core, double precision
    (call once, before JAX's first computation)."""
    import jax

    jax.config.update("jax_num_cpu_devices", os.cpu_count() or 1)
    jax.config.update("jax_enable_x64", True)
    return jax


def _truth():
    import teflon_jax as tj
    from teflon_jax.units import PSI

    friction, b = tj.interface_parameters("UF", 1000 * PSI, "P")
    return tj.paper_bearing(friction, breakaway_ratio=b)


def _model(duration):
    from teflon_jax.excitation import StochasticGroundMotion
    from teflon_jax.units import STANDARD_GRAVITY

    return StochasticGroundMotion(peak_ground_acceleration=0.3 * STANDARD_GRAVITY, duration=duration,
                                  time_step=0.01, strong_motion_duration=min(10.0, duration / 2))


def _structure(kind, bearing):
    from teflon_jax.systems import MONTE_CARLO_NEWTON_TOLERANCE, isolated_structure

    return isolated_structure(kind, bearing=bearing, newton_tolerance=MONTE_CARLO_NEWTON_TOLERANCE)


def throughput(kind, n_motions, duration, posterior, point) -> dict:
    """(a): records/s of one chunk of `n_motions` with the point bearing and with one draw of
    `posterior` per motion, alternated."""
    import jax

    from teflon_jax.studies import motion_draws
    from teflon_jax.studies._montecarlo import ChunkRunner, _motion_source

    model = _model(duration)
    source, _ = _motion_source(model, n_motions, jax.random.key(0))
    span = (source.samples - 1) * source.time_step
    structure = _structure(kind, point)
    runners = {"one_bearing": ChunkRunner(structure, source, span, None, jax.devices(), n_motions, None, None),
               "posterior": ChunkRunner(structure, source, span, None, jax.devices(), n_motions, None, None,
                                        bearings=posterior.bearings(point))}
    draws = {"one_bearing": None, "posterior": motion_draws(n_motions, posterior.size, seed=0)}
    indices = np.arange(n_motions)
    out = {name: {"compile_s": None, "run_s": []} for name in runners}
    for name, runner in runners.items():  # compile (and a first run) apart
        jax.block_until_ready(runner(indices, draws=draws[name]))
        out[name]["compile_s"] = runner.compile_s
    peaks = {}
    for _ in range(REPEATS):
        for name, runner in runners.items():
            tic = time.perf_counter()
            peaks[name] = jax.block_until_ready(runner(indices, draws=draws[name]))
            out[name]["run_s"].append(time.perf_counter() - tic)
    for entry in out.values():
        entry["records_per_s"] = [n_motions / t for t in entry["run_s"]]
        entry["median_records_per_s"] = float(np.median(entry["records_per_s"]))
    ratio = out["posterior"]["median_records_per_s"] / out["one_bearing"]["median_records_per_s"]
    disp = {name: np.asarray(p[0].base_disp) for name, p in peaks.items()}
    return {"structure": kind, "motions": n_motions, "duration_s": duration, **out,
            "posterior_over_one_bearing": ratio, "meets_80_percent": bool(ratio >= 0.8),
            "peak_disp_median_m": {name: float(np.median(d)) for name, d in disp.items()}}


def test_record(cycles):
    """A record of `cycles` cycles of the true bearing with `NOISE` force noise."""
    import teflon_jax as tj
    from teflon_jax.formats import test_record_from_arrays
    from teflon_jax.units import INCH, KIP

    t = np.arange(0.0, cycles / FREQUENCY_HZ + 1e-9, 1.0 / SAMPLING_HZ)
    u = 4 * INCH * (1.0 - np.cos(2 * np.pi * FREQUENCY_HZ * t))
    load = 78.5 * KIP
    f = np.asarray(tj.imposed_path_test(_truth(), tj.tabulated_motion(t, u), load).fx)
    f = f + NOISE * np.sqrt(np.mean(f**2)) * np.random.default_rng(int(cycles)).standard_normal(f.size)
    return test_record_from_arrays(u, f, time=t, normal_load=load)


def fitted_posterior(cycles, folder, quick) -> dict:
    """The Bayesian fit of a record of `cycles` cycles, written as a bearing file with its
    posterior and read back: (point bearing, `BearingPosterior`, fit summary)."""
    from identification.bayes import fit_bayes
    from identification.bearing_fit import fitted_bearing
    from teflon_jax.formats import load_bearing, load_bearing_posterior, save_bearing

    truth = _truth()
    fixed = {"yield_disp": float(truth.hysteresis.yield_disp), "breakaway_ratio": float(truth.breakaway_ratio)}
    record = test_record(cycles)
    tic = time.perf_counter()
    warmup, draws = (100, 100) if quick else (WARMUP, DRAWS)
    result = fit_bayes(record, free=("f_max", "delta_f", "rate_a"), fixed=fixed, num_warmup=warmup,
                       num_samples=draws, num_chains=CHAINS, seed=int(cycles))
    elapsed = time.perf_counter() - tic
    path = save_bearing(folder / f"bearing-{cycles}-cycles.json", fitted_bearing(result.least_squares),
                        posterior=result.bearing_posterior())
    posterior = load_bearing_posterior(path)
    summary = {"cycles": cycles, "samples": int(record.ux.size), "fit_s": elapsed,
               "chains": CHAINS, "warmup": warmup, "draws_per_chain": draws, "converged": result.converged,
               "divergences": int(result.divergences), "messages": list(result.messages),
               "posterior": {n: {"mean": float(np.mean(posterior.draws[n])), "sd": float(np.std(posterior.draws[n])),
                                 "ess_bulk": posterior.effective_sample_size[n],
                                 "truth": float(getattr(truth.friction, n))} for n in posterior.names},
               "draws_kept": posterior.size}
    return {"point": load_bearing(path), "posterior": posterior, "summary": summary}


def variance_study(fits, n_bearings, n_motions, duration) -> dict:
    """(b): each posterior's K draws and the true bearing on the same M motions of the building."""
    import jax

    from teflon_jax.studies import monte_carlo, nested_draws

    model, out = _model(duration), {}
    truth = monte_carlo(_structure("building", _truth()), model, n_motions, key=jax.random.key(1))
    out["truth_p95_disp_m"] = float(np.percentile(truth.base_disp, 95))
    for cycles, fit in fits.items():
        k = min(n_bearings, fit["posterior"].size)
        result = monte_carlo(_structure("building", fit["point"]), model, n_motions, key=jax.random.key(1),
                             bearings=fit["posterior"].bearings(fit["point"]),
                             bearing_draw=nested_draws(k, fit["posterior"].size, seed=0), nested=True)
        out[cycles] = {"bearings": k, "motions": n_motions, "wall_s": result.wall_s, "compile_s": result.compile_s,
                       "all_converged": bool(np.all(result.converged)),
                       **{name: {"variance": result.variance_split(name),
                                 "p95": result.percentile_band(name, 95.0, (5.0, 95.0))}
                          for name in ("base_disp", "base_shear_ratio")}}
    return out


def figure(study, fits, path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cycles = [c for c in study if isinstance(c, int)]
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    for ax, name, label in ((axes[0], "base_disp", "peak base displacement"),
                            (axes[1], "base_shear_ratio", "peak base shear / weight")):
        shares = [study[c][name]["variance"]["bearing_share"] for c in cycles]
        ax.bar([f"{c} cycles" for c in cycles], shares, color="0.6", edgecolor="k")
        for i, s in enumerate(shares):
            ax.text(i, s, f"{s:.3g}", ha="center", va="bottom")
        ax.set_ylabel("bearing share of the variance [-]")
        ax.set_title(label)
    ax = axes[2]
    for i, c in enumerate(cycles):
        values = np.array(study[c]["base_disp"]["p95"]["per_bearing"]) / 0.0254
        ax.plot(np.full(values.size, i) + np.linspace(-0.1, 0.1, values.size), values, "k.", alpha=0.6)
        low, high = np.array(study[c]["base_disp"]["p95"]["band"]) / 0.0254
        ax.vlines(i + 0.2, low, high, color="k", lw=3, label="5-95 % band" if i == 0 else None)
    ax.axhline(study["truth_p95_disp_m"] / 0.0254, color="r", ls="--", label="true bearing")
    ax.set_xticks(range(len(cycles)), [f"{c} cycles" for c in cycles])
    ax.set_ylabel("95th percentile of the peak base displacement [in]")
    ax.set_title("per-bearing 95th percentile")
    ax.legend(fontsize=8)
    fig.suptitle("Building of Table 2, posterior of f_max, delta_f, rate_a from a test record; "
                 f"{study[cycles[0]]['bearings']} draws x {study[cycles[0]]['motions']} motions", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def markdown(out) -> str:
    lines = [f"# Monte Carlo over a bearing posterior ({out['machine']['date_utc']})", "",
             f"Machine: {out['machine']['cpu_count']} CPU cores ({out['machine']['cpu']}), "
             f"{out['machine']['platform']}, JAX {out['machine']['jax']}, {out['machine']['devices']} "
             f"device(s); load average before {out['machine']['load_before']}, after "
             f"{out['machine']['load_after']}. {out['note']}", "",
             "## (a) records/s, posterior draws against one bearing (median of the alternated calls)", "",
             "| structure | motions | one bearing | posterior | ratio |", "|---|---|---|---|---|"]
    for t in out["throughput"]:
        lines.append(f"| {t['structure']} | {t['motions']} x {t['duration_s']:g} s | "
                     f"{t['one_bearing']['median_records_per_s']:.1f} | {t['posterior']['median_records_per_s']:.1f} | "
                     f"{t['posterior_over_one_bearing']:.2f} |")
    study = out["variance"]
    lines += ["", "## (b) bearing share of the building's peak variance", "",
              "| record | draws kept, ESS (f_max) | sd f_max / truth | share base disp | share base shear | "
              "p95 disp [in] with 5-95 % band |", "|---|---|---|---|---|---|"]
    for c, fit in out["fits"].items():
        s = study[c]
        p = s["base_disp"]["p95"]
        lines.append(f"| {c} cycles | {fit['draws_kept']}, {fit['posterior']['f_max']['ess_bulk']:.0f} | "
                     f"{fit['posterior']['f_max']['sd'] / fit['posterior']['f_max']['truth']:.2e} | "
                     f"{s['base_disp']['variance']['bearing_share']:.3g} | "
                     f"{s['base_shear_ratio']['variance']['bearing_share']:.3g} | "
                     f"{p['pooled'] / 0.0254:.3f} ({p['band'][0] / 0.0254:.3f}-{p['band'][1] / 0.0254:.3f}) |")
    lines += ["", f"True bearing on the same motions: p95 base displacement {study['truth_p95_disp_m'] / 0.0254:.3f} in.",
              f"Share falls with more data: {out['share_falls']}.", ""]
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--tag", default=None)
    parser.add_argument("--note", default="")
    parser.add_argument("--motions", type=int, default=None,
                        help="motions M of the variance study (default 96; more motions make the 95th "
                             "percentile less sensitive to one motion's jump between branches)")
    parser.add_argument("--skip-throughput", action="store_true", help="the variance study alone")
    options = parser.parse_args(argv)
    jax = _setup_jax()
    sys.path.insert(0, str(HERE.parent))
    size = dict(SIZES["quick" if options.quick else "full"])
    if options.motions is not None:
        size["motions"] = options.motions
    load_before = list(os.getloadavg())
    with tempfile.TemporaryDirectory() as folder:
        fits = {c: fitted_posterior(c, pathlib.Path(folder), options.quick) for c in (3, 10)}
    out = {"throughput": [] if options.skip_throughput else [
        throughput(kind, n, size["duration"], fits[3]["posterior"], fits[3]["point"])
        for kind, n in size["throughput"].items()]}
    out["variance"] = variance_study(fits, size["bearings"], size["motions"], size["duration"])
    out["fits"] = {c: f["summary"] for c, f in fits.items()}
    shares = [out["variance"][c]["base_disp"]["variance"]["bearing_share"] for c in (3, 10)]
    out["share_falls"] = bool(shares[1] < shares[0])
    out["machine"] = {"cpu_count": os.cpu_count(), "cpu": platform.processor() or platform.machine(),
                      "platform": platform.platform(), "jax": jax.__version__, "devices": len(jax.devices()),
                      "python": platform.python_version(), "load_before": load_before,
                      "load_after": list(os.getloadavg()),
                      "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
    out["note"] = options.note
    out["sizes"] = size
    out["nuts"] = {"chains": CHAINS, "warmup": WARMUP, "draws": DRAWS, "noise": NOISE, "sampling_hz": SAMPLING_HZ}
    tag = options.tag or ("quick" if options.quick else f"cpu-{os.cpu_count()}core-{time.strftime('%Y%m%d')}")
    stem = HERE / "results" / f"posterior-montecarlo-{tag}"
    stem.with_suffix(".json").write_text(json.dumps(out, indent=2, default=float) + "\n")
    stem.with_suffix(".md").write_text(markdown(out))
    figure(out["variance"], fits, stem.with_suffix(".png"))
    print(markdown(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
