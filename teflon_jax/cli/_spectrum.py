"""`teflon-jax run --suite FILE` scaled to a target spectrum: the flags, their checks before any
record is run, the amplitude factor of each pair (`teflon_jax.studies.amplitude_factors`), the
JSON entry and the plot of the scaled spectra against the target."""

import numpy as np

from ..units import STANDARD_GRAVITY, parse_quantity

SCALING_DEFAULTS = {"combination": "srss", "scaling": "pair", "suite_statistic": "mean", "min_ratio": "1"}
"""The values of the scaling flags a run with a target leaves out (`read_target`)."""


def add_spectrum_flags(parser) -> None:
    """The flags of spectrum scaling on `teflon-jax run --suite`."""
    parser.add_argument("--target-spectrum", default=None, metavar="FILE",
                        help="with --suite: scale each pair to this target spectrum (two columns with "
                        "units in the header, e.g. 'period [s], Sa [g]')")
    parser.add_argument("--design-spectrum", default=None, metavar="S_DS,S_D1,T_L",
                        help="with --suite: scale to the two-parameter design shape of S_DS, S_D1 and the "
                        "long period T_L, e.g. 1.0g,0.6g,8s")
    parser.add_argument("--period-range", nargs=2, default=None, metavar=("LOW", "HIGH"),
                        help="periods over which the scaled spectra may not fall below the target by more "
                        "than --min-ratio, e.g. 1.5s 4s (required with a target)")
    parser.add_argument("--combination", default=None, choices=("srss", "rotd100"),
                        help="the pair's spectrum: srss of the two components' or rotd100, the largest "
                        "over directions (default srss)")
    parser.add_argument("--scaling", default=None, choices=("pair", "suite"),
                        help="one amplitude factor per pair, or one for the whole suite (default pair)")
    parser.add_argument("--suite-statistic", default=None, choices=("mean", "max"),
                        help="--scaling suite: the statistic over pairs lifted to the target (default mean)")
    parser.add_argument("--min-ratio", default=None, help="the scaled spectrum may not fall below this "
                        "fraction of the target in the range, e.g. 0.9 or 90%% (default 1)")
    parser.add_argument("--max-factor", default=None, help="refuse (before any run) pairs that would be "
                        "scaled by more than this (default: no limit)")
    parser.add_argument("--spectrum-plot", default=None, metavar="PNG",
                        help="write the scaled spectra, their statistic and the target to this PNG")


def read_target(args):
    """(target, check periods [s], description) from the flags, or `None` without a target;
    `ValueError` naming the flag for every mistake, before records are read: a flag of the
    scaling given without a target, or --suite-statistic without --scaling suite. With a target,
    the flags left out take their defaults (`SCALING_DEFAULTS`) on `args`."""
    from ..studies import DesignSpectrum, TabulatedSpectrum, check_period_range

    given = [f for f, v in (("--target-spectrum", args.target_spectrum), ("--design-spectrum", args.design_spectrum))
             if v is not None]
    extra = [f for f, v in (("--period-range", args.period_range), ("--max-factor", args.max_factor),
                            ("--spectrum-plot", args.spectrum_plot), ("--combination", args.combination),
                            ("--scaling", args.scaling), ("--suite-statistic", args.suite_statistic),
                            ("--min-ratio", args.min_ratio)) if v is not None]
    if not given:
        if extra:
            raise ValueError(f"{extra[0]}: only used with --target-spectrum or --design-spectrum.")
        return None
    if args.suite_statistic is not None and args.scaling != "suite":
        raise ValueError(f"--suite-statistic {args.suite_statistic}: the statistic one factor for the whole suite "
                         "lifts to the target; add --scaling suite, or leave --suite-statistic out.")
    for name, default in SCALING_DEFAULTS.items():
        if getattr(args, name) is None:
            setattr(args, name, default)
    if len(given) == 2:
        raise ValueError("--design-spectrum: give a target file or a design spectrum, not both.")
    if args.suite is None:
        raise ValueError(f"{given[0]}: scales the pairs of a suite; add --suite FILE.")
    if args.period_range is None:
        raise ValueError("--period-range: a target spectrum needs the range of periods to match, e.g. "
                         "--period-range 1.5s 4s.")
    if args.target_spectrum is not None:
        from ..formats import read_target_spectrum

        target = TabulatedSpectrum(*read_target_spectrum(args.target_spectrum))
        text = f"file {args.target_spectrum}"
    else:
        parts = [p.strip() for p in args.design_spectrum.split(",")]
        if len(parts) != 3:
            raise ValueError(f"--design-spectrum: write S_DS,S_D1,T_L, e.g. 1.0g,0.6g,8s; got {args.design_spectrum!r}.")
        values = [parse_quantity(p, d, where=f"--design-spectrum {n}")
                  for p, d, n in zip(parts, ("acceleration", "acceleration", "time"), ("S_DS", "S_D1", "T_L"))]
        try:
            target = DesignSpectrum(*values)
        except ValueError as error:
            raise ValueError(f"--design-spectrum: {error}") from None
        text = f"design shape S_DS {parts[0]}, S_D1 {parts[1]}, T_L {parts[2]}"
    low, high = (parse_quantity(p, "time", where="--period-range") for p in args.period_range)
    periods = check_period_range(target, low, high, "--period-range")
    ratio = parse_quantity(args.min_ratio, "dimensionless", where="--min-ratio")
    if not (np.isfinite(ratio) and ratio > 0):
        raise ValueError(f"--min-ratio: must be > 0, got {args.min_ratio}.")
    if args.max_factor is not None:
        limit = parse_quantity(args.max_factor, "dimensionless", where="--max-factor")
        if not (np.isfinite(limit) and limit > 0):
            raise ValueError(f"--max-factor: must be > 0, got {args.max_factor}.")
    return target, periods, text


def check_unscaled(pairs, args) -> None:
    """With a target, the records are scaled by the factors only: a suite CSV scale or --scale
    other than 1 would scale them twice; refused naming the pair."""
    if float(args.scale) != 1.0:
        raise ValueError("--scale: the target spectrum sets the amplitude factors; leave --scale out.")
    for name, *_, scale in pairs:
        if scale != 1.0:
            raise ValueError(f"--suite: pair {name} has scale {scale:g}; with a target spectrum the factors are "
                             "computed, so leave the scale column at 1 (or empty).")


def scale_to_target(args, spec, names, ax, ay, dt) -> tuple[np.ndarray, dict]:
    """(factors (P,), JSON entry) for the pairs (ax, ay) (P, nt) [m/s^2]; `ValueError` naming
    --max-factor for pairs beyond it, before any run."""
    from ..studies import (
        amplitude_factors,
        check_factor_limit,
        combined_spectrum,
        suite_statistic,
    )

    target, periods, text = spec
    ratio = parse_quantity(args.min_ratio, "dimensionless", where="--min-ratio")
    spectra = np.array([combined_spectrum(x, y, dt, periods, method=args.combination)
                        for x, y in zip(ax, ay)])
    factors, governing = amplitude_factors(spectra, target(periods), min_ratio=ratio, per=args.scaling,
                                           statistic=args.suite_statistic)
    limit = None if args.max_factor is None else parse_quantity(args.max_factor, "dimensionless", where="--max-factor")
    check_factor_limit(names, factors, limit, "--max-factor")
    statistic = suite_statistic(spectra, factors, args.suite_statistic)
    entry = {"target": text, "combination": args.combination, "scaling": args.scaling,
             "suite_statistic": args.suite_statistic, "min_ratio": ratio,
             "period_range_s": [float(periods[0]), float(periods[-1])], "check_periods_s": periods.tolist(),
             "factors": {n: float(f) for n, f in zip(names, factors)},
             "governing_period_s": {n: float(periods[k]) for n, k in zip(names, governing)},
             "suite_statistic_over_target_min": float(np.min(statistic / target(periods))),
             "rule": "f_i = max over the check periods of min_ratio * target / combined spectrum"}
    if args.spectrum_plot is not None:
        _plot(args.spectrum_plot, names, periods, factors[:, None] * spectra, statistic, target, ratio, entry)
    return factors, entry


def _plot(path, names, periods, scaled, statistic, target, ratio, entry) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    for values in scaled:
        ax.loglog(periods, values / STANDARD_GRAVITY, "-", lw=0.7, color="0.6")
    ax.lines[0].set_label(f"{len(names)} scaled pairs ({entry['combination']})")
    ax.loglog(periods, statistic / STANDARD_GRAVITY, "k-", lw=2, label=f"suite {entry['suite_statistic']}")
    ax.loglog(periods, target(periods) / STANDARD_GRAVITY, "r-", lw=1.5, label="target")
    if ratio != 1:
        ax.loglog(periods, ratio * target(periods) / STANDARD_GRAVITY, "r--", lw=1, label=f"{ratio:g} x target")
    ax.set_xlabel("period T [s]")
    ax.set_ylabel("pseudo-spectral acceleration, 5 % damping [g]")
    ax.set_title(f"{entry['target']}; {entry['scaling']} factors over {periods[0]:g}-{periods[-1]:g} s", fontsize=8)
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
