"""`teflon-jax montecarlo` over intensity levels, with limits, fragility curves, storey results
and pelicun demand files (`--pga 0.1g,0.2g,...`, `--limit`, `--storeys`, `--pelicun-demands`).

N motions at each level (`monte_carlo_levels`); for each limit the runs exceeding it are
counted at each level and, with two or more levels, a lognormal fragility is fitted by maximum
likelihood with profile-likelihood intervals (`fit_fragility`; Baker 2015, Earthquake Spectra
31(1)). Failed runs are kept in the files, flagged, and out of the counts and statistics.
With `--scheduler` the motions run as chunks on a Dask cluster
(`monte_carlo_levels_distributed`), their peaks streamed to `--out FILE.nc`, and the counts,
fits, statistics and pelicun files are computed here from those peaks as from an in-process run.
With `--vertical-ratio` the structure and motions carry the vertical component: the uplifted
motions of each level are listed, and stay in the counts and statistics.
With a `--bearing` file's posterior draws every level runs the same draws through the one
compiled program: `--bearing-draws K` runs K bearings on every level's motions, and each
limit gets the fit of all runs and its band over the bearings (`fragility_band`); with one
draw per motion, motion m of every level runs the same draw, and the fit has no band.
"""

import math
import sys

import numpy as np

from ._common import _write_json, motion_bar
from ._engineering import (
    intensity_unit,
    level_paths,
    parse_limits,
    pelicun_peaks,
    wants_storeys,
)
from ._main import compile_cache_dir
from ._montecarlo_summary import (
    beyond_law_words,
    chunk_marks,
    listed,
    pga_levels_g,
    run_words,
    statistics_lines,
    throughput,
    unbalanced_parts,
)
from ._posterior_flags import (
    MOTION_DRAWS_NO_BAND,
    posterior_arguments,
    posterior_levels_entry,
    runs_of,
)


def check_level_outputs(args, n_levels: int) -> None:
    """`ValueError` naming the flag, before any run, for outputs this run cannot write."""
    if args.out is not None and args.scheduler is None:  # with --scheduler: a .nc file (_check_flags)
        from ..studies import check_output_path

        path = check_output_path(args.out)
        if n_levels > 1 and path.suffix not in (".nc", ".zarr"):
            raise ValueError(f"--out {args.out}: the motions' levels are kept in NetCDF or Zarr; name it .nc "
                             "or .zarr (one level: any format).")
    if args.pelicun_demands is not None:
        from ..formats import check_pelicun_path

        check_pelicun_path(args.pelicun_demands)


def _fragility(limit, result, level_index, levels, unit, factor) -> tuple[dict, object]:
    """The JSON entry of one limit and its `FragilityFit` (or the counts when no fit); for K
    bearing draws each run on the motions (`result.nested`) the fit of all runs and its band
    over the draws (`_bearing_band`), the `FragilityBand` in place of the fit."""
    from ..studies import exceedance_counts, fit_fragility

    peaks, converged = limit.peaks(result), np.asarray(result.converged, bool)
    per_draw = None
    if getattr(result, "nested", False):  # (K, L N): the counts of each draw, and of all runs
        per_draw = [exceedance_counts(peaks[k], converged[k], level_index, levels.size, limit.value)
                    for k in range(peaks.shape[0])]
        n_runs, n_exceed = (np.sum([c[i] for c in per_draw], axis=0) for i in (0, 1))
    else:
        n_runs, n_exceed = exceedance_counts(peaks, converged, level_index, levels.size, limit.value)
    entry = {"limit": limit.text, "limit_si": limit.value, "intensity_unit": unit,
             "levels": (levels / factor).tolist(), "n_runs": n_runs.tolist(), "n_exceed": n_exceed.tolist(),
             "fraction": [k / n if n else None for k, n in zip(n_exceed, n_runs)]}
    if levels.size < 2:
        entry["error"] = "a fragility needs two or more --pga levels; the fraction exceeding is given"
        return entry, (levels / factor, np.maximum(n_runs, 1), n_exceed)
    try:
        fit = fit_fragility(levels / factor, n_runs, n_exceed)
    except ValueError as error:
        entry["error"] = f"--limit {limit.text}: {error}"
        return entry, (levels / factor, np.maximum(n_runs, 1), n_exceed)

    def finite(value):
        return value if math.isfinite(value) and value > 0 else None

    entry.update({"median": fit.median, "dispersion": fit.dispersion,
                  "median_interval": [finite(v) for v in fit.median_interval],
                  "dispersion_interval": [finite(v) for v in fit.dispersion_interval],
                  "confidence": fit.confidence, "interval": "profile likelihood (null: not bounded by the data)",
                  "method": "maximum likelihood on the counts at each level (Baker 2015)"})
    if per_draw is None:
        if result.bearing_draw is not None:  # one draw per motion: no band over the draws
            entry.update({"bearing_band": None, "bearing_band_none": MOTION_DRAWS_NO_BAND})
        return entry, fit
    band = _bearing_band(entry, limit, levels / factor, per_draw, result.bearing_draw)
    return entry, fit if band is None else band


BEARING_BAND = 0.90
"""Share of the bearing draws the fragility band spans (its 5 and 95 % percentiles)."""


def _bearing_band(entry, limit, levels, per_draw, draws):
    """`entry["bearing_band"]`: each bearing draw's counts (`n_runs`, `n_exceed` (K, L)), the
    fragility of each draw's runs and their spread (`fragility_band`: medians, dispersions,
    the same percentiles of their intervals' ends, the curve band at the levels); the
    `FragilityBand`, or None (the reason in the entry)."""
    from ..studies import fragility_band

    n_runs = np.stack([c[0] for c in per_draw])
    n_exceed = np.stack([c[1] for c in per_draw])
    try:
        band = fragility_band(levels, n_runs, n_exceed, band=BEARING_BAND)
    except ValueError as error:
        entry["bearing_band"] = {"error": f"--limit {limit.text}: {error}", "n_draws": len(per_draw),
                                 "draws": [int(k) for k in draws], "n_runs": n_runs.tolist(),
                                 "n_exceed": n_exceed.tolist()}
        return None

    def finite(value):
        return value if math.isfinite(value) and value > 0 else None

    below, above = band.probability_band(levels)
    entry["bearing_band"] = {
        "band": band.band, "n_draws": len(per_draw), "n_fitted": len(band.draw_fits),
        "draws": [int(k) for k in draws], "n_runs": n_runs.tolist(), "n_exceed": n_exceed.tolist(),
        "unfitted": {str(int(draws[k])): why for k, why in band.unfitted.items()},
        "median_band": list(band.median_band), "dispersion_band": list(band.dispersion_band),
        "median_interval": [finite(v) for v in band.median_interval],
        "dispersion_interval": [finite(v) for v in band.dispersion_interval],
        "probability_band_at_levels": [below.tolist(), above.tolist()],
        "draw_medians": [finite(v) if np.isfinite(v) else None for v in band.draw_medians],
        "draw_dispersions": [finite(v) if np.isfinite(v) else None for v in band.draw_dispersions],
        "method": "each bearing draw's runs fitted alone; the 5 and 95 % percentiles over the draws of the "
                  "median, the dispersion and the fitted probability, and of the draws' profile-likelihood "
                  "interval ends (the bearing's and the motions' uncertainty together)"}
    return band


def _storey_summary(result, rows, units) -> dict:
    """Median and largest peak drift per storey and total acceleration per level [g] over the
    converged runs of `rows`."""
    from ..units import STANDARD_GRAVITY

    ok = np.asarray(result.converged, bool)[rows]
    drift = np.asarray(result.storey_drift)[rows][ok]
    acc = np.asarray(result.floor_acceleration)[rows][ok] / STANDARD_GRAVITY
    if not ok.any():
        return {"n": 0}
    return {"n": int(ok.sum()), "storey_drift_p50": np.median(drift, 0).tolist(), "storey_drift_max": drift.max(0).tolist(),
            "level_acceleration_g_p50": np.median(acc, 0).tolist(), "level_acceleration_g_max": acc.max(0).tolist(),
            "levels": "0: base slab on the isolators, j: floor j; storeys from 1 (base slab to floor 1)"}


def _motion_range(rows) -> dict:
    """{"first", "last", "count"} of the consecutive motion indices `rows` (one level's)."""
    return {"first": int(rows[0]), "last": int(rows[-1]), "count": int(rows.size)}


def _one_level(per_level) -> dict:
    """The peaks of a one-level run at the top of its summary, as a run without the level
    flags writes them (`statistics`, and `groups` and `surfaces` where it has them); {} over
    several levels, whose peaks are under `levels` only."""
    if len(per_level) != 1:
        return {}
    return {key: per_level[0][key] for key in ("statistics", "groups", "surfaces") if key in per_level[0]}


def _storey_lines(summary) -> list[str]:
    """The printed lines of `_storey_summary`: median and largest peak drift ratio per storey
    [%] and total acceleration per level [g], per direction with two components."""
    if not summary["n"]:
        return []
    lines = []
    for name, key, count, fmt in (("storey drift ratio", "storey_drift", "storeys 1", "{:.3%}"),
                                  ("level acceleration [g]", "level_acceleration_g", "levels 0", "{:.3g}")):
        p50, top = np.asarray(summary[f"{key}_p50"]), np.asarray(summary[f"{key}_max"])
        axes = [("", p50, top)] if p50.ndim == 1 else [(f" in {a}", p50[k], top[k]) for k, a in enumerate("xy")]
        for where, middle, largest in axes:
            end = largest.size if key == "storey_drift" else largest.size - 1
            lines.append(f"  {name}{where}, {count}-{end}: p50 " + " ".join(fmt.format(v) for v in middle)
                         + "; max " + " ".join(fmt.format(v) for v in largest))
    return lines


def _payload(args, structure, units) -> dict:
    from ._provenance import isolator_as_run

    return {"structure": args.structure, "time_step_s": structure.time_step, "chunk_size": args.chunk_size,
            "design": isolator_as_run(args, units.pressure),
            "motions": {"model": "Clough-Penzien, Jennings-Housner-Tsai envelope", "duration_s": args.duration,
                        "seed": args.seed, "components": args.components,
                        "pga_g": pga_levels_g(args)},
            "units": {"base_disp": units.length[0], "base_shear_ratio": "-", "storey_drift": "-",
                      "level_acceleration": "g", "wall_s": "s"}}


def run_levels(args, structure, model, units, statistics, posterior=None) -> int:
    """Run the motions of every level, then write the JSON, the plot, the results file and the
    pelicun files; returns the exit status (0; 1 when a run failed or a fragility could not be
    fitted: everything is written all the same). `statistics(result, units)`: the JSON
    statistics of one level's `MonteCarloResult` (those of a one-level run); `posterior`: the
    `PosteriorRun` of the --bearing file's draws (`read_posterior_flags`), or None."""
    from ..report import plot_fragility, plot_montecarlo
    from ..studies import save_levels
    from ..tables import load_table2
    from ._montecarlo_summary import capacity_attributes, slider_capacities
    from ._normal_load import uplift_payload

    levels = np.asarray(args.pga_levels, float)
    limits = parse_limits(args.limit, args.structure, args.components)
    capacities = slider_capacities(structure)
    for limit in limits:
        if limit.name == "slider_capacity_ratio" and capacities is None:
            raise ValueError(f"--limit {limit.text}: the isolator has no sliders in series; it needs --isolator "
                             "double-fp or triple-fp.")
    height = load_table2().storey_height if wants_storeys(args, limits) else None
    check_level_outputs(args, levels.size)
    unit, factor = intensity_unit(args.pga_text)
    payload = _payload(args, structure, units)
    bearing = f"{args.ptfe} PTFE at {args.pressure_text}" if args.bearing is None else f"bearing {args.bearing}"
    stamp = (f"{args.structure}, {bearing}{_draws_words(posterior)}, Tb = {args.isolation_period_text}, "
             f"zeta_b = {args.isolation_damping_text}; Clough-Penzien motions, {args.motions} per level at PGA "
             f"{args.pga_text}, {args.duration_text}, seed {args.seed}"
             + (f"; vertical {args.vertical_ratio:g} x PGA" if args.vertical_ratio is not None else ""))
    bar = motion_bar(levels.size * runs_of(args, posterior), args.no_progress)
    progress, marks = chunk_marks(bar)  # the rate after the first chunk, as a run without levels gives it
    result, level_index = _run(args, structure, model, levels, height, progress,
                               posterior_arguments(posterior, args.motions))
    bar.close()
    result.attrs.update(capacity_attributes(structure))  # as a file streamed by --scheduler says
    converged = np.asarray(result.converged, bool)  # (L N,), or (K, L N) for K bearings
    files = []
    if args.scheduler is not None:  # streamed there by the cluster's chunks, levels included
        files.append(str(args.out))
    elif args.out is not None:
        if args.out.suffix in (".csv", ".npz"):  # one level only (check_level_outputs)
            files.append(str(result.save(args.out)))
        else:
            files.append(str(save_levels(result, level_index, args.out)))
    if args.pelicun_demands is not None:
        from ..formats import write_pelicun_demands

        length = "in" if units.length[0] == "in" else "mm"
        for j, path in enumerate(level_paths(args.pelicun_demands, levels.size)):
            rows = np.flatnonzero(level_index == j)
            files.append(str(write_pelicun_demands(path, **pelicun_peaks(result, rows, args.components),
                                                   length_unit=length)))
    per_level, printed = [], []  # each level's JSON entry and printed lines
    for j, level in enumerate(levels):
        entry, lines = _level_entry(result, np.flatnonzero(level_index == j), statistics, units,
                                    {f"pga_{unit}": level / factor})
        per_level.append(entry)
        printed.append(lines)
    fragility, curves = {}, {}
    for limit in limits:
        fragility[limit.text], curves[limit.text] = _fragility(limit, result, level_index, levels, unit, factor)
    payload.update({"n_motions": result.n_motions, "motions_per_level": args.motions,
                    "n_converged": int(converged.sum()), "not_converged": _failed_runs(converged),
                    **({} if result.beyond_pressure_law is None else
                       {"beyond_pressure_law": _failed_runs(~result.beyond_flags)}),
                    "all_converged": bool(converged.all()), **throughput(result, marks),
                    **_one_level(per_level), "levels": per_level, "fragility": fragility, "files": files})
    payload["motions"]["pga_levels"] = {"unit": unit, "values": (levels / factor).tolist()}
    payload.update(uplift_payload(result, model))
    payload.update(posterior_levels_entry(result, posterior))
    if result.group_peak_load is not None:
        payload["units"]["group_load"] = units.force[0]
    if "vertical" in payload:
        payload["vertical"]["levels"] = ("the vertical component's expected peak is vertical_ratio times "
                                         "each level's; the uplifted motions of each level under levels[j].uplift")
        if result.storey_drift is not None:
            payload["vertical"]["storeys"] = _VERTICAL_STOREYS
        if args.pelicun_demands is not None:
            payload["vertical"]["pelicun_demands"] = ("horizontal demands of the runs with the vertical "
                                                      "component; no vertical PFA is written (see storeys)")
    _write_json(args.json, payload)
    if args.plot is not None:
        if limits and levels.size > 1:
            plot_fragility(curves, args.plot, unit=unit, factor=1.0, title=stamp)
        else:
            plot_montecarlo(result, args.plot, title=stamp, length=units.length)
    return _report(result, levels, unit, factor, fragility, per_level, printed)


def _level_entry(result, rows, statistics, units, intensity: dict) -> tuple[dict, list]:
    """One level's JSON entry (its `intensity`, the range of its motions `rows`, the converged
    count, `statistics`, and where the run has them its storeys, uplift, groups and surfaces)
    and its printed lines."""
    from ._montecarlo_summary import group_summary, surface_summary
    from ._normal_load import uplift_of

    part = _select(result, rows)
    entry = {**intensity, "motions": _motion_range(rows),
             "n_converged": int(np.asarray(result.converged, bool)[..., rows].sum()),
             "statistics": statistics(part, units)}
    lines = ["  " + line for line in statistics_lines(entry["statistics"], units)]
    if result.storey_drift is not None:
        entry["storeys"] = _storey_summary(result, rows, units)
        lines += _storey_lines(entry["storeys"])
    if result.uplift_time is not None:  # the level's vertical records: N = W (1 + a_v / g) <= 0
        entry["uplift"] = uplift_of(_first_bearing(result.uplift_time, result), rows)
    if result.group_peak_load is not None:  # a plan's groups that share the weight unevenly
        entry["groups"], more = group_summary(part, units)
        lines += more
    if result.surfaces:  # a series pendulum's sliders, the heated surfaces
        entry["surfaces"], more = surface_summary(part, units)
        lines += more
    return entry, lines


def _run(args, structure, model, levels, height, progress, draws):
    """(`MonteCarloResult` of every level's motions, level index of each): in this process
    (`monte_carlo_levels`; `draws`: the keywords of a bearing posterior's draws,
    `posterior_arguments`) or, with --scheduler, as chunks on a Dask cluster streamed to --out
    (`monte_carlo_levels_distributed`: the same motions, chunks and peaks; no draws)."""
    import jax

    if args.scheduler is None:
        from ..studies import monte_carlo_levels

        return monte_carlo_levels(structure, model, levels, args.motions, key=jax.random.key(args.seed),
                                  chunk_size=args.chunk_size, progress=progress, storey_height=height, **draws)
    from ..studies import monte_carlo_levels_distributed
    from ._montecarlo_summary import capacity_attributes

    return monte_carlo_levels_distributed(
        structure, model, levels, args.motions, out=args.out, seed=args.seed, scheduler=args.scheduler,
        chunk_size=args.chunk_size, progress=progress, storey_height=height,
        compilation_cache=None if args.no_compile_cache else str(compile_cache_dir()),
        attrs=capacity_attributes(structure))


_VERTICAL_STOREYS = ("storey drifts and level accelerations are horizontal: the superstructure is rigid "
                     "vertically (every level moves with the ground's a_v; N varies on the isolators only), "
                     "so vertical floor accelerations and column axial loads are not computed")


def _select(result, rows):
    """The motions `rows` of a one-design `MonteCarloResult` (of every bearing of a nested one,
    whose draws per bearing stay; one draw per motion: the rows' draws)."""
    import dataclasses

    axis = result.dims.index("motion")
    picked = {f.name: np.take(getattr(result, f.name), rows, axis=0 if f.name in ("pga", "bearing_draw") else axis)
              for f in dataclasses.fields(result)
              if isinstance(getattr(result, f.name), np.ndarray) and not (f.name == "bearing_draw" and result.nested)}
    return dataclasses.replace(result, **picked)


def _first_bearing(values, result):
    """A per-motion array of the record alone (the uplift time): of the first bearing when nested."""
    return np.asarray(values)[0] if result.nested else values


def _failed_runs(converged) -> list:
    """The runs that did not converge: motion indices, or {"bearing", "motion"} for K bearings."""
    if converged.ndim == 1:
        return np.flatnonzero(~converged).tolist()
    return [{"bearing": int(k), "motion": int(m)} for k, m in np.argwhere(~converged)]


def _draws_words(posterior) -> str:
    if posterior is None:
        return ""
    if posterior.bearings is None:
        return " (a posterior draw per motion, the same at every level)"
    return f" ({posterior.bearings} posterior draws on every level's motions)"


def _report(result, levels, unit, factor, fragility, per_level, printed) -> int:
    """Print the runs, each level's peaks (`printed`: its lines, those of a one-level run
    without the level flags), uplift counts and fragilities, and name the failed runs; the
    exit status."""
    converged = np.asarray(result.converged, bool)
    bearings = f"{converged.shape[0]} bearings x " if converged.ndim == 2 else ""
    print(f"{bearings}{result.n_motions} motions at {levels.size} level(s) {run_words(result)}; "
          f"{int(converged.sum())} of {converged.size} runs converged; statistics over the converged runs"
          + (" of each level:" if levels.size > 1 else ":"))
    for x, entry, lines in zip(levels, per_level, printed):
        if levels.size > 1:
            motions = entry["motions"]
            print(f"  {x / factor:g}{unit} (motions {motions['first']} to {motions['last']}, "
                  f"{entry['n_converged']} runs converged):")
        for line in lines:
            print("  " * (levels.size > 1) + line)
    if result.uplift_time is not None:
        counts = ", ".join(f"{x / factor:g}{unit}: {e['uplift']['n_uplifted']}/{e['motions']['count']}"
                           for x, e in zip(levels, per_level))
        print(f"  uplift (N <= 0), motions per level: {counts}; kept in the statistics and counts")
    status = 0
    for text, entry in fragility.items():
        fractions = ", ".join(f"{x:g}{unit}: {k}/{n}" for x, k, n in zip(entry["levels"], entry["n_exceed"],
                                                                          entry["n_runs"]))
        print(f"  {text}: exceeding {fractions}")
        if "error" in entry:
            print(f"teflon-jax montecarlo: {entry['error']}", file=sys.stderr)
            status = 1 if levels.size > 1 else status
            continue
        low, high = entry["median_interval"]
        print(f"    fragility: median {entry['median']:.4g} {unit} ({_end(low)} - {_end(high)}), dispersion "
              f"{entry['dispersion']:.3g}")
        band = entry.get("bearing_band")
        if band is not None and "error" in band:
            print(f"teflon-jax montecarlo: no band over the bearing draws: {band['error']}", file=sys.stderr)
            status = 1
        elif band is not None:
            low, high = band["median_interval"]
            print(f"    over {band['n_fitted']} of {band['n_draws']} bearing draws ({100 * band['band']:g} % band): "
                  f"median {band['median_band'][0]:.4g} - {band['median_band'][1]:.4g} {unit} ({_end(low)} - "
                  f"{_end(high)} with the motions' sampling), dispersion {band['dispersion_band'][0]:.3g} - "
                  f"{band['dispersion_band'][1]:.3g}")
    beyond = result.beyond_flags
    which = "motion indices" if converged.ndim == 1 else "bearing:motion"

    def names(runs):
        return listed(i if converged.ndim == 1 else f"{i['bearing']}:{i['motion']}" for i in runs)

    if beyond.any():
        runs = _failed_runs(~beyond)
        print(f"teflon-jax montecarlo: {len(runs)} of {converged.size} runs {beyond_law_words(f'{which} {names(runs)}')}",
              file=sys.stderr)
        status = 1
    for count, why, advice in unbalanced_parts(~(converged | beyond), result.tipped_flags,
                                               lambda runs: f"{which} {names(_failed_runs(~runs))}"):
        print(f"teflon-jax montecarlo: {count} of {converged.size} runs had a time step {why}; they are "
              f"flagged in the files and left out of the counts and statistics. {advice}", file=sys.stderr)
        status = 1
    return status


def _end(value) -> str:
    return "unbounded" if value is None else f"{value:.4g}"
