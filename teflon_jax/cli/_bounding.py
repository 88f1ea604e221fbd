"""`teflon-jax montecarlo --property-factors LOWER,UPPER|posterior`: the nominal, upper- and
lower-bound bearings (`teflon_jax.studies.bounding_design`, or from the posterior of a
`--bearing` file: `posterior_friction_bounds`) under the same motions in one call, a table of
their peaks and the case that governs the isolators' displacement, the base shear and, for the
building, the storey drift and floor acceleration (`governing_cases`).

`Bounds` and `read_bounds` are the flags' reading, shared with `run --suite`."""

import dataclasses
import sys

import numpy as np

from ..catalogue import IN_SERIES
from ..units import STANDARD_GRAVITY, parse_quantity
from ._common import _write_json, motion_bar

POSTERIOR_WORD = "posterior"
"""The `--property-factors` value that takes the bounds from the posterior of `--bearing`."""


def add_bounding_flags(parser, help: str) -> None:
    """`--property-factors LOWER,UPPER|posterior` (its `help` says what the three cases run)
    and `--posterior-quantiles LOWER,UPPER` (with `--property-factors posterior`)."""
    parser.add_argument("--property-factors", metavar="LOWER,UPPER|posterior", default=None, help=help)
    parser.add_argument("--posterior-quantiles", metavar="LOWER,UPPER", default=None,
                        help="with --property-factors posterior: the quantiles of each friction constant's "
                        "posterior draws that the bound cases take (the upper case the upper quantile of f_max "
                        "and rate_a and the lower of delta_f, the lower case the other ends) (default 0.05,0.95); "
                        "with LOWER,UPPER factors and a --bearing file holding a posterior, its bounds at these "
                        "quantiles are reported beside the factors")


@dataclasses.dataclass(frozen=True)
class Bounds:
    """What `--property-factors` asks for: user `factors` (lower, upper), or (`factors` None)
    the `posterior` of `--bearing` at `quantiles`; `point`: the file's Eq. 1 constants (None
    without `--bearing`), `cases`: their three `FrictionParameters` from the posterior (None
    with factors), `text` as typed; `unbounded`: why the posterior's bounds beside user
    factors could not be formed at the default quantiles (else None)."""

    text: str
    factors: tuple | None
    quantiles: tuple
    posterior: object | None
    point: object | None
    cases: dict | None
    unbounded: str | None = None

    @property
    def from_posterior(self) -> bool:
        return self.factors is None

    def factor_table(self) -> dict:
        """{case: {constant: value over the point's}} of these bounds (`friction_factors`)."""
        from ..studies import friction_factors

        if self.from_posterior:
            return friction_factors(self.cases)
        return {case: dict.fromkeys(("f_max", "delta_f", "rate_a", "f_min"), 1.0)
                | {k: f for k in ("f_max", "delta_f", "f_min")}
                for case, f in zip(("nominal", "upper", "lower"), (1.0, self.factors[1], self.factors[0]))}

    def posterior_table(self) -> dict | None:
        """The posterior's factors at `quantiles`, when `--bearing` holds one (beside user factors)."""
        from ..studies import friction_factors, posterior_friction_bounds

        if self.posterior is None or self.unbounded is not None:
            return None
        cases = self.cases or posterior_friction_bounds(self.point, self.posterior, quantiles=self.quantiles)
        return friction_factors(cases)

    def payload(self, bearing_path) -> dict:
        """The JSON's `property_factors` entry: the factors or the posterior's bounds, and each
        case's constants over the point's (`factors`), the posterior's beside user factors."""
        applied = ("f_max and delta_f of Eq. 1 (the friction coefficient at every velocity; on every surface of a "
                   "triple or double pendulum, radii and capacities kept)")
        if not self.from_posterior:
            out = {"lower": self.factors[0], "upper": self.factors[1], "applied_to": applied,
                   "factors": self.factor_table()}
            if self.posterior is not None:
                out["posterior_factors"] = {"quantiles": list(self.quantiles), "factors": self.posterior_table(),
                                            "note": f"the bounds --property-factors posterior would take from "
                                                    f"{bearing_path}, not run here"}
                if self.unbounded is not None:
                    out["posterior_factors"]["error"] = self.unbounded
            return out
        sampled = [n for n in ("f_max", "delta_f", "rate_a") if n in self.posterior.names]
        return {"source": f"posterior of --bearing {bearing_path}", "quantiles": list(self.quantiles),
                "draws": self.posterior.size, "sampled": sampled,
                "kept_at_point": [n for n in self.posterior.names if n not in sampled],
                "effective_sample_size": {n: self.posterior.effective_sample_size[n] for n in sampled},
                "applied_to": "each Eq. 1 constant at its own quantile: the upper case the upper quantile of f_max "
                              "and rate_a and the lower of delta_f (the most friction at every velocity), the "
                              "lower case the other ends",
                "factors": self.factor_table()}

    def print_factors(self) -> None:
        """The bound cases' constants over the point's, lower / upper, as a small table."""
        rows = []
        if self.unbounded is not None:
            print(f"no posterior bounds beside the factors: {self.unbounded}")
        elif self.from_posterior or self.posterior is not None:
            q = self.quantiles
            rows.append((f"posterior {q[0]:g}-{q[1]:g}", self.posterior_table()))
        if not self.from_posterior:
            rows.append((f"factors {self.text}", self.factor_table()))
        names = ("f_max", "delta_f", "rate_a", "f_min")
        print("friction constants over the point estimate's, lower / upper case:")
        print("  " + f"{'':22s}" + "".join(f"{n:>15s}" for n in names))
        for label, table in rows:
            cells = "".join(f"{_ratio(table['lower'][n]) + ' / ' + _ratio(table['upper'][n]):>15s}" for n in names)
            print(f"  {label:22s}{cells}")


def _ratio(value) -> str:
    return "-" if value is None else f"{value:.3f}"


def _pair(text, flag, example, dimension="dimensionless") -> list[float]:
    parts = [p.strip() for p in str(text).split(",")]
    if len(parts) != 2 or not all(parts):
        raise ValueError(f"{flag}: write LOWER,UPPER, e.g. {example}; got {text!r}.")
    return [parse_quantity(p, dimension, where=flag) for p in parts]


def read_bounds(args, read) -> Bounds | None:
    """`--property-factors` and `--posterior-quantiles` read and checked (`Bounds`), or None
    without the first, on what was read of `--bearing FILE` (`read`: its `BearingFile`, or the
    `Isolator` read with it, each with `.bearing` and `.posterior`; the file is not read again); `ValueError` naming the flag as typed: a malformed, non-positive or
    swapped pair of factors; `posterior` without `--bearing`, with a bearing file that has no
    posterior, on a triple or double pendulum or on an anisotropic bearing; quantiles outside
    (0, 1) or not lower < upper; `--posterior-quantiles` with nothing to apply to."""
    from ..studies import (
        POSTERIOR_QUANTILES,
        check_posterior_quantiles,
        check_property_factors,
    )

    text, q_text = args.property_factors, getattr(args, "posterior_quantiles", None)
    if text is None:
        if q_text is not None:
            raise ValueError("--posterior-quantiles: picks the bounds of --property-factors posterior; add it.")
        return None
    wants_posterior = text.strip().lower() == POSTERIOR_WORD
    posterior, point = _bearing_posterior(args, read, text, wants_posterior)
    quantiles = POSTERIOR_QUANTILES
    if q_text is not None:
        if posterior is None:
            raise ValueError(f"--posterior-quantiles: applies to the posterior of a --bearing file, and "
                             f"--property-factors {text} has none; leave it out.")
        try:
            quantiles = check_posterior_quantiles(*_pair(q_text, "--posterior-quantiles", "0.05,0.95"))
        except ValueError as error:
            raise ValueError(f"--posterior-quantiles {q_text}: {error}") from None
    factors = None
    if not wants_posterior:
        try:
            factors = check_property_factors(*_pair(text, "--property-factors", "0.85,1.3 (or posterior)"))
        except ValueError as error:
            message = str(error)
            raise ValueError(message if message.startswith("--property-factors:")
                             else f"--property-factors {text}: {message}") from None
    cases, unbounded = None, None
    if posterior is not None:
        from ..studies import posterior_friction_bounds

        try:  # checked before any run, also when asked for beside the factors
            bounds = posterior_friction_bounds(point, posterior, quantiles=quantiles)
        except ValueError as error:
            where = f"--posterior-quantiles {q_text}" if q_text else f"--bearing {args.bearing} (quantiles 0.05,0.95)"
            if wants_posterior or q_text is not None:
                raise ValueError(f"{where}: {error}") from None
            unbounded = f"{where}: {error}"  # only the report beside the factors lacks it
        else:
            cases = bounds if wants_posterior else None
    return Bounds(text, factors, quantiles, posterior, point, cases, unbounded)


def _bearing_posterior(args, read, text, wants_posterior) -> tuple:
    """(the posterior of --bearing or None, the file's Eq. 1 constants or None), of `read`."""
    if getattr(args, "bearing", None) is None:
        if wants_posterior:
            raise ValueError("--property-factors posterior: takes the bounds from the posterior of a bearing file; "
                             "add --bearing FILE (a file with a posterior section, e.g. from fit --bayes), or give "
                             "LOWER,UPPER factors.")
        return None, None
    bearing, posterior = read.bearing, read.posterior
    if not wants_posterior:
        return posterior, None if posterior is None else bearing.friction
    if posterior is None:
        raise ValueError(f"--property-factors posterior: --bearing {args.bearing} has no posterior section; "
                         "give a bearing file written with its posterior (fit --bayes), or LOWER,UPPER factors.")
    if getattr(args, "isolator", None) in IN_SERIES:
        raise ValueError(f"--property-factors posterior: bounds the --bearing file's friction, and --isolator "
                         f"{args.isolator} runs its isolator file's surfaces; give LOWER,UPPER factors.")
    if bearing.friction_perpendicular is not None:
        raise ValueError(f"--property-factors posterior: the bearing of --bearing {args.bearing} is anisotropic, "
                         "and its posterior's friction constants are those along the lay only; give LOWER,UPPER "
                         "factors (both directions alike).")
    return posterior, bearing.friction


def read_property_factors(args, isolator) -> Bounds | None:
    """`read_bounds` of `montecarlo` on `isolator` (`read_isolator`), and the flags the bounding
    cases cannot be combined with refused by name."""
    bounds = read_bounds(args, isolator)
    if bounds is None:
        return None
    for flag, used in (("--pga", len(args.pga_levels) > 1), ("--limit", bool(args.limit)),
                       ("--pelicun-demands", args.pelicun_demands is not None)):
        if used:
            raise ValueError(f"--property-factors: runs the three bearings at one --pga level; "
                             f"leave out {flag}{' levels' if flag == '--pga' else ''}.")
    if getattr(args, "storeys", False) and args.structure != "building":  # the building's are always kept
        raise ValueError("--storeys: storey results need --structure building.")
    return bounds


def run_bounding(args, bounds, structure, model, units) -> int:
    """Run the three cases of `bounds` (`read_property_factors`), write the JSON (`property_factors`,
    `cases`, `governs`), the results file and print the tables; returns 0, or 1 when a run failed (kept out of the statistics,
    flagged in the file)."""
    from ..studies import (
        BOUNDING_CASES,
        bounding_design,
        friction_bounding_design,
        governing_cases,
    )
    from ._montecarlo_summary import (
        beyond_law_words,
        group_summary,
        listed,
        run_words,
        throughput,
        unbalanced_parts,
    )
    from ._normal_load import uplift_message, uplift_payload

    if bounds.from_posterior:
        design = friction_bounding_design(bounds.cases)
    else:
        try:  # on a triple or double pendulum: no surface's f_max above 1 in the upper case
            design = bounding_design(structure, lower=bounds.factors[0], upper=bounds.factors[1])
        except ValueError as error:
            raise ValueError(f"--property-factors {args.property_factors}: {error}") from None
    building = args.structure == "building"
    result, files, marks = _bounding_runs(args, structure, model, design, bounds)
    length, factor = units.length
    peaks = {f"base_disp_{length}": result.base_disp / factor, "base_shear_ratio": result.base_shear_ratio}
    if building:
        worst = lambda values: np.max(np.reshape(values, np.shape(values)[:2] + (-1,)), axis=-1)  # noqa: E731
        peaks["storey_drift_max"] = worst(result.storey_drift)  # every storey (and direction)
        peaks["level_acceleration_max_g"] = worst(result.floor_acceleration) / STANDARD_GRAVITY
    peaks.update(result.surface_peaks)  # a series pendulum's sliders, the heated surfaces (SI)
    by_mean = governing_cases(peaks, result.converged, statistic="mean")
    by_max = governing_cases(peaks, result.converged, statistic="max")
    converged = np.asarray(result.converged, bool)
    table = bounds.factor_table()
    payload = {
        "structure": args.structure, "n_motions": result.n_motions, **throughput(result, marks),
        "property_factors": bounds.payload(args.bearing),
        "cases": {case: {**_case_friction(structure, design, i, table[case], bounds), "n_converged": int(converged[i].sum()),
                         "mean": {k: v[case] for k, v in by_mean.items()},
                         "max": {k: v[case] for k, v in by_max.items()}}
                  for i, case in enumerate(BOUNDING_CASES)},
        "governs": {k: {"by_mean": by_mean[k]["governs"], "by_max": by_max[k]["governs"]} for k in peaks},
        "motions": {"pga_g": [args.pga / STANDARD_GRAVITY], "duration_s": args.duration, "seed": args.seed,
                    "components": args.components},
        "files": files,
    }
    if result.group_peak_load is not None:  # a plan's groups: their loads under each case
        for i, case in enumerate(BOUNDING_CASES):
            payload["cases"][case]["groups"] = group_summary(_case(result, i), units)[0]
        payload["units"] = {"group_load": units.force[0]}
    payload.update(uplift_payload(result, model))  # the same vertical records under the three bearings
    _write_json(args.json, payload)
    print(f"{result.n_motions} motions x 3 bearings {run_words(result)}; mean of the converged runs' peaks:")
    print_governing(by_mean)
    bounds.print_factors()
    if uplift_message(payload):
        print(uplift_message(payload) + " (each bearing)")
    beyond = result.beyond_flags
    if beyond.any():
        runs = listed(f"{BOUNDING_CASES[c]}:{m}" for c, m in np.argwhere(beyond))
        print(f"teflon-jax montecarlo: {int(beyond.sum())} of {converged.size} runs "
              + beyond_law_words(f"case:motion {runs}"), file=sys.stderr)
    if not (converged | beyond).all():
        def names(runs):
            return "case:motion " + listed(f"{BOUNDING_CASES[c]}:{m}" for c, m in np.argwhere(runs))

        for count, why, advice in unbalanced_parts(~converged & ~beyond, result.tipped_flags, names):
            print(f"teflon-jax montecarlo: {count} of {converged.size} runs had a time step "
                  f"{why}; they are flagged in the results and left out of the table. {advice}", file=sys.stderr)
    if not converged.all():
        return 1
    return 0


def _case(result, index):
    """The `MonteCarloResult` of bounding case `index` alone (its row of the design axis)."""
    picked = {name: np.asarray(getattr(result, name))[index] for name in
              ("converged", "group_peak_load", "group_min_load", "group_uplift_time")}
    return dataclasses.replace(result, **picked)


def print_governing(by_mean) -> None:
    """The table of each peak's mean per case and the case that governs it."""
    from ..studies import BOUNDING_CASES

    print("  " + f"{'':28s}" + "".join(f"{c:>12s}" for c in BOUNDING_CASES) + "   governs")
    for name, row in by_mean.items():
        cells = "".join(f"{row[c]:12.4g}" if row[c] is not None else f"{'-':>12s}" for c in BOUNDING_CASES)
        print(f"  {name:28s}{cells}   {row['governs']}")


def _bounding_runs(args, structure, model, design, bounds) -> tuple:
    """(the `MonteCarloResult` of the three cases, design variants (3, N), the files written,
    the progress marks in runs, `chunk_marks`):
    in this process (`monte_carlo`), or with --scheduler as the design axis of one distributed
    run (`monte_carlo_distributed`: every task runs its motions under the three bearings, the
    peaks streamed to --out), the same motions either way (motion i from fold_in(key(seed), i))."""
    import jax

    from ..studies import BOUNDING_CASES, monte_carlo, monte_carlo_distributed
    from ..tables import load_table2
    from ._main import compile_cache_dir
    from ._montecarlo_summary import chunk_marks

    height = load_table2().storey_height if args.structure == "building" else None
    cases = len(BOUNDING_CASES)
    bar = motion_bar(cases * args.motions, args.no_progress)  # runs: each motion under the three bearings
    mark, marks = chunk_marks(bar)
    progress = lambda done, total: mark(cases * done, cases * total)  # noqa: E731
    if args.scheduler is None:
        result = monte_carlo(structure, model, args.motions, key=jax.random.key(args.seed), design=design,
                             chunk_size=args.chunk_size, progress=progress, storey_height=height)
        files = [] if args.out is None else [str(result.save(args.out))]
    else:
        attrs = {"structure": args.structure, "bounding_cases": ",".join(BOUNDING_CASES)}
        if bounds.from_posterior:
            attrs.update({"property_factors": "posterior", "posterior_quantile_lower": bounds.quantiles[0],
                          "posterior_quantile_upper": bounds.quantiles[1]})
        else:
            attrs.update({"property_factor_lower": bounds.factors[0], "property_factor_upper": bounds.factors[1]})
        result = monte_carlo_distributed(
            structure, model, args.motions, out=args.out, seed=args.seed, scheduler=args.scheduler,
            chunk_size=args.chunk_size, design=design, progress=progress, attrs=attrs, storey_height=height,
            compilation_cache=None if args.no_compile_cache else str(compile_cache_dir()))
        files = [str(args.out)]
    bar.close()
    return result, files, marks


def _case_friction(structure, design, index, factors, bounds) -> dict:
    """The JSON entries of bounding case `index`: its constants over the point's (`factors`;
    with user factors also the one `friction_factor`) and the friction it runs with, f_max,
    delta_f (and rate_a from a posterior) of the flat bearing, or of each surface of a triple
    or double pendulum ({surface: value})."""
    from ..studies import surface_frictions

    if bounds.from_posterior:
        return {"friction_factors": factors, **{k: float(v[index]) for k, v in design.items()}}
    factor = factors["f_max"]
    if getattr(structure, "system", None) is not None:  # built on a plan: every group's bearings alike
        return {"friction_factor": factor}
    if "f_max" in design:
        return {"friction_factor": factor, "f_max": float(design["f_max"][index]),
                "delta_f": float(design["delta_f"][index])}
    return {"friction_factor": factor, **surface_frictions(structure.pendulum, factor)}
