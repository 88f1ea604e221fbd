"""The range of each bearing constant: where it is physical, and where a fit searches for it.

One table serves every consumer (the least-squares fitter, discovery, the posterior): each
derives its bounds from `PARAMETER_BOUNDS` rather than keeping its own.

- `physical` is the open interval outside which the model stops meaning anything (a
  negative friction coefficient, b < 1 in Eq. 17, a factor 1 + asymmetry Z that could turn
  negative). The fitter searches it (semi-infinite ranges through softplus bijections).
- `search` is a finite interval inside `physical` that holds every PTFE-steel interface of
  Table 1 of Constantinou, Mokha & Reinhorn (1990) with a wide margin; discovery searches it
  (its sigmoid bijections need finite ends) and the posterior's default priors span it where
  they do not scale with the record.
- `log_scale`: a positive constant spanning decades, searched uniformly in log x.

Reference: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 3, 17 and Table 1.
"""

import math
from typing import NamedTuple

from ..units import INCH


class ConstantBounds(NamedTuple):
    """Ranges of one bearing constant (SI units).

    - `physical`: `(lower, upper)` open interval of meaningful values; `-inf`/`inf` allowed.
    - `search`: `(lower, upper)` finite interval inside `physical` a bounded fit searches.
    - `log_scale`: searched uniformly in log x (then `0 < search[0]`).
    - `unit`: unit for reports.
    - `field`: `(part, constant)` of the bearing model and of the bearing file, or `None`
      for a constant that is a count (`n_interfaces`, a static integer of the bearing).
    """

    physical: tuple[float, float]
    search: tuple[float, float]
    log_scale: bool = False
    unit: str = "-"
    field: tuple[str, str] | None = None


_INF = math.inf

_F_MAX = ((0.0, _INF), (0.002, 0.5))
_DELTA_F = ((0.0, _INF), (0.0, 0.45))
_RATE_A = ((0.0, _INF), (0.005 / INCH, 50.0 / INCH))

PARAMETER_BOUNDS: dict[str, ConstantBounds] = {
    "f_max": ConstantBounds(*_F_MAX, field=("friction", "f_max")),
    "delta_f": ConstantBounds(*_DELTA_F, field=("friction", "delta_f")),
    "rate_a": ConstantBounds(*_RATE_A, log_scale=True, unit="s/m",
                             field=("friction", "rate_a")),
    "f_max_perpendicular": ConstantBounds(*_F_MAX, field=("friction_perpendicular", "f_max")),
    "delta_f_perpendicular": ConstantBounds(*_DELTA_F,
                                            field=("friction_perpendicular", "delta_f")),
    "rate_a_perpendicular": ConstantBounds(*_RATE_A, log_scale=True, unit="s/m",
                                           field=("friction_perpendicular", "rate_a")),
    "yield_disp": ConstantBounds((0.0, _INF), (0.0002 * INCH, 0.2 * INCH), log_scale=True,
                                 unit="m", field=("hysteresis", "yield_disp")),
    "breakaway_ratio": ConstantBounds((1.0, _INF), (1.0, 8.0), field=("breakaway", "ratio")),
    "pressure_exponent": ConstantBounds((-_INF, _INF), (-1.0, 2.0),
                                        field=("pressure_dependence", "exponent")),
    "heat_scale": ConstantBounds((0.0, _INF), (0.0, 20.0), field=("heating", "heat_scale")),
    "asymmetry": ConstantBounds((-1.0, 1.0), (-0.6, 0.6), field=("asymmetry", "asymmetry")),
    "wear_change": ConstantBounds((-1.0, _INF), (-0.8, 3.0), field=("wear", "change")),
    "n_interfaces": ConstantBounds((1.0, _INF), (1.0, 60.0), log_scale=True),
    "backlash_gap": ConstantBounds((0.0, _INF), (1e-6, 0.1), log_scale=True, unit="m",
                                   field=("backlash", "gap")),
}
"""Bearing constant name -> its `ConstantBounds`: friction of Eq. 1 (parallel and perpendicular
to the lay), Y of Eq. 3, b of Eq. 17 and the constants of the optional parts."""
