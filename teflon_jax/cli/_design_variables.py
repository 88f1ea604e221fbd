"""The design variables of `teflon-jax design`: the isolator's (the period T_b of the flat
sliders' springs, or the radius R of a single friction pendulum's concave surface, whose
period is T_b = 2 pi sqrt(R / g), Zayas, Low & Mahin 1990) and the friction's (the contact
pressure, through Table 1's rows, or f_max of Eq. 1 itself). Each pair of bounds is a flag;
a flag of the other isolator or of the other friction variable is refused by name."""

import math

from ..units import INCH, PSI, STANDARD_GRAVITY
from ._common import ISOLATORS, add_quantity
from ._design_triple import ALL_FLAGS

TRIPLE_DESIGN_VARIABLES = tuple(ALL_FLAGS)
"""The design variables of the triple and double pendulums (their names, as the JSON writes them)."""

DEFAULT_RANGES = {
    "period_range": (("1s", "4s"), (1.0, 4.0)),
    "radius_range": (("40in", "160in"), (40 * INCH, 160 * INCH)),
    "pressure_range": (("1000psi", "2000psi"), (1000 * PSI, 2000 * PSI)),
}
"""Bounds of each range flag when it is not given: (text, SI values)."""

FLAG_OF = {"isolation_period": "--period-range", "radius": "--radius-range", "capacity": "--capacity-range",
           "pressure": "--pressure-range", "f_max": "--f-max-range"}
"""The range flag of each design variable."""


def add_design_variable_flags(parser) -> None:
    """`--isolator`, `--period-range` or `--radius-range`, `--pressure-range` or `--f-max-range`."""
    parser.add_argument("--isolator", default="flat", choices=ISOLATORS,
                        help="flat sliders on springs of period Tb (designed over --period-range), "
                        "a single friction pendulum, restoring force W u / R (designed over "
                        "--radius-range), the triple friction pendulum of --isolator-file "
                        "(designed over --outer-radius-scale-range, --inner-f-max-range, "
                        "--outer-f-max-range and --capacity-scale-range) or the double one "
                        "(over --radius-scale-range, --surface-f-max-range and "
                        "--capacity-scale-range) (default flat)")
    add_quantity(parser, "--period-range", "time", None, "flat sliders: bounds of the isolation "
                 "period Tb (default 1s 4s)", minimum=0.0, nargs=2)
    add_quantity(parser, "--radius-range", "length", None, "--isolator single-fp: bounds of the "
                 "radius R of the concave surface, period 2 pi sqrt(R / g) (default 40in 160in: "
                 "2.0-4.0 s)", minimum=0.0, nargs=2)
    add_quantity(parser, "--capacity-range", "length", None, "--isolator single-fp: bounds of the "
                 "displacement capacity d of the surface, beyond which a stiffening restrainer adds "
                 "k_r (|u| - d) (default: no restrainer, d not designed)", minimum=0.0, nargs=2)
    add_quantity(parser, "--restrainer-ratio", "dimensionless", None, "with --capacity-range: the "
                 "restrainer's stiffness k_r as a multiple of the surface's W / R at the low end of "
                 "--radius-range (k_r is held as R is designed) (default 10)", minimum=0.0)
    add_quantity(parser, "--pressure-range", "pressure", None, "bounds of the bearing pressure "
                 "(inside Table 1's rows; one interval of the table keeps the friction constants "
                 "smooth in it) (default 1000psi 2000psi)", minimum=0.0, nargs=2)
    add_quantity(parser, "--f-max-range", "dimensionless", None, "design f_max of Eq. 1 over these "
                 "bounds instead of the pressure: delta_f, a and b stay Table 1's at 1000 psi (or "
                 "the --bearing file's)", minimum=0.0, nargs=2, maximum=1.0)
    add_quantity(parser, "--pressure", "pressure", None, "design the isolator alone, on bearings "
                 "at this pressure (Table 1's friction there), instead of over --pressure-range",
                 minimum=0.0)


def resolve_design_variables(args) -> dict:
    """{design variable: (low, high)} [SI] of the flags, with the defaults of the flags not
    given in place (no friction variable with `--pressure`); `ValueError` naming a flag that
    does not apply (a period range on the pendulum, a radius range on flat sliders, two
    friction flags at once)."""
    pendulum = args.isolator == "single-fp"
    wrong, right = ("--period-range", "--radius-range") if pendulum else ("--radius-range", "--period-range")
    if getattr(args, wrong.lstrip("-").replace("-", "_") + "_text") is not None:
        what = ("the single-fp isolator's period is 2 pi sqrt(R / g) of its radius" if pendulum
                else "flat sliders have no radius")
        raise ValueError(f"{wrong}: does not apply to --isolator {args.isolator} ({what}); give {right} "
                         f"instead{'' if pendulum else ' or add --isolator single-fp'}.")
    _check_restrainer_flags(args, pendulum)
    if args.f_max_range_text is not None and args.pressure_range_text is not None:
        raise ValueError("--f-max-range: designs f_max instead of the pressure; give --f-max-range "
                         "or --pressure-range, not both.")
    for flag in ("--pressure-range", "--f-max-range"):
        if args.pressure_text is not None and getattr(args, flag[2:].replace("-", "_") + "_text") is not None:
            raise ValueError(f"--pressure: fixes the friction, which {flag} designs; give one of them.")
    for name in DEFAULT_RANGES:
        if getattr(args, name + "_text") is None:
            text, values = DEFAULT_RANGES[name]
            setattr(args, name, values)
            setattr(args, name + "_text", text)
    variables = {"radius": args.radius_range} if pendulum else {"isolation_period": args.period_range}
    if args.capacity_range_text is not None:
        variables["capacity"] = args.capacity_range
    if args.f_max_range_text is not None:
        variables["f_max"] = args.f_max_range
    elif args.pressure_text is None:
        variables["pressure"] = args.pressure_range
    if args.isolation_damping_text is None:  # a pendulum's damping is its friction
        args.isolation_damping = 0.0 if pendulum else 0.05
        args.isolation_damping_text = "0%" if pendulum else "5%"
    args.design_flags = tuple(FLAG_OF[name] for name in variables)
    return {name: tuple(float(v) for v in bounds) for name, bounds in variables.items()}


def _check_restrainer_flags(args, pendulum: bool) -> None:
    """`ValueError` naming `--capacity-range` on flat sliders, or `--restrainer-ratio` without
    it; the default ratio (10) set."""
    if args.capacity_range_text is not None and not pendulum:
        raise ValueError(f"--capacity-range: does not apply to --isolator {args.isolator} (flat sliders "
                         "have no surface to leave); add --isolator single-fp.")
    if args.restrainer_ratio_text is not None and args.capacity_range_text is None:
        raise ValueError("--restrainer-ratio: sets the restrainer beyond the capacity, which only "
                         "--capacity-range designs; add --capacity-range LOW HIGH or leave it out.")
    if args.restrainer_ratio_text is None:
        args.restrainer_ratio, args.restrainer_ratio_text = 10.0, "10"


def restrained_options(args, variables: dict, structure, options: dict) -> dict:
    """`isolated_structure`'s keywords `options` with the pendulum's surface given a
    restrainer (`concave_surface`): capacity at the low end of `--capacity-range`, stiffness
    k_r = ratio W / R_low, W the weight the bearings carry in `structure` [N]."""
    import numpy as np

    from ..bearing import concave_surface

    weight = float(structure(np.zeros(2)).bearing_load)
    radius = variables["radius"][0]
    surface = concave_surface(radius, displacement_capacity=variables["capacity"][0],
                              restrainer_stiffness=args.restrainer_ratio * weight / radius)
    return {**options, "radius": None, "surface": surface}


def check_f_max_range(args, structure) -> None:
    """f_min = f_max - delta_f must stay >= 0 at the low end of `--f-max-range` (delta_f of
    Table 1 at the structure's pressure, or of the bearing file)."""
    if args.f_max_range_text is None:
        return
    bearing, _, _ = structure.isolation({})
    delta_f = float(bearing.friction.delta_f)
    if not args.f_max_range[0] >= delta_f:
        raise ValueError(f"--f-max-range: the low end {args.f_max_range_text[0]} lies below "
                         f"delta_f = {delta_f:.4g} of the bearing (f_min = f_max - delta_f would be "
                         f"negative); raise it to at least {delta_f:.4g}.")


def structure_options(args, variables: dict) -> dict:
    """Keywords of `isolated_structure` that place the structure at the low ends of the
    design ranges (the design overrides them)."""
    pressure = args.pressure if args.pressure_text is not None else (
        variables.get("pressure", DEFAULT_RANGES["pressure_range"][1])[0])
    options = {"isolation_damping": args.isolation_damping, "pressure": pressure}
    if "radius" in variables:
        options.update(isolator="single-fp", radius=variables["radius"][0], isolation_period=None)
    else:
        options["isolation_period"] = variables["isolation_period"][0]
    return options


def pendulum_period(radius: float) -> float:
    """T_b = 2 pi sqrt(R / g) [s] of a pendulum of radius R [m]."""
    return 2 * math.pi * math.sqrt(radius / STANDARD_GRAVITY)


def design_fields(values: dict, units) -> dict:
    """JSON entries of a design point (name -> SI value): R in `units` and its period, or
    T_b; the pressure in `units` or f_max."""
    fields = {}
    if "radius" in values:
        fields[f"radius_{units.length[0]}"] = values["radius"] / units.length[1]
        fields["isolation_period_s"] = pendulum_period(values["radius"])
        if "capacity" in values:
            fields[f"capacity_{units.length[0]}"] = values["capacity"] / units.length[1]
    elif "isolation_period" in values:
        fields["isolation_period_s"] = values["isolation_period"]
    fields.update({n: values[n] for n in TRIPLE_DESIGN_VARIABLES if n in values})
    if "pressure" in values:
        fields[f"pressure_{units.pressure[0]}"] = values["pressure"] / units.pressure[1]
    if "f_max" in values:
        fields["f_max"] = values["f_max"]
    return fields


def design_text(values: dict, units) -> str:
    """'Tb = 3.267 s, pressure = 2000 psi' or 'R = 61.2 in (Tb = 2.5 s), f_max = 0.08'."""
    if "radius" in values:
        parts = [f"R = {units.show(values['radius'], 'length')} (Tb = {pendulum_period(values['radius']):.4g} s)"]
        if "capacity" in values:
            parts.append(f"d = {units.show(values['capacity'], 'length')}")
    elif "isolation_period" in values:
        parts = [f"Tb = {values['isolation_period']:.4g} s"]
    else:
        parts = [f"{n} = {values[n]:.5g}" for n in TRIPLE_DESIGN_VARIABLES if n in values]
    if "pressure" in values:
        parts.append(f"pressure = {units.show(values['pressure'], 'pressure')}")
    if "f_max" in values:
        parts.append(f"f_max = {values['f_max']:.4g}")
    return ", ".join(parts)


def plot_units(units) -> dict:
    """`plot_design`'s units of the design variables and of lengths."""
    return {"isolation_period": (1.0, "s"), "pressure": units.pressure[::-1], "radius": units.length[::-1],
            "capacity": units.length[::-1],
            "f_max": (1.0, "-"), "length": units.length[::-1],
            **{n: (1.0, "-") for n in TRIPLE_DESIGN_VARIABLES}}


def pendulum_start(sweep, bounds, structure, records, record_step: float, disp_limit: float,
                   penalty: float, statistic: str = "mean") -> dict:
    """BFGS's start on a pendulum: the grid's best point for the limit on the smoothed mean
    lowered by the gap between the true and the smoothed mean peak at the grid's best point
    for `disp_limit` (the limit BFGS then starts on, `optimise_design`). The unlowered limit
    binds nowhere on a grid whose smoothed peaks lie below it, and its best point is then the
    largest radius, far from the design that meets the limit on the true peaks."""
    from ..studies import (
        constrained_response,
        expected_response,
        sweep_objective,
        sweep_start,
    )

    start = sweep_start(sweep, bounds)
    response = constrained_response(expected_response(structure, start, records, record_step), statistic)
    lowered = disp_limit - (float(response["peak_disp"]) - float(response["disp"]))
    if not lowered > 0:
        return start
    return sweep_start({**sweep, "objective": sweep_objective(sweep, lowered, penalty)}, bounds)
