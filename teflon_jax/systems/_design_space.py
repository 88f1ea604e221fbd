"""The design space of each isolator (`DESIGN_SPACES`): the variables a design dict may set on
an isolated structure of that isolator, their admissible ranges, the check of a box of
bounds, and the isolator a design gives. Every consumer (the design study, the command
line) looks the isolator up here (`design_space`, `designed_isolator`).

- "flat": sliders on springs (`IsolatedStructure`): the period T_b [s] of the springs, the
  contact pressure [Pa] (Table 1's Eq. 1 constants there), zeta_b [-] and Eq. 1 / Eq. 17
  constants overriding Table 1's (Constantinou, Mokha & Reinhorn 1990).
- "single-fp": a concave surface of radius R [m], T_b = 2 pi sqrt(R / g) (Zayas, Low &
  Mahin 1990), and its displacement capacity d [m] where a restrainer engages; the friction
  variables of the flat sliders.
- "triple-fp", "double-fp": a change of the isolator file's pendulum (`TriplePendulum`,
  `DoublePendulum`; Fenz & Constantinou 2006, 2008): the outer radii's scale, the inner and
  outer f_max, the capacities' scale; or both radii's scale, the surfaces' f_max, the
  capacities' scale (`designed_triple`, `designed_double`).
"""

from collections.abc import Callable, Mapping
from typing import NamedTuple

import numpy as np

from ._isolated import DESIGN_VARIABLES, check_design, design_ranges
from ._triple_design import (
    DOUBLE_DESIGN_VARIABLES,
    TRIPLE_DESIGN_VARIABLES,
    check_double_box,
    check_triple_box,
    designed_double,
    designed_triple,
    double_design_ranges,
    triple_design_ranges,
)


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
