"""Covariance, standard errors and correlations of a least-squares fit from its Jacobian."""

from typing import NamedTuple

import numpy as np
import optimistix as optx

SOLVERS = ("levenberg_marquardt", "levenberg_marquardt_scaled", "gauss_newton")


class LeastSquaresResult(NamedTuple):
    """Outcome of `fit_least_squares` (numpy / Python values, physical parameters).

    - `parameters`: name -> estimate.
    - `std_errors`: name -> standard error (`inf` when not identifiable from the residuals).
    - `correlation`: (p, p) correlation matrix in the order of `names`.
    - `names`: parameter names, in the order of `correlation` and `jacobian` columns.
    - `residual`: residual vector at the optimum.
    - `cost`: half the sum of squared residuals, `0.5 * sum(residual**2)`.
    - `converged`: whether optimistix reported success.
    - `message`: the solver's status in words (and notes on singular Jacobians).
    - `n_steps`: solver steps taken.
    - `jacobian`: (n, p) Jacobian of the residuals in the physical parameters.
    """

    parameters: dict[str, float]
    std_errors: dict[str, float]
    correlation: np.ndarray
    names: tuple[str, ...]
    residual: np.ndarray
    cost: float
    converged: bool
    message: str
    n_steps: int
    jacobian: np.ndarray


def covariance_from_jacobian(jacobian, residual) -> tuple[np.ndarray, list[str]]:
    """Asymptotic covariance `sigma^2 (J^T J)^-1`, `sigma^2 = SSR / (n - p)`.

    **Arguments:** `jacobian` (n, p) of the residuals in the physical parameters at the
    optimum; `residual` (n,) there.

    **Returns:** `(covariance (p, p), notes)`. Columns of `J` that carry no information (zero,
    or linearly dependent on the others) give `inf` variances and a note naming the index.
    """
    jac = np.asarray(jacobian, dtype=float)
    res = np.asarray(residual, dtype=float)
    n, p = jac.shape
    notes = []
    dof = n - p
    if dof <= 0:
        notes.append(f"only {n} residuals for {p} parameters: no standard errors")
        return np.full((p, p), np.inf), notes
    sigma2 = float(res @ res) / dof
    # Scale columns so that the conditioning test is independent of parameter units.
    norms = np.linalg.norm(jac, axis=0)
    safe = np.where(norms > 0, norms, 1.0)
    scaled = jac / safe
    u, s, vt = np.linalg.svd(scaled, full_matrices=False)
    tol = max(n, p) * np.finfo(float).eps * (s[0] if s.size and s[0] > 0 else 1.0) * 1e3
    good = s > tol
    inv = (vt[good].T / s[good] ** 2) @ vt[good]
    cov = sigma2 * inv / np.outer(safe, safe)
    null = vt[~good]
    involved = np.any(np.abs(null) > 1e-3, axis=0) if null.size else np.zeros(p, dtype=bool)
    bad = np.flatnonzero((norms == 0) | involved)
    for i in bad:
        cov[i, :] = np.inf
        cov[:, i] = np.inf
        notes.append(f"parameter {i} not identifiable (singular Jacobian)")
    return cov, notes


def correlation_from_covariance(cov):
    d = np.sqrt(np.diag(cov))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(d, d)
    corr[~np.isfinite(corr)] = np.nan
    np.fill_diagonal(corr, np.where(np.isfinite(d), 1.0, np.nan))
    return corr


def summarise(names, x, residual, jacobian, result_code, n_steps) -> LeastSquaresResult:
    """Build a `LeastSquaresResult` from the raw outputs of one solve (numpy)."""
    x = np.asarray(x, dtype=float)
    residual = np.asarray(residual, dtype=float)
    jacobian = np.asarray(jacobian, dtype=float).reshape(residual.size, len(names))
    code = int(result_code)
    converged = code == 0
    message = "converged" if converged else _result_message(code)
    if not np.all(np.isfinite(residual)):
        converged = False
        message = "non-finite residuals at the final parameters"
    cov, notes = covariance_from_jacobian(jacobian, residual)
    notes = [note.replace(f"parameter {i} ", f"{names[i]} ") for note in notes
             for i in range(len(names)) if note.startswith(f"parameter {i} ")] + [
        note for note in notes if not note.startswith("parameter ")]
    if notes:
        message = message + "; " + "; ".join(notes)
    std = np.sqrt(np.abs(np.diag(cov)))
    return LeastSquaresResult(
        parameters={name: float(x[i]) for i, name in enumerate(names)},
        std_errors={name: float(std[i]) for i, name in enumerate(names)},
        correlation=correlation_from_covariance(cov),
        names=tuple(names),
        residual=residual,
        cost=float(0.5 * residual @ residual),
        converged=converged,
        message=message,
        n_steps=int(n_steps),
        jacobian=jacobian,
    )


def _result_message(code: int) -> str:
    """The optimistix status message of a result code."""
    names = list(optx.RESULTS._name_to_item)
    messages = optx.RESULTS._index_to_message
    if 0 <= code < len(messages):
        text = f"{names[code]}: {messages[code].splitlines()[0]}"
    else:
        text = f"optimistix result code {code}"
    return "not converged (" + text + ")"
