"""The isolator file: the geometry and friction of a triple friction pendulum, in any units.

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
of each surface. Every value carries its unit; nothing is defaulted.
"""


import jax.numpy as jnp

from ..bearing import BoucWen, FrictionParameters, TriplePendulum, check_triple_pendulum
from ._bearing_file import BEARING_PARTS, read_constant
from ._text import read_json_document

FORMAT_NAME = "teflon-jax isolator"
FORMAT_VERSION = 1
SURFACES = ("inner", "bottom", "top")
"""The surface groups of the file: inner (2 and 3), bottom (1), top (4)."""

_SURFACE = {"radius": "length", "capacity": "length"}
_FRICTION = BEARING_PARTS["friction"]  # Eq. 1's constants, as in the bearing file


def _value(entry, kind, where) -> float:
    """SI value of one `{"value": ..., "unit": ...}` entry (read as the bearing file reads its
    constants); an isolator file states no standard errors."""
    value, error = read_constant(entry, kind, where)
    if error is not None:
        raise ValueError(f"{where}: an isolator file states no standard_error; leave it out.")
    return value


def _keys(part, expected, where):
    if not isinstance(part, dict):
        raise ValueError(f"{where}: must be an object with {', '.join(expected)}.")
    missing = [key for key in expected if key not in part]
    unknown = [key for key in part if key not in expected]
    if missing or unknown:
        raise ValueError(f"{where}: " + "; ".join(
            text for text in (f"missing {missing}" if missing else "",
                              f"unknown {unknown}" if unknown else "") if text)
            + f" (expected {', '.join(expected)}; nothing is defaulted).")


def _surface(part, where):
    _keys(part, ("radius", "capacity", "friction"), where)
    values = {key: _value(part[key], kind, f"{where}.{key}") for key, kind in _SURFACE.items()}
    _keys(part["friction"], tuple(_FRICTION), f"{where}.friction")
    friction = FrictionParameters(*(jnp.asarray(_value(part["friction"][key], kind,
                                                       f"{where}.friction.{key}"))
                                    for key, kind in _FRICTION.items()))
    return values["radius"], values["capacity"], friction


def isolator_from_dict(document, *, where: str = "isolator") -> TriplePendulum:
    """The `TriplePendulum` of an isolator-file object (module docstring); `ValueError` naming
    `where` and the key for anything missing, unknown, unitless or that the series model
    cannot take (`check_triple_pendulum`)."""
    if not isinstance(document, dict):
        raise ValueError(f"{where}: an isolator file is a JSON object; see the format in the manual.")
    if document.get("format") != FORMAT_NAME:
        raise ValueError(f"{where}: 'format' must be \"{FORMAT_NAME}\".")
    version = document.get("format_version")
    if not isinstance(version, int) or isinstance(version, bool) or version > FORMAT_VERSION:
        raise ValueError(f"{where}: 'format_version' must be an integer up to {FORMAT_VERSION}, "
                         f"got {version!r}.")
    _keys(document, ("format", "format_version", "isolator", "surfaces", "yield_disp"), where)
    if document["isolator"] != "triple-fp":
        raise ValueError(f"{where}: 'isolator' must be \"triple-fp\" (a single pendulum takes "
                         f"--radius), got {document['isolator']!r}.")
    _keys(document["surfaces"], SURFACES, f"{where}: surfaces")
    parts = {name: _surface(document["surfaces"][name], f"{where}: surfaces.{name}")
             for name in SURFACES}
    yield_disp = _value(document["yield_disp"], "length", f"{where}: yield_disp")
    bearing = TriplePendulum(
        inner_radius=parts["inner"][0], bottom_radius=parts["bottom"][0],
        top_radius=parts["top"][0], inner_capacity=parts["inner"][1],
        bottom_capacity=parts["bottom"][1], top_capacity=parts["top"][1],
        inner_friction=parts["inner"][2], bottom_friction=parts["bottom"][2],
        top_friction=parts["top"][2], hysteresis=BoucWen(yield_disp))
    try:
        check_triple_pendulum(bearing)
        if not yield_disp > 0:
            raise ValueError(f"yield_disp: must be > 0, got {yield_disp}.")
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None
    return bearing


def load_isolator(path) -> TriplePendulum:
    """Read an isolator file (JSON) into a `TriplePendulum` (SI)."""
    document = read_json_document(path, "isolator file")
    return isolator_from_dict(document, where=str(path))
