"""BFGS on a box for a penalised limit: J(s) = F(s) + rho max(0, c(s))^2 over the unit box.

A bound is a constraint of the design, not of the parametrisation: the design variables are
moved affinely onto the unit box, s = (x - lo) / (hi - lo), and a step that leaves the box is
projected back onto it (s <- clip(s, 0, 1)). Each step (Bertsekas 1982) holds the binding
variables, those on (or within a small distance eps of) a bound with the slope of J pushing
out of the box (s_k = 0 and dJ/ds_k > 0, or s_k = 1 and dJ/ds_k < 0), on that bound, and moves
the free ones by the step d that minimises the model of J on them,

    m(d) = grad(F) . d + d^T A d / 2 + rho max(0, c + grad(c) . d)^2.

A is the BFGS approximation of the Hessian of F + rho max(0, c)^2 less the Gauss-Newton term
of the penalty: a structured secant update (Dennis, Martinez & Tapia 1989) with
y = grad(F)' - grad(F) + 2 rho max(0, c') (grad(c)' - grad(c)), ' at the new point (Nocedal &
Wright 2006, Eq. 6.19, started at (y . y / y . s) I, Eq. 6.20; an update whose curvature is
not positive is skipped); before the first update A = (max |dJ/ds_F| / r) I, the reach r
starting at `FIRST_STEP` and growing by `GROWTH` while whole steps are taken. The penalty is
modelled exactly, one-sided: its curvature switches on where the limit c = 0 is crossed,
which a secant approximation of the whole of J would smear over the steps that cross it. m is
convex and piecewise quadratic, and its minimum is one of two closed forms (`_model_step`).

Along s(t) = clip(s + t d, 0, 1), t is reduced from 1 until the projected Armijo condition
J(s(t)) <= J(s) + c_A dJ/ds . (s(t) - s) holds, each time to the minimum of the parabola
through J(s), its slope and J(s(t)), within [t / 10, t / 2] (Nocedal & Wright Sec. 3.5), or
until the trial step is itself below the tolerance (where J's rounding may decide the Armijo
test). The iteration ends when a step changes every s_k by less than atol + rtol |s_k| and J
by less than atol + rtol |J| (optimistix's Cauchy test), or when no variable is free. A
variable that ends on a bound is then a minimum there in the sense of the first-order
(Karush-Kuhn-Tucker) conditions: J rises into the box from it. Unlike a map through a sigmoid
onto the box, the slope in s does not fade near a bound, so a variable whose optimum is a
bound reaches it in a few steps. The solver is a host loop over a function of s (one compiled
call per step), so that the same compiled function serves every run and every check.

References: D. P. Bertsekas (1982), "Projected Newton methods for optimization problems with
simple constraints", SIAM J. Control Optim. 20(2); J. E. Dennis, H. J. Martinez & R. A.
Tapia (1989), "Convergence theory for the structured BFGS secant method with an application
to nonlinear least squares", J. Optim. Theory Appl. 61(2); Nocedal & Wright, "Numerical
Optimization", 2nd ed., 2006, Sec. 3.5, 6.1, 16.7 and 17.1 (the quadratic penalty).
"""

import dataclasses

import numpy as np

ARMIJO_SLOPE = 1e-4
"""The fraction c of the predicted decrease a step must achieve (projected Armijo) [-]."""

NEAR = 1e-2
"""The largest distance of a variable from its bound (a fraction of its range) at which a
slope pushing out of the box moves it onto the bound [-]."""

FIRST_STEP = 1e-6
"""Before BFGS has curvature, the first step moves a variable about this fraction of its range
where the penalty does not hold it: small, so that a step does not leap over a feature of J
(a kink, a flat piece) that the slope at the start cannot see [-]."""

GROWTH = 10.0
"""Until BFGS has curvature, a step taken whole lets the next one reach this many times
further (up to the whole range); one cut short by the line search, as far as it went [-]."""


@dataclasses.dataclass(frozen=True)
class BoxSolution:
    """The outcome of `minimise_in_box`: `value` (s in [0, 1]^n), `objective` J and `gradient`
    dJ/ds there, `limit` c there, `steps` (evaluations of J, rejected trial steps included), `converged` (the
    Cauchy test met, or no free variable left), `binding` (indices on a bound with the slope
    pushing out) and `hessian` (the BFGS part A of the Hessian, to start a related run with)."""

    value: np.ndarray
    objective: float
    gradient: np.ndarray
    limit: float
    steps: int
    converged: bool
    binding: tuple
    hessian: np.ndarray | None


def binding_variables(s: np.ndarray, g: np.ndarray) -> np.ndarray:
    """True where s_k lies on a bound of [0, 1] and the slope g_k points out of the box."""
    return ((s <= 0.0) & (g > 0.0)) | ((s >= 1.0) & (g < 0.0))


def _model_step(hessian, gf, c, gc, penalty):
    """The minimum d of grad(F) . d + d^T A d / 2 + rho max(0, c + grad(c) . d)^2 (A positive
    definite): the step of A alone, d_A = -A^-1 grad(F), where it keeps l = c + grad(c) . d <= 0;
    else the minimum of the quadratic with the penalty on both sides,

        d = d_A - A^-1 grad(c) 2 rho l(d_A) / (1 + 2 rho grad(c)^T A^-1 grad(c)),

    whose l(d) = l(d_A) / (1 + 2 rho grad(c)^T A^-1 grad(c)) >= 0 lies where the one-sided
    penalty is the two-sided one."""
    plain = -np.linalg.solve(hessian, gf)
    excess = c + gc @ plain
    if excess <= 0.0:
        return plain
    towards = np.linalg.solve(hessian, gc)
    return plain - towards * 2 * penalty * excess / (1 + 2 * penalty * (gc @ towards))


def _near_bounds(s, g):
    """The move onto a bound of each variable within eps of it whose slope g_k pushes out of the
    box (NaN elsewhere), eps = min(`NEAR`, max_k |s_k - clip(s_k - g_k, 0, 1)|) (Bertsekas 1982:
    a variable next to its bound is held there, so that a projection does not cut the step
    of the others short)."""
    eps = min(NEAR, float(np.max(np.abs(s - np.clip(s - g, 0.0, 1.0)))))
    move = np.full_like(s, np.nan)
    move[(s <= eps) & (g > 0.0)] = 0.0
    move[(s >= 1.0 - eps) & (g < 0.0)] = 1.0
    return move - s


def _direction(hessian, point, penalty, s, reach):
    """The step: the variables next to a bound onto it (`_near_bounds`), and the model's step of
    the others for those moves (`_model_step`), A = `hessian` or, without one yet,
    (max |dJ/ds_F| / `reach`) I; steepest descent of that length where the step is no
    descent."""
    _, gf, c, gc, g = point
    d = _near_bounds(s, g)
    free = np.isnan(d)
    d[free] = 0.0
    if not free.any():
        return d
    scale = max(np.max(np.abs(g[free])), np.finfo(float).tiny) / reach
    model = hessian if hessian is not None else scale * np.eye(g.size)
    try:
        d[free] = _model_step(model[np.ix_(free, free)], gf[free] + model[np.ix_(free, ~free)] @ d[~free],
                              c + gc[~free] @ d[~free], gc[free], penalty)
    except np.linalg.LinAlgError:
        d[free] = 0.0
    if np.dot(d, g) < 0.0:  # with the moves onto the bounds
        return d
    d[free] = -g[free] / scale
    return d


def _bfgs_update(hessian, step, change):
    """B + y y^T / (y . s) - B s s^T B / (s^T B s) (Nocedal & Wright Eq. 6.19), started at
    (y . y / y . s) I; unchanged where the curvature y . s is not positive."""
    curvature = float(np.dot(change, step))
    if not curvature > 1e-12 * np.linalg.norm(change) * np.linalg.norm(step):
        return hessian
    if hessian is None:
        hessian = np.eye(step.size) * float(np.dot(change, change)) / curvature
    bs = hessian @ step
    return hessian + np.outer(change, change) / curvature - np.outer(bs, bs) / float(np.dot(step, bs))


def _backtrack(rise: float, slope: float) -> float:
    """The factor on t of a rejected step: the minimum of the parabola through J(s) with slope
    `slope` (g . (s(t) - s) < 0) that rises by `rise` at the trial, within [1/10, 1/2]."""
    if not (np.isfinite(rise) and slope < 0.0 and rise > slope):
        return 0.1
    return float(np.clip(-slope / (2.0 * (rise - slope)), 0.1, 0.5))


def _penalised(fun, penalty):
    """s -> (J, grad(F), c, grad(c), grad(J)) of `fun`'s (F, grad(F), c, grad(c))."""

    def point(s):
        f, gf, c, gc = fun(s)
        gf, gc, excess = np.asarray(gf, dtype=float), np.asarray(gc, dtype=float), max(float(c), 0.0)
        return float(f) + penalty * excess**2, gf, float(c), gc, gf + 2 * penalty * excess * gc

    return point


def minimise_in_box(fun, s0, *, penalty: float = 0.0, rtol: float = 1e-7, atol: float = 1e-9,
                    max_steps: int = 200, hessian=None) -> BoxSolution:
    """Minimise J(s) = F(s) + `penalty` max(0, c(s))^2 over the unit box [0, 1]^n from `s0`
    (projected structured BFGS, module docstring).

    **Arguments:** `fun(s)` -> (F, dF/ds, c, dc/ds) (floats and (n,) arrays) at s in the box
    (c = 0 and its slope zero where there is no limit); `s0` (n,) (clipped onto the box);
    `rtol`, `atol`: the Cauchy test on the last step (as optimistix's BFGS); `max_steps`: most
    evaluations of `fun`; `hessian`: an (n, n) BFGS part A to start from (e.g. a previous
    run's on a related objective), else none.

    **Returns:** a `BoxSolution`.
    """
    point = _penalised(fun, penalty)
    s = np.clip(np.asarray(s0, dtype=float), 0.0, 1.0)
    here = point(s)
    steps, converged, reach = 1, False, FIRST_STEP

    def small(trial, there):  # optimistix's Cauchy test on a step
        return (np.all(np.abs(trial - s) < atol + rtol * np.abs(trial))
                and abs(there[0] - here[0]) < atol + rtol * abs(there[0]))

    while steps < max_steps:
        d = _direction(hessian, here, penalty, s, reach)
        if not d.any():  # every variable on a bound, its slope pushing out
            converged = True
            break
        t, accepted = 1.0, False
        while steps < max_steps and not accepted:
            trial = np.clip(s + t * d, 0.0, 1.0)
            there = point(trial)
            steps += 1
            slope = float(np.dot(here[4], trial - s))
            accepted = np.isfinite(there[0]) and (there[0] <= here[0] + ARMIJO_SLOPE * slope or small(trial, there))
            if not accepted:
                t *= _backtrack(there[0] - here[0], slope)
        if not accepted:
            break
        change = there[1] - here[1] + 2 * penalty * max(there[2], 0.0) * (there[3] - here[3])
        if hessian is None:
            reach = min(1.0, reach * GROWTH) if t == 1.0 else reach * t
        hessian = _bfgs_update(hessian, trial - s, change)
        converged = small(trial, there)
        s, here = trial, there
        if converged:
            break
    binding = tuple(int(k) for k in np.flatnonzero(binding_variables(s, here[4])))
    return BoxSolution(s, here[0], here[4], here[2], steps, converged, binding, hessian)
