"""`teflon-jax diagnose RECORD --json OUT.json --report DIR [--isolator ISOLATOR]`.

Fits the baseline model to a test record, names the missing effects one at a time
(`identification.discovery`), and writes the JSON summary, a Markdown report with figures and,
when asked, what it found (a bearing file, or the isolator file of a series pendulum).

The command's flow is written once (`run_diagnose`); what differs between isolators is the
table `DIAGNOSES`, looked up by `--isolator`:

- `flat`: the record as it is; `discover_effects` from `--baseline` (default paper1990).
- `single-fp`: the surface's restoring force N u / R (Zayas, Low & Mahin 1990) belongs to the
  baseline and is taken off the force before the search, with R given by `--radius` or fitted
  beside the baseline's friction (Eq. 1 with Bouc-Wen, `identification.bearing_fit.
  fit_pendulum_test`). A fitted R is refitted beside the effects the search found
  (`refit_pendulum_radius`) and the search run again until R settles: the fixed point of the
  alternation is a stationary point of the squared error in R and the final model's constants
  together, as in `fit_pendulum_test`.
- `triple-fp`, `double-fp`: the baseline is the series fit of `--isolator-file` (`fit
  --isolator triple-fp|double-fp`, from the start file's values) and the candidates are the
  effects the series model represents on its surfaces (`identification.discovery.
  SERIES_EFFECTS`), judged by the flat slider's evidence and decision rule
  (`discover_series_effects`).

On stderr (not with `--quiet`) it says its plan before any fit: the candidates, the batched fits
and roughly how long they take, from their number and the record's samples; then each round's
candidates as they are tried and, as the round's fits return, each one's residual and evidence,
with the time the round took and the time the rounds left would take at its pace; the last line
is the result with the search's and the whole command's time. stdout stays empty.
"""

import argparse
import dataclasses
import pathlib
import sys
import typing

from ..units import INCH
from ._bearing_flags import add_save_bearing_flag, check_output_file
from ._common import (
    _write_json,
    add_units_flag,
    as_flags,
    output_units,
    parse_name_values,
    read_bearing_record,
)
from ._diagnose_mixture import (
    add_mixture_flags,
    check_mixture_flags,
    mixture_failure,
    mixture_lines,
    mixture_of,
    save_found_bearing,
)
from ._fit_outputs import isolator_writer
from ._isolator_flags import (
    SERIES_NAMES,
    add_isolator_flags,
    add_record_load_flags,
    check_normal_load_used,
    load_isolator_file,
    per_isolator,
)

_DIMENSIONS = {"-": "dimensionless", "m": "length", "s/m": "slowness"}

RADIUS_ROUNDS = 3
"""Most searches a single friction pendulum runs with a refitted radius after the first."""

RADIUS_RTOL = 1e-4
"""Relative change of R below which it has settled."""


HELP = "find the effects a bearing test shows beyond the 1990 model"
"""The line of this command in `teflon-jax --help`."""

EFFECT_NAMES = ("velocity_dependence", "breakaway", "pressure_dependence", "heating", "anisotropy",
                "asymmetry", "wear", "interfaces", "backlash")
"""The candidate effects (`identification.discovery.EFFECT_NAMES`), written out so that `--help`
answers without loading JAX (`tests/test_diagnose_help.py` holds the two equal)."""

BASELINES = ("paper1990", "coulomb")
"""The baselines (`identification.discovery.BASELINES`), written out likewise."""


class Found(typing.NamedTuple):
    """What one isolator's search found: `result` (`DiscoveryResult` or
    `SeriesDiscoveryResult`), `entries` added to its JSON document, `failure` (the message
    of a search that could not finish what was asked: exit status 1) or None."""

    result: object
    entries: dict
    failure: str | None = None


class Diagnosis(typing.NamedTuple):
    """How `diagnose` treats one `--isolator`.

    - `search(args, diagnosis, candidates, say) -> Found`: read the inputs and run the search;
    - `report`: the writer of `identification.discovery` for its result;
    - `saves`: (flag, attribute, what) of the file it writes what it found to;
    - `save(args, result, mixture)`: the function of no arguments that writes it there (with the
      `--mixture` of a bearing), after every check of what it writes (`ValueError` naming the
      flag: the command then writes nothing and exits 2);
    - `notes(result)`: lines said after the files are written;
    - `isolator_file`: whether `--isolator-file` is required (the series start file);
    - `refused`: (flag, attribute, message) of each flag it cannot take, in the order checked
      (the message formatted with `flag` and `isolator`);
    - `restoring_force`: the record holds a concave surface's N u / R.
    """

    search: typing.Callable
    report: str
    saves: tuple
    save: typing.Callable
    notes: typing.Callable
    isolator_file: bool
    refused: tuple
    restoring_force: bool = False


def add_diagnose_parser(subparsers) -> argparse.ArgumentParser:
    """Add the `diagnose` sub-command to an `argparse` sub-parser collection."""
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
    add_record_load_flags(parser, normal=" (e.g. a friction damper): one that puts force / N near 0.1, as the "
                          "friction constants are bounded (f_max <= 0.5)", task="searched")
    parser.add_argument("--json", type=pathlib.Path, required=True, dest="json_path",
                        metavar="OUT.json", help="where to write the JSON summary")
    parser.add_argument("--report", type=pathlib.Path, required=True, metavar="DIR",
                        help="folder for report.md and the figures")
    parser.add_argument(
        "--baseline",
        choices=BASELINES,
        default=None,
        help="model to start from (default: paper1990 = Eq. 1 + Bouc-Wen; with --isolator "
        "triple-fp|double-fp the baseline is the series fit of --isolator-file)",
    )
    parser.add_argument("--candidates", default=None,
                        help="comma-separated effects to consider (default: all applicable)")
    parser.add_argument("--bic-threshold", type=float, default=10.0,
                        help="smallest BIC drop that adds an effect (default 10, 'very strong')")
    parser.add_argument("--max-effects", type=int, default=4,
                        help="at most this many effects are added (default 4)")
    parser.add_argument("--max-samples", type=int, default=3000,
                        help="longer records are decimated to about this many samples (default 3000)")
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
    _add_isolator_flags(parser)
    add_save_bearing_flag(parser)
    add_mixture_flags(parser)
    add_units_flag(parser)
    return parser


def _add_isolator_flags(parser) -> None:
    """`--isolator`, `--radius R`, `--isolator-file START.json` and `--save-isolator FILE`."""
    add_isolator_flags(
        parser, isolator="single-fp: the record is of a single friction pendulum; its restoring force N u / R "
        "joins the baseline and the search looks at the friction; triple-fp, double-fp: the baseline is the "
        "series fit of --isolator-file and the candidates its surfaces' effects",
        radius="the radius R of the concave surface, when known (default: fitted with the baseline's friction)",
        file="the isolator file the series fit starts from (a surface's 'heating' entry gives the heating "
        "candidate its contact pressure; docs/formats.md)", file_metavar="START.json",
        save="write the final model as an isolator file (with the surfaces' heating when it was added)")


def run_diagnose(args) -> int:
    """Run `diagnose` for parsed arguments; returns the exit status (0 ok, 1 a search that could
    not finish what was asked, e.g. a fitted radius that did not settle beside the effects
    found; 2 bad input, or a found model the file of --save-bearing or --save-isolator cannot
    hold, refused before any output is written)."""
    import time

    started = time.perf_counter()

    def say(text):
        if not args.quiet:
            print(text, file=sys.stderr, flush=True)

    say(f"teflon-jax diagnose {args.record}: loading JAX, then reading the record and planning "
        "the search...")
    from identification import discovery

    diagnosis = DIAGNOSES[args.isolator]

    candidates = None
    if args.candidates:
        candidates = [c.strip() for c in args.candidates.split(",") if c.strip()]
    try:
        check_flags(args, diagnosis)
        found = diagnosis.search(args, diagnosis, candidates, say)
        mixture = mixture_of(args, found.result)
    except (ValueError, FileNotFoundError) as error:
        print(f"teflon-jax diagnose: error: {error}", file=sys.stderr)
        return 2
    result = found.result
    flag, attribute, what = diagnosis.saves
    saved = getattr(args, attribute)
    try:  # every check of the saved file, before the first output is written
        write_saved = diagnosis.save(args, result, mixture) if saved is not None else None
    except ValueError as error:
        print(f"teflon-jax diagnose: error: {error}", file=sys.stderr)
        return 2
    say(f"writing {args.json_path}, {args.report / 'report.md'} and its figures...")
    document = result.to_json()
    document.update(found.entries)
    if mixture is not None:
        document["mixture"] = mixture.to_json()
    _write_json(args.json_path, document)
    report = getattr(discovery, diagnosis.report)(
        result, args.report, record_name=args.record.name, length=output_units(args.units).length,
        **({} if mixture is None else {"mixture": mixture}))
    if write_saved is not None:
        write_saved()
    for line in diagnosis.notes(result) + mixture_lines(mixture):
        say(line)
    say(f"{document['conclusion']}; nrmse {result.nrmse_initial:.4f} -> {result.nrmse_final:.4f}; "
        f"search {result.runtime_s:.1f} s, total {time.perf_counter() - started:.1f} s. "
        f"Wrote {args.json_path} and {report}"
        + (f" and the {what} to {saved}." if saved else "."))
    failures = [f for f in (found.failure, mixture_failure(args, mixture)) if f is not None]
    for failure in failures:
        print(f"teflon-jax diagnose: {failure}", file=sys.stderr)
    return 1 if failures else 0


def check_flags(args, diagnosis: Diagnosis) -> None:
    """`ValueError` naming the first flag `args.isolator` cannot take, before any work: a
    missing or absent start file, a flag of another isolator, an output that cannot be
    written."""
    isolator = args.isolator
    if diagnosis.isolator_file and args.isolator_file is None:
        raise ValueError(f"--isolator-file: --isolator {isolator} starts the series fit from an "
                         "isolator file (radius, capacity and friction of each surface; docs/formats.md).")
    for flag, attribute, message in diagnosis.refused:
        value = getattr(args, attribute)
        if value is not None and value != []:
            raise ValueError(message.format(flag=flag, isolator=isolator))
    if diagnosis.isolator_file and not args.isolator_file.is_file():
        raise ValueError(f"--isolator-file: {args.isolator_file} does not exist.")
    flag, attribute, _ = diagnosis.saves
    check_output_file(getattr(args, attribute), flag)
    check_mixture_flags(args)
    check_search_flags(args)


def check_search_flags(args) -> None:
    """`ValueError` naming the flag for a search setting out of range (--bic-threshold,
    --max-effects, --max-samples) or an effect --candidates does not know, before any work."""
    import math

    from identification.discovery import EFFECT_NAMES, MIN_SAMPLES

    if not (math.isfinite(args.bic_threshold) and args.bic_threshold >= 0):
        raise ValueError(f"--bic-threshold: must be a finite number >= 0 (the smallest drop of the BIC that "
                         f"adds an effect), got {args.bic_threshold:g}.")
    if args.max_effects < 0:
        raise ValueError(f"--max-effects: must be >= 0 (0 fits the baseline alone), got {args.max_effects}.")
    if args.max_samples < MIN_SAMPLES:
        raise ValueError(f"--max-samples: must be >= {MIN_SAMPLES} (the record is decimated to about this many "
                         f"samples), got {args.max_samples}.")
    names = [c.strip() for c in (args.candidates or "").split(",") if c.strip()]
    unknown = [c for c in names if c not in EFFECT_NAMES]
    if unknown or (args.candidates is not None and not names):
        raise ValueError(f"--candidates {args.candidates}: unknown effect {', '.join(unknown) or '(none named)'}; "
                         f"choose among {', '.join(EFFECT_NAMES)}.")


# ------------------------------------------------------------------ flat and single-fp sliders


def _search_slider(args, diagnosis, candidates, say) -> Found:
    """The flat slider's search, on the record less N u / R for a single friction pendulum."""
    from identification.discovery import discover_effects

    args.baseline = args.baseline or "paper1990"
    known = parse_name_values(args.known, known_dimensions(), "--known")
    record = read_bearing_record(args.record)
    check_normal_load_used(args, [record], [args.record])
    record = with_normal_load(record, args.record, args.normal_load)

    def search(friction_record):
        return discover_effects(friction_record, baseline=args.baseline, candidates=candidates,
                                bic_threshold=args.bic_threshold, max_effects=args.max_effects,
                                max_samples=args.max_samples, known=known, callback=say)

    if not diagnosis.restoring_force:
        return Found(search(record), {})
    result, radius, entries = _search_pendulum(args, record, search, say)
    failure = None
    if entries.get("radius_settled") is False:
        failure = (f"the radius did not settle beside the effects found ({radius / INCH:.6g} in, "
                   f"refitted {entries['radius_last_refit_m'] / INCH:.6g} in after the last search); "
                   "give it with --radius.")
    return Found(result, {"isolator": args.isolator, "radius_m": radius,
                          "radius_given": args.radius is not None, **entries}, failure)


def _pendulum_radius(args, record, say) -> float:
    """R [m] of `--radius`, or fitted with the baseline's friction (Eq. 1 with Bouc-Wen)."""
    from identification.bearing_fit import fit_pendulum_test

    if args.radius is not None:
        say(f"single friction pendulum: R = {args.radius_text} (--radius); the search looks at the "
            "force less N u / R.")
        return args.radius
    say("single friction pendulum: fitting R with the baseline's friction (Eq. 1 with Bouc-Wen, "
        "4 starts; compiling first), before the search...")
    fit = fit_pendulum_test(record, n_starts=4)
    if not fit.converged:
        raise ValueError(f"{args.record}: the radius could not be fitted with the baseline's "
                         "friction (the fit did not converge); give it with --radius.")
    say(f"single friction pendulum: R = {fit.radius / INCH:.5g} in +- {fit.radius_std_error / INCH:.2g} in, "
        "fitted with Eq. 1 friction and held; the search looks at the force less N u / R.")
    return fit.radius


def _search_pendulum(args, record, search, say):
    """`search(friction record)` on `record` less N u / R; a fitted R refitted beside what each
    search found and the search rerun, at most `RADIUS_ROUNDS` times.

    **Returns:** (the last search's result, R [m], the JSON entries of a fitted radius: the
    baseline's R, the reruns and whether R settled within `RADIUS_RTOL`)."""
    from identification.bearing_fit import pendulum_friction_record, refit_pendulum_radius

    radius = _pendulum_radius(args, record, say)
    result = search(pendulum_friction_record(record, radius))
    if args.radius is not None:
        return result, radius, {}
    entries = {"radius_with_baseline_m": radius}
    for rounds in range(RADIUS_ROUNDS + 1):
        new = refit_pendulum_radius(result.data, result.forces["final"], radius)
        settled = abs(new - radius) <= RADIUS_RTOL * radius
        if settled or rounds == RADIUS_ROUNDS:
            break
        say(f"single friction pendulum: R refitted beside the effects found: {new / INCH:.6g} in "
            f"(was {radius / INCH:.6g} in); searching again.")
        radius = new
        result = search(pendulum_friction_record(record, radius))
    entries.update(radius_reruns=rounds, radius_settled=bool(settled), radius_last_refit_m=new)
    return result, radius, entries


def _stack_notes(result) -> list:
    stack = result.stack_check
    if not stack or stack["consistent_with_stated"]:
        return []
    return [f"stack check: the fitted rate_a is rate_a / n = {stack['rate_effective'] * INCH:.3g} "
            f"s/in; with a single-interface rate_a within Table 1's range, n is in "
            f"[{stack['n_low']:.1f}, {stack['n_high']:.1f}] interfaces in series (not separable "
            "from rate_a; give --known rate_a=... to identify n)."]


# ------------------------------------------------------------------ triple and double pendulums


def _search_series(args, diagnosis, candidates, say) -> Found:
    """The series pendulum's search from the start file of `--isolator-file`."""
    from identification.discovery import discover_series_effects

    start = load_isolator_file(args.isolator_file, args.isolator, command="diagnose")
    record = read_bearing_record(args.record)
    check_normal_load_used(args, [record], [args.record])
    try:
        result = discover_series_effects(
            record, start, candidates=candidates, bic_threshold=args.bic_threshold,
            max_effects=args.max_effects, max_samples=args.max_samples,
            normal_load=args.normal_load, reference_load=args.reference_load, callback=say)
    except ValueError as error:
        raise ValueError(as_flags(str(error))) from None
    return Found(result, {} if args.reference_load is None else {"reference_load_N": args.reference_load})


def _save_isolator(args, result, mixture):
    return isolator_writer(args.save_isolator, result.pendulum())


def _held_notes(result) -> list:
    return [f"held: {reason}" for reason in dict.fromkeys(result.held.values())]


# ------------------------------------------------------------------ the table


def _not_series(flag):
    return (flag, flag[2:].replace("-", "_"), "{flag}: applies to --isolator " + SERIES_NAMES + " only (the "
            "{isolator} bearing has no isolator file); leave {flag} out.")


def _not_with_series(flag, attribute, why):
    return (flag, attribute, "{flag}: not with --isolator {isolator} (" + why + "); leave {flag} out.")


_SLIDER = Diagnosis(
    search=_search_slider, report="write_report", saves=("--save-bearing", "save_bearing", "bearing"),
    save=save_found_bearing, notes=_stack_notes, isolator_file=False,
    refused=(_not_series("--isolator-file"), _not_series("--save-isolator"), _not_series("--reference-load")))

_SERIES = Diagnosis(
    search=_search_series, report="write_series_report",
    saves=("--save-isolator", "save_isolator", "isolator"), save=_save_isolator, notes=_held_notes,
    isolator_file=True,
    refused=(_not_with_series("--radius", "radius", "the radii come from --isolator-file"),
             _not_with_series("--baseline", "baseline", "the baseline is the series fit of "
                              "--isolator-file"),
             _not_with_series("--known", "known", "the series fit holds what the record cannot "
                              "tell at --isolator-file's values"),
             _not_with_series("--save-bearing", "save_bearing", "a bearing file holds one flat "
                              "slider: give --save-isolator"),
             _not_with_series("--mixture", "mixture", "the compositions' mixture is a bearing "
                              "file's, and a bearing file holds one flat slider")))

DIAGNOSES = per_isolator(
    flat=_SLIDER._replace(refused=_SLIDER.refused + (
        ("--radius", "radius", "--radius: applies to --isolator single-fp only (a flat slider has "
         "no radius); add --isolator single-fp or leave --radius out."),)),
    single=_SLIDER._replace(restoring_force=True),
    series=lambda name, facts: _SERIES,
)
"""`--isolator` -> its `Diagnosis`: every isolator `diagnose` takes (`per_isolator`)."""


# ------------------------------------------------------------------ shared with fit --effects


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


def known_dimensions() -> dict:
    """{name: dimension} of the constants `--known` holds: f_max, yield_disp and every
    effect's parameters (`identification.discovery.EFFECTS`)."""
    from identification.discovery import EFFECTS

    units = {"f_max": "-", "yield_disp": "m"}
    units.update({p.name: p.unit for e in EFFECTS.values() for p in e.parameters})
    return {name: _DIMENSIONS.get(unit, "dimensionless") for name, unit in units.items()}


def main(argv=None) -> int:
    """Stand-alone entry point (`python -m teflon_jax.cli._diagnose ...`)."""
    parser = argparse.ArgumentParser(prog="teflon-jax")
    subparsers = parser.add_subparsers(dest="command", required=True)
    add_diagnose_parser(subparsers)
    args = parser.parse_args(argv)
    return run_diagnose(args)


if __name__ == "__main__":
    sys.exit(main())
