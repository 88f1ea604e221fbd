"""The gradient check of a design variable whose central difference straddles a kink.

The peak statistics of a time-stepping simulation are piecewise smooth in the design: a step
that enters or leaves the restrainer, two motions whose peaks swap order under a percentile,
a step that sticks instead of sliding, each makes a kink (a jump of the slope) at some x_j.
With many steps near the restrainer, kinks lie close together and one may fall inside the
central stencil [x_j - h, x_j + h]; the central difference then averages two slopes and no
derivative agrees with it, though the forward-mode derivative (that of the piece x lies on)
is right.

Where the central check fails, the one-sided second-order differences (Fornberg 1988, Math.
Comp. 51(184))

    D_s(h) = s (-3 f(x) + 4 f(x + s h e_j) - f(x + 2 s h e_j)) / (2 h),   s = +1, -1,

are taken with the steps h, h/2 and h/4. On a side whose stencil holds no kink,
D_s(h) - D_s(h/2) is the truncation error, 3/4 c h^2 (Richardson), so D_s(h/2) is known to
within |D_s(h) - D_s(h/2)| / 3; a kink of slope jump J inside it changes D_s(h), D_s(h/2) and
D_s(h/4) by different multiples of J (for one kink, never two pairs alike). A side is
CONSISTENT when both spreads are below `SPREAD_FRACTION` of the tolerance (or the rounding
resolution of the differences). A KINK lies within the stencils when a side is not
consistent, or when D_+(h/2) and D_-(h/2) differ by more than the tolerance plus both sides'
error estimates. Then x's own
piece extends to the consistent side (the kink lies on the other, in (x, x + 2 s h]), and the
derivative is checked against that side's D_s(h/2); with both sides consistent the kink sits
at x itself, and the derivative must agree with one of them. With neither consistent (kinks
on both sides) h shrinks tenfold, at most `STEP_REDUCTIONS` times, until one side is
consistent or no kink lies within the smaller stencil (the derivative is then checked against
its central difference). Without a detected kink the central check's verdict stands, so a
derivative wrong on a smooth piece still fails, and one wrong at a kink agrees with neither
side's slope.
"""

import numpy as np

from ._design_contact import ROUNDING_FACTOR

SPREAD_FRACTION = 0.25
"""A one-sided difference is consistent (no kink in its stencil) when it moves by less than
this times the gradient tolerance (relative) between the steps h, h/2 and h/4 [-]."""

STEP_REDUCTIONS = 2
"""How many times the step shrinks tenfold when kinks lie on both sides of x [-]."""


def _one_sided(f, s, step, outputs):
    """{output: D_s} of the values f[offset] at offsets 0, s step, 2 s step."""
    return {k: s * (-3 * f[0.0][k] + 4 * f[s * step][k] - f[2 * s * step][k]) / (2 * step) for k in outputs}


def _analyse(value, x, name, h, tolerance, outputs):
    """One step h: the one-sided differences, each side's consistency and whether a kink lies
    within the stencils (see the module docstring)."""
    offsets = (0.0, h / 4, -h / 4, h / 2, -h / 2, h, -h, 2 * h, -2 * h)
    f = {o: value(dict(x, **{name: x[name] + o})) for o in offsets}
    rounding = {k: ROUNDING_FACTOR * np.finfo(float).eps * max(abs(v[k]) for v in f.values()) / (h / 4)
                for k in outputs}
    sides = {}
    for s, label in ((1, "forward"), (-1, "backward")):
        coarse, fine, finer = (_one_sided(f, s, step, outputs) for step in (h, h / 2, h / 4))
        # h / 4 too: a kink at 0.8 h changes D_s(h) and D_s(h/2) alike (at 0.4 h, D_s(h/2) and D_s(h/4))
        spread = {k: max(abs(coarse[k] - fine[k]), abs(fine[k] - finer[k])) for k in outputs}
        consistent = all(spread[k] <= SPREAD_FRACTION * tolerance * abs(fine[k]) + rounding[k] for k in outputs)
        sides[label] = {"difference": fine, "coarse_difference": coarse, "spread": spread,
                        "consistent": consistent}
    fw, bw = sides["forward"], sides["backward"]
    kink = not (fw["consistent"] and bw["consistent"]) or any(
        abs(fw["difference"][k] - bw["difference"][k])
        > tolerance * max(abs(fw["difference"][k]), abs(bw["difference"][k]))
        + (fw["spread"][k] + bw["spread"][k]) / 3 + 2 * rounding[k] for k in outputs)
    sides["central"] = {"difference": {k: (f[h][k] - f[-h][k]) / (2 * h) for k in outputs}}
    return sides, kink, rounding


def _error(g, d, floor):
    """|g - D| / max(|g|, |D|), zero where both lie below the rounding `floor`."""
    scale = max(abs(g), abs(d))
    return 0.0 if scale <= floor else abs(g - d) / scale


def kink_gradient_check(value, gradient: dict, x: dict, name: str, h: float, tolerance: float) -> dict:
    """The check of the derivative in design variable `name` where its central difference of
    step `h` failed: is there a kink within the stencil, and does the forward-mode derivative
    agree with the one-sided difference on the side x's own piece extends to?

    **Arguments:** `value`: z -> {output: float}; `gradient`: {output: dJ/dx_name} at `x`
    (name -> float); `tolerance`: the largest relative error accepted.

    **Returns:** {"variable", "kink" (bool: the two one-sided slopes disagree beyond their
    error estimates), "side" ("forward", "backward", "central" where kinks on both sides made
    the step shrink until none lay within it, or None: the side checked), "kink_within"
    ([low, high], the variable's interval that holds the kink, or None), "step" (the last h),
    "one_sided_differences" ({"forward", "backward"}: {output: D_s(h/2)}), "consistent"
    ({"forward": bool, "backward": bool}), "derivative", "rel_error" (against the side
    checked; None where no kink was found or neither side is consistent), "reason" (words)}.
    """
    step, x0 = h, x[name]
    for _ in range(STEP_REDUCTIONS + 1):
        sides, kink, rounding = _analyse(value, x, name, step, tolerance, tuple(gradient))
        if not kink or any(sides[s]["consistent"] for s in ("forward", "backward")):
            break
        step /= 10
    central = sides.pop("central")["difference"]
    report = {"variable": name, "kink": kink or step < h, "side": None, "kink_within": None, "step": step,
              "one_sided_differences": {s: v["difference"] for s, v in sides.items()},
              "consistent": {s: v["consistent"] for s, v in sides.items()}, "derivative": dict(gradient),
              "rel_error": None}
    if not kink and step == h:
        report["reason"] = ("no kink within the stencil: the forward and backward differences agree, "
                            "so the central check stands")
        return report
    if not kink:  # kinks on both sides at the step 10 `step`, none within this one
        report.update(side="central", kink_within=[x0 - 20 * step, x0 + 20 * step],
                      rel_error=max(_error(gradient[k], central[k], rounding[k]) for k in gradient),
                      reason=f"kinks lie on both sides of {name} within {20 * step:.3g} and none within "
                      f"{2 * step:.3g}: the derivative is checked against the central difference of "
                      f"step {step:.3g}")
        return report
    clean = [s for s, v in sides.items() if v["consistent"]]
    if not clean:
        report["reason"] = (f"kinks on both sides of {name} within every stencil down to the step "
                            f"{step:.3g}: no one-sided difference can be trusted")
        return report
    errors = {s: max(_error(gradient[k], sides[s]["difference"][k], rounding[k]) for k in gradient) for s in clean}
    side = min(errors, key=errors.get)
    if len(clean) == 2:
        within, where = [x0, x0], f"at {name} = {x0:.6g} itself"
    else:
        s = -1 if side == "forward" else 1  # the kink lies on the other side
        within = sorted([x0, x0 + 2 * s * step])
        where = f"between {name} = {within[0]:.6g} and {within[1]:.6g}"
    report.update(side=side, kink_within=within, rel_error=errors[side],
                  reason=f"a kink lies {where} (the one-sided slopes differ beyond their step-halving "
                  f"error estimates); the derivative is checked against the {side} difference, "
                  "on the piece the design lies on")
    return report
