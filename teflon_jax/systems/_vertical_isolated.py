"""The isolated structures of the studies under a horizontal and a vertical ground motion."""

import equinox as eqx

from ._isolated import IsolatedStructure
from ._vertical import with_vertical_motion


class VerticalIsolatedStructure(eqx.Module):
    """`uniaxial` (an `IsolatedStructure`) with the vertical ground acceleration on its
    isolators' normal load (`with_vertical_motion`; a friction pendulum's W / R scales with it).

    Call as `structure((ground_horizontal, ground_vertical), design)` with two `Signal`s
    [m/s^2] (vertical up positive); returns a `StructureOnSliders`.
    """

    uniaxial: IsolatedStructure

    @property
    def time_step(self) -> float:
        """The structure's step [s] (`IsolatedStructure.time_step`)."""
        return self.uniaxial.time_step

    @property
    def kind(self) -> str:
        """"rigid" or "building"."""
        return self.uniaxial.kind

    def __call__(self, ground, design=None):
        horizontal, vertical = ground
        system = self.uniaxial(horizontal, design)
        surface = self.uniaxial.surface
        radius = None if surface is None else self.uniaxial.designed_surface(design).radius
        return with_vertical_motion(system, vertical, radius)


def with_vertical_component(structure: IsolatedStructure) -> VerticalIsolatedStructure:
    """`structure` taking (horizontal, vertical) ground motions (`VerticalIsolatedStructure`)."""
    if not isinstance(structure, IsolatedStructure):
        raise ValueError(f"structure: expected an IsolatedStructure (isolated_structure(...)), got "
                         f"{type(structure).__name__}.")
    return VerticalIsolatedStructure(structure)
