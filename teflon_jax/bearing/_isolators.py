"""The isolators teflon-jax runs, listed once.

Each isolator has a name (the command line's `--isolator`, the isolator file's `"isolator"`),
and a series pendulum its class, whose class attributes carry the rest: the names of its
sliders (the isolator file's surfaces), its description and its check. Every list of isolators
in the library, the file formats and the command line is read from here.
"""

from ._series_pendulum import (
    DoublePendulum,
    SeriesPendulum,
    SinglePendulum,
    check_double_pendulum,
    check_single_pendulum,
)
from ._triple_pendulum import TriplePendulum, check_triple_pendulum

SERIES_PENDULUMS: dict[str, type[SeriesPendulum]] = {cls.isolator: cls for cls in (TriplePendulum, DoublePendulum)}
"""Name -> class of the friction pendulums of sliders in series ("triple-fp", "double-fp")."""

ISOLATORS = ("flat", "single-fp", *SERIES_PENDULUMS)
"""Every isolator's name: flat sliders, the single friction pendulum (a `SlidingBearing` on a
`ConcaveSurface`) and the series pendulums."""

SERIES_CHECKS = {TriplePendulum: check_triple_pendulum, DoublePendulum: check_double_pendulum,
                 SinglePendulum: check_single_pendulum}
"""Class -> the check of its constants (`ValueError` naming the constant); the one-surface
`SinglePendulum` (a single pendulum, or a flat slider at R = inf) runs on the series engine
but is not yet an isolator of the command line, whose "flat" and "single-fp" are the
`SlidingBearing`'s."""


def check_series_pendulum(bearing: SeriesPendulum) -> None:
    """The check of `bearing`'s class (`SERIES_CHECKS`); `ValueError` for anything else."""
    if type(bearing) not in SERIES_CHECKS:
        raise ValueError(f"bearing: expected one of {', '.join(c.__name__ for c in SERIES_CHECKS)}, "
                         f"got {type(bearing).__name__}.")
    SERIES_CHECKS[type(bearing)](bearing)


def series_pendulum_class(isolator: str) -> type[SeriesPendulum]:
    """The class of the series pendulum named `isolator`; `ValueError` naming the accepted."""
    if isolator not in SERIES_PENDULUMS:
        raise ValueError(f"isolator: {isolator!r} is not a friction pendulum of sliders in series; "
                         f"accepted: {', '.join(SERIES_PENDULUMS)}.")
    return SERIES_PENDULUMS[isolator]
