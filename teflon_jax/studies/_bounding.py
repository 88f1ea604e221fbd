"""Bounding analysis: the nominal bearing and its upper- and lower-bound variants from property
modification factors on the friction constants, run together, and the case that governs each
response.

A property modification factor lambda multiplies the sliding friction coefficient at every
velocity, f(v) = f_max - delta_f exp(-a |v|) (Eq. 1 of Constantinou, Mokha & Reinhorn 1990),
so f_max and delta_f = f_max - f_min are both multiplied and the rate parameter a is kept:

    f_max' = lambda f_max,   delta_f' = lambda delta_f.

The factors (from tests, ageing, temperature, contamination, ...) are the engineer's; upper
bounds usually govern forces and storey drifts, lower bounds the isolators' displacement, but
that is what the runs decide: the governing case of a response is the one with the largest
statistic of its peaks over the runs whose solve converged.

A triple or double friction pendulum has the law on each of its surfaces: every surface's
f_max and delta_f are multiplied by the same lambda (Coulomb surfaces, delta_f = 0, have their
mu = f_max multiplied), and the radii and displacement capacities, geometry, are kept.
Reference for property modification factors: Constantinou, Kalpakidis, Filiatrault & Ecker
Lay (2011), "LRFD-based analysis and design procedures for bridge bearings and seismic
isolators", MCEER-11-0004.
"""

import numpy as np

from ..bearing import FrictionParameters, SeriesPendulum
from ..systems import FRICTION_FACTOR, TripleIsolatedStructure, VerticalIsolatedStructure

BOUNDING_CASES = ("nominal", "upper", "lower")
"""The design variants of `bounding_design`, in order."""


def check_property_factors(lower: float, upper: float) -> tuple[float, float]:
    """(lower, upper) once finite, > 0 and lower <= upper; else `ValueError` naming them."""
    for name, value in (("lower", lower), ("upper", upper)):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"{name}: a property modification factor must be finite and > 0, got {value}.")
    if not lower <= upper:
        raise ValueError(f"lower: the lower-bound factor {lower:g} is above the upper-bound factor {upper:g}.")
    return float(lower), float(upper)


def scaled_friction(params: FrictionParameters, factor: float) -> FrictionParameters:
    """The Eq. 1 constants of a bearing whose friction coefficient is `factor` times that of
    `params` at every velocity: f_max and delta_f times `factor`, rate_a kept
    (`FrictionParameters.scaled`)."""
    return params.scaled(factor)


def bounding_design(structure, *, lower: float, upper: float) -> dict:
    """The `monte_carlo` design dict of the three `BOUNDING_CASES`: f_max and delta_f of `structure`'s
    bearing (Table 1 at its pressure; an `IsolatedStructure` or a bidirectional one built on
    it) times 1, `upper` and `lower` (module docstring). Values that leave the physical range
    (f_max' > 1) are refused when the run checks its design. On triple or double friction
    pendulums (a `TripleIsolatedStructure`) every surface's friction is scaled:
    `series_bounding_design`. A structure with a vertical component is read through to the
    one inside."""
    lower, upper = check_property_factors(lower, upper)
    inner = structure.structure if isinstance(structure, VerticalIsolatedStructure) else structure
    if isinstance(inner, TripleIsolatedStructure):
        return series_bounding_design(inner.pendulum, lower=lower, upper=upper)
    base = getattr(inner, "uniaxial", inner)
    params, _ = base.table().at(base.pressure)
    cases = [scaled_friction(params, factor) for factor in (1.0, upper, lower)]
    return {"f_max": np.array([float(c.f_max) for c in cases]), "delta_f": np.array([float(c.delta_f) for c in cases])}


def series_bounding_design(pendulum: SeriesPendulum, *, lower: float, upper: float) -> dict:
    """The design dict of the three `BOUNDING_CASES` on a triple or double friction pendulum:
    `FRICTION_FACTOR` 1, `upper`, `lower`, which multiplies f_max and delta_f of Eq. 1 on
    every surface (`SeriesPendulum.scaled_friction`; the module docstring's law, surface by
    surface). Radii and capacities are geometry and stay. `ValueError` naming `upper` when
    it takes a surface's f_max above 1."""
    lower, upper = check_property_factors(lower, upper)
    f_max = np.atleast_1d(np.asarray(pendulum.frictions().f_max, float))
    worst = int(np.argmax(f_max))
    if upper * f_max[worst] > 1:
        raise ValueError(f"upper: {upper:g} times the {pendulum.slider_names[worst]} surface's f_max "
                         f"{f_max[worst]:g} is {upper * f_max[worst]:.4g}, above 1; take upper <= "
                         f"{1 / f_max[worst]:.4g}.")
    return {FRICTION_FACTOR: np.array([1.0, upper, lower])}


def surface_frictions(pendulum: SeriesPendulum, factor: float) -> dict:
    """{"f_max": {surface: value}, "delta_f": {surface: value}} [-] of `pendulum`'s surfaces with
    their friction times `factor` (a bounding case of `series_bounding_design`)."""
    scaled = pendulum.scaled_friction(factor)
    return {key: {name: float(np.asarray(getattr(getattr(scaled, f"{name}_friction"), key)))
                  for name in pendulum.slider_names} for key in ("f_max", "delta_f")}


def governing_cases(peaks: dict, converged, *, statistic: str = "mean") -> dict:
    """For each response name -> peaks (3, N) of the three `BOUNDING_CASES`: the `statistic` ("mean"
    or "max") over each case's converged runs and the case with the largest,
    {name: {"nominal": .., "upper": .., "lower": .., "governs": case}}; a case without a
    converged run gives `None` and cannot govern."""
    if statistic not in ("mean", "max"):
        raise ValueError(f"statistic: expected 'mean' or 'max', got {statistic!r}.")
    ok = np.asarray(converged, bool)
    out = {}
    for name, values in peaks.items():
        values = np.asarray(values, float)
        row = {}
        for index, case in enumerate(BOUNDING_CASES):
            kept = values[index][ok[index]]
            row[case] = None if kept.size == 0 else float(kept.mean() if statistic == "mean" else kept.max())
        known = {c: v for c, v in row.items() if v is not None}
        row["governs"] = max(known, key=known.get) if known else None
        out[name] = row
    return out
