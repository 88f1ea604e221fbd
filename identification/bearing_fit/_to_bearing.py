"""What a fit found, as the one bearing model: parameter names -> the bearing's parts.

The fitter, the posterior and discovery name their constants as the engineer does (`f_max`,
`rate_a`, `yield_disp`, `heat_scale`, ...); `PARAMETER_FIELDS` says which constant of which
part of a `teflon_jax.bearing.SlidingBearing` (and of the bearing file) each name is.
"""

from teflon_jax.bearing import PARAMETER_BOUNDS, SlidingBearing

from ._record_force import bearing_of

PARAMETER_FIELDS = {name: b.field for name, b in PARAMETER_BOUNDS.items() if b.field is not None}
"""Parameter name -> (part, constant) of the bearing model and the bearing file (the `field`
column of `teflon_jax.bearing.PARAMETER_BOUNDS`)."""


def part_errors(std_errors: dict) -> dict:
    """Standard errors keyed by `(part, constant)` (names without a field are left out)."""
    return {PARAMETER_FIELDS[name]: value for name, value in std_errors.items()
            if name in PARAMETER_FIELDS and value is not None}


def fitted_bearing(fit, *, interfaces_in_series: int = 1) -> SlidingBearing:
    """The `SlidingBearing` of a least-squares `BearingFit` (breakaway only where fitted)."""
    return bearing_of(dict(fit.parameters), interfaces_in_series=interfaces_in_series)
