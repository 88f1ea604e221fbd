"""Model discovery on a triple or double friction pendulum's test record.

The baseline is the series fit of the pendulum (`identification.bearing_fit`: the sliders of
Fenz & Constantinou 2006, 2008 in series, Eq. 1 friction at each surface's velocity, the
constants the record can tell fitted from the start file's values). The candidates are the
effects of the flat slider's discovery (`EFFECTS`) that the series model can represent on each
of its surfaces (`SERIES_EFFECTS`; `bearing_fit._series_effects`): frictional heating (each
surface heated by its own flux mu_e p_e v_e, its friction times k_T(T0 + heat_scale dT_e) /
k_T(T0), one heat_scale fitted), and velocity dependence (Eq. 1's delta_f and rate_a) on the
sliding surfaces that the start file gives Coulomb friction, which the series fit holds. The
others are reported as skipped, with why.

Each round refits the current model and the current model with each candidate added, on the
whole record and on two folds of alternate cycles (one vmapped, compiled call of the
Levenberg-Marquardt solver), and the evidence and the decision are the flat slider's
(`candidate_evidence`, `chosen_effect`): the candidate with the largest BIC drop (n_eff
effective samples) among those that predict the held-out cycles better is added when its BIC
drop exceeds the threshold (10, "very strong"), else the model is complete.
"""

import dataclasses
import time as _time

import numpy as np

from ..bearing_fit import (
    candidate_start,
    fit_series_members,
    member_parameters,
    member_pendulum,
    member_std_errors,
    optimiser_start,
    prepare_series_problem,
)
from ._batch_fit import _finite_or_null, _fold_weights
from ._diagnostics import effective_samples, half_cycle_index
from ._discovery import check_settings, chosen_effect
from ._effects import EFFECT_NAMES
from ._progress import SERIES_COST, Progress, candidate_lines
from ._result import DEFAULT_BIC_THRESHOLD, DiscoveryStep
from ._rounds import candidate_evidence, fit_nrmse, held_out_rms

SERIES_BASELINE = "series"
"""The baseline's name in the results: the series fit of the pendulum."""

SERIES_EFFECTS = {
    "velocity_dependence": "mu_e = f_max,e - delta_f,e exp(-rate_a,e |v_e|) (Eq. 1) on each "
                           "sliding surface e whose start friction is Coulomb's",
    "heating": "mu_e *= k_T(T0 + heat_scale dT_e) / k_T(T0) on each surface e, k_T(T) = 0.79 "
               "(0.70^(T/50) + 0.40); dT_e = sqrt(kappa/pi)/k int q_e(s) (t-s)^(-1/2) ds with "
               "q_e = mu_e p_e |v_e| (the heat flux into surface e at its own sliding speed)",
}
"""The candidates the series model represents on its surfaces, with the law each adds."""

_NOT_IN_SERIES = {
    "anisotropy": "the record runs along one axis",
    "interfaces": "the series model's surfaces are single interfaces (a stack is a flat bearing's part)",
    "backlash": "the series model has no backlash gap (a flat bearing's part)",
}
"""Why an effect of `EFFECTS` outside `SERIES_EFFECTS` is not a candidate here."""

_SURFACE_PARTS = ("breakaway", "pressure_dependence", "wear", "asymmetry")
"""The effects a surface of the start file may carry as a part (`SurfaceParts`, under the same
key in the isolator file), which the series search does not add."""


RATE_IN_BASELINE = ("no sliding surface has Coulomb friction in the start file: Eq. 1 of each is "
                    "in the baseline (the series fit frees delta_f and rate_a where the speeds "
                    "show them)")
"""Why velocity dependence is not a candidate when every sliding surface has Eq. 1."""


def _skip_reason(name: str) -> str:
    if name in _SURFACE_PARTS:
        return (f"not among the series search's candidates; a surface of the start file may carry it "
                f"(its \"{name}\" entry), at constants the fit holds")
    return _NOT_IN_SERIES.get(name, f"the series model of the pendulum has no {name} part")


@dataclasses.dataclass
class SeriesDiscoveryResult:
    """Outcome of `discover_series_effects`, in the shape of `DiscoveryResult`: `isolator`,
    `baseline` ("series"), `effects_added`, `steps` (`DiscoveryStep`s), `final_round`,
    `nrmse_initial`, `nrmse_final` (RMS(model - measured) / RMS(measured) force),
    `parameters` and `std_errors` of the final model (SI; the pendulum's constants and
    heat_scale), `baseline_parameters`, `forces` ("baseline", "final" [N] at the samples
    used), `problem` (the prepared record, `SeriesProblem`), `runtime_s`, `applicable`,
    `skipped` {name: why}, `fit_convergence`, `held` {constant: why}, `swapped` (bottom and
    top reported in the start file's order of f_max)."""

    isolator: str
    baseline: str
    effects_added: list
    steps: list
    final_round: dict
    nrmse_initial: float
    nrmse_final: float
    parameters: dict
    std_errors: dict
    baseline_parameters: dict
    forces: dict
    problem: object
    runtime_s: float
    applicable: list
    skipped: dict
    fit_convergence: dict
    held: dict
    swapped: bool
    final_values: dict = dataclasses.field(default_factory=dict)

    @property
    def effects(self) -> list:
        return list(self.effects_added)

    def pendulum(self):
        """The final model as a `TriplePendulum` or `DoublePendulum` (heated surfaces where
        heating was added), for `formats.write_isolator`."""
        return member_pendulum(self.problem, self.final_values, self.effects_added)[0]

    def to_json(self) -> dict:
        """The JSON document of `diagnose --isolator triple-fp|double-fp` (the keys of
        `DiscoveryResult.to_json`, and `isolator`, `held`, `bottom_top_swapped`)."""
        problem = self.problem
        return _finite_or_null({
            "isolator": self.isolator,
            "baseline": self.baseline,
            "steps": [{"effect": s.effect, "evidence": s.evidence, "nrmse_before": s.nrmse_before,
                       "nrmse_after": s.nrmse_after, "parameters": s.parameters,
                       "candidates": s.candidates} for s in self.steps],
            "effects_added": list(self.effects_added),
            "effects": self.effects,
            "nrmse_initial": self.nrmse_initial,
            "nrmse_final": self.nrmse_final,
            "parameters": self.parameters,
            "std_errors": self.std_errors,
            "baseline_parameters": self.baseline_parameters,
            "conclusion": ("no missing effect" if not self.effects_added
                           else "added: " + ", ".join(self.effects_added)),
            "refused_candidates": self.final_round,
            "skipped_candidates": self.skipped,
            "runtime_s": self.runtime_s,
            "fit_convergence": dict(self.fit_convergence),
            "stack_check": {},
            "held": dict(self.held),
            "bottom_top_swapped": self.swapped,
            "record": {
                "source": problem.source,
                "samples_used": int(problem.time.size),
                "decimation": problem.decimation,
                "contact_pressure_Pa": dict(problem.pressures),
                "contact_pressure_assumed": list(problem.pressure_assumed),
            },
        })


def heat_regressor(problem) -> np.ndarray:
    """Temperature-rise index [K-like] of a flux proportional to the bearing's speed |v|: the
    heat kernel of the model (`problem.kernel`) applied to |v|; heating's signature."""
    rates, weights = (np.asarray(a) for a in problem.kernel)
    dt = float(problem.time[1] - problem.time[0])
    speed = np.abs(np.gradient(np.asarray(problem.path), dt))
    decay = np.exp(-rates * dt)
    state, index = np.zeros_like(rates), np.zeros(speed.size)
    for i, v in enumerate(speed):
        index[i] = float(weights @ state)
        state = decay * state + v * (1.0 - decay) / rates
    return index


def _residual_correlation(problem, model_force, regressor) -> float:
    """Pearson correlation of the friction residual (measured - model) / N sign(v) with the
    regressor, on the samples where the bearing moves (positive: friction under-predicted
    where the regressor is large)."""
    velocity = np.gradient(np.asarray(problem.path))
    moving = np.abs(velocity) > 1e-3 * np.max(np.abs(velocity))
    load = np.broadcast_to(problem.load, np.shape(problem.force))[moving]
    d_mu = (problem.force - model_force)[moving] / load * np.sign(velocity[moving])
    g = regressor[moving]
    if d_mu.size < 3 or np.std(g) == 0 or np.std(d_mu) == 0:
        return 0.0
    return float(np.corrcoef(d_mu, g)[0, 1])


class _Round:
    """The fits of one discovery: the record's folds and the batch size (one compile)."""

    def __init__(self, problem, n_candidates, max_steps):
        n = problem.time.size
        fold_a, fold_b = _fold_weights(n, half_cycle_index(np.asarray(problem.path)))
        self.problem, self.max_steps = problem, max_steps
        self.weights = (np.ones(n), fold_a, fold_b)
        self.n_members = 3 * (1 + n_candidates)
        self.log = {"fits": 0, "unconverged": 0, "max_iterations_used": 0,
                    "iteration_limit": int(max_steps)}

    def fit(self, configs, values, current):
        """Members of each configuration (effect lists) on the record and both folds, from the
        current model's `values` (optimiser keys) with each added candidate at its start
        (`candidate_start`); padded to `n_members`. Returns [(full, fold a, fold b)]."""
        starts, effects, weights = [], [], []
        for config in configs:
            start = candidate_start(self.problem, values, [e for e in config if e not in current])
            for w in self.weights:
                starts.append(start)
                effects.append(tuple(config))
                weights.append(w)
        b = len(starts)
        pad = self.n_members - b
        members = fit_series_members(self.problem, starts + starts[:1] * pad,
                                     effects + effects[:1] * pad, weights + weights[:1] * pad,
                                     max_steps=self.max_steps)[:b]
        self.log.update(fits=self.log["fits"] + b,
                        unconverged=self.log["unconverged"] + sum(not m.converged for m in members),
                        max_iterations_used=max(self.log["max_iterations_used"],
                                                *(m.n_steps for m in members)))
        return [tuple(members[3 * i: 3 * i + 3]) for i in range(len(configs))]


def _evidence(problem, fits, pool, regressor, folds):
    """Evidence per candidate of `pool` (fits[0] the current model's, fits[j] candidate j's;
    `folds` the 0/1 weights of the two folds)."""
    err = [[m.force - problem.force for m in trio] for trio in fits]
    held_a, held_b = folds
    ref_sse = float(np.sum(err[0][0] ** 2))
    ref_cv = held_out_rms(err[0][1], err[0][2], held_a, held_b)
    evid = {}
    for j, name in enumerate(pool, start=1):
        cv = held_out_rms(err[j][1], err[j][2], held_a, held_b)
        keys = problem.effect_keys(name)
        evid[name] = {
            **candidate_evidence(ref_sse, ref_cv, err[j][0], cv, len(keys), problem.scale),
            "residual_correlation": _residual_correlation(problem, fits[0][0].force,
                                                          regressor[name]),
            "parameters": {k: fits[j][0].values[k] for k in keys},
        }
    return evid


def _requested(candidates) -> tuple[list, dict]:
    """(requested series candidates, skipped {name: why}); `ValueError` for an unknown name or
    for a request of none that the series model takes."""
    names = list(SERIES_EFFECTS) if candidates is None else list(dict.fromkeys(candidates))
    unknown = [c for c in names if c not in EFFECT_NAMES]
    if unknown:
        raise ValueError(f"candidates: unknown {unknown}; choose from {list(EFFECT_NAMES)} (the "
                         f"series pendulums take {', '.join(SERIES_EFFECTS)}).")
    skipped = {name: _skip_reason(name) for name in EFFECT_NAMES if name not in SERIES_EFFECTS}
    if not any(name in SERIES_EFFECTS for name in names):
        raise ValueError("candidates: the series pendulums take " + ", ".join(SERIES_EFFECTS)
                         + "; not " + "; ".join(f"{n} ({skipped[n]})" for n in names) + ".")
    for name in SERIES_EFFECTS:
        if name not in names:
            skipped[name] = "not among the requested candidates"
    return [c for c in SERIES_EFFECTS if c in names], skipped


def _calls_left(pool, added: int, max_effects: int) -> int:
    """The batched calls a series search may still make after the one that fitted the
    candidates `pool`, `added` effects added so far: one after each effect added while
    candidates are left and `max_effects` is not reached."""
    return max(0, min(len(pool) - 1, max_effects - added - 1))


def _series_progress(say, start, problem, rounds, pool, skipped, max_effects) -> Progress:
    """The `Progress` of a series search, its plan said: the series fit with every candidate,
    then one call over the candidates left after each effect added."""
    n = problem.time.size
    progress = Progress(say, SERIES_COST, ("series", start.isolator, rounds.n_members, n, rounds.max_steps),
                        rounds.n_members, n, label=SERIES_BASELINE)
    calls = 1 + _calls_left(pool, 0, max_effects)
    work = f"the {start.description[:-1]}'s series fit"
    if pool:
        work += (f" alone and with each candidate added ({', '.join(pool)}), on the record and on two "
                 "folds of its cycles" + (", then again over the candidates left after each effect "
                                          "added" if calls > 1 else ""))
    progress.plan(work, calls, [name for name in skipped if name in SERIES_EFFECTS])
    return progress


def discover_series_effects(record, start, *, candidates=None,
                            bic_threshold: float = DEFAULT_BIC_THRESHOLD, max_effects: int = 4,
                            max_samples: int = 3000, max_steps: int = 200, normal_load=None,
                            reference_load=None, callback=None) -> SeriesDiscoveryResult:
    """Find the effects a triple or double friction pendulum's test record shows beyond its
    series fit, one at a time (module docstring).

    **Arguments:** `record`: a `TestRecord` time history along one axis at a uniform step,
    under a constant normal load (its N, else `normal_load` [N]), or under one that varies
    given `reference_load` [N], the load the contact pressures are given under
    (`prepare_series_problem`), from the centre; `start`:
    the `TriplePendulum` or `DoublePendulum` the fit starts from (e.g. `load_isolator`; a
    surface's `heating` entry gives the heating candidate its contact pressure and steel);
    `candidates`: names to consider (default: `SERIES_EFFECTS`); `bic_threshold`,
    `max_effects`, `max_samples`, `max_steps`, `callback`: as `discover_effects`.

    **Returns:** a `SeriesDiscoveryResult`. `ValueError` naming a bad record, start or setting.
    """
    check_settings(bic_threshold, max_effects, max_steps)
    started = _time.perf_counter()
    say = callback or (lambda text: None)
    pool, skipped = _requested(candidates)
    problem = prepare_series_problem(record, start, normal_load=normal_load, reference_load=reference_load,
                                     max_samples=max_samples)
    if "velocity_dependence" in pool and not problem.rate_surfaces:
        pool.remove("velocity_dependence")
        skipped["velocity_dependence"] = RATE_IN_BASELINE
    applicable = list(pool)
    rounds = _Round(problem, len(pool), max_steps)
    regressor = {"heating": heat_regressor(problem),
                 "velocity_dependence": np.abs(np.gradient(np.asarray(problem.path), problem.time))}
    current, steps, final_round = [], [], {}
    progress = _series_progress(say, start, problem, rounds, pool, skipped, max_effects)
    progress.calling(f"baseline {SERIES_BASELINE}: the {start.description[:-1]} alone"
                     + (f" and with each of {', '.join(pool)} added (round 1)" if pool else ""))
    fits = rounds.fit([current] + [[c] for c in pool], optimiser_start(problem)[0], current)
    took = progress.called()
    baseline = fits[0][0]
    nrmse_initial = fit_nrmse(baseline.force, problem.force, problem.scale)
    say(f"baseline {SERIES_BASELINE} ({start.description[:-1]}): nrmse {nrmse_initial:.4f}")
    progress.took(f"baseline {SERIES_BASELINE} and round 1", took, _calls_left(pool, 0, max_effects))
    fit = baseline
    while pool and len(steps) < max_effects:
        number = len(steps) + 1
        evid = _evidence(problem, fits, pool, regressor, rounds.weights[1:])
        for line in candidate_lines(evid, pool):
            say(line)
        say(f"round {number}: delta_bic "
            + ", ".join(f"{c} {evid[c]['delta_bic']:.1f}" for c in pool))
        chosen = chosen_effect(evid, pool, bic_threshold)
        if chosen is None:
            final_round = evid
            break
        fit = fits[1 + pool.index(chosen)][0]
        current.append(chosen)
        pool.remove(chosen)
        steps.append(DiscoveryStep(
            effect=chosen, evidence={k: v for k, v in evid[chosen].items() if k != "parameters"},
            nrmse_before=evid[chosen]["nrmse_before"], nrmse_after=evid[chosen]["nrmse_after"],
            candidates=evid, parameters=member_parameters(problem, fit.values, current)))
        say(f"added {chosen}: nrmse {evid[chosen]['nrmse_before']:.4f} -> "
            f"{evid[chosen]['nrmse_after']:.4f}")
        if pool and len(steps) < max_effects:
            progress.calling(f"round {number + 1}: trying {', '.join(pool)}, each added to "
                             f"{' + '.join([SERIES_BASELINE, *current])}")
            fits = rounds.fit([current] + [current + [c] for c in pool], fit.values, current)
            progress.took(f"round {number + 1}", progress.called(),
                          _calls_left(pool, len(steps), max_effects))
    progress.done()
    residual = (fit.force - problem.force) / problem.scale
    rounds.log["final_converged"] = fit.converged
    return SeriesDiscoveryResult(
        isolator=start.isolator, baseline=SERIES_BASELINE, effects_added=list(current),
        steps=steps, final_round=final_round, nrmse_initial=nrmse_initial,
        nrmse_final=fit_nrmse(fit.force, problem.force, problem.scale),  # the baseline's where nothing was added
        parameters=member_parameters(problem, fit.values, current),
        std_errors=member_std_errors(problem, fit, current, effective_samples(residual)),
        baseline_parameters=member_parameters(problem, baseline.values, ()),
        forces={"baseline": baseline.force, "final": fit.force}, problem=problem,
        runtime_s=float(_time.perf_counter() - started),
        applicable=applicable,
        skipped=skipped, fit_convergence=dict(rounds.log),
        held={k: v for k, v in problem.held.items()
              if not any(k in problem.effect_keys(e) for e in current)},
        swapped=member_pendulum(problem, fit.values, current)[1], final_values=dict(fit.values))
