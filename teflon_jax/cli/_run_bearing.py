"""The bearing `teflon-jax run` builds from its flags (a bearing file or a Table 1 row), and
the ratio flags it reads."""

import numpy as np

from ..units import parse_quantity
from ._common import check_table1


def fraction(text, flag):
    """A ratio typed as 5% or 0.05, in [0, 1); `ValueError` naming `flag`."""
    text = str(text).strip()
    try:
        value = float(text[:-1]) / 100 if text.endswith("%") else float(text)
    except ValueError:
        raise ValueError(f"{flag}: expected a ratio such as 5% or 0.05, got {text!r}.") from None
    if not 0 <= value < 1:
        raise ValueError(f"{flag}: must lie in [0, 100%), got {text!r}.")
    return value


def bearing_of_flags(args, from_file, ptfe, pressure_text, flag, friction_factor: float = 1.0):
    """The bearing of `run`'s flags: `from_file`, the bearing of `--bearing FILE` as read
    (`Isolator.bearing`), at the contact pressure `pressure_text` (its pressure dependence
    folded in), or (`from_file` None) Table 1's row of `ptfe` at that pressure, its f_max and
    delta_f times `friction_factor` (a bounding case of --property-factors), with the
    anisotropy, lay and breakaway flags; `ValueError` naming `flag`."""
    from ..bearing import paper_bearing
    from ..systems import check_structure_bearing
    from ..tables import interface_parameters

    pressure = parse_quantity(pressure_text, "pressure", where=flag)
    if from_file is not None:
        if not pressure > 0:
            raise ValueError(f"{flag}: must be > 0, got {pressure_text}.")
        if (pressure_text != args.pressure and from_file.pressure_dependence is None
                and from_file.heating is None):
            raise ValueError(f"{flag}: a group's pressure changes a bearing from --bearing "
                             "only through its pressure dependence or heating, and this one "
                             "has neither; leave the group's pressure out.")
        try:  # a pressure dependence is taken at the contact pressure of these bearings
            check_structure_bearing(from_file, pressure)
        except ValueError as error:
            raise ValueError(f"--bearing {args.bearing}: {error}") from None
        return from_file.at_contact_pressure(pressure)
    check_table1(ptfe, pressure, pressure_text, flag)
    try:
        params, table_b = interface_parameters(ptfe.upper(), pressure, "P")
        perpendicular = interface_parameters(ptfe.upper(), pressure, "T")[0] if args.anisotropic else None
    except ValueError as error:
        raise ValueError(f"{flag}: {error}") from None
    if friction_factor != 1.0:
        from ..studies import scaled_friction

        params = scaled_friction(params, friction_factor)
        perpendicular = None if perpendicular is None else scaled_friction(perpendicular, friction_factor)
    lay_angle = None
    if args.lay_angle is not None:
        if not args.anisotropic:
            raise ValueError("--lay-angle: the lay of the steel matters only for anisotropic bearings; "
                             "add --anisotropic (or leave --lay-angle out).")
        lay_angle = parse_quantity(args.lay_angle, "angle", where="--lay-angle")
        if not np.isfinite(lay_angle):
            raise ValueError(f"--lay-angle: must be finite, got {args.lay_angle}.")
    breakaway = None
    if args.breakaway == "table":
        breakaway = table_b
    elif args.breakaway is not None:
        try:
            breakaway = float(args.breakaway)
        except ValueError:
            raise ValueError(f"--breakaway: expected a number >= 1 or 'table', got {args.breakaway!r}.") from None
        if not breakaway >= 1:
            raise ValueError(f"--breakaway: must be >= 1 (Table 1: 1.3-4.4), got {args.breakaway}.")
    return paper_bearing(params, breakaway_ratio=breakaway, friction_perpendicular=perpendicular,
                         lay_angle=lay_angle)
