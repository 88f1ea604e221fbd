"""The isolator file: the geometry and friction of a triple or double friction pendulum, in
any units.

A JSON object (format version 1):

    {"format": "teflon-jax isolator", "format_version": 1, "isolator": "triple-fp",
     "surfaces": {
        "inner":  {"radius": {"value": 16, "unit": "in"}, "capacity": {"value": 2, "unit": "in"},
                   "friction": {"f_max": {"value": 0.02, "unit": "1"},
                                "delta_f": {"value": 0.0, "unit": "1"},
                                "rate_a": {"value": 0.0, "unit": "s/in"}}},
        "bottom": {...}, "top": {...}},
     "yield_disp": {"value": 0.005, "unit": "in"}}

`inner` holds surfaces 2 and 3 (alike), `bottom` surface 1 and `top` surface 4; `radius`
is the effective radius R - h and `capacity` the effective displacement capacity d (R - h) / R
of each surface. A double friction pendulum is `"isolator": "double-fp"` with the surfaces
`bottom` and `top` alone, in the same form. Every value carries its unit; nothing is defaulted.

A surface may add `"heating"`: its frictional heating (`FrictionalHeating`, the bearing file's
`heating` constants) and the contact pressure on it under the static load,

    "heating": {"contact_area": {"value": 0.05, "unit": "m^2"},
                "contact_pressure": {"value": 30, "unit": "MPa"},
                "heat_scale": {"value": 1, "unit": "1"},
                "conductivity": {"value": 16.2, "unit": "W/(m K)"},
                "diffusivity": {"value": 4.4, "unit": "mm^2/s"},
                "initial_temperature": {"value": 20, "unit": "degC"}}

(all six required); the one-direction structures and the bearing test run it.

A surface may also carry the other parts of the flat bearing's law (`SurfaceParts`), each an
object of the bearing file's constants under the bearing file's name: `"breakaway"`
({"ratio"}), `"friction_perpendicular"` (Eq. 1 across the lay) with an optional `"lay"`
({"angle"}), `"wear"` ({"change", "reference_travel"}), `"asymmetry"` ({"asymmetry"}) and
`"pressure_dependence"` ({"exponent", "reference_load", "contact_area", "contact_pressure"}:
the tested bearing's constants and the surface's contact pressure under the static load, which
must equal its heating's where both are given). `"stack"`, `"backlash"` and a surface's own
`"hysteresis"` are the whole bearing's, not a surface's, and are refused.

An optional top-level `"posterior"` holds the draws of a Bayesian fit of the surfaces'
friction (`_isolator_posterior.py`).
"""


import difflib
import re
import typing

import jax.numpy as jnp

from ..bearing import (
    SERIES_PENDULUMS,
    BoucWen,
    DirectionAsymmetry,
    FrictionalHeating,
    FrictionParameters,
    PressureDependence,
    SeriesPendulum,
    SurfaceParts,
    TriplePendulum,
    Wear,
    check_series_pendulum,
    check_surface_parts,
)
from ._bearing_file import BEARING_PARTS, read_constant
from ._isolator_posterior import IsolatorPosterior, isolator_posterior_from_dict
from ._text import read_json_document

FORMAT_NAME = "teflon-jax isolator"
FORMAT_VERSION = 1
SURFACES = TriplePendulum.slider_names
"""The surface groups of a triple-fp file: inner (2 and 3), bottom (1), top (4)."""

ISOLATOR_SURFACES = {name: cls.slider_names for name, cls in SERIES_PENDULUMS.items()}
"""The surface groups of each isolator of the file: its sliders (`SERIES_PENDULUMS`)."""

MAX_SURFACE_FRICTION = 1.0
"""The largest `f_max` [-] of a surface in an isolator file: a friction coefficient above 1 (a
friction force above the normal load) is outside the range of sliding bearings, whose
surfaces have 0.01 to about 0.2."""

_SURFACE = {"radius": "length", "capacity": "length"}
_FRICTION = BEARING_PARTS["friction"]  # Eq. 1's constants, as in the bearing file
HEATING_CONSTANTS = {**BEARING_PARTS["heating"], "contact_pressure": "pressure"}
"""Constants of a surface's optional `heating` entry -> kind of quantity."""

SURFACE_PART_CONSTANTS = {
    "breakaway": BEARING_PARTS["breakaway"],
    "friction_perpendicular": BEARING_PARTS["friction_perpendicular"],
    "lay": BEARING_PARTS["lay"],
    "wear": BEARING_PARTS["wear"],
    "asymmetry": BEARING_PARTS["asymmetry"],
    "pressure_dependence": {**BEARING_PARTS["pressure_dependence"], "contact_pressure": "pressure"},
}
"""A surface's optional parts beyond Eq. 1 and heating -> constant -> kind of quantity."""

WHOLE_BEARING_PARTS = {"stack": "interfaces in series", "backlash": "a gap in series with the bearing",
                       "hysteresis": "the Bouc-Wen constants (the file's yield_disp)"}
"""Parts of the bearing file that belong to the whole isolator, not one surface."""


def _value(entry, kind, where) -> float:
    """SI value of one `{"value": ..., "unit": ...}` entry (read as the bearing file reads its
    constants); an isolator file states no standard errors."""
    value, error = read_constant(entry, kind, where)
    if error is not None:
        raise ValueError(f"{where}: an isolator file states no standard_error; leave it out.")
    return value


def _keys(part, expected, where, optional=()):
    """`ValueError` naming `where` where the object `part` lacks one of `expected` or has a key
    that is neither expected nor `optional`: the keys it takes, and for a misspelt one the
    key it is closest to."""
    if not isinstance(part, dict):
        raise ValueError(f"{where}: must be an object with {', '.join(expected)}.")
    missing = [key for key in expected if key not in part]
    unknown = [key for key in part if key not in expected and key not in optional]
    if missing or unknown:
        guesses = [f"'{key}' is not '{close[0]}'" for key in unknown
                   for close in [difflib.get_close_matches(str(key), [*expected, *optional], n=1)] if close]
        also = f"; optional {', '.join(optional)}" if optional else ""
        raise ValueError(f"{where}: " + "; ".join(
            text for text in (f"missing {missing}" if missing else "",
                              f"unknown {unknown}" if unknown else "") if text)
            + f" (expected {', '.join(expected)}{also}; nothing is defaulted)"
            + (f"; check the spelling: {', '.join(guesses)}." if guesses else "."))


def _surface(part, where):
    for name, what in WHOLE_BEARING_PARTS.items():
        if isinstance(part, dict) and name in part:
            raise ValueError(f"{where}.{name}: {what} belongs to the whole bearing, not one surface of a "
                             f"friction pendulum; leave it out (a surface takes heating, "
                             f"{', '.join(SURFACE_PART_CONSTANTS)}).")
    _keys(part, ("radius", "capacity", "friction"), where, optional=("heating", *SURFACE_PART_CONSTANTS))
    values = {key: _value(part[key], kind, f"{where}.{key}") for key, kind in _SURFACE.items()}
    _keys(part["friction"], tuple(_FRICTION), f"{where}.friction")
    friction = FrictionParameters(*(jnp.asarray(_value(part["friction"][key], kind,
                                                       f"{where}.friction.{key}"))
                                    for key, kind in _FRICTION.items()))
    if not float(friction.f_max) <= MAX_SURFACE_FRICTION:
        raise ValueError(f"{where}.friction.f_max: must be in (0, {MAX_SURFACE_FRICTION:g}] (a friction "
                         f"coefficient; sliding surfaces have 0.01 to about 0.2), got {float(friction.f_max):g}.")
    heating = pressure = None
    if "heating" in part:
        _keys(part["heating"], tuple(HEATING_CONSTANTS), f"{where}.heating")
        heat = {key: _value(part["heating"][key], kind, f"{where}.heating.{key}")
                for key, kind in HEATING_CONSTANTS.items()}
        pressure = heat.pop("contact_pressure")
        heating = FrictionalHeating(**heat)
    surface_parts, pressure = _surface_parts(part, where, pressure)
    return values["radius"], values["capacity"], friction, heating, pressure, surface_parts


def _surface_parts(part, where, pressure):
    """(`SurfaceParts` of the surface's optional parts, or `None`; the surface's contact
    pressure [Pa], from its heating or its pressure dependence)."""
    read = {}
    for name, constants in SURFACE_PART_CONSTANTS.items():
        if name in part:
            _keys(part[name], tuple(constants), f"{where}.{name}")
            read[name] = {key: _value(part[name][key], kind, f"{where}.{name}.{key}")
                          for key, kind in constants.items()}
    if not read:
        return None, pressure
    if "pressure_dependence" in read:
        given = read["pressure_dependence"].pop("contact_pressure")
        if pressure is not None and given != pressure:
            raise ValueError(f"{where}.pressure_dependence.contact_pressure: {given:g} Pa differs from "
                             f"heating.contact_pressure ({pressure:g} Pa); the surface has one contact pressure.")
        pressure = given
    if "lay" in read and "friction_perpendicular" not in read:
        raise ValueError(f"{where}.lay: the lay of the steel matters only for an anisotropic surface; "
                         "add friction_perpendicular (or leave lay out).")
    perpendicular = read.get("friction_perpendicular")
    parts = SurfaceParts(
        breakaway_ratio=None if "breakaway" not in read else jnp.asarray(read["breakaway"]["ratio"]),
        friction_perpendicular=None if perpendicular is None else FrictionParameters(
            *(jnp.asarray(perpendicular[key]) for key in _FRICTION)),
        lay_angle=None if "lay" not in read else jnp.asarray(read["lay"]["angle"]),
        pressure_dependence=None if "pressure_dependence" not in read else PressureDependence(
            **read["pressure_dependence"]),
        wear=None if "wear" not in read else Wear(**read["wear"]),
        asymmetry=None if "asymmetry" not in read else DirectionAsymmetry(read["asymmetry"]["asymmetry"]),
    )
    try:
        check_surface_parts(parts, where, pressure)
    except ValueError as error:  # the file's keys for the two constants named otherwise in Python
        raise ValueError(str(error).replace(".breakaway_ratio", ".breakaway.ratio")
                         .replace(".lay_angle", ".lay.angle")) from None
    return parts, pressure


def _heating_fields(parts) -> dict:
    """`<surface>_heating` and `<surface>_pressure` of the surfaces that have heating or a
    contact pressure, and `surface_parts` where a surface has a part beyond them."""
    fields = {}
    for name, part in parts.items():
        if part[3] is not None:
            fields[f"{name}_heating"] = part[3]
        if part[4] is not None:
            fields[f"{name}_pressure"] = part[4]
    if any(part[5] is not None for part in parts.values()):
        fields["surface_parts"] = tuple(part[5] for part in parts.values())
    return fields


def isolator_from_dict(document, *, where: str = "isolator") -> SeriesPendulum:
    """The `TriplePendulum` or `DoublePendulum` of an isolator-file object (module docstring);
    `ValueError` naming `where` and the key for anything missing, unknown, unitless or that
    the series model cannot take (`check_series_pendulum`): the class of its "isolator"
    (`SERIES_PENDULUMS`) of its surfaces' fields."""
    if not isinstance(document, dict):
        raise ValueError(f"{where}: an isolator file is a JSON object; see the format in the manual.")
    if document.get("format") != FORMAT_NAME:
        raise ValueError(f"{where}: 'format' must be \"{FORMAT_NAME}\".")
    version = document.get("format_version")
    if not isinstance(version, int) or isinstance(version, bool) or version > FORMAT_VERSION:
        raise ValueError(f"{where}: 'format_version' must be an integer up to {FORMAT_VERSION}, "
                         f"got {version!r}.")
    _keys(document, ("format", "format_version", "isolator", "surfaces", "yield_disp"), where,
          optional=("posterior",))
    isolator = document["isolator"]
    _check_isolator(isolator, document["surfaces"], where)
    _keys(document["surfaces"], ISOLATOR_SURFACES[isolator], f"{where}: surfaces")
    parts = {name: _surface(document["surfaces"][name], f"{where}: surfaces.{name}")
             for name in ISOLATOR_SURFACES[isolator]}
    yield_disp = _value(document["yield_disp"], "length", f"{where}: yield_disp")
    fields = {f"{name}_{field}": parts[name][index] for name in ISOLATOR_SURFACES[isolator]
              for index, field in enumerate(("radius", "capacity", "friction"))}
    pendulum = SERIES_PENDULUMS[isolator](hysteresis=BoucWen(yield_disp), **fields, **_heating_fields(parts))
    keys = {f"{name}_{field}": f"surfaces.{name}.{key}" for name in ISOLATOR_SURFACES[isolator]
            for field, key in (("radius", "radius"), ("capacity", "capacity"), ("friction", "friction"),
                               ("heating", "heating"), ("pressure", _pressure_key(parts[name][3])))}
    return _checked(pendulum, check_series_pendulum, where, keys)


def _pressure_key(heating) -> str:
    """The file's key of a surface's contact pressure: its heating's, else its pressure
    dependence's (one pressure when both are given, `_surface_parts`)."""
    return "pressure_dependence.contact_pressure" if heating is None else "heating.contact_pressure"


def _check_isolator(isolator, surfaces, where) -> None:
    """`ValueError` for an unknown `isolator`, or one whose surfaces are another's."""
    if isolator not in ISOLATOR_SURFACES:
        names = " or ".join(f'"{name}"' for name in ISOLATOR_SURFACES)
        raise ValueError(f"{where}: 'isolator' must be {names} (a single pendulum takes --radius), "
                         f"got {isolator!r}.")
    if isinstance(surfaces, dict):
        for other, names in ISOLATOR_SURFACES.items():
            if other != isolator and set(surfaces) == set(names):
                raise ValueError(f"{where}: 'isolator' must be \"{other}\" for the surfaces "
                                 f"{', '.join(names)} (a {isolator} file names "
                                 f"{', '.join(ISOLATOR_SURFACES[isolator])}), got {isolator!r}.")


def _checked(bearing, check, where, keys):
    """`bearing` once `check` and a positive yield displacement pass, else the `ValueError`
    prefixed by `where`, the pendulum's fields named by the file's `keys` (field -> key:
    `bottom_friction` -> `surfaces.bottom.friction`)."""
    try:
        check(bearing)
        yield_disp = float(bearing.hysteresis.yield_disp)
        if not yield_disp > 0:
            raise ValueError(f"yield_disp: must be > 0, got {yield_disp}.")
    except ValueError as error:
        field = re.compile(rf"\b({'|'.join(keys)})\b")
        message = field.sub(lambda match: keys[match.group(1)], str(error))
        raise ValueError(f"{where}: {message}") from None
    return bearing


class IsolatorFile(typing.NamedTuple):
    """What one read of an isolator file holds (`read_isolator_file`): `pendulum`, its
    `TriplePendulum` or `DoublePendulum` (SI), and `posterior` (`IsolatorPosterior`), None
    where the file has none."""

    pendulum: SeriesPendulum
    posterior: IsolatorPosterior | None


def read_isolator_file(path) -> IsolatorFile:
    """Read and parse the isolator file `path` once (`IsolatorFile`); `ValueError` naming the
    file and the key for anything `load_isolator` or `load_isolator_posterior` refuses."""
    document = read_json_document(path, "isolator file")
    pendulum = isolator_from_dict(document, where=str(path))
    if "posterior" not in document:
        return IsolatorFile(pendulum, None)
    return IsolatorFile(pendulum, isolator_posterior_from_dict(document["posterior"], pendulum, str(path)))


def load_isolator(path) -> SeriesPendulum:
    """Read an isolator file (JSON) into a `TriplePendulum` or `DoublePendulum` (SI), as its
    "isolator" says; a `posterior` section is checked (`load_isolator_posterior`)."""
    return read_isolator_file(path).pendulum


def load_isolator_posterior(path) -> IsolatorPosterior | None:
    """The posterior draws an isolator file holds (`IsolatorPosterior`, its `posterior`
    section: `_isolator_posterior.py`), or `None` where it holds none."""
    return read_isolator_file(path).posterior
