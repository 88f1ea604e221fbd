"""Fit a triple friction pendulum's radii and friction to a bearing test record.

The record's displacement drives the series model of the bearing (`simulate_triple_test`:
three sliders of radii 2 a, b - a and c - a carrying one force, each with Eq. 1 friction at its
surface's velocity and Bouc-Wen's Z; Fenz & Constantinou 2008, Earthquake Spectra 24(4);
Constantinou, Mokha & Reinhorn 1990, Eqs. 1, 3), and Levenberg-Marquardt (optimistix,
`fit_least_squares`) minimises

    S(theta) = sum_i ((F_model,i(theta) - F_i) / N)^2

over the constants theta the record can tell (`triple_fit_plan`), differentiating the simulation in
forward mode. The optimiser sees a, b - a and c - a (all > 0, so the inner surfaces stay the
tighter ones); f_max, delta_f in (0, 1); rate_a and the capacities > 0. Standard errors are
the asymptotic ones, sigma^2 (J^T J)^-1 with sigma^2 = S / (n - p) (Seber & Wild 1989,
Ch. 2), with J taken in the reported constants (a, b, c, ...). The series model is symmetric
in its outer surfaces: a fit whose bottom surface ends up with the larger f_max is reported
with the two swapped (the isolator file's order, bottom the slipperier).
"""

import dataclasses
import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from teflon_jax.bearing import FrictionParameters, TriplePendulum, check_triple_pendulum
from teflon_jax.formats import TestRecord
from teflon_jax.systems import simulate_triple_test

from ..least_squares import covariance_from_jacobian, fit_least_squares
from ._prepare import _normal_load, _record_name
from ._triple_plan import (
    FRICTION_CONSTANTS,
    PARAMETER_NAMES,
    PARAMETER_UNITS,
    SURFACES,
    check_free,
    triple_fit_plan,
)

_EXCESS = {"bottom_radius": "bottom_excess", "top_radius": "top_excess"}
"""The optimiser's b - a and c - a in place of b and c."""


@dataclasses.dataclass
class TripleFit:
    """Result of `fit_triple_pendulum_test` (SI).

    - `bearing`: the fitted `TriplePendulum` (held constants the start's);
    - `parameters`: name -> value of every constant (`PARAMETER_NAMES`); `std_errors`: name ->
      standard error of the fitted ones (inf where the record cannot tell it), None for held;
    - `free`: the fitted names; `held`: held name -> why;
    - `nrmse`: RMS(model - measured) / RMS(measured) of the force; `converged`: the optimiser
      converged and every step of the simulation balanced its sliders; `message`: the
      optimiser's status; `n_steps`; `swapped`: bottom and top exchanged (module docstring);
      `warnings`: why the result may not be usable; `fitted_force` [N]: the model's force
      at the record's samples (like its fx, or (nt, 2) with fy).
    """

    bearing: TriplePendulum
    parameters: dict
    std_errors: dict
    free: tuple
    held: dict
    nrmse: float
    converged: bool
    message: str
    n_steps: int
    swapped: bool
    warnings: list
    fitted_force: np.ndarray

    def to_json_dict(self) -> dict:
        """The JSON report (SI; a "units" map names each constant's unit)."""
        return {
            "isolator": "triple-fp",
            "parameters": self.parameters,
            "std_errors": {k: (v if v is None or math.isfinite(v) else None)
                           for k, v in self.std_errors.items()},
            "units": dict(PARAMETER_UNITS),
            "free": list(self.free),
            "held": dict(self.held),
            "nrmse": self.nrmse,
            "converged": bool(self.converged),
            "message": self.message,
            "n_steps": self.n_steps,
            "bottom_top_swapped": self.swapped,
            "warnings": list(self.warnings),
        }


def triple_parameters(bearing: TriplePendulum) -> dict:
    """name -> value [SI] of every constant of `bearing` (`PARAMETER_NAMES`)."""
    out = {}
    for surface in SURFACES:
        out[f"{surface}_radius"] = float(np.asarray(getattr(bearing, f"{surface}_radius")))
        out[f"{surface}_capacity"] = float(np.asarray(getattr(bearing, f"{surface}_capacity")))
        friction = getattr(bearing, f"{surface}_friction")
        for c in FRICTION_CONSTANTS:
            out[f"{surface}_{c}"] = float(np.asarray(getattr(friction, c)))
    return {n: out[n] for n in PARAMETER_NAMES}


def triple_with_parameters(bearing: TriplePendulum, values) -> TriplePendulum:
    """`bearing` with the constants named in `values` (`PARAMETER_NAMES`, scalars or traced)
    in place of its own; also takes "bottom_excess" / "top_excess" (b - a, c - a)."""
    get = {**_leaves_of(bearing), **values}
    a = get["inner_radius"]
    b = a + values["bottom_excess"] if "bottom_excess" in values else get["bottom_radius"]
    c = a + values["top_excess"] if "top_excess" in values else get["top_radius"]
    frictions = {s: FrictionParameters(*(get[f"{s}_{k}"] for k in FRICTION_CONSTANTS)) for s in SURFACES}
    return TriplePendulum(
        inner_radius=a, bottom_radius=b, top_radius=c, inner_capacity=get["inner_capacity"],
        bottom_capacity=get["bottom_capacity"], top_capacity=get["top_capacity"],
        inner_friction=frictions["inner"], bottom_friction=frictions["bottom"],
        top_friction=frictions["top"], hysteresis=bearing.hysteresis)


def _leaves_of(bearing: TriplePendulum) -> dict:
    """As `triple_parameters`, the leaves kept as they are (traceable)."""
    out = {}
    for surface in SURFACES:
        out[f"{surface}_radius"] = getattr(bearing, f"{surface}_radius")
        out[f"{surface}_capacity"] = getattr(bearing, f"{surface}_capacity")
        for c in FRICTION_CONSTANTS:
            out[f"{surface}_{c}"] = getattr(getattr(bearing, f"{surface}_friction"), c)
    return out


def _residual(params, args):
    start, time, path, force, load = args
    response = simulate_triple_test(triple_with_parameters(start, params), time, path, load)
    return ((response.force - force) / load).reshape(-1)


def _arrays(record: TestRecord, normal_load):
    """(time, displacement (nt,) or (nt, 2), force like it, N) of a time-history record;
    `ValueError` naming what the fit cannot take."""
    name = _record_name(record, 0)
    if record.is_digitised or record.time is None:
        raise ValueError(f"{name}: the triple pendulum fit takes a time history (time, ux, fx); "
                         "this record is a digitised loop.")
    time = np.asarray(record.time, dtype=float)
    steps = np.diff(time)
    if time.size < 10 or not (np.all(steps > 0) and np.ptp(steps) <= 1e-6 * steps.mean()):
        raise ValueError(f"{name}: the triple pendulum fit needs at least 10 samples at a uniform "
                         "time step (the series model is stepped at the record's samples); resample it.")
    load = _normal_load(record, name, normal_load)
    if np.ptp(load) > 1e-9 * np.max(np.abs(load)) or not load[0] > 0:
        raise ValueError(f"{name}: the triple pendulum fit takes a constant positive normal load; "
                         f"the record's N spans {load.min():.6g}-{load.max():.6g} N.")
    if record.is_biaxial:
        path = np.stack([record.ux, record.uy], axis=-1)
        force = np.stack([record.fx, record.fy], axis=-1)
    else:
        path, force = np.asarray(record.ux, float), np.asarray(record.fx, float)
    if np.max(np.abs(path[0])) > 1e-6 * np.max(np.abs(path)):
        raise ValueError(f"{name}: the record starts off the centre (u = {np.ravel(path[0]).tolist()} m); "
                         "the series model starts at rest at u = 0: trim or shift the record.")
    return time, path, force, float(load[0])


def _bounds(names, values):
    """Bounds and the start of the optimiser's variables (module docstring)."""
    bounds, initial = {}, {}
    for name in names:
        key = _EXCESS.get(name, name)
        initial[key] = values[name] - values["inner_radius"] if key in _EXCESS.values() else values[name]
        bounds[key] = (0.0, 1.0) if name.endswith(("f_max", "delta_f")) else (0.0, math.inf)
    return initial, bounds


def fit_triple_pendulum_test(record: TestRecord, initial: TriplePendulum, *, free=None,
                             normal_load: float | None = None, full_model: bool = False,
                             max_steps: int = 200, rtol: float = 1e-10, atol: float = 1e-12) -> TripleFit:
    """Fit a triple pendulum's effective radii, its surfaces' friction (Eq. 1) and, where
    the loop reaches them, its capacities to one test record (module docstring).

    **Arguments:** `record`: a `TestRecord` time history (uniaxial, or biaxial along an
    orbit) at a uniform time step, under a constant normal load (its N column or metadata,
    else `normal_load` [N]); `initial`: the start (`TriplePendulum`, e.g. `load_isolator`);
    the constants it does not free are held at its values; `free`: names to fit
    (`PARAMETER_NAMES`; default: what the record can tell, `triple_fit_plan`); `full_model`: free
    delta_f and rate_a whatever the record's speeds; `max_steps`, `rtol`, `atol`:
    optimistix's Levenberg-Marquardt settings.

    **Returns:** a `TripleFit`. `ValueError` naming a bad record, start or name.
    """
    if not isinstance(initial, TriplePendulum):
        raise ValueError(f"initial: expected a TriplePendulum (e.g. formats.load_isolator), got "
                         f"{type(initial).__name__}.")
    check_triple_pendulum(initial)
    if not (isinstance(max_steps, int) and max_steps >= 1):
        raise ValueError(f"max_steps: must be an integer >= 1, got {max_steps!r}.")
    time, path, force, load = _arrays(record, normal_load)
    start = jax.tree_util.tree_map(lambda x: jnp.asarray(x, float), initial)
    simulate = eqx.filter_jit(simulate_triple_test)
    response = simulate(start, time, path, load)
    if not bool(np.all(np.asarray(response.converged))):
        raise ValueError(f"{_record_name(record, 0)}: the start's series solve does not balance at "
                         f"{int(np.sum(~np.asarray(response.converged)))} samples; use a finer time step.")
    names, held = triple_fit_plan(start, response, time, full_model=full_model)
    if free is not None:
        names = check_free(free)
        held = {n: "held: not in free" for n in PARAMETER_NAMES if n not in names}
    values = triple_parameters(start)
    x0, bounds = _bounds(names, values)
    result = fit_least_squares(_residual, x0, bounds, args=(start, time, path, force, load),
                               max_steps=max_steps, rtol=rtol, atol=atol)
    return _result(start, result, names, held, (time, path, force, load), simulate)


def _reported_jacobian(result, names):
    """The Jacobian in (a, b, c, ...) from the optimiser's (a, b - a, c - a, ...)."""
    column = {n: result.jacobian[:, i] for i, n in enumerate(result.names)}
    jac = np.stack([column[_EXCESS.get(n, n)] for n in names], axis=1)
    if "inner_radius" in names:
        i = names.index("inner_radius")
        for excess in ("bottom_excess", "top_excess"):
            if excess in column:
                jac[:, i] = jac[:, i] - column[excess]
    return jac


def _result(start, result, names, held, data, simulate) -> TripleFit:
    """The `TripleFit` of an optimiser's result (errors in the reported constants)."""
    bearing = triple_with_parameters(start, {k: jnp.asarray(v) for k, v in result.parameters.items()})
    time, path, force, load = data
    response = simulate(bearing, time, path, load)
    model = np.asarray(response.force)
    nrmse = float(np.sqrt(np.mean((model - force) ** 2) / np.mean(force**2)))
    cov, _ = covariance_from_jacobian(_reported_jacobian(result, names), result.residual)
    errors = dict(zip(names, np.sqrt(np.abs(np.diag(cov))).tolist()))
    warnings = []
    balanced = bool(np.all(np.asarray(response.converged)))
    if not balanced:
        warnings.append("the series solve did not balance the sliders at every sample with the "
                        "fitted constants; the fit cannot be trusted (use a finer time step).")
    warnings += [f"{n}: not identifiable from this record (its standard error is infinite); hold "
                 "it (leave it out of free)" for n in names if not math.isfinite(errors[n])]
    bearing, swapped = _bottom_first(bearing)
    parameters = triple_parameters(bearing)
    if swapped:
        errors = {_swap_name(k): v for k, v in errors.items()}
        held = {_swap_name(k): v for k, v in held.items()}
        names = tuple(n for n in PARAMETER_NAMES if n in {_swap_name(k) for k in names})
    try:
        check_triple_pendulum(bearing)
    except ValueError as error:
        warnings.append(f"the fitted constants break the series model's order: {error}")
    return TripleFit(bearing=bearing, parameters=parameters,
                     std_errors={n: errors.get(n) for n in PARAMETER_NAMES}, free=tuple(names),
                     held=held, nrmse=nrmse, converged=bool(result.converged and balanced),
                     message=result.message, n_steps=result.n_steps, swapped=swapped,
                     warnings=warnings, fitted_force=model)


def _swap_name(name: str) -> str:
    surface, rest = name.split("_", 1)
    return {"bottom": "top", "top": "bottom"}.get(surface, surface) + "_" + rest


def _bottom_first(bearing: TriplePendulum):
    """(bearing, swapped): bottom and top exchanged when the bottom's f_max is the larger."""
    if not float(np.asarray(bearing.bottom_friction.f_max)) > float(np.asarray(bearing.top_friction.f_max)):
        return bearing, False
    return dataclasses.replace(
        bearing, bottom_radius=bearing.top_radius, top_radius=bearing.bottom_radius,
        bottom_capacity=bearing.top_capacity, top_capacity=bearing.bottom_capacity,
        bottom_friction=bearing.top_friction, top_friction=bearing.bottom_friction), True
