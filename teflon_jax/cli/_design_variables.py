"""The design variables of `teflon-jax design`, one flow for every isolator: the variables of
`--isolator` are those of its design space (`teflon_jax.bearing.design_space`), each designed
over the bounds of its range flag (`VARIABLE_FLAGS`); a flag of another isolator's variables
or options is refused by name. The isolators: flat sliders (the period T_b of their springs),
a single friction pendulum (the radius R of its concave surface, period T_b = 2 pi sqrt(R / g),
Zayas, Low & Mahin 1990, and its displacement capacity), the friction of either (the contact
pressure, through Table 1's rows, or f_max of Eq. 1 itself), and the triple and double
friction pendulums of an isolator file (scales of their radii and capacities, f_max of their
surfaces; `teflon_jax.bearing.designed_isolator`)."""

import math
from typing import NamedTuple

from ..units import INCH, PSI, STANDARD_GRAVITY
from ._common import add_quantity
from ._isolator_flags import SERIES_NAMES, add_isolator_flags, per_isolator


class VariableFlag(NamedTuple):
    """The range flag of one design variable: `flag`, its `dimension` (`add_quantity`'s),
    `help` (naming the isolators whose design space has the variable), `default` bounds
    ((text, SI values), designed without the flag) or None, `maximum` of each bound, the
    printed `label` and significant `digits` of a value."""

    flag: str
    dimension: str
    help: str
    default: tuple | None = None
    maximum: float | None = None
    label: str = ""
    digits: int = 4


_TRIPLE, _SERIES = "--isolator triple-fp: bounds of the", f"--isolator {SERIES_NAMES}: bounds of the"
VARIABLE_FLAGS = {
    "radius": VariableFlag(
        "--radius-range", "length", "--isolator single-fp: bounds of the radius R of the concave "
        "surface, period 2 pi sqrt(R / g)", (("40in", "160in"), (40 * INCH, 160 * INCH)), label="R"),
    "capacity": VariableFlag(
        "--capacity-range", "length", "--isolator single-fp: bounds of the displacement capacity d "
        "of the surface, beyond which a stiffening restrainer adds k_r (|u| - d) (default: no "
        "restrainer, d not designed)", label="d"),
    "isolation_period": VariableFlag(
        "--period-range", "time", "--isolator flat: bounds of the isolation period Tb of the "
        "sliders' springs", (("1s", "4s"), (1.0, 4.0)), label="Tb"),
    "outer_radius_scale": VariableFlag(
        "--outer-radius-scale-range", "dimensionless", f"{_TRIPLE} factor on the outer surfaces' "
        "effective radii b and c (regimes II-IV soften as it grows)", digits=5),
    "inner_f_max": VariableFlag(
        "--inner-f-max-range", "dimensionless", f"{_TRIPLE} f_max of the inner surfaces (their "
        "Eq. 1 scaled to it; at most the bottom's)", digits=5),
    "outer_f_max": VariableFlag(
        "--outer-f-max-range", "dimensionless", f"{_TRIPLE} f_max of the bottom surface, the top's "
        "Eq. 1 scaled by the same factor", digits=5),
    "capacity_scale": VariableFlag(
        "--capacity-scale-range", "dimensionless", f"{_SERIES} factor on the effective displacement "
        "capacities (all of the isolator's)", digits=5),
    "radius_scale": VariableFlag(
        "--radius-scale-range", "dimensionless", "--isolator double-fp: bounds of the factor on both "
        "effective radii R_1 and R_2 (every slope of the loop falls as it grows)", digits=5),
    "surface_f_max": VariableFlag(
        "--surface-f-max-range", "dimensionless", "--isolator double-fp: bounds of the f_max of the "
        "bottom surface, the top's Eq. 1 scaled by the same factor (which surface slides first "
        "kept)", digits=5),
    "pressure": VariableFlag(
        "--pressure-range", "pressure", "--isolator flat or single-fp: bounds of the bearing pressure "
        "(inside Table 1's rows; one interval of the table keeps the friction constants smooth in "
        "it)", (("1000psi", "2000psi"), (1000 * PSI, 2000 * PSI)), label="pressure"),
    "f_max": VariableFlag(
        "--f-max-range", "dimensionless", "--isolator flat or single-fp: design f_max of Eq. 1 over "
        "these bounds instead of the pressure: delta_f, a and b stay Table 1's at 1000 psi (or the "
        "--bearing file's)", maximum=1.0, label="f_max"),
}
"""The range flag of each design variable (in the order the JSON and the summary show them)."""


class IsolatorDesign(NamedTuple):
    """What `teflon-jax design` does with one `--isolator` beyond its design space: `words`
    of the plot ("{file}": --isolator-file), its `options` (flags besides the range flags),
    its viscous `damping` (SI, text) when --isolation-damping is not given, `why` another
    isolator's flag does not apply, and whether the 95th percentile's derivative is checked at
    the optimum (`percentile_check`). BFGS starts from the grid's best point for the lowered
    limit on every isolator (`lowered_start`)."""

    words: str
    options: tuple[str, ...]
    damping: tuple[float, str]
    why: str
    percentile_check: bool = False

    @property
    def uses_file(self) -> bool:
        """Whether the isolator is the pendulum of an isolator file (`--isolator-file`)."""
        return "--isolator-file" in self.options


_SLIDER_OPTIONS = ("--pressure", "--isolation-damping", "--bearing")
_SERIES_WHY = "its friction, period and damping are its surfaces'"
ISOLATOR_DESIGNS = per_isolator(
    flat=IsolatorDesign("flat sliders", _SLIDER_OPTIONS, (0.05, "5%"), "flat sliders have no concave surface"),
    single=IsolatorDesign("a single friction pendulum", (*_SLIDER_OPTIONS, "--restrainer-ratio"),
                          (0.0, "0%"), "its period is 2 pi sqrt(R / g) of its radius"),
    series=lambda name, facts: IsolatorDesign(f"{facts.description} of {{file}}", ("--isolator-file",),
                                              (0.0, "0 (friction only)"), _SERIES_WHY, percentile_check=True),
)
"""The command's choices for each `--isolator` (`IsolatorDesign`)."""


def add_design_variable_flags(parser) -> None:
    """`--isolator`, `--isolator-file`, the range flag of each design variable
    (`VARIABLE_FLAGS`), `--restrainer-ratio` and `--pressure`."""
    add_isolator_flags(parser, choices=tuple(ISOLATOR_DESIGNS), radius=None,
                       isolator="flat sliders on springs of period Tb, a single friction pendulum "
                       "(restoring force W u / R), or the triple or double friction pendulum of "
                       "--isolator-file; each designed over the range flags that name it",
                       file="the isolator file whose bearing is designed (each variable a change of it)")
    for spec in VARIABLE_FLAGS.values():
        add_quantity(parser, spec.flag, spec.dimension, None, spec.help + (
            f" (default {' '.join(spec.default[0])})" if spec.default else ""), minimum=0.0, nargs=2,
            maximum=spec.maximum)
    add_quantity(parser, "--restrainer-ratio", "dimensionless", None, "with --capacity-range: the "
                 "restrainer's stiffness k_r as a multiple of the surface's W / R at the low end of "
                 "--radius-range (k_r is held as R is designed) (default 10)", minimum=0.0)
    add_quantity(parser, "--pressure", "pressure", None, "design the isolator alone, on bearings "
                 "at this pressure (Table 1's friction there), instead of over --pressure-range",
                 minimum=0.0)


def _given(args, flag: str) -> bool:
    dest = flag[2:].replace("-", "_")
    return getattr(args, dest + "_text") is not None if hasattr(args, dest + "_text") else (
        getattr(args, dest, None) is not None)


def _own_flags(isolator: str) -> tuple[str, ...]:
    """The range flags of `isolator`'s design space, in its order."""
    from ..bearing import design_space

    return tuple(VARIABLE_FLAGS[n].flag for n in design_space(isolator).variables if n in VARIABLE_FLAGS)


def _refuse_other_flags(args) -> None:
    """`ValueError` naming the first flag given that `--isolator` does not take (a range flag
    of a variable outside its design space, or an option of another isolator)."""
    isolator, design = args.isolator, ISOLATOR_DESIGNS[args.isolator]
    ranges = _own_flags(isolator)
    options = dict.fromkeys(o for d in ISOLATOR_DESIGNS.values() for o in d.options)
    for flag in ("--isolator-file", *(s.flag for s in VARIABLE_FLAGS.values()), *options):
        if not _given(args, flag) or flag in ranges + design.options:
            continue
        owners = [k for k, d in ISOLATOR_DESIGNS.items() if flag in _own_flags(k) + d.options]
        if not design.uses_file and all(ISOLATOR_DESIGNS[k].uses_file for k in owners):
            raise ValueError(f"{flag}: applies to --isolator {' or '.join(owners)} only, not {isolator}; "
                             f"add --isolator {owners[0]} or leave {flag} out.")
        raise ValueError(f"{flag}: does not apply to --isolator {isolator} ({design.why}); design it over "
                         f"{', '.join(ranges)}, or add --isolator {' or '.join(owners)}.")


def resolve_design_variables(args) -> dict:
    """{design variable: (low, high)} [SI] of the flags, in the order of `--isolator`'s design
    space, with the default bounds of the variables not given in place (no friction variable
    with `--pressure` or `--f-max-range`); `ValueError` naming a flag that does not apply, two
    friction flags at once, or a design without variables. Sets `args.design_flags` and the
    isolator's damping when `--isolation-damping` is not given."""
    from ..bearing import design_space

    _refuse_other_flags(args)
    design = ISOLATOR_DESIGNS[args.isolator]
    _check_restrainer_flags(args, "--restrainer-ratio" in design.options)
    if args.f_max_range_text is not None and args.pressure_range_text is not None:
        raise ValueError("--f-max-range: designs f_max instead of the pressure; give --f-max-range "
                         "or --pressure-range, not both.")
    for flag in ("--pressure-range", "--f-max-range"):
        if args.pressure_text is not None and _given(args, flag):
            raise ValueError(f"--pressure: fixes the friction, which {flag} designs; give one of them.")
    if design.uses_file and args.isolator_file is None:
        raise ValueError(f"--isolator-file: --isolator {args.isolator} designs the bearing of an isolator "
                         "file (docs/formats.md#isolator-file); give one.")
    friction_fixed = args.pressure_text is not None or args.f_max_range_text is not None
    variables = {}
    for name in design_space(args.isolator).variables:
        spec = VARIABLE_FLAGS.get(name)
        if spec is None:
            continue
        dest = spec.flag[2:].replace("-", "_")
        if getattr(args, dest + "_text") is None:
            if spec.default is None or (name == "pressure" and friction_fixed):
                continue
            setattr(args, dest + "_text", spec.default[0])
            setattr(args, dest, spec.default[1])
        variables[name] = tuple(float(v) for v in getattr(args, dest))
    if not variables:
        raise ValueError(f"--isolator {args.isolator}: give at least one of "
                         f"{', '.join(_own_flags(args.isolator))} (the variables to design, with their bounds).")
    if args.isolation_damping_text is None:  # a pendulum's damping is its friction
        args.isolation_damping, args.isolation_damping_text = design.damping
    args.design_flags = tuple(VARIABLE_FLAGS[name].flag for name in variables)
    return variables


def _check_restrainer_flags(args, takes_it: bool) -> None:
    """`ValueError` naming `--restrainer-ratio` without `--capacity-range`; the default ratio
    (10) set on an isolator that `takes_it`."""
    if args.restrainer_ratio_text is not None and args.capacity_range_text is None:
        raise ValueError("--restrainer-ratio: sets the restrainer beyond the capacity, which only "
                         "--capacity-range designs; add --capacity-range LOW HIGH or leave it out.")
    if args.restrainer_ratio_text is None and takes_it:
        args.restrainer_ratio, args.restrainer_ratio_text = 10.0, "10"


def flag_error(error: ValueError) -> ValueError:
    """`error` of a design space's box check ("name: ...") with the variable's range flag in
    place of its name."""
    name, _, rest = str(error).partition(":")
    spec = VARIABLE_FLAGS.get(name)
    return ValueError(f"{spec.flag}:{rest}") if spec is not None else error


def restrained_options(args, variables: dict, structure, options: dict) -> dict:
    """`isolated_structure`'s keywords `options` with the pendulum's surface given a
    restrainer (`concave_surface`): capacity at the low end of `--capacity-range`, stiffness
    k_r = ratio W / R_low, W the weight the bearings carry in `structure` [N]."""
    import numpy as np

    from ..bearing import concave_surface, one_surface

    weight = float(structure(np.zeros(2)).bearing_load)
    radius = variables["radius"][0]
    surface = concave_surface(radius, displacement_capacity=variables["capacity"][0],
                              restrainer_stiffness=args.restrainer_ratio * weight / radius)
    bearing, _ = one_surface(options["isolator"])
    return {**options, "isolator": one_surface_isolator(bearing, surface)}


def structure_options(args, variables: dict, bearing=None) -> dict:
    """Keywords of `isolated_structure` that place the structure at the low ends of the
    design ranges (the design overrides them): its isolator value flat sliders of `bearing`
    (`None`: Table 1's) or, with a radius range, the single pendulum of that bearing on
    `concave_surface(R_low)`."""
    pressure = args.pressure if args.pressure_text is not None else (
        variables.get("pressure", VARIABLE_FLAGS["pressure"].default[1])[0])
    options = {"isolation_damping": args.isolation_damping, "pressure": pressure}
    if "radius" in variables:
        from ..bearing import concave_surface

        options.update(isolator=one_surface_isolator(bearing, concave_surface(variables["radius"][0])),
                       isolation_period=None)
    else:
        options.update(isolator=bearing, isolation_period=variables["isolation_period"][0])
    return options


def one_surface_isolator(bearing, surface):
    """The isolator value (`teflon_jax.bearing.isolator_kind`) of `bearing` (`None`: Table 1's)
    on `surface` (`None`: flat sliders): `bearing`, `surface` or the pair."""
    if surface is None:
        return bearing
    return surface if bearing is None else (bearing, surface)


def pendulum_period(radius: float) -> float:
    """T_b = 2 pi sqrt(R / g) [s] of a pendulum of radius R [m]."""
    return 2 * math.pi * math.sqrt(radius / STANDARD_GRAVITY)


def design_fields(values: dict, units) -> dict:
    """JSON entries of a design point (name -> SI value), in `VARIABLE_FLAGS`' order: a length
    or pressure in `units` (a radius with its period), a time in seconds, a ratio as it is."""
    fields = {}
    for name, spec in VARIABLE_FLAGS.items():
        if name not in values:
            continue
        if spec.dimension in ("length", "pressure"):
            unit, scale = getattr(units, spec.dimension)
            fields[f"{name}_{unit}"] = values[name] / scale
        elif spec.dimension == "time":
            fields[f"{name}_s"] = values[name]
        else:
            fields[name] = values[name]
        if name == "radius":
            fields["isolation_period_s"] = pendulum_period(values["radius"])
    return fields


def design_text(values: dict, units) -> str:
    """'Tb = 3.267 s, pressure = 2000 psi' or 'R = 61.2 in (Tb = 2.5 s), f_max = 0.08'."""
    parts = []
    for name, spec in VARIABLE_FLAGS.items():
        if name not in values:
            continue
        value = values[name]
        shown = (units.show(value, spec.dimension) if spec.dimension in ("length", "pressure")
                 else f"{value:.{spec.digits}g} s" if spec.dimension == "time" else f"{value:.{spec.digits}g}")
        if name == "radius":
            shown += f" (Tb = {pendulum_period(value):.4g} s)"
        parts.append(f"{spec.label or name} = {shown}")
    return ", ".join(parts)


def plot_units(units) -> dict:
    """`plot_design`'s units (SI factor, name) of the design variables and of lengths."""
    of = {"length": units.length[::-1], "pressure": units.pressure[::-1], "time": (1.0, "s")}
    return {**{name: of.get(spec.dimension, (1.0, "-")) for name, spec in VARIABLE_FLAGS.items()},
            "length": units.length[::-1]}


def lowered_start(sweep, bounds, structure, records, record_step: float, disp_limit: float,
                  penalty: float, statistic: str = "mean") -> dict:
    """BFGS's start on any isolator: the grid's best point for the limit on the smoothed
    statistic lowered by the gap between the true and the smoothed peak at the grid's best
    point for `disp_limit` (the limit BFGS then starts on, `optimise_design`), the objective
    `grid_best` is read on too. The unlowered limit binds too late on a grid whose smoothed
    peaks lie below the true ones: its best point is then too soft a design (the largest
    radius or period), far from the one that meets the limit on the true peaks."""
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
