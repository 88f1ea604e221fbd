"""Model discovery: fit a baseline, find the missing effect, add it, refit, repeat.

The workflow an experimentalist follows with a new bearing test, made explicit:

1. Fit the baseline model (`paper1990`: Eq. 1 + Bouc-Wen; or `coulomb`: constant friction +
   Bouc-Wen) to the whole record.
2. For every candidate effect not yet in the model, refit the model with that effect added
   (a) to the whole record and (b) in two folds of alternate cycles (fit on the odd cycles
   and predict the even ones, and the reverse).
3. Evidence for each candidate:
   - `delta_bic`: the drop of the Bayesian information criterion,
         delta_bic = n_eff ln(SSR_before / SSR_after) - k_added ln(n_eff),
     where n_eff = n (1 - rho) / (1 + rho) is the effective number of independent samples of
     the candidate's residual (rho its lag-1 autocorrelation, AR(1) approximation; Bretherton
     et al. 1999), so correlated residuals do not buy evidence they do not carry.
     delta_bic approximates 2 ln(Bayes factor) and is read on the scale of Kass & Raftery
     (1995): > 10 "very strong", 6-10 "strong", 2-6 "positive", < 2 "not worth more than a
     bare mention".
   - `holdout_gain`: 1 - CV_after / CV_before, with CV the root-mean-square prediction error
     on the cycles left out of each fold's fit (blocked cross-validation).
4. The candidate with the largest delta_bic among those with a positive held-out gain is
   added if its delta_bic exceeds `bic_threshold` (10, "very strong"); otherwise the model is
   declared complete ("no missing effect"). How sure the *naming* is (this effect rather than
   the runner-up) is the margin of its delta_bic over the runner-up's, read on the same scale.

Every fit of one round (current model and every candidate, full record and both folds) is a
single vmapped, compiled call of a masked Levenberg-Marquardt solver (`fit_batch`): effects are
switched by a 0/1 mask and the parameters of effects that are off are frozen, so the model is
compiled once per record.
"""

import math
import time as _time
from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from teflon_jax.tables import load_table1
from teflon_jax.units import INCH

from ..least_squares import covariance_from_jacobian
from ._augmented import (
    PARAMETER_EFFECT,
    PARAMETER_NAMES,
    PARAMETERS,
    AugmentedData,
    RecordInfo,
    active_mask,
    prepare_record,
)
from ._batch_fit import (
    _HI,
    _LO,
    _LOG,
    _fold_weights,
    _free_mask,
    _simulate_batch,
    _stacked,
    fit_batch,
    to_physical,
    to_unconstrained,
)
from ._diagnostics import (
    effective_samples,
    half_cycle_index,
    regressors,
    residual_correlation,
)
from ._effects import BASELINES, EFFECT_NAMES, EFFECTS
from ._result import (
    DEFAULT_BIC_THRESHOLD,
    DiscoveryResult,
    DiscoveryStep,
    confidence_wording,
)

INTERFACES_NOT_SEPARABLE = (
    "not separable from rate_a: Eq. 1 at |v| / n depends on rate_a and n only through "
    "rate_a / n, at every speed, so no set of amplitudes or frequencies separates them; "
    "the fitted rate_a is rate_a / n (see `stack_check`), and n is identified with rate_a "
    "known (e.g. from Table 1, `known={'rate_a': ...}`)"
)
"""Why `interfaces` is not a candidate while rate_a is fitted."""


def _applicable(info: RecordInfo, known):
    applicable, skipped = [], {}
    for name, effect in EFFECTS.items():
        if name == "interfaces" and "rate_a" not in known:
            skipped[name] = INTERFACES_NOT_SEPARABLE
        elif effect.requires == "varying_normal_load" and not info.varying_normal_load:
            skipped[name] = (
                "normal load constant in this record (no contrast to identify it)"
            )
        elif effect.requires == "biaxial" and not info.biaxial:
            skipped[name] = "uniaxial record (one sliding direction only)"
        elif effect.requires == "uniaxial" and info.biaxial:
            skipped[name] = "modelled for uniaxial records only (a gap along one axis)"
        else:
            applicable.append(name)
    return applicable, skipped


TABLE1_RATE_RANGE = (
    min(row.rate_a for row in load_table1()),
    max(row.rate_a for row in load_table1()),
)
"""Smallest and largest rate_a of Table 1 (16 single PTFE-steel interfaces; 0.32 and 0.90
s/in) [s/m]."""


def stack_check(rate_a: float, series: int = 1) -> dict:
    """What a fitted rate_a says about a stack when n and rate_a are not separable.

    Eq. 1 at |v| / n has the effective rate rate_a / n. If each interface has a rate within
    Table 1's range [a_lo, a_hi] (0.32-0.90 s/in), a fitted effective rate r means
        n in [a_lo / r, a_hi / r]
    (times the `interfaces_in_series` already stated in the record, whose rate_a the fit
    reports per interface). `consistent_with_stated` is False when the interval excludes the
    stated count: a hint of a stack (or of a material outside Table 1), not a proof.

    **Arguments:** `rate_a` fitted [s/m]; `series` interfaces in series stated in the record.

    **Returns:** dict(rate_effective [s/m], n_low, n_high, consistent_with_stated).
    """
    lo, hi = TABLE1_RATE_RANGE
    n_low, n_high = series * lo / rate_a, series * hi / rate_a
    return {
        "rate_effective": float(rate_a / series),
        "n_low": float(n_low),
        "n_high": float(n_high),
        "consistent_with_stated": bool(n_low <= series <= n_high),
    }


def _start_values(data: AugmentedData) -> dict:
    mu = np.hypot(np.asarray(data.force), np.asarray(data.force_y)) / np.asarray(
        data.normal
    )
    start = {p.name: p.initial for p in PARAMETERS}
    start["f_max"] = float(np.clip(np.percentile(mu, 90), 0.003, 0.45))
    start["delta_f"] = 0.5 * start["f_max"]
    return start


def _inside(values: np.ndarray) -> np.ndarray:
    lower = np.array([p.lower for p in PARAMETERS])
    upper = np.array([p.upper for p in PARAMETERS])
    margin = 1e-4 * (upper - lower)
    return np.clip(values, lower + margin, upper - margin)


def discover_effects(
    record,
    *,
    baseline: str = "paper1990",
    candidates=None,
    bic_threshold: float = DEFAULT_BIC_THRESHOLD,
    max_effects: int = 4,
    max_samples: int = 3000,
    max_steps: int = 200,
    known=None,
    callback=None,
) -> DiscoveryResult:
    """Find the effects a test record shows beyond a baseline model, one at a time.

    **Arguments:**

    - `record`: a `TestRecord` (uniaxial, with time and normal load).
    - `baseline`: `"paper1990"` (Eq. 1 + Bouc-Wen, default) or `"coulomb"`, or a sequence of
      effect names: the composition to start from (with `max_effects=0`, a fit of exactly
      that composition, as `teflon-jax fit --effects`).
    - `candidates`: names from `EFFECT_NAMES` to consider (default: all that the record can
      identify).
    - `bic_threshold`: smallest delta_bic that adds an effect (default 10: "very strong").
    - `max_effects`: at most this many effects are added.
    - `max_samples`: longer records are decimated to about this many samples.
    - `max_steps`: Levenberg-Marquardt iteration limit per fit; each fit stops when it
      converges (`FIT_RTOL`) and reports whether it did (`DiscoveryResult.fit_convergence`).
    - `known`: parameters held at given values (SI), e.g. `{"rate_a": 23.6}` from Table 1;
      with `rate_a` known the `interfaces` candidate becomes identifiable.
    - `callback`: called with a line of progress text (for a CLI), or `None`.

    **Returns:** a `DiscoveryResult`.
    """
    base_effects = _baseline_effects(baseline)
    _check_settings(bic_threshold, max_effects, max_steps)
    started = _time.perf_counter()
    say = callback or (lambda text: None)
    known = _checked_known(known)
    data, info = prepare_record(record, max_samples=max_samples)
    applicable, skipped = _applicable(info, known)
    applicable = _requested_candidates(applicable, skipped, candidates)
    current = list(base_effects)
    pool = [c for c in applicable if c not in current]
    setup = _fit_setup(data, info, known, len(pool), max_steps)
    fit_log = {"fits": 0, "unconverged": 0, "max_iterations_used": 0,
               "iteration_limit": int(max_steps)}

    fit, nrmse_initial, fit_log = _fit_baseline(setup, current, fit_log)
    say(f"baseline {baseline}: nrmse {nrmse_initial:.4f}")
    baseline_fit = fit

    steps, final_round = [], {}
    while pool and len(steps) < max_effects:
        evid, nrmse_before, candidate_fits, fit_log = _fit_round(
            setup, fit.values, current, pool, fit_log
        )
        ranked = sorted(
            (c for c in pool if evid[c]["holdout_gain"] > 0),
            key=lambda c: -evid[c]["delta_bic"],
        )
        summary = ", ".join(f"{c} {evid[c]['delta_bic']:.1f}" for c in pool)
        say(f"round {len(steps) + 1}: delta_bic {summary}")
        if not ranked or evid[ranked[0]]["delta_bic"] <= bic_threshold:
            final_round = evid
            break
        chosen = ranked[0]
        _compare_with_runner_up(evid, pool, chosen)
        fit = candidate_fits[chosen]
        current.append(chosen)
        pool.remove(chosen)
        steps.append(
            DiscoveryStep(
                effect=chosen,
                evidence={k: v for k, v in evid[chosen].items() if k != "parameters"},
                nrmse_before=float(nrmse_before),
                nrmse_after=evid[chosen]["nrmse_after"],
                candidates=evid,
                parameters=_active_parameters(fit.values, current),
            )
        )
        say(
            f"added {chosen}: nrmse {nrmse_before:.4f} -> {evid[chosen]['nrmse_after']:.4f}"
        )
    fit_log["final_converged"] = fit.converged

    force, scale = setup.force, setup.scale
    nrmse_final = float(np.sqrt(np.mean((fit.force - force) ** 2)) / scale)
    stack = {}
    if skipped.get("interfaces") == INTERFACES_NOT_SEPARABLE and "velocity_dependence" in current:
        stack = stack_check(float(fit.values[PARAMETER_NAMES.index("rate_a")]),
                            info.n_interfaces_in_series)
        skipped["interfaces"] += _stack_note(stack, info.n_interfaces_in_series)
    std_errors = _std_errors(fit.u, fit.jacobian, (fit.force - force) / scale, current, known)
    n = data.n_samples
    return DiscoveryResult(
        baseline=baseline,
        effects_added=[s.effect for s in steps],
        steps=steps,
        final_round=final_round,
        nrmse_initial=nrmse_initial,
        nrmse_final=nrmse_final,
        parameters=_active_parameters(fit.values, current),
        std_errors=std_errors,
        baseline_parameters=_active_parameters(baseline_fit.values, list(base_effects)),
        baseline_effects=list(base_effects),
        data=data,
        info=info,
        forces={"baseline": baseline_fit.force[:n], "final": fit.force[:n]},
        runtime_s=float(_time.perf_counter() - started),
        applicable=applicable,
        skipped=skipped,
        stack_check=stack,
        fit_convergence=fit_log,
    )


def _check_settings(bic_threshold, max_effects, max_steps) -> None:
    if not bic_threshold >= 0:
        raise ValueError(f"bic_threshold: must be >= 0, got {bic_threshold}.")
    if max_effects < 0:
        raise ValueError(f"max_effects: must be >= 0, got {max_effects}.")
    if max_steps < 1:
        raise ValueError(f"max_steps: must be >= 1, got {max_steps}.")


def _checked_known(known) -> dict:
    """The parameters held at given values, each checked against its name and range."""
    known = dict(known or {})
    for name, value in known.items():
        if name not in PARAMETER_NAMES:
            raise ValueError(
                f"known: unknown parameter '{name}'; choose from {list(PARAMETER_NAMES)}."
            )
        p = PARAMETERS[PARAMETER_NAMES.index(name)]
        if not p.lower < float(value) < p.upper:
            raise ValueError(
                f"known['{name}']: {value} is outside the range ({p.lower}, {p.upper}) [{p.unit}]."
            )
    return known


def _requested_candidates(applicable, skipped, candidates) -> list:
    """The applicable effects among `candidates`; the others are noted in `skipped`."""
    if candidates is None:
        return applicable
    unknown = [c for c in candidates if c not in EFFECTS]
    if unknown:
        raise ValueError(
            f"candidates: unknown {unknown}; choose from {list(EFFECT_NAMES)}."
        )
    for name in applicable:
        if name not in candidates:
            skipped[name] = "not among the requested candidates"
    return [c for c in applicable if c in candidates]


class _FitSetup(NamedTuple):
    """What every fit of one discovery shares: the record, its folds and the batch size."""

    data: AugmentedData
    known: dict
    fixed: np.ndarray  # 0 for a known parameter, 1 for a fitted one
    force: np.ndarray  # measured force, both axes stacked
    scale: float  # root-mean-square measured force
    half_cycles: np.ndarray
    travel_range: float
    fold_weights: tuple  # (whole record, fold a, fold b)
    held_a: np.ndarray
    held_b: np.ndarray
    n_members: int  # batch size: current model and every candidate, three fits each
    max_steps: int


def _fit_setup(data, info, known, n_candidates, max_steps) -> _FitSetup:
    force = _stacked(np.asarray(data.force), np.asarray(data.force_y), data.biaxial)
    scale = float(np.sqrt(np.mean(force**2)))
    if not scale > 0:
        raise ValueError(f"{info.source}: the measured force is zero throughout.")
    n = data.n_samples
    half_cycles = half_cycle_index(np.asarray(data.ux))
    fold_a, fold_b = _fold_weights(n, half_cycles)
    held_a, held_b = (_stacked(w, w, data.biaxial) for w in (fold_a, fold_b))
    return _FitSetup(
        data=data,
        known=known,
        fixed=np.array([0.0 if name in known else 1.0 for name in PARAMETER_NAMES]),
        force=force,
        scale=scale,
        half_cycles=half_cycles,
        travel_range=float(np.ptp(np.asarray(data.ux))),
        fold_weights=(np.ones(n), fold_a, fold_b),
        held_a=held_a,
        held_b=held_b,
        n_members=3 * (1 + n_candidates),
        max_steps=max_steps,
    )


class _Fit(NamedTuple):
    """One fitted model: physical and unconstrained parameters, Jacobian, stacked force."""

    values: np.ndarray
    u: np.ndarray
    jacobian: np.ndarray
    converged: bool
    force: np.ndarray


def _fit_of_member(extra, fitted, i, force) -> _Fit:
    return _Fit(fitted[i], extra["u"][i], extra["jacobian"][i], bool(extra["converged"][i]),
                force)


def _fit_padded(setup: _FitSetup, starts, actives, weights, fit_log):
    """Fit B configurations; pads to `n_members` so the solve compiles once.

    Returns (extra, fitted, sims, fit_log) for the B configurations, the log counting them.
    """
    b = len(starts)
    pad = setup.n_members - b
    starts = list(starts) + [starts[0]] * pad
    actives = np.array(list(actives) + [actives[0]] * pad)
    weights = np.array(list(weights) + [weights[0]] * pad)
    values = _inside(np.array([[s[name] for name in PARAMETER_NAMES] for s in starts]))
    free = np.array([_free_mask(a) * setup.fixed for a in actives])
    u, _, jac, conv, steps_taken = fit_batch(
        jnp.asarray(to_unconstrained(values)),
        jnp.asarray(free),
        jnp.asarray(actives),
        jnp.asarray(weights),
        setup.data,
        setup.scale,
        n_iter=setup.max_steps,
    )
    fitted = np.asarray(to_physical(u))
    sims = _simulate_batch(jnp.asarray(fitted), setup.data, jnp.asarray(actives))
    conv = np.asarray(conv)[:b]
    fit_log = {
        **fit_log,
        "fits": fit_log["fits"] + b,
        "unconverged": fit_log["unconverged"] + int(np.count_nonzero(~conv)),
        "max_iterations_used": max(fit_log["max_iterations_used"],
                                   int(np.max(np.asarray(steps_taken)[:b]))),
    }
    extra = {"u": np.asarray(u)[:b], "jacobian": np.asarray(jac)[:b], "converged": conv}
    return extra, fitted[:b], {k: np.asarray(v)[:b] for k, v in sims.items()}, fit_log


def _baseline_starts(setup: _FitSetup) -> list:
    """Several starts of the rate and of the yield displacement, one per batch member."""
    known = setup.known
    start0 = _start_values(setup.data)
    start0.update({name: float(v) for name, v in known.items()})
    starts = []
    for k in range(setup.n_members):
        s = dict(start0)
        if "rate_a" not in known:
            s["rate_a"] = PARAMETERS[PARAMETER_NAMES.index("rate_a")].initial * 10.0 ** (
                (k % 3) - 1
            )
        s["yield_disp"] = start0["yield_disp"] * 4.0 ** ((k // 3) % 3 - 1)
        starts.append(s)
    return starts


def _fit_baseline(setup: _FitSetup, effects, fit_log):
    """Fit `effects` from several starts and keep the best: (fit, nrmse, fit_log)."""
    n_members = setup.n_members
    mask = np.asarray(active_mask(effects))
    extra, fitted, sims, fit_log = _fit_padded(
        setup, _baseline_starts(setup), [mask] * n_members,
        [setup.fold_weights[0]] * n_members, fit_log,
    )
    stacked = _stacked(sims["force"], sims["force_y"], setup.data.biaxial)
    sse = np.sum((stacked - setup.force) ** 2, axis=1)
    best = int(np.argmin(sse))
    fit = _fit_of_member(extra, fitted, best, stacked[best].copy())
    nrmse = float(np.sqrt(sse[best] / setup.force.size) / setup.scale)
    return fit, nrmse, fit_log


def _candidate_start(setup: _FitSetup, values, current, config) -> dict:
    """Start of a fit of `config`: the current fit, effects not yet in it at their start."""
    known = setup.known
    s = {name: float(values[i]) for i, name in enumerate(PARAMETER_NAMES)}
    for name in config:
        if name not in current:
            s.update({p.name: p.initial for p in EFFECTS[name].parameters
                      if p.name not in known})
            for p in EFFECTS[name].parameters:
                # Start at the value for which the effect vanishes (isotropy: T = P).
                if p.neutral_of is not None and p.name not in known:
                    s[p.name] = s[p.neutral_of]
            if name == "backlash" and "backlash_gap" not in known:
                s["backlash_gap"] = 0.02 * setup.travel_range
            if name == "velocity_dependence":
                # Keep the low-speed friction where the constant friction was.
                f_now = s["f_max"]
                if "f_max" not in known:
                    s["f_max"] = 1.5 * f_now
                if "delta_f" not in known:
                    s["delta_f"] = s["f_max"] - f_now
    return s


def _fit_round(setup: _FitSetup, values, current, pool, fit_log):
    """Refit the current model and each candidate added, on the record and both folds.

    Returns (evidence per candidate, nrmse of the current model, fit per candidate, fit_log).
    """
    configs = [list(current)] + [list(current) + [c] for c in pool]
    starts, actives, weights = [], [], []
    for config in configs:
        s = _candidate_start(setup, values, current, config)
        for w in setup.fold_weights:
            starts.append(s)
            actives.append(np.asarray(active_mask(config)))
            weights.append(w)
    extra, fitted, sims, fit_log = _fit_padded(setup, starts, actives, weights, fit_log)
    err = _stacked(sims["force"], sims["force_y"], setup.data.biaxial) - setup.force[None, :]
    evid, nrmse_before = _round_evidence(setup, err, fitted, sims, pool)
    fits = {
        name: _fit_of_member(extra, fitted, 3 * j, err[3 * j] + setup.force)
        for j, name in enumerate(pool, start=1)
    }
    return evid, nrmse_before, fits, fit_log


def _held_out_rms(setup: _FitSetup, err, i) -> float:
    """Held-out root-mean-square error of the fold pair at rows i + 1 and i + 2 of `err`."""
    return math.sqrt(
        (np.sum((err[i + 1] ** 2) * setup.held_b) + np.sum((err[i + 2] ** 2) * setup.held_a))
        / setup.force.size
    )


def _round_evidence(setup: _FitSetup, err, fitted, sims, pool):
    """Evidence for each candidate of a round (module docstring) and the nrmse before it."""
    n_total, scale, data = setup.force.size, setup.scale, setup.data
    ref_cv = _held_out_rms(setup, err, 0)
    ref_sse = float(np.sum(err[0] ** 2))
    nrmse_before = math.sqrt(ref_sse / n_total) / scale
    regress = regressors(data, sims_row(sims, 0), setup.half_cycles)
    evid = {}
    for j, name in enumerate(pool, start=1):
        full = err[3 * j]
        sse_c = float(np.sum(full**2))
        cv = _held_out_rms(setup, err, 3 * j)
        n_eff = effective_samples(full)
        k = max(sum(p.name not in setup.known for p in EFFECTS[name].parameters), 1)
        delta_bic = n_eff * math.log(ref_sse / max(sse_c, 1e-300)) - k * math.log(n_eff)
        evid[name] = {
            "delta_bic": float(delta_bic),
            "holdout_gain": float(1.0 - cv / ref_cv) if ref_cv > 0 else 0.0,
            "n_eff": float(n_eff),
            "nrmse_before": float(nrmse_before),
            "nrmse_after": float(math.sqrt(sse_c / n_total) / scale),
            "residual_correlation": residual_correlation(
                sims["force"][0], regress, name, data, sims_row(sims, 0)
            ),
            "confidence": confidence_wording(delta_bic),
            "parameters": {
                p.name: float(fitted[3 * j][PARAMETER_NAMES.index(p.name)])
                for p in EFFECTS[name].parameters
            },
        }
    return evid, nrmse_before


def _compare_with_runner_up(evid, pool, chosen) -> None:
    """Add to `evid[chosen]` the runner-up, the margin over it and how sure the naming is."""
    others = sorted(
        (c for c in pool if c != chosen), key=lambda c: -evid[c]["delta_bic"]
    )
    if others:
        margin = evid[chosen]["delta_bic"] - max(evid[others[0]]["delta_bic"], 0.0)
        evid[chosen]["runner_up"] = others[0]
    else:
        margin = evid[chosen]["delta_bic"]
        evid[chosen]["runner_up"] = None
    evid[chosen]["margin_over_runner_up"] = float(margin)
    evid[chosen]["naming_confidence"] = confidence_wording(margin)


def _stack_note(stack: dict, series: int) -> str:
    """What `stack_check` says, appended to why `interfaces` was skipped."""
    return (
        f"; here rate_a / n = {stack['rate_effective'] * INCH:.3g} s/in, so with a rate_a "
        f"per interface in Table 1's range n is in [{stack['n_low']:.1f}, "
        f"{stack['n_high']:.1f}]"
        + ("" if stack["consistent_with_stated"] else
           f", not the {series} stated: a stack of interfaces in "
           "series (or a material outside Table 1)")
    )


def _baseline_effects(baseline) -> tuple:
    """Effects of a named baseline, or of a composition given as effect names (checked)."""
    if isinstance(baseline, str):
        if baseline not in BASELINES:
            raise ValueError(
                f"baseline: unknown '{baseline}'; use one of {', '.join(BASELINES)}."
            )
        return tuple(BASELINES[baseline])
    unknown = [name for name in baseline if name not in EFFECTS]
    if unknown:
        raise ValueError(f"effects: unknown {unknown}; the known effects are "
                         f"{', '.join(EFFECT_NAMES)}.")
    return tuple(dict.fromkeys(baseline))


def sims_row(sims: dict, i: int) -> dict:
    """Row `i` of a batch of simulation outputs."""
    return {k: v[i] for k, v in sims.items()}


def _std_errors(u, jac_u, residual, effects, known) -> dict:
    """Standard errors of the fitted parameters at the optimum, in SI.

    The Jacobian in the unconstrained parameters u is mapped to the physical ones through
    dx/du of `to_physical`; the covariance is sigma^2 (J^T J)^-1 (`covariance_from_jacobian`),
    inflated by n / n_eff for residuals correlated from sample to sample (n_eff as in the
    evidence), since n correlated samples carry the information of n_eff independent ones.
    """
    u = np.asarray(u, float)
    s = 1.0 / (1.0 + np.exp(-u))
    x = np.asarray(to_physical(jnp.asarray(u)))
    dxdu = (_HI - _LO) * s * (1 - s) * np.where(_LOG, x, 1.0)
    names = [n for n in _active_parameters(x, effects) if n not in known]
    cols = [PARAMETER_NAMES.index(n) for n in names]
    jac_x = np.asarray(jac_u)[:, cols] / dxdu[cols]
    cov, _ = covariance_from_jacobian(jac_x, np.asarray(residual))
    inflation = len(residual) / effective_samples(residual)
    out = {n: float(np.sqrt(abs(cov[i, i]) * inflation)) for i, n in enumerate(names)}
    out.update({n: 0.0 for n in known})
    return out


def _active_parameters(values, effects) -> dict:
    out = {}
    for i, name in enumerate(PARAMETER_NAMES):
        owner = PARAMETER_EFFECT[i]
        if owner == "baseline" or owner in effects:
            out[name] = float(values[i])
    return out
