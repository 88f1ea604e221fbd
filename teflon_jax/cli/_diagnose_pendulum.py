"""`teflon-jax diagnose --isolator single-fp [--radius R]`: discovery on a single friction
pendulum's record looks for effects of the liner's friction only. The surface's restoring
force N u / R (Zayas, Low & Mahin 1990) belongs to the baseline: it is taken off the force
before the search, with R given by `--radius`, or fitted beside the baseline's friction
(Eq. 1 with Bouc-Wen, `identification.bearing_fit.fit_pendulum_test`). A fitted R is then
refitted beside the effects the search found (`refit_pendulum_radius`) and the search run
again, until R settles: the fixed point of the alternation is a stationary point of the squared error in R and
the final model's constants together, as in `fit_pendulum_test`."""

from ._common import ISOLATORS, add_quantity

RADIUS_ROUNDS = 3
"""Most searches run with a refitted radius after the first."""

RADIUS_RTOL = 1e-4
"""Relative change of R below which it has settled."""


def add_pendulum_diagnose_flags(parser) -> None:
    """`--isolator flat|single-fp|triple-fp|double-fp` and `--radius R` of `diagnose`."""
    parser.add_argument("--isolator", default="flat", choices=ISOLATORS,
                        help="single-fp: the record is of a single friction pendulum; its "
                        "restoring force N u / R joins the baseline and the search looks at the "
                        "friction; triple-fp, double-fp: the baseline is the series fit of "
                        "--isolator-file and the candidates its surfaces' effects (default flat)")
    add_quantity(parser, "--radius", "length", None, "with --isolator single-fp: the radius R of "
                 "the concave surface, when known (default: fitted with the baseline's friction)",
                 minimum=0.0)


def friction_part(args, record, say):
    """(`record` less N u / R, R [m]) for `--isolator single-fp`; (`record`, None) on a flat
    slider. `ValueError` naming `--radius` when it does not apply or is bad."""
    from identification.bearing_fit import fit_pendulum_test, pendulum_friction_record

    from ..units import INCH

    if args.isolator == "flat":
        if args.radius is not None:
            raise ValueError("--radius: applies to --isolator single-fp only (a flat slider has no "
                             "radius); add --isolator single-fp or leave --radius out.")
        return record, None
    radius = args.radius
    if radius is None:
        fit = fit_pendulum_test(record, n_starts=4)
        if not fit.converged:
            raise ValueError(f"{args.record}: the radius could not be fitted with the baseline's "
                             "friction (the fit did not converge); give it with --radius.")
        radius = fit.radius
        say(f"single friction pendulum: R = {radius / INCH:.5g} in +- {fit.radius_std_error / INCH:.2g} in, "
            "fitted with Eq. 1 friction and held; the search looks at the force less N u / R.")
    else:
        say(f"single friction pendulum: R = {args.radius_text} (--radius); the search looks at the "
            "force less N u / R.")
    return pendulum_friction_record(record, radius), radius


def search_pendulum(args, record, search, say):
    """`search(friction record)` on `record` less N u / R (`friction_part`); a fitted R refitted
    beside what each search found and the search rerun, at most `RADIUS_ROUNDS` times.

    **Returns:** (the last search's result, R [m] or None on a flat slider, the JSON entries of
    the radius: the baseline's R, the reruns and whether R settled within `RADIUS_RTOL`)."""
    from identification.bearing_fit import pendulum_friction_record, refit_pendulum_radius

    from ..units import INCH

    friction, radius = friction_part(args, record, say)
    result = search(friction)
    if radius is None or args.radius is not None:
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
