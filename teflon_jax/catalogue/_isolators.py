"""The isolators teflon-jax runs, each listed once, with what the rest of the code says of it.

A kind's `name` is the command line's `--isolator` and the isolator file's `"isolator"`; the
bearing package gives each kind its value (`teflon_jax.bearing.isolator_kind`: flat sliders and
the single friction pendulum are a `SlidingBearing` with or without a `ConcaveSurface`, the
double and triple pendulums a class of sliders in series whose name and description are read
from here), its file reader and its design space; the command line builds its tables, one row
per kind, from the same list. Plain Python, so that `teflon-jax --help` reads it without JAX.

References: Zayas, Low & Mahin (1990), Earthquake Spectra 6(2) (the single friction
pendulum); Fenz & Constantinou (2006), Earthquake Engng Struct. Dyn. 35 (the double);
Fenz & Constantinou (2008), Earthquake Spectra 24(4) (the triple).
"""

from typing import NamedTuple


class IsolatorKind(NamedTuple):
    """One kind of isolator.

    - `name`: `--isolator` and the isolator file's `"isolator"`.
    - `description`: the isolator's bearings in the plural, as messages name them.
    - `sliders`: the sliders in series that a step balances (1: the flat sliders' engine).
    - `curved`: True for a concave surface (a period 2 pi sqrt(R / g) of its radius).
    - `file_example`: the example name of its isolator file (`--isolator-file`), `None` for a
      kind given by flags alone.
    - `model`: the model a simulated test record of it names, `None` for the paper's own.
    - `order_note`: what a fit of its loop cannot tell apart (`None`: nothing).
    """

    name: str
    description: str
    sliders: int
    curved: bool
    file_example: str | None = None
    model: str | None = None
    order_note: str | None = None

    @property
    def in_series(self) -> bool:
        """True for a pendulum of several sliders in series (given by its isolator file)."""
        return self.sliders > 1


FLAT = IsolatorKind("flat", "flat sliders", 1, False)
SINGLE_FP = IsolatorKind("single-fp", "single friction pendulums", 1, True)
TRIPLE_FP = IsolatorKind("triple-fp", "triple friction pendulums", 3, True, "tfp.json",
                         "series model of Fenz & Constantinou (2008)")
DOUBLE_FP = IsolatorKind("double-fp", "double friction pendulums", 2, True, "dfp.json",
                         "series model of Fenz & Constantinou (2006)",
                         "a loop cannot tell the bottom surface from the top one; they are reported in the "
                         "start file's order of f_max")

KINDS: dict[str, IsolatorKind] = {kind.name: kind for kind in (FLAT, SINGLE_FP, TRIPLE_FP, DOUBLE_FP)}
"""Every kind by its name, in the order the command line lists them."""

ISOLATORS = tuple(KINDS)
"""Every isolator's name: "flat", "single-fp", "triple-fp", "double-fp"."""

ONE_SURFACE = tuple(name for name, kind in KINDS.items() if not kind.in_series)
"""The isolators of one sliding surface: flat sliders and the single friction pendulum."""

IN_SERIES = tuple(name for name, kind in KINDS.items() if kind.in_series)
"""The pendulums of sliders in series, each given by its isolator file."""

