"""Checks of a design optimum: which variables sit on a bound, and whether the derivative the
optimiser used agrees with finite differences there.

The derivative of the expected responses E[V_s], E[D_s] (`expected_response`) with respect
to design variable x_k is compared with

    central:   (f(x + h e_k) - f(x - h e_k)) / (2 h)                      (interior x_k)
    one-sided: -/+ (3 f(x) - 4 f(x -/+ h e_k) + f(x -/+ 2 h e_k)) / (2 h)  (x_k on a bound)

both second-order accurate, h = relative_step |x_k|. On a bound the stencil points inward:
outside the box the problem is not defined, and where the bound is a tabulated pressure of
Table 1 the friction constants, linearly interpolated, have a kink, so a central difference
there averages two different slopes (the 57 % error of the old default design problem, whose
optimum sat on 3000 psi, was exactly this). A kink inside the box (a Table 1 row strictly
between the bounds) is reported when the optimum sits on it: the derivative is one-sided
there and no gradient check can pass. The kink of a friction pendulum's restrainer at the
largest peak is checked one-sided on each side (`restrainer_contact_check`); any other kink
that falls inside a central stencil (a smaller peak that touches the restrainer, two peaks
that swap order) is found and checked on the design's own side (`kink_gradient_check`).
Reference for the finite-difference formulas: Fornberg (1988), Math. Comp. 51(184).
"""

import jax
import numpy as np

from ..units import PSI
from ._design_contact import ROUNDING_FACTOR, restrainer_contact_check
from ._design_kinks import kink_gradient_check
from ._design_records import components_of, record_duration, record_ground, records_array
from ._forward_jacobian import forward_jacobian

GRADIENT_TOLERANCE = 1e-4
"""Largest relative difference between forward-mode and finite-difference derivatives [-]."""

BOUND_TOLERANCE = 1e-4
"""A variable within this fraction of its range from a bound is reported as on the bound."""

_OUTPUTS = ("shear", "disp")


def bound_side(value: float, lo: float, hi: float) -> int:
    """-1 where `value` lies within `BOUND_TOLERANCE` of the range from its lower bound `lo`, +1
    from its upper bound `hi`, else 0."""
    if value - lo <= BOUND_TOLERANCE * (hi - lo):
        return -1
    if hi - value <= BOUND_TOLERANCE * (hi - lo):
        return 1
    return 0


def _difference(value, x, name, h, side):
    def at(offset):
        return value(dict(x, **{name: x[name] + offset}))

    if side == 0:
        plus, minus = at(h), at(-h)
        values = (plus, minus)
        fd = {k: (plus[k] - minus[k]) / (2 * h) for k in _OUTPUTS}
    else:
        values = centre, one, two = at(0.0), at(side * h), at(2 * side * h)
        fd = {k: side * (-3 * centre[k] + 4 * one[k] - two[k]) / (2 * h) for k in _OUTPUTS}
    floor = {k: ROUNDING_FACTOR * np.finfo(float).eps * max(abs(v[k]) for v in values) / h for k in _OUTPUTS}
    return fd, floor


def _rel_error(g, fd, floor):
    """|g - fd| / max(|g|, |fd|), zero where both lie below the difference's rounding `floor`."""
    scale = max(abs(g), abs(fd))
    return 0.0 if scale <= floor else abs(g - fd) / scale


def design_gradient_check(structure, response, x: dict, bounds, *, relative_step=1e-5,
                          derivatives=None) -> dict:
    """Compare the forward-mode derivatives of E[V_s] and E[D_s] with finite differences at
    the design `x` (name -> float) inside `bounds` (`design_bounds`).

    **Arguments:** `structure` (an `IsolatedStructure`, for its Table 1 rows); `response`:
    x -> dict with "shear" and "disp" (e.g. `expected_response` with its records);
    `relative_step`: h / |x_k|; `derivatives`: x -> (responses {key: float}, jacobian {key:
    {name: float}}) over at least "shear", "disp" (and "peak_disp_max" with a capacity), e.g.
    the optimiser's compiled program (`response_derivatives`), whose responses then give the
    differences too; default: `response` and its forward-mode jacobian, compiled here.

    **Returns:** {"gradient", "finite_differences": {"shear": {name: ..}, "disp": {..}},
    "rel_error": max over outputs and variables of |g - fd| / max(|g|, |fd|),
    "at_bounds": names on a bound, "messages": warnings and reasons, "central_rel_error": the
    error of the central (or bound) differences, "restrainer_contact": None without a capacity,
    else `restrainer_contact_check`'s report, "kink_checks": `kink_gradient_check`'s report
    (with "central_rel_error") of each interior variable whose central check failed (none at
    the restrainer contact), "check":
    "central", "piecewise" (a kink found within a failed central stencil: that variable is
    checked one-sided on the piece x lies on) or "one-sided" (at the restrainer contact)}. A
    derivative and its difference both below the difference's rounding resolution,
    `ROUNDING_FACTOR` eps |f| / h, count as equal. At the restrainer contact "rel_error" is the
    one-sided check's there (the central differences straddle the kink).
    """
    names = tuple(bounds.ranges)
    x = {k: float(x[k]) for k in names}
    keys = _OUTPUTS + (("peak_disp_max",) if "capacity" in names else ())
    value, jacobian = _value_and_jacobian(response, keys, derivatives)

    gradient = {k: v for k, v in jacobian(x).items() if k in _OUTPUTS}
    differences, errors = {k: {} for k in _OUTPUTS}, {}
    at_bounds, messages, on_row = [], [], []
    knots = np.asarray(structure.table().pressures if hasattr(structure, "table") else [], dtype=float)
    for name in names:
        lo, hi = bounds.ranges[name]
        h = relative_step * max(abs(x[name]), 1e-12)
        side = -bound_side(x[name], lo, hi)  # the one-sided differences step into the box
        if side:
            bound = lo if side > 0 else hi
            at_bounds.append(name)
            messages.append(
                f"{name} = {_show(name, x[name])} lies on its {'lower' if side > 0 else 'upper'} "
                f"bound {_show(name, bound)}: the optimum is the bound, not a stationary point "
                "(widen the range if it is admissible); the gradient check there uses one-sided "
                "differences."
            )
        elif name == "pressure":
            near = knots[(np.abs(knots - x[name]) <= 2 * h)]
            if near.size:
                on_row.append(name)
                messages.append(
                    f"pressure = {_show(name, x[name])} sits on Table 1's row at "
                    f"{_show(name, float(near[0]))}, where the linearly interpolated friction "
                    "constants have a kink: the derivative is one-sided there; restrict the "
                    "pressure range to one side of that row."
                )
        fd, floor = _difference(value, x, name, h, side)
        for k in _OUTPUTS:
            differences[k][name] = float(fd[k])
        errors[name] = max(_rel_error(gradient[k][name], fd[k], floor[k]) for k in _OUTPUTS)
    central = float(max(errors.values()))
    contact = restrainer_contact_check(value, jacobian, x, bounds, _OUTPUTS, relative_step=relative_step)
    kinks = []
    if contact is not None and contact["at_contact"]:  # the one-sided check at the contact decides
        rel_error, check = contact["rel_error"], "one-sided"
        messages.append(_contact_message(contact, central))
    else:
        kinks = _kink_checks(value, gradient, x, errors, (*at_bounds, *on_row), relative_step)
        for report in kinks:
            if report["rel_error"] is not None:
                errors[report["variable"]] = report["rel_error"]
            messages.append(f"{report['variable']}: central differences miss by "
                            f"{report['central_rel_error']:.2g}; {report['reason']}.")
        rel_error = float(max(errors.values()))
        check = "piecewise" if any(r["kink"] for r in kinks) else "central"
    if not rel_error <= GRADIENT_TOLERANCE:
        messages.append(
            f"gradient check failed: the derivatives the optimiser used differ from finite "
            f"differences by {rel_error:.3g} (relative; allowed {GRADIENT_TOLERANCE:g}) at the "
            "optimum, so it may not be one."
        )
    return {
        "gradient": gradient,
        "finite_differences": differences,
        "rel_error": rel_error,
        "at_bounds": tuple(at_bounds),
        "messages": tuple(messages),
        "central_rel_error": central,
        "restrainer_contact": contact,
        "check": check,
        "kink_checks": tuple(kinks),
    }


def _value_and_jacobian(response, keys, derivatives):
    """(z -> {key: float}, z -> {key: {name: float}}) of `design_gradient_check`: from
    `derivatives` where given, else `response` and its `forward_jacobian`, each compiled."""
    if derivatives is not None:
        return (lambda z: {k: derivatives(z)[0][k] for k in keys},
                lambda z: {k: derivatives(z)[1][k] for k in keys})
    outputs = jax.jit(lambda z: {k: response(z)[k] for k in keys})
    forward = jax.jit(forward_jacobian(lambda z: {k: response(z)[k] for k in keys}))
    return (lambda z: {k: float(v) for k, v in outputs(z).items()},
            lambda z: {k: {n: float(v) for n, v in d.items()} for k, d in forward(z).items()})


def _kink_checks(value, gradient, x, errors, skipped, relative_step) -> list:
    """`kink_gradient_check`'s report (with "central_rel_error") of each variable whose central
    check failed, but those `skipped` (on a bound, or on a row of Table 1, a kink of the data
    that the optimum must not sit on)."""
    reports = []
    for name, error in errors.items():
        if error <= GRADIENT_TOLERANCE or name in skipped:
            continue
        h = relative_step * max(abs(x[name]), 1e-12)
        report = kink_gradient_check(value, {k: gradient[k][name] for k in _OUTPUTS}, x, name, h,
                                     GRADIENT_TOLERANCE)
        reports.append({**report, "central_rel_error": error})
    return reports


def _contact_message(contact, central) -> str:
    """The note of an optimum at the restrainer contact (`restrainer_contact_check`)."""
    return (f"capacity = {_show('capacity', contact['capacity'])} sits at the restrainer contact: the "
            f"largest peak without restrainer, {_show('capacity', contact['free_largest_peak'])}, lies "
            f"a fraction {abs(contact['gap']):.2g} {'below' if contact['gap'] >= 0 else 'above'} it "
            f"(at most {contact['tolerance']:g}), where the responses have a kink (their derivative in "
            "the capacity is zero beyond it); the gradient there is checked one-sided, on each side "
            f"of the kink (largest relative error {contact['rel_error']:.2g}; central differences, "
            f"which straddle it: {central:.2g}).")


def _show(name, value):
    if name == "pressure":
        return f"{value / PSI:.6g} psi"
    if name == "isolation_period":
        return f"{value:.6g} s"
    if name in ("radius", "capacity"):
        return f"{value:.6g} m"
    return f"{value:.6g}"


def percentile_disp_gradient_check(structure, design: dict, records, record_time_step: float, *,
                                   q: float = 95.0, duration: float | None = None, disp_width=1e-3,
                                   relative_step: float = 1e-5) -> dict:
    """The q-th percentile over the motions of the smooth peak base displacement D_s (the
    log-mean-cosh maximum of `peak_response`, width `disp_width` [m]; linear interpolation
    between order statistics, as numpy's default) at the design `design` (name -> float), its
    forward-mode derivative in each design variable, and central differences
    (f(x + h e_k) - f(x - h e_k)) / (2 h), h = `relative_step` |x_k|.

    **Returns:** {"value" [m], "gradient", "finite_differences": {name: ..} [m per unit],
    "rel_error": max_k |g_k - fd_k| / max(|g_k|, |fd_k|)}.
    """
    import jax.numpy as jnp

    from ..systems import peak_response

    records = records_array(records, record_time_step, components_of(structure))
    duration = record_duration(records, record_time_step) if duration is None else duration

    def percentile(x):
        def one(values):
            system = structure(record_ground(values, record_time_step), x)
            return peak_response(system, duration, disp_width=disp_width)["smooth_base_disp_resultant"]

        return jnp.percentile(jax.vmap(one)(records), q)

    x = {k: jnp.asarray(float(v)) for k, v in design.items()}
    value = jax.jit(percentile)
    gradient = {k: float(v) for k, v in jax.jit(forward_jacobian(percentile))(x).items()}
    differences = {}
    for name in x:
        h = relative_step * max(abs(float(x[name])), 1e-12)
        plus, minus = (float(value(dict(x, **{name: x[name] + s * h}))) for s in (1, -1))
        differences[name] = (plus - minus) / (2 * h)
    rel_error = max(abs(gradient[n] - differences[n]) / max(abs(gradient[n]), abs(differences[n]), 1e-300)
                    for n in x)
    return {"value": float(value(x)), "gradient": gradient, "finite_differences": differences,
            "rel_error": float(rel_error)}
