"""The structure `teflon-jax run` builds from its flags: the rigid mass, the Table 2 building or
a rigid slab on bearing groups (`--plan`), on any isolator of `read_isolator`, under the ground
components; for a suite, that structure under each record pair (`suite_build`). The numbers of
the flags and the plan are read and checked before any record (`read_structure`)."""

import typing

from ..units import parse_quantity
from ._isolator_flags import slab_isolators
from ._plan_file import read_plan
from ._run_bearing import bearing_of_flags, fraction

STRUCTURES = ("rigid", "building", "slab")

DEFAULT_WEIGHT = "100kN"
"""The rigid mass's weight where `--weight` is not given."""


class StructureFlags(typing.NamedTuple):
    """The structure flags in SI: solver `time_step` [s], `weight` [N] of the rigid mass, the
    flat sliders' spring `period` [s] (a single pendulum's 2 pi sqrt(R / g); None: no springs),
    the isolation `damping` ratio, the bearings' contact `pressure` [Pa]; the slab's `plan`
    (`read_plan`) and its groups' isolator parts `slab` (`slab_isolators`), else None."""

    time_step: float
    weight: float
    period: float | None
    damping: float
    pressure: float
    plan: dict | None
    slab: dict | None


def read_structure(args, isolator) -> StructureFlags:
    """`StructureFlags` of `run`'s flags and `isolator`; `ValueError` naming the flag (or the
    plan's file and key)."""
    time_step = parse_quantity(args.time_step, "time", where="--time-step")
    if not time_step > 0:
        raise ValueError(f"--time-step: must be > 0, got {args.time_step}.")
    if args.weight is not None and args.structure != "rigid":
        whose = "Table 2's (672 kip)" if args.structure == "building" else "the plan's weight"
        raise ValueError(f"--weight: is the rigid mass's; the {args.structure}'s weight is {whose}; leave "
                         "--weight out.")
    weight = parse_quantity(DEFAULT_WEIGHT if args.weight is None else args.weight, "force", where="--weight")
    if not weight > 0:
        raise ValueError(f"--weight: must be > 0, got {args.weight}.")
    period = isolator.period
    if args.isolation_period is not None:
        period = parse_quantity(args.isolation_period, "time", where="--isolation-period")
        if not period > 0:
            raise ValueError(f"--isolation-period: must be > 0, got {args.isolation_period}.")
    damping = 0.0 if args.isolation_damping is None else fraction(args.isolation_damping, "--isolation-damping")
    if damping > 0 and period is None:
        raise ValueError("--isolation-damping: dampers need springs; give --isolation-period too.")
    pressure = parse_quantity(args.pressure, "pressure", where="--pressure")  # heating's p
    plan = None if args.plan is None else read_plan(args.plan, args.structure)
    slab = None if plan is None else slab_isolators(args, isolator, plan, period)
    return StructureFlags(time_step, weight, period, damping, pressure, plan, slab)


def build_structure(args, isolator, flags: StructureFlags, ground_x, ground_y, two: bool = True,
                    friction_factor: float = 1.0):
    """The system of `args.structure` on `isolator` under the ground `Signal`s [m/s^2]: flat
    sliders and single pendulums in both directions (`rigid_mass`,
    `six_storey_building` with `components=2`, `slab_on_bearings`), series pendulums in one direction, or in
    two with `two` (`triple_structure`; on a slab always two). The
    `friction_factor` of a bounding case scales f_max and delta_f of Table 1's row or each surface's."""
    if flags.plan is not None:
        return _on_plan(args, isolator, flags, ground_x, ground_y, friction_factor)
    if isolator.pendulum is not None:
        from ..systems import triple_structure

        pendulum = _scaled([isolator.pendulum], friction_factor)[0]
        return triple_structure(args.structure, pendulum, ground_x, time_step=flags.time_step,
                                weight=flags.weight, ground_y=ground_y if two else None)
    from ..systems import rigid_mass, six_storey_building

    bearing = bearing_of_flags(args, isolator.bearing, args.ptfe, args.pressure, "--pressure", friction_factor)
    common = dict(bearing=bearing, ground_acceleration=ground_x, ground_y=ground_y, components=2, time_step=flags.time_step,
                  isolation_period=flags.period, contact_pressure=flags.pressure)
    if args.structure == "rigid":
        return rigid_mass(weight=flags.weight, damping_ratio=flags.damping, **common)
    return six_storey_building(isolation_damping=flags.damping, **common)


def _scaled(pendulums, factor: float):
    """`pendulums` with every surface's f_max and delta_f times `factor` (a bounding case; 1
    otherwise): `SeriesPendulum.scaled_friction`."""
    return pendulums if factor == 1.0 else [p.scaled_friction(factor) for p in pendulums]


def _on_plan(args, isolator, flags: StructureFlags, ground_x, ground_y, friction_factor: float):
    """`slab_on_bearings` (or `building_on_plan` under --structure building) of the plan on its
    groups' isolator values: series pendulums (`flags.slab`), or each group's
    bearing at its pressure, alone (flat sliders) or on the group's surface (single pendulums),
    with the isolation damping; f_max and delta_f times `friction_factor`."""
    from ..systems import building_on_plan, slab_on_bearings

    plan, groups = flags.plan, flags.plan["groups"]
    options = dict(flags.slab)
    if "pendulums" in options:
        values = _scaled(options.pop("pendulums"), friction_factor)
    else:
        from ..bearing import concave_surface

        pressures = [g["pressure"] or args.pressure for g in groups]
        bearings = [bearing_of_flags(args, isolator.bearing, g["ptfe"] or args.ptfe, p,
                                     f"--plan: {args.plan}: {g['name']}.pressure", friction_factor)
                    for g, p in zip(groups, pressures)]
        radii = options.pop("radii", None)  # single pendulums: each group's (bearing, surface)
        values = bearings if radii is None else [(b, concave_surface(r)) for b, r in zip(bearings, radii)]
        options.update(
            contact_pressures=[parse_quantity(p, "pressure", where=f"--plan: {args.plan}: {g['name']}.pressure")
                               for g, p in zip(groups, pressures)],
            isolation_damping=flags.damping)
    stiffness = [g["vertical_stiffness"] for g in groups]
    common = dict(
        length_x=plan["length_x"], length_y=plan["length_y"], centre_of_mass=plan["centre_of_mass"],
        positions=[(g["x"], g["y"]) for g in groups], loads=[g["load"] for g in groups], ground_acceleration=ground_x,
        ground_y=ground_y, time_step=flags.time_step, names=[g["name"] for g in groups], isolator=values,
        vertical_stiffness=None if all(k is None for k in stiffness) else [1.0 if k is None else k
                                                                         for k in stiffness],
        **options)
    if args.structure == "building":  # its levels at Table 2's storey heights (`read_plan`)
        return building_on_plan(**common)
    return slab_on_bearings(weight=plan["weight"], height_of_centre_of_mass=plan["height_of_centre_of_mass"],
                            **common)


def suite_build(args, isolator, ax0, ay0, dt, friction_factors=None, vertical=None, *, friction_factor=1.0):
    """(build(ground_x, ground_y[, ground_z]) -> the structure of one pair, its degrees of
    freedom, the slab's plan or None) of `run --suite`: the
    structure of the flags (`build_structure`, under both components, Table 1's or the
    surfaces' f_max and delta_f times `friction_factor`) built once on the first
    pair (`ax0`, `ay0` [m/s^2], step `dt` [s]), its ground motion replaced by each pair's; with
    `friction_factors` ({"f_max", "delta_f", "rate_a": factor}) a `--bearing` file's Eq. 1
    constants scaled wherever the structure carries them (`studies.with_friction_factors`);
    with `vertical` (az (P, n) [m/s^2], the pressure law, the pair names), under each pair's
    vertical component too, as `run --record-z` puts it (`with_vertical`), each checked before
    any run (`check_vertical_pressures`)."""
    from ..excitation import uniform_signal
    from ..systems import under_ground
    from ._normal_load import check_vertical_pressures, with_vertical

    flags = read_structure(args, isolator)
    template = build_structure(args, isolator, flags, uniform_signal(ax0, dt), uniform_signal(ay0, dt),
                               friction_factor=friction_factor)
    if friction_factors is not None:
        from ..studies import with_friction_factors

        template = with_friction_factors(template, friction_factors)
    if vertical is not None:
        az, law, names = vertical
        template = with_vertical(template, az[0], dt, radius=isolator.radius if flags.plan is None else None,
                                 **law)  # a slab's groups hold their W_g / R_g
        check_vertical_pressures(template, [(f"--suite {args.suite}, pair {name}: record_z", row)
                                            for name, row in zip(names, az)], dt)

    def build(ground_x, ground_y, ground_z=None):
        return under_ground(template, ground_x, ground_y, ground_z)

    return build, template.mass.shape[-1], flags.plan


def built_on_plan(args, isolator, *, time_step: float, period, damping: float, record_step: float, vertical: bool = False, solver=None):
    """`montecarlo --plan`: the slab or the building of the plan on its groups' isolators, as
    `run --plan` builds it (`build_structure`), at rest, built once and run under each motion
    (`studies.BuiltStructure`); `args` carries `montecarlo`'s flags in SI with their text
    (`--pressure` as typed) and the bearings are Table 1's rows with breakaway, as its other
    structures take them. `time_step` [s], the flat sliders' spring `period` [s] (None: none)
    and `damping` ratio as resolved; `vertical`: the motions carry a vertical component, on
    the groups' normal loads with the friction following them (`pressure_law`); `solver`: the
    `newton_iterations` and `newton_tolerance` that replace the structure's own."""
    import argparse
    import dataclasses

    import numpy as np

    from ..excitation import uniform_signal
    from ..studies import BuiltStructure
    from ._normal_load import pressure_law, with_vertical

    view = argparse.Namespace(**{**vars(args), "pressure": args.pressure_text, "anisotropic": False,
                                 "lay_angle": None, "breakaway": "table"})
    plan = read_plan(args.plan, args.structure)
    flags = StructureFlags(time_step, 0.0, period, damping, args.pressure, plan,
                           slab_isolators(view, isolator, plan, period))
    rest = uniform_signal(np.zeros(2), record_step)  # each motion's replaces it
    system = build_structure(view, isolator, flags, rest, rest)
    if vertical:
        system = with_vertical(system, np.zeros(2), record_step, **pressure_law(view, isolator, plan))
    return BuiltStructure(dataclasses.replace(system, **(solver or {})),
                          group_names=tuple(g["name"] for g in plan["groups"]))
