"""Eq. 1's delta_f inside the optimiser as its ratio to f_max, so that every step keeps
0 <= delta_f <= f_max: the friction at rest, f_max - delta_f, is never negative (Constantinou,
Mokha & Reinhorn 1990, Eq. 1: mu = f_max - delta_f exp(-rate_a |v|)). The flat slider's fit
(`fit_bearing_test`) and the series pendulums' (`fit_series_pendulum_test`, `diagnose`) share it.

A pair `(delta, f_max, ratio)` names delta_f, f_max and the optimiser's ratio = delta_f / f_max,
bounded to (0, 1). Values may be floats or (traced) arrays; f_max comes from the same mapping,
else from `held` (its value where the fit holds it).
"""

from collections.abc import Mapping

import numpy as np

from ..least_squares import (
    LeastSquaresResult,
    correlation_from_covariance,
    covariance_from_jacobian,
)

RATIO_PAIRS = (("delta_f", "f_max", "delta_ratio"),
               ("delta_f_perpendicular", "f_max_perpendicular", "delta_ratio_perpendicular"))
"""The flat slider's pairs: inside the optimiser delta_f = ratio x f_max, 0 < ratio < 1."""

RATIO_BOUNDS = (0.0, 1.0)
"""Bounds of a ratio [-]."""


def series_ratio_pairs(surfaces) -> tuple:
    """The pairs of a series pendulum's `surfaces` (`<surface>_delta_f`, ...)."""
    return tuple((f"{s}_delta_f", f"{s}_f_max", f"{s}_delta_ratio") for s in surfaces)


def _f_max(values: Mapping, held: Mapping, name: str):
    return values[name] if name in values else held[name]


def deltas_of(params: Mapping, pairs, held: Mapping = {}) -> dict:
    """{delta: ratio x f_max} of each pair whose ratio is in `params`."""
    return {delta: params[ratio] * _f_max(params, held, f_max)
            for delta, f_max, ratio in pairs if ratio in params}


def to_ratios(values: Mapping, pairs, held: Mapping = {}) -> dict:
    """`values` in the optimiser's names: each pair's delta_f among them replaced, in its
    place, by its ratio delta_f / f_max."""
    ratio_of = {delta: (f_max, ratio) for delta, f_max, ratio in pairs}
    out = {}
    for name, value in values.items():
        if name in ratio_of:
            f_max, ratio = ratio_of[name]
            out[ratio] = value / _f_max(values, held, f_max)
        else:
            out[name] = value
    return out


def from_ratios(params: Mapping, pairs, held: Mapping = {}) -> dict:
    """Inverse of `to_ratios`: each ratio among `params` replaced, in its place, by delta_f."""
    deltas = deltas_of(params, pairs, held)
    delta_of = {ratio: delta for delta, _, ratio in pairs}
    return {delta_of.get(k, k): deltas[delta_of[k]] if k in delta_of else v for k, v in params.items()}


def ratio_bounds(bounds: Mapping, pairs) -> dict:
    """`bounds` (name -> (lower, upper)) in the optimiser's names: a delta_f's replaced by its
    ratio's `RATIO_BOUNDS`."""
    return {ratio_name(k, pairs): RATIO_BOUNDS if ratio_name(k, pairs) != k else v for k, v in bounds.items()}


def jacobian_from_ratios(names, jacobian, params: Mapping, pairs, held: Mapping = {}):
    """(names, jacobian (n, p)) of a residual in the optimiser's names (ratios; `params` their
    values at the Jacobian) -> in delta_f and f_max, by the chain rule of delta_f = r f_max:
    dR/d delta_f = (dR/dr) / f_max, and dR/df_max = (dR/df_max at fixed r) - r dR/d delta_f."""
    names, jac = list(names), np.array(jacobian, dtype=float)
    for delta, f_max, ratio in pairs:
        if ratio not in names:
            continue
        i = names.index(ratio)
        jac[..., i] = jac[..., i] / _f_max(params, held, f_max)
        if f_max in names:
            j = names.index(f_max)
            jac[..., j] = jac[..., j] - params[ratio] * jac[..., i]
        names[i] = delta
    return tuple(names), jac


def ratio_name(name: str, pairs) -> str:
    """The optimiser's name of `name`: its ratio's where it is a pair's delta_f."""
    return {delta: ratio for delta, _, ratio in pairs}.get(name, name)


def result_from_ratios(result: LeastSquaresResult, pairs, held: Mapping = {}) -> LeastSquaresResult:
    """A `LeastSquaresResult` of the optimiser's ratios in delta_f and f_max: its parameters,
    names, Jacobian, standard errors and correlation."""
    names, jac = jacobian_from_ratios(result.names, result.jacobian, result.parameters, pairs, held)
    cov, _ = covariance_from_jacobian(jac, result.residual)
    std = np.sqrt(np.abs(np.diag(cov)))
    return result._replace(parameters={k: float(v) for k, v in from_ratios(result.parameters, pairs, held).items()},
                           names=names, jacobian=jac, std_errors=dict(zip(names, std.tolist())),
                           correlation=correlation_from_covariance(cov))
