"""Result of the Bayesian fit: posterior summary, convergence diagnostics, NetCDF draws, pair plot."""

import dataclasses
import math
import warnings as _warnings

import numpy as np

from teflon_jax.bearing import PARAMETER_BOUNDS
from teflon_jax.formats import BearingPosterior, IsolatorPosterior, thinned_posterior

from ..bearing_fit import PARAMETER_NAMES
from ._model import base_name, to_base, to_physical

UNITS = {**{name: PARAMETER_BOUNDS[name].unit for name in PARAMETER_NAMES[:5]},
         "noise_level": "N"}
"""Unit of each reported quantity: the bearing constants' from `PARAMETER_BOUNDS`."""

NOT_IDENTIFIED_RATIO = 0.5
"""Posterior sd / prior sd (on the prior's log or logit scale) above which a constant is
reported as not identified by the data: its posterior stays at the prior."""

WEAK_RATIO = 0.2
"""Above this ratio (and below `NOT_IDENTIFIED_RATIO`) the constant is weakly identified."""


def _arviz():
    with _warnings.catch_warnings():
        _warnings.simplefilter("ignore", FutureWarning)
        import arviz as az
    return az


@dataclasses.dataclass
class BayesResult:
    """Posterior of a Bayesian bearing fit (SI).

    - `draws`: name -> (chains, draws) array of each free constant and of `noise_level_<i>`
      [N] (one per record).
    - `table`: name -> dict(mean, median, q05, q95, sd, rhat, ess_bulk, ess_tail,
      identified, sd_ratio) (`sd_ratio`: posterior / prior spread on the prior's scale).
    - `divergences`: number of divergent transitions after warm-up.
    - `converged`: all R-hat < `rhat_max`, all ESS >= `ess_min`, no divergence.
    - `messages`: why the run is not converged, which constants stay at the prior, notes.
    - `least_squares`: the `BearingFit` used as warm start.
    - `prior`: "bounds" or "table1"; `priors`: the `ParameterPrior` of each constant.
    - `elapsed_s`, `elapsed_least_squares_s`: wall times of sampling and of the LS fit [s].
    - `interrupted`: why sampling stopped before all the draws asked for (e.g. "interrupted
      after 100 of 1000 draws per chain"), else None; an interrupted run is not converged.
    - `seed`: the sampler's random seed.
    - `units`: the unit of each constant's name where they are not the flat bearing's
      (`UNITS`): a series pendulum's `<surface>_<constant>`.
    """

    draws: dict
    table: dict
    divergences: int
    converged: bool
    messages: list
    least_squares: object
    prior: str
    priors: dict
    free: tuple
    num_chains: int
    num_samples: int
    elapsed_s: float
    elapsed_least_squares_s: float
    rhat_max: float
    ess_min: float
    interrupted: str | None = None
    seed: int = 0
    units: dict | None = None

    @property
    def unit_names(self) -> dict:
        """The unit of each reported name: `units`, or the flat bearing's `UNITS`."""
        return UNITS if self.units is None else {**self.units, "noise_level": "N"}

    def bearing_posterior(self, max_draws: int = 1000) -> BearingPosterior:
        """The draws of the free constants as a `teflon_jax.formats.BearingPosterior` for the
        bearing file: the chains one after the other, thinned to at most `max_draws`, with
        each constant's bulk ESS of the whole run. `ValueError` (naming the constant) where
        an ESS is below `MIN_POSTERIOR_ESS`."""
        return thinned_posterior({n: self.draws[n] for n in self.free},
                                 {n: self.table[n]["ess_bulk"] for n in self.free},
                                 max_draws=max_draws, chains=self.num_chains, seed=self.seed)

    def isolator_posterior(self, max_draws: int = 1000) -> IsolatorPosterior:
        """The draws of a series pendulum's surface friction (`fit_series_bayes`) as a
        `teflon_jax.formats.IsolatorPosterior` for the isolator file, thinned as
        `bearing_posterior`'s."""
        return thinned_posterior({n: self.draws[n] for n in self.free},
                                 {n: self.table[n]["ess_bulk"] for n in self.free},
                                 max_draws=max_draws, chains=self.num_chains, seed=self.seed,
                                 kind=IsolatorPosterior)

    def summary(self, unit_of=None) -> str:
        """Text table: mean, median, 5-95 % interval, R-hat, ESS, identification; SI, or in
        the units `unit_of(name)` -> (unit, SI value of one unit) gives for a parameter name
        (noise levels as "noise_level")."""
        head = (f"{'parameter':<16}{'unit':>5}{'mean':>12}{'median':>12}{'5 %':>12}{'95 %':>12}"
                f"{'LS est.':>12}{'LS s.e.':>11}{'R-hat':>7}{'ESS':>7}  identified")
        lines = [head]
        ls = self.least_squares
        for name, row in self.table.items():
            base = name.rsplit("_", 1)[0] if name.startswith("noise") else name
            unit, factor = (self.unit_names.get(base, "-"), 1.0) if unit_of is None else unit_of(base)
            unit = unit or "-"
            est = ls.parameters.get(name) if name in self.free else None
            se = ls.std_errors.get(name) if name in self.free else None
            lines.append(
                f"{name:<16}{unit:>5}{row['mean'] / factor:>12.5g}{row['median'] / factor:>12.5g}"
                f"{row['q05'] / factor:>12.5g}{row['q95'] / factor:>12.5g}"
                f"{'' if est is None else format(est / factor, '.5g'):>12}"
                f"{'' if se is None else format(se / factor, '.3g'):>11}"
                f"{row['rhat']:>7.3f}{row['ess_bulk']:>7.0f}  {row['identified']}")
        status = "converged" if self.converged else "NOT converged"
        lines.append(f"{self.num_chains} chains x {self.num_samples} draws, {self.divergences} "
                     f"divergences, {status} (R-hat < {self.rhat_max}, ESS >= {self.ess_min:.0f})")
        lines.extend(self.messages)
        return "\n".join(lines)

    def to_json_dict(self) -> dict:
        def clean(x):
            return x if not isinstance(x, float) or math.isfinite(x) else None

        return {
            "posterior": {k: {kk: clean(vv) for kk, vv in v.items()} for k, v in self.table.items()},
            "units": dict(self.unit_names), "prior": self.prior,
            "prior_ranges": {k: [p.low, p.high] for k, p in self.priors.items()},
            "divergences": int(self.divergences), "converged": bool(self.converged),
            "status": self.interrupted or ("converged" if self.converged else "not converged"),
            "messages": list(self.messages), "num_chains": self.num_chains,
            "num_samples": self.num_samples, "elapsed_s": self.elapsed_s,
            "least_squares": self.least_squares.to_json_dict(),
        }

    def inference_data(self):
        """The draws as ArviZ `InferenceData` (groups `posterior`, `sample_stats`)."""
        az = _arviz()
        return az.from_dict(
            posterior={k: np.asarray(v) for k, v in self.draws.items()},
            sample_stats={"diverging": self._diverging},
            attrs={"prior": self.prior, "units": str(self.unit_names),
                   "model": "Constantinou, Mokha & Reinhorn (1990), Eq. 1, 3, 17"},
        )

    def to_netcdf(self, path) -> None:
        """Write the draws to NetCDF (ArviZ conventions: dims chain, draw)."""
        self.inference_data().to_netcdf(str(path))

    def plot_pairs(self, path, unit_of=None) -> None:
        """Pair plot of the free constants (divergent draws marked) to an image file, each
        axis labelled with its unit: SI, or `unit_of(name)` -> (unit, SI value of one unit)
        as in `summary`; tick labels without offsets."""
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt
        from matplotlib.ticker import ScalarFormatter

        az = _arviz()
        shown = {}
        for name in self.free:
            unit, factor = (self.unit_names.get(name, "-"), 1.0) if unit_of is None else unit_of(name)
            shown[f"{name} [{unit or '-'}]"] = np.asarray(self.draws[name]) / factor
        data = az.from_dict(posterior=shown, sample_stats={"diverging": self._diverging})
        with _warnings.catch_warnings():  # ArviZ 0.23 calls a deprecated matplotlib helper
            _warnings.simplefilter("ignore", DeprecationWarning)
            axes = az.plot_pair(data, var_names=list(shown), kind="scatter", divergences=True,
                                marginals=True, textsize=9)
        for ax in np.asarray(axes).ravel():
            if ax is None:
                continue
            for axis in (ax.xaxis, ax.yaxis):
                formatter = axis.get_major_formatter()
                if isinstance(formatter, ScalarFormatter):
                    formatter.set_useOffset(False)
            ax.tick_params(axis="x", labelrotation=45)
        fig = np.asarray(axes).ravel()[0].get_figure()
        fig.suptitle("Posterior draws (Bayesian bearing fit)")
        fig.savefig(str(path), dpi=110)
        plt.close(fig)

    def compare_least_squares(self) -> dict:
        """Posterior sd / least-squares standard error of each free constant."""
        ls = self.least_squares.std_errors
        return {n: self.table[n]["sd"] / ls[n] if ls.get(n, 0) and math.isfinite(ls[n])
                else float("nan") for n in self.free}


def _prior_sd(p) -> float:
    """Standard deviation of a prior on its base scale (`ParameterPrior.kind`), closed form:
    (b - a) / sqrt(12) for a uniform on (a, b); for N(m, s) truncated to (a, b), with
    alpha = (a - m) / s, beta = (b - m) / s and Z = Phi(beta) - Phi(alpha),
    s^2 [1 + (alpha phi(alpha) - beta phi(beta)) / Z - ((phi(alpha) - phi(beta)) / Z)^2]
    (Johnson, Kotz & Balakrishnan, "Continuous Univariate Distributions" 1, 1994, 13.10)."""
    lo, hi, loc, sd = (float(x) for x in p.base_values())
    if p.kind in ("uniform_physical", "uniform"):
        return (hi - lo) / math.sqrt(12.0)
    if p.kind == "normal":
        return sd
    alpha, beta = (lo - loc) / sd, (hi - loc) / sd

    def phi(x):
        return 0.0 if math.isinf(x) else math.exp(-0.5 * x * x) / math.sqrt(2.0 * math.pi)

    def x_phi(x):
        return 0.0 if math.isinf(x) else x * phi(x)

    mass = 0.5 * (math.erf(beta / math.sqrt(2.0)) - math.erf(alpha / math.sqrt(2.0)))
    var = (1.0 + (x_phi(alpha) - x_phi(beta)) / mass
           - ((phi(alpha) - phi(beta)) / mass) ** 2)
    return sd * math.sqrt(var)


def diagnose_run(base, diverging, priors, fit, data, *, rhat_max, ess_min, elapsed,
                 elapsed_least_squares, prior, interrupted=None, seed=0, order=PARAMETER_NAMES,
                 ratios=(("delta_f", "f_max"),), units=None) -> BayesResult:
    """Summaries and convergence checks of a numpyro run: `base`, site -> (chains, draws, ...)
    draws of the sampled sites; `diverging`, (chains, draws) flags; `interrupted`, why the run
    stopped early (then it is not converged), or None. `order`: the constants' names in the
    order reported; `ratios`: (name, of) pairs of the constants sampled as a ratio to another
    (delta_f as delta_f / f_max), `of` read from the draws or, held, from `fit`; `units`: the
    unit of each name (`None`: `UNITS`)."""
    az = _arviz()
    base = {k: np.asarray(v) for k, v in base.items()}
    samples = {name: np.asarray(to_physical(p, base[base_name(p)])) for name, p in priors.items()}
    sampled_ratio = {}
    for name, of in ratios:
        if name in samples:
            sampled_ratio[name] = samples[name]
            samples[name] = samples[name] * samples.get(of, fit.parameters[of])
    for i, rec in enumerate(data):
        samples[f"noise_level_{i}"] = base["noise_rel"][..., i] * rec["scale"]
    diverging = np.asarray(diverging)
    free = tuple(n for n in order if n in priors)
    draws = {n: samples[n] for n in free}
    for i in range(len(data)):
        draws[f"noise_level_{i}"] = samples[f"noise_level_{i}"]
    idata = az.from_dict(posterior=draws)
    rhat = az.rhat(idata)
    ess_bulk = az.ess(idata, method="bulk")
    ess_tail = az.ess(idata, method="tail")
    table, messages = {}, []
    for name, x in draws.items():
        flat = x.reshape(-1)
        row = dict(mean=float(flat.mean()), median=float(np.median(flat)),
                   q05=float(np.quantile(flat, 0.05)), q95=float(np.quantile(flat, 0.95)),
                   sd=float(flat.std(ddof=1)), rhat=float(rhat[name]),
                   ess_bulk=float(ess_bulk[name]), ess_tail=float(ess_tail[name]),
                   identified="yes", sd_ratio=float("nan"))
        if name in priors:
            p = priors[name]
            site = sampled_ratio.get(name, x)
            ratio = float(np.std(np.asarray(to_base(p, site))) / _prior_sd(p))
            row["sd_ratio"] = ratio
            if ratio > NOT_IDENTIFIED_RATIO:
                row["identified"] = "no (posterior = prior)"
                messages.append(
                    f"{name}: not identified by these records; its posterior spread is "
                    f"{ratio:.0%} of the prior's, so the interval reflects the prior "
                    f"({p.low:.3g} to {p.high:.3g}), not the data.")
            elif ratio > WEAK_RATIO:
                row["identified"] = "weakly"
                messages.append(f"{name}: weakly identified (posterior spread {ratio:.0%} of "
                                "the prior's); the prior shapes its interval.")
        table[name] = row
    n_div = int(diverging.sum())
    bad = [] if interrupted is None else [interrupted]
    if n_div:
        bad.append(f"{n_div} divergent transitions (the sampler could not follow the posterior; "
                   "raise target_accept or reparametrise)")
    worst = max(table, key=lambda k: table[k]["rhat"])
    if not table[worst]["rhat"] < rhat_max:
        bad.append(f"R-hat of {worst} is {table[worst]['rhat']:.4f} >= {rhat_max} (chains disagree)")
    low = [k for k in table if min(table[k]["ess_bulk"], table[k]["ess_tail"]) < ess_min]
    if low:
        bad.append(f"effective sample size below {ess_min:.0f} for {', '.join(low)} (run more "
                   "draws)")
    converged = not bad
    if bad:
        messages.insert(0, "NOT converged: " + "; ".join(bad) + ". Do not use these intervals.")
    if not fit.converged:
        messages.append(f"least-squares warm start did not converge: {fit.message}")
    result = BayesResult(
        draws=draws, table=table, divergences=n_div, converged=converged, messages=messages,
        least_squares=fit, prior=prior, priors=priors, free=free,
        num_chains=int(diverging.shape[0]), num_samples=int(diverging.shape[1]),
        elapsed_s=float(elapsed), elapsed_least_squares_s=float(elapsed_least_squares),
        rhat_max=float(rhat_max), ess_min=float(ess_min), interrupted=interrupted, seed=int(seed),
        units=units)
    result._diverging = diverging
    return result
