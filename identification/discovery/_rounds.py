"""The fits of one discovery round: every fit of a round is one padded, vmapped call of the
Levenberg-Marquardt solver (`fit_batch`), and the evidence for each candidate comes
from its fits to the whole record and to two folds of alternate cycles."""

import math
from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from ._augmented import PARAMETER_NAMES, PARAMETERS, AugmentedData, active_mask
from ._batch_fit import (
    FIT_ATOL,
    _fold_weights,
    _free_mask,
    _simulate_batch,
    fit_batch,
)
from ._diagnostics import (
    effective_samples,
    half_cycle_index,
    regressors,
    residual_correlation,
)
from ._effects import EFFECTS
from ._result import confidence_wording


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
    force = data.stack(np.asarray(data.force), np.asarray(data.force_y))
    scale = float(np.sqrt(np.mean(force**2)))
    if not scale > 0:
        raise ValueError(f"{info.source}: the measured force is zero throughout.")
    n = data.n_samples
    half_cycles = half_cycle_index(np.asarray(data.ux))
    fold_a, fold_b = _fold_weights(n, half_cycles)
    held_a, held_b = (data.stack(w, w) for w in (fold_a, fold_b))
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
    """One fitted model: parameters, the Jacobian of its residual in them, stacked force."""

    values: np.ndarray
    jacobian: np.ndarray
    converged: bool
    force: np.ndarray


def _fit_of_member(extra, fitted, i, force) -> _Fit:
    return _Fit(fitted[i], extra["jacobian"][i], bool(extra["converged"][i]), force)


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
    fitted, _, jac, conv, steps_taken = fit_batch(
        values, free, actives, weights, setup.data, setup.scale, max_steps=setup.max_steps)
    sims = _simulate_batch(jnp.asarray(fitted), setup.data, jnp.asarray(actives))
    conv = conv[:b]
    fit_log = {
        **fit_log,
        "fits": fit_log["fits"] + b,
        "unconverged": fit_log["unconverged"] + int(np.count_nonzero(~conv)),
        "max_iterations_used": max(fit_log["max_iterations_used"],
                                   int(np.max(steps_taken[:b]))),
    }
    extra = {"jacobian": jac[:b], "converged": conv}
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
    stacked = setup.data.stack(sims["force"], sims["force_y"])
    sse = np.sum((stacked - setup.force) ** 2, axis=1)
    best = int(np.argmin(sse))
    fit = _fit_of_member(extra, fitted, best, stacked[best].copy())
    return fit, nrmse(float(sse[best]), setup.force.size, setup.scale), fit_log


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
    err = setup.data.stack(sims["force"], sims["force_y"]) - setup.force[None, :]
    evid, nrmse_before = _round_evidence(setup, err, fitted, sims, pool)
    fits = {
        name: _fit_of_member(extra, fitted, 3 * j, err[3 * j] + setup.force)
        for j, name in enumerate(pool, start=1)
    }
    return evid, nrmse_before, fits, fit_log


def _held_out_rms(setup: _FitSetup, err, i) -> float:
    """Held-out root-mean-square error of the fold pair at rows i + 1 and i + 2 of `err`."""
    return held_out_rms(err[i + 1], err[i + 2], setup.held_a, setup.held_b)


def nrmse(sse: float, n: int, scale: float) -> float:
    """RMS(model - measured) / RMS(measured) force [-]: sqrt(SSE / n) / `scale`, from the sum of
    squared residuals `sse` [N^2] over `n` samples; the one formula of every nrmse a discovery
    reports (a baseline refitted with nothing added reads the same number to the bit)."""
    return float(math.sqrt(sse / n) / scale)


def fit_nrmse(model, measured, scale: float) -> float:
    """`nrmse` of a fit's force `model` against the `measured` force [N] (arrays alike)."""
    return nrmse(float(np.sum((np.asarray(model) - measured) ** 2)), np.size(measured), scale)


def held_out_rms(err_a, err_b, held_a, held_b) -> float:
    """Root-mean-square prediction error on the cycles each fold's fit left out: `err_a` the
    error of the fit to fold a (weights `held_a`), read on fold b (`held_b`), and the reverse."""
    return math.sqrt((np.sum(err_a**2 * held_b) + np.sum(err_b**2 * held_a)) / np.size(err_a))


RESOLUTION = FIT_ATOL
"""The smallest root-mean-square force error, as a fraction of the record's force scale (its RMS
force), that the evidence tells from rounding: the batched fits' tolerance (`FIT_ATOL`, 1e-5;
the series pendulums' members use the same), below which a fit's steps no longer change its
residuals. A smaller sum of squares is read as this level, and a held-out error below it leaves
nothing to gain, so that no evidence is a ratio of two rounding errors (a noise-free record
of the current model)."""


def candidate_evidence(ref_sse: float, ref_cv: float, full, cv: float, k: int, scale: float) -> dict:
    """The evidence for one candidate (module docstring of `_discovery`): its residual `full`
    (n,) on the whole record and held-out error `cv` against the current model's `ref_sse`,
    `ref_cv`; `k` its fitted parameters; `scale` the RMS measured force. Keys `delta_bic`
    (n_eff ln(SSR_before / SSR_after) - k ln(n_eff), each SSR at least n (`RESOLUTION` scale)^2),
    `holdout_gain` (1 - CV_after / CV_before; 0 where CV_before is at most `RESOLUTION` scale:
    `nothing_to_gain`), `holdout_improvement` ((CV_before - CV_after) / scale, the absolute
    improvement against the force scale, defined either way), `nothing_to_gain`, `n_eff`,
    `nrmse_before`, `nrmse_after`, `confidence`."""
    n_total = np.size(full)
    sse_c = float(np.sum(np.asarray(full) ** 2))
    n_eff = effective_samples(full)
    floor = n_total * (RESOLUTION * scale) ** 2
    delta_bic = n_eff * math.log(max(ref_sse, floor) / max(sse_c, floor)) - k * math.log(n_eff)
    nothing_to_gain = not ref_cv > RESOLUTION * scale
    return {
        "delta_bic": float(delta_bic),
        "holdout_gain": 0.0 if nothing_to_gain else float(1.0 - cv / ref_cv),
        "holdout_improvement": float((ref_cv - cv) / scale),
        "nothing_to_gain": nothing_to_gain,
        "n_eff": float(n_eff),
        "nrmse_before": nrmse(ref_sse, n_total, scale),
        "nrmse_after": nrmse(sse_c, n_total, scale),
        "confidence": confidence_wording(delta_bic),
    }


def _round_evidence(setup: _FitSetup, err, fitted, sims, pool):
    """Evidence for each candidate of a round (module docstring) and the nrmse before it."""
    n_total, scale, data = setup.force.size, setup.scale, setup.data
    ref_cv = _held_out_rms(setup, err, 0)
    ref_sse = float(np.sum(err[0] ** 2))
    nrmse_before = nrmse(ref_sse, n_total, scale)
    regress = regressors(data, sims_row(sims, 0), setup.half_cycles)
    evid = {}
    for j, name in enumerate(pool, start=1):
        k = max(sum(p.name not in setup.known for p in EFFECTS[name].parameters), 1)
        evid[name] = {
            **candidate_evidence(ref_sse, ref_cv, err[3 * j], _held_out_rms(setup, err, 3 * j),
                                 k, scale),
            "residual_correlation": residual_correlation(
                sims["force"][0], regress, name, data, sims_row(sims, 0)
            ),
            "parameters": {
                p.name: float(fitted[3 * j][PARAMETER_NAMES.index(p.name)])
                for p in EFFECTS[name].parameters
            },
        }
    return evid, nrmse_before


def sims_row(sims: dict, i: int) -> dict:
    """Row `i` of a batch of simulation outputs."""
    return {k: v[i] for k, v in sims.items()}
