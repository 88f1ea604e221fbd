"""What `teflon-jax fit` and `simulate-test` do differently for each isolator: one row per
`--isolator` name (`FIT_ROWS`, `TEST_ROWS`, keyed by `_isolator_flags.per_isolator` from the
command line's one list of isolators, which mirrors the registry
`teflon_jax.bearing.ISOLATORS`). The commands' flows (`_fit.run_fit`,
`_simulate.run_simulate`) look the row up once and read these facts from it: the flags the
isolator refuses or needs, the constants `--fixed` takes beside the friction law's, how its
inputs are read, how it is fitted, printed, plotted and saved.

The friction-law fits (flat slider, single pendulum) share `_parse_fixed`, `fit_status` and
`_shown`; the series pendulums fit the constants of a start file (`--isolator-file`).
JAX is imported inside the functions (`--help` loads none).
"""

import dataclasses
import functools
import pathlib
import re
from collections.abc import Callable
from typing import NamedTuple

from ..catalogue import IN_SERIES
from ..units import INCH, parse_quantity
from ._common import as_flags, name_value_items, output_units, parse_name_values
from ._isolator_flags import SERIES_NAMES, per_isolator
from ._isolator_flags import load_isolator_file as _load

PARAMETER_DIMENSIONS = {"f_max": "dimensionless", "delta_f": "dimensionless", "rate_a": "slowness",
                        "yield_disp": "length", "breakaway_ratio": "dimensionless"}
"""Dimension of each fitted parameter, for `--fixed NAME=VALUE` (e.g. yield_disp=0.005in)."""

DEFAULT_STARTS = 8
"""`--starts` of a flat slider's or single pendulum's fit."""


@dataclasses.dataclass(frozen=True)
class OwnConstant:
    """A constant of the isolator itself that `--fixed NAME=VALUE` holds beside the friction
    law's: its `dimension`, an `example` value and what a valid value `must_be`."""

    dimension: str
    example: str
    must_be: str


class FitInputs(NamedTuple):
    """What a fit reads from the flags: `free` (parsed, or --free's text for the fitter to
    read), `fixed` (friction constants held [SI]), `own` (the isolator's held constants,
    keyword -> SI value) and `start` (the isolator of --isolator-file, or None)."""

    free: object
    fixed: dict
    own: dict
    start: object = None


@dataclasses.dataclass(frozen=True)
class FitRow:
    """How `fit` treats one isolator. `requires` and `refuses`: the flags it needs and those it
    cannot take (`required`, `refused`: attribute of the parsed arguments, message), checked in
    that order; `one_record`: it fits one record; `starts`: default --starts (None: no
    starts); `own`: `OwnConstant`s by name; `posterior`: --each can fit and sample its law
    record by record. The callables take the parsed arguments `args`: `read(args, own) ->
    FitInputs`, `announce(args, inputs, records) -> str`, `solve(args, inputs, records) ->
    result`, `friction(result)` -> the friction law's `BearingFit` (saved with --save-bearing,
    sampled with --bayes) or None, `sampled(args, result, records)` -> the records --bayes
    samples that law on (by default the records themselves), `plot(args, result,
    records)` and `report(args, result) -> lines` for stderr; `bayes(args, result, records)
    -> exit status`: the isolator's own posterior run after its fit (`None`: the friction
    law's, `_fit_bayes.run_bayes`)."""

    read: Callable
    announce: Callable
    solve: Callable
    friction: Callable
    plot: Callable
    report: Callable
    requires: tuple = ()
    refuses: tuple = ()
    one_record: bool = False
    starts: int | None = DEFAULT_STARTS
    own: dict = dataclasses.field(default_factory=dict)
    posterior: bool = False
    sampled: Callable = lambda args, result, records: records
    bayes: Callable | None = None


@dataclasses.dataclass(frozen=True)
class SimulationRow:
    """How `simulate-test` treats one isolator: `refuses` and `requires` (as `FitRow`'s, the
    refused checked first); `file_of_it`: --isolator-file must hold this isolator; `model`:
    the model the record names."""

    refuses: tuple = ()
    requires: tuple = ()
    file_of_it: bool = False
    model: str = ""


# --- the friction law's fits: flat slider and single pendulum --------------------------------


def _parse_fixed(text):
    """--fixed NAME=VALUE[,...] of the friction law's constants (text, or the repeated flag's
    list) -> {name: SI value} (`parse_name_values`)."""
    from identification.bearing_fit import PARAMETER_NAMES

    return parse_name_values(text, {name: PARAMETER_DIMENSIONS.get(name, "dimensionless")
                                    for name in PARAMETER_NAMES}, "--fixed")


def _own_constants(text, own: dict) -> tuple[dict, object]:
    """(the isolator's constants held by --fixed [SI], the other non-empty items) for `own`
    (name -> `OwnConstant`, each positive); without own constants, {} and the text as given.
    A bad value is refused naming it."""
    if not own:
        return {}, text
    values, others = {}, []
    for item in name_value_items(text):
        name, _, value = item.partition("=")
        name = name.strip()
        if name not in own:
            others.append(item)
            continue
        values[name] = parse_quantity(value, own[name].dimension, where=f"--fixed {name}")
        if not values[name] > 0:
            raise ValueError(f"--fixed {name}: must be {own[name].must_be}, got {value.strip()}.")
    return values, others


def _read_friction(args, own: dict) -> FitInputs:
    """--free, --fixed and the isolator's `own` constants held by --fixed."""
    from identification.bearing_fit import parse_free

    values, others = _own_constants(args.fixed, own)
    free = parse_free(args.free) if args.free is not None else None
    try:
        fixed = _parse_fixed(others)
    except ValueError as error:
        if not own or "unknown parameter" not in str(error):
            raise
        also = ", ".join(f"{name} (e.g. {name}={c.example})" for name, c in own.items())
        raise ValueError(f"{error} With --isolator {args.isolator} also {also}.") from None
    both = [name for name in (free or ()) if name in fixed or name in values]
    if both:
        raise ValueError(f"--free and --fixed both name {', '.join(both)}; a constant is either fitted or "
                         "held: leave it out of one of them.")
    return FitInputs(free, fixed, values)


def _fit_flat(args, inputs, records):
    from identification.bearing_fit import fit_bearing_test

    return fit_bearing_test(records, free=inputs.free, fixed=inputs.fixed, normal_load=args.normal_load,
                            n_starts=args.starts, reduce=not args.full_model)


def _fit_single(args, inputs, records):
    from identification.bearing_fit import fit_pendulum_test

    return fit_pendulum_test(records, free=inputs.free, fixed=inputs.fixed, radius=inputs.own.get("radius"),
                             normal_load=args.normal_load, n_starts=args.starts,
                             reduce=not args.full_model)


def _friction_parts(args, fit, records) -> list:
    """The friction part of each pendulum record at the fitted radius, fx less N u / R
    (`pendulum_friction_record`): what the liner's posterior is sampled on, R held at its
    least-squares value."""
    from identification.bearing_fit import pendulum_friction_record

    return [pendulum_friction_record(r, fit.radius, normal_load=args.normal_load) for r in records]


def _plot_friction(args, fit, records) -> None:
    """Measured and fitted loops of the flat slider's law, the records and load in the title."""
    from ..report import plot_fit

    units = output_units(args.units)
    stamp = f"{', '.join(pathlib.Path(r).name for r in args.records)}" + (
        f", normal load {args.normal_load_text}" if args.normal_load_text else "")
    plot_fit(args.plot, fit, length=units.length, force=units.force, title=stamp)


def _plot_single(args, fit, records) -> None:
    """The friction part of the pendulum's force (measured less N u / R) and its fit."""
    from ..report import plot_fit

    units = output_units(args.units)
    plot_fit(args.plot, fit.friction, length=units.length, force=units.force,
             title=f"friction part of the pendulum's force: measured less N u / R, R = "
                   f"{units.show(fit.radius, 'length')}")


def _report_flat(args, fit) -> list[str]:
    """Warnings and notes, the reduced law, the constants and the status (`fit_status`)."""
    notes = [w for w in fit.warnings if _is_correlation_note(w)]
    lines = [f"teflon-jax fit: {'note' if w in notes else 'warning'}: {w}" for w in fit.warnings]
    if fit.reduced:
        lines.append(f"teflon-jax fit: reduced model: {fit.reduction} Reduced: " + "; ".join(
            f"{k} {v}" for k, v in fit.reduced.items()) + ".")
    summary = ", ".join(_shown(k, fit.parameters[k], fit.std_errors[k], args.units == "us") for k in fit.free)
    lines.append(f"{summary}; nrmse = {fit.nrmse:.4f} [-]; {fit.message}; "
                 f"{fit_status(fit, len(notes), args.records)}")
    return lines


def _report_single(args, fit) -> list[str]:
    """Warnings, R with its error and period, the friction constants and the status."""
    units, us, friction = output_units(args.units), args.units == "us", fit.friction
    lines = [f"teflon-jax fit: warning: {warning}" for warning in friction.warnings]
    shown = ", ".join(_shown(k, friction.parameters[k], friction.std_errors[k], us) for k in friction.free)
    error = "" if fit.radius_fixed else f" +- {units.show(fit.radius_std_error, 'length', 2)}"
    status = "converged" if fit.converged else (
        "NOT CONVERGED (R still moving after "
        f"{fit.iterations} rounds)" if friction.converged else "NOT CONVERGED")
    lines.append(f"R = {units.show(fit.radius, 'length', 6)}{error}{' (held)' if fit.radius_fixed else ''} "
                 f"(T = {fit.isolation_period:.4g} s); {shown}; nrmse = {fit.nrmse:.4f} [-]; {status}")
    return lines


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


def _is_correlation_note(text: str) -> bool:
    """A high correlation between two fitted constants: a note, which leaves a fit clean
    (`BearingFit.clean`), not a warning."""
    return bool(re.match(r"^[a-z_]+, [a-z_]+: correlation -?[0-9.]+; ", text))


def _shown(name, value, error, us):
    """`name = value +- error unit` in the family chosen by --units."""
    from ..report import parameter_unit

    unit, factor = parameter_unit(name, ("in", INCH) if us else ("mm", 1e-3))
    error = float("nan") if error is None else error
    return f"{name} = {value / factor:.5g} +- {error / factor:.2g}{' ' + unit if unit else ''}"


# --- the series pendulums: the constants of a start file --------------------------------------


def _read_series(args, own: dict) -> FitInputs:
    """--free's text and the start isolator of --isolator-file (of this isolator)."""
    return FitInputs(args.free, {}, {}, _load(args.isolator_file, args.isolator, command="fit"))


def _fit_series(args, inputs, records):
    from identification.bearing_fit import fit_series_pendulum_test

    try:
        return fit_series_pendulum_test(records[0], inputs.start, free=inputs.free,
                                        normal_load=args.normal_load, reference_load=args.reference_load,
                                        full_model=args.full_model)
    except ValueError as error:
        raise ValueError(f"--free: {error}" if str(error).startswith("free:") else as_flags(str(error))) from None


def _report_series(args, fit, *, order_note: str | None) -> list[str]:
    """Held constants, the order of surfaces a loop cannot tell (`order_note` when the fit kept
    the start file's), warnings, the constants and the status."""
    units = output_units(args.units)
    lines = [f"teflon-jax fit: held: {reason}" for reason in dict.fromkeys(fit.held.values())]
    if fit.swapped:
        lines.append("teflon-jax fit: bottom and top exchanged: a loop cannot tell the two surfaces in "
                     "series apart; they are reported in the start file's order of f_max")
    elif order_note is not None:
        lines.append(f"teflon-jax fit: note: {order_note}")
    lines += [f"teflon-jax fit: warning: {warning}" for warning in fit.warnings]
    lines.append("; ".join(_shown_series(name, fit, units) for name in fit.free) +
                 f"; nrmse = {fit.nrmse:.4g} [-]; "
                 f"{'converged' if fit.converged else 'NOT CONVERGED: ' + fit.message}")
    return lines


def _shown_series(name, fit, units) -> str:
    value, error = fit.parameters[name], fit.std_errors[name]
    if name.endswith(("radius", "capacity")):
        return f"{name} = {units.show(value, 'length', 6)} +- {units.show(error, 'length', 2)}"
    if name.endswith("rate_a"):
        length, factor = units.length
        return f"{name} = {value * factor:.6g} +- {error * factor:.2g} s/{length}"
    return f"{name} = {value:.6g} +- {error:.2g}"


def _plot_series(args, fit, records) -> None:
    """Measured (grey) and fitted (black, dashed) loops along x (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    record, units = records[0], output_units(args.units)
    fitted = np.asarray(fit.fitted_force)
    fitted = fitted[:, 0] if fitted.ndim == 2 else fitted
    (length, lf), (force, ff) = units.length, units.force
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    ax.plot(np.asarray(record.ux) / lf, np.asarray(record.fx) / ff, color="0.55", lw=1.6, label="measured")
    ax.plot(np.asarray(record.ux) / lf, fitted / ff, "k--", lw=1.0, label="fitted series model")
    ax.set(xlabel=f"displacement [{length}]", ylabel=f"force [{force}]",
           title=f"{fit.bearing.description[:-1]} fit, nrmse {fit.nrmse:.3g}")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.plot, dpi=120)
    plt.close(fig)


# --- the table ---------------------------------------------------------------------------------

SERIES_ONLY = ("{flag}: applies to --isolator " + SERIES_NAMES + " only; add --isolator " + IN_SERIES[0]
               + " (or another of them) or leave {flag} out.")
_NOT_SERIES = (("isolator_file", SERIES_ONLY), ("save_isolator", SERIES_ONLY), ("reference_load", SERIES_ONLY))


def _series_fit(order_note: str | None = None) -> FitRow:
    """The row of a series pendulum's fit: one record, from --isolator-file's constants."""
    refused = (("effects", "the series model has no optional parts"),
               ("fixed", "held constants keep --isolator-file's values: name the fitted ones with --free"),
               ("starts", "the fit starts from --isolator-file's values"),
               ("save_bearing", "a bearing file holds one flat slider: give --save-isolator"))
    return FitRow(
        read=_read_series, solve=_fit_series, friction=lambda fit: None, plot=_plot_series,
        announce=lambda args, inputs, records: f"{inputs.start.description}, Levenberg-Marquardt through "
                                               "the series model (compiling first)...",
        report=functools.partial(_report_series, order_note=order_note),
        requires=(("isolator_file", "{flag}: --isolator {isolator} starts from an isolator file (radius, "
                   "capacity and friction of each surface; docs/formats.md)."),),
        refuses=tuple((name, "{flag}: not with --isolator {isolator} (" + why + "); leave {flag} out.")
                      for name, why in refused),
        one_record=True, starts=None, bayes=_bayes_series)


def _bayes_series(args, fit, records) -> int:
    from ._fit_bayes import run_series_bayes

    return run_series_bayes(args, fit, records)


_RADIUS = OwnConstant("length", "88in", "a positive radius of curvature")

FIT_ROWS: dict[str, FitRow] = per_isolator(
    flat=FitRow(
        read=_read_friction, solve=_fit_flat, friction=lambda fit: fit, plot=_plot_friction,
        report=_report_flat, refuses=_NOT_SERIES, posterior=True,
        announce=lambda args, inputs, records: f"{len(records)} record(s), {args.starts} least-squares "
                                               "starts (compiling first)..."),
    single=FitRow(
        read=_read_friction, solve=_fit_single, friction=lambda fit: fit.friction, plot=_plot_single,
        report=_report_single, own={"radius": _RADIUS}, sampled=_friction_parts,
        refuses=(*_NOT_SERIES, ("effects", "{flag}: not available with --isolator {isolator}; leave {flag} out.")),
        announce=lambda args, inputs, records: f"{len(records)} record(s) of a single friction pendulum, "
                                               f"{'R held' if inputs.own else 'R and the friction alternated'} "
                                               "(compiling first)..."),
    series=lambda name, facts: _series_fit(facts.order_note),
)
"""`fit`'s row of each isolator (`per_isolator`)."""

_SERIES_FILE = ("{flag}: --isolator {isolator} needs the isolator file of its surfaces (radius, capacity "
                "and friction of each; docs/formats.md), e.g. --isolator-file {example}.")

_SERIES_RADIUS = ("radius", "{flag}: does not apply to --isolator {isolator} (its radii are in --isolator-file); "
                  "leave {flag} out.")

TEST_ROWS: dict[str, SimulationRow] = per_isolator(
    flat=SimulationRow(refuses=(("radius", "{flag}: applies to --isolator single-fp only (a flat slider has "
                                "no radius); add --isolator single-fp or leave {flag} out."),)),
    single=SimulationRow(
        refuses=(("isolator_file", "--isolator: the isolator comes from --isolator-file {isolator_file} (a "
                  "triple or double pendulum, as the file says); leave --isolator single-fp out."),),
        requires=(("radius", "{flag}: --isolator single-fp needs the radius of its concave surface, e.g. "
                   "--radius 88in."),)),
    series=lambda name, facts: SimulationRow(
        refuses=(_SERIES_RADIUS,), requires=(("isolator_file", _SERIES_FILE.replace("{example}", facts.file_example)),),
        file_of_it=True, model=facts.model),
)
"""`simulate-test`'s row of each isolator (`per_isolator`); an --isolator-file
given with the flat slider's row simulates the pendulum the file holds."""


def refused(args, rules) -> None:
    """`ValueError` with the message of the first of `rules` (pairs of an attribute of `args`
    and a message) whose flag is given; the message is filled in with `flag` (the flag as
    typed) and `args`' values."""
    _first(args, rules, given=True)


def required(args, rules) -> None:
    """`ValueError` with the message of the first of `rules` whose flag is not given (as
    `refused`)."""
    _first(args, rules, given=False)


def _first(args, rules, *, given: bool) -> None:
    for name, message in rules:
        if (getattr(args, name) is not None) == given:
            raise ValueError(message.format(**{**vars(args), "flag": "--" + name.replace("_", "-")}))
