"""The isolated structures of the studies (rigid mass, building) on triple or double friction
pendulums."""

from collections.abc import Mapping

import equinox as eqx
import jax

from ..bearing import SeriesPendulum, check_series_pendulum, designed_pendulum
from ..validation import concrete
from ._triple_biaxial import BiaxialStructureOnTriple
from ._triple_structure import (
    TRIPLE_NEWTON_ITERATIONS,
    TRIPLE_TOLERANCE,
    triple_structure,
)

TRIPLE_MONTE_CARLO_TOLERANCE = 1e-7
"""`TripleIsolatedStructure.newton_tolerance` of the Monte Carlo command: the sliders' force
imbalance over W (a displacement error below 1e-7 R_e of each slider)."""

class TripleIsolatedStructure(eqx.Module):
    """Builds the rigid mass or the Table 2 building on triple or double friction pendulums for
    one motion (`triple_structure`), called as `structure(ground_acceleration, design)` like
    `IsolatedStructure` (a `StructureOnTriple`), or as `structure((ground_x, ground_y))` for
    two components (a `BiaxialStructureOnTriple`, what `monte_carlo` builds for
    `TwoComponentGroundMotion`); `design` may set the variables of the pendulum's design space
    (`design_space("triple-fp")`: the outer radii's scale, the inner and outer f_max, the
    capacities' scale; `design_space("double-fp")`: the radii's scale, the surfaces' f_max, the
    capacities' scale), and on either `FRICTION_FACTOR` (every surface's friction times a
    bounding case's factor; `designed_pendulum`).

    **Fields:** `pendulum` (`TriplePendulum` or `DoublePendulum`; also read as `triple`),
    `kind` (static) "rigid" or "building", `time_step` [s] (static), `weight` [N] of the
    rigid mass (static), `newton_iterations`, `newton_tolerance` (static): `StructureOnTriple`'s.
    """

    pendulum: SeriesPendulum
    kind: str = eqx.field(static=True, default="rigid")
    time_step: float = eqx.field(static=True, default=0.005)
    weight: float = eqx.field(static=True, default=100e3)
    newton_iterations: int = eqx.field(static=True, default=TRIPLE_NEWTON_ITERATIONS)
    newton_tolerance: float = eqx.field(static=True, default=TRIPLE_TOLERANCE)

    @property
    def triple(self) -> SeriesPendulum:
        """The isolator (`pendulum`), under the name the triple pendulum gave it first."""
        return self.pendulum

    @property
    def isolator(self) -> str:
        """"triple-fp" or "double-fp"."""
        return self.pendulum.isolator

    @property
    def isolation_period(self):
        """None: the period of a multi-surface pendulum changes with its regime."""
        return None

    def __call__(self, ground_acceleration, design: Mapping | None = None):
        pendulum = self.pendulum
        if design:
            pendulum = designed_pendulum(pendulum, design)
        two = isinstance(ground_acceleration, tuple)  # (x, y): two components
        system = triple_structure(self.kind, pendulum, ground_acceleration[0] if two else ground_acceleration,
                                  time_step=self.time_step, weight=self.weight,
                                  newton_iterations=self.newton_iterations, newton_tolerance=self.newton_tolerance)
        return BiaxialStructureOnTriple(system, ground_acceleration[1]) if two else system


def triple_isolated_structure(kind: str, pendulum: SeriesPendulum, *, time_step: float,
                              newton_iterations: int, newton_tolerance: float | None,
                              conflicting: Mapping) -> TripleIsolatedStructure:
    """`isolated_structure(kind, isolator=pendulum)` of a `TriplePendulum` or `DoublePendulum`,
    checked: `ValueError` naming the constant the series model cannot take
    (`check_triple_pendulum`, `check_double_pendulum`), the time step, and each name in
    `conflicting` (inputs of the flat sliders given with the pendulum)."""
    if all(concrete(leaf) is not None for leaf in jax.tree_util.tree_leaves(pendulum)):
        check_series_pendulum(pendulum)  # traced constants (gradients): the caller's to check
    if isinstance(time_step, bool) or not isinstance(time_step, (int, float)) or not time_step > 0:
        raise ValueError(f"time_step: must be a positive number of seconds, got {time_step!r}.")
    for conflict, reason in conflicting.items():
        raise ValueError(f"{conflict}: does not apply to the {pendulum.isolator} isolator ({reason}).")
    tolerance = TRIPLE_TOLERANCE if newton_tolerance is None else float(newton_tolerance)
    return TripleIsolatedStructure(pendulum=pendulum, kind=kind, time_step=float(time_step),
                                   newton_iterations=int(newton_iterations), newton_tolerance=tolerance)
