"""`teflon-jax fit`: fit the bearing model to test records from the command line.

Messages go to stderr; the JSON report (SI, with a "units" map) and the plot are the outputs.
"""

import argparse
import pathlib
import re
import sys

from ..units import INCH, parse_quantity
from ._bearing_flags import add_save_bearing_flag, check_output_file
from ._common import (
    ISOLATORS,
    _write_json,
    add_quantity,
    add_units_flag,
    output_units,
    read_bearing_record,
    read_quantities,
)
from ._fit_bayes import _unit_of as _unit_of
from ._fit_bayes import add_bayes_file_flags, check_bayes_flags
from ._triple import SERIES_ISOLATORS

PARAMETER_DIMENSIONS = {"f_max": "dimensionless", "delta_f": "dimensionless", "rate_a": "slowness",
                        "yield_disp": "length", "breakaway_ratio": "dimensionless"}
"""Dimension of each fitted parameter, for `--fixed NAME=VALUE` (e.g. yield_disp=0.005in)."""

FIT_HELP = "fit f_max, delta_f, rate_a, yield_disp, breakaway_ratio to bearing test records"


def add_fit_parser(subparsers) -> argparse.ArgumentParser:
    """Add the `fit` sub-command to an `argparse` sub-parser collection."""
    parser = subparsers.add_parser("fit", help=FIT_HELP, description=FIT_HELP + (
        ". Several records are fitted jointly (one parameter set). Records are test-record "
        "CSV files (FORMATS.md: time histories or digitised loops) or friction-damper JSON "
        "files. When the records do not separate f_max, delta_f and rate_a (e.g. friction "
        "that does not change over the tested speeds), the reduced law they determine is "
        "fitted (rate_a held, else Coulomb friction, delta_f = 0) and the console and the "
        "JSON ('reduced', 'reduction', 'full_model') say which constants and why. Exit "
        "status: 0 when the fit converged, whether 'clean' or not (clean: every fitted "
        "constant determined within 50 %, none at a bound, no warning; the warnings "
        "printed say why a fit is not clean, notes on high correlations leave it clean; a "
        "converged fit that is not clean is a result with those limits, and the console names "
        "the `diagnose` command that looks for the effects the model lacks); 1 when the fit, or "
        "with --bayes the sampler, did not converge (no result); 2 for bad input; 130 when "
        "--bayes is stopped with Ctrl-C."))
    parser.add_argument("records", nargs="+", metavar="RECORD",
                        help="test record files (uniaxial, or biaxial ux, uy, fx, fy: then the "
                             "constants perpendicular to the lay are fitted too)")
    parser.add_argument("--free", default=None,
                        help="comma-separated parameters to fit (default: f_max, delta_f, "
                             "rate_a, yield_disp, and breakaway_ratio when the record starts "
                             "from rest)")
    parser.add_argument("--fixed", "--known", action="append", default=None, metavar="NAME=VALUE[,...]",
                        help="values of parameters held fixed, with units where they have one "
                             "(e.g. yield_disp=0.005in,rate_a=0.6s/in,breakaway_ratio=1.5); "
                             "repeatable; --known is the same flag, as in diagnose (default: none)")
    add_quantity(parser, "--normal-load", "force", None, "normal load for records without one; "
                 "'1N' fits the force itself (f_max, delta_f in newtons)", minimum=0.0)
    parser.add_argument("--starts", type=int, default=None, help="number of least-squares starts of a "
                        "flat slider's or single pendulum's fit (default 8; the triple pendulum's fit "
                        "starts from its --isolator-file)")
    parser.add_argument("--full-model", action="store_true",
                        help="fit the default constants even when the records do not separate "
                             "them (no reduced friction law)")
    parser.add_argument("--json", required=True, metavar="OUT.json", help="JSON report (SI)")
    parser.add_argument("--plot", default=None, metavar="OUT.png",
                        help="plot of measured and fitted loops with the residual")
    parser.add_argument("--bayes", default=None, metavar="DIR",
                        help="also sample the posterior with NUTS (numpyro), warm-started from "
                             "the least-squares fit, and write posterior.json (mean, median, "
                             "5-95 %% interval, R-hat, ESS), posterior.nc (draws, ArviZ layout) "
                             "and pairs.png into DIR, and with --save-bearing the draws into the "
                             "bearing file beside the point estimate; exits 1 when the chains did "
                             "not converge, 130 on Ctrl-C (the draws so far written, not converged)")
    parser.add_argument("--prior", choices=("bounds", "table1"), default="bounds",
                        help="with --bayes: log-uniform over physical bounds, or Table 1 as an "
                             "informative prior (default bounds)")
    parser.add_argument("--draws", type=int, default=1000,
                        help="with --bayes: warm-up steps and draws per chain (default 1000)")
    parser.add_argument("--chains", type=int, default=4, help="with --bayes: chains (default 4)")
    parser.add_argument("--seed", type=int, default=0, help="with --bayes: random seed (default 0)")
    parser.add_argument("--no-progress", action="store_true", help="with --bayes: no progress bar")
    add_bayes_file_flags(parser)
    parser.add_argument("--effects", default=None, metavar="NAME,...",
                        help="fit Eq. 1 with Bouc-Wen plus these optional parts of the bearing "
                             "model (one record; e.g. backlash,asymmetry as `diagnose` names "
                             "them; 'list' prints the known ones); --fixed then also takes "
                             "their constants")
    parser.add_argument("--isolator", default="flat", choices=ISOLATORS,
                        help="single-fp: the records are of a single friction pendulum, force "
                        "N u / R + friction; fit its radius R too ('--fixed radius=88in' holds "
                        "it). triple-fp: one record of a triple friction pendulum, fitted from "
                        "--isolator-file's constants (its radii, friction of each surface, "
                        "and capacities where the loop reaches them; --free names them). double-fp: "
                        "the same of a double friction pendulum (R_1, R_2 and each surface's "
                        "friction; bottom and top kept in the start file's order of f_max, which a "
                        "loop cannot tell) (default flat)")
    parser.add_argument("--isolator-file", default=None, metavar="START.json", type=pathlib.Path,
                        help="with --isolator triple-fp or double-fp: the isolator file the fit starts from "
                        "(and whose constants it holds where the record cannot tell them)")
    parser.add_argument("--save-isolator", default=None, metavar="FITTED.json", type=pathlib.Path,
                        help="with --isolator triple-fp or double-fp: write the fitted isolator file (the "
                        "format of --isolator-file)")
    add_save_bearing_flag(parser)
    add_units_flag(parser)
    parser.set_defaults(command_function=run_fit)
    return parser


def _parse_fixed(text):
    from identification.bearing_fit import PARAMETER_NAMES

    fixed = {}
    if not text:
        return fixed
    if not isinstance(text, str):  # the repeated flag: one list
        text = ",".join(text)
    for item in text.split(","):
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep:
            raise ValueError(f"--fixed: '{item}' is not NAME=VALUE.")
        if name not in PARAMETER_NAMES:
            raise ValueError(f"--fixed: unknown parameter '{name}'; the parameters are "
                             f"{', '.join(PARAMETER_NAMES)}.")
        fixed[name] = parse_quantity(value, PARAMETER_DIMENSIONS.get(name, "dimensionless"),
                                     where=f"--fixed {name}")
    return fixed


DEFAULT_STARTS = 8
"""`--starts` of a flat slider's or single pendulum's fit."""


def run_fit(args) -> int:
    """Run `teflon-jax fit`; returns the exit status (0 ok, 1 not converged, 2 bad input)."""
    from identification.bearing_fit import fit_bearing_test, parse_free

    from ..report import plot_fit

    try:
        check_bayes_flags(args)
    except ValueError as error:
        print(f"teflon-jax fit: error: {error}", file=sys.stderr)
        return 2
    if args.isolator in SERIES_ISOLATORS:
        from ._fit_triple import run_fit_triple

        return run_fit_triple(args)
    args.starts = DEFAULT_STARTS if args.starts is None else args.starts
    for flag, value in (("--isolator-file", args.isolator_file), ("--save-isolator", args.save_isolator)):
        if value is not None:
            print(f"teflon-jax fit: error: {flag}: applies to --isolator triple-fp or "
                  f"double-fp only; add --isolator triple-fp (or double-fp) or leave {flag} out.", file=sys.stderr)
            return 2
    if args.isolator == "single-fp":
        from ._fit_pendulum import run_fit_pendulum

        return run_fit_pendulum(args, check_counts=_check_counts, parse_fixed=_parse_fixed,
                                save_fitted=_save_fitted, shown_as=_shown)
    if args.effects is not None:
        from ._fit_effects import run_fit_effects

        return run_fit_effects(args)
    try:
        read_quantities(args, "fit")
        check_output_file(args.save_bearing, "--save-bearing")
        _check_counts(args)  # before the fit, as the output paths (`check_outputs`)
        free = parse_free(args.free) if args.free is not None else None
        fixed = _parse_fixed(args.fixed)
        records = [read_bearing_record(p) for p in args.records]
        if args.each:
            from ._fit_bayes import run_fit_each

            return run_fit_each(args, free, fixed, records, _save_fitted)
        print(f"teflon-jax fit: {len(records)} record(s), {args.starts} least-squares starts "
              "(compiling first)...", file=sys.stderr)
        fit = fit_bearing_test(records, free=free, fixed=fixed, normal_load=args.normal_load,
                               n_starts=args.starts, reduce=not args.full_model)
    except ValueError as error:
        print(f"teflon-jax fit: error: {error}", file=sys.stderr)
        return 2
    _write_json(args.json, fit.to_json_dict())
    _save_fitted(args, fit, records)
    us = args.units == "us"
    if args.plot:
        units = output_units(args.units)
        stamp = f"{', '.join(pathlib.Path(r).name for r in args.records)}" + (
            f", normal load {args.normal_load_text}" if args.normal_load_text else "")
        plot_fit(args.plot, fit, length=units.length, force=units.force, title=stamp)
    notes = [w for w in fit.warnings if _is_correlation_note(w)]
    for warning in fit.warnings:
        kind = "note" if warning in notes else "warning"
        print(f"teflon-jax fit: {kind}: {warning}", file=sys.stderr)
    if fit.reduced:
        print(f"teflon-jax fit: reduced model: {fit.reduction} Reduced: " + "; ".join(
            f"{k} {v}" for k, v in fit.reduced.items()) + ".", file=sys.stderr)
    summary = ", ".join(_shown(k, fit.parameters[k], fit.std_errors[k], us) for k in fit.free)
    print(f"{summary}; nrmse = {fit.nrmse:.4f} [-]; {fit.message}; {fit_status(fit, len(notes), args.records)}",
          file=sys.stderr)
    if args.bayes is None or not fit.converged:
        return 0 if fit.converged else 1
    from ._fit_bayes import run_bayes

    return run_bayes(args, records, fixed, fit, _save_fitted)


def fit_status(fit, notes: int, records) -> str:
    """The last words of `fit`'s summary line, which say what its exit status means: "clean"
    (exit 0); converged but not clean, a result with the limits its warnings name (exit 0),
    with the `diagnose` command that looks for the effects the model lacks; or NOT CONVERGED,
    no result (exit 1). `notes`: how many of the warnings are notes on correlations."""
    if fit.clean:
        return "clean" + (f" ({notes} note(s) on correlations above)" if notes else "")
    names = [str(r) for r in records]
    command = (f"`teflon-jax diagnose {names[0]}`" if len(names) == 1
               else f"`teflon-jax diagnose RECORD` on each of {', '.join(names)}")
    if fit.converged:
        return (f"converged, not clean ({len(fit.warnings) - notes} warning(s) above): the constants are the "
                f"best this model reaches, with the limits the warnings name; {command} looks for the effects "
                "the model lacks")
    return (f"NOT CONVERGED: the least-squares solve stopped before reaching a minimum, so the constants are "
            f"no result (exit status 1); see the warnings above and {command}")


def _save_fitted(args, fit, records, *, posterior=None, bayes=None, path=None,
                 sources=None) -> None:
    """`--save-bearing` (or `path`): the least-squares bearing with its standard errors, and
    the draws of `posterior` (a `BearingPosterior`) with `bayes`, a summary of the run."""
    from identification.bearing_fit import fitted_bearing, part_errors

    from ..formats import interface_counts, save_bearing

    path = args.save_bearing if path is None else path
    if path is None:
        return
    series = interface_counts(records[0].metadata)[1]
    summary = {"command": "fit", "effects": [], "nrmse": fit.nrmse,
               "converged": bool(fit.converged), "free": list(fit.free)}
    save_bearing(path, fitted_bearing(fit, interfaces_in_series=series),
                 standard_errors=part_errors(fit.std_errors),
                 sources=args.records if sources is None else sources,
                 fit=summary if bayes is None else {**summary, "bayes": bayes},
                 posterior=posterior)


def _is_correlation_note(text: str) -> bool:
    """A high correlation between two fitted constants: a note, which leaves a fit clean
    (`BearingFit.clean`), not a warning."""
    return bool(re.match(r"^[a-z_]+, [a-z_]+: correlation -?[0-9.]+; ", text))


def _check_counts(args) -> None:
    """--starts >= 1; with --bayes, --draws >= 10 and --chains >= 2 (R-hat needs two chains)."""
    if args.starts < 1:
        raise ValueError(f"--starts: must be an integer >= 1 (least-squares starts), got {args.starts}.")
    if args.bayes is not None and args.draws < 10:
        raise ValueError(f"--draws: must be >= 10 (warm-up steps and draws per chain), got {args.draws}.")
    if args.bayes is not None and args.chains < 2:
        raise ValueError(f"--chains: must be >= 2 (R-hat compares chains), got {args.chains}.")


def _shown(name, value, error, us):
    """`name = value +- error unit` in the family chosen by --units."""
    from ..report import parameter_unit

    unit, factor = parameter_unit(name, ("in", INCH) if us else ("mm", 1e-3))
    error = float("nan") if error is None else error
    return f"{name} = {value / factor:.5g} +- {error / factor:.2g}{' ' + unit if unit else ''}"
