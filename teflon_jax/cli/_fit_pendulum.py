"""`teflon-jax fit --isolator single-fp`: the radius R of a single friction pendulum and its
liner's friction constants from test records (`identification.bearing_fit.fit_pendulum_test`).
`--fixed radius=88in` holds R (the friction alone is fitted)."""

import sys

from ..units import parse_quantity
from ._bearing_flags import check_output_file
from ._common import _write_json, output_units, read_bearing_record, read_quantities


def _radius_of(args) -> tuple[float | None, list]:
    """(R [m] of `--fixed radius=...` or None, the other --fixed items); a bad radius is
    refused naming it."""
    text = args.fixed
    items = [] if not text else [i for part in ([text] if isinstance(text, str) else text)
                                 for i in part.split(",") if i.strip()]
    radius, others = None, []
    for item in items:
        name, _, value = item.partition("=")
        if name.strip() != "radius":
            others.append(item)
            continue
        radius = parse_quantity(value, "length", where="--fixed radius")
        if not radius > 0:
            raise ValueError(f"--fixed radius: must be a positive radius of curvature, got {value.strip()}.")
    return radius, others


def run_fit_pendulum(args, *, check_counts, parse_fixed, save_fitted, shown_as) -> int:
    """`fit --isolator single-fp`: exit 0 converged, 1 not converged, 2 bad input. The flat
    fit's helpers come as arguments (`teflon_jax.cli._fit`: its --starts check, its --fixed
    reader, its --save-bearing writer and its parameter text)."""
    from identification.bearing_fit import fit_pendulum_test, parse_free

    try:
        read_quantities(args, "fit")
        for flag, value in (("--bayes", args.bayes), ("--effects", args.effects)):
            if value is not None:
                raise ValueError(f"{flag}: not available with --isolator single-fp; leave {flag} out.")
        check_output_file(args.save_bearing, "--save-bearing")
        check_counts(args)
        radius, others = _radius_of(args)
        free = parse_free(args.free) if args.free is not None else None
        try:
            fixed = parse_fixed(others)
        except ValueError as error:
            raise ValueError(f"{error} With --isolator single-fp also radius (e.g. radius=88in)."
                             if "unknown parameter" in str(error) else str(error)) from None
        records = [read_bearing_record(p) for p in args.records]
        print(f"teflon-jax fit: {len(records)} record(s) of a single friction pendulum, "
              f"{'R held' if radius else 'R and the friction alternated'} (compiling first)...",
              file=sys.stderr)
        fit = fit_pendulum_test(records, free=free, fixed=fixed, radius=radius,
                                normal_load=args.normal_load, n_starts=args.starts,
                                reduce=not args.full_model)
    except ValueError as error:
        print(f"teflon-jax fit: error: {error}", file=sys.stderr)
        return 2
    _write_json(args.json, fit.to_json_dict())
    save_fitted(args, fit.friction, records)
    if args.plot:
        from ..report import plot_fit

        units = output_units(args.units)
        plot_fit(args.plot, fit.friction, length=units.length, force=units.force,
                 title=f"friction part of the pendulum's force: measured less N u / R, R = "
                       f"{units.show(fit.radius, 'length')}")
    units, us = output_units(args.units), args.units == "us"

    for warning in fit.friction.warnings:
        print(f"teflon-jax fit: warning: {warning}", file=sys.stderr)
    shown = ", ".join(shown_as(k, fit.friction.parameters[k], fit.friction.std_errors[k], us)
                      for k in fit.friction.free)
    error = "" if fit.radius_fixed else f" +- {units.show(fit.radius_std_error, 'length', 2)}"
    status = "converged" if fit.converged else (
        "NOT CONVERGED (R still moving after "
        f"{fit.iterations} rounds)" if fit.friction.converged else "NOT CONVERGED")
    print(f"R = {units.show(fit.radius, 'length', 6)}{error}{' (held)' if fit.radius_fixed else ''} "
          f"(T = {fit.isolation_period:.4g} s); {shown}; nrmse = {fit.nrmse:.4f} [-]; {status}",
          file=sys.stderr)
    return 0 if fit.converged else 1
