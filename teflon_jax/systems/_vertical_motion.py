"""The vertical ground acceleration on any structure the library steps: flat sliders and single
friction pendulums (`_vertical.py`), one or two horizontal directions, and the series pendulums
(triple, double) in one or two directions.

Every isolator takes the normal load N = W max(1 + a_v / g, 0) from the vertical record a_v
(up positive), the superstructure being rigid vertically; at N <= 0 it carries no shear.
Every isolator takes N at the end of each step (`_triple_structure.py` for the series pendulums).
Reference: Almazan, De la Llera & Inaudi (1998), Earthquake Eng. Struct. Dyn. 27(8), 845-867.
"""

import dataclasses

from ..excitation import Signal
from ._slab_series import SlabOnSeries
from ._structure_response import check_duration
from ._triple_biaxial import BiaxialStructureOnTriple
from ._triple_structure import StructureOnTriple
from ._vertical import uplift_steps
from ._vertical import with_vertical_motion as _on_sliders


def with_vertical_motion(system, vertical_acceleration: Signal, radius=None):
    """`system` with the vertical ground acceleration `vertical_acceleration` [m/s^2, up +] on
    its isolators' normal load N = W max(1 + a_v / g, 0).

    `system`: a `StructureOnSliders` or `BidirectionalStructure` (flat sliders, single friction
    pendulum; `radius` R [m] of a pendulum whose W / R the load scales, see `_vertical.py`), or
    a `StructureOnTriple` / `BiaxialStructureOnTriple` / `SlabOnSeries` (triple or double
    pendulums, whose radii are their surfaces': `radius` must be `None`); a slab on flat
    sliders or single pendulums is a `BidirectionalStructure`. `ValueError` naming the
    argument otherwise.
    """
    if not isinstance(system, (StructureOnTriple, BiaxialStructureOnTriple, SlabOnSeries)):
        return _on_sliders(system, vertical_acceleration, radius)
    if not isinstance(vertical_acceleration, Signal):
        raise ValueError("vertical_acceleration: expected a Signal of the vertical ground "
                         f"acceleration [m/s^2], got {type(vertical_acceleration).__name__}.")
    if radius is not None:
        raise ValueError("radius: a triple or double pendulum's radii are its surfaces' (its "
                         "SeriesPendulum); leave radius out.")
    if isinstance(system, BiaxialStructureOnTriple):
        uniaxial = dataclasses.replace(system.uniaxial, vertical_acceleration=vertical_acceleration)
        return dataclasses.replace(system, uniaxial=uniaxial)
    return dataclasses.replace(system, vertical_acceleration=vertical_acceleration)


def series_uplift_time(system: BiaxialStructureOnTriple, duration: float):
    """Time [s] of the steps 1..n (n = duration / dt, `check_duration`) whose end has N <= 0 in
    a two-direction series-pendulum structure, as `peak_response` counts it in one direction;
    `None` without a vertical record."""
    uniaxial = system.uniaxial
    if uniaxial.vertical_acceleration is None:
        return None
    n_steps = check_duration(uniaxial, duration)
    return uplift_steps(uniaxial, n_steps) * float(uniaxial.time_step)
