"""`teflon-jax montecarlo --property-factors LOWER,UPPER`: the nominal, upper- and lower-bound
bearings (`teflon_jax.studies.bounding_design`) under the same motions in one call, a table of
their peaks and the case that governs the isolators' displacement, the base shear and, for the
building, the storey drift and floor acceleration (`governing_cases`)."""

import sys

import numpy as np

from ..units import STANDARD_GRAVITY, parse_quantity
from ._common import _write_json, motion_bar


def read_property_factors(args) -> tuple[float, float] | None:
    """(lower, upper) of `--property-factors`, or `None`; `ValueError` naming the flag for a
    malformed, non-positive or swapped pair and for flags it cannot be combined with."""
    from ..studies import check_property_factors

    text = args.property_factors
    if text is None:
        return None
    parts = [p.strip() for p in text.split(",")]
    if len(parts) != 2 or not all(parts):
        raise ValueError(f"--property-factors: write LOWER,UPPER, e.g. 0.85,1.3; got {text!r}.")
    values = [parse_quantity(p, "dimensionless", where="--property-factors") for p in parts]
    try:
        lower, upper = check_property_factors(*values)
    except ValueError as error:
        raise ValueError(f"--property-factors {text}: {error}") from None
    for flag, used in (("--pga", len(args.pga_levels) > 1), ("--limit", bool(args.limit)),
                       ("--pelicun-demands", args.pelicun_demands is not None)):
        if used:
            raise ValueError(f"--property-factors: runs the three bearings at one --pga level; "
                             f"leave out {flag}{' levels' if flag == '--pga' else ''}.")
    return lower, upper


def run_bounding(args, structure, model, units) -> int:
    """Run the three cases, write the JSON (`cases`, `governs`), the results file and print the
    table; returns 0, or 1 when a run failed (kept out of the statistics, flagged in the file)."""
    from ..studies import BOUNDING_CASES, bounding_design, governing_cases
    from ._montecarlo_vertical import uplift_message, uplift_payload

    lower, upper = read_property_factors(args)
    try:  # on a triple or double pendulum: no surface's f_max above 1 in the upper case
        design = bounding_design(structure, lower=lower, upper=upper)
    except ValueError as error:
        raise ValueError(f"--property-factors {args.property_factors}: {error}") from None
    building = args.structure == "building"
    result, files = _bounding_runs(args, structure, model, design, (lower, upper))
    length, factor = units.length
    peaks = {f"base_disp_{length}": result.base_disp / factor, "base_shear_ratio": result.base_shear_ratio}
    if building:
        worst = lambda values: np.max(np.reshape(values, np.shape(values)[:2] + (-1,)), axis=-1)  # noqa: E731
        peaks["storey_drift_max"] = worst(result.storey_drift)  # every storey (and direction)
        peaks["level_acceleration_max_g"] = worst(result.floor_acceleration) / STANDARD_GRAVITY
    by_mean = governing_cases(peaks, result.converged, statistic="mean")
    by_max = governing_cases(peaks, result.converged, statistic="max")
    converged = np.asarray(result.converged, bool)
    payload = {
        "structure": args.structure, "n_motions": result.n_motions, "wall_s": result.wall_s,
        "property_factors": {"lower": lower, "upper": upper,
                             "applied_to": "f_max and delta_f of Eq. 1 (the friction coefficient at every velocity; on "
                                           "every surface of a triple or double pendulum, radii and capacities kept)"},
        "cases": {case: {**_case_friction(structure, design, i, (1.0, upper, lower)[i]), "n_converged": int(converged[i].sum()),
                         "mean": {k: v[case] for k, v in by_mean.items()},
                         "max": {k: v[case] for k, v in by_max.items()}}
                  for i, case in enumerate(BOUNDING_CASES)},
        "governs": {k: {"by_mean": by_mean[k]["governs"], "by_max": by_max[k]["governs"]} for k in peaks},
        "motions": {"pga_g": args.pga / STANDARD_GRAVITY, "duration_s": args.duration, "seed": args.seed,
                    "components": args.components},
        "files": files,
    }
    payload.update(uplift_payload(result, model))  # the same vertical records under the three bearings
    _write_json(args.json, payload)
    print(f"{result.n_motions} motions x 3 bearings in {result.wall_s:.1f} s; mean of the converged runs' peaks:")
    print("  " + f"{'':28s}" + "".join(f"{c:>12s}" for c in BOUNDING_CASES) + "   governs")
    for name, row in by_mean.items():
        cells = "".join(f"{row[c]:12.4g}" if row[c] is not None else f"{'-':>12s}" for c in BOUNDING_CASES)
        print(f"  {name:28s}{cells}   {row['governs']}")
    if uplift_message(payload):
        print(uplift_message(payload) + " (each bearing)")
    if not converged.all():
        print(f"teflon-jax montecarlo: {int((~converged).sum())} of {converged.size} runs did not converge; they "
              "are flagged in the results and left out of the table. Try a smaller --time-step.", file=sys.stderr)
        return 1
    return 0


def _bounding_runs(args, structure, model, design, factors) -> tuple:
    """(the `MonteCarloResult` of the three cases, design variants (3, N), the files written):
    in this process (`monte_carlo`), or with --scheduler as the design axis of one distributed
    run (`monte_carlo_distributed`: every task runs its motions under the three bearings, the
    peaks streamed to --out), the same motions either way (motion i from fold_in(key(seed), i))."""
    import jax

    from ..studies import BOUNDING_CASES, monte_carlo, monte_carlo_distributed
    from ..tables import load_table2
    from ._main import compile_cache_dir

    height = load_table2().storey_height if args.structure == "building" else None
    bar = motion_bar(args.motions, args.no_progress)
    progress = lambda done, total: bar.update(done - bar.n)  # noqa: E731
    if args.scheduler is None:
        result = monte_carlo(structure, model, args.motions, key=jax.random.key(args.seed), design=design,
                             chunk_size=args.chunk_size, progress=progress, storey_height=height)
        files = [] if args.out is None else [str(result.save(args.out))]
    else:
        attrs = {"structure": args.structure, "bounding_cases": ",".join(BOUNDING_CASES),
                 "property_factor_lower": factors[0], "property_factor_upper": factors[1]}
        result = monte_carlo_distributed(
            structure, model, args.motions, out=args.out, seed=args.seed, scheduler=args.scheduler,
            chunk_size=args.chunk_size, design=design, progress=progress, attrs=attrs, storey_height=height,
            compilation_cache=None if args.no_compile_cache else str(compile_cache_dir()))
        files = [str(args.out)]
    bar.close()
    return result, files


def _case_friction(structure, design, index, factor) -> dict:
    """The JSON entries of bounding case `index` (friction times `factor`): the factor and the
    friction the case runs with, f_max and delta_f of the flat bearing, or of each surface of a
    triple or double pendulum ({surface: value})."""
    from ..studies import surface_frictions

    if "f_max" in design:
        return {"friction_factor": factor, "f_max": float(design["f_max"][index]),
                "delta_f": float(design["delta_f"][index])}
    pendulum = getattr(structure, "structure", structure).pendulum  # through a vertical component's wrapper
    return {"friction_factor": factor, **surface_frictions(pendulum, factor)}


def add_suite_bounding_flag(parser) -> None:
    """`--property-factors LOWER,UPPER` on `teflon-jax run --suite`."""
    parser.add_argument("--property-factors", metavar="LOWER,UPPER", default=None,
                        help="with --suite: run the suite with the nominal bearing and its lower- and "
                        "upper-bound variants (f_max and delta_f of Eq. 1 times LOWER and UPPER, e.g. "
                        "0.85,1.3), and report which case governs displacement, base shear and drift")


def read_suite_factors(args) -> tuple[float, float] | None:
    """(lower, upper) of `run --property-factors`, or `None`; `ValueError` naming the flag."""
    from ..studies import check_property_factors

    text = getattr(args, "property_factors", None)
    if text is None:
        return None
    if args.suite is None:
        raise ValueError("--property-factors: bounds a suite's analysis; add --suite FILE.")
    if args.scheduler is not None:
        raise ValueError("--property-factors: the three bearings run in this process; leave out --scheduler.")
    if getattr(args, "bearing", None) is not None:
        raise ValueError("--property-factors: scales Table 1's friction (--ptfe, --pressure) or an isolator "
                         "file's surfaces, not a --bearing file's; leave out --bearing or --property-factors.")
    parts = [p.strip() for p in text.split(",")]
    if len(parts) != 2 or not all(parts):
        raise ValueError(f"--property-factors: write LOWER,UPPER, e.g. 0.85,1.3; got {text!r}.")
    try:
        return check_property_factors(*(parse_quantity(p, "dimensionless", where="--property-factors") for p in parts))
    except ValueError as error:
        raise ValueError(f"--property-factors {text}: {error}") from None


def run_suite_bounding(args, factors, build_structure, names, ax, ay, dt, notes, scaling) -> int:
    """The suite's pairs (ax, ay) (P, n) [m/s^2] through the nominal, upper- and lower-bound
    bearings (`build_structure` of `teflon-jax run` with `friction_factor`), one table and
    NetCDF file per case (<stem>-<case>.csv, .nc) and the JSON with the governing cases."""
    import argparse
    import json
    import pathlib
    import time

    from ..studies import BOUNDING_CASES, governing_cases, save_suite, suite_peaks
    from ..tables import load_table2
    from ._engineering import suite_pelicun_peaks
    from ._run_slab import NORMAL_LOAD_NOTE, suite_normal_load
    from ._suite_build import suite_build

    lower, upper = factors
    height = load_table2().storey_height if args.structure == "building" else None
    stem = pathlib.Path(args.json).with_suffix("") if args.json else pathlib.Path("suite")
    results, start, plan = {}, time.perf_counter(), None
    for case, factor in zip(BOUNDING_CASES, (1.0, upper, lower)):
        case_args = argparse.Namespace(**{**vars(args), "friction_factor": factor})
        build, _, base_index, plan = suite_build(case_args, build_structure, ax[0], ay[0], dt)  # one per case
        results[case] = suite_peaks(build, names, ax, ay, dt, (ax.shape[1] - 1) * dt, base_index,
                                    batch_size=args.chunk_size, storey_height=height,
                                    group_names=None if plan is None else [g["name"] for g in plan["groups"]])
        save_suite(results[case], table_path=f"{stem}-{case}.csv", netcdf_path=f"{stem}-{case}.nc",
                   attrs={"structure": args.structure, "suite": str(args.suite), "bounding_case": case,
                          "friction_factor": factor})
        if args.pelicun_demands is not None:  # one demand file per case: <FILE stem>-<case>.csv
            from ..formats import write_pelicun_demands

            path = pathlib.Path(args.pelicun_demands)
            write_pelicun_demands(path.with_name(f"{path.stem}-{case}{path.suffix}"),
                                  **suite_pelicun_peaks(results[case], ax, ay))
    wall = time.perf_counter() - start
    peaks = {k: np.stack([results[c].peaks[k] for c in BOUNDING_CASES]) for k in results["nominal"].peaks}
    converged = np.stack([results[c].converged for c in BOUNDING_CASES])
    by_mean = governing_cases(peaks, converged, statistic="mean")
    by_max = governing_cases(peaks, converged, statistic="max")
    payload = {"structure": args.structure, "suite": str(args.suite), "notes": notes, "wall_s": wall,
               "property_factors": {"lower": lower, "upper": upper,
                                    "applied_to": "f_max and delta_f of Eq. 1 (the friction coefficient at every velocity; on every surface of a triple or double pendulum)"},
               "cases": {c: {"friction_factor": f, "summary": results[c].summary, "failed": int(np.sum(~results[c].converged)),
                             "pairs": {n: {k: float(v[i]) for k, v in results[c].peaks.items()}
                                       | ({} if results[c].groups is None else suite_normal_load(plan, results[c].groups, i))
                                       for i, n in enumerate(names)},
                             "files": [f"{stem}-{c}.csv", f"{stem}-{c}.nc"]}
                         for c, f in zip(BOUNDING_CASES, (1.0, upper, lower))},
               "governs": {k: {"by_mean": by_mean[k]["governs"], "by_max": by_max[k]["governs"]} for k in peaks}}
    if results["nominal"].groups is not None:  # each case's groups: <stem>-<case>.csv, .nc and "pairs"
        payload["normal_load_note"] = NORMAL_LOAD_NOTE
    if scaling is not None:
        payload["spectrum_scaling"] = scaling
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(payload, indent=2))
    print(f"{len(names)} pairs x 3 bearings in {wall:.1f} s; mean over the converged pairs:")
    print("  " + f"{'':28s}" + "".join(f"{c:>12s}" for c in BOUNDING_CASES) + "   governs")
    for name, row in by_mean.items():
        cells = "".join(f"{row[c]:12.4g}" if row[c] is not None else f"{'-':>12s}" for c in BOUNDING_CASES)
        print(f"  {name:28s}{cells}   {row['governs']}")
    if not converged.all():
        failed = {c: [n for n, ok in zip(names, converged[i]) if not ok] for i, c in enumerate(BOUNDING_CASES)}
        print("teflon-jax run: error: pairs that could not be balanced in every step, left out of the "
              "statistics: " + "; ".join(f"{c}: {', '.join(f)}" for c, f in failed.items() if f)
              + ". Run such a pair alone to see why (a slab that tips, or try a smaller --time-step).",
              file=sys.stderr)
        return 1
    return 0
