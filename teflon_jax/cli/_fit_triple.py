"""`teflon-jax fit --isolator triple-fp|double-fp --isolator-file START.json RECORD.csv`: the
radii and surfaces' friction of a triple or double friction pendulum from one test record
(`identification.bearing_fit.fit_series_pendulum_test`), written as a JSON report and, with
`--save-isolator`, as an isolator file of the fitted constants."""

import sys

from ._bearing_flags import check_output_file
from ._common import _write_json, output_units, read_bearing_record, read_quantities
from ._triple import _load


def _check_flags(args) -> None:
    """`ValueError` naming each flag `fit --isolator triple-fp|double-fp` cannot take or misses."""
    if args.isolator_file is None:
        raise ValueError(f"--isolator-file: --isolator {args.isolator} starts from an isolator file "
                         "(radius, capacity and friction of each surface; docs/formats.md).")
    if not args.isolator_file.is_file():
        raise ValueError(f"--isolator-file: {args.isolator_file} does not exist.")
    refused = (("--bayes", args.bayes, f"no posterior sampling of the {args.isolator} pendulum"),
               ("--effects", args.effects, "the series model has no optional parts"),
               ("--fixed", args.fixed, "held constants keep --isolator-file's values: name the "
                "fitted ones with --free"),
               ("--starts", args.starts, "the fit starts from --isolator-file's values"),
               ("--save-bearing", args.save_bearing, "a bearing file holds one flat slider: "
                "give --save-isolator"))
    for flag, value, why in refused:
        if value is not None:
            raise ValueError(f"{flag}: not with --isolator {args.isolator} ({why}); leave {flag} out.")
    if len(args.records) != 1:
        raise ValueError(f"RECORD: --isolator {args.isolator} fits one record, got {len(args.records)}.")
    check_output_file(args.save_isolator, "--save-isolator")
    check_output_file(args.plot, "--plot")


def run_fit_triple(args) -> int:
    """`fit --isolator triple-fp|double-fp`: exit 0 converged, 1 not converged, 2 bad input."""
    from identification.bearing_fit import fit_series_pendulum_test

    from ..formats import write_isolator

    try:
        read_quantities(args, "fit")
        _check_flags(args)
        start = _load(args.isolator_file, args.isolator, command="fit")
        record = read_bearing_record(args.records[0])
        print(f"teflon-jax fit: {start.description}, Levenberg-Marquardt through the series "
              "model (compiling first)...", file=sys.stderr)
        try:
            fit = fit_series_pendulum_test(record, start, free=args.free, normal_load=args.normal_load,
                                           full_model=args.full_model)
        except ValueError as error:
            raise ValueError(f"--free: {error}" if str(error).startswith("free:") else str(error)) from None
    except ValueError as error:
        print(f"teflon-jax fit: error: {error}", file=sys.stderr)
        return 2
    _write_json(args.json, fit.to_json_dict())
    if args.save_isolator is not None:
        write_isolator(args.save_isolator, fit.bearing)
    units = output_units(args.units)
    if args.plot:
        _plot(args.plot, record, fit, units)
    for reason in dict.fromkeys(fit.held.values()):
        print(f"teflon-jax fit: held: {reason}", file=sys.stderr)
    if fit.swapped:
        print("teflon-jax fit: bottom and top exchanged: a loop cannot tell the two surfaces in series "
              "apart; they are reported in the start file's order of f_max", file=sys.stderr)
    elif args.isolator == "double-fp":
        print("teflon-jax fit: note: a loop cannot tell the bottom surface from the top one; they "
              "are reported in the start file's order of f_max", file=sys.stderr)
    for warning in fit.warnings:
        print(f"teflon-jax fit: warning: {warning}", file=sys.stderr)
    print("; ".join(_shown(name, fit, units) for name in fit.free) +
          f"; nrmse = {fit.nrmse:.4g} [-]; {'converged' if fit.converged else 'NOT CONVERGED: ' + fit.message}",
          file=sys.stderr)
    return 0 if fit.converged else 1


def _shown(name, fit, units) -> str:
    value, error = fit.parameters[name], fit.std_errors[name]
    if name.endswith(("radius", "capacity")):
        return f"{name} = {units.show(value, 'length', 6)} +- {units.show(error, 'length', 2)}"
    if name.endswith("rate_a"):
        length, factor = units.length
        return f"{name} = {value * factor:.6g} +- {error * factor:.2g} s/{length}"
    return f"{name} = {value:.6g} +- {error:.2g}"


def _plot(path, record, fit, units) -> None:
    """Measured (grey) and fitted (black, dashed) loops along x (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

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
    fig.savefig(path, dpi=120)
    plt.close(fig)
