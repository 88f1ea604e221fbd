"""The gradient check of a design optimum that sits where a friction pendulum's largest peak
just touches its restrainer.

The restrainer adds k_r max(|u| - d, 0) to the surface's restoring force (Zayas, Low & Mahin
1990, Earthquake Spectra 6(2)). As long as the capacity d lies at or beyond the largest peak

    P_0(x) = max_i max_n |u_i,n|     (over the motions i and time steps n, without restrainer)

no step reaches it and the response is the one without restrainer, whatever d; below P_0 the
restrainer pushes back. The responses therefore have a kink on the surface d = P_0(x) of the
design space: their derivative in d is exactly zero on its free side (d > P_0) and not on its
contact side (d < P_0), and a variable x_j that moves P_0 moves the kink. Where the
displacement limit does not bind, BFGS drives d onto that surface (the base shear falls as d
grows, until the restrainer is no longer reached), and a central difference there straddles
the kink: it averages two slopes, and no derivative can agree with it.

The optimum is AT THE CONTACT when |d - P_0| <= `CONTACT_TOLERANCE` d. There every derivative
is checked one-sided from the kink's point x_0 (x with d = P_0, where the restrainer touches the
peak with zero force): for each variable x_j and direction s = +1, -1 that stays in the box,

    D_s,j = s (-3 f(x_0) + 4 f(x_0 + s h e_j) - f(x_0 + 2 s h e_j)) / (2 h),   h = relative_step |x_j|,

(second-order accurate, Fornberg 1988, Math. Comp. 51(184)) against the forward-mode
derivative on the side of the kink that stencil enters: the free side when
s (delta_j,d - dP_0/dx_j) >= 0, else the contact side; each side's derivative is taken at
x_0 with d = P_0 (1 +/- `SIDE_OFFSET`). A derivative below the rounding resolution of the
difference, `ROUNDING_FACTOR` eps |f| / h, counts as zero on both sides.
"""

import numpy as np

CONTACT_TOLERANCE = 1e-3
"""The optimum sits at the restrainer contact when |d - P_0| <= this times d [-] (P_0 the
largest peak base displacement over the motions without restrainer, d the capacity)."""

SIDE_OFFSET = 1e-8
"""Relative offset of d from P_0 at which the derivative of each side of the kink is taken [-]."""

ROUNDING_FACTOR = 100.0
"""Derivatives below this times eps |f| / h (the rounding resolution of a difference of step
h of values f) count as zero [-]."""

FREE_CAPACITY_FACTOR = 1e6
"""The largest peak without restrainer is read with the capacity set this many times its
upper bound, which no motion reaches [-]."""


def _sides(name, gradient_of_peak, x, bounds, h):
    """[(direction s, side "free" or "contact")] of the one-sided stencils of variable `name`
    that stay in the box (the capacity may leave it: any d > 0 is a surface)."""
    lo, hi = bounds.ranges[name]
    slope = (1.0 if name == "capacity" else 0.0) - gradient_of_peak[name]
    out = []
    for s in (1, -1):
        if name != "capacity" and not lo <= x[name] + 2 * s * h <= hi:
            continue
        out.append((s, "free" if s * slope >= 0 else "contact"))
    return out


def _error(g, d, values, h):
    """|g - D| / max(|g|, |D|), zero where both lie below the difference's rounding resolution."""
    floor = ROUNDING_FACTOR * np.finfo(float).eps * max(abs(v) for v in values) / h
    scale = max(abs(g), abs(d))
    return 0.0 if scale <= floor else abs(g - d) / scale


def restrainer_contact_check(value, jacobian, x: dict, bounds, outputs, *, relative_step=1e-5) -> dict | None:
    """Whether the design `x` (name -> float, with "capacity") sits at the restrainer contact
    and, if so, its one-sided gradient check (see the module docstring).

    **Arguments:** `value`: z -> {output: float, ..., "peak_disp_max": P [m]} (the largest
    true peak over the motions); `jacobian`: z -> {output: {name: float}} of the same outputs
    in forward mode; `bounds` (`Bounds`); `outputs`: the outputs checked ("shear", "disp").

    **Returns:** None without a capacity; else {"at_contact", "capacity", "largest_peak" (P
    at x), "free_largest_peak" (P_0), "gap": (d - P_0) / d, "tolerance"} and, at the contact,
    "checks": [{"variable", "direction" ("forward"/"backward"), "side", "one_sided_difference",
    "derivative" (each {output: value}), "rel_error"}] and "rel_error" (their largest).
    """
    if "capacity" not in x:
        return None
    d = x["capacity"]
    free = dict(x, capacity=FREE_CAPACITY_FACTOR * bounds.ranges["capacity"][1])
    peak_free = value(free)["peak_disp_max"]
    report = {"at_contact": abs(d - peak_free) <= CONTACT_TOLERANCE * d, "capacity": d,
              "largest_peak": value(x)["peak_disp_max"], "free_largest_peak": peak_free,
              "gap": (d - peak_free) / d, "tolerance": CONTACT_TOLERANCE}
    if not report["at_contact"]:
        return report
    gradient_of_peak = jacobian(free)["peak_disp_max"]
    kink = dict(x, capacity=peak_free)
    derivative = {side: jacobian(dict(x, capacity=peak_free * (1 + sign * SIDE_OFFSET)))
                  for side, sign in (("free", 1), ("contact", -1))}
    centre = value(kink)
    checks = []
    for name in bounds.ranges:
        h = relative_step * max(abs(kink[name]), 1e-12)
        for s, side in _sides(name, gradient_of_peak, kink, bounds, h):
            one, two = (value(dict(kink, **{name: kink[name] + k * s * h})) for k in (1, 2))
            difference = {k: s * (-3 * centre[k] + 4 * one[k] - two[k]) / (2 * h) for k in outputs}
            errors = [_error(derivative[side][k][name], difference[k], (centre[k], one[k], two[k]), h)
                      for k in outputs]
            checks.append({"variable": name, "direction": "forward" if s > 0 else "backward", "side": side,
                           "one_sided_difference": difference,
                           "derivative": {k: derivative[side][k][name] for k in outputs},
                           "rel_error": max(errors)})
    report.update(checks=checks, rel_error=max(c["rel_error"] for c in checks))
    return report
