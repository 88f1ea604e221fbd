"""Results of model discovery: each step of the forward selection and the final verdict."""

import dataclasses
import math

from ._augmented import AugmentedData, RecordInfo
from ._batch_fit import _finite_or_null

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


def gain_text(evidence: dict, digits: str = ".3g") -> str:
    """The held-out gain of `candidate_evidence` as said and reported: a percentage (to
    `digits`), or that there was nothing to gain (with the absolute change against the force
    scale)."""
    if evidence.get("nothing_to_gain"):
        return (f"nothing to gain (held-out error at rounding level; change "
                f"{evidence['holdout_improvement']:+.1e} of the force scale)")
    return f"{100 * evidence['holdout_gain']:{digits}} %"


@dataclasses.dataclass
class DiscoveryStep:
    """One accepted effect: its name, the evidence, and the error before and after.

    `evidence` holds `delta_bic`, `holdout_gain`, `holdout_improvement`, `nothing_to_gain`
    (`_rounds.candidate_evidence`), `n_eff`, `nrmse_before`, `nrmse_after`,
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
class CompositionFit:
    """One composition of effects the search fitted to the whole record.

    `effects` (names, the baseline's first), `values` (P,) every parameter of the augmented
    model in the order of `PARAMETER_NAMES` [SI] (those of effects that are off at their
    start), `free` (P,) 1 where the parameter was fitted (active and not known), `jacobian`
    (n_r, P) of the residual in the physical parameters, `residual` (n_r,) the force residual
    (F_model - F_measured) / RMS(F_measured), `converged` whether its fit met the test."""

    effects: tuple
    values: object
    free: object
    jacobian: object
    residual: object
    converged: bool


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
      baseline and final fits, `runtime_s`, `applicable` candidates and `skipped` ones with why,
    - `fit_convergence`: how many inner fits ran, how many did not meet the convergence test
      within the iteration limit, the most iterations one took,
    - `stack_check`: while `interfaces` is not separable (rate_a fitted), the interval of
      interfaces in series that the fitted rate_a implies (`stack_check` of `_discovery`);
    - `compositions`: every composition fitted to the whole record (`CompositionFit`s: the
      baseline and each round's candidates; the final model among them), which
      `discovery_mixture` weighs.
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
    fit_convergence: dict = dataclasses.field(default_factory=dict)
    baseline_effects: list = dataclasses.field(default_factory=list)
    stack_check: dict = dataclasses.field(default_factory=dict)
    compositions: list = dataclasses.field(default_factory=list)

    @property
    def effects(self) -> list:
        """Every effect of the final model: the baseline's and those added."""
        return list(self.baseline_effects) + list(self.effects_added)

    def bearing(self, parameters=None, effects=None):
        """The final model as a `teflon_jax.bearing.SlidingBearing` (its parts only), or the
        model of `effects` with `parameters` (name -> value [SI], arrays of draws too). A
        pressure dependence carries the record's contact area when the record states one (a
        structure needs it to take the dependence at its own contact pressure)."""
        import equinox as eqx

        from ._augmented import discovered_bearing

        parameters = self.parameters if parameters is None else parameters
        effects = self.effects if effects is None else effects
        bearing = discovered_bearing(parameters, self.data, effects)
        if bearing.pressure_dependence is None or self.info.contact_area_assumed:
            return bearing
        return eqx.tree_at(lambda b: b.pressure_dependence.contact_area, bearing,
                           self.data.contact_area, is_leaf=lambda x: x is None)

    def bearing_errors(self) -> dict:
        """Standard errors keyed by `(part, constant)` of the bearing file."""
        from ..bearing_fit import part_errors

        return part_errors(self.std_errors)

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
                "effects": self.effects,
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
                "fit_convergence": dict(self.fit_convergence),
                "stack_check": dict(self.stack_check),
                "record": {
                    "source": self.info.source,
                    "samples_used": int(self.data.n_samples),
                    "decimation": self.info.decimation,
                    "interfaces_recorded": self.info.n_interfaces_recorded,
                    "contact_area_assumed": self.info.contact_area_assumed,
                },
            }
        )
