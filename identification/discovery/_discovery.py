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
     on the cycles left out of each fold's fit (blocked cross-validation). Where CV_before is
     at rounding level (at most `RESOLUTION` = 1e-5 of the RMS force, the fits' tolerance: a
     noise-free record of the current model) there is nothing to gain: the gain is 0
     (`nothing_to_gain`), `holdout_improvement` (CV_before - CV_after) / RMS force gives the
     change against the force scale, and each SSR of delta_bic counts as at least that level,
     so no candidate is added on rounding errors.
4. The candidate with the largest delta_bic among those with a positive held-out gain is
   added if its delta_bic exceeds `bic_threshold` (10, "very strong"); otherwise the model is
   declared complete ("no missing effect"). How sure the *naming* is (this effect rather than
   the runner-up) is the margin of its delta_bic over the runner-up's, read on the same scale.

Every fit of one round (current model and every candidate, full record and both folds) is a
single vmapped, compiled call of optimistix's Levenberg-Marquardt solver (`fit_batch`): effects
are switched by a 0/1 mask and the parameters of effects that are off are held, so the model is
compiled once per record.
"""

import time as _time

import numpy as np

from teflon_jax.tables import load_table1
from teflon_jax.units import INCH

from ..least_squares import covariance_from_jacobian
from ._augmented import (
    PARAMETER_EFFECT,
    PARAMETER_NAMES,
    PARAMETERS,
    AugmentedData,
    BiaxialAugmentedData,
    RecordInfo,
    active_mask,
    prepare_record,
)
from ._batch_fit import _free_mask
from ._diagnostics import effective_samples
from ._effects import BASELINES, EFFECT_NAMES, EFFECTS
from ._progress import FLAT_COST, Progress, candidate_lines
from ._result import (
    DEFAULT_BIC_THRESHOLD,
    CompositionFit,
    DiscoveryResult,
    DiscoveryStep,
    confidence_wording,
)
from ._rounds import _fit_baseline, _fit_round, _fit_setup, fit_nrmse

INTERFACES_NOT_SEPARABLE = (
    "not separable from rate_a: Eq. 1 at |v| / n depends on rate_a and n only through "
    "rate_a / n, at every speed, so no set of amplitudes or frequencies separates them; "
    "the fitted rate_a is rate_a / n (see `stack_check`), and n is identified with rate_a "
    "known (e.g. from Table 1, `known={'rate_a': ...}`)"
)
"""Why `interfaces` is not a candidate while rate_a is fitted."""


def _applicable(data: AugmentedData, info: RecordInfo, known):
    applicable, skipped = [], {}
    for name, effect in EFFECTS.items():
        if name == "interfaces" and "rate_a" not in known:
            skipped[name] = INTERFACES_NOT_SEPARABLE
        elif effect.requires == "varying_normal_load" and not info.varying_normal_load:
            skipped[name] = (
                "normal load constant in this record (no contrast to identify it)"
            )
        elif effect.requires == "biaxial" and not isinstance(data, BiaxialAugmentedData):
            skipped[name] = "uniaxial record (one sliding direction only)"
        elif effect.requires == "uniaxial" and isinstance(data, BiaxialAugmentedData):
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


def _check_coefficient_range(data: AugmentedData, info: RecordInfo) -> None:
    """`ValueError` when force / normal load lies far above the friction constants' range (a
    normal load given only to scale the force, e.g. 1 N, makes every model force zero)."""
    upper = PARAMETERS[PARAMETER_NAMES.index("f_max")].upper
    mu = np.hypot(np.asarray(data.force), np.asarray(data.force_y)) / np.asarray(data.normal)
    typical = float(np.percentile(mu, 90))
    if typical > upper:
        needed = typical / (0.5 * upper) * float(np.mean(np.asarray(data.normal)))
        raise ValueError(
            f"{info.source}: force / normal load reaches {typical:.3g}, above the range of the "
            f"friction constants (f_max <= {upper}); give the normal load that presses the "
            f"surfaces together, or one that scales the force into that range (e.g. "
            f"--normal-load {needed / 1000:.3g}kN).")


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
      converges (`FIT_RTOL`, `FIT_ATOL`) and reports whether it did (`DiscoveryResult.fit_convergence`).
    - `known`: parameters held at given values (SI), e.g. `{"rate_a": 23.6}` from Table 1;
      with `rate_a` known the `interfaces` candidate becomes identifiable.
    - `callback`: called with a line of progress text (for a CLI), or `None`.

    **Returns:** a `DiscoveryResult`.
    """
    base_effects = _baseline_effects(baseline)
    check_settings(bic_threshold, max_effects, max_steps)
    started = _time.perf_counter()
    say = callback or (lambda text: None)
    known = _checked_known(known)
    data, info = prepare_record(record, max_samples=max_samples)
    _check_coefficient_range(data, info)
    applicable, skipped = _applicable(data, info, known)
    applicable = _requested_candidates(applicable, skipped, candidates)
    pool = [c for c in applicable if c not in base_effects]
    setup = _fit_setup(data, info, known, len(pool), max_steps)
    fit_log = {"fits": 0, "unconverged": 0, "max_iterations_used": 0,
               "iteration_limit": int(max_steps)}

    name = baseline if isinstance(baseline, str) else " + ".join(base_effects) or "coulomb"
    progress = _announce(say, data, setup, name, pool, [s for s in skipped if s not in base_effects],
                         max_effects, max_steps)
    progress.calling(f"baseline {name}: fitting from {setup.n_members} starts")
    fit, nrmse_initial, fit_log = _fit_baseline(setup, list(base_effects), fit_log)
    say(f"baseline {baseline}: nrmse {nrmse_initial:.4f}")
    progress.took(f"baseline {name}", progress.called(), min(max_effects, len(pool)))
    baseline_fit = fit
    compositions = [_composition(setup, base_effects, fit)]

    fit, current, steps, final_round, fit_log = _add_effects(
        setup, fit, list(base_effects), pool, max_effects, bic_threshold, progress, fit_log,
        compositions)
    progress.done()
    fit_log["final_converged"] = fit.converged

    force, scale = setup.force, setup.scale
    nrmse_final = fit_nrmse(fit.force, force, scale)
    stack = {}
    if skipped.get("interfaces") == INTERFACES_NOT_SEPARABLE and "velocity_dependence" in current:
        stack = stack_check(float(fit.values[PARAMETER_NAMES.index("rate_a")]),
                            info.n_interfaces_in_series)
        skipped["interfaces"] += _stack_note(stack, info.n_interfaces_in_series)
    std_errors = _std_errors(fit.values, fit.jacobian, (fit.force - force) / scale, current,
                             known)
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
        compositions=compositions,
    )


def _composition(setup, effects, fit) -> CompositionFit:
    """The `CompositionFit` of `fit`, a fit of `effects` to the whole record."""
    return CompositionFit(
        effects=tuple(effects), values=np.asarray(fit.values, float),
        free=_free_mask(np.asarray(active_mask(list(effects)))) * setup.fixed,
        jacobian=np.asarray(fit.jacobian, float),
        residual=(np.asarray(fit.force) - setup.force) / setup.scale, converged=bool(fit.converged))


def _announce(say, data, setup, baseline, pool, skipped, max_effects, max_steps) -> Progress:
    """The `Progress` of a search from the baseline named `baseline`, its plan said: the
    baseline, then at most one round per effect added, each one batched call of
    `setup.n_members` fits; `skipped` the candidates named as not tried."""
    progress = Progress(say, FLAT_COST, (type(data).__name__, setup.n_members, data.n_samples,
                                         max_steps), setup.n_members, data.n_samples, label=baseline)
    rounds = min(max_effects, len(pool))
    work = f"baseline {baseline} alone"
    if rounds:
        work = (f"baseline {baseline}, then up to {rounds} round{'s' if rounds != 1 else ''} over "
                f"{len(pool)} candidate{'s' if len(pool) != 1 else ''} ({', '.join(pool)}), each "
                "fitting the model alone and with each candidate, on the record and on two folds "
                "of its cycles")
    progress.plan(work, 1 + rounds, skipped)
    return progress


def _add_effects(setup, fit, current, pool, max_effects, bic_threshold, progress, fit_log,
                 compositions):
    """Add the candidate with the strongest evidence, round after round, while it passes;
    every candidate's fit to the whole record is appended to `compositions`; each round said
    through `progress` (`Progress`).

    Returns (fit, effects of the final model, steps, evidence of the refused last round, fit_log).
    """
    say = progress.say
    current, pool = list(current), list(pool)
    steps, final_round = [], {}
    while pool and len(steps) < max_effects:
        number = len(steps) + 1
        progress.calling(f"round {number}: trying {', '.join(pool)}, each added to "
                         f"{' + '.join([progress.label, *(s.effect for s in steps)])}")
        evid, nrmse_before, candidate_fits, fit_log = _fit_round(
            setup, fit.values, current, pool, fit_log
        )
        took = progress.called()
        compositions += [_composition(setup, current + [c], candidate_fits[c]) for c in pool]
        for line in candidate_lines(evid, pool):
            say(line)
        summary = ", ".join(f"{c} {evid[c]['delta_bic']:.1f}" for c in pool)
        say(f"round {number}: delta_bic {summary}")
        chosen = chosen_effect(evid, pool, bic_threshold)
        if chosen is None:
            final_round = evid
            progress.took(f"round {number}", took, 0)
            break
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
        progress.took(f"round {number}", took, min(max_effects - len(steps), len(pool)))
    return fit, current, steps, final_round, fit_log


def chosen_effect(evid: dict, pool, bic_threshold: float):
    """The decision rule (module docstring, step 4): the candidate with the largest delta_bic
    among those with a positive held-out gain, if its delta_bic exceeds `bic_threshold`, with
    its runner-up and naming confidence added to `evid[chosen]`; None when no candidate passes."""
    ranked = sorted((c for c in pool if evid[c]["holdout_gain"] > 0),
                    key=lambda c: -evid[c]["delta_bic"])
    if not ranked or evid[ranked[0]]["delta_bic"] <= bic_threshold:
        return None
    _compare_with_runner_up(evid, pool, ranked[0])
    return ranked[0]


def check_settings(bic_threshold, max_effects, max_steps) -> None:
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


def _std_errors(values, jacobian, residual, effects, known) -> dict:
    """Standard errors of the fitted parameters at the optimum, in SI.

    From the Jacobian of the residual in the physical parameters, the covariance is
    sigma^2 (J^T J)^-1 (`covariance_from_jacobian`), inflated by n / n_eff for residuals
    correlated from sample to sample (n_eff as in the evidence), since n correlated samples
    carry the information of n_eff independent ones.
    """
    names = [n for n in _active_parameters(values, effects) if n not in known]
    cols = [PARAMETER_NAMES.index(n) for n in names]
    jac_x = np.asarray(jacobian)[:, cols]
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
