"""`teflon-jax run --suite FILE --property-factors LOWER,UPPER|posterior`: the suite's pairs
through the nominal, upper- and lower-bound bearings (f_max and delta_f of Eq. 1 times 1, UPPER
and LOWER, on every surface of a triple or double pendulum; or each Eq. 1 constant of a
`--bearing` file at a quantile of its posterior, `teflon_jax.studies.posterior_friction_bounds`),
a table per case and the case that governs displacement, base shear and drift
(`teflon_jax.studies.governing_cases`). A `--bearing` file's bearing takes the case's factors
wherever the structure carries it (`with_friction_factors`). In this process the
three cases run one after the other (`suite_peaks`); with `--scheduler` every (case, chunk of
pairs) is a task of one run on a Dask cluster, the peaks of all three cases streamed to
`--out FILE.nc` (`suite_cases_distributed`)."""

import sys

import numpy as np

from ._bounding import add_bounding_flags, print_governing, read_bounds
from ._common import _write_json
from ._provenance import provenance_attributes
from ._run_stop import failed_pairs, pair_flags


def add_suite_bounding_flag(parser) -> None:
    """`--property-factors LOWER,UPPER|posterior` and `--posterior-quantiles` on `teflon-jax run --suite`."""
    add_bounding_flags(parser, "with --suite: run the suite with the nominal bearing and its lower- and "
                       "upper-bound variants (f_max and delta_f of Eq. 1 times LOWER and UPPER, e.g. "
                       "0.85,1.3; 'posterior': each constant at a quantile of the posterior draws of the "
                       "--bearing file, see --posterior-quantiles), and report which case governs "
                       "displacement, base shear and drift; with --scheduler the three cases run on the "
                       "cluster, all in --out FILE.nc")


def read_suite_factors(args, isolator=None):
    """The `Bounds` of `run --property-factors` on `isolator` (`read_isolator`; `read_bounds`), or
    `None`; `ValueError` naming the flag, also without --suite (then `isolator` may be None: the
    bounds are refused before they need it)."""
    if getattr(args, "property_factors", None) is not None and args.suite is None:
        raise ValueError("--property-factors: bounds a suite's analysis; add --suite FILE.")
    return read_bounds(args, isolator)


def _case_factors(bounds) -> dict:
    """{case: {"f_max", "delta_f", "rate_a": factor}} a --bearing file's bearing takes."""
    return {case: {k: v for k, v in row.items() if k != "f_min"} for case, row in bounds.factor_table().items()}


def _case_results(args, bounds, isolator, names, ax, ay, dt, stem, vertical=None):
    """({case: `SuiteResult`}, the slab's plan or None, {case: its files}, the NetCDF file of
    every case or None): the three cases in this process (a table and a NetCDF file per case,
    and with --out one file of all three) or on the cluster of --scheduler (a table per case,
    the peaks in --out); `vertical`: the pairs' vertical components, their pressure law and
    names (`suite_build`), or None."""
    from ..studies import (
        BOUNDING_CASES,
        save_suite,
        save_suite_cases,
        suite_cases_distributed,
        suite_peaks,
    )
    from ..tables import load_table2
    from ._run_structure import suite_build

    height = load_table2().storey_height if args.structure == "building" else None
    table = _case_factors(bounds)
    builds, plan = {}, None
    for case in BOUNDING_CASES:  # the structure of each case, built once
        if args.bearing is None:  # Table 1's or an isolator file's friction times the factor
            builds[case], _, plan = suite_build(args, isolator, ax[0], ay[0], dt, vertical=vertical,
                                                friction_factor=table[case]["f_max"])
        else:  # the bearing file's constants, wherever the structure carries them
            builds[case], _, plan = suite_build(args, isolator, ax[0], ay[0], dt, table[case], vertical)
    az = None if vertical is None else vertical[0]
    groups = None if plan is None else [g["name"] for g in plan["groups"]]
    duration = (ax.shape[1] - 1) * dt
    attrs = {"structure": args.structure, "suite": str(args.suite), **provenance_attributes()}
    if args.scheduler is None:
        results = {case: suite_peaks(build, names, ax, ay, dt, duration, batch_size=args.chunk_size,
                                     storey_height=height, group_names=groups, az=az)
                   for case, build in builds.items()}
        files = {case: [f"{stem}-{case}.csv", f"{stem}-{case}.nc"] for case in BOUNDING_CASES}
        for case, result in results.items():
            save_suite(result, table_path=files[case][0], netcdf_path=files[case][1],
                       attrs={**attrs, "bounding_case": case, **{f"friction_factor_{k}": v for k, v in table[case].items()}})
        if args.out is not None:
            save_suite_cases(results, args.out, attrs=_file_attrs(attrs, bounds))
        return results, plan, files, args.out
    from ._main import compile_cache_dir

    results = suite_cases_distributed(
        builds, names, ax, ay, dt, duration, out=args.out, scheduler=args.scheduler,
        chunk_size=8 if args.chunk_size is None else args.chunk_size, attrs=_file_attrs(attrs, bounds),
        compilation_cache=None if getattr(args, "no_compile_cache", False) else str(compile_cache_dir()),
        storey_height=height, group_names=groups, az=az)
    files = {case: [f"{stem}-{case}.csv"] for case in BOUNDING_CASES}
    for case, result in results.items():
        save_suite(result, table_path=files[case][0])
    return results, plan, files, args.out


def _file_attrs(attrs, bounds) -> dict:
    from ..studies import BOUNDING_CASES

    out = {**attrs, "bounding_cases": ",".join(BOUNDING_CASES)}
    if bounds.from_posterior:
        return out | {"property_factors": "posterior", "posterior_quantile_lower": bounds.quantiles[0],
                      "posterior_quantile_upper": bounds.quantiles[1]}
    return out | {"property_factor_lower": bounds.factors[0], "property_factor_upper": bounds.factors[1]}


def run_suite_bounding(args, bounds, isolator, names, ax, ay, dt, notes, scaling, vertical=None) -> int:
    """The suite's pairs (ax, ay) (P, n) [m/s^2] (and their `vertical` components with their
    pressure law, or None) through the nominal, upper- and lower-bound
    bearings of `bounds` (`read_suite_factors`; the structure of `run`'s flags on `isolator`
    with the case's f_max factor, or a --bearing file's bearing with the case's factors), one table per case
    (<stem>-<case>.csv; in this process also <stem>-<case>.nc), the NetCDF file of every case
    (--out) and the JSON with the governing cases; 1 when a pair failed in some case."""
    import pathlib
    import time

    from ..studies import BOUNDING_CASES, SUITE_VERTICAL_UNITS, governing_cases
    from ._normal_load import NORMAL_LOAD_NOTE, suite_normal_load

    stem = pathlib.Path(args.json).with_suffix("") if args.json else pathlib.Path("suite")
    start = time.perf_counter()
    results, plan, files, netcdf = _case_results(args, bounds, isolator, names, ax, ay, dt, stem, vertical)
    if args.pelicun_demands is not None:  # one demand file per case: <FILE stem>-<case>.csv
        from ..formats import write_pelicun_demands
        from ._engineering import suite_pelicun_peaks

        path = pathlib.Path(args.pelicun_demands)
        for case in BOUNDING_CASES:
            write_pelicun_demands(path.with_name(f"{path.stem}-{case}{path.suffix}"),
                                  **suite_pelicun_peaks(results[case], ax, ay))
    wall = time.perf_counter() - start
    every = {c: results[c].peaks | results[c].surface_peaks for c in BOUNDING_CASES}  # with the sliders, surfaces
    peaks = {k: np.stack([every[c][k] for c in BOUNDING_CASES]) for k in every["nominal"]
             if k not in SUITE_VERTICAL_UNITS}  # the uplift is the record's, the same in every case
    converged = np.stack([results[c].converged for c in BOUNDING_CASES])
    by_mean = governing_cases(peaks, converged, statistic="mean")
    by_max = governing_cases(peaks, converged, statistic="max")
    payload = {"structure": args.structure, "suite": str(args.suite), "notes": notes, "wall_s": wall,
               "property_factors": bounds.payload(args.bearing),
               "cases": {c: {**_case_entry(bounds, c), "summary": results[c].summary, "failed": int(np.sum(~results[c].converged)),
                             "pairs": {n: {k: float(v[i]) for k, v in every[c].items()}
                                       | pair_flags(results[c], i)
                                       | ({} if results[c].groups is None else suite_normal_load(plan, results[c].groups, i))
                                       for i, n in enumerate(names)},
                             "files": files[c]}
                         for c in BOUNDING_CASES},
               "governs": {k: {"by_mean": by_mean[k]["governs"], "by_max": by_max[k]["governs"]} for k in peaks}}
    if netcdf is not None:
        payload["netcdf"] = str(netcdf)
    if args.scheduler is not None:
        payload["scheduler"] = args.scheduler
    if results["nominal"].groups is not None:  # each case's groups: <stem>-<case>.csv, the NetCDF, "pairs"
        payload["normal_load_note"] = NORMAL_LOAD_NOTE
    if scaling is not None:
        payload["spectrum_scaling"] = scaling
    if args.json:
        _write_json(args.json, payload)
    print(f"{len(names)} pairs x 3 bearings in {wall:.1f} s; mean over the converged pairs:")
    print_governing(by_mean)
    bounds.print_factors()
    failed = {c: failed_pairs(results[c]) for c in BOUNDING_CASES}
    if any(failed.values()):
        print("teflon-jax run: error: pairs left out of the statistics, by case: "
              + " | ".join(f"{c}: {m}" for c, m in failed.items() if m) + ".", file=sys.stderr)
        return 1
    return 0


def _case_entry(bounds, case) -> dict:
    """A case's JSON entries: its one factor (user factors), or its constants over the point's
    and the constants themselves (a posterior's bounds)."""
    if not bounds.from_posterior:
        return {"friction_factor": bounds.factor_table()[case]["f_max"]}
    params = bounds.cases[case]
    return {"friction_factors": bounds.factor_table()[case],
            **{k: float(np.asarray(getattr(params, k))) for k in ("f_max", "delta_f", "rate_a")}}
