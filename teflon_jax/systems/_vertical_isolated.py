"""The isolated structures of the studies under horizontal and vertical ground motion."""

import equinox as eqx

from ._isolated import IsolatedStructure
from ._triple_isolated import TripleIsolatedStructure
from ._vertical_motion import with_vertical_motion


class VerticalIsolatedStructure(eqx.Module):
    """`structure` with the vertical ground acceleration on its isolators' normal load
    (`with_vertical_motion`; a single friction pendulum's W / R scales with it).

    `structure`: an `IsolatedStructure` (one horizontal component), a
    `BidirectionalIsolatedStructure` (two), or a `TripleIsolatedStructure` (triple or double
    pendulums, one or two). Call as `structure((horizontal, ground_vertical), design)` with
    `horizontal` what `structure` takes (a `Signal`, or the (x, y) pair of `Signal`s) and
    `ground_vertical` a `Signal` [m/s^2, up positive]; returns the structure's system with
    the vertical record.
    """

    structure: eqx.Module

    @property
    def uniaxial(self):
        """The one-direction `IsolatedStructure` inside (that of a bidirectional one), or the
        `TripleIsolatedStructure`."""
        return getattr(self.structure, "uniaxial", self.structure)

    @property
    def time_step(self) -> float:
        """The structure's step [s]."""
        return self.structure.time_step

    @property
    def kind(self) -> str:
        """"rigid" or "building"."""
        return self.uniaxial.kind

    def __call__(self, ground, design=None):
        horizontal, vertical = ground
        system = self.structure(horizontal, design)
        inner = self.uniaxial
        surface = None if isinstance(inner, TripleIsolatedStructure) else inner.surface
        radius = None if surface is None else inner.designed_surface(design).radius
        return with_vertical_motion(system, vertical, radius)


def with_vertical_component(structure) -> VerticalIsolatedStructure:
    """`structure` taking (horizontal, vertical) ground motions (`VerticalIsolatedStructure`):
    an `IsolatedStructure`, a `BidirectionalIsolatedStructure` (`bidirectional_isolated_structure`)
    or a `TripleIsolatedStructure` (`isolated_structure(kind, isolator="triple-fp", ...)`)."""
    inner = getattr(structure, "uniaxial", structure)
    if not isinstance(inner, (IsolatedStructure, TripleIsolatedStructure)):
        raise ValueError(f"structure: expected an IsolatedStructure, a BidirectionalIsolatedStructure or a "
                         f"TripleIsolatedStructure (isolated_structure(...)), got {type(structure).__name__}.")
    return VerticalIsolatedStructure(structure)
