"""A structure built once and run under each motion of a study: any structure of
`teflon_jax.systems` (the slab or the building on a plan of bearing groups, a structure on
series pendulums, ...) as the `structure` callable of `monte_carlo`."""

import equinox as eqx

from ..bearing import FRICTION_FACTOR, SeriesPendulum
from ..systems import under_ground
from ._bounding import with_friction_factors


class BuiltStructure(eqx.Module):
    """`system` under each motion of a study (`monte_carlo`, `monte_carlo_distributed`): called
    with a motion's ground `Signal`s [m/s^2] (one, `(ground_x, ground_y)` for a structure that
    steps under two components, and `(horizontal, ground_z)` with a vertical record), it returns
    `system` under them (`systems.under_ground`); the structure itself is not rebuilt, so of the
    design variables it takes only a bounding case's property modification factor
    (`FRICTION_FACTOR`: f_max and delta_f of Eq. 1 times it on every group's bearings, or on every
    surface of its series pendulums; `bounding_design`). A structure with a vertical record (`with_vertical_motion`,
    any record: each motion's replaces it) takes motions with a vertical component."""

    system: eqx.Module
    group_names: tuple = eqx.field(static=True, default=())

    @property
    def vertical(self) -> bool:
        """Whether the structure takes a vertical component (it has a vertical record)."""
        return self.system.vertical_acceleration is not None

    @property
    def time_step(self) -> float:
        """The structure's solver step [s]."""
        return self.system.time_step

    @property
    def pendulum(self):
        """The structure's series pendulums, or `None` (how a study compiles its runs)."""
        return self.system.pendulum

    def __call__(self, ground, design=None):
        horizontal, vertical = ground if self.vertical else (ground, None)
        components = horizontal if isinstance(horizontal, tuple) else (horizontal,)
        system = self.system if design is None else self.with_friction_factor(design)
        return under_ground(system, *components, ground_z=vertical)

    def with_friction_factor(self, design):
        """`system` with its friction times `design[FRICTION_FACTOR]` (may be traced);
        `ValueError` naming any other design variable."""
        unknown = sorted(set(design) - {FRICTION_FACTOR})
        if unknown:
            raise ValueError(f"design: a BuiltStructure is built once and takes no design variables but "
                             f"{FRICTION_FACTOR!r} (a bounding case), got {unknown}; build one per design, or use "
                             "isolated_structure(...) for design studies.")
        factor = design[FRICTION_FACTOR]
        if isinstance(self.system.bearing, SeriesPendulum):
            return eqx.tree_at(lambda s: s.bearing, self.system, self.system.bearing.scaled_friction(factor))
        return with_friction_factors(self.system, {"f_max": factor, "delta_f": factor})
