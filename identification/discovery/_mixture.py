"""The compositions a discovery fitted, weighed by their evidence, as a bearing mixture.

A search fits many compositions of effects to one record (the baseline and every candidate of
every round, `DiscoveryResult.compositions`). Their Bayesian information criterion, with one
effective number of independent samples n_eff for all (that of the selected model's residual,
AR(1) approximation as in the evidence of each round; Bretherton et al. 1999),

    BIC_c = n_eff ln(max(SSR_c / n, RESOLUTION^2)) + p_c ln(n_eff),

SSR_c the sum of squared force residuals (relative to the record's RMS force) and p_c the
constants fitted, gives each composition
the weight (Schwarz 1978; Kass & Raftery 1995; Burnham & Anderson 2002, Sec. 6.4)

    w_c = exp(-dBIC_c / 2) / sum_j exp(-dBIC_j / 2),   dBIC_c = BIC_c - min_j BIC_j,

the approximate posterior probability of composition c under equal prior odds. A mean square
below `RESOLUTION`^2 (the fits' tolerance, as in the evidence of each round) is rounding and
read as that level, so that compositions which all fit a noise-free record to rounding differ
by p_c ln(n_eff) alone (the fewest constants weigh most), not by their rounding. Compositions
whose weight is below `MIN_MIXTURE_WEIGHT` are left out (named, with their weights) and the
others' weights normalised again.

The constants of each composition kept are drawn from the Gaussian of its least-squares fit
(the Laplace approximation that BIC rests on): mean the estimate, covariance
sigma^2 (J^T J)^-1 inflated by n / n_eff of its own residual (its standard errors), truncated
to the constants' ranges (`teflon_jax.bearing.PARAMETER_BOUNDS`, and delta_f < f_max) by
rejection. A constant the record does not determine (infinite variance) is held at its
estimate, and the composition says so.
"""

import dataclasses
import math

import numpy as np

from teflon_jax.bearing import PARAMETER_BOUNDS, check_bearing
from teflon_jax.formats import (
    POSTERIOR_FIELDS,
    BearingMixture,
    BearingPosterior,
    MixtureComposition,
    posterior_constant,
)

from ..bearing_fit import part_errors
from ..least_squares import covariance_from_jacobian
from ._augmented import PARAMETER_NAMES
from ._diagnostics import effective_samples
from ._discovery import _active_parameters
from ._rounds import RESOLUTION

MIN_MIXTURE_WEIGHT = 1e-3
"""Weight below which a composition is left out of the mixture (fewer than one motion in a
thousand would run it)."""

MIXTURE_DRAWS = 1000
"""Draws of each composition's constants (default)."""

MAX_DRAW_ROUNDS = 20
"""Rounds of 2 K Gaussian draws a composition may take to keep K inside the ranges."""

LAPLACE = "Laplace"
"""The sampler's name in a composition's posterior: independent draws from the Gaussian of
the least-squares fit, truncated to the ranges."""


def composition_bic(residuals, free_parameters, n_eff: float) -> np.ndarray:
    """BIC_c = n_eff ln(max(SSR_c / n, RESOLUTION^2)) + p_c ln(n_eff) of each composition
    (module docstring).

    **Arguments:** `residuals` C residual vectors of one length n, each relative to the
    record's RMS force (`CompositionFit.residual`); `free_parameters` (C,)
    the constants each fitted, p_c; `n_eff` the effective samples (1 < n_eff <= n).

    **Returns:** (C,) BIC values [-]."""
    n_eff = float(n_eff)
    if not (math.isfinite(n_eff) and n_eff > 1):
        raise ValueError(f"n_eff: must be a finite number > 1, got {n_eff}.")
    ssr = np.array([float(np.sum(np.square(r))) for r in residuals])
    n = np.array([np.size(r) for r in residuals])
    return n_eff * np.log(np.maximum(ssr / n, RESOLUTION**2)) + np.asarray(free_parameters) * math.log(n_eff)


def composition_weights(bic) -> np.ndarray:
    """w_c = exp(-dBIC_c / 2) / sum_j exp(-dBIC_j / 2), dBIC_c = BIC_c - min_j BIC_j.

    **Returns:** (C,) weights, summing to 1."""
    bic = np.asarray(bic, dtype=float)
    if bic.ndim != 1 or bic.size == 0 or not np.all(np.isfinite(bic)):
        raise ValueError(f"bic: expected a non-empty 1-D array of finite numbers, got {bic!r}.")
    relative = np.exp(-(bic - bic.min()) / 2.0)
    return relative / relative.sum()


@dataclasses.dataclass
class DiscoveryMixture:
    """Every composition a discovery fitted with its evidence, and the mixture of those kept.

    - `criterion` ("bic"), `effective_samples` n_eff, `min_weight`;
    - `table`: one dict per composition, heaviest first: `effects`, `free_parameters`,
      `nrmse`, `bic`, `delta_bic`, `weight` (over all compositions), `selected` (the model
      the search chose), `converged`, `in_mixture` and `note` (why it was left out, or the
      constants held at their estimates);
    - `mixture`: the `BearingMixture` of the compositions kept, or None (`why_none`)."""

    criterion: str
    effective_samples: float
    min_weight: float
    table: list
    mixture: BearingMixture | None
    why_none: str = ""

    def to_json(self) -> dict:
        """The `mixture` entry of the `diagnose` JSON."""
        kept = {} if self.mixture is None else {c.label: c.weight for c in self.mixture.compositions}
        rows = [{**row, "weight_in_mixture": kept.get("+".join(row["effects"]) or "baseline")}
                for row in self.table]
        return {"criterion": self.criterion, "formula": "w_c = exp(-dBIC_c / 2) / sum_j exp(-dBIC_j / 2)",
                "bic": "n_eff ln(max(SSR_c / n, RESOLUTION^2)) + p_c ln(n_eff)", "resolution": RESOLUTION, "effective_samples": self.effective_samples,
                "min_weight": self.min_weight, "compositions": rows,
                **({"why_none": self.why_none} if self.mixture is None else {})}


def discovery_mixture(result, *, draws: int = MIXTURE_DRAWS, seed: int = 0,
                      min_weight: float = MIN_MIXTURE_WEIGHT) -> DiscoveryMixture:
    """Weigh the compositions of a `DiscoveryResult` by BIC and draw each kept one's constants
    (module docstring).

    **Arguments:** `result` of `discover_effects`; `draws` K >= 100 per composition (the floor
    of `teflon_jax.formats.MIN_POSTERIOR_ESS`); `seed` of the draws; `min_weight` in [0, 1).

    **Returns:** a `DiscoveryMixture`."""
    if isinstance(draws, bool) or not isinstance(draws, int) or draws < 100:
        raise ValueError(f"draws: must be an integer >= 100 (independent draws, each composition's "
                         f"effective sample size), got {draws!r}.")
    if not 0.0 <= min_weight < 1.0:
        raise ValueError(f"min_weight: must be in [0, 1), got {min_weight}.")
    fits = list({frozenset(f.effects): f for f in sorted(
        result.compositions, key=lambda f: -float(np.sum(f.residual**2)))}.values())
    selected = next(f for f in fits if frozenset(f.effects) == frozenset(result.effects))
    n_eff = effective_samples(selected.residual)
    free = [int(np.sum(f.free)) for f in fits]
    bic = composition_bic([f.residual for f in fits], free, n_eff)
    weights = composition_weights(bic)
    order = np.argsort(-weights, kind="stable")
    rng = np.random.default_rng(seed)
    table, kept = [], []
    for c in order:
        fit = fits[c]
        row = {"effects": list(fit.effects), "free_parameters": free[c],
               "nrmse": float(np.sqrt(np.mean(fit.residual**2))), "bic": float(bic[c]),
               "delta_bic": float(bic[c] - bic.min()), "weight": float(weights[c]),
               "selected": fit is selected, "converged": fit.converged, "in_mixture": False, "note": ""}
        table.append(row)
        if weights[c] < min_weight:
            row["note"] = f"weight below {min_weight:g}: left out"
            continue
        composition, row["note"] = _composition(result, fit, row, draws, rng, seed)
        if composition is not None:
            kept.append(composition)
            row["in_mixture"] = True
    mixture, why = _mixture(kept, table, min_weight)
    return DiscoveryMixture("bic", float(n_eff), float(min_weight), table, mixture, why)


def _mixture(kept, table, min_weight):
    """(`BearingMixture` of the compositions kept, their weights normalised; or None, why)."""
    if not kept:
        return None, "no composition could be drawn (see each one's note)"
    total = math.fsum(c["weight"] for c in kept)
    left_out = tuple({"effects": row["effects"], "weight": row["weight"]}
                     for row in table if not row["in_mixture"])
    compositions = tuple(MixtureComposition(weight=c["weight"] / total, **{
        k: v for k, v in c.items() if k != "weight"}) for c in kept)
    return BearingMixture(compositions, criterion="bic", left_out=left_out,
                          min_weight=min_weight), ""


def _composition(result, fit, row, draws, rng, seed):
    """(the keyword arguments of a `MixtureComposition` for `fit` with its weight, its note);
    (None, why) when its constants cannot be drawn."""
    effects = list(fit.effects)
    active = _active_parameters(fit.values, effects)
    point = result.bearing(active, effects)
    std, cov_root, identified = _laplace(fit)
    held = [PARAMETER_NAMES[i] for i in np.flatnonzero(fit.free) if i not in identified]
    note = (f"held at their estimates (the record does not determine them): {', '.join(held)}"
            if held else "")
    values, acceptance = _truncated_draws(fit.values, identified, cov_root, draws, rng, active)
    if values is None:
        return None, (f"its Gaussian draws fall inside the constants' ranges {acceptance:.2%} of the "
                      "time: left out")
    batch = result.bearing({n: values[:, i] for i, n in enumerate(PARAMETER_NAMES)
                            if n in active}, effects)
    try:
        check_bearing(batch)
    except ValueError as error:
        return None, f"a draw of its constants is not a valid bearing ({error}): left out"
    sampled = {}
    for name in POSTERIOR_FIELDS:
        x = None if posterior_constant(point, name) is None else posterior_constant(batch, name)
        if x is not None and np.ndim(x) == 1 and np.ptp(np.asarray(x)) > 0:
            sampled[name] = np.asarray(x, float)
    if not sampled:
        return None, "none of its constants is determined by the record: left out"
    posterior = BearingPosterior(names=tuple(sampled), draws=sampled,
                                 effective_sample_size={n: float(draws) for n in sampled},
                                 draws_before_thinning=draws, thinning=1, chains=1, seed=seed,
                                 method=LAPLACE)
    errors = part_errors({n: std[i] for i, n in enumerate(PARAMETER_NAMES) if n in active})
    return {"effects": tuple(effects), "weight": row["weight"], "delta_bic": row["delta_bic"],
            "bearing": point, "posterior": posterior, "standard_errors": errors, "note": note}, note


def _laplace(fit):
    """(standard errors (P,) [SI; 0 for constants held known, inf where not determined], a
    square root L of the covariance of the identified free constants (L L^T = C), their
    indices)."""
    free = np.flatnonzero(fit.free)
    cov, _ = covariance_from_jacobian(fit.jacobian[:, free], fit.residual)
    cov = cov * (fit.residual.size / effective_samples(fit.residual))
    std = np.zeros(fit.values.size)
    std[free] = np.sqrt(np.abs(np.diag(cov)))
    good = np.isfinite(np.diag(cov))
    block = cov[np.ix_(good, good)]
    eigenvalues, vectors = np.linalg.eigh(0.5 * (block + block.T))
    return std, vectors * np.sqrt(np.clip(eigenvalues, 0.0, None)), free[good]


def _truncated_draws(values, identified, root, draws, rng, active):
    """(K draws (K, P) of the Gaussian around `values` in the `identified` constants, each inside
    the constants' ranges, with delta_f < f_max where `active` has delta_f; the fraction
    accepted) or (None, fraction) when too few fall inside."""
    names = [PARAMETER_NAMES[i] for i in identified]
    lower = np.array([PARAMETER_BOUNDS[n].physical[0] for n in names])
    upper = np.array([PARAMETER_BOUNDS[n].physical[1] for n in names])
    pairs = [(PARAMETER_NAMES.index(a), PARAMETER_NAMES.index(b))
             for a, b in (("f_max", "delta_f"), ("f_max_perpendicular", "delta_f_perpendicular"))
             if b in active]
    kept, tried = [], 0
    for _ in range(MAX_DRAW_ROUNDS):
        x = np.tile(values, (2 * draws, 1))
        x[:, identified] += rng.standard_normal((2 * draws, identified.size)) @ root.T
        inside = np.all((x[:, identified] > lower) & (x[:, identified] < upper), axis=1)
        for f, d in pairs:
            inside &= x[:, f] > x[:, d]
        kept.append(x[inside])
        tried += 2 * draws
        if sum(len(k) for k in kept) >= draws:
            return np.concatenate(kept)[:draws], sum(len(k) for k in kept) / tried
    return None, sum(len(k) for k in kept) / tried
