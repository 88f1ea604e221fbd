"""Fit a single friction pendulum's radius and its liner's friction to test records.

The force of a slider on a spherical surface of radius R under the normal load N is

    F = N u / R + F_f(theta),   F_f = m mu(v / n) N Z     (Zayas, Low & Mahin 1990; Eq. 1)

with F_f the flat slider's force of `fit_bearing_test` (constants theta: f_max, delta_f,
rate_a, yield_disp, breakaway_ratio). The curvature k = 1 / R enters F linearly, so for given
theta the least-squares k is closed-form,

    k(theta) = sum_i w_i (F_i - F_f,i) N_i u_i / sum_i w_i (N_i u_i)^2,

and theta for given k is the flat slider's fit of the records less k N u. The two are
alternated from k_0, the regression of F on N u alone (the friction, odd in the velocity,
averages out over whole cycles), until k changes by less than `rtol`: the fixed point is a
stationary point of the weighted sum of squares in (k, theta) together (w_i = 1 / RMS of a
record's friction force, as the flat fit weighs it). The friction of a slider is nearly
orthogonal to N u (it follows the velocity, the restoring force the displacement), so the
alternation converges in a few rounds. The standard error of R is that of k given theta,
carried to R = 1 / k (s_R = s_k / k^2).
"""

import dataclasses
import math

import numpy as np

from teflon_jax.catalogue import SINGLE_FP
from teflon_jax.formats import TestRecord
from teflon_jax.units import STANDARD_GRAVITY

from ._fit import as_records, fit_bearing_test
from ._plan import BearingFit
from ._prepare import _normal_load, _record_name


@dataclasses.dataclass
class PendulumFit:
    """Result of `fit_pendulum_test` (SI).

    - `radius` R [m] and `radius_std_error` [m]; `isolation_period` 2 pi sqrt(R / g) [s];
    - `friction`: the `BearingFit` of the liner's constants on the records less N u / R (its
      `records` hold the friction part: measured less N u / R, and the fitted friction);
    - `iterations`: rounds of the alternation; `converged`: the friction fit converged and
      R settled within the tolerance; `radius_fixed`: R was given, not fitted;
    - `nrmse`: RMS(model - measured) / RMS(measured) of the whole force over all records.
    """

    radius: float
    radius_std_error: float
    isolation_period: float
    friction: BearingFit
    iterations: int
    converged: bool
    radius_fixed: bool
    nrmse: float

    def to_json_dict(self) -> dict:
        """The JSON report (SI): the friction fit's, with the pendulum's entries added."""
        out = self.friction.to_json_dict()
        out.update({
            "isolator": SINGLE_FP.name,
            "radius [m]": self.radius,
            "radius_std_error [m]": None if not math.isfinite(self.radius_std_error) else self.radius_std_error,
            "radius_fixed": self.radius_fixed,
            "isolation_period [s]": self.isolation_period,
            "pendulum_iterations": self.iterations,
            "pendulum_converged": self.converged,
            "friction_nrmse": out["nrmse"],
            "nrmse": self.nrmse,
            "converged": bool(self.converged),
        })
        return out


def _uniaxial(records, normal_load):
    """(record, N) of each record: uniaxial time histories only (`ValueError` naming one)."""
    out = []
    for i, record in enumerate(records):
        name = _record_name(record, i)
        if record.is_digitised or record.is_biaxial:
            raise ValueError(f"{name}: the pendulum fit takes uniaxial time histories (time, ux, fx); "
                             "this record is " + ("a digitised loop." if record.is_digitised else "biaxial."))
        out.append((record, _normal_load(record, name, normal_load)))
    return out


def _less_restoring(record: TestRecord, load, curvature: float) -> TestRecord:
    """`record` with fx less N u k: the friction part of a pendulum's force (the other
    columns, the metadata and the file's name kept)."""
    fx = np.asarray(record.fx) - load * np.asarray(record.ux) * curvature
    return dataclasses.replace(record, fx=fx, normal_load=np.asarray(load, dtype=float))


def pendulum_friction_record(record: TestRecord, radius: float, *, normal_load=None) -> TestRecord:
    """The friction part of a uniaxial pendulum record: fx less N u / R (`radius` R [m] > 0;
    `normal_load` [N] for a record without one). `ValueError` naming a bad radius or a record
    of another kind."""
    _check_radius(radius)
    ((record, load),) = _uniaxial([record], normal_load)
    return _less_restoring(record, load, 1.0 / radius)


def _check_radius(radius) -> None:
    if radius is not None and not (isinstance(radius, (int, float)) and math.isfinite(radius) and radius > 0):
        raise ValueError(f"radius: must be a positive radius of curvature [m], got {radius!r}.")


def _curvature(pairs, friction_forces, weights) -> tuple[float, float]:
    """(k, its standard error) of the weighted least squares of F - F_f on N u."""
    num = den = 0.0
    for (record, load), f_f, w in zip(pairs, friction_forces, weights):
        x = load * np.asarray(record.ux)
        num += w**2 * float(np.sum((np.asarray(record.fx) - f_f) * x))
        den += w**2 * float(np.sum(x**2))
    if not den > 0:
        raise ValueError("records: the slider never leaves the centre (u = 0 throughout); "
                         "the radius cannot be seen.")
    k = num / den
    residual = sum(w**2 * float(np.sum((np.asarray(r.fx) - f_f - k * n * np.asarray(r.ux)) ** 2))
                   for (r, n), f_f, w in zip(pairs, friction_forces, weights))
    size = sum(r.ux.size for r, _ in pairs)
    return k, math.sqrt(residual / max(size - 1, 1) / den)


def _held(fit: BearingFit) -> dict:
    """The constants a friction fit held, as `fixed` of the next round (its reduced law)."""
    return {k: v for k, v in fit.parameters.items() if k not in fit.free and v is not None}


def fit_pendulum_test(records, *, free=None, fixed=None, radius: float | None = None,
                      normal_load: float | None = None, n_starts: int = 8, rtol: float = 1e-12,
                      max_iterations: int = 30, reduce: bool = True) -> PendulumFit:
    """Fit the radius R and the friction constants of a single friction pendulum to one or
    more uniaxial test records (see the module docstring).

    **Arguments:** `free`, `fixed`, `normal_load`, `n_starts`, `reduce`: as `fit_bearing_test`
    for the friction constants; `radius` [m] > 0: hold R at this value (fit the friction
    alone); `rtol`: relative change of k = 1 / R that ends the alternation; `max_iterations`.

    **Returns:** a `PendulumFit`. A `ValueError` names a bad radius, a record of another
    kind, or records in which the restoring force does not show (R not positive or not finite).
    """
    records = as_records(records)
    _check_radius(radius)
    if not (isinstance(max_iterations, int) and max_iterations >= 1):
        raise ValueError(f"max_iterations: must be an integer >= 1, got {max_iterations!r}.")
    pairs = _uniaxial(records, normal_load)
    zero = [np.zeros(r.ux.shape) for r, _ in pairs]
    ones = [1.0] * len(pairs)
    k = 1.0 / radius if radius is not None else _curvature(pairs, zero, ones)[0]
    if not k > 0:
        raise ValueError(f"records: the force does not grow with the displacement (N u regression "
                         f"gives 1 / R = {k:.3g} 1/m): not a pendulum's record; fit it as a flat slider.")
    fit, k_error, iterations, settled = None, 0.0, 0, radius is not None
    for round_ in range(1, max_iterations + 1):
        iterations = round_
        friction_records = [_less_restoring(r, n, k) for r, n in pairs]
        if fit is None:
            fit = fit_bearing_test(friction_records, free=free, fixed=fixed, normal_load=normal_load,
                                   n_starts=n_starts, reduce=reduce)
        else:
            fit = fit_bearing_test(friction_records, free=fit.free, fixed={**_held(fit), **(fixed or {})},
                                   initial={n: fit.parameters[n] for n in fit.free},
                                   normal_load=normal_load, n_starts=1, reduce=False)
        if radius is not None:
            break
        forces = [np.asarray(rec.fitted) for rec in fit.records]
        weights = [1.0 / float(np.sqrt(np.mean(np.asarray(rec.measured) ** 2))) for rec in fit.records]
        k_new, k_error = _curvature(pairs, forces, weights)
        if not k_new > 0:
            raise ValueError(f"records: the fitted 1 / R = {k_new:.3g} 1/m is not positive: the "
                             "restoring force does not show in these records.")
        change, k = abs(k_new - k), k_new
        if change <= rtol * abs(k):
            settled = True
            break
    return _result(pairs, fit, k, k_error, iterations, settled, radius is not None)


def _result(pairs, fit, k, k_error, iterations, settled, fixed_radius) -> PendulumFit:
    """The `PendulumFit` of the last round (nrmse of the whole force at the final k)."""
    res = meas = 0.0
    for (record, load), rec in zip(pairs, fit.records):
        model = np.asarray(rec.fitted) + k * load * np.asarray(record.ux)
        res += float(np.sum((model - np.asarray(record.fx)) ** 2))
        meas += float(np.sum(np.asarray(record.fx) ** 2))
    radius = 1.0 / k
    return PendulumFit(
        radius=radius, radius_std_error=0.0 if fixed_radius else k_error / k**2,
        isolation_period=2 * math.pi * math.sqrt(radius / STANDARD_GRAVITY), friction=fit,
        iterations=iterations, converged=bool(fit.converged and settled), radius_fixed=fixed_radius,
        nrmse=math.sqrt(res / meas))


def refit_pendulum_radius(data, model_force, radius: float) -> float:
    """R [m] refitted beside a friction model of a record less N u / `radius`: the least-squares
    curvature of what the model leaves, k = 1 / R + sum(r N u) / sum((N u)^2), r = `data.force`
    less `model_force` [N] at the samples of `data` (discovery's `AugmentedData` of the record,
    e.g. a search's `result.data` and `result.forces["final"]`)."""
    n = data.n_samples
    load_u = np.asarray(data.normal) / data.in_parallel * np.asarray(data.ux)
    residual = np.asarray(data.force) - np.asarray(model_force)[:n]
    curvature = 1.0 / radius + float(np.sum(residual * load_u)) / float(np.sum(load_u**2))
    if not curvature > 0:
        raise ValueError("radius: the curvature refitted beside the friction model is not positive; "
                         "the restoring force N u / R does not show in what the model leaves.")
    return 1.0 / curvature
