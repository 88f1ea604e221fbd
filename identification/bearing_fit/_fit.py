"""Fit the constants of a PTFE bearing model to bearing tests.

The model is the one of Constantinou, Mokha & Reinhorn (1990): the force is

    F = m mu N Z,  mu = f_max - delta_f exp(-rate_a |v| / n)     (Eq. 1)
                   mu = breakaway_ratio (f_max - delta_f)         (Eq. 17, before max|Z| >= 0.999)

with m = `interfaces_in_parallel` and n = `interfaces_in_series` of the record (FORMATS.md), Z
from Bouc-Wen (Eq. 3; A = 1, beta = 0.1, gamma = 0.9, eta = 2, yield displacement `yield_disp`)
or, for a biaxial record (ux, uy, fx, fy), from Park et al. (Eqs. 8-9) with f_max, delta_f and
rate_a interpolated linearly in the sliding angle between the parallel constants and the
`*_perpendicular` ones. The force model and the velocity at the samples are those of
`simulate_record_force` (see its module), the same as the diagnosis uses; on the simulator's own
noise-free records the fit returns the simulator's constants. The fitter minimises the force
residual, sample by sample, divided by the RMS measured force of each record, with optimistix
Levenberg-Marquardt and forward-mode Jacobians (`identification.least_squares`).

Parameters (SI): `f_max` [-], `delta_f` [-], `rate_a` [s/m], `yield_disp` [m],
`breakaway_ratio` [-] (and `f_max_perpendicular`, `delta_f_perpendicular`,
`rate_a_perpendicular`). Inside the optimiser `delta_f` is written as `delta_ratio * f_max` with
`0 < delta_ratio < 1` (so that `f_max - delta_f > 0` always), `breakaway_ratio > 1`, the others
`> 0`; standard errors are reported in the parameters above. A fit is `clean` only when it
converged and no parameter is unidentifiable, poorly determined (standard error above 50 %) or
at a bound; otherwise its `warnings` say why.

Normal load: the `N` column of the record, else its constant `normal_load` (or
`contact_area * contact_pressure`) metadata, else the `normal_load=` argument. A record with
none of these is an error. The friction damper of the ARTS Laboratory has no normal load: fit it
with `normal_load=1.0`, so that `F = mu Z` and `f_max`, `delta_f` come out in newtons.
"""

from collections.abc import Mapping, Sequence

import numpy as np

from teflon_jax.formats import TestRecord

from ..least_squares import check_bounds, fit_least_squares_batch
from ._loop_features import PreparedBiaxialRecord
from ._model import BearingModel
from ._plan import (
    RATE_NAMES,
    BearingFit,
    _check_names,
    _finish,
    _fixed_tree,
    _internal,
    _multi_starts,
    _pad,
    _plan,
    _stack,
    _tree_index,
)
from ._prepare import prepare_record
from ._reduce import reduce_friction_law, unresolved

SOLVER = "levenberg_marquardt_scaled"
"""The least-squares solver of `fit_bearing_test` (`identification.least_squares`): Marquardt's
damping scaled by diag(J^T J), so that a constant whose influence fades near a bound of its
bijection (delta_f / f_max near 1, rate_a near 0) still takes steps of order one and reaches
the bound instead of creeping towards it."""


def as_records(records) -> list:
    """`records` (one `TestRecord` or several) as a non-empty list, each checked to be one."""
    if isinstance(records, TestRecord):
        return [records]
    records = list(records)
    if not records:
        raise ValueError("records: give at least one test record.")
    for i, r in enumerate(records):
        if not isinstance(r, TestRecord):
            raise ValueError(f"records[{i}]: expected a TestRecord, got {type(r).__name__}.")
    return records


def fit_bearing_test(
    records,
    *,
    free: Sequence[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    initial: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    normal_load: float | None = None,
    n_starts: int = 8,
    max_steps: int = 200,
    rtol: float = 1e-8,
    atol: float = 1e-8,
    reduce: bool = True,
) -> BearingFit:
    """Fit one parameter set to one record, or jointly to several records of one interface.

    **Arguments:**

    - `records`: a `TestRecord` or a list of them (time histories and/or digitised loops).
    - `free`: names to fit among `PARAMETER_NAMES`. Default: f_max, delta_f, rate_a,
      yield_disp (unless the sampling is too coarse to see the elastic branch),
      breakaway_ratio when a record starts from rest (contains the first excursion), and the
      three `*_perpendicular` constants when a record is biaxial.
    - `fixed`: values of parameters held fixed (SI). `yield_disp` defaults to 0.005 in;
      `breakaway_ratio` not free and not fixed means no breakaway (Eq. 1 throughout).
    - `initial`: start values overriding the loop features; `bounds`: name -> (lower, upper).
    - `normal_load` [N]: for records without one (1.0 fits the force itself).
    - `n_starts`: number of starts (the feature start and perturbations), solved in one
      vmapped call; the lowest converged cost wins.
    - `reduce`: with the default free set (`free=None`), when the records do not separate
      f_max, delta_f and rate_a (a relative standard error above 50 %, or no convergence
      with a correlation beyond 0.999 among them), fit the reduced law the records determine: rate_a
      held, else Coulomb friction (delta_f = 0); the result's `reduced`, `reduction` and
      `full_model` say what and why (`identification.bearing_fit._reduce`). An explicit
      `free` set is always fitted as given.

    **Returns:** a `BearingFit`.
    """
    records = as_records(records)
    _check_names(free or (), "free")
    yield_ref = (fixed or {}).get("yield_disp")
    prepared = [prepare_record(r, index=i, normal_load=normal_load, yield_ref=yield_ref)
                for i, r in enumerate(records)]
    settings = dict(initial=initial, bounds=bounds, normal_load=normal_load, n_starts=n_starts,
                    max_steps=max_steps, rtol=rtol, atol=atol)
    fit = _fit_prepared(records, prepared, free, fixed, **settings)
    if not (reduce and free is None and unresolved(fit)):
        return fit

    def refit(free_reduced, fixed_reduced, start):
        # one start: the full fit's estimates, carried to the reduced law
        return _fit_prepared(records, prepared, free_reduced, fixed_reduced,
                             **{**settings, "initial": {**(initial or {}), **start}})

    return reduce_friction_law(fit, prepared, dict(fixed or {}), refit)


def _fit_prepared(records, prepared, free, fixed, *, initial, bounds, normal_load, n_starts,
                  max_steps, rtol, atol) -> BearingFit:
    """One least-squares fit of prepared records (see `fit_bearing_test`)."""
    free, values, start, warnings = _plan(prepared, free, fixed, initial, bounds)
    if normal_load is not None and any(r.normal_load is None for r in records):
        warnings.append(
            f"normal load: records without one were fitted with normal_load = {normal_load} N; "
            "f_max and delta_f are then force / normal_load, in newtons for normal_load = 1.")
    names, internal_bounds, to_internal, ratio = _internal(free, values, start, bounds)
    configs = tuple(p.config for p in prepared)
    anisotropic = values["anisotropic"]
    model = BearingModel(free=names, configs=configs, ratio=ratio, anisotropic=anisotropic)
    model_user = BearingModel(free=free, configs=configs, ratio=False, anisotropic=anisotropic)
    args = {"fixed": _fixed_tree(values), "records": [p.arrays for p in prepared]}
    starts = _multi_starts(start, free, n_starts) if not initial else [start]
    internal_starts = [_rates_inside(to_internal(s), internal_bounds, bounds) for s in starts]
    check_bounds(internal_starts[0], internal_bounds)
    batch_initial = {n: np.array([s[n] for s in internal_starts]) for n in names}
    # keep perturbed starts inside the bounds
    for n, (lo, hi) in internal_bounds.items():
        x = batch_initial[n]
        span = np.where(np.isfinite(hi - lo), hi - lo, np.abs(x))
        batch_initial[n] = np.clip(x, lo + 1e-6 * span, hi - 1e-6 * span)
    results = fit_least_squares_batch(
        model, batch_initial, internal_bounds, args=args, args_batched=False,
        max_steps=max_steps, rtol=rtol, atol=atol, solver=SOLVER)
    best = _best(results)
    return _finish(prepared, model_user, free, values, results[best], args, warnings,
                   starts[best], len(starts))


def _rates_inside(start: dict, bounds: dict, given: Mapping | None) -> dict:
    """`start` with the rates of Eq. 1 moved inside their search range (`RATE_NAMES`), where
    the loop features (or a reduced law, from the full fit's estimate on the bound) may start
    outside it; a rate the caller bounds (`given`) is left for `check_bounds` to judge."""
    out = dict(start)
    for name in RATE_NAMES:
        if name in out and name in bounds and name not in (given or {}):
            lo, hi = bounds[name]
            margin = 1e-6 * (hi - lo)
            out[name] = float(np.clip(out[name], lo + margin, hi - margin))
    return out


def _best(results) -> int:
    costs = [r.cost if (r.converged and np.isfinite(r.cost)) else np.inf for r in results]
    if np.all(np.isinf(costs)):
        costs = [r.cost if np.isfinite(r.cost) else np.inf for r in results]
    return int(np.argmin(costs))


def fit_bearing_tests_batch(
    records: Sequence[TestRecord],
    *,
    free: Sequence[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    normal_load: float | None = None,
    n_starts: int = 3,
    max_steps: int = 200,
    rtol: float = 1e-8,
    atol: float = 1e-8,
) -> list[BearingFit]:
    """Fit many independent time-history records (one parameter set each) in one vmapped call.

    Records are padded to a common length (padding has zero weight). The free set is common;
    by default it is the default of `fit_bearing_test` for the first record (all records are
    expected to come from the same kind of test, e.g. one per Table 1 interface).

    **Returns:** one `BearingFit` per record, each with its own `converged` status.
    """
    records = as_records(records)
    _check_names(free or (), "free")
    yield_ref = (fixed or {}).get("yield_disp")
    prepared = [prepare_record(r, index=i, normal_load=normal_load, yield_ref=yield_ref)
                for i, r in enumerate(records)]
    if any(p.kind != "time" or isinstance(p, PreparedBiaxialRecord) for p in prepared):
        raise ValueError("records: the batch fit takes uniaxial time histories; fit digitised "
                         "loops and biaxial records with fit_bearing_test.")
    plans = [_plan([p], free, fixed, None, bounds) for p in prepared]
    common_free = plans[0][0] if free is None else tuple(free)
    plans = [_plan([p], common_free, fixed, None, bounds) for p in prepared]
    if len({pl[1]["breakaway_ratio"] is None for pl in plans}) > 1:
        raise ValueError("records: some records use breakaway and others not; fit them apart.")
    length = max(p.arrays["time"].size for p in prepared)
    config = prepared[0].config
    if any(p.config != config for p in prepared):
        raise ValueError("records: all records of a batch need the same "
                         "'interfaces_in_parallel' and 'interfaces_in_series'.")
    names = None
    initial_rows, trees, meta = [], [], []
    bounds_all = None
    for p, (fr, values, start, warnings) in zip(prepared, plans):
        names, internal_bounds, to_internal, ratio = _internal(fr, values, start, bounds)
        if bounds_all is None:
            bounds_all = internal_bounds
        elif any(internal_bounds[k] != bounds_all[k] for k in internal_bounds):
            raise ValueError("records: parameter bounds differ between records (fixed values "
                             "enter the bounds); fit them apart.")
        starts = _multi_starts(start, fr, n_starts)
        tree = {"fixed": _fixed_tree(values), "records": [_pad(p.arrays, length)]}
        for s in starts:
            initial_rows.append(_rates_inside(to_internal(s), internal_bounds, bounds))
            trees.append(tree)
        meta.append((fr, values, warnings, starts))
    model = BearingModel(free=names, configs=(config,), ratio=ratio)
    model_user = BearingModel(free=common_free, configs=(config,), ratio=False)
    batch_initial = {n: np.array([row[n] for row in initial_rows]) for n in names}
    for n, (lo, hi) in bounds_all.items():
        x = batch_initial[n]
        span = np.where(np.isfinite(hi - lo), hi - lo, np.abs(x))
        batch_initial[n] = np.clip(x, lo + 1e-6 * span, hi - 1e-6 * span)
    args = _stack(trees)
    results = fit_least_squares_batch(
        model, batch_initial, bounds_all, args=args, args_batched=True,
        max_steps=max_steps, rtol=rtol, atol=atol)
    fits = []
    k = 0
    for p, (fr, values, warnings, starts) in zip(prepared, meta):
        group = results[k: k + len(starts)]
        best = _best(group)
        args_i = _tree_index(args, k + best)
        k += len(starts)
        raw = group[best]
        fits.append(_finish([p], model_user, fr, values, raw, args_i, warnings, starts[best],
                            len(starts)))
    return fits
