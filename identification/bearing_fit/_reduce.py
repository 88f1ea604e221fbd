"""Reduced friction laws: what to fit when the records do not separate f_max, delta_f, rate_a.

Eq. 1 of Constantinou, Mokha & Reinhorn (1990),

    mu(v) = f_max - delta_f exp(-rate_a |v|)                          [-]

has three constants, but a record determines only what its sliding speeds show. Over a
speed range in which `rate_a v << 1` the law is a straight line, `mu ~ (f_max - delta_f) +
delta_f rate_a v`, and any `rate_a` fits with the matching `f_max`, `delta_f`; when the
friction does not change with speed at all, only one number, `mu` itself, is determined.
The least-squares problem is then singular along a curve, the three estimates correlate
at +-1, and the optimiser creeps along the valley until its step budget runs out.

`fit_bearing_test` (default free set) therefore checks the full fit: when a friction-law
constant has a relative standard error above `RELATIVE_ERROR_LIMIT` (50 %), or the fit did
not converge while two of them correlate beyond `CORRELATION_LIMIT`, it refits, in order,

1. `rate_a` held at the full fit's value, `f_max` and `delta_f` free (two numbers: the
   level and the slope of mu over the observed speeds);
2. Coulomb friction with Bouc-Wen: `delta_f = 0`, `mu = f_max` constant [-], `rate_a` then
   has no effect,

and keeps the first whose constants are determined (converged, every friction constant
within the error limit; a strong correlation with small standard errors is kept and noted,
as the level and slope of a straight line correlate when the line is far from v = 0). The result says which constants
were reduced (`BearingFit.reduced`) and why (`BearingFit.reduction`: the speed range,
`exp(-rate_a v)` over it, the largest correlation, the condition number of the scaled
Jacobian, and the nrmse of the full and the reduced model).
"""

import math

import numpy as np

from teflon_jax.bearing import FrictionParameters, sliding_friction

from ._plan import RELATIVE_ERROR_LIMIT, BearingFit

FRICTION_LAW = ("f_max", "delta_f", "rate_a")
"""The constants of Eq. 1 (parallel to the lay) that a reduction may hold."""

CORRELATION_LIMIT = 0.999
"""Two friction-law constants whose estimates correlate beyond this are not separated."""


def unresolved(fit: BearingFit) -> list[str]:
    """Why the fitted friction-law constants are not separately determined (empty if they are).

    Looks at the free constants among `FRICTION_LAW`: a non-finite standard error or one
    above `RELATIVE_ERROR_LIMIT` of the estimate; and, for a fit that did not converge, a
    correlation beyond `CORRELATION_LIMIT` between two of them (the optimiser crept along a
    valley). A converged fit whose constants correlate strongly but have small standard
    errors is determined: the correlation alone is reported in its warnings, not reduced.
    """
    names = [n for n in FRICTION_LAW if n in fit.free]
    reasons = []
    for name in names:
        se, x = fit.std_errors[name], fit.parameters[name]
        if not math.isfinite(se):
            reasons.append(f"{name} has no finite standard error")
        elif se > RELATIVE_ERROR_LIMIT * abs(x):
            reasons.append(f"{name} has a standard error of {se / max(abs(x), 1e-300):.0%}")
    index = {n: fit.free.index(n) for n in names}
    worst = None
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            c = float(fit.correlation[index[a], index[b]])
            if math.isfinite(c) and abs(c) > CORRELATION_LIMIT and (
                    worst is None or abs(c) > abs(worst[2])):
                worst = (a, b, c)
    if worst is not None and (reasons or not fit.converged):
        reasons.append(f"{worst[0]} and {worst[1]} correlate at {worst[2]:+.4f}")
    return reasons


def _speed_text(prepared, rate_a) -> str:
    lows = [p.speed_low for p in prepared if p.speed_low is not None]
    highs = [p.speed_high for p in prepared if p.speed_high is not None]
    if not lows:
        return "the loops give no sliding speeds"
    v_low, v_high = min(lows), max(highs)
    return (f"sliding speeds {v_low:.3g} to {v_high:.3g} m/s (5-95 %), where "
            f"exp(-rate_a v) = {math.exp(-rate_a * v_low):.3g} to "
            f"{math.exp(-rate_a * v_high):.3g} at rate_a = {rate_a:.4g} s/m")


def _max_correlation(fit: BearingFit) -> str:
    names = [n for n in FRICTION_LAW if n in fit.free]
    index = [fit.free.index(n) for n in names]
    sub = np.abs(np.asarray(fit.correlation)[np.ix_(index, index)])
    np.fill_diagonal(sub, 0.0)
    if sub.size < 4 or not np.any(np.isfinite(sub)):
        return "no finite correlation"
    i, j = np.unravel_index(np.nanargmax(sub), sub.shape)
    c = float(np.asarray(fit.correlation)[index[i], index[j]])
    return f"largest correlation {c:+.4f} ({names[i]}, {names[j]})"


def reduce_friction_law(full: BearingFit, prepared, fixed: dict, refit) -> BearingFit:
    """Refit with the reduced friction laws of the module docstring; returns the chosen fit.

    - `full`: the fit with the default free set, for which `unresolved(full)` is not empty.
    - `prepared`: the prepared records (their sliding speeds go into the message).
    - `fixed`: the caller's fixed values.
    - `refit(free, fixed, start) -> BearingFit`: fits the same records with another free set
      from one start (name -> value).

    The returned fit carries `reduced` (name -> what was done with it), `reduction` (why, with
    the numbers) and `full_model` (the full fit's parameters, nrmse and status).
    """
    reasons = unresolved(full)
    others = [n for n in full.free if n not in FRICTION_LAW]
    rate_a = float(full.parameters["rate_a"])
    steps = []
    if "rate_a" in full.free and {"f_max", "delta_f"} <= set(full.free):
        steps.append((("f_max", "delta_f"), {"rate_a": rate_a},
                      {"rate_a": f"held at {rate_a:.4g} s/m (the full fit's value); f_max and "
                                 "delta_f are tied to it"}))
    if "f_max" in full.free:
        steps.append((("f_max",), {"delta_f": 0.0, "rate_a": rate_a},
                      {"delta_f": "fixed at 0: Coulomb friction, mu = f_max at every speed",
                       "rate_a": "no effect (delta_f = 0)"}))
    lows = [p.speed_low for p in prepared if p.speed_low is not None]
    highs = [p.speed_high for p in prepared if p.speed_high is not None]
    v_mid = math.sqrt(min(lows) * max(highs)) if lows else 0.0
    p = full.parameters
    mu_mid = float(sliding_friction(FrictionParameters(p["f_max"], p["delta_f"], rate_a), v_mid))
    tried = []
    chosen = None
    for law, hold, what in steps:
        held = {**fixed, **{k: v for k, v in hold.items() if k in full.free}}
        free = tuple(n for n in full.free if n in law or n in others)
        start = {n: p[n] for n in free}
        if "delta_f" in held and held["delta_f"] == 0.0:
            start["f_max"] = mu_mid  # Coulomb: the friction at the middle of the speed range
        fit = refit(free, held, start)
        left = unresolved(fit)
        tried.append((law, fit, left))
        if fit.converged and not left:
            chosen = (fit, {k: v for k, v in what.items() if k in full.free})
            break
    if chosen is None:
        # even Coulomb friction is not determined: return the smallest model, not clean
        law, fit, left = tried[-1]
        chosen = (fit, {k: v for k, v in steps[-1][2].items() if k in full.free})
        fit.warnings.append("reduced model: " + "; ".join(left or ["did not converge"]))
        fit.clean = False
    fit, reduced = chosen
    status = "converged" if full.converged else "did not converge"
    rejected = "".join(
        f"; with only {', '.join(law_)} of Eq. 1 free, {'; '.join(left_) or 'no convergence'}"
        for law_, fit_, left_ in tried if fit_ is not fit)
    correlation = "" if any("correlate" in r for r in reasons) else f"; {_max_correlation(full)}"
    law_text = ("mu = f_max, constant" if "delta_f" in reduced else
                "Eq. 1 with rate_a held")
    fit.reduction = (
        f"friction law reduced to {law_text}: the full fit (f_max, delta_f, rate_a free) "
        f"{status}, and {'; '.join(reasons)}{rejected}; {_speed_text(prepared, rate_a)}"
        f"{correlation}; condition number of the scaled Jacobian "
        f"{full.condition_number:.3g}; nrmse {full.nrmse:.5f} with all constants, "
        f"{fit.nrmse:.5f} reduced.")
    fit.reduced = reduced
    fit.full_model = {"parameters": dict(full.parameters), "free": list(full.free),
                      "nrmse": full.nrmse, "converged": bool(full.converged),
                      "message": full.message, "condition_number": full.condition_number,
                      "std_errors": dict(full.std_errors)}
    return fit
