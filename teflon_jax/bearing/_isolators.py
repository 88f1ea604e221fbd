"""The isolator value every structure builder takes, and the class of each series pendulum.

The kinds of isolator, their names and descriptions, are listed once, in `teflon_jax.catalogue`
(`ISOLATORS`); a series pendulum's class reads its name and description from there and carries
the rest: the names of its sliders (the isolator file's surfaces) and its check.

A structure builder's one `isolator=` is a value, whose type says the isolator
(`isolator_kind`) and the engine that runs it (`runs_in_series`):

- `None`: flat sliders of Table 1's bearing (the builder's PTFE row at its pressure);
- a `SlidingBearing`: flat sliders of that bearing;
- a `ConcaveSurface`: single friction pendulums of Table 1's bearing on that surface;
  a (`SlidingBearing`, `ConcaveSurface`) pair: of that bearing;
- a `SinglePendulum` (one surface of sliders in series): flat sliders (R = inf) or the single
  friction pendulum of its surface's bearing;
- a `TriplePendulum` or `DoublePendulum`: the series pendulum.

One surface (static: a class with one slider) runs on the flat sliders' engine, the fastest for
it (benchmarks/one_surface_engine.py: the series engine is 2-6x slower there); S > 1 sliders on
the series engine.
"""

import math

from ..catalogue import FLAT, IN_SERIES, SINGLE_FP
from ..catalogue import ISOLATORS as ISOLATORS
from ._bearing import SlidingBearing
from ._pendulum import ConcaveSurface, concave_surface
from ._series_pendulum import (
    DoublePendulum,
    SeriesPendulum,
    SinglePendulum,
)
from ._triple_pendulum import TriplePendulum

_SERIES_CLASSES = {cls.isolator: cls for cls in (TriplePendulum, DoublePendulum)}
if set(_SERIES_CLASSES) != set(IN_SERIES):  # a kind added to the catalogue needs its class here
    raise ImportError(f"teflon_jax.catalogue lists the pendulums in series {IN_SERIES}, and the bearing package "
                      f"has classes for {tuple(_SERIES_CLASSES)}; give each kind in series its class.")

SERIES_PENDULUMS: dict[str, type[SeriesPendulum]] = {name: _SERIES_CLASSES[name] for name in IN_SERIES}
"""Name -> class of the friction pendulums of sliders in series (`teflon_jax.catalogue.IN_SERIES`,
in its order)."""

SERIES_CLASSES = (*SERIES_PENDULUMS.values(), SinglePendulum)
"""The classes of series pendulums, each with its own check (`SeriesPendulum.check`); the
one-surface `SinglePendulum` (a single pendulum, or a flat slider at R = inf) is an isolator
value too (`isolator_kind`), run on the flat sliders' engine (`one_surface`)."""

ISOLATOR_VALUES = ("None (Table 1's flat sliders), a SlidingBearing (flat sliders), a ConcaveSurface or "
                   "(SlidingBearing, ConcaveSurface) (single friction pendulum), a SinglePendulum, a "
                   "TriplePendulum or a DoublePendulum")
"""What `isolator=` takes, as errors say it."""


def check_series_pendulum(bearing: SeriesPendulum) -> None:
    """The check of `bearing`'s class (`SeriesPendulum.check`); `ValueError` for anything else."""
    if type(bearing) not in SERIES_CLASSES:
        raise ValueError(f"bearing: expected one of {', '.join(c.__name__ for c in SERIES_CLASSES)}, "
                         f"got {type(bearing).__name__}.")
    bearing.check()


def series_pendulum_class(isolator: str) -> type[SeriesPendulum]:
    """The class of the series pendulum named `isolator`; `ValueError` naming the accepted."""
    if isolator not in SERIES_PENDULUMS:
        raise ValueError(f"isolator: {isolator!r} is not a friction pendulum of sliders in series; "
                         f"accepted: {', '.join(SERIES_PENDULUMS)}.")
    return SERIES_PENDULUMS[isolator]


def _pair_kind(value) -> str | None:
    """"single-fp" for a (`SlidingBearing`, `ConcaveSurface`) pair, else None."""
    if isinstance(value, tuple) and len(value) == 2 and isinstance(value[0], SlidingBearing) \
            and isinstance(value[1], ConcaveSurface):
        return SINGLE_FP.name
    return None


def _single_kind(value: SinglePendulum) -> str:
    """"flat" for a `SinglePendulum` of infinite radius (a traced radius: "single-fp")."""
    try:
        return FLAT.name if math.isinf(float(value.surface_radius)) else SINGLE_FP.name
    except (TypeError, ValueError, ArithmeticError):  # traced or not a scalar: a pendulum
        return SINGLE_FP.name


_KINDS = {type(None): lambda value: FLAT.name, SlidingBearing: lambda value: FLAT.name,
          ConcaveSurface: lambda value: SINGLE_FP.name, tuple: _pair_kind, SinglePendulum: _single_kind,
          **{cls: lambda value: value.isolator for cls in SERIES_PENDULUMS.values()}}
"""Type of an isolator value -> its name (`ISOLATORS`)."""


def isolator_kind(value, where: str = "isolator") -> str:
    """The name (`ISOLATORS`) of the isolator value `value` (module docstring); `ValueError`
    naming `where` and what it takes for a value of any other type."""
    kind = _KINDS.get(type(value), lambda value: None)(value)
    if kind is None:
        raise ValueError(f"{where}: expected {ISOLATOR_VALUES}; got {_shown(value)}.")
    return kind


def _shown(value) -> str:
    if isinstance(value, tuple):
        return f"a tuple of ({', '.join(type(v).__name__ for v in value)})"
    return f"{value!r}" if isinstance(value, str) else f"a {type(value).__name__}"


def runs_in_series(value) -> bool:
    """Whether the isolator `value` runs on the series engine: its class has more than one
    slider (static). One surface runs on the flat sliders' engine (`one_surface`)."""
    isolator_kind(value)
    return isinstance(value, SeriesPendulum) and value.slider_count > 1


def one_surface(value, where: str = "isolator") -> tuple[SlidingBearing | None, ConcaveSurface | None]:
    """(bearing, surface) of the one-surface isolator `value` for the flat sliders' engine: the
    bearing `None` for Table 1's, the surface `None` for flat sliders. A `SinglePendulum` gives
    its surface's `SlidingBearing` back (the inverse of `single_pendulum`) on
    `concave_surface(R)` (flat at R = inf); `ValueError` naming `where` for one with a
    restrainer or a contact pressure (give (bearing, concave_surface(R, displacement_capacity=d,
    restrainer_stiffness=k)) and `pressure`) and for a series pendulum."""
    kind = isolator_kind(value, where)
    if isinstance(value, SinglePendulum):
        return _single_parts(value, kind, where)
    if runs_in_series(value):
        raise ValueError(f"{where}: a {type(value).__name__} has {value.slider_count} sliders in series; "
                         "it is not one surface.")
    if isinstance(value, tuple):
        return value
    return (value, None) if isinstance(value, SlidingBearing) or value is None else (None, value)


def _single_parts(value: SinglePendulum, kind: str, where: str):
    for name in ("surface_capacity", "surface_pressure"):
        if getattr(value, name) is not None:
            raise ValueError(f"{where}: the SinglePendulum's {name} has no place on the flat sliders' "
                             "engine; give (bearing, concave_surface(R, displacement_capacity=d, "
                             "restrainer_stiffness=k)) and the contact pressure as pressure.")
    part = {} if value.surface_parts is None else {
        name: getattr(value.surface_parts[0], name) for name in (
            "breakaway_ratio", "friction_perpendicular", "lay_angle", "pressure_dependence", "wear", "asymmetry")}
    bearing = SlidingBearing(friction=value.surface_friction, hysteresis=value.hysteresis,
                             heating=value.surface_heating, **part)
    return bearing, (None if kind == FLAT.name else concave_surface(value.surface_radius))
