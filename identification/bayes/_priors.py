"""Priors of the Bayesian bearing fit: physical bounds (default) or Table 1 (informative).

Every parameter is sampled on a bounded range; the default ("bounds") prior is

    f_max ~ LogUniform(0.2 m_hi, 5 m_hi)        m_hi = max |F / N| of the records   [-]
    delta_ratio = delta_f / f_max ~ Uniform(0, 1)                                     [-]
    rate_a ~ LogUniform(a_lo, a_hi)            search range of PARAMETER_BOUNDS       [s/m]
    yield_disp ~ LogUniform(1e-4 S, 0.1 S)     S = stroke (peak-to-peak ux)           [m]
    breakaway_ratio - 1 ~ LogUniform(1e-3, b_hi - 1)   b_hi: its search upper bound   [-]
    noise_rel ~ LogUniform(1e-4, 1)            noise standard deviation / RMS force   [-]

Log-uniform (Jeffreys) priors are the scale-free choice for positive constants whose order
of magnitude is unknown (Gelman et al., "Bayesian Data Analysis", 3rd ed., 2013, Sec. 2.8).
With `prior="table1"` the same bounds truncate a log-normal prior (logit-normal for
`delta_ratio`) whose centre and spread are the mean and standard deviation, on that scale,
of the 16 interfaces of Table 1 of Constantinou, Mokha & Reinhorn (1990): an informative
prior for PTFE-steel interfaces. `bounds=` overrides a range; a range outside the physical
one (f_max, rate_a, yield_disp > 0; breakaway_ratio > 1) or not finite is refused.

The ranges come from the one table of the bearing's constants
(`teflon_jax.bearing.PARAMETER_BOUNDS`): the physical ranges as they are, and where a proper
prior needs a finite range, the table's search range (rate_a, breakaway_ratio) or, for f_max
and yield_disp, a range scaled by the record itself (their physical ranges are unbounded and
their search ranges would not follow the record's units of scale).
"""

import dataclasses
import math
from typing import NamedTuple

import numpy as np

from teflon_jax.bearing import PARAMETER_BOUNDS
from teflon_jax.tables import load_table1

PHYSICAL = {name: PARAMETER_BOUNDS[name].physical
            for name in ("f_max", "delta_f", "rate_a", "yield_disp", "breakaway_ratio")}
"""Physical ranges of the five constants (open intervals; `teflon_jax.bearing.PARAMETER_BOUNDS`)."""

BREAKAWAY_OFFSET = 1e-3
"""Smallest b - 1 of the default breakaway prior: it is uniform in log(b - 1), which needs a
positive lower end where the physical range starts at b = 1 [-]."""

SITE = {"f_max": "f_max", "delta_f": "delta_ratio", "rate_a": "rate_a",
        "yield_disp": "yield_disp", "breakaway_ratio": "breakaway_ratio"}
"""Name of the sampled variable of each constant (delta_f is sampled as delta_f / f_max)."""


class PriorShape(NamedTuple):
    """What a compiled sampler needs to know of a prior, without its numbers: the sampled
    site, its `scale` and the `kind` of distribution (`ParameterPrior.kind`)."""

    site: str
    scale: str
    kind: str


@dataclasses.dataclass(frozen=True)
class ParameterPrior:
    """Prior of one sampled variable on `(low, high)`.

    `scale`: "log" (log x), "logit" (log(x / (1 - x))) or "log1" (log(x - 1)): the scale on
    which the prior is uniform (`loc is None`) or a truncated normal N(loc, sd).
    """

    site: str
    low: float
    high: float
    scale: str
    loc: float | None = None
    sd: float | None = None

    def transformed_bounds(self):
        return _forward(self.scale, self.low), _forward(self.scale, self.high)

    @property
    def kind(self) -> str:
        """The distribution of the sampled (base-scale) variable: "uniform_physical" (uniform
        in the physical value on (low, high): delta_ratio), "uniform" (uniform on the scale),
        "normal" (N(loc, sd) on a scale that maps (low, high) to the whole line) or
        "truncated_normal"."""
        if self.loc is None:
            return "uniform_physical" if self.scale == "logit" else "uniform"
        t_lo, t_hi = self.transformed_bounds()
        return "normal" if not (np.isfinite(t_lo) or np.isfinite(t_hi)) else "truncated_normal"

    @property
    def shape(self) -> PriorShape:
        return PriorShape(self.site, self.scale, self.kind)

    def base_values(self) -> np.ndarray:
        """(lower, upper, loc, sd) of the base-scale distribution (`kind`): the numbers a
        compiled sampler takes as data (placeholders 0, 1 where the kind has none)."""
        kind = self.kind
        if kind == "uniform_physical":
            return np.array([self.low, self.high, 0.0, 1.0])
        t_lo, t_hi = (float(x) for x in self.transformed_bounds())
        if kind == "uniform":
            return np.array([t_lo, t_hi, 0.0, 1.0])
        if kind == "normal":
            return np.array([0.0, 1.0, self.loc, self.sd])
        return np.array([t_lo, t_hi, self.loc, self.sd])


def _forward(scale, x):
    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore"):
        if scale == "log":
            return np.log(x)
        if scale == "logit":
            return np.log(x) - np.log1p(-x)
        return np.log(x - 1.0)


def _table1_moments(site):
    rows = load_table1()
    if site == "f_max":
        x = np.log([r.f_max for r in rows])
    elif site == "delta_ratio":
        p = np.array([r.delta_f / r.f_max for r in rows])
        x = np.log(p) - np.log1p(-p)
    elif site == "rate_a":
        x = np.log([r.rate_a for r in rows])
    elif site == "breakaway_ratio":
        x = np.log([r.breakaway_ratio - 1.0 for r in rows])
    else:
        return None, None
    return float(np.mean(x)), float(max(np.std(x, ddof=1), 0.1))


def default_bounds(records) -> dict:
    """Default prior ranges from the record arrays `fx`, `load`, `ux` (module docstring)."""
    mu_hi = max(float(np.max(np.abs(r["fx"] / r["load"]))) for r in records)
    stroke = max(float(np.ptp(r["ux"])) for r in records)
    return {
        "f_max": (0.2 * mu_hi, 5.0 * mu_hi),
        "rate_a": PARAMETER_BOUNDS["rate_a"].search,
        "yield_disp": (1e-4 * stroke, 0.1 * stroke),
        "breakaway_ratio": (PHYSICAL["breakaway_ratio"][0] + BREAKAWAY_OFFSET,
                            PARAMETER_BOUNDS["breakaway_ratio"].search[1]),
    }


def build_priors(free, records, *, prior="bounds", bounds=None) -> dict:
    """The `ParameterPrior` of each free constant, checked against the physical ranges."""
    if prior not in ("bounds", "table1"):
        raise ValueError(f"prior: unknown '{prior}'; use 'bounds' (physical ranges) or "
                         "'table1' (informative, from Table 1 of the paper).")
    bounds = dict(bounds or {})
    unknown = sorted(set(bounds) - set(free))
    if unknown:
        raise ValueError(f"bounds: {', '.join(unknown)} not among the free parameters "
                         f"({', '.join(free)}).")
    ranges = default_bounds(records)
    out = {}
    for name in free:
        site = SITE[name]
        if name == "delta_f":
            if "delta_f" in bounds:
                raise ValueError("bounds['delta_f']: delta_f is sampled as delta_f / f_max in "
                                 "(0, 1); bound f_max instead.")
            lo, hi, scale = 0.0, 1.0, "logit"
        else:
            lo, hi = ranges[name]
            scale = "log1" if name == "breakaway_ratio" else "log"
            if name in bounds:
                lo, hi = _checked_range(name, bounds[name])
        loc, sd = _table1_moments(site) if prior == "table1" else (None, None)
        out[name] = ParameterPrior(site=site, low=lo, high=hi, scale=scale, loc=loc, sd=sd)
    return out


def _checked_range(name, pair):
    try:
        lo, hi = float(pair[0]), float(pair[1])
    except (TypeError, ValueError, IndexError):
        raise ValueError(f"bounds['{name}']: must be a pair (lower, upper), got {pair!r}.") from None
    p_lo, p_hi = PHYSICAL[name]
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ValueError(f"bounds['{name}']: a prior range must be finite (a proper prior), "
                         f"got ({lo}, {hi}).")
    if not lo < hi:
        raise ValueError(f"bounds['{name}']: need lower < upper, got ({lo}, {hi}).")
    if lo <= p_lo or hi > p_hi:
        raise ValueError(
            f"bounds['{name}']: prior range ({lo}, {hi}) is outside the physical range "
            f"({p_lo}, {p_hi}) of {name}; {name} must be > {p_lo}.")
    return lo, hi
