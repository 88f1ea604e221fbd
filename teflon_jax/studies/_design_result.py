"""The result of a gradient-based design (`optimise_design`): the optimum and the checks that
say whether to trust it."""

import dataclasses
import math


@dataclasses.dataclass
class DesignResult:
    """Optimum of `optimise_design` (SI units) and the checks that say whether to trust it.

    - `optimum`: name -> value; `objective` J there (with the limit `smooth_disp_limit`);
      `mean_shear`, `mean_disp`: E[V_s], E[D_s]; `peak_shear`, `peak_disp`: means of the
      true peaks; `p95_disp`, `p95_peak_disp`: the 95th percentiles over the motions of D_s
      and of the true peak; `limit_statistic`: "mean" or "p95", the statistic `disp_limit`
      [m] applies to (`limited_disp`: its true value, `limited_smooth_disp`: its smoothed
      one); `smooth_disp_limit` [m]: the limit on the smoothed statistic at the optimum
      (D_limit lowered by the corrections on true peaks); `limit_met`: `limited_disp` <=
      `disp_limit`;
    - `start`: the initial design; `steps`: evaluations of the objective and its gradient by
      BFGS, over all its restarts; `wall_s`: total time [s]; `stages_s`: its parts [s]
      ("compile_and_first_evaluation", "optimiser" (that included), "gradient_check");
    - `optimiser_converged`: BFGS met rtol/atol (`minimise_in_box`) and every variable it left
      on a bound is a minimum there (the objective rises into the box);
    - `simulation_converged`: every step of every motion's Newton solve converged at the
      optimum; `n_failed_motions`: motions with a failed step there;
    - `at_bounds`: design variables within `BOUND_TOLERANCE` of their range at the optimum
      (the optimum is then the bound, not a stationary point: widen the range or accept it);
    - `gradient_rel_error`: the largest relative difference, over E[V_s], E[D_s] and the
      design variables, between the forward-mode derivative and finite differences at the
      optimum (`design_gradient_check`); `gradient`, `finite_differences`: the two, as
      {"shear": {name: ..}, "disp": {name: ..}};
    - `restrainer_contact`: with a capacity designed, `restrainer_contact_check`'s report (is
      the optimum where the largest peak just touches the restrainer; there
      `gradient_rel_error` is the one-sided check's, `central_rel_error` the central one's,
      which straddles the kink); None otherwise;
    - `gradient_check`: which check `gradient_rel_error` is, "central", "piecewise" (a kink
      found inside a failed central stencil, the variable checked one-sided on the optimum's
      own piece) or "one-sided" (at the restrainer contact); `kink_checks`: the reports of the
      variables whose central check failed (`kink_gradient_check`);
    - `converged`: optimiser, simulations, gradient check (<= `GRADIENT_TOLERANCE`) and the
      limit on the true peaks all succeeded; `messages`: why not, and warnings (a bound, a kink of Table 1).
    """

    optimum: dict
    objective: float
    mean_shear: float
    mean_disp: float
    peak_shear: float
    peak_disp: float
    disp_limit: float
    smooth_disp_limit: float
    limit_met: bool
    start: dict
    steps: int
    optimiser_converged: bool
    simulation_converged: bool
    n_failed_motions: int
    at_bounds: tuple
    gradient_rel_error: float
    gradient: dict
    finite_differences: dict
    converged: bool
    messages: tuple
    wall_s: float
    limit_statistic: str = "mean"
    p95_disp: float = math.nan
    p95_peak_disp: float = math.nan
    restrainer_contact: dict | None = None
    central_rel_error: float = math.nan
    gradient_check: str = "central"
    kink_checks: tuple = ()
    stages_s: dict = dataclasses.field(default_factory=dict)

    @property
    def limited_disp(self) -> float:
        """The true value [m] of the statistic the limit applies to (mean or 95th percentile)."""
        return self.peak_disp if self.limit_statistic == "mean" else self.p95_peak_disp

    @property
    def limited_smooth_disp(self) -> float:
        """Its smoothed value [m], the one BFGS sees."""
        return self.mean_disp if self.limit_statistic == "mean" else self.p95_disp
