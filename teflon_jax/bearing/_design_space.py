"""The design space of each isolator (`DESIGN_SPACES`): the variables a design dict may set on
an isolated structure of that isolator, their admissible ranges, the check of a box of
bounds, and the isolator a design gives. Every consumer (the isolated structures, the design
study, the command line) looks the isolator up here (`design_space`, `designed_isolator`);
it depends on the isolator types only (duck-typed structures), and the structures on it.

- "flat": sliders on springs (`IsolatedStructure`): the period T_b [s] of the springs, the
  contact pressure [Pa] (Table 1's Eq. 1 constants there), zeta_b [-] and Eq. 1 / Eq. 17
  constants overriding Table 1's (Constantinou, Mokha & Reinhorn 1990; `DESIGN_VARIABLES`,
  `design_ranges`, `check_design`).
- "single-fp": a concave surface of radius R [m], T_b = 2 pi sqrt(R / g) (Zayas, Low &
  Mahin 1990), and its displacement capacity d [m] where a restrainer engages; the friction
  variables of the flat sliders.
- "triple-fp" (`TRIPLE_DESIGN_VARIABLES`, `designed_triple`): a smooth change of the isolator
  file's `TriplePendulum` (Fenz & Constantinou 2008): `outer_radius_scale` s [-] (the outer
  surfaces' effective radii b, c -> s b, s c: the stiffness of regimes II-IV, 1 / (a + b),
  1 / (b + c), 1 / (a + c), falls as s grows); `inner_f_max` [-] (Eq. 1 of the inner surfaces
  scaled so that their f_max is this value, delta_f in proportion: mu(v) -> (f / f_max) mu(v),
  f_min >= 0 kept); `outer_f_max` [-] (Eq. 1 of the bottom surface scaled to this f_max, the
  top's by the same factor: their ratio, which orders regimes II and III, kept);
  `capacity_scale` [-] (the three effective displacement capacities times it). The series
  model needs a < s min(b, c) and inner f_max <= bottom f_max <= top f_max
  (`check_triple_pendulum`); `check_triple_box` refuses ranges that leave them.
- "double-fp" (`DOUBLE_DESIGN_VARIABLES`, `designed_double`): both radii's scale, the
  surfaces' f_max, the capacities' scale of the `DoublePendulum` (Fenz & Constantinou 2006).

Either series pendulum also takes `FRICTION_FACTOR` (a bounding case: every surface's Eq. 1
friction times a property modification factor; `designed_pendulum`).
"""

import math
from collections.abc import Callable, Mapping
from typing import NamedTuple

import equinox as eqx
import numpy as np

from ..units import PSI
from ..validation import concrete
from ._friction import FrictionParameters
from ._series_pendulum import DoublePendulum
from ._triple_pendulum import TriplePendulum

DESIGN_VARIABLES = (
    "isolation_period",
    "pressure",
    "isolation_damping",
    "f_max",
    "delta_f",
    "rate_a",
    "breakaway_ratio",
    "radius",
    "capacity",
)
"""Names a design dict may set: T_b [s] (flat sliders), contact pressure [Pa] (Eq. 1 constants
and b from Table 1 at that pressure), zeta_b [-], Eq. 1 / Eq. 17 constants overriding Table 1,
the radius R [m] of a friction pendulum's surface and its displacement capacity d [m] (where
its restrainer engages; the surface must have one)."""


def design_ranges(structure) -> dict[str, tuple[float, float]]:
    """Admissible range [low, high] of each design variable (SI) of an isolated structure
    (`isolated_structure`): the pressure within the Table 1 rows (any positive contact
    pressure for a given bearing), positive periods, damping in [0, 1), friction constants in
    their physical ranges; a triple or double pendulum's (a structure with a `pendulum`):
    those of its `design_space`."""
    if getattr(structure, "pendulum", None) is not None:
        return pendulum_design_ranges(structure.pendulum)
    if structure.bearing is None:
        pressures = np.asarray(structure.table().pressures)
        pressure = (float(pressures[0]), float(pressures[-1]))
    else:  # a given bearing's contact pressure (through its heating or pressure dependence)
        pressure = (1.0, math.inf)
    return {
        "isolation_period": (1e-3, math.inf),
        "pressure": pressure,
        "isolation_damping": (0.0, 1.0),
        "f_max": (1e-6, 1.0),
        "delta_f": (0.0, 1.0),
        "rate_a": (0.0, math.inf),
        "breakaway_ratio": (1.0, math.inf),
        "radius": (1e-3, math.inf),
        "capacity": (1e-6, math.inf),
    }


def check_design(structure, design: Mapping) -> None:
    """`ValueError` naming the variable when a concrete design value is outside its range
    (`design_ranges`), e.g. a pressure outside Table 1's 1000-6500 psi for UF."""
    ranges = design_ranges(structure)
    for name, value in design.items():
        if name not in ranges:
            raise ValueError(
                f"design: unknown variable {name!r}; accepted: {', '.join(ranges)}."
            )
        array = concrete(value)
        if array is None:  # traced: checked by the caller's bounds instead
            continue
        array = array.astype(float)
        lo, hi = ranges[name]
        tolerance = 1e-6 * max(abs(lo), abs(hi) if math.isfinite(hi) else 0.0, 1.0)  # float32 rounding
        bad = ~np.isfinite(array) | (array < lo - tolerance) | (array > hi + tolerance)
        if np.any(bad):
            if name == "pressure":
                text = (
                    f"outside the Table 1 rows of {structure.ptfe}/{structure.direction}, "
                    f"{lo / PSI:.0f}-{hi / PSI:.0f} psi ({lo:.4g}-{hi:.4g} Pa)"
                )
                shown = (array[bad] / PSI).tolist()
                raise ValueError(f"pressure: {text}; got {shown} psi.")
            raise ValueError(
                f"{name}: must lie in [{lo}, {hi}]; got {array[bad].tolist()}."
            )


TRIPLE_DESIGN_VARIABLES = ("outer_radius_scale", "inner_f_max", "outer_f_max", "capacity_scale")
"""Names a design dict of a `TripleIsolatedStructure` on a `TriplePendulum` may set (module docstring)."""


def _scaled(friction: FrictionParameters, factor) -> FrictionParameters:
    return FrictionParameters(friction.f_max * factor, friction.delta_f * factor, friction.rate_a)


def designed_triple(triple: TriplePendulum, design: Mapping) -> TriplePendulum:
    """`triple` with the design variables of `design` applied (module docstring; values may
    be traced). `ValueError` naming an unknown variable."""
    unknown = sorted(set(design) - set(TRIPLE_DESIGN_VARIABLES))
    if unknown:
        raise ValueError(f"design: unknown variable(s) {unknown} for the triple-fp isolator; "
                         f"accepted: {', '.join(TRIPLE_DESIGN_VARIABLES)}.")
    s = design.get("outer_radius_scale", 1.0)
    inner = design.get("inner_f_max", triple.inner_friction.f_max) / triple.inner_friction.f_max
    outer = design.get("outer_f_max", triple.bottom_friction.f_max) / triple.bottom_friction.f_max
    k = design.get("capacity_scale", 1.0)
    return with_fields(
        triple, bottom_radius=s * triple.bottom_radius,
        top_radius=s * triple.top_radius, inner_capacity=k * triple.inner_capacity,
        bottom_capacity=k * triple.bottom_capacity, top_capacity=k * triple.top_capacity,
        inner_friction=_scaled(triple.inner_friction, inner),
        bottom_friction=_scaled(triple.bottom_friction, outer),
        top_friction=_scaled(triple.top_friction, outer))


def with_fields(pendulum, **fields):
    """`pendulum` with the named fields replaced (values may be traced), everything else (its
    heating, contact pressures and surface parts) kept."""
    names = list(fields)
    return eqx.tree_at(lambda p: [getattr(p, name) for name in names], pendulum, [fields[n] for n in names])


def triple_design_ranges(triple: TriplePendulum) -> dict:
    """Admissible (low, high) of each design variable of `triple` taken alone: the outer
    radii above the inner one, friction within (0, 1] in the series model's order, positive
    capacities."""
    a, b, c = (float(np.asarray(x)) for x in (triple.inner_radius, triple.bottom_radius, triple.top_radius))
    m2, m1, m4 = (float(np.asarray(f.f_max)) for f in (triple.inner_friction, triple.bottom_friction,
                                                       triple.top_friction))
    return {"outer_radius_scale": (a / min(b, c) * (1 + 1e-9), math.inf),
            "inner_f_max": (1e-6, m1),
            "outer_f_max": (m2, m1 / m4),
            "capacity_scale": (1e-6, math.inf)}


def check_triple_box(triple: TriplePendulum, variables: Mapping) -> None:
    """`ValueError` naming the variable whose bounds (low, high) leave the series model's
    order at a corner of the box (`designed_triple`, module docstring)."""
    ranges = triple_design_ranges(triple)
    m1 = float(np.asarray(triple.bottom_friction.f_max))
    for name, (lo, hi) in variables.items():
        if name not in ranges:
            raise ValueError(f"design: unknown variable {name!r} for the triple-fp isolator; "
                             f"accepted: {', '.join(TRIPLE_DESIGN_VARIABLES)}.")
        low, high = ranges[name]
        if name == "inner_f_max" and "outer_f_max" in variables:
            high = variables["outer_f_max"][0]  # the inner surfaces stay the slipperier
        if name == "outer_f_max":
            low = max(variables.get("inner_f_max", (0.0, 0.0))[1], low)
            high = m1 / float(np.asarray(triple.top_friction.f_max))  # top f_max <= 1
        if not (low <= lo and hi <= high):
            raise ValueError(
                f"{name}: bounds ({lo:.6g}, {hi:.6g}) leave the admissible ({low:.6g}, {high:.6g}) "
                "of this isolator (the outer radii above the inner one; inner f_max <= bottom "
                "f_max <= top f_max <= 1; positive capacities); narrow them.")


DOUBLE_DESIGN_VARIABLES = ("radius_scale", "surface_f_max", "capacity_scale")
"""Names a design dict of a `TripleIsolatedStructure` on a `DoublePendulum` may set:
`radius_scale` s [-] (R_1, R_2 -> s R_1, s R_2: every slope 1 / R_1, 1 / (R_1 + R_2),
1 / R_2 of the backbone falls by 1 / s), `surface_f_max` [-] (Eq. 1 of the bottom surface
scaled to this f_max, the top's by the same factor: their ratio, and so which surface slides
first, kept), `capacity_scale` [-] (d_1, d_2 times it). Fenz & Constantinou (2006), Earthquake
Engng Struct. Dyn. 35."""


def designed_double(double: DoublePendulum, design: Mapping) -> DoublePendulum:
    """`double` with the design variables of `design` applied (`DOUBLE_DESIGN_VARIABLES`;
    values may be traced). `ValueError` naming an unknown variable."""
    unknown = sorted(set(design) - set(DOUBLE_DESIGN_VARIABLES))
    if unknown:
        raise ValueError(f"design: unknown variable(s) {unknown} for the double-fp isolator; "
                         f"accepted: {', '.join(DOUBLE_DESIGN_VARIABLES)}.")
    s, k = design.get("radius_scale", 1.0), design.get("capacity_scale", 1.0)
    factor = design.get("surface_f_max", double.bottom_friction.f_max) / double.bottom_friction.f_max
    return with_fields(
        double, bottom_radius=s * double.bottom_radius, top_radius=s * double.top_radius,
        bottom_capacity=k * double.bottom_capacity, top_capacity=k * double.top_capacity,
        bottom_friction=_scaled(double.bottom_friction, factor),
        top_friction=_scaled(double.top_friction, factor))


FRICTION_FACTOR = "friction_factor"
"""The design variable of a bounding case on a triple or double pendulum (`designed_pendulum`):
the property modification factor lambda [-] on every surface's Eq. 1 friction coefficient,
f_max -> lambda f_max and delta_f -> lambda delta_f (`SeriesPendulum.scaled_friction`)."""


def designed_pendulum(pendulum, design: Mapping):
    """`designed_triple` or `designed_double` of `pendulum`, whichever its type, after
    `FRICTION_FACTOR` (if set) has scaled every surface's friction; with that variable alone
    the isolator keeps everything else, heating included."""
    rest = {k: v for k, v in design.items() if k != FRICTION_FACTOR}
    if FRICTION_FACTOR in design:
        pendulum = pendulum.scaled_friction(design[FRICTION_FACTOR])
    if not rest:
        return pendulum
    if isinstance(pendulum, DoublePendulum):
        return designed_double(pendulum, rest)
    return designed_triple(pendulum, rest)


def double_design_ranges(double: DoublePendulum) -> dict:
    """Admissible (low, high) of each design variable of `double`: positive scales, the bottom
    f_max such that the top's (scaled alike) stays at most 1."""
    m1, m2 = (float(np.asarray(f.f_max)) for f in (double.bottom_friction, double.top_friction))
    return {"radius_scale": (1e-6, math.inf), "surface_f_max": (1e-6, min(1.0, m1 / m2)),
            "capacity_scale": (1e-6, math.inf)}


def pendulum_design_ranges(pendulum) -> dict:
    """`triple_design_ranges` or `double_design_ranges` of `pendulum`, whichever its type."""
    if isinstance(pendulum, DoublePendulum):
        return double_design_ranges(pendulum)
    return triple_design_ranges(pendulum)


def check_double_box(double: DoublePendulum, variables: Mapping) -> None:
    """`ValueError` naming the variable whose bounds (low, high) leave what the double pendulum
    takes: positive radii and capacities, both f_max within (0, 1] (the top's is the bottom's
    times f_top / f_bottom)."""
    m1, m2 = (float(np.asarray(f.f_max)) for f in (double.bottom_friction, double.top_friction))
    ranges = double_design_ranges(double)
    for name, (lo, hi) in variables.items():
        if name not in ranges:
            raise ValueError(f"design: unknown variable {name!r} for the double-fp isolator; "
                             f"accepted: {', '.join(DOUBLE_DESIGN_VARIABLES)}.")
        low, high = ranges[name]
        if not (low <= lo and hi <= high):
            raise ValueError(
                f"{name}: bounds ({lo:.6g}, {hi:.6g}) leave the admissible ({low:.6g}, {high:.6g}) "
                "of this isolator (positive radii and capacities; the bottom f_max and the top's, "
                f"{m2 / m1:.4g} times it, within (0, 1]); narrow them.")


class DesignSpace(NamedTuple):
    """The design variables of one isolator, each function taking the isolated structure
    (`isolated_structure` of that isolator) whose isolator the design changes.

    **Fields:**

    - `variables`: the names a design dict may set, in the order a design keeps them.
    - `ranges(structure)`: {name: (low, high)} admissible for each variable taken alone [SI].
    - `check(structure, box)`: `ValueError` naming the variable when a box {name: (low, high)}
      leaves what the isolator takes (also at its corners, where variables bound each other).
    - `designed(structure, design)`: the isolator the design {name: value} gives (values may
      be traced): (bearing, T_b [s], zeta_b) of flat sliders, (bearing, `ConcaveSurface`,
      zeta_b) of a single pendulum, the `TriplePendulum` or `DoublePendulum` of a series one.
    """

    variables: tuple[str, ...]
    ranges: Callable
    check: Callable
    designed: Callable


_SURFACE = ("radius", "capacity")
"""The variables of a single pendulum's concave surface (`IsolatedStructure.designed_surface`)."""

_FLAT = tuple(n for n in DESIGN_VARIABLES if n not in _SURFACE)
_SINGLE = _SURFACE + tuple(n for n in _FLAT if n != "isolation_period")


def _sliders_space(variables: tuple[str, ...]) -> DesignSpace:
    """The `DesignSpace` of flat sliders or a single pendulum (`IsolatedStructure`)."""

    def ranges(structure) -> dict:
        admissible = design_ranges(structure)
        return {name: admissible[name] for name in variables}

    def check(structure, box: Mapping) -> None:
        _check_known(structure, box, variables)
        for name, (lo, hi) in box.items():
            check_design(structure, {name: np.array([lo, hi], dtype=float)})
        _check_f_min(structure, box)

    def designed(structure, design: Mapping):
        _check_known(structure, design, variables)
        bearing, period, damping = structure.isolation(design)
        return (bearing, period if structure.surface is None else structure.designed_surface(design), damping)

    return DesignSpace(variables, ranges, check, designed)


def _check_known(structure, names, variables) -> None:
    unknown = [name for name in names if name not in variables]
    if unknown:
        raise ValueError(f"design: unknown variable {unknown[0]!r} for the {structure.isolator} isolator; "
                         f"accepted: {', '.join(variables)}.")


def _check_f_min(structure, box: Mapping) -> None:
    """f_min = f_max - delta_f of Eq. 1 must stay >= 0 at the low end of f_max: delta_f the
    box's high end, or the bearing's (at each end of the box's pressure)."""
    if "f_max" not in box:
        return
    if "delta_f" in box:
        delta_f = float(box["delta_f"][1])
    else:
        corners = [{"pressure": p} for p in box["pressure"]] if "pressure" in box else [{}]
        delta_f = max(float(structure.isolation(c)[0].friction.delta_f) for c in corners)
    low = float(box["f_max"][0])
    if not low >= delta_f:
        raise ValueError(f"f_max: the low end {low:.6g} lies below delta_f = {delta_f:.4g} of the bearing "
                         f"(f_min = f_max - delta_f would be negative); raise it to at least {delta_f:.4g}.")


def _pendulum_space(variables, ranges, check, designed) -> DesignSpace:
    """The `DesignSpace` of a series pendulum (`TripleIsolatedStructure`), its functions taking
    the structure's `pendulum`."""
    return DesignSpace(variables, lambda structure: ranges(structure.pendulum),
                       lambda structure, box: check(structure.pendulum, box),
                       lambda structure, design: designed(structure.pendulum, design))


DESIGN_SPACES: Mapping[str, DesignSpace] = {
    "flat": _sliders_space(_FLAT),
    "single-fp": _sliders_space(_SINGLE),
    "triple-fp": _pendulum_space(TRIPLE_DESIGN_VARIABLES, triple_design_ranges, check_triple_box, designed_triple),
    "double-fp": _pendulum_space(DOUBLE_DESIGN_VARIABLES, double_design_ranges, check_double_box, designed_double),
}
"""The `DesignSpace` of each isolator (`teflon_jax.bearing.ISOLATORS`), keyed by its name."""


def design_space(isolator: str) -> DesignSpace:
    """The `DesignSpace` of `isolator` ("flat", "single-fp", "triple-fp", "double-fp");
    `ValueError` naming an unknown one."""
    if isolator not in DESIGN_SPACES:
        raise ValueError(f"isolator: unknown {isolator!r}; accepted: {', '.join(DESIGN_SPACES)}.")
    return DESIGN_SPACES[isolator]


def designed_isolator(structure, design: Mapping):
    """The isolator of `structure` (an `isolated_structure`) with the design {name: value}
    applied (`DesignSpace.designed` of its isolator); `ValueError` naming a variable its
    isolator does not take."""
    return design_space(structure.isolator).designed(structure, design)
