"""Writing a bearing file: a `SlidingBearing` in SI, with the standard errors, the sources and
the fit it came from, and the draws of a Bayesian fit or a mixture's compositions (the format:
`_bearing_file.py`, docs/formats.md)."""

import json
import math
import pathlib

import jax.numpy as jnp

from ..bearing import SlidingBearing
from ._bearing_file import (
    BEARING_PARTS,
    FORMAT_NAME,
    FORMAT_VERSION,
    SI_UNITS,
    check_posterior,
)
from ._bearing_mixture import BearingMixture
from ._bearing_posterior import POSTERIOR_FIELDS, BearingPosterior


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


def _posterior_to_dict(posterior: BearingPosterior) -> dict:
    def unit(name):
        part, constant = POSTERIOR_FIELDS[name]
        return SI_UNITS[BEARING_PARTS[part][constant]]

    return {
        "constants": {n: dict(zip(("part", "constant"), POSTERIOR_FIELDS[n]), unit=unit(n))
                      for n in posterior.names},
        "draws": {n: posterior.draws[n].tolist() for n in posterior.names},
        "effective_sample_size": dict(posterior.effective_sample_size),
        "draws_before_thinning": posterior.draws_before_thinning,
        "thinning": posterior.thinning,
        "sampler": {"method": posterior.method, "chains": posterior.chains,
                    "seed": posterior.seed}}


def _mixture_to_dict(mixture: BearingMixture) -> dict:
    def composition(c):
        check_posterior(c.posterior, c.bearing, f"mixture.compositions[{c.label}]")
        return {"effects": list(c.effects), "weight": c.weight, "delta_bic": c.delta_bic,
                "parts": bearing_to_dict(c.bearing, standard_errors=c.standard_errors)["parts"],
                "posterior": _posterior_to_dict(c.posterior), "note": c.note}

    return {"criterion": mixture.criterion, "min_weight": mixture.min_weight,
            "compositions": [composition(c) for c in mixture.compositions],
            "left_out": [dict(entry) for entry in mixture.left_out]}


def bearing_to_dict(bearing: SlidingBearing, *, standard_errors=None, sources=(),
                    fit=None, posterior: BearingPosterior | None = None,
                    mixture: BearingMixture | None = None) -> dict:
    """A bearing-file object for `bearing` (SI units).

    **Arguments:** `standard_errors` mapping `(part, constant)` -> standard error [SI];
    `sources` the records the bearing came from; `fit` a JSON-able summary of the fit;
    `posterior` the draws of a Bayesian fit (`BearingPosterior`), whose constants must be
    constants of `bearing`'s parts and make a valid bearing draw by draw; or `mixture` the
    compositions' bearings with their weights and draws (`BearingMixture`).
    """
    if mixture is not None and (posterior is not None or not isinstance(mixture, BearingMixture)):
        raise ValueError("mixture: must be a BearingMixture, and not given with a posterior.")
    if posterior is not None:
        if not isinstance(posterior, BearingPosterior):
            raise ValueError(f"posterior: must be a BearingPosterior, got {type(posterior).__name__}.")
        check_posterior(posterior, bearing, "posterior")
    errors = dict(standard_errors or {})
    parts = {}

    def put(part, constants):
        parts[part] = {}
        for key, value in constants.items():
            entry = {"value": _scalar(value), "unit": SI_UNITS[BEARING_PARTS[part][key]]}
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
            "sources": [str(s) for s in sources], **({"fit": fit} if fit is not None else {}),
            **({"posterior": _posterior_to_dict(posterior)} if posterior is not None else {}),
            **({"mixture": _mixture_to_dict(mixture)} if mixture is not None else {})}


def save_bearing(path, bearing: SlidingBearing, *, standard_errors=None, sources=(),
                 fit=None, posterior: BearingPosterior | None = None,
                 mixture: BearingMixture | None = None) -> pathlib.Path:
    """Write `bearing` as a bearing file (JSON; see `bearing_to_dict`), with the draws of
    `posterior` (a `BearingPosterior`) or the compositions of `mixture` (a `BearingMixture`)
    beside the point estimate when given."""
    path = pathlib.Path(path)
    document = bearing_to_dict(bearing, standard_errors=standard_errors, sources=sources, fit=fit,
                               posterior=posterior, mixture=mixture)
    path.write_text(json.dumps(document, indent=2, allow_nan=False) + "\n")
    return path
