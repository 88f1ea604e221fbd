"""What a Monte Carlo at one intensity reports: the summary JSON (`summary_payload`, with the
run's devices and speed of `throughput`, which a run over intensity levels writes too), the
results file's attributes (`run_attributes`), the converged runs' statistics (`statistics`),
the plot's title (`stamp`) and the printed lines with the exit status (`report`)."""

import math
import sys
import time

from ..units import STANDARD_GRAVITY
from ._run_stop import TIPPING, TIPPING_REMEDY


def steady_rate(marks) -> float | None:
    """Motions per second from the end of the first chunk to the end of the last, as B3
    counts them (`benchmarks/bench_gpu.py`): without the compilation and the first chunk's
    start-up on the device; `None` with a single chunk."""
    if len(marks) < 2 or marks[-1][0] <= marks[0][0]:
        return None
    return (marks[-1][1] - marks[0][1]) / (marks[-1][0] - marks[0][0])


def chunk_marks(bar) -> tuple:
    """(progress(done, total), marks): the progress callback of a Monte Carlo, which moves `bar`
    (a tqdm bar) to `done` runs and appends (time [s], runs done) to `marks` after each chunk,
    the list `steady_rate` reads."""
    marks = []

    def progress(done, _total):
        marks.append((time.perf_counter(), done))
        bar.update(done - bar.n)

    return progress, marks


def throughput(result, marks) -> dict:
    """The run's devices and speed in a Monte Carlo's summary JSON, one level or several:
    `devices` (JAX devices, or a cluster's workers), `device_kind` (this process's first
    device), `wall_s` and `compile_s` [s], `records_per_s` (runs per second less compilation:
    N motions, K N with K bearing draws, over all levels) and
    `records_per_s_after_first_chunk` (`steady_rate` of `marks`, `chunk_marks`)."""
    import jax
    import numpy as np

    runs = int(np.size(result.converged))  # (N,) or (K, N): every run, over all levels
    return {"devices": result.n_devices, "device_kind": jax.devices()[0].device_kind,
            "wall_s": result.wall_s, "compile_s": result.compile_s,
            "records_per_s": runs / max(result.wall_s - result.compile_s, 1e-9),
            "records_per_s_after_first_chunk": steady_rate(marks)}


def run_words(result) -> str:
    """"on D device(s) in T s": where and how long a Monte Carlo ran, as its first printed line
    says it."""
    return f"on {result.n_devices} device(s) in {result.wall_s:.1f} s"


def summary_payload(args, result, structure, model, units, stats, files, marks) -> dict:
    """The summary JSON of `teflon-jax montecarlo` (displacements in `units`; `marks`: the
    progress marks of `chunk_marks`)."""
    import numpy as np

    from ._provenance import isolator_as_run

    converged, two, length = np.asarray(result.converged, bool).reshape(-1), args.components == 2, units.length[0]
    payload = {
        "n_motions": result.n_motions,
        "n_converged": int(converged.sum()),
        "not_converged": np.flatnonzero(~converged).tolist(),
        **({} if result.beyond_pressure_law is None else {
            "beyond_pressure_law": np.flatnonzero(result.beyond_flags.reshape(-1)).tolist()}),
        "structure": args.structure,
        **throughput(result, marks),
        "chunk_size": result.chunk_size,
        "time_step_s": structure.time_step,
        "all_converged": bool(converged.all()),
        "statistics": stats,
        "design": isolator_as_run(args, units.pressure),
        "motions": {"model": "Clough-Penzien, Jennings-Housner-Tsai envelope",
                    "pga_g": pga_levels_g(args), "duration_s": args.duration,
                    "seed": args.seed, "components": args.components},
        "units": {"base_disp": length, "base_shear_ratio": "-", "wall_s": "s"},
        "files": files,
    }
    if two:
        payload["motions"].update({
            "principal_angle_deg": math.degrees(float(model.principal_angle)),
            "minor_ratio": float(model.minor_ratio),
            "peaks": "resultants of the x and y components: |(d_x, d_y)| and |(V_x, V_y)| / W, V the "
                     "force on the structure above the bearings"})
    return payload


def pga_levels_g(args) -> list[float]:
    """The summary's `motions.pga_g`: the PGA of every `--pga` level [g], a list in every run
    (one value without levels)."""
    return [level / STANDARD_GRAVITY for level in args.pga_levels]


def run_attributes(args) -> dict:
    """What was run, as the results file's attributes: the structure, the isolator and bearings
    as run (`isolator_as_run`, SI: a bearing or isolator file by its path and SHA-256, not the
    flags it replaced), the motions and their seed, each also as the user typed it, and the
    provenance of every result (`provenance_attributes`: version, command line, inputs)."""
    from ._provenance import isolator_as_run, provenance_attributes, replaced_flags

    replaced = replaced_flags(args)
    typed = [k for k in ("pressure", "isolation_period", "isolation_damping", "pga", "duration")
             if "--" + k.replace("_", "-") not in replaced]
    return {"structure": args.structure, **isolator_as_run(args), "pga_m_s2": args.pga, "duration_s": args.duration,
            "record_step_s": args.record_step, "seed": args.seed, "site_frequency_hz": args.site_frequency,
            "site_damping": args.site_damping, "strong_motion_s": args.strong_motion, "components": args.components,
            "inputs_as_given": " ".join(f"{k}={getattr(args, k + '_text')}" for k in typed),
            **provenance_attributes()}


def statistics(result, units) -> dict:
    """The converged runs' percentiles, mean and standard deviation (`result.percentiles()`,
    each with the count `n` it rests on), the displacement in the output units."""
    stats = result.percentiles()
    factor = units.length[1]
    disp = {k: (v if k == "n" or v is None else v / factor) for k, v in stats["base_disp_m"].items()}
    return {f"base_disp_{units.length[0]}": disp, "base_shear_ratio": stats["base_shear_ratio"]}


def statistics_lines(stats, units) -> list[str]:
    """The printed lines of `statistics` (one per peak: "base_disp_in: p5 0.55 in, ..."), as
    every Monte Carlo prints them, over one level or each of several."""
    lines = []
    for name, values in stats.items():
        unit = f" {units.length[0]}" if name.startswith("base_disp") else ""
        lines.append(f"{name}: " + ", ".join(f"{k} {v:.4g}{unit}" for k, v in values.items()
                                             if k != "n" and v is not None))
    return lines


def stamp(args, horizontal) -> str:
    """The plot's title: structure, bearing, isolation system and motions as typed."""
    bearing_words = (f"{args.ptfe} PTFE at {args.pressure_text}" if args.bearing is None
                     else f"bearing {args.bearing}")
    return (f"{args.structure}, {bearing_words}, Tb = "
            f"{args.isolation_period_text}, zeta_b = {args.isolation_damping_text}; "
            f"Clough-Penzien motions, PGA {args.pga_text}, {args.duration_text}, seed {args.seed}"
            + (f"; 2 components, major at {math.degrees(float(horizontal.principal_angle)):g} deg, minor "
               f"ratio {float(horizontal.minor_ratio):g}" if args.components == 2 else "")
            + (f"; vertical {args.vertical_ratio:g} x PGA" if args.vertical_ratio is not None else ""))


def listed(labels) -> str:
    """The first 20 of `labels` (run indices, "case:motion", ...) as one comma-separated text,
    "..." after them where there are more."""
    labels = [str(label) for label in labels]
    return ", ".join(labels[:20]) + (" ..." if len(labels) > 20 else "")


def beyond_law_words(named: str) -> str:
    """What the runs beyond Table 1's pressure law (`named`: "motion indices 3, 7", as the
    user reads them) did, and what to do."""
    from ..systems import LAW_REACH

    return (f"({named}) took the bearings' contact pressure {LAW_REACH}; "
            "they are left out of the statistics and flagged in the results ('beyond_pressure_law'). Give the "
            "bearing's constants at such pressures (--bearing, a file with a pressure dependence) or a "
            "lighter --vertical-ratio.")


def report(args, result, stats, units, more_lines) -> int:
    """Print the runs' statistics (and `more_lines`: the uplift, the bearing posterior) and name
    the runs that did not converge; the exit status (1 when some did not)."""
    import numpy as np

    converged = np.asarray(result.converged, bool).reshape(-1)
    print(f"{result.n_motions} motions {run_words(result)}; "
          f"statistics over the {int(converged.sum())} of {converged.size} runs that converged:")
    for line in statistics_lines(stats, units):
        print("  " + line)
    for line in more_lines:
        print(line)
    beyond = result.beyond_flags.reshape(-1)
    if beyond.any():
        runs = np.flatnonzero(beyond)
        print(f"teflon-jax montecarlo: {runs.size} of {converged.size} runs "
              f"{beyond_law_words('motion indices ' + listed(runs))}", file=sys.stderr)
    failed = ~converged & ~beyond
    if not failed.any():
        return int(beyond.any())
    parts = unbalanced_parts(failed, result.tipped_flags.reshape(-1),
                             lambda runs: "motion indices " + listed(np.flatnonzero(runs)), getattr(args, "float32", False),
                             getattr(args, "newton_iterations", None) is not None)
    for count, why, advice in parts:
        print(f"teflon-jax montecarlo: {count} of {converged.size} runs had a time step {why}; they are left "
              f"out of the statistics and flagged in the results ('converged'). {advice}", file=sys.stderr)
    return 1


def unbalanced_parts(failed, tipped, names, float32: bool = False,
                     capped: bool = False) -> list[tuple[int, str, str]]:
    """[(count, why, what to do)] of the runs `failed` (bool) with a step that did not balance,
    `names(mask)` naming a set of them: those whose first unbalanced step tipped the slab or
    the building's base on a plan's overturning loads (`tipped`, bool of the same shape:
    `MonteCarloResult.tipped_flags`), which a smaller step does not mend, and those whose
    Newton solve did not converge (`float32`: run in single precision; `capped`: under a
    --newton-iterations of the user's)."""
    import numpy as np

    failed = np.asarray(failed, bool)
    tipped = failed & np.asarray(tipped, bool)
    newton = failed & ~tipped
    parts = []
    if tipped.any():
        parts.append((int(tipped.sum()), "on which the slab (or the building's base) tipped, its overturning moment "
                      f"beyond {TIPPING} ({names(tipped)})", f"{TIPPING_REMEDY.capitalize()} "
                      "or weaken the motions; a smaller --time-step does not mend it."))
    if newton.any():
        advice = ("Single precision is too coarse for the bearing's Newton solve: drop --float32." if float32
                  else "Raise --newton-iterations (or leave it out, for the library's), or try a smaller "
                  "--time-step." if capped else "Try a smaller --time-step.")
        parts.append((int(newton.sum()), f"whose Newton solve did not converge ({names(newton)})", advice))
    return parts


def group_summary(result, units) -> tuple[dict, list]:
    """({name: ...}, printed lines) of a structure on a plan whose groups share the
    weight unevenly, over the converged runs: each group's largest normal load (p50, p84, max),
    least (min, p16, p50), both in `units`' force, and the runs in which it lifted (N_g <= 0);
    ({}, []) without groups."""
    import numpy as np

    if result.group_peak_load is None:
        return {}, []
    ok = np.asarray(result.converged, bool)
    unit, factor = units.force
    peak, least = np.asarray(result.group_peak_load)[ok] / factor, np.asarray(result.group_min_load)[ok] / factor
    lifted = np.asarray(result.group_uplift_time)[ok] > 0
    def stats(values, qs, extreme, word):
        if not values.size:
            return {}
        return {f"p{q}": float(np.percentile(values, q)) for q in qs} | {word: float(extreme(values))}

    groups, lines = {}, [f"bearing groups' normal loads [{unit}] over the {int(ok.sum())} converged runs:"]
    for j, name in enumerate(result.group_names):
        groups[name] = {"peak_load": stats(peak[:, j], (50, 84), np.max, "max"),
                        "min_load": stats(least[:, j], (16, 50), np.min, "min"),
                        "n_uplifted": int(lifted[:, j].sum())}
        entry = groups[name]
        lines.append(f"  {name}: largest " + ", ".join(f"{k} {v:.4g}" for k, v in entry["peak_load"].items())
                     + "; least " + ", ".join(f"{k} {v:.4g}" for k, v in entry["min_load"].items())
                     + f"; lifted in {entry['n_uplifted']} runs")
    return groups, lines


def slider_capacities(structure):
    """(G, S) [m]: each slider's travel before its restrainer in the series model
    (`series_capacities`: a double pendulum's surface capacities d; a triple pendulum's inner
    pair together) of the pendulum of `structure` (stacked on a plan: per group), or `None`
    without sliders."""
    import numpy as np

    pendulum = getattr(structure, "pendulum", None)
    if pendulum is None:
        return None
    capacities = np.asarray(pendulum.series_capacities(), float)
    return capacities.T if capacities.ndim == 2 else capacities[None]


def capacity_attributes(structure) -> dict:
    """{"slider_capacities_m": (G, S) nested lists} of `slider_capacities`, a results file's
    record of each slider's travel before its restrainer; {} without sliders."""
    capacities = slider_capacities(structure)
    return {} if capacities is None else {"slider_capacities_m": capacities.tolist()}


def surface_summary(result, units) -> tuple[dict, list]:
    """({name: {[group: ]{surface: {"p50", "p84", "max"}}}}, printed lines) of the isolator's
    surfaces over the converged runs: each series-pendulum slider's peak travel in `units`'
    length ("slider_travel_<unit>"), with the capacities the result keeps
    (`attrs["slider_capacities_m"]`, `capacity_attributes`) also its capacity ("capacity", in
    the same unit) and the runs in which it went beyond it onto the restrainer
    ("n_on_restrainer"), and each heated
    surface's peak temperature rise ("surface_temperature_rise_K"), per bearing group where a
    plan has several; ({}, []) without them."""
    import numpy as np

    from ..studies import SURFACE_VARIABLES

    ok = np.asarray(result.converged, bool)
    capacities = result.attrs.get("slider_capacities_m")
    capacities = None if capacities is None else np.asarray(capacities, float)
    summary, lines = {}, []
    for name, (_, labels) in result.surfaces.items():
        si_unit = SURFACE_VARIABLES[name][1]
        unit, factor = units.length if si_unit == "m" else (si_unit, 1.0)
        values = np.asarray(getattr(result, name))[ok]  # (runs, G, S) [SI]
        limits = capacities if name == "slider_travel" else None
        words = name.replace("_", " ")
        per_group = {}
        for j, group in enumerate(result.group_names):
            row = {label: _surface_stats(values[:, j, e], factor, None if limits is None else limits[j, e])
                   for e, label in enumerate(labels)}
            per_group[group] = row
            where = f" ({group})" if len(result.group_names) > 1 else ""
            lines.append(f"{words}{where} [{unit}] over the {int(ok.sum())} converged runs: " + "; ".join(
                f"{label} " + ", ".join(f"{k} {stats[k]:.4g}" for k in ("p50", "p84", "max") if k in stats)
                + (f" (capacity {stats['capacity']:.4g}, on its restrainer in {stats['n_on_restrainer']} runs)"
                   if "n_on_restrainer" in stats else "")
                for label, stats in row.items()))
        summary[f"{name}_{unit}"] = per_group if len(per_group) > 1 else next(iter(per_group.values()))
    return summary, lines


def _surface_stats(values, factor: float, capacity=None) -> dict:
    """p50, p84 and max of `values` [SI] in units of `factor`, with a `capacity` [m] the runs
    beyond it; {} over no run."""
    import numpy as np

    if not values.size:
        return {}
    stats = {"p50": float(np.percentile(values, 50)) / factor, "p84": float(np.percentile(values, 84)) / factor,
             "max": float(values.max()) / factor}
    if capacity is None:
        return stats
    return stats | {"capacity": float(capacity) / factor, "n_on_restrainer": int(np.sum(values > capacity))}
