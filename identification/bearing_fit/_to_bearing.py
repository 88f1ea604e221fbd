"""What a fit found, as the one bearing model: parameter names -> the bearing's parts.

The fitter, the posterior and discovery name their constants as the engineer does (`f_max`,
`rate_a`, `yield_disp`, `heat_scale`, ...); `PARAMETER_FIELDS` says which constant of which
part of a `teflon_jax.bearing.SlidingBearing` (and of the bearing file) each name is.
"""

from teflon_jax.bearing import SlidingBearing

from ._record_force import bearing_of

PARAMETER_FIELDS = {
    "f_max": ("friction", "f_max"),
    "delta_f": ("friction", "delta_f"),
    "rate_a": ("friction", "rate_a"),
    "f_max_perpendicular": ("friction_perpendicular", "f_max"),
    "delta_f_perpendicular": ("friction_perpendicular", "delta_f"),
    "rate_a_perpendicular": ("friction_perpendicular", "rate_a"),
    "yield_disp": ("hysteresis", "yield_disp"),
    "breakaway_ratio": ("breakaway", "ratio"),
    "pressure_exponent": ("pressure_dependence", "exponent"),
    "heat_scale": ("heating", "heat_scale"),
    "wear_change": ("wear", "change"),
    "asymmetry": ("asymmetry", "asymmetry"),
    "backlash_gap": ("backlash", "gap"),
}
"""Parameter name -> (part, constant) of the bearing model and the bearing file."""


def part_errors(std_errors: dict) -> dict:
    """Standard errors keyed by `(part, constant)` (names without a field are left out)."""
    return {PARAMETER_FIELDS[name]: value for name, value in std_errors.items()
            if name in PARAMETER_FIELDS and value is not None}


def fitted_bearing(fit, *, interfaces_in_series: int = 1) -> SlidingBearing:
    """The `SlidingBearing` of a least-squares `BearingFit` (breakaway only where fitted)."""
    values = dict(fit.parameters)
    use_breakaway = values.get("breakaway_ratio") is not None
    return bearing_of(values, use_breakaway=use_breakaway,
                      interfaces_in_series=interfaces_in_series)
