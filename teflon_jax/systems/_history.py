"""One history driver for every structure: `simulate_history(system, duration)` runs a rigid
mass, a building or a slab on any isolator, under one or two ground components, from rest and
returns its `StructureResponse`."""

import jax

from ._bidirectional import BidirectionalStructure
from ._bidirectional_models import simulate_bidirectional
from ._response import StructureResponse
from ._slab_series import SlabOnSeries
from ._slab_series_build import simulate_slab_series
from ._structure import StructureOnSliders
from ._structure_build import simulate_structure
from ._triple_biaxial import BiaxialStructureOnTriple, biaxial_histories
from ._triple_structure import StructureOnTriple, simulate_triple_structure


def biaxial_response(system: BiaxialStructureOnTriple, duration: float) -> StructureResponse:
    """The histories of series pendulums under two ground components (`biaxial_histories`) as
    a `StructureResponse`: coordinates (nt, 2n), the x block then the y block; `bearing_force`
    (nt, 2) [N]; `slider` (nt, S, 2) [m]; `converged` (nt,). jit/vmap-safe."""
    time, x, force, slider, acceleration, converged = biaxial_histories(system, duration)
    n = system.mass.shape[-1]
    nt = time.shape[0]
    return StructureResponse(
        time=time, displacement=x[:, :, :n].reshape(nt, 2 * n), velocity=x[:, :, n:].reshape(nt, 2 * n),
        total_acceleration=acceleration.reshape(nt, 2 * n), ground=jax.vmap(system.ground)(time),
        bearing_force=force, slider=slider, converged=converged)


def simulate_history(system, duration: float, **options) -> StructureResponse:
    """Integrate `system` from rest over `duration` [s] with its engine and return its
    `StructureResponse`: a `StructureOnSliders` (`simulate_structure`; `options` are its
    keywords), a `BidirectionalStructure` (`simulate_bidirectional`), a `StructureOnTriple`
    (`simulate_triple_structure`), a `BiaxialStructureOnTriple` (`biaxial_response`) or a
    `SlabOnSeries` (`simulate_slab_series`)."""
    drivers = {StructureOnSliders: simulate_structure, BidirectionalStructure: simulate_bidirectional,
               StructureOnTriple: simulate_triple_structure, BiaxialStructureOnTriple: biaxial_response,
               SlabOnSeries: simulate_slab_series}
    for kind, driver in drivers.items():
        if isinstance(system, kind):
            return driver(system, duration, **options)
    raise TypeError(f"system: no history driver for a {type(system).__name__}; give a structure built by "
                    "teflon_jax.systems (rigid mass, building or slab on its isolators).")
