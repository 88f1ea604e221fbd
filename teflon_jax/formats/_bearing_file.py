"""The bearing file: a `SlidingBearing` with its parts, units, standard errors and provenance.

A JSON object (format version 1):

    {"format": "teflon-jax bearing", "format_version": 1, "teflon_jax_version": "0.1.0",
     "parts": {"friction": {"f_max": {"value": 0.1193, "unit": "1", "standard_error": 0.001},
                            "delta_f": {...}, "rate_a": {"value": 23.6, "unit": "s/m"}},
               "hysteresis": {"yield_disp": {"value": 0.000127, "unit": "m"}, "A": ..., ...},
               "breakaway": {"ratio": ...}, "heating": {...}, ...},
     "sources": ["test75.csv"], "fit": {"nrmse": 0.012, ...}}

Every constant is an object with `value`, `unit` (`"1"` for a ratio) and optionally
`standard_error` (same unit; `null` with a `standard_error_note` saying why where the records
do not determine the constant). `friction` and `hysteresis` are required; every other part is
optional, and a part that is present lists all its constants (nothing is defaulted) except
those in `OPTIONAL_CONSTANTS`. The
parts and their constants are `BEARING_PARTS`. Written in SI; read in any unit of the right
kind (`s/in`, `in`, `kip`, `in^2`, ...).
"""

import json
import math
import pathlib

import jax.numpy as jnp

from ..bearing import (
    Backlash,
    BoucWen,
    DirectionAsymmetry,
    FrictionalHeating,
    FrictionParameters,
    PressureDependence,
    SlidingBearing,
    Wear,
    check_bearing,
)
from ..units import unit_factor
from ._text import read_json_document

FORMAT_NAME = "teflon-jax bearing"
FORMAT_VERSION = 1

_FRICTION = {"f_max": "dimensionless", "delta_f": "dimensionless", "rate_a": "slowness"}
BEARING_PARTS = {
    "friction": _FRICTION,
    "friction_perpendicular": _FRICTION,
    "lay": {"angle": "angle"},
    "hysteresis": {"yield_disp": "length", "A": "dimensionless", "beta": "dimensionless",
                   "gamma": "dimensionless", "eta": "dimensionless"},
    "breakaway": {"ratio": "dimensionless"},
    "stack": {"interfaces_in_series": "dimensionless"},
    "pressure_dependence": {"exponent": "dimensionless", "reference_load": "force",
                            "contact_area": "area"},
    "heating": {"contact_area": "area", "heat_scale": "dimensionless",
                "conductivity": "thermal conductivity", "diffusivity": "diffusivity",
                "initial_temperature": "temperature"},
    "wear": {"change": "dimensionless", "reference_travel": "length"},
    "asymmetry": {"asymmetry": "dimensionless"},
    "backlash": {"gap": "length"},
}
"""Part -> constant -> kind of quantity. `friction` and `hysteresis` are required."""

OPTIONAL_CONSTANTS = {("pressure_dependence", "contact_area")}
"""Constants a part may leave out (the model then does without them and says so where one is
needed): the tested bearing's contact area, which a structure needs to use pressure dependence."""

REQUIRED_PARTS = ("friction", "hysteresis")

_SI = {"dimensionless": "1", "slowness": "s/m", "angle": "rad", "length": "m", "force": "N",
       "area": "m^2", "thermal conductivity": "W/(m K)", "diffusivity": "m^2/s",
       "temperature": "degC", "pressure": "Pa"}
_SPECIAL_UNITS = {
    "thermal conductivity": {"W/(m K)": 1.0, "W/(m*K)": 1.0, "W/m/K": 1.0},
    "diffusivity": {"m^2/s": 1.0, "mm^2/s": 1e-6},
    "temperature": {"degC": 1.0},
    "dimensionless": {"1": 1.0, "-": 1.0},
}


def _factor(unit, kind, where):
    if not isinstance(unit, str):
        raise ValueError(f"{where}: 'unit' must be a string such as '{_SI[kind]}', got {unit!r}.")
    if unit in _SPECIAL_UNITS.get(kind, {}):
        return _SPECIAL_UNITS[kind][unit]
    if kind in ("thermal conductivity", "diffusivity", "temperature"):
        known = ", ".join(_SPECIAL_UNITS[kind])
        raise ValueError(f"{where}: unit '{unit}' is not one of {known}.")
    return unit_factor(unit, kind, where=where)


def read_constant(entry, kind, where):
    """SI value and standard error (or None) of one constant entry."""
    if not isinstance(entry, dict):
        raise ValueError(f"{where}: write {{\"value\": ..., \"unit\": \"{_SI[kind]}\"}}; "
                         f"got {entry!r} (a value without a unit is not read).")
    unknown = set(entry) - {"value", "unit", "standard_error", "standard_error_note"}
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {sorted(unknown)}; allowed: value, unit, "
                         "standard_error, standard_error_note.")
    for key in ("value", "unit"):
        if key not in entry:
            raise ValueError(f"{where}: missing '{key}' (e.g. \"unit\": \"{_SI[kind]}\").")
    factor = _factor(entry["unit"], kind, f"{where}.unit")
    values = []
    for key in ("value", "standard_error"):
        raw = entry.get(key)
        if raw is None and key == "standard_error":
            values.append(None)
            continue
        if isinstance(raw, bool) or not isinstance(raw, int | float):
            raise ValueError(f"{where}.{key}: must be a number, got {raw!r}.")
        values.append(float(raw) * factor)
    return values[0], values[1]


def _read_parts(parts, where):
    if not isinstance(parts, dict):
        raise ValueError(f"{where}: 'parts' must be an object of parts.")
    unknown = [name for name in parts if name not in BEARING_PARTS]
    if unknown:
        raise ValueError(f"{where}: unknown part(s) {unknown}; known parts: "
                         f"{', '.join(BEARING_PARTS)}.")
    for name in REQUIRED_PARTS:
        if name not in parts:
            raise ValueError(f"{where}: the part '{name}' is missing (required: "
                             f"{', '.join(REQUIRED_PARTS)}).")
    values, errors = {}, {}
    for name, part in parts.items():
        at = f"{where}: parts.{name}"
        if not isinstance(part, dict):
            raise ValueError(f"{at}: must be an object of constants.")
        expected = BEARING_PARTS[name]
        extra = [key for key in part if key not in expected]
        if extra:
            raise ValueError(f"{at}: unknown constant(s) {extra}; {name} has "
                             f"{', '.join(expected)}.")
        missing = [key for key in expected if key not in part
                   and (name, key) not in OPTIONAL_CONSTANTS]
        if missing:
            raise ValueError(f"{at}: missing constant(s) {missing}; nothing is defaulted.")
        for key, kind in expected.items():
            if key in part:
                values[name, key], errors[name, key] = read_constant(part[key], kind, f"{at}.{key}")
    return values, errors


def _bearing_from_values(v) -> SlidingBearing:
    def friction(part):
        return FrictionParameters(*(jnp.asarray(v[part, k]) for k in _FRICTION))

    def part(name, build):
        if (name, next(iter(BEARING_PARTS[name]))) not in v:
            return None
        return build(**{k: jnp.asarray(v[name, k]) for k in BEARING_PARTS[name]
                        if (name, k) in v})

    series = v.get(("stack", "interfaces_in_series"), 1.0)
    if series != int(series) or series < 1:
        raise ValueError(f"parts.stack.interfaces_in_series: must be an integer >= 1, got {series}.")
    has_perpendicular = ("friction_perpendicular", "f_max") in v
    return SlidingBearing(
        friction=friction("friction"),
        hysteresis=part("hysteresis", lambda **c: BoucWen(**c)),
        breakaway_ratio=(jnp.asarray(v["breakaway", "ratio"]) if ("breakaway", "ratio") in v
                         else None),
        friction_perpendicular=friction("friction_perpendicular") if has_perpendicular else None,
        n_interfaces=int(series),
        lay_angle=jnp.asarray(v["lay", "angle"]) if ("lay", "angle") in v else None,
        pressure_dependence=part("pressure_dependence",
                                 lambda **c: PressureDependence(**c)),
        heating=part("heating", lambda **c: FrictionalHeating(**c)),
        wear=part("wear", lambda change, reference_travel: Wear(change, reference_travel)),
        asymmetry=part("asymmetry", lambda asymmetry: DirectionAsymmetry(asymmetry)),
        backlash=part("backlash", lambda gap: Backlash(gap)),
    )


def bearing_from_dict(document: dict, *, where: str = "bearing") -> SlidingBearing:
    """The `SlidingBearing` of a bearing-file object (see the module docstring); `ValueError`
    naming `where` and the key for anything missing, unknown, unitless or out of range."""
    if not isinstance(document, dict):
        raise ValueError(f"{where}: a bearing file is a JSON object; see the format in the manual.")
    if document.get("format") != FORMAT_NAME:
        raise ValueError(f"{where}: 'format' must be \"{FORMAT_NAME}\" (is this a bearing file "
                         "written by `teflon-jax fit --save-bearing`?).")
    version = document.get("format_version")
    if not isinstance(version, int) or isinstance(version, bool):
        raise ValueError(f"{where}: 'format_version' must be an integer, got {version!r}.")
    if version > FORMAT_VERSION:
        raise ValueError(f"{where}: format_version {version} is newer than this teflon-jax reads "
                         f"({FORMAT_VERSION}); update teflon-jax.")
    unknown = set(document) - {"format", "format_version", "teflon_jax_version", "parts",
                               "sources", "fit"}
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {sorted(unknown)}.")
    if "parts" not in document:
        raise ValueError(f"{where}: the key 'parts' is missing.")
    values, _ = _read_parts(document["parts"], where)
    bearing = _bearing_from_values(values)
    try:
        check_bearing(bearing)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None
    return bearing


def load_bearing(path) -> SlidingBearing:
    """Read a bearing file (JSON, `save_bearing`) into a `SlidingBearing` (SI)."""
    document = read_json_document(path, "bearing file")
    return bearing_from_dict(document, where=str(path))


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("teflon-jax")
    except PackageNotFoundError:
        return "unknown"


NOT_IDENTIFIABLE = ("not identifiable: the records do not determine this constant (an infinite or "
                    "undefined standard error), so its value is the fit's start or a guess")
"""The `standard_error_note` written beside a `null` standard error."""


def _standard_error(error: float) -> dict:
    """The standard-error keys of a constant: the number, or (strict JSON has no Infinity or
    NaN) `null` with `standard_error_note` saying why."""
    if math.isfinite(error):
        return {"standard_error": error}
    return {"standard_error": None, "standard_error_note": NOT_IDENTIFIABLE}


def _scalar(x) -> float:
    return float(jnp.asarray(x))


def bearing_to_dict(bearing: SlidingBearing, *, standard_errors=None, sources=(),
                    fit=None) -> dict:
    """A bearing-file object for `bearing` (SI units).

    **Arguments:** `standard_errors` mapping `(part, constant)` -> standard error [SI];
    `sources` the records the bearing came from; `fit` a JSON-able summary of the fit.
    """
    errors = dict(standard_errors or {})
    parts = {}

    def put(part, constants):
        parts[part] = {}
        for key, value in constants.items():
            entry = {"value": _scalar(value), "unit": _SI[BEARING_PARTS[part][key]]}
            if (part, key) in errors and errors[part, key] is not None:
                entry.update(_standard_error(float(errors[part, key])))
            parts[part][key] = entry

    f = bearing.friction
    put("friction", {"f_max": f.f_max, "delta_f": f.delta_f, "rate_a": f.rate_a})
    if bearing.friction_perpendicular is not None:
        g = bearing.friction_perpendicular
        put("friction_perpendicular", {"f_max": g.f_max, "delta_f": g.delta_f, "rate_a": g.rate_a})
    if bearing.lay_angle is not None:
        put("lay", {"angle": bearing.lay_angle})
    h = bearing.hysteresis
    put("hysteresis", {"yield_disp": h.yield_disp, "A": h.A, "beta": h.beta, "gamma": h.gamma,
                       "eta": h.eta})
    if bearing.breakaway_ratio is not None:
        put("breakaway", {"ratio": bearing.breakaway_ratio})
    put("stack", {"interfaces_in_series": bearing.n_interfaces})
    for name in bearing.effects:
        module = getattr(bearing, name)
        put(name, {key: getattr(module, key) for key in BEARING_PARTS[name]
                   if getattr(module, key) is not None})
    return {"format": FORMAT_NAME, "format_version": FORMAT_VERSION,
            "teflon_jax_version": _version(), "parts": parts,
            "sources": [str(s) for s in sources], **({"fit": fit} if fit is not None else {})}


def save_bearing(path, bearing: SlidingBearing, *, standard_errors=None, sources=(),
                 fit=None) -> pathlib.Path:
    """Write `bearing` as a bearing file (JSON; see `bearing_to_dict`)."""
    path = pathlib.Path(path)
    document = bearing_to_dict(bearing, standard_errors=standard_errors, sources=sources, fit=fit)
    path.write_text(json.dumps(document, indent=2, allow_nan=False) + "\n")
    return path
