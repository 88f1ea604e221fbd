"""One history driver for every structure: `simulate_history(system, duration)` runs a rigid
mass, a building or a slab on any isolator, under one or two ground components, from rest and
returns its `StructureResponse`."""

from ._bidirectional import BidirectionalStructure
from ._bidirectional_models import simulate_bidirectional
from ._response import StructureResponse
from ._structure import StructureOnSliders
from ._structure_build import simulate_structure
from ._triple_structure import StructureOnSeries, simulate_series


def simulate_history(system, duration: float, **options) -> StructureResponse:
    """Integrate `system` from rest over `duration` [s] with its engine and return its
    `StructureResponse`: a `StructureOnSliders` (`simulate_structure`; `options` are its
    keywords), a `BidirectionalStructure` on sliders or series pendulums
    (`simulate_bidirectional`) or a `StructureOnSeries` in one or two components
    (`simulate_series`)."""
    drivers = {StructureOnSliders: simulate_structure, BidirectionalStructure: simulate_bidirectional,
               StructureOnSeries: simulate_series}
    for kind, driver in drivers.items():
        if isinstance(system, kind):
            return driver(system, duration, **options)
    raise TypeError(f"system: no history driver for a {type(system).__name__}; give a structure built by "
                    "teflon_jax.systems (rigid mass, building or slab on its isolators).")
