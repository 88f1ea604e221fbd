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
    if getattr(args, "storeys", False) and args.structure != "building":  # the building's are always kept
        raise ValueError("--storeys: storey results need --structure building.")
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
