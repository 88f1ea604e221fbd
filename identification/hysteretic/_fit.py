"""Identification of the Bouc-Wen oscillator from an (input force, displacement) record.

Output-error least squares: minimise sum_k (y_model(t_k) - y_k)^2 / sum_k y_k^2 over
m, c, k, alpha, beta_gamma, beta_delta (nu fixed, default 1) with optimistix
Levenberg-Marquardt (`identification.least_squares.fit_least_squares`), m, c, k, alpha > 0.

Start values (no knowledge of the truth): an equation-error fit of the linear model
m y'' + c y' + K y = u to the record (y', y'' from a cubic spline of y) gives m, c and the
initial stiffness K = k + alpha; the output-error fit then starts from k = alpha = K / 2 and
each sign combination of beta_gamma, beta_delta at +-|K| / (20 max|u|) (z reaches a few
percent of its elastic value at the record's largest force), and keeps the lowest converged
cost. The fitted model's relative RMS error on a record it did not see is `validate`'s answer.
"""

import dataclasses
import math

import jax.numpy as jnp
import numpy as np
from scipy.interpolate import CubicSpline

from ..least_squares import fit_least_squares
from ._model import PARAMETER_NAMES, PARAMETER_UNITS, fine_input, simulate_hysteretic


@dataclasses.dataclass
class HystereticFit:
    """Result of `fit_hysteretic` (SI): estimates, standard errors, fit error, status."""

    parameters: dict
    std_errors: dict
    correlation: np.ndarray
    relative_rms_error: float
    converged: bool
    message: str
    n_sub: int
    nu: float
    starts_tried: int
    warnings: list

    def predict(self, time, u, *, state0=None) -> np.ndarray:
        """Displacement [m] of the fitted model driven by a force record u [N] at `time` [s]."""
        time, u = _check_record(time, u, None)
        p = dict(self.parameters)
        p["nu"] = self.nu
        return np.asarray(simulate_hysteretic(p, time, fine_input(time, u, self.n_sub),
                                              state0=state0))

    def validate(self, time, u, y) -> float:
        """Relative RMS error RMS(y_model - y) / RMS(y) on a record (e.g. one not fitted)."""
        time, u, y = _check_record(time, u, y)
        pred = self.predict(time, u)
        return float(np.sqrt(np.mean((pred - y) ** 2) / np.mean(y**2)))

    def summary(self) -> str:
        lines = [f"{'parameter':<12}{'estimate':>14}{'std. error':>13}  unit"]
        for n in PARAMETER_NAMES:
            lines.append(f"{n:<12}{self.parameters[n]:>14.6g}{self.std_errors[n]:>13.3g}  "
                         f"{PARAMETER_UNITS[n]}")
        lines.append(f"relative RMS error {self.relative_rms_error:.3g}; "
                     f"{'converged' if self.converged else 'NOT converged: ' + self.message}")
        return "\n".join(lines + self.warnings)


def _check_record(time, u, y):
    time = np.asarray(time, dtype=float)
    u = np.asarray(u, dtype=float)
    arrays = [("time", time), ("u", u)] + ([("y", np.asarray(y, dtype=float))] if y is not None
                                           else [])
    for name, x in arrays:
        if x.ndim != 1:
            raise ValueError(f"{name}: must be a 1-D array, got shape {x.shape}.")
        if x.size != time.size:
            raise ValueError(f"{name}: {x.size} samples, but time has {time.size}.")
        if not np.all(np.isfinite(x)):
            i = int(np.argmin(np.isfinite(x)))
            raise ValueError(f"{name}: sample {i} is not finite ({x[i]}).")
    if time.size < 2 or not np.all(np.diff(time) > 0):
        raise ValueError("time: must increase strictly, with at least two samples.")
    if y is None:
        return time, u
    return time, u, arrays[2][1]


def _residual(params, args):
    p = dict(params)
    p["nu"] = args["nu"]
    y = simulate_hysteretic(p, args["time"], args["u_fine"])
    return (y - args["y"]) * args["weight"]


def linear_start(time, u, y):
    """Equation-error fit of m y'' + c y' + K y = u: returns (m, c, K)."""
    spline = CubicSpline(time, y)
    v, a = spline(time, 1), spline(time, 2)
    design = np.stack([a, v, y], axis=1)[5:-5]
    coef, *_ = np.linalg.lstsq(design, u[5:-5], rcond=None)
    return coef


def fit_hysteretic(time, u, y, *, nu: float = 1.0, n_sub: int = 4, initial=None,
                   max_steps: int = 300) -> HystereticFit:
    """Identify m, c, k, alpha, beta_gamma, beta_delta from one record starting at rest.

    **Arguments:** `time` [s], `u` [N] input force, `y` [m] displacement (1-D, same length;
    the record starts at rest); `nu` (fixed exponent); `n_sub` RK4 steps per sample;
    `initial`: start values overriding the equation-error start.

    **Returns:** a `HystereticFit`. Refused: mismatched or non-finite arrays, fewer than 20
    samples per free parameter, a record without motion.
    """
    time, u, y = _check_record(time, u, y)
    if time.size < 20 * len(PARAMETER_NAMES):
        raise ValueError(f"y: {time.size} samples for {len(PARAMETER_NAMES)} parameters; need at "
                         f"least {20 * len(PARAMETER_NAMES)}.")
    if not np.any(y != 0):
        raise ValueError("y: the record has no motion; nothing to identify.")
    m0, c0, k_tot = linear_start(time, u, y)
    warnings = []
    if not (m0 > 0 and k_tot > 0):
        warnings.append(f"equation-error start gave m = {m0:.3g}, K = {k_tot:.3g}; using "
                        "|values|.")
        m0, k_tot = abs(m0), abs(k_tot)
    c0 = c0 if c0 > 0 else 0.01 * 2 * math.sqrt(k_tot * m0)
    b0 = k_tot / (20.0 * np.max(np.abs(u)))
    base = dict(m=m0, c=c0, k=0.5 * k_tot, alpha=0.5 * k_tot)
    starts = [dict(base, beta_gamma=sg * b0, beta_delta=sd * b0)
              for sg in (1.0, -1.0) for sd in (1.0, -1.0)]
    if initial:
        starts = [dict(starts[0], **initial)]
    args = dict(time=jnp.asarray(time), u_fine=jnp.asarray(fine_input(time, u, n_sub)),
                y=jnp.asarray(y), weight=1.0 / float(np.sqrt(np.mean(y**2))), nu=float(nu))
    bounds = {n: (0.0, math.inf) for n in ("m", "c", "k", "alpha")}
    best = None
    for s in starts:
        try:
            res = fit_least_squares(_residual, s, bounds, args=args, max_steps=max_steps)
        except np.linalg.LinAlgError:  # the simulation diverged from this start (z blew up)
            warnings.append(f"start {s} diverged; skipped.")
            continue
        ok = res.converged and np.isfinite(res.cost)
        key = (not ok, res.cost if np.isfinite(res.cost) else np.inf)
        if best is None or key < best[0]:
            best = (key, res)
    if best is None:
        raise RuntimeError("fit_hysteretic: every start diverged; give `initial` values.")
    res = best[1]
    if not res.converged:
        warnings.append(f"solver: {res.message}")
    return HystereticFit(
        parameters=dict(res.parameters), std_errors=dict(res.std_errors),
        correlation=res.correlation,
        relative_rms_error=float(np.sqrt(2.0 * res.cost / y.size)),
        converged=bool(res.converged), message=res.message, n_sub=int(n_sub), nu=float(nu),
        starts_tried=len(starts), warnings=warnings)
