"""One history driver for every structure: `simulate_history(system, duration)` runs a rigid
mass, a building or a slab on any isolator, under one or two ground components, from rest and
returns its `StructureResponse`."""

from ._bidirectional import BidirectionalStructure
from ._bidirectional_models import simulate_bidirectional
from ._response import StructureResponse
from ._series_step import simulate_on_series
from ._structure import StructureOnSliders
from ._structure_build import simulate_structure


def simulate_history(system, duration: float, **options) -> StructureResponse:
    """Integrate `system` from rest over `duration` [s] with its engine and return its
    `StructureResponse`: a `StructureOnSliders` on flat sliders or single pendulums
    (`simulate_structure`; `options` are its keywords) or on series pendulums in one or two
    components (their sliders balanced at each step, `_series_step.py`; no options), or a
    `BidirectionalStructure` on any isolator's groups (`simulate_bidirectional`)."""
    if isinstance(system, StructureOnSliders) and system.pendulum is not None:
        if options:
            raise ValueError(f"{', '.join(options)}: a structure on series pendulums steps at its time_step and "
                             "keeps every step; drop these options.")
        return simulate_on_series(system, duration)
    drivers = {StructureOnSliders: simulate_structure, BidirectionalStructure: simulate_bidirectional}
    for kind, driver in drivers.items():
        if isinstance(system, kind):
            return driver(system, duration, **options)
    raise TypeError(f"system: no history driver for a {type(system).__name__}; give a structure built by "
                    "teflon_jax.systems (rigid mass, building or slab on its isolators).")
