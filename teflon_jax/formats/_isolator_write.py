"""Writing the isolator file (`_isolator_file.py`'s format, version 1) of a triple or double
friction pendulum, in SI: what `load_isolator` reads back to the same bearing."""

import json
import pathlib

import numpy as np

from ..bearing import SeriesPendulum, check_series_pendulum
from ._isolator_file import FORMAT_NAME, FORMAT_VERSION, ISOLATOR_SURFACES
from ._isolator_posterior import IsolatorPosterior, isolator_posterior_to_dict

_FRICTION_UNITS = {"f_max": "1", "delta_f": "1", "rate_a": "s/m"}
_HEATING_UNITS = {"contact_area": "m^2", "heat_scale": "1", "conductivity": "W/(m K)",
                  "diffusivity": "m^2/s", "initial_temperature": "degC"}


def _entry(value, unit: str) -> dict:
    return {"value": float(np.asarray(value)), "unit": unit}


def isolator_to_dict(bearing: SeriesPendulum) -> dict:
    """The isolator-file object of `bearing`, a `TriplePendulum` or `DoublePendulum` (SI
    units: m, 1, s/m; a heated surface's `heating` in m^2, W/(m K), m^2/s, degC, Pa; a
    surface's other parts in 1, s/m, rad, m, N, m^2, Pa); `ValueError` for another type, or for
    one the series model cannot take
    (`check_series_pendulum`)."""
    check_series_pendulum(bearing)
    surfaces = {}
    for name, part in zip(ISOLATOR_SURFACES[bearing.isolator], bearing.parts()):
        friction = getattr(bearing, f"{name}_friction")
        surfaces[name] = {
            "radius": _entry(getattr(bearing, f"{name}_radius"), "m"),
            "capacity": _entry(getattr(bearing, f"{name}_capacity"), "m"),
            "friction": {k: _entry(getattr(friction, k), unit) for k, unit in _FRICTION_UNITS.items()},
        }
        heating = getattr(bearing, f"{name}_heating")
        if heating is not None:
            surfaces[name]["heating"] = {
                **{k: _entry(getattr(heating, k), unit) for k, unit in _HEATING_UNITS.items()},
                "contact_pressure": _entry(getattr(bearing, f"{name}_pressure"), "Pa")}
        surfaces[name].update(_parts_entries(part, getattr(bearing, f"{name}_pressure", None)))
    return {"format": FORMAT_NAME, "format_version": FORMAT_VERSION, "isolator": bearing.isolator,
            "surfaces": surfaces, "yield_disp": _entry(bearing.hysteresis.yield_disp, "m")}


def _parts_entries(part, pressure) -> dict:
    """The isolator-file entries of a surface's `SurfaceParts` (none for `None`), in SI."""
    if part is None:
        return {}
    entries = {}
    if part.breakaway_ratio is not None:
        entries["breakaway"] = {"ratio": _entry(part.breakaway_ratio, "1")}
    if part.friction_perpendicular is not None:
        entries["friction_perpendicular"] = {k: _entry(getattr(part.friction_perpendicular, k), unit)
                                             for k, unit in _FRICTION_UNITS.items()}
    if part.lay_angle is not None:
        entries["lay"] = {"angle": _entry(part.lay_angle, "rad")}
    if part.wear is not None:
        entries["wear"] = {"change": _entry(part.wear.change, "1"),
                           "reference_travel": _entry(part.wear.reference_travel, "m")}
    if part.asymmetry is not None:
        entries["asymmetry"] = {"asymmetry": _entry(part.asymmetry.asymmetry, "1")}
    if part.pressure_dependence is not None:
        p = part.pressure_dependence
        entries["pressure_dependence"] = {"exponent": _entry(p.exponent, "1"),
                                          "reference_load": _entry(p.reference_load, "N"),
                                          "contact_area": _entry(p.contact_area, "m^2"),
                                          "contact_pressure": _entry(pressure, "Pa")}
    return entries


def write_isolator(path, bearing: SeriesPendulum, *, posterior: IsolatorPosterior | None = None) -> None:
    """Write `bearing` as an isolator file (JSON, `isolator_to_dict`) at `path`, with the draws
    of `posterior` (checked in `bearing`) where given."""
    document = isolator_to_dict(bearing)
    if posterior is not None:
        posterior.check_draws(bearing)
        document["posterior"] = isolator_posterior_to_dict(posterior)
    pathlib.Path(path).write_text(json.dumps(document, indent=2) + "\n")
