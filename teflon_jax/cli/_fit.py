"""`teflon-jax fit`: fit the bearing model to test records from the command line.

The lead's `teflon_jax/_cli.py` wires `add_fit_parser` and `run_fit` into the `teflon-jax`
command. Messages go to stderr; the JSON report and the plot are the outputs.
"""

import argparse
import pathlib
import sys

FIT_HELP = "fit f_max, delta_f, rate_a, yield_disp, breakaway_ratio to bearing test records"


def add_fit_parser(subparsers) -> argparse.ArgumentParser:
    """Add the `fit` sub-command to an `argparse` sub-parser collection."""
    parser = subparsers.add_parser("fit", help=FIT_HELP, description=FIT_HELP + (
        ". Several records are fitted jointly (one parameter set). Records are test-record "
        "CSV files (FORMATS.md) or friction-damper JSON files."))
    parser.add_argument("records", nargs="+", metavar="RECORD",
                        help="test record files (uniaxial, or biaxial ux, uy, fx, fy: then the "
                             "constants perpendicular to the lay are fitted too)")
    parser.add_argument("--free", default=None,
                        help="comma-separated parameters to fit (default: f_max, delta_f, "
                             "rate_a, yield_disp, and breakaway_ratio when the record starts "
                             "from rest)")
    parser.add_argument("--fixed", default=None, metavar="NAME=VALUE,...",
                        help="values of parameters held fixed, SI (e.g. yield_disp=1.27e-4)")
    parser.add_argument("--normal-load", default=None, metavar="LOAD",
                        help="normal load with its unit (e.g. 78.5kip, 350kN) for records without "
                             "one; '1N' fits the force itself (f_max, delta_f in newtons)")
    parser.add_argument("--starts", type=int, default=8, help="number of starts (default 8)")
    parser.add_argument("--json", required=True, metavar="OUT.json", help="JSON report (SI)")
    parser.add_argument("--plot", default=None, metavar="OUT.png",
                        help="plot of measured and fitted loops with the residual")
    parser.set_defaults(command_function=run_fit)
    return parser


def _parse_fixed(text):
    from identification.bearing_fit import PARAMETER_NAMES

    fixed = {}
    if not text:
        return fixed
    for item in text.split(","):
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep:
            raise ValueError(f"--fixed: '{item}' is not NAME=VALUE.")
        if name not in PARAMETER_NAMES:
            raise ValueError(f"--fixed: unknown parameter '{name}'; the parameters are "
                             f"{', '.join(PARAMETER_NAMES)}.")
        try:
            fixed[name] = float(value)
        except ValueError:
            raise ValueError(f"--fixed: value of {name} is not a number: '{value}'.") from None
    return fixed


def read_record(path):
    """A `TestRecord` from a CSV test record or a friction-damper JSON file."""
    path = pathlib.Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such file.")
    if path.suffix.lower() == ".json":
        from ..formats import read_friction_damper_json

        return read_friction_damper_json(path)
    from ..formats import read_test_record

    return read_test_record(path)


def run_fit(args) -> int:
    """Run `teflon-jax fit`; returns the exit status (0 ok, 1 not converged, 2 bad input)."""
    from identification.bearing_fit import (
        fit_bearing_test,
        parse_free,
        plot_fit,
        write_fit_json,
    )

    try:
        free = parse_free(args.free) if args.free is not None else None
        fixed = _parse_fixed(getattr(args, "fixed", None))
        records = [read_record(p) for p in args.records]
        normal_load = getattr(args, "normal_load", None)
        if normal_load is not None:
            from ..units import parse_quantity

            normal_load = parse_quantity(normal_load, "force", where="--normal-load")
            if not normal_load > 0:
                raise ValueError(f"--normal-load: must be > 0, got {args.normal_load}.")
        fit = fit_bearing_test(records, free=free, fixed=fixed, normal_load=normal_load,
                               n_starts=getattr(args, "starts", 8))
    except ValueError as error:
        print(f"teflon-jax fit: error: {error}", file=sys.stderr)
        return 2
    write_fit_json(args.json, fit)
    if args.plot:
        plot_fit(args.plot, fit)
    for warning in fit.warnings:
        print(f"teflon-jax fit: warning: {warning}", file=sys.stderr)
    summary = ", ".join(f"{k} = {fit.parameters[k]:.5g} +- {fit.std_errors[k]:.2g}"
                        for k in fit.free)
    status = "clean" if fit.clean else (
        f"NOT CLEAN ({len(fit.warnings)} warning(s) above)" if fit.converged else "NOT CONVERGED")
    print(f"{summary}; nrmse = {fit.nrmse:.4f}; {fit.message}; {status}", file=sys.stderr)
    return 0 if fit.converged else 1
