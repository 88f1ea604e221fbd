"""The isolator of a plan's bearing groups (`slab_on_bearings`, `building_on_plan`): one
isolator value for every group or one per group (`bearing.isolator_kind`), or the isolator
named with its parts given apart (`bearings`, `radii`, `pendulums`), read into one
`PlanIsolator` whose type of groups picks the engine: series pendulums (S > 1 sliders) on the
series slab's, one surface (flat sliders, single friction pendulums) on the sliders' engine."""

import typing

import numpy as np

from ..bearing import (
    ISOLATORS,
    SERIES_PENDULUMS,
    ConcaveSurface,
    SeriesPendulum,
    SlidingBearing,
    isolator_kind,
    one_surface,
    runs_in_series,
)
from ..catalogue import FLAT


class PlanIsolator(typing.NamedTuple):
    """The groups' isolator: its `name` (`ISOLATORS`), and either the series `pendulums` (one
    per group, or the value given for all, checked by `stack_pendulums`) or the one-surface
    groups' `bearings` (G `SlidingBearing`s) and `radii` (G,) [m] (`None`: flat sliders)."""

    name: str
    bearings: list | None = None
    radii: np.ndarray | None = None
    pendulums: object = None


def plan_isolator(isolator, groups: int, *, bearings=None, radii=None, pendulums=None) -> PlanIsolator:
    """The `PlanIsolator` of `groups` groups: `isolator` an isolator value for all groups or a
    list of one per group, or a name (`None`: "flat") with `bearings`, `radii`, `pendulums`.
    `ValueError` naming the argument for a count other than G, groups of different isolators,
    parts the isolator does not take or lacks."""
    if isolator is None or isinstance(isolator, str):
        return _named(isolator or FLAT.name, groups, bearings, radii, pendulums)
    for name, value in (("bearings", bearings), ("radii", radii), ("pendulums", pendulums)):
        if value is not None:
            raise ValueError(f"{name}: the isolator value carries the groups' isolators; leave {name} out.")
    values = [isolator] * groups if _one_value(isolator) else list(isolator)
    if len(values) != groups:
        raise ValueError(f"isolator: {len(values)} given for {groups} groups; give one for all or one per group.")
    kinds = [isolator_kind(value, f"isolator (group {g + 1})") for g, value in enumerate(values)]
    if len(set(kinds)) > 1:
        raise ValueError(f"isolator: the groups stand on one isolator, got {', '.join(sorted(set(kinds)))}.")
    if runs_in_series(values[0]):
        return PlanIsolator(kinds[0], pendulums=values)
    parts = [one_surface(value, f"isolator (group {g + 1})") for g, value in enumerate(values)]
    for g, (bearing, surface) in enumerate(parts):
        if bearing is None:
            raise ValueError(f"isolator (group {g + 1}): the groups need their SlidingBearing, e.g. "
                             "(bearing, concave_surface(R)) for a single friction pendulum.")
        if surface is not None and not surface.is_linear:
            raise ValueError(f"isolator (group {g + 1}): a plan's pendulums restore with W_g / R_g; give "
                             "concave_surface(R) without restrainer or large-displacement form.")
    surfaces = [surface for _, surface in parts]
    radii = None if surfaces[0] is None else np.array([float(s.radius) for s in surfaces])
    return PlanIsolator(kinds[0], bearings=[bearing for bearing, _ in parts], radii=radii)


def refuse_springs(radii, isolation_period, spring_shares) -> None:
    """`ValueError` naming `isolation_period` and `spring_shares` given with single friction
    pendulums (`radii` set), which restore each group with W_g / R_g instead of springs."""
    if radii is not None and (isolation_period is not None or spring_shares is not None):
        raise ValueError("isolation_period, spring_shares: a slab on single friction pendulums has no "
                         "springs (each group restores with W_g / R_g); leave them out.")


def _one_value(value) -> bool:
    """Whether `value` is one isolator value (for every group) rather than one per group."""
    if isinstance(value, tuple) and len(value) == 2 and isinstance(value[0], SlidingBearing) \
            and isinstance(value[1], ConcaveSurface):
        return True
    return not isinstance(value, (list, tuple))


def _named(name, groups, bearings, radii, pendulums) -> PlanIsolator:
    """The `PlanIsolator` of the isolator `name` and its parts (the messages name the part)."""
    if name not in ISOLATORS:
        raise ValueError(f"isolator: one of {', '.join(map(repr, ISOLATORS))} (or an isolator value), got {name!r}.")
    if name in SERIES_PENDULUMS:
        if pendulums is None:
            raise ValueError(f"pendulums: isolator {name!r} needs its pendulum (one for all groups, or "
                             "one per group; e.g. formats.load_isolator(path)).")
        values = [pendulums] * groups if isinstance(pendulums, SeriesPendulum) else list(pendulums)
        return PlanIsolator(name, pendulums=values)
    if pendulums is not None:
        raise ValueError(f"pendulums: apply to isolator {' or '.join(map(repr, SERIES_PENDULUMS))}, not {name!r}.")
    if bearings is None:
        raise ValueError(f"bearings: isolator {name!r} needs the groups' SlidingBearing(s).")
    bearings = [bearings] * groups if isinstance(bearings, SlidingBearing) else list(bearings)
    if len(bearings) != groups:
        raise ValueError(f"bearings: {len(bearings)} given for {groups} groups.")
    return PlanIsolator(name, bearings=bearings, radii=_radii(name, radii, groups))


def _radii(name, radii, groups):
    """The radii R_g (G,) [m] of the single pendulum (None for flat sliders), checked."""
    flat = name == ISOLATORS[0]  # the name given: flat sliders have no radii, a pendulum needs them
    if flat and radii is not None:
        raise ValueError("radii: apply to isolator 'single-fp' only (flat sliders have none).")
    if not flat and radii is None:
        raise ValueError("radii: isolator 'single-fp' needs the radius R [m] of the groups' surfaces.")
    if flat:
        return None
    radii = np.asarray(radii, dtype=float).reshape(-1)
    if radii.size not in (1, groups):
        raise ValueError(f"radii: give one radius for all groups or one per group ({groups}).")
    radii = np.broadcast_to(radii, (groups,)).copy()
    if not np.all(np.isfinite(radii) & (radii > 0)):
        raise ValueError(f"radii: must be > 0 m, got {radii.tolist()}.")
    return radii
