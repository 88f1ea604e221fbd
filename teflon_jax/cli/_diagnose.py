"""`teflon-jax diagnose RECORD --json OUT.json --report DIR [--baseline paper1990|coulomb]`.

Fits the baseline model to a test record, names the missing effects one at a time (see
`identification._discovery`), and writes the JSON summary and a Markdown report with figures.
"""

import argparse
import dataclasses
import pathlib
import sys

from ..units import INCH, parse_quantity
from ._bearing_flags import add_save_bearing_flag, check_output_file, save_bearing_flag
from ._common import (
    _write_json,
    add_quantity,
    add_units_flag,
    output_units,
    read_bearing_record,
)
from ._diagnose_pendulum import add_pendulum_diagnose_flags, search_pendulum
from ._diagnose_series import (
    add_series_diagnose_flags,
    check_series_flags,
    run_series_diagnose,
)
from ._triple import SERIES_ISOLATORS

_DIMENSIONS = {"-": "dimensionless", "m": "length", "s/m": "slowness"}


HELP = "find the effects a bearing test shows beyond the 1990 model"
"""The line of this command in `teflon-jax --help`."""


def add_diagnose_parser(subparsers) -> argparse.ArgumentParser:
    """Add the `diagnose` sub-command to an `argparse` sub-parser collection."""
    from identification.discovery import BASELINES, EFFECT_NAMES

    parser = subparsers.add_parser(
        "diagnose",
        help=HELP,
        description=(
            "Fit a baseline model to a test record (test-record CSV), rank candidate effects "
            "("
            + ", ".join(EFFECT_NAMES)
            + ") by evidence (BIC drop with an effective sample "
            "size, and the gain on held-out cycles), add the best while it earns its "
            "parameters, and report each step."
        ),
    )
    parser.add_argument("record", type=pathlib.Path,
                        help="test-record CSV file or friction-damper JSON (the inputs of `fit`)")
    add_quantity(parser, "--normal-load", "force", None, "normal load for records without one "
                 "(e.g. a friction damper): one that puts force / N near 0.1, as the friction "
                 "constants are bounded (f_max <= 0.5)", minimum=0.0)
    parser.add_argument(
        "--json",
        type=pathlib.Path,
        required=True,
        dest="json_path",
        metavar="OUT.json",
        help="where to write the JSON summary",
    )
    parser.add_argument(
        "--report",
        type=pathlib.Path,
        required=True,
        metavar="DIR",
        help="folder for report.md and the figures",
    )
    parser.add_argument(
        "--baseline",
        choices=tuple(BASELINES),
        default=None,
        help="model to start from (default: paper1990 = Eq. 1 + Bouc-Wen; with --isolator "
        "triple-fp|double-fp the baseline is the series fit of --isolator-file)",
    )
    parser.add_argument(
        "--candidates",
        default=None,
        help="comma-separated effects to consider (default: all applicable)",
    )
    parser.add_argument(
        "--bic-threshold",
        type=float,
        default=10.0,
        help="smallest BIC drop that adds an effect (default 10, 'very strong')",
    )
    parser.add_argument(
        "--max-effects",
        type=int,
        default=4,
        help="at most this many effects are added (default 4)",
    )
    parser.add_argument(
        "--max-samples",
        type=int,
        default=3000,
        help="longer records are decimated to about this many samples (default 3000)",
    )
    parser.add_argument(
        "--known",
        "--fixed",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="hold a parameter at a value, with its unit where it has one, e.g. rate_a=0.6s/in "
        "or yield_disp=0.005in (repeatable; with rate_a known, 'interfaces' can be identified; "
        "--fixed is the same flag, as in fit; default: none)",
    )
    parser.add_argument("--quiet", "--no-progress", action="store_true",
                        help="no progress lines (--no-progress is the same flag, as in the other commands)")
    add_pendulum_diagnose_flags(parser)
    add_series_diagnose_flags(parser)
    add_save_bearing_flag(parser)
    add_units_flag(parser)
    parser.set_defaults(func=run_diagnose)
    return parser


def run_diagnose(args) -> int:
    """Run `diagnose` for parsed arguments; returns the exit status (0 ok, 1 a fitted radius that did not
    settle beside the effects found, 2 bad input)."""

    from identification.discovery import discover_effects, write_report

    def say(text):
        if not args.quiet:
            print(text, file=sys.stderr)

    candidates = None
    if args.candidates:
        candidates = [c.strip() for c in args.candidates.split(",") if c.strip()]
    if args.isolator in SERIES_ISOLATORS:
        return run_series_diagnose(args, candidates, say)
    args.baseline = args.baseline or "paper1990"
    try:
        check_series_flags(args)
        check_output_file(args.save_bearing, "--save-bearing")
        known = _parse_known(args.known)
        record = with_normal_load(read_bearing_record(args.record), args.record, args.normal_load)

        def search(friction_record):
            return discover_effects(
                friction_record,
                baseline=args.baseline,
                candidates=candidates,
                bic_threshold=args.bic_threshold,
                max_effects=args.max_effects,
                max_samples=args.max_samples,
                known=known,
                callback=say,
            )

        result, radius, radius_entries = search_pendulum(args, record, search, say)
    except (ValueError, FileNotFoundError) as error:
        print(f"teflon-jax diagnose: {error}", file=sys.stderr)
        return 2
    document = result.to_json()
    if radius is not None:
        document.update(isolator="single-fp", radius_m=radius,
                        radius_given=args.radius is not None, **radius_entries)
    _write_json(args.json_path, document)
    report = write_report(result, args.report, record_name=args.record.name,
                          length=output_units(args.units).length)
    save_bearing_flag(args, result.bearing(), standard_errors=result.bearing_errors(),
                      sources=[args.record], fit=_fit_summary(result))
    stack = result.stack_check
    if stack and not stack["consistent_with_stated"]:
        say(
            f"stack check: the fitted rate_a is rate_a / n = {stack['rate_effective'] * INCH:.3g} "
            f"s/in; with a single-interface rate_a within Table 1's range, n is in "
            f"[{stack['n_low']:.1f}, {stack['n_high']:.1f}] interfaces in series (not separable "
            "from rate_a; give --known rate_a=... to identify n)."
        )
    say(
        f"{document['conclusion']}; nrmse {result.nrmse_initial:.4f} -> {result.nrmse_final:.4f}; "
        f"{result.runtime_s:.1f} s. Wrote {args.json_path} and {report}"
        + (f" and the bearing to {args.save_bearing}." if args.save_bearing else ".")
    )
    if radius_entries.get("radius_settled") is False:
        print(f"teflon-jax diagnose: the radius did not settle beside the effects found "
            f"({radius / INCH:.6g} in, refitted {radius_entries['radius_last_refit_m'] / INCH:.6g} in "
            "after the last search); give it with --radius.", file=sys.stderr)
        return 1
    return 0


def with_normal_load(record, path, normal_load):
    """`record`, with the constant `normal_load` [N] (`--normal-load`) where it states none."""
    import numpy as np

    if record.normal_load is not None:
        return record
    if normal_load is None:
        raise ValueError(f"{path}: the record has no normal load; give one with --normal-load: the "
                         "load that presses the surfaces together, or one that puts force / N "
                         "near 0.1 (e.g. ten times the typical force).")
    return dataclasses.replace(record, normal_load=np.full(np.shape(record.ux), float(normal_load)))


def _fit_summary(result) -> dict:
    return {"command": "diagnose", "effects": result.effects,
            "nrmse_before": result.nrmse_initial, "nrmse": result.nrmse_final,
            "fit_convergence": dict(result.fit_convergence)}


def _parse_known(items) -> dict:
    from identification.discovery import EFFECTS

    units = {"f_max": "-", "yield_disp": "m"}
    units.update({p.name: p.unit for e in EFFECTS.values() for p in e.parameters})
    known = {}
    for item in items:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep:
            raise ValueError(f"--known: expected NAME=VALUE (e.g. rate_a=0.6s/in), got '{item}'.")
        if name not in units:
            raise ValueError(f"--known: unknown parameter '{name}'; the parameters are "
                             f"{', '.join(units)}.")
        known[name] = parse_quantity(value, _DIMENSIONS.get(units[name], "dimensionless"),
                                     where=f"--known {name}")
    return known


def main(argv=None) -> int:
    """Stand-alone entry point (`python -m identification._cli_diagnose ...`)."""
    parser = argparse.ArgumentParser(prog="teflon-jax")
    subparsers = parser.add_subparsers(dest="command", required=True)
    add_diagnose_parser(subparsers)
    args = parser.parse_args(argv)
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
