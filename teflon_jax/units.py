"""Named unit constants (factors to SI) and the quantity parser used at the boundaries."""

from ._units import (
    CM as CM,
    FOOT as FOOT,
    INCH as INCH,
    KIP as KIP,
    KN as KN,
    KPA as KPA,
    KSI as KSI,
    LBF as LBF,
    MM as MM,
    MPA as MPA,
    PSI as PSI,
    STANDARD_GRAVITY as STANDARD_GRAVITY,
    UNITS as UNITS,
    parse_quantity as parse_quantity,
    unit_factor as unit_factor,
)
