"""`diagnose --mixture bic [--mixture-draws K]`: every composition of effects the search fitted,
weighed by its evidence (`identification.discovery.discovery_mixture`), in the JSON and, with
`--save-bearing FILE`, as the bearing file's `mixture` that `montecarlo --bearing FILE` draws
from. Without `--mixture` the command writes what it wrote before, number for number."""

MIXTURE_CHOICES = ("bic",)
"""The criteria `--mixture` takes (`teflon_jax.formats.MIXTURE_CRITERIA`)."""

DEFAULT_DRAWS = 1000
"""Draws of each composition's constants without `--mixture-draws` (as `fit --posterior-draws`)."""

MIN_DRAWS = 100
"""The fewest draws a composition may have (`teflon_jax.formats.MIN_POSTERIOR_ESS`)."""


def add_mixture_flags(parser) -> None:
    """`--mixture bic` and `--mixture-draws K`."""
    parser.add_argument(
        "--mixture", choices=MIXTURE_CHOICES, default=None,
        help="weigh every composition of effects the search fitted by its evidence: bic gives "
        "w = exp(-dBIC / 2), normalised (BIC with the effective samples of the chosen model's "
        "residual); the JSON lists every composition ('mixture'), and --save-bearing writes those "
        "of weight 0.001 or more, each with draws of its constants, as the file's 'mixture', which "
        "montecarlo --bearing draws from (default: none)")
    parser.add_argument(
        "--mixture-draws", type=int, default=None, metavar="K",
        help=f"with --mixture: draws of each composition's constants from the Gaussian of its fit, "
        f"truncated to their ranges (default {DEFAULT_DRAWS}, at least {MIN_DRAWS})")


def check_mixture_flags(args) -> None:
    """`ValueError` naming `--mixture-draws` without `--mixture`, or below `MIN_DRAWS`."""
    draws = args.mixture_draws
    if draws is None:
        return
    if args.mixture is None:
        raise ValueError("--mixture-draws: applies with --mixture bic only; add --mixture bic or "
                         "leave --mixture-draws out.")
    if draws < MIN_DRAWS:
        raise ValueError(f"--mixture-draws: must be at least {MIN_DRAWS} (each composition's draws "
                         f"are independent, and a posterior needs {MIN_DRAWS} effective draws), "
                         f"got {draws}.")


def mixture_of(args, result):
    """The `DiscoveryMixture` of `result` that `--mixture` asks for, or None."""
    if args.mixture is None:
        return None
    from identification.discovery import discovery_mixture

    return discovery_mixture(result, draws=args.mixture_draws or DEFAULT_DRAWS)


def mixture_failure(args, mixture) -> str | None:
    """Why `--save-bearing` holds no mixture although `--mixture` asked for one, or None."""
    if mixture is None or mixture.mixture is not None or args.save_bearing is None:
        return None
    return (f"--mixture {args.mixture}: {mixture.why_none}; {args.save_bearing} holds the chosen "
            "composition alone.")


def mixture_lines(mixture) -> list:
    """What is said of the weights: the compositions of weight 0.001 or more, heaviest first."""
    if mixture is None:
        return []
    shown = [row for row in mixture.table if row["weight"] >= 1e-3]
    kept = sum(row["in_mixture"] for row in mixture.table)
    return [f"mixture ({mixture.criterion}, n_eff {mixture.effective_samples:.0f}): "
            + ", ".join(f"{'+'.join(row['effects']) or 'baseline'} {row['weight']:.3g}" for row in shown)
            + f"; {kept} of {len(mixture.table)} compositions kept"]


def save_found_bearing(args, result, mixture):
    """The function of no arguments that writes the chosen composition's bearing to
    `--save-bearing`, with the compositions' mixture when `--mixture` made one (`bearing_writer`:
    `ValueError` first when the file cannot hold it)."""
    from ._fit_outputs import bearing_writer

    return bearing_writer(args.save_bearing, result.bearing(), standard_errors=result.bearing_errors(),
                          sources=[args.record], fit={"command": "diagnose", "effects": result.effects,
                                                      "nrmse_before": result.nrmse_initial,
                                                      "nrmse": result.nrmse_final,
                                                      "fit_convergence": dict(result.fit_convergence)},
                          mixture=None if mixture is None else mixture.mixture)
