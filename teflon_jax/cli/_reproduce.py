"""The `teflon-jax reproduce --out DIR` sub-command (argparse wiring only)."""

import argparse
import sys

HELP = "regenerate Figs. 3-11 of Constantinou, Mokha & Reinhorn (1990)"
"""The line of this command in `teflon-jax --help`."""


def add_reproduce_parser(subparsers) -> argparse.ArgumentParser:
    """Add `reproduce` to an argparse `subparsers` object; returns the new parser."""
    parser = subparsers.add_parser(
        "reproduce",
        help=HELP,
        description=(
            "Rerun the paper's figures 3-11: writes PNG figures, the numbers behind them as CSV, "
            "report.md (the paper's statements beside our results) and summary.json into --out."
        ),
    )
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder (created if missing)")
    parser.add_argument("--quick", action="store_true", help="coarse Tb grid, no convergence check")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    parser.add_argument("--allow-missing", action="store_true",
                        help="exit with status 0 even when a figure had to be skipped (a record "
                        "could not be read); the skipped figures are still listed")
    return parser


def run_reproduce(args) -> int:
    """Run `reproduce` for parsed `args`; returns the exit status: 0 when every figure was
    made (or `--allow-missing`), 1 when a figure was skipped, 2 on bad input."""
    import jax

    jax.config.update("jax_enable_x64", not getattr(args, "float32", False))
    from tqdm.auto import tqdm

    from ..paper import reproduce
    from ._provenance import provenance

    bar = tqdm(total=8, desc="reproduce", unit="stage", disable=args.no_progress)

    def progress(stage, done, total):
        bar.set_postfix_str(stage)
        bar.update(done - bar.n)

    try:
        summary = reproduce(args.out, progress=progress, quick=args.quick, header=provenance())
    except (ValueError, FileNotFoundError, OSError) as error:
        print(f"teflon-jax reproduce: error: {error}", file=sys.stderr)
        return 2
    finally:
        bar.close()
    failed = [s["figure"] for s in summary["statements"] if not s["holds"]]
    print(f"wrote {args.out}/report.md and summary.json; "
          f"{len(summary['statements']) - len(failed)} of {len(summary['statements'])} statements hold")
    for skipped in summary["skipped"]:
        print(f"teflon-jax reproduce: skipped {skipped['figure']}: {skipped['reason']}", file=sys.stderr)
    if summary["skipped"] and not args.allow_missing:
        print(f"teflon-jax reproduce: {len(summary['skipped'])} figure(s) or part(s) skipped; put the "
              "records in place (see README) or pass --allow-missing to accept this.", file=sys.stderr)
        return 1
    return 0
