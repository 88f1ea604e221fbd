"""Fit a triple or double friction pendulum's radii and friction to a bearing test record.

The record's displacement drives the series model of the bearing (`imposed_path_test`:
the triple's three sliders of radii 2 a, b - a and c - a, or the double's two of radii R_1 and
R_2, carrying one force, each with Eq. 1 friction at its surface's velocity and Bouc-Wen's Z;
Fenz & Constantinou 2006, Earthquake Engng Struct. Dyn. 35; 2008, Earthquake Spectra 24(4);
Constantinou, Mokha & Reinhorn 1990, Eqs. 1, 3), and Levenberg-Marquardt (optimistix,
`fit_least_squares`) minimises

    S(theta) = sum_i ((F_model,i(theta) - F_i) / N_i)^2

over the constants theta the record can tell (`triple_fit_plan`), differentiating the simulation in
forward mode, with Marquardt's scaled damping (`SOLVER`, as the flat slider's fit). The
optimiser sees a, b - a and c - a of a triple (all > 0, so the inner surfaces stay the tighter
ones), R_1 and R_2 of a double (> 0); f_max in (0, 1) and delta_f as its ratio to f_max in
(0, 1), so that 0 <= delta_f <= f_max (`_ratio`; a held delta_f bounds f_max from below
instead); rate_a and the capacities > 0. Standard errors are the asymptotic ones,
sigma^2 (J^T J)^-1 with sigma^2 = S / (n - p) (Seber & Wild 1989, Ch. 2), with J taken in the
reported constants (a, b, c, ...). The force of sliders in series does not depend on their order, so a loop cannot tell the bottom surface from the top
one: the fit reports them in the start file's order of f_max (a triple's bottom the
slipperier, as its series model needs; a double's as its start file has them), swapping the
two when the optimiser has crossed them (`swapped`).
"""

import dataclasses
import functools
import math
import numbers

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from teflon_jax.bearing import (
    DoublePendulum,
    FrictionParameters,
    SeriesPendulum,
    TriplePendulum,
    check_series_pendulum,
)
from teflon_jax.formats import TestRecord
from teflon_jax.systems import imposed_path_test, normal_load_varies, sampled_path

from ..least_squares import covariance_from_jacobian, fit_least_squares
from ._fit import SOLVER
from ._prepare import _normal_load, _record_name
from ._ratio import (
    from_ratios,
    ratio_bounds,
    result_from_ratios,
    series_ratio_pairs,
    to_ratios,
)
from ._triple_plan import (
    FRICTION_CONSTANTS,
    check_free,
    parameter_names,
    parameter_units,
    triple_fit_plan,
)

_EXCESS = {"bottom_radius": "bottom_excess", "top_radius": "top_excess"}
"""The optimiser's b - a and c - a in place of a triple's b and c."""


@dataclasses.dataclass
class TripleFit:
    """Result of `fit_series_pendulum_test` (SI).

    - `bearing`: the fitted `TriplePendulum` or `DoublePendulum` (held constants the start's);
    - `parameters`: name -> value of every constant (`parameter_names` of its surfaces,
      `TRIPLE_PARAMETER_NAMES` or `DOUBLE_PARAMETER_NAMES`); `std_errors`: name ->
      standard error of the fitted ones (inf where the record cannot tell it), None for held;
    - `free`: the fitted names; `held`: held name -> why;
    - `nrmse`: RMS(model - measured) / RMS(measured) of the force; `converged`: the optimiser
      converged and every step of the simulation balanced its sliders; `message`: the
      optimiser's status; `n_steps`; `swapped`: bottom and top exchanged to the start's order
      (module docstring);
      `warnings`: why the result may not be usable; `fitted_force` [N]: the model's force
      at the record's samples (like its fx, or (nt, 2) with fy); `reference_load` [N]: the
      load the contact pressures are given under (None: the record's constant N).
    """

    bearing: SeriesPendulum
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
    reference_load: float | None = None

    def to_json_dict(self) -> dict:
        """The JSON report (SI; a "units" map names each constant's unit)."""
        return {
            "isolator": self.bearing.isolator,
            "parameters": self.parameters,
            "std_errors": {k: (v if v is None or math.isfinite(v) else None)
                           for k, v in self.std_errors.items()},
            "units": parameter_units(self.bearing.slider_names),
            "free": list(self.free),
            "held": dict(self.held),
            "nrmse": self.nrmse,
            "converged": bool(self.converged),
            "message": self.message,
            "n_steps": self.n_steps,
            "bottom_top_swapped": self.swapped,
            "bottom_top_order": "the start file's order of f_max (a loop cannot tell the two apart)",
            "warnings": list(self.warnings),
            "reference_load": self.reference_load,
        }


SeriesFit = TripleFit
"""`TripleFit`, the result of a triple or double pendulum's fit."""


def triple_parameters(bearing: SeriesPendulum) -> dict:
    """name -> value [SI] of every constant of `bearing` (`parameter_names` of its surfaces)."""
    out = {k: float(np.asarray(v)) for k, v in _leaves_of(bearing).items()}
    return {n: out[n] for n in parameter_names(bearing.slider_names)}


def triple_with_parameters(bearing: SeriesPendulum, values) -> SeriesPendulum:
    """`bearing` (triple or double) with the constants named in `values` (`parameter_names`,
    scalars or traced) in place of its own, its heating and surface parts kept; a triple's
    also takes "bottom_excess" / "top_excess" (b - a, c - a)."""
    get = {**_leaves_of(bearing), **values}
    fields = {}
    for s in bearing.slider_names:
        fields[f"{s}_radius"] = get[f"{s}_radius"]
        fields[f"{s}_capacity"] = get[f"{s}_capacity"]
        fields[f"{s}_friction"] = FrictionParameters(*(get[f"{s}_{k}"] for k in FRICTION_CONSTANTS))
    for radius, excess in _EXCESS.items():
        if excess in values:
            fields[radius] = get["inner_radius"] + values[excess]
    names = list(fields)
    return eqx.tree_at(lambda b: [getattr(b, name) for name in names], bearing, [fields[n] for n in names])


series_parameters = triple_parameters
series_with_parameters = triple_with_parameters
"""`triple_parameters`, `triple_with_parameters`, which take any series pendulum."""


def _leaves_of(bearing: SeriesPendulum) -> dict:
    """As `triple_parameters`, the leaves kept as they are (traceable)."""
    out = {}
    for surface in bearing.slider_names:
        out[f"{surface}_radius"] = getattr(bearing, f"{surface}_radius")
        out[f"{surface}_capacity"] = getattr(bearing, f"{surface}_capacity")
        for c in FRICTION_CONSTANTS:
            out[f"{surface}_{c}"] = getattr(getattr(bearing, f"{surface}_friction"), c)
    return out


def _residual(params, args):
    start, path, force, load, reference_load = args
    values = from_ratios(params, series_ratio_pairs(start.slider_names), _leaves_of(start))
    response = imposed_path_test(triple_with_parameters(start, values), path, reference_load=reference_load)
    return ((response.force - force) / (load if force.ndim == 1 else load[:, None])).reshape(-1)


def series_arrays(record: TestRecord, normal_load):
    """(time, displacement (nt,) or (nt, 2), force like it, N (nt,)) of a time-history record
    at increasing sample times under a positive normal load at each sample; `ValueError`
    naming what the fit cannot take."""
    name = _record_name(record, 0)
    if record.is_digitised or record.time is None:
        raise ValueError(f"{name}: the series pendulum fit takes a time history (time, ux, fx); "
                         "this record is a digitised loop.")
    time = np.asarray(record.time, dtype=float)
    steps = np.diff(time)
    if time.size < 10 or not np.all(steps > 0):
        raise ValueError(f"{name}: the series pendulum fit needs at least 10 samples at increasing times "
                         "(the series model is stepped at the record's samples).")
    load = _normal_load(record, name, normal_load)
    if not np.all(load > 0):
        raise ValueError(f"{name}: the series pendulum fit needs a positive normal load at every sample; "
                         f"the record's N spans {load.min():.6g}-{load.max():.6g} N.")
    if record.is_biaxial:
        path = np.stack([record.ux, record.uy], axis=-1)
        force = np.stack([record.fx, record.fy], axis=-1)
    else:
        path, force = np.asarray(record.ux, float), np.asarray(record.fx, float)
    if np.max(np.abs(path[0])) > 1e-6 * np.max(np.abs(path)):
        raise ValueError(f"{name}: the record starts off the centre (u = {np.ravel(path[0]).tolist()} m); "
                         "the series model starts at rest at u = 0: trim or shift the record.")
    return time, path, force, load


def check_reference_load(reference_load) -> None:
    """`ValueError` naming `reference_load` [N] where it is not a positive finite number."""
    if not (isinstance(reference_load, numbers.Real) and not isinstance(reference_load, bool)
            and math.isfinite(reference_load) and reference_load > 0):
        raise ValueError(f"reference_load: give the positive load [N] the start's contact pressures are "
                         f"given under, got {reference_load!r}.")


def check_pressure_load(record: TestRecord, start: SeriesPendulum, load, reference_load=None) -> None:
    """`ValueError` naming the record and the start's surfaces where surfaces that read their
    contact pressure (`SeriesPendulum.reads_pressure`: heating, pressure dependence; their
    `<slider>_pressure` given under one load) meet a record whose normal load (nt,) [N] varies
    and no `reference_load` [N] states the load those pressures are given under (neither the
    record nor the start states it); a `reference_load` that is not a positive number, or one
    given where no surface reads its pressure (it would change nothing), is refused by name."""
    if reference_load is not None:
        check_reference_load(reference_load)
        if not start.reads_pressure:
            raise ValueError(f"reference_load: no surface of the {start.description[:-1]} reads its contact "
                             "pressure (heating or pressure dependence), so the load its pressures are given "
                             "under changes nothing; leave it out.")
        return
    if not (start.reads_pressure and bool(normal_load_varies(load))):
        return
    surfaces = [name for name, part, heating in zip(start.slider_names, start.parts(), start.surface_heatings())
                if heating is not None or (part is not None and part.pressure_dependence is not None)]
    raise ValueError(f"{_record_name(record, 0)}: its normal load varies ({np.min(load):.6g}-{np.max(load):.6g} N), "
                     f"and the start's surfaces {', '.join(surfaces)} read their contact pressure (heating or "
                     "pressure dependence), given under one load: state that load as reference_load "
                     "(the W of the structures the pendulum will carry), or fit a record under a constant "
                     "normal load.")


def _bounds(names, values):
    """Bounds and the start of the optimiser's variables (module docstring), delta_f as
    itself (`to_ratios`, `ratio_bounds` make it the optimiser's ratio); the f_max of a
    surface whose delta_f is held is bounded below by it."""
    bounds, initial = {}, {}
    excess = _EXCESS if "inner_radius" in values else {}
    for name in names:
        key = excess.get(name, name)
        initial[key] = values[name] - values["inner_radius"] if key in excess.values() else values[name]
        bounds[key] = (0.0, 1.0) if name.endswith(("f_max", "delta_f")) else (0.0, math.inf)
        delta = name.replace("f_max", "delta_f")
        if name.endswith("f_max") and delta not in names:
            bounds[key] = (values[delta], 1.0)
    return initial, bounds


def fit_series_pendulum_test(record: TestRecord, initial: SeriesPendulum, *, free=None,
                             normal_load: float | None = None, reference_load: float | None = None,
                             full_model: bool = False, max_steps: int = 200, rtol: float = 1e-10,
                             atol: float = 1e-12) -> TripleFit:
    """Fit a triple or double pendulum's effective radii, its surfaces' friction (Eq. 1) and,
    where the loop reaches them, its capacities to one test record (module docstring).

    **Arguments:** `record`: a `TestRecord` time history (uniaxial, or biaxial along an
    orbit) at increasing sample times, under its normal load at each sample (its N column or
    metadata, else `normal_load` [N]; the force is homogeneous in N, so a load that varies
    is followed sample by sample); `reference_load` [N]: the load the start's contact
    pressures (`<slider>_pressure`) are given under, where its surfaces read them (heating,
    pressure dependence): each sample's pressure is then that times N / `reference_load`, as
    in a structure of that weight under a vertical record (`imposed_path_test`); without
    it such a start needs a constant N; `initial`: the start (`TriplePendulum` or `DoublePendulum`, e.g.
    `load_isolator`); the constants it does not free are held at its values; `free`: names to
    fit (`parameter_names` of its surfaces; default: what the record can tell,
    `triple_fit_plan`); `full_model`: free delta_f and rate_a whatever the record's speeds;
    `max_steps`, `rtol`, `atol`: optimistix's Levenberg-Marquardt settings.

    **Returns:** a `TripleFit`. `ValueError` naming a bad record, start or name.
    """
    if type(initial) not in (TriplePendulum, DoublePendulum):
        raise ValueError(f"initial: expected a TriplePendulum or DoublePendulum (e.g. "
                         f"formats.load_isolator), got {type(initial).__name__}.")
    check_series_pendulum(initial)
    _check_apart(initial)
    if not (isinstance(max_steps, int) and max_steps >= 1):
        raise ValueError(f"max_steps: must be an integer >= 1, got {max_steps!r}.")
    time, path, force, load = series_arrays(record, normal_load)
    check_pressure_load(record, initial, load, reference_load)
    start = jax.tree_util.tree_map(lambda x: jnp.asarray(x, float), initial)
    simulate = eqx.filter_jit(functools.partial(imposed_path_test, reference_load=reference_load))
    sampled = sampled_path(time, path, load)
    response = simulate(start, sampled)
    if not bool(np.all(np.asarray(response.converged))):
        raise ValueError(f"{_record_name(record, 0)}: the start's series solve does not balance at "
                         f"{int(np.sum(~np.asarray(response.converged)))} samples; use a finer time step.")
    names, held = triple_fit_plan(start, response, time, full_model=full_model)
    known = parameter_names(start.slider_names)
    if free is not None:
        names = check_free(free, known)
        held = {n: "held: not in free" for n in known if n not in names}
    values = triple_parameters(start)
    x0, bounds = _bounds(names, values)
    pairs = series_ratio_pairs(start.slider_names)
    result = fit_least_squares(_residual, to_ratios(x0, pairs, values), ratio_bounds(bounds, pairs),
                               args=(start, sampled, force, load, reference_load),
                               max_steps=max_steps, rtol=rtol, atol=atol, solver=SOLVER)
    result = result_from_ratios(result, pairs, values)
    fit = _result(start, result, names, held, (sampled, force), simulate)
    return dataclasses.replace(fit, reference_load=None if reference_load is None else float(reference_load))


def fit_triple_pendulum_test(record: TestRecord, initial: TriplePendulum, **options) -> TripleFit:
    """`fit_series_pendulum_test` of a `TriplePendulum` start (`ValueError` for another)."""
    if not isinstance(initial, TriplePendulum):
        raise ValueError(f"initial: expected a TriplePendulum (e.g. formats.load_isolator), got "
                         f"{type(initial).__name__}.")
    return fit_series_pendulum_test(record, initial, **options)


def fit_double_pendulum_test(record: TestRecord, initial: DoublePendulum, **options) -> TripleFit:
    """`fit_series_pendulum_test` of a `DoublePendulum` start (`ValueError` for another): its
    radii R_1, R_2 and each surface's Eq. 1 constants from one loop, bottom and top in the
    start's order of f_max (module docstring)."""
    if not isinstance(initial, DoublePendulum):
        raise ValueError(f"initial: expected a DoublePendulum (e.g. formats.load_isolator), got "
                         f"{type(initial).__name__}.")
    return fit_series_pendulum_test(record, initial, **options)


def _check_apart(initial: SeriesPendulum) -> None:
    """`ValueError` for a start whose bottom and top surfaces are alike in radius and friction:
    both sliders then move alike, the fit's steps keep them so, and it cannot tell them apart."""
    leaves = _leaves_of(initial)
    keys = ("radius",) + FRICTION_CONSTANTS
    if all(float(np.asarray(leaves[f"bottom_{k}"])) == float(np.asarray(leaves[f"top_{k}"])) for k in keys):
        raise ValueError("initial: the bottom and top surfaces have the same radius and friction; "
                         "the fit moves them alike and cannot separate them: start them apart "
                         "(e.g. a smaller f_max on the surface that slides first).")


def _reported_jacobian(result, names):
    """The Jacobian in (a, b, c, ...) from the optimiser's (a, b - a, c - a, ...)."""
    column = {n: result.jacobian[:, i] for i, n in enumerate(result.names)}
    jac = np.stack([column[n if n in column else _EXCESS[n]] for n in names], axis=1)
    if "inner_radius" in names:
        i = names.index("inner_radius")
        for excess in ("bottom_excess", "top_excess"):
            if excess in column:
                jac[:, i] = jac[:, i] - column[excess]
    return jac


def _result(start, result, names, held, data, simulate) -> TripleFit:
    """The `TripleFit` of an optimiser's result (errors in the reported constants)."""
    bearing = triple_with_parameters(start, {k: jnp.asarray(v) for k, v in result.parameters.items()})
    path, force = data
    response = simulate(bearing, path)
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
    bearing, swapped = _in_start_order(bearing, start)
    parameters = triple_parameters(bearing)
    known = parameter_names(bearing.slider_names)
    if swapped:
        errors = {_swap_name(k): v for k, v in errors.items()}
        held = {_swap_name(k): v for k, v in held.items()}
        names = tuple(n for n in known if n in {_swap_name(k) for k in names})
    try:
        check_series_pendulum(bearing)
    except ValueError as error:
        warnings.append(f"the fitted constants break the series model's order: {error}")
    return TripleFit(bearing=bearing, parameters=parameters,
                     std_errors={n: errors.get(n) for n in known}, free=tuple(names),
                     held=held, nrmse=nrmse, converged=bool(result.converged and balanced),
                     message=result.message, n_steps=result.n_steps, swapped=swapped,
                     warnings=warnings, fitted_force=model)


def _swap_name(name: str) -> str:
    surface, rest = name.split("_", 1)
    return {"bottom": "top", "top": "bottom"}.get(surface, surface) + "_" + rest


def _f_max(bearing, surface: str) -> float:
    return float(np.asarray(getattr(bearing, f"{surface}_friction").f_max))


def _in_start_order(bearing: SeriesPendulum, start: SeriesPendulum):
    """(bearing, swapped): bottom and top exchanged when their order of f_max is not the
    start's (a start with them equal, or a triple's, has the bottom the slipperier)."""
    start_bottom_larger = _f_max(start, "bottom") > _f_max(start, "top")
    bottom, top = _f_max(bearing, "bottom"), _f_max(bearing, "top")
    if bottom == top or (bottom > top) == start_bottom_larger:
        return bearing, False
    swap = {}
    for part in ("radius", "capacity", "friction"):
        swap[f"bottom_{part}"] = getattr(bearing, f"top_{part}")
        swap[f"top_{part}"] = getattr(bearing, f"bottom_{part}")
    return dataclasses.replace(bearing, **swap), True
