"""A triple or double friction pendulum's series model fitted with and without the frictional
heating of its surfaces, many fits in one compiled, vmapped call (for `diagnose`).

The model is the series fit's (`fit_series_pendulum_test`: the sliders of Fenz & Constantinou
2006, 2008 with Eq. 1 friction at each surface's velocity; the constants the record can tell,
`triple_fit_plan`, free from the start file's values). The heating candidate gives every
surface the frictional heating the series model already runs (`SeriesPendulum.heat_fluxes`,
`FrictionalHeating`: q_e = mu_e p_e v_e into surface e, the surface temperature rise of a
semi-infinite steel body, Carslaw & Jaeger 1959 Sec. 2.9, and mu_e times
k_T(T0 + heat_scale dT_e) / k_T(T0) of Kumar, Whittaker & Constantinou 2015), each surface at
its own temperature, with one `heat_scale` [-] shared by the surfaces and fitted. The contact
pressure p_e is the start file's `heating.contact_pressure` where it has one, else the
record's `contact_pressure` (or N / `contact_area`), else `NOMINAL_CONTACT_PRESSURE`
(1000 psi), as the flat slider's candidate takes it; dT scales with heat_scale p_e, so
heat_scale absorbs a pressure that is off by a factor.

The velocity-dependence candidate frees delta_f and rate_a of Eq. 1, mu = f_max - delta_f
exp(-rate_a |v|) (Constantinou, Mokha & Reinhorn 1990), on each sliding surface that the start
file gives Coulomb friction (delta_f or rate_a zero), which the series fit holds
(`triple_fit_plan`); it starts from 1.5 f_max, delta_f = 0.5 f_max (the friction at rest where
it was) and rate_a = 1 s/in, as the flat slider's candidate does.

Every member of a batch is the heated model with every candidate's constants; a member without
heating holds heat_scale at 0, where k_T(T0) / k_T(T0) = 1 makes it exactly the series fit's
model, and one without velocity dependence holds the start's delta_f and rate_a. The residual of member b
is w_b (F_model - F) / s, with w_b its 0/1 sample weights (a fold of cycles) and s the
root-mean-square measured force.
Inside the optimiser a free delta_f is its ratio to f_max in (0, 1), as in the series fit
(`_ratio`), so that no member's friction at rest, f_max - delta_f, is negative.
"""

import dataclasses
import functools
import math
from types import SimpleNamespace
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from teflon_jax.bearing import (
    AMBIENT_TEMPERATURE,
    HEAT_HORIZON,
    PARAMETER_BOUNDS,
    STEEL_CONDUCTIVITY,
    STEEL_DIFFUSIVITY,
    DoublePendulum,
    FrictionalHeating,
    SeriesPendulum,
    TriplePendulum,
    check_series_pendulum,
    heat_kernel_exponentials,
)
from teflon_jax.formats import TestRecord
from teflon_jax.systems import (
    imposed_path_test,
    normal_load_varies,
    sampled_path,
)
from teflon_jax.units import INCH, PSI

from ..least_squares import covariance_from_jacobian, fit_least_squares_batch
from ._prepare import _record_name
from ._ratio import (
    from_ratios,
    ratio_bounds,
    ratio_name,
    result_from_ratios,
    series_ratio_pairs,
    to_ratios,
)
from ._triple_fit import (
    _bounds,
    _check_apart,
    _in_start_order,
    _leaves_of,
    _reported_jacobian,
    _swap_name,
    check_pressure_load,
    check_reference_load,
    series_arrays,
    triple_parameters,
    triple_with_parameters,
)
from ._triple_plan import parameter_names, triple_fit_plan

NOMINAL_CONTACT_PRESSURE = 1000.0 * PSI
"""Contact pressure [Pa] the heating candidate takes for a surface whose pressure neither the
start file nor the record states (as the flat slider's candidate)."""

HEAT_SCALE = "heat_scale"
"""The heating candidate's constant (shared by the surfaces)."""

RATE_START = 1.0 / INCH
"""rate_a [s/m] the velocity-dependence candidate starts from (1 s/in)."""

FIT_RTOL = 1e-5
FIT_ATOL = 1e-5
"""Convergence of each fit: a step changes every residual (forces over their RMS) by less than
FIT_ATOL + FIT_RTOL |r| (as the flat slider's discovery)."""


class SeriesProblem(NamedTuple):
    """A record prepared for the series fits (SI): `time` (n,), `path` (n,), `force` (n,),
    `load` N [N] (one value, or (n,) with a `reference_load`), `scale` RMS force [N], `start` the start pendulum (arrays, no heating), `free`
    the constants the record can tell and `held` {name: why} (`triple_fit_plan`), `pressures`
    {surface: p [Pa]}, `heating` {surface: `FrictionalHeating`} (constants of each surface's
    heating, heat_scale 1), `pressure_assumed` (surfaces at `NOMINAL_CONTACT_PRESSURE`),
    `kernel` (rates, weights) of the heat kernel, `decimation`, `source`, `rate_surfaces` the
    sliding surfaces whose start friction is Coulomb's (the velocity-dependence candidate's),
    `reference_load` [N] the load the contact pressures are given under (None: `load`)."""

    time: np.ndarray
    path: np.ndarray
    force: np.ndarray
    load: float | np.ndarray
    scale: float
    start: SeriesPendulum
    free: tuple
    held: dict
    pressures: dict
    heating: dict
    pressure_assumed: tuple
    kernel: tuple
    decimation: int
    source: str
    rate_surfaces: tuple = ()
    reference_load: float | None = None

    def effect_keys(self, effect: str) -> tuple:
        """The optimiser's keys of a candidate's constants."""
        if effect == "heating":
            return (HEAT_SCALE,)
        if effect == "velocity_dependence":
            return tuple(f"{s}_{c}" for s in self.rate_surfaces for c in ("delta_f", "rate_a"))
        raise ValueError(f"effect: the series model takes heating or velocity_dependence, not {effect!r}.")


def _without_heating(bearing: SeriesPendulum) -> SeriesPendulum:
    fields = {}
    for name in bearing.slider_names:
        fields[f"{name}_heating"] = None
        fields[f"{name}_pressure"] = None
    return dataclasses.replace(bearing, **fields)


def _surface_heating(start: SeriesPendulum, metadata: dict, load: float):
    """({surface: FrictionalHeating at heat_scale 1}, {surface: p [Pa]}, assumed surfaces)."""
    heating, pressures, assumed = {}, {}, []
    if "contact_pressure" in metadata:
        stated = float(metadata["contact_pressure"])
    elif "contact_area" in metadata:
        stated = load / float(metadata["contact_area"])
    else:
        stated = None
    for name, given in zip(start.slider_names, start.surface_heatings()):
        if given is not None:
            heating[name] = dataclasses.replace(given, heat_scale=1.0)
            pressures[name] = float(np.asarray(getattr(start, f"{name}_pressure")))
            continue
        pressure = NOMINAL_CONTACT_PRESSURE if stated is None else stated
        if stated is None:
            assumed.append(name)
        heating[name] = FrictionalHeating(contact_area=load / pressure, heat_scale=1.0,
                                          conductivity=STEEL_CONDUCTIVITY,
                                          diffusivity=STEEL_DIFFUSIVITY,
                                          initial_temperature=AMBIENT_TEMPERATURE)
        pressures[name] = pressure
    return heating, pressures, tuple(assumed)


def prepare_series_problem(record: TestRecord, start: SeriesPendulum, *, normal_load=None,
                           reference_load=None, max_samples: int = 3000) -> SeriesProblem:
    """The record and start of the series fits (`SeriesProblem`): the series fit's checks of
    the record (a time history at a uniform step, from the centre, under a constant N or,
    given `reference_load` [N], the load the contact pressures are given under, an N that
    varies: each sample's pressure is then the given one times N / `reference_load`), along
    one axis (the series model heats its surfaces along one axis only), one in `decimation`
    samples so that about `max_samples` are used. `ValueError` naming what cannot be taken."""
    if type(start) not in (TriplePendulum, DoublePendulum):
        raise ValueError(f"initial: expected a TriplePendulum or DoublePendulum (e.g. "
                         f"formats.load_isolator), got {type(start).__name__}.")
    check_series_pendulum(start)
    _check_apart(start)
    name = _record_name(record, 0)
    if record.is_biaxial:
        raise ValueError(f"{name}: the record runs in the plane (ux and uy); the series model heats "
                         "its surfaces along one axis only, so diagnose takes a record along one axis.")
    if not (isinstance(max_samples, int) and max_samples >= 10):
        raise ValueError(f"max_samples: must be an integer >= 10, got {max_samples!r}.")
    time, path, force, load = series_arrays(record, normal_load)
    if reference_load is None:
        check_pressure_load(record, start, load)
        _check_one_step_and_load(name, time, load)
        load = float(load[0])
    else:
        check_reference_load(reference_load)
        _check_one_step_and_load(name, time, None)
        reference_load = float(reference_load)
    decimation = max(1, math.ceil(time.size / max_samples))
    time, path, force = time[::decimation], path[::decimation], force[::decimation]
    load = load if reference_load is None else load[::decimation]
    scale = float(np.sqrt(np.mean(force**2)))
    if not scale > 0:
        raise ValueError(f"{name}: the measured force is zero throughout.")
    heating, pressures, assumed = _surface_heating(start, dict(record.metadata or {}),
                                                   load if reference_load is None else reference_load)
    bare = jax.tree_util.tree_map(lambda x: jnp.asarray(x, float), _without_heating(start))
    response = jax.jit(functools.partial(imposed_path_test, reference_load=reference_load))(
        bare, sampled_path(time, path, load))
    if not bool(np.all(np.asarray(response.converged))):
        raise ValueError(f"{name}: the start's series solve does not balance at "
                         f"{int(np.sum(~np.asarray(response.converged)))} samples; use a finer "
                         "time step (or a larger max_samples).")
    free, held = triple_fit_plan(bare, response, time)
    kernel = tuple(jnp.asarray(a) for a in heat_kernel_exponentials(float(time[1] - time[0]),
                                                                    HEAT_HORIZON))
    return SeriesProblem(time=time, path=path, force=force, load=load, scale=scale, start=bare,
                         free=tuple(free), held=held, pressures=pressures, heating=heating,
                         pressure_assumed=assumed, kernel=kernel, decimation=decimation,
                         source=name, rate_surfaces=_coulomb_surfaces(bare, free),
                         reference_load=reference_load)


def _check_one_step_and_load(name: str, time, load) -> None:
    """Heated surfaces are stepped by one kernel, at one interval, and without a reference load
    take their contact pressures at one load: `ValueError` naming the record `name` where the
    sample times (nt,) [s] are not uniform or the normal load (nt,) [N] (None: not checked)
    is not constant."""
    steps = np.diff(time)
    if not np.ptp(steps) <= 1e-6 * steps.mean():
        raise ValueError(f"{name}: heated surfaces are stepped at one interval; this record needs a uniform "
                         "time step: resample it.")
    if load is not None and bool(normal_load_varies(load)):
        raise ValueError(f"{name}: heated surfaces take their contact pressures at one load; this record's "
                         f"normal load varies (its N spans {load.min():.6g}-{load.max():.6g} N): state the "
                         "load the contact pressures are given under as reference_load (the weight W the "
                         "pendulum will carry), or give a record under a constant normal load.")


def _coulomb_surfaces(start: SeriesPendulum, free) -> tuple:
    """The sliding surfaces (f_max free) whose start friction is Coulomb's."""
    out = []
    for name in start.slider_names:
        friction = getattr(start, f"{name}_friction")
        coulomb = float(np.asarray(friction.delta_f)) == 0 or float(np.asarray(friction.rate_a)) == 0
        if coulomb and f"{name}_f_max" in free:
            out.append(name)
    return tuple(out)


def heated_pendulum(bearing: SeriesPendulum, heating: dict, pressures: dict, heat_scale):
    """`bearing` with each surface's `heating` (name -> `FrictionalHeating`) at the shared
    `heat_scale` [-] (traceable) and contact pressure `pressures[name]` [Pa]."""
    fields = {}
    for name in bearing.slider_names:
        fields[f"{name}_heating"] = dataclasses.replace(heating[name], heat_scale=heat_scale)
        fields[f"{name}_pressure"] = pressures[name]
    return dataclasses.replace(bearing, **fields)


def optimiser_start(problem: SeriesProblem) -> dict:
    """The optimiser's start (keys: the free constants at the start file's values, a triple's
    b - a and c - a in place of b and c; the candidates' constants at their start:
    `HEAT_SCALE` 1, delta_f half the start's f_max and rate_a `RATE_START` on `rate_surfaces`)
    and its bounds: ({key: value}, {key: (lower, upper)})."""
    initial, bounds = _bounds(problem.free, triple_parameters(problem.start))
    initial[HEAT_SCALE] = 1.0
    bounds[HEAT_SCALE] = PARAMETER_BOUNDS[HEAT_SCALE].search
    for name in problem.rate_surfaces:
        initial.update({f"{name}_delta_f": 0.5 * initial[f"{name}_f_max"],
                        f"{name}_rate_a": RATE_START})
        bounds.update({f"{name}_delta_f": (0.0, 1.0), f"{name}_rate_a": (0.0, math.inf)})
    return initial, bounds


def candidate_start(problem: SeriesProblem, values: dict, effects) -> dict:
    """The start of a fit adding `effects` to a model fitted at `values` (optimiser keys):
    each added candidate's constants at their start (`optimiser_start`); velocity dependence
    keeps the friction at rest where it was (f_max 1.5 times, delta_f half of it)."""
    initial = optimiser_start(problem)[0]
    out = dict(values)
    for effect in effects:
        for key in problem.effect_keys(effect):
            out[key] = initial[key]
        if effect == "velocity_dependence":
            for name in problem.rate_surfaces:
                f_now = values[f"{name}_f_max"]
                out[f"{name}_f_max"], out[f"{name}_delta_f"] = 1.5 * f_now, 0.5 * f_now
    return out


def _model(params, shared):
    problem_start, heating, pressures, kernel, path, reference_load = shared
    values = {k: v for k, v in params.items() if k != HEAT_SCALE}
    bearing = heated_pendulum(triple_with_parameters(problem_start, values), heating, pressures,
                              params[HEAT_SCALE])
    return imposed_path_test(bearing, path, heat_kernel=kernel, reference_load=reference_load)


def _residual(params, args):
    (free, start, weight), (shared, force, scale) = args
    bearing = shared[0]
    params = from_ratios(params, series_ratio_pairs(bearing.slider_names), _leaves_of(bearing))
    values = {k: jnp.where(free[k] > 0, params[k], start[k]) for k in params}
    return weight * (_model(values, shared).force - force) / scale


def _shared(problem: SeriesProblem):
    return ((problem.start, problem.heating, problem.pressures, problem.kernel,
             sampled_path(jnp.asarray(problem.time), jnp.asarray(problem.path), problem.load),
             problem.reference_load),
            jnp.asarray(problem.force), problem.scale)


class SeriesMember(NamedTuple):
    """One fitted member: optimiser `values` (key -> value), `force` (n,) [N] of the model on
    the whole record, `jacobian` (n, keys) of the weighted residual in the optimiser's keys
    (`keys` their order), `converged`, `n_steps`."""

    values: dict
    force: np.ndarray
    jacobian: np.ndarray
    keys: tuple
    converged: bool
    n_steps: int


def _off_values(problem: SeriesProblem) -> dict:
    """The value each candidate's constant holds while the candidate is off: heat_scale 0 and
    the start file's delta_f and rate_a."""
    values = triple_parameters(problem.start)
    out = {HEAT_SCALE: 0.0}
    out.update({k: values[k] for k in problem.effect_keys("velocity_dependence")})
    return out


def fit_series_members(problem: SeriesProblem, starts, effects, weights, *,
                       max_steps: int = 200) -> list:
    """Fit B members in one vmapped Levenberg-Marquardt call (optimistix, scaled damping):
    member b starts from `starts[b]` (optimiser keys, `optimiser_start`), frees the plan's
    constants and those of its candidates `effects[b]` (the others held off, `_off_values`),
    on the samples where `weights[b]` (n,) is 1. **Returns:** B `SeriesMember`s."""
    initial, bounds = optimiser_start(problem)
    keys = tuple(initial)
    b = len(starts)
    off = _off_values(problem)
    on = [set(k for e in effects[i] for k in problem.effect_keys(e)) for i in range(b)]
    free = {k: np.array([0.0 if k in off and k not in on[i] else 1.0 for i in range(b)])
            for k in keys}
    start = {k: np.array([float(off[k]) if not free[k][i] else float(s[k])
                          for i, s in enumerate(starts)]) for k in keys}
    batch = ({k: jnp.asarray(v) for k, v in free.items()},
             {k: jnp.asarray(v) for k, v in start.items()}, jnp.asarray(np.asarray(weights, float)))
    pairs, held = series_ratio_pairs(problem.start.slider_names), triple_parameters(problem.start)
    fits = fit_least_squares_batch(_residual, _ratio_guess(initial, starts, free, pairs, held),
                                   ratio_bounds(bounds, pairs), args=(batch, _shared(problem)),
                                   args_batched=(True, False), max_steps=max_steps,
                                   rtol=FIT_RTOL, atol=FIT_ATOL,
                                   solver="levenberg_marquardt_scaled", converged_on="residuals")
    members = []
    for i, fit in enumerate(fits):
        fit = result_from_ratios(fit, pairs, held)
        values = {k: (float(fit.parameters[k]) if free[k][i] else float(start[k][i])) for k in keys}
        members.append(SeriesMember(values=values, force=None, jacobian=np.asarray(fit.jacobian),
                                    keys=tuple(fit.names), converged=bool(fit.converged),
                                    n_steps=int(fit.n_steps)))
    forces = _member_forces(problem, [m.values for m in members])
    return [m._replace(force=f) for m, f in zip(members, forces)]


def _ratio_guess(initial, starts, free, pairs, held) -> dict:
    """The optimiser's start of each member (`to_ratios`): its own start where it frees a
    constant, else `initial`'s (so that a held delta_f's ratio starts inside its bounds)."""
    inner = to_ratios(initial, pairs, held)
    own = [to_ratios({k: s[k] for k in initial if free[k][i]}, pairs, held) for i, s in enumerate(starts)]
    return {ratio_name(k, pairs): np.array([float(o[ratio_name(k, pairs)]) if free[k][i]
                                            else float(inner[ratio_name(k, pairs)]) for i, o in enumerate(own)])
            for k in initial}


@jax.jit
def _forces_batch(values, shared):
    return jax.vmap(lambda v: _model(v, shared).force)(values)


def _member_forces(problem, values) -> np.ndarray:
    stacked = {k: jnp.asarray([v[k] for v in values]) for k in values[0]}
    return np.asarray(_forces_batch(stacked, _shared(problem)[0]))


def member_pendulum(problem: SeriesProblem, values: dict, effects):
    """(the fitted pendulum with `effects` (heated surfaces where heating is among them),
    swapped): bottom and top in the start file's order of f_max, as the series fit reports them."""
    values = {**values, **{k: v for k, v in _off_values(problem).items()
                           if not any(k in problem.effect_keys(e) for e in effects)}}
    plain = {k: jnp.asarray(v) for k, v in values.items() if k != HEAT_SCALE}
    bearing, swapped = _in_start_order(triple_with_parameters(problem.start, plain), problem.start)
    if "heating" in effects:
        bearing = heated_pendulum(bearing, problem.heating, problem.pressures, values[HEAT_SCALE])
    return bearing, swapped


def member_parameters(problem: SeriesProblem, values: dict, effects) -> dict:
    """name -> value [SI] of every constant of the fitted member with `effects`
    (`parameter_names` of its surfaces; `heat_scale` where heating is among them)."""
    bearing, _ = member_pendulum(problem, values, effects)
    out = triple_parameters(bearing)
    if "heating" in effects:
        out[HEAT_SCALE] = float(values[HEAT_SCALE])
    return out


def member_std_errors(problem: SeriesProblem, member: SeriesMember, effects,
                      n_eff: float) -> dict:
    """Standard errors [SI] of the member's fitted constants (reported names, bottom and top in
    the start file's order): sigma^2 (J^T J)^-1 of the residual at the optimum (Seber & Wild
    1989, Ch. 2), inflated by n / n_eff for residuals correlated from sample to sample (n_eff
    as in the discovery's evidence); inf where the record cannot tell a constant."""
    known = parameter_names(problem.start.slider_names)
    added = {k for e in effects for k in problem.effect_keys(e)}
    names = tuple(n for n in known if n in problem.free or n in added)
    names += (HEAT_SCALE,) if "heating" in effects else ()
    jac = _reported_jacobian(SimpleNamespace(names=member.keys, jacobian=member.jacobian), names)
    residual = (member.force - problem.force) / problem.scale
    cov, _ = covariance_from_jacobian(jac, residual)
    inflation = residual.size / max(float(n_eff), 1.0)
    errors = {n: float(np.sqrt(abs(cov[i, i]) * inflation)) for i, n in enumerate(names)}
    _, swapped = member_pendulum(problem, member.values, effects)
    return {_swap_name(n) if swapped else n: v for n, v in errors.items()}
