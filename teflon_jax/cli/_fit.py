"""`teflon-jax fit`: fit the bearing model to test records from the command line.

One flow for every isolator: what differs (the flags an isolator refuses or needs, the
constants `--fixed` takes, the fitter, the printed, plotted and saved result) is its row of
`_isolator_table.FIT_ROWS`, looked up by `--isolator`. Messages go to stderr; the JSON report
(SI, with a "units" map) and the plot are the outputs.
"""

import argparse
import pathlib
import sys

from ._bearing_flags import add_save_bearing_flag, check_output_file
from ._common import (
    _write_json,
    add_units_flag,
    read_bearing_record,
    read_quantities,
    seed_value,
)
from ._fit_bayes import _unit_of as _unit_of
from ._fit_bayes import add_bayes_file_flags, check_bayes_flags
from ._fit_outputs import bearing_writer, isolator_writer
from ._isolator_flags import (
    add_isolator_flags,
    add_record_load_flags,
    check_normal_load_used,
)
from ._isolator_table import FIT_ROWS, refused, required
from ._paths import check_distinct_files

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
        "with --bayes the sampler, did not converge (no result); 2 for bad input, and for a fitted "
        "isolator --save-isolator, or bearing --save-bearing, cannot hold (e.g. friction out of the "
        "series model's order), refused before anything is written; 130 when --bayes is stopped with Ctrl-C."))
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
    add_record_load_flags(parser, normal="; '1N' fits the force itself (f_max, delta_f in newtons)", task="fitted")
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
                             "not converge, 130 on Ctrl-C (the draws so far written, not converged). "
                             "With --isolator single-fp: the liner's friction, sampled on the records "
                             "less N u / R at the fitted radius (R held there)")
    parser.add_argument("--prior", choices=("bounds", "table1"), default=None,
                        help="with --bayes: log-uniform over physical bounds, or Table 1 as an "
                             "informative prior (default bounds)")
    parser.add_argument("--draws", type=int, default=None,
                        help="with --bayes: warm-up steps and draws per chain (default 1000)")
    parser.add_argument("--chains", type=int, default=None, help="with --bayes: chains (default 4)")
    parser.add_argument("--seed", type=seed_value, default=None, help="with --bayes: random seed, 0 to 4294967295 (default 0)")
    parser.add_argument("--no-progress", action="store_true", help="with --bayes: no progress bar")
    add_bayes_file_flags(parser)
    parser.add_argument("--effects", default=None, metavar="NAME,...",
                        help="fit Eq. 1 with Bouc-Wen plus these optional parts of the bearing "
                             "model (one record; e.g. backlash,asymmetry as `diagnose` names "
                             "them; 'list' prints the known ones); --fixed then also takes "
                             "their constants")
    add_isolator_flags(
        parser, radius=None, isolator="single-fp: the records are of a single friction pendulum, force N u / R + "
        "friction; fit its radius R too ('--fixed radius=88in' holds it). triple-fp: one record of a triple "
        "friction pendulum, fitted from --isolator-file's constants (its radii, friction of each surface, and "
        "capacities where the loop reaches them; --free names them). double-fp: the same of a double friction "
        "pendulum (R_1, R_2 and each surface's friction; bottom and top kept in the start file's order of "
        "f_max, which a loop cannot tell)",
        file="the isolator file the fit starts from (and whose constants it holds where the record cannot "
        "tell them)", file_metavar="START.json",
        save="write the fitted isolator file (the format of --isolator-file)", save_metavar="FITTED.json")
    add_save_bearing_flag(parser)
    add_units_flag(parser)
    parser.set_defaults(command_function=run_fit)
    return parser


def run_fit(args) -> int:
    """Run `teflon-jax fit`; returns the exit status (0 ok, 1 not converged, 2 bad input or a
    fitted isolator --save-isolator or bearing --save-bearing cannot hold, refused before any
    output is written)."""
    row = FIT_ROWS[args.isolator]
    try:
        check_bayes_flags(args, posterior=row.posterior, series=row.bayes is not None)
        read_quantities(args, "fit")
        _check_isolator_flags(args, row)
    except ValueError as error:
        print(f"teflon-jax fit: error: {error}", file=sys.stderr)
        return 2
    args.starts = row.starts if args.starts is None else args.starts  # as the JSON's settings say
    if args.effects is not None:  # the rows that cannot take --effects refused it above
        from ._fit_effects import run_fit_effects

        return run_fit_effects(args)
    try:
        check_output_file(args.save_bearing, "--save-bearing")
        _check_counts(args)  # before the fit, as the output paths (`check_outputs`)
        inputs = row.read(args, row.own)
        check_distinct_files([("the record", p) for p in args.records], "give each record once (one given twice counts its "
                             "samples twice and shrinks the standard errors by a factor of sqrt(2))")
        records = [read_bearing_record(p) for p in args.records]
        check_normal_load_used(args, records, args.records)
        if args.each:  # a row without a posterior refused --each above
            from ._fit_bayes import run_fit_each

            return run_fit_each(args, inputs.free, inputs.fixed, records, _save_fitted)
        print(f"teflon-jax fit: {row.announce(args, inputs, records)}", file=sys.stderr)
        fit = row.solve(args, inputs, records)
    except ValueError as error:
        print(f"teflon-jax fit: error: {error}", file=sys.stderr)
        return 2
    friction = row.friction(fit)
    try:  # every check of what --save-isolator and --save-bearing write, before the first output
        write_isolator = (isolator_writer(args.save_isolator, fit.bearing)
                          if args.save_isolator is not None else None)  # the series rows alone take it
        write_bearing = _fitted_writer(args, friction, records) if friction is not None else None
    except ValueError as error:
        print(f"teflon-jax fit: error: {error}", file=sys.stderr)
        return 2
    _write_json(args.json, fit.to_json_dict())
    for write in (write_bearing, write_isolator):
        if write is not None:
            write()
    if args.plot:
        row.plot(args, fit, records)
    for line in row.report(args, fit):
        print(line, file=sys.stderr)
    if args.bayes is None or not fit.converged:  # a row without a posterior refused --bayes above
        return 0 if fit.converged else 1
    if row.bayes is not None:
        return row.bayes(args, fit, records)
    from ._fit_bayes import run_bayes

    return run_bayes(args, row.sampled(args, fit, records), inputs.fixed, friction, _save_fitted)


def _check_isolator_flags(args, row) -> None:
    """`ValueError` naming the first flag the isolator's row needs and is missing (or names a
    missing file), refuses, or the record count or an output path it cannot take."""
    required(args, row.requires)
    for name, _ in row.requires:
        value = getattr(args, name)
        if isinstance(value, pathlib.Path) and not value.is_file():
            raise ValueError(f"--{name.replace('_', '-')}: {value} does not exist.")
    refused(args, row.refuses)
    if row.one_record and len(args.records) != 1:
        raise ValueError(f"RECORD: --isolator {args.isolator} fits one record, got {len(args.records)}.")
    check_output_file(args.save_isolator, "--save-isolator")
    check_output_file(args.plot, "--plot")


def _save_fitted(args, fit, records, **entries) -> None:
    """`--save-bearing` (or `path`): the least-squares bearing with its standard errors, and
    the draws of `posterior` (a `BearingPosterior`) with `bayes`, a summary of the run
    (`_fitted_writer`'s file, written at once)."""
    _fitted_writer(args, fit, records, **entries)()


def _fitted_writer(args, fit, records, *, posterior=None, bayes=None, path=None, sources=None):
    """A function of no arguments that writes `_save_fitted`'s bearing file (nothing without
    `--save-bearing` or `path`); `ValueError` naming --save-bearing first when the file cannot
    hold the fitted bearing (`_fit_outputs.bearing_writer`: built and read back as
    `load_bearing` reads it)."""
    from identification.bearing_fit import fitted_bearing, part_errors

    from ..formats import interface_counts

    path = args.save_bearing if path is None else path
    if path is None:
        return lambda: None
    series = interface_counts(records[0].metadata)[1]
    summary = {"command": "fit", "effects": [], "nrmse": fit.nrmse,
               "converged": bool(fit.converged), "free": list(fit.free)}
    return bearing_writer(path, fitted_bearing(fit, interfaces_in_series=series),
                          standard_errors=part_errors(fit.std_errors),
                          sources=args.records if sources is None else sources,
                          fit=summary if bayes is None else {**summary, "bayes": bayes},
                          posterior=posterior)


def _check_counts(args) -> None:
    """--starts >= 1 (where the fit makes starts); with --bayes, --draws >= 10 and --chains >= 2
    (R-hat needs two chains)."""
    if args.starts is not None and args.starts < 1:
        raise ValueError(f"--starts: must be an integer >= 1 (least-squares starts), got {args.starts}.")
    if args.bayes is not None and args.draws < 10:
        raise ValueError(f"--draws: must be >= 10 (warm-up steps and draws per chain), got {args.draws}.")
    if args.bayes is not None and args.chains < 2:
        raise ValueError(f"--chains: must be >= 2 (R-hat compares chains), got {args.chains}.")
