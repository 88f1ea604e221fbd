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

import dataclasses
import functools
import math
import time as _time

import jax
import jax.numpy as jnp
import numpy as np

from ._augmented import (
    PARAMETER_EFFECT,
    PARAMETER_NAMES,
    PARAMETERS,
    AugmentedData,
    RecordInfo,
    active_mask,
    prepare_record,
    simulate_augmented,
)
from ._diagnostics import half_cycle_index, regressors, residual_correlation
from ._effects import BASELINES, EFFECT_NAMES, EFFECTS
from ._fit import covariance_from_jacobian

DEFAULT_BIC_THRESHOLD = 10.0
"""Smallest delta_bic that adds an effect: "very strong" evidence on Kass & Raftery's scale."""


def confidence_wording(delta_bic: float) -> str:
    """Kass & Raftery (1995) wording for 2 ln(Bayes factor) ~ delta_bic."""
    if not math.isfinite(delta_bic) or delta_bic < 0:
        return "against (the data prefer the model without it)"
    if delta_bic < 2:
        return "not worth more than a bare mention"
    if delta_bic < 6:
        return "positive"
    if delta_bic < 10:
        return "strong"
    return "very strong"


@dataclasses.dataclass
class DiscoveryStep:
    """One accepted effect: its name, the evidence, and the error before and after.

    `evidence` holds `delta_bic`, `holdout_gain`, `n_eff`, `nrmse_before`, `nrmse_after`,
    `residual_correlation`, `confidence` (that the effect is there), `runner_up`,
    `margin_over_runner_up` (its delta_bic minus the runner-up's, or minus 0 when that is
    negative) and `naming_confidence` (Kass & Raftery wording of that margin: that it is this
    effect rather than the next best); `candidates` the evidence of every candidate of the
    round (name -> dict), `parameters` the fitted model after the step.
    """

    effect: str
    evidence: dict
    nrmse_before: float
    nrmse_after: float
    candidates: dict
    parameters: dict


@dataclasses.dataclass
class DiscoveryResult:
    """Outcome of `discover_effects`.

    - `baseline`, `effects_added` (in order), `steps` (`DiscoveryStep`s), `final_round`
      (evidence of the candidates that were refused, name -> dict; empty if none were left),
    - `nrmse_initial`, `nrmse_final`: normalised RMS error of the baseline and final fits,
      sqrt(mean((F_model - F_meas)^2)) / sqrt(mean(F_meas^2)),
    - `parameters`: fitted parameters of the final model (SI, active ones only),
    - `std_errors`: their standard errors (see `_std_errors`; 0 for parameters held known),
    - `baseline_parameters`, `data`, `info` (the prepared record), `forces`: model force of the
      baseline and final fits, `runtime_s`, `applicable` candidates and `skipped` ones with why.
    """

    baseline: str
    effects_added: list
    steps: list
    final_round: dict
    nrmse_initial: float
    nrmse_final: float
    parameters: dict
    std_errors: dict
    baseline_parameters: dict
    data: AugmentedData
    info: RecordInfo
    forces: dict
    runtime_s: float
    applicable: list
    skipped: dict

    def to_json(self) -> dict:
        """The JSON document of the `diagnose` command (plain Python types; a non-finite
        number, e.g. the standard error of an unidentifiable parameter, becomes `null`)."""
        return _finite_or_null(
            {
                "baseline": self.baseline,
                "steps": [
                    {
                        "effect": s.effect,
                        "evidence": s.evidence,
                        "nrmse_before": s.nrmse_before,
                        "nrmse_after": s.nrmse_after,
                        "parameters": s.parameters,
                        "candidates": s.candidates,
                    }
                    for s in self.steps
                ],
                "effects_added": list(self.effects_added),
                "nrmse_initial": self.nrmse_initial,
                "nrmse_final": self.nrmse_final,
                "parameters": self.parameters,
                "std_errors": self.std_errors,
                "baseline_parameters": self.baseline_parameters,
                "conclusion": (
                    "no missing effect"
                    if not self.effects_added
                    else "added: " + ", ".join(self.effects_added)
                ),
                "refused_candidates": self.final_round,
                "skipped_candidates": self.skipped,
                "runtime_s": self.runtime_s,
                "record": {
                    "source": self.info.source,
                    "samples_used": int(self.data.n_samples),
                    "decimation": self.info.decimation,
                    "interfaces_recorded": self.info.n_interfaces_recorded,
                    "contact_area_assumed": self.info.contact_area_assumed,
                },
            }
        )


def _finite_or_null(value):
    if isinstance(value, dict):
        return {k: _finite_or_null(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite_or_null(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


_LOWER = np.array([p.lower for p in PARAMETERS])
_UPPER = np.array([p.upper for p in PARAMETERS])
_LOG = np.array([p.log_scale for p in PARAMETERS])
_LO = np.array([math.log(p.lower) if p.log_scale else p.lower for p in PARAMETERS])
_HI = np.array([math.log(p.upper) if p.log_scale else p.upper for p in PARAMETERS])


def to_physical(u):
    """Unconstrained vector -> physical parameters: x = lo + (hi - lo) sigmoid(u), in log
    space for the parameters marked `log_scale` (bounds are never left)."""
    y = _LO + (_HI - _LO) * jax.nn.sigmoid(u)
    return jnp.where(_LOG, jnp.exp(y), y)


def to_unconstrained(x) -> np.ndarray:
    """Inverse of `to_physical` (numpy; x strictly inside the bounds)."""
    x = np.asarray(x, float)
    y = np.where(_LOG, np.log(np.maximum(x, 1e-300)), x)
    p = np.clip((y - _LO) / (_HI - _LO), 1e-9, 1 - 1e-9)
    return np.log(p) - np.log1p(-p)


def _free_mask(active) -> np.ndarray:
    """1 for the parameters of the baseline and of the active effects."""
    on = {name: active[i] > 0 for i, name in enumerate(EFFECT_NAMES)}
    return np.array(
        [1.0 if owner == "baseline" or on[owner] else 0.0 for owner in PARAMETER_EFFECT]
    )


@functools.partial(jax.jit, static_argnames=("n_iter",))
def fit_batch(u0, free, actives, weights, data, scale, *, n_iter: int = 40):
    """Masked, bounded Levenberg-Marquardt fits of B model configurations in one call.

    Minimises sum((w (F_model - F_meas) / scale)^2) over the unconstrained parameters u
    (`to_physical`), with the parameters where `free` is 0 held at their start. Steps:
    (J^T J + lam diag(J^T J)) du = -J^T r (Marquardt 1963), lam divided by 3 after a success
    and multiplied by 4 after a failure; `n_iter` iterations.

    **Arguments:** `u0`, `free` (B, P); `actives` (B, E) effect masks; `weights` (B, n) sample
    weights (0 leaves a sample out); `data` (`AugmentedData`); `scale` force scale [N].

    **Returns:** `(u, cost, jacobian)`: final unconstrained parameters (B, P), cost
    0.5 sum r^2 (B,), and the Jacobian of r in u at the end (B, n, P).
    """

    def one(u_start, free_i, active, weight):
        def residual(u):
            params = {name: x for name, x in zip(PARAMETER_NAMES, to_physical(u))}
            sim = simulate_augmented(params, data, active)
            r = weight * (sim["force"] - data.force) / scale
            if data.biaxial:
                r = jnp.concatenate([r, weight * (sim["force_y"] - data.force_y) / scale])
            return r, r

        def cost_of(u):
            return 0.5 * jnp.sum(residual(u)[0] ** 2)

        def body(_, carry):
            u, lam, cost = carry
            jac, r = jax.jacfwd(residual, has_aux=True)(u)
            jac = jac * free_i
            grad = jac.T @ r
            hess = jac.T @ jac
            diag = jnp.diag(hess)
            system = hess + jnp.diag(lam * (diag + 1e-12) + (1.0 - free_i))
            step = -jnp.linalg.solve(system, grad) * free_i
            trial = u + jnp.clip(step, -4.0, 4.0)
            trial_cost = cost_of(trial)
            better = jnp.isfinite(trial_cost) & (trial_cost < cost)
            u = jnp.where(better, trial, u)
            cost = jnp.where(better, trial_cost, cost)
            lam = jnp.clip(jnp.where(better, lam / 3.0, lam * 4.0), 1e-9, 1e9)
            return u, lam, cost

        u, _, cost = jax.lax.fori_loop(0, n_iter, body, (u_start, 1e-2, cost_of(u_start)))
        jac = jax.jacfwd(lambda v: residual(v)[0])(u) * free_i
        return u, cost, jac

    return jax.vmap(one)(u0, free, actives, weights)


@jax.jit
def _simulate_batch(values, data, actives):
    def one(v, active):
        params = {name: v[i] for i, name in enumerate(PARAMETER_NAMES)}
        return simulate_augmented(params, data, active)

    return jax.vmap(one)(values, actives)


def _fold_weights(n: int, hc) -> tuple[np.ndarray, np.ndarray]:
    """Two complementary 0/1 masks over the samples: alternate cycles.

    A cycle here is a pair of consecutive strokes (half-cycles 1-2, 3-4, ...; the stroke from
    rest, 0, is a cycle of its own), so each fold holds sliding in both directions and an
    effect that differs between them (asymmetry) stays identifiable in every fold. Records
    with fewer than two cycles are split into alternate eighths of their length instead.
    """
    cycle = (np.asarray(hc) + 1) // 2
    if cycle.max() >= 2:
        a = (cycle % 2 == 0).astype(float)
    else:
        a = ((np.arange(n) * 8 // n) % 2 == 0).astype(float)
    return a, 1.0 - a


def _stacked(x, y, biaxial: bool):
    """x and y components one after the other along the last axis (biaxial), else x."""
    return np.concatenate([x, y], axis=-1) if biaxial else x


def _lag1(r) -> float:
    r = np.asarray(r, float) - np.mean(r)
    denominator = float(r @ r)
    if denominator <= 0:
        return 0.0
    return float(np.clip((r[1:] @ r[:-1]) / denominator, 0.0, 0.999))


def effective_samples(residual) -> float:
    """n_eff = n (1 - rho) / (1 + rho) with rho the lag-1 autocorrelation (>= 0) of `residual`."""
    rho = _lag1(residual)
    return max(float(len(residual)) * (1.0 - rho) / (1.0 + rho), 2.0)


def _applicable(info: RecordInfo, known):
    applicable, skipped = [], {}
    for name, effect in EFFECTS.items():
        if name == "interfaces" and "rate_a" not in known:
            skipped[name] = (
                "Eq. 1 at |v| / n only rescales rate_a, which is fitted: n is identifiable only "
                "with rate_a known (e.g. from Table 1, `known={'rate_a': ...}`)"
            )
        elif effect.requires == "varying_normal_load" and not info.varying_normal_load:
            skipped[name] = (
                "normal load constant in this record (no contrast to identify it)"
            )
        elif effect.requires == "biaxial" and not info.biaxial:
            skipped[name] = "uniaxial record (one sliding direction only)"
        else:
            applicable.append(name)
    return applicable, skipped


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
    max_steps: int = 40,
    known=None,
    callback=None,
) -> DiscoveryResult:
    """Find the effects a test record shows beyond a baseline model, one at a time.

    **Arguments:**

    - `record`: a `TestRecord` (uniaxial, with time and normal load).
    - `baseline`: `"paper1990"` (Eq. 1 + Bouc-Wen, default) or `"coulomb"`.
    - `candidates`: names from `EFFECT_NAMES` to consider (default: all that the record can
      identify).
    - `bic_threshold`: smallest delta_bic that adds an effect (default 10: "very strong").
    - `max_effects`: at most this many effects are added.
    - `max_samples`: longer records are decimated to about this many samples.
    - `max_steps`: Levenberg-Marquardt steps per fit.
    - `known`: parameters held at given values (SI), e.g. `{"rate_a": 23.6}` from Table 1;
      with `rate_a` known the `interfaces` candidate becomes identifiable.
    - `callback`: called with a line of progress text (for a CLI), or `None`.

    **Returns:** a `DiscoveryResult`.
    """
    if baseline not in BASELINES:
        raise ValueError(
            f"baseline: unknown '{baseline}'; use one of {', '.join(BASELINES)}."
        )
    if not bic_threshold >= 0:
        raise ValueError(f"bic_threshold: must be >= 0, got {bic_threshold}.")
    if max_effects < 0:
        raise ValueError(f"max_effects: must be >= 0, got {max_effects}.")
    if max_steps < 1:
        raise ValueError(f"max_steps: must be >= 1, got {max_steps}.")
    started = _time.perf_counter()
    say = callback or (lambda text: None)
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
    fixed = np.array([0.0 if name in known else 1.0 for name in PARAMETER_NAMES])
    data, info = prepare_record(record, max_samples=max_samples)
    applicable, skipped = _applicable(info, known)
    if candidates is not None:
        unknown = [c for c in candidates if c not in EFFECTS]
        if unknown:
            raise ValueError(
                f"candidates: unknown {unknown}; choose from {list(EFFECT_NAMES)}."
            )
        for name in applicable:
            if name not in candidates:
                skipped[name] = "not among the requested candidates"
        applicable = [c for c in applicable if c in candidates]
    current = list(BASELINES[baseline])
    pool = [c for c in applicable if c not in current]

    n = data.n_samples
    force = _stacked(np.asarray(data.force), np.asarray(data.force_y), data.biaxial)
    n_total = force.size
    scale = float(np.sqrt(np.mean(force**2)))
    if not scale > 0:
        raise ValueError(f"{info.source}: the measured force is zero throughout.")
    half_cycles = half_cycle_index(np.asarray(data.ux))
    fold_a, fold_b = _fold_weights(n, half_cycles)
    held_a, held_b = (_stacked(w, w, data.biaxial) for w in (fold_a, fold_b))
    ones = np.ones(n)
    n_members = 3 * (1 + len(pool))

    def run_batch(starts, actives, weights):
        """Fit B configurations; pads to `n_members` so the solve compiles once."""
        b = len(starts)
        pad = n_members - b
        starts = list(starts) + [starts[0]] * pad
        actives = np.array(list(actives) + [actives[0]] * pad)
        weights = np.array(list(weights) + [weights[0]] * pad)
        values = _inside(np.array([[s[name] for name in PARAMETER_NAMES] for s in starts]))
        free = np.array([_free_mask(a) * fixed for a in actives])
        u, _, jac = fit_batch(
            jnp.asarray(to_unconstrained(values)),
            jnp.asarray(free),
            jnp.asarray(actives),
            jnp.asarray(weights),
            data,
            scale,
            n_iter=max_steps,
        )
        fitted = np.asarray(to_physical(u))
        sims = _simulate_batch(jnp.asarray(fitted), data, jnp.asarray(actives))
        extra = {"u": np.asarray(u)[:b], "jacobian": np.asarray(jac)[:b]}
        return extra, fitted[:b], {k: np.asarray(v)[:b] for k, v in sims.items()}

    # Baseline: several starts of the rate and of the yield displacement, keep the best.
    start0 = _start_values(data)
    start0.update({name: float(v) for name, v in known.items()})
    starts = []
    for k in range(n_members):
        s = dict(start0)
        if "rate_a" not in known:
            s["rate_a"] = PARAMETERS[PARAMETER_NAMES.index("rate_a")].initial * 10.0 ** (
                (k % 3) - 1
            )
        s["yield_disp"] = start0["yield_disp"] * 4.0 ** ((k // 3) % 3 - 1)
        starts.append(s)
    mask = np.asarray(active_mask(current))
    extra, fitted, sims = run_batch(starts, [mask] * n_members, [ones] * n_members)
    sims["stacked"] = _stacked(sims["force"], sims["force_y"], data.biaxial)
    sse = np.sum((sims["stacked"] - force) ** 2, axis=1)
    best = int(np.argmin(sse))
    values = fitted[best]
    final_u, final_jac = extra["u"][best], extra["jacobian"][best]
    model_force = sims["stacked"][best]
    nrmse_initial = float(np.sqrt(sse[best] / n_total) / scale)
    say(f"baseline {baseline}: nrmse {nrmse_initial:.4f}")
    baseline_values, baseline_force = values.copy(), model_force.copy()

    steps, final_round = [], {}
    while pool and len(steps) < max_effects:
        configs = [list(current)] + [list(current) + [c] for c in pool]
        starts, actives, weights = [], [], []
        for config in configs:
            s = {name: float(values[i]) for i, name in enumerate(PARAMETER_NAMES)}
            for name in config:
                if name not in current:
                    s.update(
                        {
                            p.name: p.initial
                            for p in EFFECTS[name].parameters
                            if p.name not in known
                        }
                    )
                    if name == "velocity_dependence":
                        # Keep the low-speed friction where the constant friction was.
                        f_now = s["f_max"]
                        if "f_max" not in known:
                            s["f_max"] = 1.5 * f_now
                        if "delta_f" not in known:
                            s["delta_f"] = s["f_max"] - f_now
            for w in (ones, fold_a, fold_b):
                starts.append(s)
                actives.append(np.asarray(active_mask(config)))
                weights.append(w)
        extra, fitted, sims = run_batch(starts, actives, weights)
        err = _stacked(sims["force"], sims["force_y"], data.biaxial) - force[None, :]
        evid = {}
        ref_full = err[0]
        ref_cv = math.sqrt(
            (np.sum((err[1] ** 2) * held_b) + np.sum((err[2] ** 2) * held_a)) / n_total
        )
        ref_sse = float(np.sum(ref_full**2))
        nrmse_before = math.sqrt(ref_sse / n_total) / scale
        regress = regressors(data, sims_row(sims, 0), half_cycles)
        for j, name in enumerate(pool, start=1):
            full = err[3 * j]
            sse_c = float(np.sum(full**2))
            cv = math.sqrt(
                (
                    np.sum((err[3 * j + 1] ** 2) * held_b)
                    + np.sum((err[3 * j + 2] ** 2) * held_a)
                )
                / n_total
            )
            n_eff = effective_samples(full)
            k = max(sum(p.name not in known for p in EFFECTS[name].parameters), 1)
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
        eligible = [c for c in pool if evid[c]["holdout_gain"] > 0]
        ranked = sorted(eligible, key=lambda c: -evid[c]["delta_bic"])
        summary = ", ".join(f"{c} {evid[c]['delta_bic']:.1f}" for c in pool)
        say(f"round {len(steps) + 1}: delta_bic {summary}")
        if not ranked or evid[ranked[0]]["delta_bic"] <= bic_threshold:
            final_round = evid
            break
        chosen = ranked[0]
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
        j = pool.index(chosen) + 1
        values = fitted[3 * j]
        final_u, final_jac = extra["u"][3 * j], extra["jacobian"][3 * j]
        model_force = err[3 * j] + force
        current.append(chosen)
        pool.remove(chosen)
        steps.append(
            DiscoveryStep(
                effect=chosen,
                evidence={k: v for k, v in evid[chosen].items() if k != "parameters"},
                nrmse_before=float(nrmse_before),
                nrmse_after=evid[chosen]["nrmse_after"],
                candidates=evid,
                parameters=_active_parameters(values, current),
            )
        )
        say(
            f"added {chosen}: nrmse {nrmse_before:.4f} -> {evid[chosen]['nrmse_after']:.4f}"
        )

    nrmse_final = float(np.sqrt(np.mean((model_force - force) ** 2)) / scale)
    std_errors = _std_errors(
        final_u, final_jac, (model_force - force) / scale, current, known
    )
    return DiscoveryResult(
        baseline=baseline,
        effects_added=[s.effect for s in steps],
        steps=steps,
        final_round=final_round,
        nrmse_initial=nrmse_initial,
        nrmse_final=nrmse_final,
        parameters=_active_parameters(values, current),
        std_errors=std_errors,
        baseline_parameters=_active_parameters(baseline_values, list(BASELINES[baseline])),
        data=data,
        info=info,
        forces={"baseline": baseline_force[:n], "final": model_force[:n]},
        runtime_s=float(_time.perf_counter() - started),
        applicable=applicable,
        skipped=skipped,
    )


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
