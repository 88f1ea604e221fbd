"""The rigid mass and the building of the studies under two ground components.

`bidirectional_isolated_structure` is `isolated_structure` (Table 1 friction at a pressure,
springs and dampers of period T_b and ratio zeta_b, Eq. 17 breakaway) built for (ground_x,
ground_y): one `IsolatedStructure` whose `components` is 2, building a planar `StructureOnSliders`
(`rigid_mass`, `six_storey_building` with `components=2`): one group of isotropic bearings with
Park's biaxial Z (Eqs. 8-9) and Eq. 1 at the resultant sliding speed. Its peaks are
`systems.peak_response`'s, as for every structure. Reference: Constantinou, Mokha & Reinhorn
(1990), J. Struct. Eng. 116(2), Eqs. 1, 8-9, 17.
"""

import dataclasses

from ..systems import (
    BIDIRECTIONAL_TIME_STEP,
    PLANAR_NEWTON_ITERATIONS,
    IsolatedStructure,
    isolated_structure,
)


def bidirectional_isolated_structure(kind: str = "rigid", **options) -> IsolatedStructure:
    """`isolated_structure(kind, **options)` (checked there, `ValueError` naming the parameter)
    for two ground components (`IsolatedStructure.components` 2, called with (ground_x,
    ground_y)), stepped at `BIDIRECTIONAL_TIME_STEP` unless `time_step` is given, its planar
    solve bounded by `newton_iterations` (default the solve's own). The friction models of one
    component run in two (Park's Z, Coulomb, none), and so do a pendulum's restrainer and
    large-displacement form. On a triple or double friction pendulum the series engine's own
    step in two components, at the time step and balance of `isolated_structure`."""
    if (structure := isolated_structure(kind, **options)).pendulum is not None:
        return dataclasses.replace(structure, components=2)
    if options.get("time_step") is None:  # the uniaxial default steps are not the bidirectional one
        options = {**options, "time_step": BIDIRECTIONAL_TIME_STEP}
    newton_iterations = options.get("newton_iterations", PLANAR_NEWTON_ITERATIONS)
    return dataclasses.replace(isolated_structure(kind, **options), components=2,
                               newton_iterations=newton_iterations)
