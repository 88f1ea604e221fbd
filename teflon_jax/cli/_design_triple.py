"""`teflon-jax design --isolator triple-fp|double-fp --isolator-file FILE`: the design variables
of a triple friction pendulum (`teflon_jax.systems.TRIPLE_DESIGN_VARIABLES`: the outer radii's
scale, the inner and outer f_max, the capacities' scale) or of a double one
(`DOUBLE_DESIGN_VARIABLES`: both radii's scale, the surfaces' f_max, the capacities' scale),
each designed over the bounds of its range flag; at least one flag is needed, and the other
isolators' flags are refused by name (and these with them)."""

import pathlib

from ._common import add_quantity

TRIPLE_FLAGS = {"outer_radius_scale": "--outer-radius-scale-range", "inner_f_max": "--inner-f-max-range",
                "outer_f_max": "--outer-f-max-range", "capacity_scale": "--capacity-scale-range"}
"""The range flag of each design variable of a triple pendulum."""

DOUBLE_FLAGS = {"radius_scale": "--radius-scale-range", "surface_f_max": "--surface-f-max-range",
                "capacity_scale": "--capacity-scale-range"}
"""The range flag of each design variable of a double pendulum."""

SERIES_FLAGS = {"triple-fp": TRIPLE_FLAGS, "double-fp": DOUBLE_FLAGS}
ALL_FLAGS = {**TRIPLE_FLAGS, **DOUBLE_FLAGS}
"""The range flags of each series pendulum, and all of them."""

_OTHERS = ("--period-range", "--radius-range", "--capacity-range", "--restrainer-ratio", "--pressure-range",
           "--f-max-range", "--pressure", "--isolation-damping")


def add_triple_design_flags(parser) -> None:
    """`--isolator-file` and the range flags of `TRIPLE_FLAGS` and `DOUBLE_FLAGS`."""
    parser.add_argument("--isolator-file", default=None, metavar="FILE", type=pathlib.Path,
                        help="with --isolator triple-fp or double-fp: the isolator file whose bearing "
                        "is designed (each variable a change of it)")
    helps = {
        "outer_radius_scale": "factor on the outer surfaces' effective radii b and c (regimes II-IV "
                              "soften as it grows)",
        "inner_f_max": "f_max of the inner surfaces (their Eq. 1 scaled to it; at most the bottom's)",
        "outer_f_max": "f_max of the bottom surface, the top's Eq. 1 scaled by the same factor",
        "capacity_scale": "factor on the effective displacement capacities (all of the isolator's)",
        "radius_scale": "factor on both effective radii R_1 and R_2 (every slope of the loop "
                        "falls as it grows)",
        "surface_f_max": "f_max of the bottom surface, the top's Eq. 1 scaled by the same factor "
                         "(which surface slides first kept)"}
    for name, flag in ALL_FLAGS.items():
        owners = " or ".join(k for k, flags in SERIES_FLAGS.items() if name in flags)
        add_quantity(parser, flag, "dimensionless", None, f"--isolator {owners}: bounds of the {helps[name]}",
                     minimum=0.0, nargs=2)


def refuse_triple_flags(args) -> None:
    """For the flat and single-fp isolators: `ValueError` naming a triple-fp or double-fp flag
    given."""
    given = [flag for name, flag in ALL_FLAGS.items() if getattr(args, name + "_range_text") is not None]
    if args.isolator_file is not None:
        given.insert(0, "--isolator-file")
    if given:
        owners = [k for k, flags in SERIES_FLAGS.items() if given[0] in flags.values()] or list(SERIES_FLAGS)
        raise ValueError(f"{given[0]}: applies to --isolator {' or '.join(owners)} only, not "
                         f"{args.isolator}; add --isolator {owners[0]} or leave {given[0]} out.")


def resolve_triple_design(args) -> tuple[dict, object]:
    """({variable: (low, high)}, the `TriplePendulum` or `DoublePendulum` of --isolator-file)
    of `design --isolator triple-fp|double-fp`, the bounds checked against the file's bearing
    (`check_triple_box`, `check_double_box`); `ValueError` naming the flag."""
    from ..systems import check_double_box, check_triple_box
    from ._triple import _load

    isolator, flags = args.isolator, SERIES_FLAGS[args.isolator]
    for flag in _OTHERS + tuple(f for f in ALL_FLAGS.values() if f not in flags.values()):
        if getattr(args, flag[2:].replace("-", "_") + "_text") is not None:
            raise ValueError(f"{flag}: does not apply to --isolator {isolator} (its friction, period and "
                             f"damping are its surfaces'); design it over {', '.join(flags.values())}.")
    if args.bearing is not None:
        raise ValueError(f"--bearing: does not apply to --isolator {isolator} (the friction of its "
                         "surfaces is in --isolator-file); leave --bearing out.")
    if args.isolator_file is None:
        raise ValueError(f"--isolator-file: --isolator {isolator} designs the bearing of an isolator "
                         "file (docs/formats.md#isolator-file); give one.")
    variables = {name: tuple(float(v) for v in getattr(args, name + "_range"))
                 for name in flags if getattr(args, name + "_range_text") is not None}
    if not variables:
        raise ValueError(f"--isolator {isolator}: give at least one of {', '.join(flags.values())} "
                         "(the variables to design, with their bounds).")
    for name, (lo, hi) in variables.items():
        if not lo < hi:
            raise ValueError(f"{flags[name]}: the low bound must lie below the high one, got "
                             f"{' '.join(getattr(args, name + '_range_text'))}.")
    pendulum = _load(args.isolator_file, isolator)
    try:
        (check_triple_box if isolator == "triple-fp" else check_double_box)(pendulum, variables)
    except ValueError as error:
        name = str(error).split(":", 1)[0]
        raise ValueError(f"{flags.get(name, name)}{str(error)[len(name):]}") from None
    args.design_flags = tuple(flags[n] for n in variables)
    args.isolation_damping, args.isolation_damping_text = 0.0, "0 (friction only)"
    return variables, pendulum


def triple_structure_for_design(args, triple):
    """The `TripleIsolatedStructure` the design differentiates: its sliders balanced to
    rounding (so that central differences see no trace of where Newton's loop stopped)."""
    import jax
    import jax.numpy as jnp

    from ..systems import isolated_structure

    triple = jax.tree_util.tree_map(lambda x: jnp.asarray(x, float), triple)
    return isolated_structure(args.structure, isolator=triple.isolator, **{triple.isolator.split("-")[0]: triple},
                              time_step=0.005 if args.time_step is None else args.time_step,
                              newton_tolerance=0.0)


def percentile_check(args, structure, result, records) -> dict:
    """The 95th percentile over the motions of the smooth peak base displacement at the
    optimum, its derivative in each design variable and central differences
    (`percentile_disp_gradient_check`), as JSON entries."""
    from ..studies import percentile_disp_gradient_check

    check = percentile_disp_gradient_check(structure, result.optimum, records, args.record_step)
    return {"p95_smooth_base_disp_m": check["value"], "p95_disp_gradient": check["gradient"],
            "p95_disp_finite_differences": check["finite_differences"],
            "p95_disp_gradient_rel_error": check["rel_error"]}
