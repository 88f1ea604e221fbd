"""The rigid mass and the building of the studies under two ground components, and their peaks.

`BidirectionalIsolatedStructure` is `IsolatedStructure` (Table 1 friction at a pressure,
springs and dampers of period T_b and ratio zeta_b, Eq. 17 breakaway) built as a
`BidirectionalStructure` (`bidirectional_rigid_mass`, `bidirectional_building`): one group
of isotropic bearings with Park's biaxial Z (Eqs. 8-9) and Eq. 1 at the resultant sliding
speed. Its peaks are `systems.peak_response`'s, as for every structure (resultants of the base
displacement and of the base shear ratio over every mass, the base's included).
Reference: Constantinou, Mokha & Reinhorn (1990), J. Struct. Eng. 116(2), Eqs. 1, 8-9, 17.
"""

import dataclasses
from collections.abc import Mapping

import equinox as eqx

from ..systems import (
    BIDIRECTIONAL_TIME_STEP,
    BidirectionalStructure,
    IsolatedStructure,
    TripleIsolatedStructure,
    bidirectional_building,
    bidirectional_rigid_mass,
    isolated_structure,
)


class BidirectionalIsolatedStructure(eqx.Module):
    """Builds the two-component rigid mass or building for one motion and one design.

    Call as `structure((ground_x, ground_y), design)` with two `Signal`s [m/s^2] and `design`
    a dict of some of the `IsolatedStructure` design variables. **Fields:** `uniaxial`, the
    `IsolatedStructure` whose kind, Table 1 row, pressure, springs, dampers, breakaway,
    weight and time step it takes; `newton_iterations` (static): the most Newton iterations of
    the bearing solve per step (`None`: `BidirectionalStructure`'s default).
    """

    uniaxial: IsolatedStructure
    newton_iterations: int | None = eqx.field(static=True, default=None)

    @property
    def time_step(self) -> float:
        """Step of the structure solver [s]."""
        return self.uniaxial.time_step

    def __call__(self, ground, design: Mapping | None = None) -> BidirectionalStructure:
        ground_x, ground_y = ground
        s = self.uniaxial
        bearing, period, damping = s.isolation(design)
        law = {"friction_model": s.friction_model,
               "surface": None if s.surface is None else s.designed_surface(design)}
        if s.kind == "rigid":
            system = bidirectional_rigid_mass(
                weight=s.weight, bearing=bearing, ground_x=ground_x, ground_y=ground_y,
                time_step=s.time_step, isolation_period=period,
                damping_ratio=damping if period is not None else 0.0,
                contact_pressure=s.contact_pressure(design), **law,
            )
        else:
            system = bidirectional_building(
                bearing=bearing, ground_x=ground_x, ground_y=ground_y, time_step=s.time_step,
                isolation_period=period, isolation_damping=damping,
                contact_pressure=s.contact_pressure(design), **law,
            )
        if self.newton_iterations is not None:
            system = dataclasses.replace(system, newton_iterations=self.newton_iterations)
        return system


def bidirectional_isolated_structure(kind: str = "rigid", **options) -> BidirectionalIsolatedStructure:
    """A `BidirectionalIsolatedStructure` with the inputs of `isolated_structure(kind,
    **options)` (checked there, `ValueError` naming the parameter), stepped at
    `BIDIRECTIONAL_TIME_STEP` unless `time_step` is given. The friction models of one
    component run in two (Park's Z, Coulomb, none), and so do a pendulum's restrainer and
    large-displacement form. On a triple or double friction pendulum the
    `TripleIsolatedStructure` of `isolated_structure`, which takes both components itself."""
    if isinstance(structure := isolated_structure(kind, **options), TripleIsolatedStructure):
        return structure  # the series engine builds both: called with (ground_x, ground_y)
    if options.get("time_step") is None:  # the uniaxial default steps are not the bidirectional one
        options = {**options, "time_step": BIDIRECTIONAL_TIME_STEP}
    newton_iterations = options.get("newton_iterations")
    return BidirectionalIsolatedStructure(isolated_structure(kind, **options), newton_iterations)
