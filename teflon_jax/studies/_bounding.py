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

Bounds from data (`posterior_friction_bounds`): where the bearing's constants come with a
posterior (K draws of a Bayesian fit), each Eq. 1 constant of the bound cases is a quantile of
its draws instead of a factor times the point estimate. A constant enters mu(v) one way at
every velocity,

    d mu / d f_max = 1 > 0,   d mu / d delta_f = -exp(-a |v|) < 0,   d mu / d a = delta_f |v| exp(-a |v|) >= 0,

so the upper case takes the upper quantile of f_max and a and the lower quantile of delta_f,
the lower case the other ends: with every constant inside its quantile interval, mu(v) lies
between the two cases' curves at every velocity. The bounds are reported as factors of the
point estimate (`friction_factors`), beside user-given factors, which are (lambda, lambda, 1).
"""

import equinox as eqx
import jax
import numpy as np

from ..bearing import FRICTION_FACTOR, FrictionParameters, SeriesPendulum, SlidingBearing

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
    bearing (its given bearing's, else Table 1's at its pressure; an `IsolatedStructure` in one
    or two components) times 1, `upper` and `lower` (module docstring). Values that leave the physical range
    (f_max' > 1) are refused when the run checks its design. On triple or double friction
    pendulums (an `IsolatedStructure` with a `pendulum`) every surface's friction is scaled:
    `series_bounding_design`. A structure with a vertical component has the same cases. A
    structure built once (`BuiltStructure`: the slab or building on a plan, any isolator) takes
    the factors themselves (`FRICTION_FACTOR`), on every group's bearings or surfaces."""
    lower, upper = check_property_factors(lower, upper)
    if getattr(structure, "system", None) is not None:  # a BuiltStructure: its groups' bearings
        return _factor_design(structure.system, lower, upper)
    if structure.pendulum is not None:
        return series_bounding_design(structure.pendulum, lower=lower, upper=upper)
    bearing = structure.bearing
    params = bearing.friction if bearing is not None else structure.table().at(structure.pressure)[0]
    cases = [scaled_friction(params, factor) for factor in (1.0, upper, lower)]
    return {"f_max": np.array([float(c.f_max) for c in cases]), "delta_f": np.array([float(c.delta_f) for c in cases])}


def _factor_design(system, lower: float, upper: float) -> dict:
    """{`FRICTION_FACTOR`: (1, upper, lower)} for the bearing groups of a built `system`;
    `ValueError` naming `upper` when it takes a group's f_max above 1."""
    bearing = system.bearing
    if isinstance(bearing, SeriesPendulum):
        return series_bounding_design(bearing, lower=lower, upper=upper)
    f_max = float(np.max(np.asarray(bearing.friction.f_max, float)))
    if upper * f_max > 1:
        raise ValueError(f"upper: {upper:g} times the bearings' largest f_max {f_max:g} is {upper * f_max:.4g}, "
                         f"above 1; take upper <= {1 / f_max:.4g}.")
    return {FRICTION_FACTOR: np.array([1.0, upper, lower])}


def series_bounding_design(pendulum: SeriesPendulum, *, lower: float, upper: float) -> dict:
    """The design dict of the three `BOUNDING_CASES` on a triple or double friction pendulum:
    `FRICTION_FACTOR` 1, `upper`, `lower`, which multiplies f_max and delta_f of Eq. 1 on
    every surface (`SeriesPendulum.scaled_friction`; the module docstring's law, surface by
    surface). Radii and capacities are geometry and stay. `ValueError` naming `upper` when
    it takes a surface's f_max above 1."""
    lower, upper = check_property_factors(lower, upper)
    count = len(pendulum.slider_names)  # surfaces first, then a plan's groups where stacked
    f_max = np.asarray(pendulum.frictions().f_max, float).reshape(count, -1).max(axis=1)
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


POSTERIOR_QUANTILES = (0.05, 0.95)
"""Default (lower, upper) quantiles of the posterior bounds (`posterior_friction_bounds`)."""

FRICTION_CONSTANTS = ("f_max", "delta_f", "rate_a")
"""The Eq. 1 constants a posterior bound sets, in `FrictionParameters` order."""

RAISES_FRICTION = {"f_max": True, "delta_f": False, "rate_a": True}
"""Whether a larger value of the constant raises mu(v) of Eq. 1 at every velocity (module
docstring): the upper case takes its upper quantile where True, its lower where False."""


def check_posterior_quantiles(lower: float, upper: float) -> tuple[float, float]:
    """(lower, upper) once both lie in (0, 1) and lower < upper; else `ValueError` naming them."""
    for name, value in (("lower", lower), ("upper", upper)):
        if not (np.isfinite(value) and 0 < value < 1):
            raise ValueError(f"{name}: a quantile must lie strictly between 0 and 1, got {value:g}.")
    if not lower < upper:
        raise ValueError(f"lower: the lower quantile {lower:g} is not below the upper quantile {upper:g}.")
    return float(lower), float(upper)


def posterior_friction_bounds(point: FrictionParameters, posterior, *,
                              quantiles=POSTERIOR_QUANTILES) -> dict[str, FrictionParameters]:
    """The Eq. 1 constants of the three `BOUNDING_CASES` from a posterior (module docstring).

    **Arguments:** `point`: the bearing's constants (the nominal case); `posterior`: a
    `teflon_jax.formats.BearingPosterior` (its `names` and `quantile(name, q)`); `quantiles`
    (lower, upper) in (0, 1).

    **Returns:** {"nominal": point, "upper": .., "lower": ..}, each constant of
    `FRICTION_CONSTANTS` that the posterior samples at the quantile `RAISES_FRICTION` gives
    it, the others kept at the point's. `ValueError` naming `quantiles` when the lower case's
    f_min = f_max - delta_f is not > 0 or the upper case's f_max is above 1, and naming the
    posterior when it samples none of `FRICTION_CONSTANTS`.
    """
    low, high = check_posterior_quantiles(*quantiles)
    sampled = [name for name in FRICTION_CONSTANTS if name in posterior.names]
    if not sampled:
        raise ValueError(f"posterior: samples {', '.join(posterior.names)}, none of the friction constants "
                         f"{', '.join(FRICTION_CONSTANTS)}; it cannot bound the friction.")
    values = {name: float(np.asarray(getattr(point, name))) for name in FRICTION_CONSTANTS}
    cases = {"nominal": point}
    for case, upper in (("upper", True), ("lower", False)):
        case_values = dict(values)
        for name in sampled:
            case_values[name] = posterior.quantile(name, high if RAISES_FRICTION[name] == upper else low)
        cases[case] = FrictionParameters(**case_values)
    f_min = cases["lower"].f_max - cases["lower"].delta_f
    if not f_min > 0:
        raise ValueError(f"quantiles: the lower case's f_max {cases['lower'].f_max:.4g} less its delta_f "
                         f"{cases['lower'].delta_f:.4g} leaves f_min = {f_min:.3g}, not > 0; take quantiles "
                         f"closer together than {low:g},{high:g}.")
    if cases["upper"].f_max > 1:
        raise ValueError(f"quantiles: the upper case's f_max {cases['upper'].f_max:.4g} is above 1; take "
                         f"an upper quantile below {high:g}.")
    return {case: cases[case] for case in BOUNDING_CASES}


def friction_factors(cases: dict) -> dict:
    """{case: {"f_max", "delta_f", "rate_a", "f_min": its value over the nominal case's}} [-] of
    {case: `FrictionParameters`} with a "nominal" entry; user-given factors lambda give
    (lambda, lambda, 1, lambda). A constant that is 0 in the nominal case (delta_f of a
    Coulomb law) has no factor: `None`."""
    def numbers(params):
        values = {name: float(np.asarray(getattr(params, name))) for name in FRICTION_CONSTANTS}
        return values | {"f_min": values["f_max"] - values["delta_f"]}

    nominal = numbers(cases["nominal"])
    return {case: {k: v / nominal[k] if nominal[k] != 0 else None for k, v in numbers(params).items()}
            for case, params in cases.items()}


def friction_bounding_design(cases: dict) -> dict:
    """The `monte_carlo` design dict of the three `BOUNDING_CASES` from {case:
    `FrictionParameters`}: f_max, delta_f and rate_a (3,) in the cases' order, which a
    structure's bearing (Table 1's or a given one) takes in place of its own."""
    return {name: np.array([float(np.asarray(getattr(cases[c], name))) for c in BOUNDING_CASES])
            for name in FRICTION_CONSTANTS}


def with_friction_factors(structure, factors: dict):
    """`structure` (any pytree: a built structure, a slab on bearing groups) with every
    `SlidingBearing` in it running Eq. 1 constants times `factors` {"f_max", "delta_f",
    "rate_a": factor [-]} (a missing name: 1), in both directions of an anisotropic one. With
    (lambda, lambda, 1) this is `SlidingBearing.scaled(lambda)`; a pressure dependence already
    folded in (`SlidingBearing.at_contact_pressure`) multiplies f_max and delta_f alike and so
    commutes with it. `ValueError` when `structure` holds no `SlidingBearing`."""
    unknown = sorted(set(factors) - set(FRICTION_CONSTANTS))
    if unknown:
        raise ValueError(f"factors: unknown constant(s) {unknown}; accepted: {', '.join(FRICTION_CONSTANTS)}.")
    found = []

    def times(params):
        return FrictionParameters(*(getattr(params, name) * factors.get(name, 1.0) for name in FRICTION_CONSTANTS))

    def scale(node):
        if not isinstance(node, SlidingBearing):
            return node
        found.append(node)
        perpendicular = node.friction_perpendicular
        return eqx.tree_at(lambda b: (b.friction, b.friction_perpendicular), node,
                           (times(node.friction), None if perpendicular is None else times(perpendicular)),
                           is_leaf=lambda x: x is None)

    out = jax.tree_util.tree_map(scale, structure, is_leaf=lambda x: isinstance(x, SlidingBearing))
    if not found:
        raise ValueError("structure: has no SlidingBearing whose friction the factors could change.")
    return out
