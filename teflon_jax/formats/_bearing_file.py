"""The bearing file: a `SlidingBearing` with its parts, units, standard errors and provenance.

A JSON object (format version 1):

    {"format": "teflon-jax bearing", "format_version": 1, "teflon_jax_version": "0.1.0",
     "parts": {"friction": {"f_max": {"value": 0.1193, "unit": "1", "standard_error": 0.001},
                            "delta_f": {...}, "rate_a": {"value": 23.6, "unit": "s/m"}},
               "hysteresis": {"yield_disp": {"value": 0.000127, "unit": "m"}, "A": ..., ...},
               "breakaway": {"ratio": ...}, "heating": {...}, ...},
     "sources": ["test75.csv"], "fit": {"nrmse": 0.012, ...},
     "posterior": {...}}

Every constant is an object with `value`, `unit` (`"1"` for a ratio) and optionally
`standard_error` (same unit; `null` with a `standard_error_note` saying why where the records
do not determine the constant). `friction` and `hysteresis` are required; every other part is
optional, and a part that is present lists all its constants (nothing is defaulted) except
those in `OPTIONAL_CONSTANTS`. The
parts and their constants are `BEARING_PARTS`. Written in SI; read in any unit of the right
kind (`s/in`, `in`, `kip`, `in^2`, ...).

The optional `posterior` object holds the thinned draws of a Bayesian fit (`BearingPosterior`):

    "posterior": {
      "constants": {"f_max": {"part": "friction", "constant": "f_max", "unit": "1"}, ...},
      "draws": {"f_max": [0.1191, 0.1195, ...], ...},          K draws per constant
      "effective_sample_size": {"f_max": 1843.0, ...},         bulk ESS, unthinned run
      "draws_before_thinning": 4000, "thinning": 4,
      "sampler": {"method": "NUTS", "chains": 4, "seed": 0}}

Each sampled constant's part must be in `parts`; "parts" keeps the point estimate.

The optional `mixture` object (not with `posterior`) holds bearings of several compositions of
parts, each with its `effects`, `weight`, `delta_bic`, `parts`, `posterior` and `note`
(`BearingMixture`; docs/formats.md).
"""

import typing

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
from ._bearing_mixture import (
    COMPOSITION_KEYS,
    MIXTURE_KEYS,
    BearingMixture,
    MixtureComposition,
    object_keys,
)
from ._bearing_posterior import POSTERIOR_FIELDS, BearingPosterior, posterior_from_entry
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

SI_UNITS = {"dimensionless": "1", "slowness": "s/m", "angle": "rad", "length": "m", "force": "N",
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
        raise ValueError(f"{where}: 'unit' must be a string such as '{SI_UNITS[kind]}', got {unit!r}.")
    if unit in _SPECIAL_UNITS.get(kind, {}):
        return _SPECIAL_UNITS[kind][unit]
    if kind in ("thermal conductivity", "diffusivity", "temperature"):
        known = ", ".join(_SPECIAL_UNITS[kind])
        raise ValueError(f"{where}: unit '{unit}' is not one of {known}.")
    return unit_factor(unit, kind, where=where)


def read_constant(entry, kind, where):
    """SI value and standard error (or None) of one constant entry."""
    if not isinstance(entry, dict):
        raise ValueError(f"{where}: write {{\"value\": ..., \"unit\": \"{SI_UNITS[kind]}\"}}; "
                         f"got {entry!r} (a value without a unit is not read).")
    unknown = set(entry) - {"value", "unit", "standard_error", "standard_error_note"}
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {sorted(unknown)}; allowed: value, unit, "
                         "standard_error, standard_error_note.")
    for key in ("value", "unit"):
        if key not in entry:
            raise ValueError(f"{where}: missing '{key}' (e.g. \"unit\": \"{SI_UNITS[kind]}\").")
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


def _posterior_constants(constants, values, where):
    """name -> SI factor of the `posterior.constants` object, each checked against `parts`."""
    at = f"{where}: posterior.constants"
    if not isinstance(constants, dict) or not constants:
        raise ValueError(f"{at}: must be an object of the sampled constants, e.g. "
                         '{"f_max": {"part": "friction", "constant": "f_max", "unit": "1"}}.')
    factors = {}
    for name, entry in constants.items():
        if name not in POSTERIOR_FIELDS:
            raise ValueError(f"{at}: unknown constant {name!r}; the constants a posterior can "
                             f"hold are {', '.join(POSTERIOR_FIELDS)}.")
        part, constant = POSTERIOR_FIELDS[name]
        if not isinstance(entry, dict) or set(entry) != {"part", "constant", "unit"}:
            raise ValueError(f"{at}.{name}: write {{\"part\": \"{part}\", \"constant\": "
                             f"\"{constant}\", \"unit\": \"{SI_UNITS[BEARING_PARTS[part][constant]]}\"}}; "
                             f"got {entry!r}.")
        if (entry["part"], entry["constant"]) != (part, constant):
            raise ValueError(f"{at}.{name}: is the constant '{constant}' of the part '{part}', "
                             f"not '{entry['constant']}' of '{entry['part']}'.")
        if (part, constant) not in values:
            raise ValueError(f"{at}.{name}: the bearing has no parts.{part}.{constant}; a "
                             "posterior's constants are constants of the bearing's parts.")
        factors[name] = _factor(entry["unit"], BEARING_PARTS[part][constant], f"{at}.{name}.unit")
    return factors


def _read_posterior(entry, values, where) -> BearingPosterior:
    """The `BearingPosterior` of a file's `posterior` object; `values` the file's parts."""
    return posterior_from_entry(entry, lambda constants, at: _posterior_constants(constants, values, at), where)


def check_posterior(posterior: BearingPosterior, bearing: SlidingBearing, where) -> None:
    """Every draw, put into `bearing`, is a valid bearing (`check_bearing`, e.g. delta_f <
    f_max draw by draw)."""
    try:
        check_bearing(posterior.bearings(bearing))
    except ValueError as error:
        raise ValueError(f"{where}: posterior.draws: {error}") from None


def _read_mixture(entry, where) -> BearingMixture:
    """The `BearingMixture` of a file's `mixture` object: each composition's parts, posterior
    draws (every draw a valid bearing) and weight, the weights checked together."""
    object_keys(entry, MIXTURE_KEYS, f"{where}: mixture")
    items = []
    for i, item in enumerate(entry["compositions"]):
        at = f"{where}: mixture.compositions[{i}]"
        object_keys(item, COMPOSITION_KEYS, at)
        values, errors = _read_parts(item["parts"], at)
        bearing = _checked(values, at)
        posterior = _read_posterior(item["posterior"], values, at)
        check_posterior(posterior, bearing, at)
        try:
            items.append(MixtureComposition(
                effects=item["effects"], weight=item["weight"], delta_bic=item["delta_bic"],
                bearing=bearing, posterior=posterior, note=str(item["note"]),
                standard_errors={k: e for k, e in errors.items() if e is not None}))
        except ValueError as error:
            raise ValueError(f"{at}.{error}") from None
    try:
        return BearingMixture(tuple(items), criterion=entry["criterion"],
                              left_out=tuple(entry["left_out"]), min_weight=entry["min_weight"])
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None


_FILE_KEYS = {"f_max": "parts.friction.f_max", "delta_f": "parts.friction.delta_f",
              "rate_a": "parts.friction.rate_a", "breakaway_ratio": "parts.breakaway.ratio",
              "lay_angle": "parts.lay.angle", "n_interfaces": "parts.stack.interfaces_in_series",
              **{name: f"parts.hysteresis.{name}" for name in BEARING_PARTS["hysteresis"]}}
"""A `SlidingBearing`'s constant, as its check names it -> the bearing file's key (a part's
constant, `heating.contact_area`, is `parts.` and its name)."""


def _file_key(name: str) -> str:
    """The bearing file's key of the constant `check_bearing` names `name`."""
    if name in _FILE_KEYS:
        return _FILE_KEYS[name]
    return f"parts.{name}" if name.split(".")[0] in BEARING_PARTS else name


def _checked(values, where) -> SlidingBearing:
    """The `SlidingBearing` of a file's constants `values`, or `ValueError` at `where` when they
    are out of range, naming the constant by the file's key (`breakaway_ratio` as
    `parts.breakaway.ratio`)."""
    try:
        bearing = _bearing_from_values(values)
        check_bearing(bearing)
    except ValueError as error:
        name, _, rule = str(error).partition(": ")
        message = f"{_file_key(name)}: {rule}" if rule else name
        raise ValueError(f"{where}: {message}") from None
    return bearing


def _read_document(document, where, *, read_draws: bool):
    """(bearing, posterior or None, mixture or None) of a bearing-file object, every key checked."""
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
                               "sources", "fit", "posterior", "mixture"}
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {sorted(unknown)}.")
    if "parts" not in document:
        raise ValueError(f"{where}: the key 'parts' is missing.")
    if "posterior" in document and "mixture" in document:
        raise ValueError(f"{where}: a bearing file holds a 'posterior' (the draws of one "
                         "composition) or a 'mixture' (several compositions), not both.")
    values, _ = _read_parts(document["parts"], where)
    bearing = _checked(values, where)
    posterior = mixture = None
    if read_draws and "posterior" in document:
        posterior = _read_posterior(document["posterior"], values, where)
        check_posterior(posterior, bearing, where)
    if read_draws and "mixture" in document:
        mixture = _read_mixture(document["mixture"], where)
    return bearing, posterior, mixture


def bearing_from_dict(document: dict, *, where: str = "bearing") -> SlidingBearing:
    """The `SlidingBearing` of a bearing-file object (see the module docstring); `ValueError`
    naming `where` and the key for anything missing, unknown, unitless or out of range
    (the `posterior` or `mixture` object included, when there is one)."""
    return _read_document(document, where, read_draws=True)[0]


class BearingFile(typing.NamedTuple):
    """What one read of a bearing file holds (`read_bearing_file`): `bearing`, the point
    estimate of `parts` (SI); `posterior` (`BearingPosterior`) and `mixture` (`BearingMixture`),
    each None where the file has none; `unidentified`, `unidentified_constants` of the file."""

    bearing: SlidingBearing
    posterior: BearingPosterior | None
    mixture: BearingMixture | None
    unidentified: list


def read_bearing_file(path) -> BearingFile:
    """Read and parse the bearing file `path` once (`BearingFile`): its point bearing, posterior,
    mixture and unidentified constants, every key checked; `ValueError` naming the file and
    the key for anything `load_bearing`, `load_bearing_posterior` or `load_bearing_mixture`
    refuses."""
    document = read_json_document(path, "bearing file")
    bearing, posterior, mixture = _read_document(document, str(path), read_draws=True)
    return BearingFile(bearing, posterior, mixture, unidentified_constants(document))


def load_bearing(path) -> SlidingBearing:
    """Read a bearing file (JSON, `save_bearing`) into a `SlidingBearing` (SI): the point
    estimate of `parts`, also where the file has a posterior."""
    return read_bearing_file(path).bearing


def unidentified_constants(path) -> list[tuple[str, float]]:
    """(`part.constant`, value [SI]) of each constant of a bearing file's `parts` whose standard
    error is null with a `standard_error_note`: the fit that wrote it could not determine it, so
    its value is that fit's start or a guess. `path` may be the file's JSON object, read already
    (`load_bearing`'s checks passed: a bad value is named there)."""
    document = path if isinstance(path, dict) else read_json_document(path, "bearing file")
    parts = document.get("parts")
    found = []
    for part, constants in (parts.items() if isinstance(parts, dict) else ()):
        for constant, entry in (constants.items() if isinstance(constants, dict) else ()):
            if isinstance(entry, dict) and entry.get("standard_error", 0) is None and "standard_error_note" in entry \
                    and isinstance(entry.get("value"), int | float):  # a bad value: load_bearing names it
                found.append((f"{part}.{constant}", entry.get("value")))
    return found


def load_bearing_posterior(path) -> BearingPosterior | None:
    """The `BearingPosterior` of a bearing file's `posterior` object (SI), or `None` when the
    file has none; with `load_bearing`'s point bearing, `posterior.bearing(point, k)` is draw
    k's bearing. `ValueError` naming the file and the key for a posterior that is not a
    valid one (`BearingPosterior`), or whose draws make an invalid bearing."""
    return read_bearing_file(path).posterior


def load_bearing_mixture(path) -> BearingMixture | None:
    """The `BearingMixture` of a bearing file's `mixture` object (SI), or `None` when the file has
    none (`load_bearing` reads its point estimate, `parts`: the composition the search chose).
    `ValueError` naming the file and the key for a mixture that is not a valid one."""
    return read_bearing_file(path).mixture
