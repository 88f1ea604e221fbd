"""`teflon-jax diagnose --isolator triple-fp|double-fp --isolator-file START.json RECORD.csv`:
discovery on a triple or double friction pendulum's record. The baseline is the series fit
(`fit --isolator triple-fp|double-fp`, from the start file's values); the candidates are the
effects the series model represents on its surfaces (`identification.discovery.SERIES_EFFECTS`:
frictional heating of each surface), judged by the flat slider's evidence and decision rule
(`identification.discovery.discover_series_effects`)."""

import pathlib
import sys

from ._bearing_flags import check_output_file
from ._common import _write_json, output_units
from ._triple import SERIES_ISOLATORS, _load


def add_series_diagnose_flags(parser) -> None:
    """`--isolator-file START.json` and `--save-isolator FILE` of `diagnose`."""
    parser.add_argument("--isolator-file", default=None, metavar="START.json", type=pathlib.Path,
                        help="with --isolator triple-fp|double-fp: the isolator file the series "
                        "fit starts from (a surface's 'heating' entry gives the heating candidate "
                        "its contact pressure; docs/formats.md)")
    parser.add_argument("--save-isolator", default=None, metavar="FILE", type=pathlib.Path,
                        help="with --isolator triple-fp|double-fp: write the final model as an "
                        "isolator file (with the surfaces' heating when it was added)")


def check_series_flags(args) -> None:
    """`ValueError` naming each flag that does not apply to `args.isolator`."""
    series = args.isolator in SERIES_ISOLATORS
    if not series:
        for flag, value in (("--isolator-file", args.isolator_file),
                            ("--save-isolator", args.save_isolator)):
            if value is not None:
                raise ValueError(f"{flag}: applies to --isolator triple-fp or double-fp only (the "
                                 f"{args.isolator} bearing has no isolator file); leave {flag} out.")
        return
    if args.isolator_file is None:
        raise ValueError(f"--isolator-file: --isolator {args.isolator} starts the series fit from an "
                         "isolator file (radius, capacity and friction of each surface; docs/formats.md).")
    refused = (("--radius", args.radius, "the radii come from --isolator-file"),
               ("--baseline", args.baseline, "the baseline is the series fit of --isolator-file"),
               ("--known", args.known or None, "the series fit holds what the record cannot tell "
                "at --isolator-file's values"),
               ("--save-bearing", args.save_bearing, "a bearing file holds one flat slider: give "
                "--save-isolator"))
    for flag, value, why in refused:
        if value is not None:
            raise ValueError(f"{flag}: not with --isolator {args.isolator} ({why}); leave {flag} out.")
    if not args.isolator_file.is_file():
        raise ValueError(f"--isolator-file: {args.isolator_file} does not exist.")
    check_output_file(args.save_isolator, "--save-isolator")


def load_start(args):
    """The start pendulum of `--isolator-file`; `ValueError` naming the file when it is not of
    `--isolator`'s kind."""
    return _load(args.isolator_file, args.isolator, command="diagnose")


def run_series_diagnose(args, candidates, say) -> int:
    """`diagnose --isolator triple-fp|double-fp`: exit 0 done, 2 bad input."""
    from identification.discovery import discover_series_effects, write_series_report

    from ..formats import write_isolator
    from ._common import read_bearing_record

    try:
        check_series_flags(args)
        start = load_start(args)
        record = read_bearing_record(args.record)
        say(f"teflon-jax diagnose: {start.description}, the series fit and each candidate on the "
            "record and two folds of its cycles (compiling first)...")
        result = discover_series_effects(
            record, start, candidates=candidates, bic_threshold=args.bic_threshold,
            max_effects=args.max_effects, max_samples=args.max_samples,
            normal_load=args.normal_load, callback=say)
    except ValueError as error:
        print(f"teflon-jax diagnose: {error}", file=sys.stderr)
        return 2
    document = result.to_json()
    _write_json(args.json_path, document)
    report = write_series_report(result, args.report, record_name=args.record.name,
                                 length=output_units(args.units).length)
    if args.save_isolator is not None:
        write_isolator(args.save_isolator, result.pendulum())
    for reason in dict.fromkeys(result.held.values()):
        say(f"held: {reason}")
    say(f"{document['conclusion']}; nrmse {result.nrmse_initial:.4f} -> {result.nrmse_final:.4f}; "
        f"{result.runtime_s:.1f} s. Wrote {args.json_path} and {report}"
        + (f" and the isolator to {args.save_isolator}." if args.save_isolator else "."))
    return 0
