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
- a series pendulum ("triple-fp", "double-fp"): the variables of its class
  (`SeriesPendulum.design_variables`, `designed`, `design_ranges`, `check_design_box`): for
  the `TriplePendulum` the outer radii's scale, the inner and the outer f_max and the
  capacities' scale (Fenz & Constantinou 2008), for the `DoublePendulum` both radii's scale,
  the surfaces' f_max and the capacities' scale (Fenz & Constantinou 2006). A pendulum added
  to `SERIES_PENDULUMS` brings its space with it.

Either series pendulum also takes `FRICTION_FACTOR` (a bounding case: every surface's Eq. 1
friction times a property modification factor; `designed_pendulum`).
"""

import math
from collections.abc import Callable, Mapping
from typing import NamedTuple

import numpy as np

from ..catalogue import KINDS, IsolatorKind
from ..units import PSI
from ..validation import concrete
from ._isolators import SERIES_PENDULUMS

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
        return structure.pendulum.design_ranges()
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


FRICTION_FACTOR = "friction_factor"
"""The design variable of a bounding case on a triple or double pendulum (`designed_pendulum`):
the property modification factor lambda [-] on every surface's Eq. 1 friction coefficient,
f_max -> lambda f_max and delta_f -> lambda delta_f (`SeriesPendulum.scaled_friction`)."""


def designed_pendulum(pendulum, design: Mapping):
    """`pendulum` (a series pendulum) with the design applied (`SeriesPendulum.designed`),
    after `FRICTION_FACTOR` (if set) has scaled every surface's friction; with that variable
    alone the isolator keeps everything else, heating included."""
    rest = {k: v for k, v in design.items() if k != FRICTION_FACTOR}
    if FRICTION_FACTOR in design:
        pendulum = pendulum.scaled_friction(design[FRICTION_FACTOR])
    return pendulum.designed(rest) if rest else pendulum


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


def _pendulum_space(variables) -> DesignSpace:
    """The `DesignSpace` of a series pendulum (`IsolatedStructure.pendulum`) of `variables`: its
    class's own (`SeriesPendulum.design_ranges`, `check_design_box`, `designed`), read from
    the structure's `pendulum`."""
    return DesignSpace(variables, lambda structure: structure.pendulum.design_ranges(),
                       lambda structure, box: structure.pendulum.check_design_box(box),
                       lambda structure, design: structure.pendulum.designed(design))


def _space_of(kind: IsolatorKind) -> DesignSpace:
    """The `DesignSpace` of `kind`: a series pendulum's from its class (`SERIES_PENDULUMS`), one
    surface's from the variables of `IsolatedStructure` (a curved one's with its radius)."""
    if kind.in_series:
        return _pendulum_space(SERIES_PENDULUMS[kind.name].design_variables)
    return _sliders_space(_SINGLE if kind.curved else _FLAT)


DESIGN_SPACES: Mapping[str, DesignSpace] = {name: _space_of(kind) for name, kind in KINDS.items()}
"""The `DesignSpace` of each isolator of the catalogue (`teflon_jax.catalogue.KINDS`), keyed by
its name."""


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
