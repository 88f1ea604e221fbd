"""Gradient-based design of sliding isolation systems over a Monte Carlo set of motions.

Smooth statistics of the peak responses (the mean over motions of the `smooth_max` of the base
shear ratio and of the base displacement, see `peak_response`) are differentiable in the
design variables: the isolation period T_b, the bearing contact pressure (through the linear
interpolation of Table 1), the isolation damping and the PTFE constants of Eq. 1. The design
problem of the paper's Fig. 11 (low base shear against a bounded base displacement) becomes

    minimise   J(x) = E[V_s(x)] + rho * max(0, E[D_s(x)] / D_limit - 1)^2
    over       x in [lo, hi] (box bounds),

with V_s, D_s the smooth maxima of the base shear ratio and base displacement, E the mean over
a fixed set of ground motions (common random numbers), and rho the penalty weight. BFGS
works on the variables scaled onto the unit box and projected back onto it
(`minimise_in_box`), so that a bound that is the optimum is reached in a few steps. The
quadratic exterior penalty is C^1, and for a large rho the optimum sits on (just beyond, by about E[V_s]'s slope / (2 rho)) the
displacement limit when the limit is active. The smooth maximum lies below the true one, so
the limit a user states, on the mean TRUE peak, is met by putting in J a limit on E[D_s]
below D_limit by the gap between the two, corrected at the optimum and BFGS restarted
(`optimise_design`'s `peak_corrections`). The limit may apply to the 95th percentile over the
motions instead of the mean (`LIMIT_STATISTICS`): E[D_s] is then replaced by the percentile
of D_s, linearly interpolated between order statistics, which is piecewise linear in the
motions' peaks and so differentiable wherever no two of them swap order (Hyndman & Fan 1996,
Statistician 45(3), definition 7).
Reference: Constantinou, Mokha & Reinhorn (1990), J. Struct. Eng. 116(2), Fig. 11.
"""

import dataclasses
import math
import time
from collections.abc import Mapping

import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import design_space
from ..systems import IsolatedStructure, peak_response
from ._design_box import BoxSolution, minimise_in_box
from ._design_check import GRADIENT_TOLERANCE, design_gradient_check
from ._design_records import components_of, record_duration, record_ground, records_array
from ._design_result import DesignResult
from ._forward_jacobian import forward_jacobian


def expected_response(
    structure: IsolatedStructure,
    design: Mapping,
    records,
    record_time_step: float,
    *,
    duration: float | None = None,
    disp_width=1e-3,
    shear_width=1e-3,
) -> dict:
    """Means over `records` of the smooth peak responses for one `design` (differentiable).

        E[V_s] = (1/N) sum_i M_w(V_i(t) / W_s),   E[D_s] = (1/N) sum_i M_w(u_0,i(t))

    with `M_w` the log-mean-cosh smooth maximum (`smooth_max`).

    **Arguments:**

    - `structure`: an `IsolatedStructure` (`isolated_structure`).
    - `design`: dict of design variables (scalars; traced under grad).
    - `records` (N, nt) [m/s^2] sampled every `record_time_step` [s]; (N, 2, nt), x and y, for
      a structure of two components (`bidirectional_isolated_structure`), whose peaks are the
      resultants'.
    - `duration` [s]: default the record length.
    - `disp_width` [m], `shear_width` [-]: smoothing widths.

    **Returns:** {"shear": E[V_s], "disp": E[D_s], "peak_shear": mean true peak,
    "peak_disp": mean true peak, "disp_p95", "peak_disp_p95": the 95th percentiles over the
    motions of D_s and of the true peak (linear interpolation between order statistics,
    `jnp.percentile`'s default: piecewise linear in the peaks, so differentiable wherever two
    motions' peaks do not swap order), "peak_disp_max": the largest true peak, "converged": all steps of all motions converged,
    "n_failed": motions with a step whose Newton solve did not converge}.
    """
    records = records_array(records, record_time_step, components_of(structure))
    duration = record_duration(records, record_time_step) if duration is None else duration

    def one(values):
        system = structure(record_ground(values, record_time_step), design)
        return peak_response(system, duration, disp_width=disp_width, shear_width=shear_width)

    peaks = jax.vmap(one)(records)
    return {
        "shear": jnp.mean(peaks.smooth_base_shear_ratio),
        "disp": jnp.mean(peaks.smooth_base_disp),
        "peak_shear": jnp.mean(peaks.base_shear_ratio),
        "peak_disp": jnp.mean(peaks.base_disp),
        "disp_p95": jnp.percentile(peaks.smooth_base_disp, 95.0),
        "peak_disp_p95": jnp.percentile(peaks.base_disp, 95.0),
        "peak_disp_max": jnp.max(peaks.base_disp),
        "converged": jnp.all(peaks.converged),
        "n_failed": jnp.sum(~peaks.converged),
    }


LIMIT_STATISTICS = {"mean": ("disp", "peak_disp"), "p95": ("disp_p95", "peak_disp_p95")}
"""The statistics over the motions a displacement limit may apply to: name -> the keys of
`expected_response` of its smoothed and its true value (the mean, the 95th percentile)."""

STATISTIC_NAMES = {"mean": "mean", "p95": "95th-percentile"}
"""The words of each of `LIMIT_STATISTICS` in messages."""


def check_limit_statistic(statistic: str) -> str:
    """`statistic` if it is one of `LIMIT_STATISTICS`, else a `ValueError` naming it."""
    if statistic not in LIMIT_STATISTICS:
        raise ValueError(f"limit_statistic: unknown {statistic!r}; accepted: {', '.join(LIMIT_STATISTICS)}.")
    return statistic


def constrained_response(response: Mapping, statistic: str = "mean") -> dict:
    """`response` (of `expected_response`) with "disp" and "peak_disp" the smoothed and the
    true value of the limited `statistic` (`LIMIT_STATISTICS`), the means kept as
    "mean_disp" and "mean_peak_disp": what `penalised_objective` and the limit read."""
    smooth, true = LIMIT_STATISTICS[check_limit_statistic(statistic)]
    return {**response, "mean_disp": response["disp"], "mean_peak_disp": response["peak_disp"],
            "disp": response[smooth], "peak_disp": response[true]}


def penalised_objective(response: Mapping, disp_limit, penalty):
    """J = E[V_s] + rho max(0, E[D_s] / D_limit - 1)^2 (see the module docstring)."""
    violation = jnp.maximum(response["disp"] / disp_limit - 1.0, 0.0)
    return response["shear"] + penalty * violation**2


@dataclasses.dataclass(frozen=True)
class Bounds:
    """Box bounds of the design variables: name -> (low, high), SI units."""

    ranges: dict

    @property
    def names(self) -> tuple:
        return tuple(self.ranges)

    def to_unit(self, x) -> np.ndarray:
        """s = (x - lo) / (hi - lo) of each variable, in the order of `names` (x a dict): the
        unit box [0, 1]^n that `minimise_in_box` works on."""
        return np.array([(float(x[n]) - lo) / (hi - lo) for n, (lo, hi) in self.ranges.items()])

    def from_unit(self, s) -> dict:
        """x = lo + (hi - lo) s of each variable (s in the order of `names`); a bound is
        returned exactly (s = 0 or 1)."""
        return {n: lo if s_k == 0.0 else hi if s_k == 1.0 else lo + (hi - lo) * float(s_k)
                for (n, (lo, hi)), s_k in zip(self.ranges.items(), s)}

    @property
    def widths(self) -> np.ndarray:
        """hi - lo of each variable, in the order of `names` (dx/ds)."""
        return np.array([hi - lo for lo, hi in self.ranges.values()])


def design_bounds(structure: IsolatedStructure, variables: Mapping) -> Bounds:
    """Checked `Bounds`: every (low, high) must be finite, low < high, and a box the isolator
    of `structure` takes (its `design_space`: each variable inside the data's range, e.g.
    Table 1's pressures, and the corners inside the isolator's model); otherwise a
    `ValueError` naming it."""
    if not variables:
        raise ValueError("variables: give at least one design variable with its (low, high) bounds.")
    space = design_space(structure.isolator)
    ranges = {}
    for name, bound in variables.items():
        if name not in space.variables:
            raise ValueError(f"variables: unknown design variable {name!r}; accepted: {', '.join(space.variables)}.")
        lo, hi = (float(b) for b in bound)
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ValueError(f"{name}: bounds must be finite with low < high, got ({lo}, {hi}).")
        ranges[name] = (lo, hi)
    space.check(structure, ranges)
    return Bounds(ranges)


def gradient_check(fn, x: Mapping, *, relative_step=1e-5) -> tuple[dict, dict, float]:
    """`jax.grad` of scalar `fn(x)` (x a dict of scalars) against central differences

        dJ/dx_k ~ (J(x + h e_k) - J(x - h e_k)) / (2 h),   h = relative_step * |x_k|

    (second-order accurate; float64 recommended). **Returns:** (gradient, finite
    differences, largest relative error max_k |g_k - fd_k| / max(|fd_k|, tiny))."""
    x = {k: jnp.asarray(v, dtype=float) for k, v in x.items()}
    gradient = jax.jit(jax.grad(fn))(x)
    value = jax.jit(fn)
    differences = {}
    errors = []
    for name in x:
        h = relative_step * max(abs(float(x[name])), 1e-12)
        plus = dict(x, **{name: x[name] + h})
        minus = dict(x, **{name: x[name] - h})
        fd = (float(value(plus)) - float(value(minus))) / (2 * h)
        differences[name] = fd
        errors.append(abs(float(gradient[name]) - fd) / max(abs(fd), 1e-300))
    return {k: float(v) for k, v in gradient.items()}, differences, max(errors)


def forward_mode_gradient(fn):
    """`fn` (a function of a small pytree of design variables, returning a scalar or a pytree
    of arrays) whose reverse-mode derivative is computed in forward mode.

    A time-stepping simulation differentiated in reverse mode must keep (or recompute) every
    step of every motion; with a handful of design variables one forward-mode pass per
    variable (`forward_jacobian`) is far cheaper and needs no tape. The
    returned function has a `jax.custom_vjp`, so `jax.grad`, optimistix and optax use it
    unchanged. Not for many variables (cost grows with their number).
    """

    @jax.custom_vjp
    def wrapped(x):
        return fn(x)

    def forward(x):
        value_and_jacobian = forward_jacobian(lambda z: (fn(z), fn(z)), has_aux=True)(x)
        jacobian, value = value_and_jacobian
        return value, jacobian

    def backward(jacobian, cotangent):
        # jacobian: for each output leaf, a tree like x of leaves shaped output + input
        leaves, treedef = jax.tree_util.tree_flatten(cotangent)
        total = None
        for c, per_input in zip(leaves, treedef.flatten_up_to(jacobian)):
            term = jax.tree_util.tree_map(lambda j, c=c: jnp.tensordot(c, j, axes=jnp.ndim(c)), per_input)
            total = term if total is None else jax.tree_util.tree_map(jnp.add, total, term)
        return (total,)

    wrapped.defvjp(forward, backward)
    return wrapped


def optimise_design(
    structure: IsolatedStructure,
    records,
    record_time_step: float,
    *,
    variables: Mapping,
    disp_limit: float,
    start: Mapping | None = None,
    penalty: float = 100.0,
    duration: float | None = None,
    disp_width=1e-3,
    shear_width=1e-3,
    rtol: float = 1e-7,
    atol: float = 1e-9,
    max_steps: int = 200,
    relative_step: float = 1e-5,
    peak_corrections: int = 4,
    limit_statistic: str = "mean",
) -> DesignResult:
    """Minimise the expected base shear subject to a base-displacement limit (BFGS).

    **Arguments:**

    - `structure`: an `IsolatedStructure` giving the fixed (non-design) properties.
    - `records` (N, nt) [m/s^2] ((N, 2, nt) under two components), `record_time_step` [s]: the
      Monte Carlo set (fixed).
    - `variables`: name -> (low, high) bounds [SI] of the design variables, e.g.
      `{"isolation_period": (1.0, 4.0), "pressure": (1000 * PSI, 3000 * PSI)}`.
    - `disp_limit` D_limit [m] > 0 on the mean TRUE peak base displacement (or on its 95th
      percentile over the motions, `limit_statistic="p95"`; `LIMIT_STATISTICS`). BFGS works on
      the smoothed statistic (E[D_s], or the 95th percentile of D_s), which lies below it: the limit on E[D_s] is set below
      D_limit by the gap at the start and corrected by the true mean peak at the optimum,
      BFGS restarting from there, at most `peak_corrections` times (`_limit_on_true_peaks`;
      0: BFGS on E[D_s] <= D_limit alone, and `limit_met` says whether the true peaks meet it).
    - `start`: initial design within the bounds, on one allowed (default: the middle of the
      bounds).
    - `penalty` rho [-]: weight of the squared relative violation.
    - `rtol`, `atol`, `max_steps`: BFGS's tolerances on the last step in the variables scaled
      to the unit box and in J, and its most evaluations per run (`minimise_in_box`).
    - `relative_step`: finite-difference step of the gradient check, relative to each
      variable (`design_gradient_check`).

    **Returns:** a `DesignResult`; check its `converged` (which includes `limit_met`) and
    `messages` before using it.
    """
    tic = time.perf_counter()
    bounds, records, start = _checked_problem(structure, records, record_time_step, variables,
                                              disp_limit, start, peak_corrections)
    response, derivatives = response_derivatives(
        structure, records, record_time_step, bounds.names, duration=duration, disp_width=disp_width,
        shear_width=shear_width, statistic=check_limit_statistic(limit_statistic))

    def run(s, limit, hessian):
        solution = minimise_in_box(_unit_objective(derivatives, bounds, limit), s, penalty=penalty,
                                   rtol=rtol, atol=atol, max_steps=max_steps, hessian=hessian)
        x = bounds.from_unit(solution.value)
        return solution, x, derivatives(x)[0]

    first = time.perf_counter()
    start_response = derivatives(start)[0]  # the first call compiles
    stages = {"compile_and_first_evaluation": time.perf_counter() - first}
    solution, x, final, smooth_limit, steps = _limit_on_true_peaks(
        run, bounds.to_unit(start), start_response, disp_limit, peak_corrections)
    stages["optimiser"] = time.perf_counter() - first
    inward = _inward(solution, bounds.names)
    optimiser_ok = solution.converged and not inward
    first = time.perf_counter()
    check = design_gradient_check(structure, response, x, bounds, relative_step=relative_step,
                                  derivatives=derivatives)
    stages["gradient_check"] = time.perf_counter() - first
    failed, limit_met = int(final["n_failed"]), float(final["peak_disp"]) <= disp_limit
    messages = [*_failures(failed, records.shape[0], optimiser_ok, f"{steps} steps (max_steps="
                           f"{max_steps}, rtol={rtol}, atol={atol})", final, disp_limit, peak_corrections,
                           limit_statistic),
                *(f"{name}: the objective falls into the box from its bound: the bound is not a "
                  "minimum, so the design is not an optimum." for name in inward),
                *check["messages"]]
    return DesignResult(
        optimum=x, objective=float(penalised_objective(final, smooth_limit, penalty)),
        mean_shear=float(final["shear"]), mean_disp=float(final["mean_disp"]),
        peak_shear=float(final["peak_shear"]), peak_disp=float(final["mean_peak_disp"]),
        disp_limit=float(disp_limit), smooth_disp_limit=float(smooth_limit), limit_met=limit_met,
        start={k: float(v) for k, v in start.items()}, steps=steps, optimiser_converged=optimiser_ok,
        simulation_converged=failed == 0, n_failed_motions=failed, at_bounds=check["at_bounds"],
        gradient_rel_error=check["rel_error"], gradient=check["gradient"],
        finite_differences=check["finite_differences"],
        converged=optimiser_ok and failed == 0 and check["rel_error"] <= GRADIENT_TOLERANCE and limit_met,
        messages=tuple(messages), wall_s=time.perf_counter() - tic, limit_statistic=limit_statistic,
        p95_disp=float(final["disp_p95"]), p95_peak_disp=float(final["peak_disp_p95"]),
        restrainer_contact=check["restrainer_contact"], central_rel_error=check["central_rel_error"],
        gradient_check=check["check"], kink_checks=check["kink_checks"], stages_s=stages,
    )


def response_derivatives(structure, records, record_time_step: float, names: tuple, *, duration=None,
                         disp_width=1e-3, shear_width=1e-3, statistic: str = "mean"):
    """The design's responses and their forward-mode derivatives, as one program compiled once.

    **Returns:** (`response`, `derivatives`): `response(x)` is `constrained_response` of
    `expected_response` at the design x (traceable); `derivatives(x)` (x: name -> float, the
    variables `names`) -> (responses {key: float}, jacobian {"shear", "disp" and, with a
    capacity designed, "peak_disp_max": {name: float}}), one call of the compiled program
    (`forward_jacobian`, one forward pass per variable) per new x; the last points are remembered,
    so that the optimiser, its restarts and the gradient check never compute one twice.
    """
    keys = ("shear", "disp") + (("peak_disp_max",) if "capacity" in names else ())

    def response(x):
        return constrained_response(expected_response(
            structure, x, records, record_time_step, duration=duration, disp_width=disp_width,
            shear_width=shear_width), statistic)

    def differentiated(x):
        r = response(x)
        return {k: r[k] for k in keys}, r

    compiled = jax.jit(forward_jacobian(differentiated, has_aux=True))
    remembered = {}

    def derivatives(x):
        point = tuple(float(x[n]) for n in names)
        if point not in remembered:
            jacobian, values = compiled({n: jnp.asarray(v, dtype=float) for n, v in zip(names, point)})
            if len(remembered) >= _REMEMBERED:
                remembered.pop(next(iter(remembered)))
            remembered[point] = ({k: float(v) for k, v in values.items()},
                                 {k: {n: float(d[n]) for n in names} for k, d in jacobian.items()})
        return remembered[point]

    return response, derivatives


_REMEMBERED = 16  # points whose responses `response_derivatives` keeps


def _unit_objective(derivatives, bounds: Bounds, limit: float):
    """s -> (E[V_s], its slope, c, its slope) on the unit box of `bounds` (`minimise_in_box`,
    whose penalty rho max(0, c)^2 completes J), c = D / L - 1 the relative excess of the
    smoothed statistic D over the limit L = `limit` [m]; slopes dx/ds = hi - lo times those
    in x."""
    widths = bounds.widths

    def fun(s):
        values, jacobian = derivatives(bounds.from_unit(s))
        shear, disp = (np.array([jacobian[k][n] for n in bounds.names]) * widths for k in ("shear", "disp"))
        return values["shear"], shear, values["disp"] / limit - 1.0, disp / limit

    return fun


def _inward(solution: BoxSolution, names: tuple) -> tuple:
    """The variables that end on a bound of the box with the objective falling into it (the
    bound is then not a minimum: the first-order conditions fail)."""
    s, g = solution.value, solution.gradient
    return tuple(names[k] for k in range(s.size)
                 if (s[k] == 0.0 and g[k] < 0.0) or (s[k] == 1.0 and g[k] > 0.0))


def _failures(failed: int, n_motions: int, optimiser_ok: bool, steps: str, final, disp_limit: float,
              corrections: int, statistic: str) -> list:
    """Why the optimum of `optimise_design` cannot be used: failed simulations, BFGS not
    converged, the limit on the true peaks not met."""
    messages = []
    if failed:
        messages.append(f"{failed} of {n_motions} motions had a time step whose Newton "
                        "solve did not converge at the optimum: its responses cannot be trusted "
                        "(try a smaller structure time step).")
    if not optimiser_ok:
        messages.append(f"BFGS did not converge after {steps}: the design is not an optimum.")
    if float(final["peak_disp"]) > disp_limit:
        messages.append(f"the {STATISTIC_NAMES[statistic]} true peak base displacement exceeds the limit by "
                        f"{100 * (float(final['peak_disp']) / disp_limit - 1):.2g} % after "
                        f"{corrections} corrections of the limit on the smoothed statistic: the "
                        "limit cannot be met inside the bounds (or more peak_corrections are needed).")
    return messages


def _checked_problem(structure, records, record_time_step, variables, disp_limit, start, corrections):
    """(`Bounds`, records array, start) of `optimise_design`, or a `ValueError` naming the input."""
    if not (disp_limit > 0 and math.isfinite(disp_limit)):
        raise ValueError(f"disp_limit: must be a positive displacement [m], got {disp_limit}.")
    if not (isinstance(corrections, int) and corrections >= 0):
        raise ValueError(f"peak_corrections: must be an integer >= 0, got {corrections!r}.")
    bounds = design_bounds(structure, variables)
    records = records_array(records, record_time_step, components_of(structure))
    if start is None:
        start = {n: 0.5 * (lo + hi) for n, (lo, hi) in bounds.ranges.items()}
    for name, value in start.items():
        lo, hi = bounds.ranges.get(name, (None, None))
        if lo is None or not lo <= float(value) <= hi:
            raise ValueError(f"start: {name} = {value} must lie within its bounds {lo, hi}.")
    return bounds, records, start


PEAK_MARGIN = 2.5e-3
"""The correction on true peaks aims the mean true peak base displacement this fraction of
the limit below it, and accepts it within twice this below the limit [-]."""

def _limit_on_true_peaks(run, s0, start_response, disp_limit: float, corrections: int):
    """BFGS on a limit L on the smoothed mean E[D_s] such that the mean TRUE peak D meets
    the limit D_limit. The smooth maximum lies below the true one (by up to w log(2 n)) and
    the exterior penalty lets the optimum sit slightly beyond L; both gaps change slowly
    along the limit. So L starts at D_limit less the gap D - E[D_s] at the start, and while
    D misses the band [(1 - 2 m) D_limit, D_limit] (m = `PEAK_MARGIN`; below it only while
    the penalty is active) BFGS restarts from the last optimum, with its curvature, on

        L <- L - (D - (1 - m) D_limit),

    at most `corrections` times; `corrections` = 0: L = D_limit. `run(s, L, hessian)` ->
    (a `BoxSolution`, x, response).

    **Returns:** (solution, x, response, the last L [m], BFGS steps).
    """
    limit, s, hessian, steps = float(disp_limit), s0, None, 0
    gap = float(start_response["peak_disp"]) - float(start_response["disp"])
    if corrections and disp_limit - gap > 0:
        limit = disp_limit - gap
    for attempt in range(corrections + 1):
        solution, x, final = run(s, limit, hessian)
        s, hessian = solution.value, solution.hessian
        steps += solution.steps
        peak, active = float(final["peak_disp"]), float(final["disp"]) >= (1 - 1e-3) * limit
        low = peak < (1 - 2 * PEAK_MARGIN) * disp_limit
        change = (1 - PEAK_MARGIN) * disp_limit - peak
        if attempt == corrections or not (peak > disp_limit or (active and low)) or not limit + change > 0:
            break
        limit += change
    return solution, x, final, limit, steps
