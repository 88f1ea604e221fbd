"""The isolator of the command line, read in one place: `--isolator flat|single-fp|triple-fp|
double-fp`, `--radius` of the single friction pendulum, `--isolator-file` of the triple and
double ones and `--bearing` of the sliders' friction become one `Isolator` value (`read_isolator`),
which every structure builder of `run` and `montecarlo` takes; a slab's bearing groups get
theirs from the plan (`slab_isolators`). `check_combination` is the one check, before any
work, of an isolator, structure, ground components and solver flags that cannot run together.

Every message names the flag (or the plan's key) as the user wrote it and says what to do.
"""

import dataclasses
import pathlib
from collections.abc import Callable

from ..catalogue import (
    FLAT,
    IN_SERIES,
    ISOLATORS,
    KINDS,
    SINGLE_FP,
    IsolatorKind,
)
from ._common import add_quantity, flags_given

SERIES: dict[str, IsolatorKind] = {name: KINDS[name] for name in IN_SERIES}
"""The series pendulums of the command line, whose surfaces an isolator file gives
(`--isolator-file`), with what the commands say of each (`teflon_jax.catalogue`)."""

SERIES_NAMES = " or ".join(IN_SERIES)
"""The series pendulums as messages name them: "triple-fp or double-fp"."""


def per_isolator(flat, single, series: Callable[[str, IsolatorKind], object]) -> dict:
    """{--isolator: row} of a command's table, in `ISOLATORS` order (`teflon_jax.catalogue`, the
    one list of them: every table keyed by isolator is this function's): the row of `flat`
    sliders, of the `single` friction pendulum and `series(name, facts)` of each series pendulum
    (`SERIES`), so that a pendulum added to the catalogue has its row in every command."""
    return {FLAT.name: flat, SINGLE_FP.name: single,
            **{name: series(name, facts) for name, facts in SERIES.items()}}


_SERIES_ONLY = f"with --isolator {SERIES_NAMES}: "
_SINGLE_ONLY = f"with --isolator {SINGLE_FP.name}: "

_RUN_ISOLATOR = ("flat sliders (with springs of --isolation-period, or none), a single friction pendulum (a "
                 "concave surface of --radius, restoring force W u / R) or a triple or double friction "
                 "pendulum (the surfaces of --isolator-file)")
_RUN_FILE = ("the isolator file of its surfaces (radius, capacity and Eq. 1 friction of each; "
             "docs/formats.md#isolator-file)")
_RUN_RADIUS = "radius of curvature R of the concave surface, period 2 pi sqrt(R / g), e.g. 88in (3 s)"


def add_isolator_flags(parser, *, isolator: str = _RUN_ISOLATOR, file: str | None = _RUN_FILE,
                       radius: str | None = _RUN_RADIUS, save: str | None = None,
                       choices: tuple = ISOLATORS, file_metavar: str = "FILE",
                       save_metavar: str = "FILE", file_alone: bool = False) -> None:
    """`--isolator NAME` (one of `choices`, default flat) and, where a command takes them,
    `--isolator-file` of the series pendulums, `--radius R` (a length) of the single friction
    pendulum and `--save-isolator` of a series pendulum's result: each flag defined here
    once, its help the command's own words (`isolator`, `file`, `radius`, `save`; `None`: the
    command has no such flag) after the isolators it applies to (`file_alone`: the file
    names its pendulum whatever --isolator says)."""
    parser.add_argument("--isolator", default=FLAT.name, choices=choices,
                        help=f"{isolator} (default {FLAT.name})")
    if file is not None:
        parser.add_argument("--isolator-file", default=None, metavar=file_metavar, type=pathlib.Path,
                            help=file if file_alone else _SERIES_ONLY + file)
    if radius is not None:
        add_quantity(parser, "--radius", "length", None, _SINGLE_ONLY + radius, minimum=0.0)
    if save is not None:
        parser.add_argument("--save-isolator", default=None, metavar=save_metavar, type=pathlib.Path,
                            help=_SERIES_ONLY + save)


def add_record_load_flags(parser, *, normal: str, task: str) -> None:
    """`--normal-load` (a force) for test records without one, in the command's words
    (`normal`), and `--reference-load` of a series pendulum whose surfaces read their contact
    pressure, whose records the command then `task`s ("fitted", "searched") under a varying N."""
    add_quantity(parser, "--normal-load", "force", None, "normal load for records without one" + normal,
                 minimum=0.0)
    add_quantity(parser, "--reference-load", "force", None, _SERIES_ONLY + "the load --isolator-file's "
                 "contact pressures are given under (the weight W the pendulum will carry); each sample's "
                 f"pressure is then that times N / W, so a record whose N varies can be {task}, surfaces that "
                 "read their pressure (heating, pressure dependence) included (default: none; such a record "
                 "is refused)", minimum=0.0)


def check_normal_load_used(args, records, paths) -> None:
    """`ValueError` for `--normal-load` given while every record of `records` (read from
    `paths`) states its own normal load (column N), which the fit or search takes: the flag
    would be ignored."""
    if getattr(args, "normal_load", None) is None or any(r.normal_load is None for r in records):
        return
    which = f"the record {paths[0]} states" if len(paths) == 1 else f"every record ({', '.join(map(str, paths))}) states"
    raise ValueError(f"--normal-load {args.normal_load_text}: {which} its normal load (column N), and that is "
                     "the load used; the flag is for records without one (a friction damper's); leave it out.")


@dataclasses.dataclass(frozen=True)
class Isolator:
    """The isolator of the flags: `name` (an `ISOLATORS` entry), `radius` R [m] of a single
    friction pendulum, `pendulum` (the `TriplePendulum` or `DoublePendulum` of `file`, the
    isolator file), `bearing` (the `SlidingBearing` of `--bearing`, or None for Table 1's row of
    --ptfe and --pressure) of flat sliders and the single pendulum, whose friction the flags give;
    `posterior` (a `BearingPosterior` or `IsolatorPosterior`) and `mixture` (a `BearingMixture`),
    the draws read with the bearing or isolator file in the same read, None where it has none."""

    name: str
    radius: float | None = None
    pendulum: object = None
    file: pathlib.Path | None = None
    bearing: object = None
    posterior: object = None
    mixture: object = None

    @property
    def period(self) -> float | None:
        """2 pi sqrt(R / g) [s] of a single pendulum; None for flat sliders (the springs of
        --isolation-period) and series pendulums (their period changes with their regime)."""
        if self.radius is None:
            return None
        from ..bearing import concave_surface

        return float(concave_surface(self.radius).isolation_period())

    @property
    def restores(self) -> bool:
        """Whether the isolator restores the structure itself (a pendulum), without springs."""
        return self.radius is not None or self.pendulum is not None

    @property
    def description(self) -> str | None:
        """The series pendulum's words (for titles), None for the others."""
        return None if self.pendulum is None else self.pendulum.description

    @property
    def value(self):
        """The library's isolator value (`teflon_jax.bearing.isolator_kind`): the series
        pendulum of the file; a single pendulum's `concave_surface(R)`, or (bearing, surface)
        with --bearing; flat sliders' --bearing (None: Table 1's row)."""
        if self.pendulum is not None or self.radius is None:
            return self.bearing if self.pendulum is None else self.pendulum
        from ..bearing import concave_surface

        surface = concave_surface(self.radius)
        return surface if self.bearing is None else (self.bearing, surface)

    def structure_options(self) -> dict:
        """The isolator's keywords of `systems.isolated_structure` (and of
        `studies.bidirectional_isolated_structure`): its `value`."""
        return {"isolator": self.value}

    def entries(self, args) -> dict:
        """The run JSON's isolator entries: name, isolator file, radius [m], the anisotropy and
        lay angle [deg] of the sliders' bearing (None where the isolator has none)."""
        import numpy as np

        from ..units import parse_quantity

        lay = getattr(args, "lay_angle", None)
        return {"isolator": self.name, "isolator_file": None if self.file is None else str(self.file),
                "radius_m": self.radius, "anisotropic": bool(getattr(args, "anisotropic", False)),
                "lay_angle_deg": None if lay is None else float(
                    np.degrees(parse_quantity(lay, "angle", where="--lay-angle")))}


def read_isolator(args) -> Isolator:
    """The `Isolator` of `--isolator`, `--radius`, `--isolator-file` and `--bearing`, with the
    flags checked first: `ValueError` naming an isolator file without a series pendulum, a
    radius without the single pendulum, the flags a pendulum takes from its own geometry (and a
    series pendulum from its file), and a file of another isolator."""
    path = getattr(args, "isolator_file", None)
    if path is not None and args.isolator not in IN_SERIES:
        raise ValueError(f"--isolator-file: applies to --isolator {SERIES_NAMES} only (the pendulums whose "
                         f"surfaces it gives), not {args.isolator}; add --isolator {IN_SERIES[0]} (or another "
                         "of them) or leave --isolator-file out.")
    return _READERS[args.isolator](args)


def _flat(args) -> Isolator:
    if getattr(args, "radius", None) is not None:
        raise ValueError("--radius: applies to --isolator single-fp only (flat sliders have no "
                         "radius); add --isolator single-fp or leave --radius out.")
    return Isolator(FLAT.name, **_bearing(args))


def _single(args) -> Isolator:
    if args.radius is None:
        raise ValueError("--radius: --isolator single-fp needs the radius of its concave surface, "
                         "e.g. --radius 88in.")
    if getattr(args, "isolation_period_text", args.isolation_period) is not None:
        raise ValueError("--isolation-period: conflicts with --isolator single-fp, whose period is "
                         "2 pi sqrt(R / g) of --radius; leave --isolation-period out.")
    return Isolator(SINGLE_FP.name, radius=args.radius, **_bearing(args))


def _series(args) -> Isolator:
    isolator, path = args.isolator, args.isolator_file
    if path is None:
        raise ValueError(f"--isolator-file: --isolator {isolator} needs the isolator file of its "
                         "surfaces (radius, capacity and friction of each; see docs/formats.md).")
    if args.radius is not None:
        raise ValueError(f"--radius: does not apply to --isolator {isolator} (its radii are in "
                         "--isolator-file); leave --radius out.")
    conflicting = [("--isolation-period", getattr(args, "isolation_period_text", args.isolation_period)),
                   ("--isolation-damping", getattr(args, "isolation_damping_text", args.isolation_damping)),
                   ("--bearing", args.bearing)]
    conflicting += [(flag, flag) for flag in flags_given(args, getattr(args, "bearing_option_defaults", {}))]
    for flag, value in conflicting:
        if value is not None:
            raise ValueError(f"{flag}: does not apply to --isolator {isolator}, whose friction, "
                             f"period and damping are its surfaces' in --isolator-file; leave {flag} out.")
    read = read_isolator_file_flag(path, isolator)
    return Isolator(isolator, pendulum=read.pendulum, file=path, posterior=read.posterior)


_READERS = per_isolator(_flat, _single, lambda name, facts: _series)
"""How each `--isolator` is read from the flags."""


def _bearing(args) -> dict:
    """The `Isolator` fields of `--bearing FILE` (its one read, `read_bearing_flag`): its bearing,
    posterior and mixture; none without the flag."""
    from ._bearing_flags import read_bearing_flag

    read = read_bearing_flag(args)
    return {} if read is None else {"bearing": read.bearing, "posterior": read.posterior, "mixture": read.mixture}


def load_isolator_file(path, isolator, command=None):
    """The pendulum of the isolator file `path` (`read_isolator_file_flag`)."""
    return read_isolator_file_flag(path, isolator, command).pendulum


def read_isolator_file_flag(path, isolator, command=None):
    """The `IsolatorFile` (pendulum and posterior) of the isolator file `path`, read once;
    `ValueError` naming the flag, also for a file of another isolator than `--isolator`'s (a
    start file of `command`, fit or diagnose, is named as such)."""
    from ..formats import read_isolator_file

    try:
        read = read_isolator_file(path)
    except ValueError as error:
        raise ValueError(f"--isolator-file {error}") from None
    pendulum = read.pendulum
    if pendulum.isolator != isolator:
        if command is not None:
            raise ValueError(f"--isolator-file: {path} holds a {pendulum.isolator} isolator; {command} "
                             f"--isolator {isolator} starts from a file of that isolator (or give "
                             f"--isolator {pendulum.isolator}).")
        raise ValueError(f"--isolator-file: {path} holds a {pendulum.isolator} isolator, not the "
                         f"{isolator} of --isolator; give --isolator {pendulum.isolator} or another file.")
    return read


def check_combination(args, isolator: Isolator) -> None:
    """`ValueError` naming the flag, before any work, for what cannot run together: a plan
    under the rigid mass, the slab without one, the building on flat sliders without springs, and
    a Newton tolerance in a flat bearing's units on series pendulums."""
    structure, plan = args.structure, getattr(args, "plan", None)
    if plan is not None and structure not in ("slab", "building"):
        raise ValueError("--plan: stands a slab (--structure slab) or the Table 2 building (--structure "
                         f"building) on bearing groups; not the {structure} mass.")
    if plan is None and structure == "slab":
        raise ValueError("--plan: --structure slab needs a plan file (bearing groups and loads).")
    if structure == "building" and not isolator.restores and args.isolation_period is None:
        raise ValueError("--isolation-period: the building needs its springs (Fig. 11: 0.2-4 s), e.g. 2.5s, "
                         "or a friction pendulum (--isolator single-fp --radius 88in).")
    if getattr(args, "newton_tolerance", None) is None:
        return
    if isolator.pendulum is not None:
        raise ValueError("--newton-tolerance: is in units of a flat bearing's yield displacement; "
                         f"the {isolator.name} isolator's sliders are solved to their own tolerance "
                         "(a force imbalance of 1e-7 W); leave --newton-tolerance out.")


_NOT_SERIES = ("--plan: {plan}: {group}.isolator_file applies with --isolator " + SERIES_NAMES + " only, not "
               "{isolator}; leave it out or give that isolator.")
_SERIES_KEY = ("--plan: {plan}: {group}.{key} does not apply to --isolator {isolator} ({why}); leave '{key}' out "
               "of the group.")
_SERIES_KEYS = (("radius", _SERIES_KEY, "its radii are in the isolator file"),
                ("springs", _SERIES_KEY, "each group restores with its pendulum"),
                ("ptfe", _SERIES_KEY, "its friction is in the isolator file"),
                ("pressure", _SERIES_KEY, "its friction is in the isolator file"))
_GROUP_KEYS_REFUSED = per_isolator(
    flat=(("isolator_file", _NOT_SERIES, ""),
          ("radius", "--plan: {plan}: {group}.radius applies with --isolator single-fp only (flat sliders have "
                     "none); add it or leave the radius out.", "")),
    single=(("isolator_file", _NOT_SERIES, ""),
            ("springs", "--plan: {plan}: {group}.springs conflicts with --isolator single-fp (each group restores "
                        "with its pendulum, W_g / R_g); leave 'springs' out.", "")),
    series=lambda name, facts: _SERIES_KEYS,
)
"""The keys of a plan's group that each isolator refuses, with the message that says why."""


def slab_isolators(args, isolator: Isolator, plan: dict, period: float | None = None) -> dict:
    """The isolator parts of the groups of `plan` (`_run_structure` makes them the isolator values
    of `systems.slab_on_bearings`)
    (`read_plan`): flat sliders' springs (of `period` [s], shared by the groups' `springs`),
    single pendulums' radii (`--radius`, a group's `radius` overriding it; kept as
    `plan["radii"]`) or series pendulums (`--isolator-file`, a group's `isolator_file`
    overriding it; kept as `plan["isolator_files"]`). `ValueError` naming the group's key that
    the isolator does not take, or its isolator file that is missing or of another isolator."""
    groups = plan["groups"]
    for key, message, why in _GROUP_KEYS_REFUSED[isolator.name]:
        for g in groups:
            if g[key] is not None:
                raise ValueError(message.format(plan=args.plan, group=g["name"], key=key, isolator=isolator.name, why=why))
    if isolator.radius is not None:
        plan["radii"] = [isolator.radius if g["radius"] is None else g["radius"] for g in groups]
        return {"radii": plan["radii"]}
    if isolator.pendulum is None:
        return {"isolation_period": period,
                "spring_shares": [1.0 if g["springs"] is None else g["springs"] for g in groups]}
    pendulums = [isolator.pendulum if g["isolator_file"] is None else _group_pendulum(args, isolator, g)
                 for g in groups]
    plan["isolator_files"] = [str(g["isolator_file"] or isolator.file) for g in groups]
    return {"pendulums": pendulums}


def _group_pendulum(args, isolator: Isolator, group: dict):
    path = group["isolator_file"]
    if not pathlib.Path(path).is_file():
        raise ValueError(f"--plan: {args.plan}: {group['name']}.isolator_file {path} is not a file "
                         "(a path relative to the plan's folder).")
    try:
        return load_isolator_file(path, isolator.name)
    except ValueError as error:
        raise ValueError(f"--plan: {args.plan}: {group['name']}.isolator_file: {error}") from None
