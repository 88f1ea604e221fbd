"""Design variables of a triple friction pendulum (`TriplePendulum`) and of a double one
(`DoublePendulum`, `DOUBLE_DESIGN_VARIABLES`), each a smooth change of the isolator file's
bearing: the "triple-fp" and "double-fp" entries of the design spaces (`DESIGN_SPACES`, read
through `design_space` and `designed_isolator`). The triple's:

- `outer_radius_scale` s [-]: the outer surfaces' effective radii b, c -> s b, s c (the
  stiffness of regimes II-IV, 1 / (a + b), 1 / (b + c), 1 / (a + c), falls as s grows);
- `inner_f_max` [-]: Eq. 1 of the inner surfaces scaled so that their f_max is this value
  (delta_f in proportion: mu(v) -> (f / f_max) mu(v), f_min >= 0 kept);
- `outer_f_max` [-]: Eq. 1 of the bottom surface scaled to this f_max, the top's by the same
  factor (their ratio, which orders regimes II and III, kept);
- `capacity_scale` [-]: the three effective displacement capacities times this factor.

Either isolator also takes `FRICTION_FACTOR` (a bounding case: every surface's Eq. 1 friction
times a property modification factor).

The series model needs a < s min(b, c) and inner f_max <= bottom f_max <= top f_max
(`check_triple_pendulum`); `check_triple_box` refuses ranges that leave them.
References: Fenz & Constantinou (2008), Earthquake Spectra 24(4); Constantinou, Mokha &
Reinhorn (1990), Eq. 1.
"""

import math
from collections.abc import Mapping

import equinox as eqx
import numpy as np

from ..bearing import DoublePendulum, FrictionParameters, TriplePendulum

TRIPLE_DESIGN_VARIABLES = ("outer_radius_scale", "inner_f_max", "outer_f_max", "capacity_scale")
"""Names a design dict of a `TripleIsolatedStructure` may set (module docstring)."""


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
