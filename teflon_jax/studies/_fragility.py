"""Lognormal fragility curves fitted by maximum likelihood to exceedance counts.

At each intensity level x_j (e.g. a peak ground acceleration) n_j motions were run and k_j of
them exceeded a limit (a base displacement, a storey drift, a base shear). The fragility

    P(exceed | x) = Phi( ln(x / theta) / beta ),

with `median` theta [the intensities' unit] and `dispersion` beta [-], is fitted by maximising
the binomial likelihood of the counts,

    ln L(theta, beta) = sum_j [ k_j ln p_j + (n_j - k_j) ln(1 - p_j) ],   p_j = P(exceed | x_j),

which weighs every level by its number of runs and accepts levels where none or all exceed
(a least-squares fit to the fractions does neither). This is the multiple-stripe analysis
estimator of Baker (2015), "Efficient analytical fragility function fitting using dynamic
structural analysis", Earthquake Spectra 31(1), 579-599, Eq. 11: the levels are assumed
independent given theta and beta, i.e. other motions at each level.

Confidence intervals are profile-likelihood intervals: the values v of one parameter whose
likelihood, maximised over the other, stays within half the chi-square quantile of the
maximum, 2 [ln L_max - ln L_profile(v)] <= chi2_1(confidence). They are not symmetric, and an
end is infinite (or 0) when the data cannot rule out that side (too few levels with
exceedances on it).

The fit exists only when the counts overlap: some run exceeds at an intensity below one where
some run does not. When every level below some intensity has no exceedance and every level
above it only exceedances, the likelihood grows without bound as beta -> 0; such counts are
refused, naming the levels, as are counts with no exceedance (or no non-exceedance) at all.

When the runs were made with K draws of the bearing's constants (a posterior's), each draw's
counts are fitted alone and the spread of the K fits is the bearing's share of the
uncertainty (`fragility_band`): percentiles of the medians and dispersions over the draws, the
same percentiles of their profile intervals' ends (sampling and bearing together), and the
pointwise percentiles of the K curves.
"""

import dataclasses
import math

import numpy as np
from scipy import optimize, special, stats


@dataclasses.dataclass(frozen=True)
class FragilityFit:
    """A fitted lognormal fragility (`fit_fragility`).

    - `median` theta [the intensities' unit]: the intensity at which half the runs exceed;
    - `dispersion` beta [-]: standard deviation of ln(capacity);
    - `median_interval`, `dispersion_interval`: (low, high) profile-likelihood intervals at
      `confidence` (an end the data cannot bound is 0 or `inf`);
    - `log_likelihood`: ln L at the fit; `intensities` (J,), `n_runs` (J,), `n_exceed` (J,):
      the data it rests on.
    """

    median: float
    dispersion: float
    median_interval: tuple
    dispersion_interval: tuple
    confidence: float
    log_likelihood: float
    intensities: np.ndarray
    n_runs: np.ndarray
    n_exceed: np.ndarray

    def probability(self, intensity) -> np.ndarray:
        """P(exceed | x) = Phi(ln(x / theta) / beta) at `intensity` (same unit as the fit)."""
        return stats.norm.cdf(np.log(np.asarray(intensity, float) / self.median) / self.dispersion)

    @property
    def fractions(self) -> np.ndarray:
        """k_j / n_j, the fraction of runs exceeding at each level."""
        return self.n_exceed / self.n_runs


def _counts(values, name: str, size: int | None) -> np.ndarray:
    array = np.asarray(values)
    if array.ndim != 1 or (size is not None and array.shape[0] != size):
        raise ValueError(f"{name}: expected one count per intensity level ({size}), got shape {array.shape}.")
    if not np.issubdtype(array.dtype, np.integer):
        if not (np.issubdtype(array.dtype, np.floating) and np.all(np.isfinite(array))
                and np.all(array == np.round(array))):
            raise ValueError(f"{name}: counts must be whole numbers, got {array.tolist()}.")
    return array.astype(np.int64)


def check_exceedances(intensities, n_runs, n_exceed) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The data of `fit_fragility` as arrays once checked: `ValueError` naming the argument and
    the level when the intensities are not positive, finite and strictly increasing, a count
    is not a whole number in range, or the counts admit no finite fit (none or all exceed, or
    no overlap: see the module docstring)."""
    x = np.asarray(intensities, float)
    if x.ndim != 1 or x.shape[0] < 2:
        raise ValueError(f"intensities: need at least two levels, got {x.tolist()}.")
    if not np.all(np.isfinite(x)) or not np.all(x > 0):
        raise ValueError(f"intensities: must be finite and > 0, got {x.tolist()}.")
    for j in range(1, x.shape[0]):
        if not x[j] > x[j - 1]:
            raise ValueError(f"intensities: must increase from level to level; level {j + 1} "
                             f"({x[j]:g}) is not above level {j} ({x[j - 1]:g}). Sort them.")
    n = _counts(n_runs, "n_runs", x.shape[0])
    k = _counts(n_exceed, "n_exceed", x.shape[0])
    if np.any(n < 1):
        raise ValueError(f"n_runs: every level needs at least one run, got {n.tolist()}.")
    if np.any(k < 0) or np.any(k > n):
        raise ValueError(f"n_exceed: each count must be in 0..n_runs, got {k.tolist()} of {n.tolist()}.")
    if k.sum() == 0:
        raise ValueError(f"n_exceed: no run exceeds the limit at any level (up to {x[-1]:g}); "
                         "too few exceedances to fit a fragility: add higher intensities.")
    if np.all(k == n):
        raise ValueError(f"n_exceed: every run exceeds the limit at every level (from {x[0]:g}); "
                         "too few non-exceedances to fit a fragility: add lower intensities.")
    first_exceeding = int(np.flatnonzero(k > 0)[0])
    last_not_all = int(np.flatnonzero(k < n)[-1])
    if last_not_all <= first_exceeding:
        where = (f"only level {first_exceeding + 1} ({x[first_exceeding]:g}) has some but not all "
                 "runs exceeding; none exceed below it and all above it" if last_not_all == first_exceeding
                 else f"no run exceeds up to {x[last_not_all]:g} and every run exceeds from "
                 f"{x[first_exceeding]:g}")
        raise ValueError(f"n_exceed: too few exceedances to fit a fragility: {where}, so the dispersion "
                         "is not bounded away from 0. Add levels in between or more runs per level.")
    return x, n, k


def _log_likelihood(eta, n, k):
    """sum_j k_j ln Phi(eta_j) + (n_j - k_j) ln Phi(-eta_j), eta (..., J)."""
    return np.sum(k * special.log_ndtr(eta) + (n - k) * special.log_ndtr(-eta), axis=-1)


def _score(eta, n, k):
    """d ln L / d eta_j (inverse Mills ratios, evaluated in logs)."""
    log_pdf = -0.5 * eta**2 - 0.5 * math.log(2 * math.pi)
    return k * np.exp(log_pdf - special.log_ndtr(eta)) - (n - k) * np.exp(log_pdf - special.log_ndtr(-eta))


def _maximum(t, n, k):
    """The probit maximum likelihood (a, b) of eta = a + b t, by BFGS on the concave ln L."""
    fractions = np.clip((k + 0.5) / (n + 1.0), 1e-3, 1 - 1e-3)
    slope, intercept = np.polyfit(t, special.ndtri(fractions), 1, w=np.sqrt(n))
    start = np.array([intercept, max(slope, 0.1)])

    def negative(params):
        eta = params[0] + params[1] * t
        score = _score(eta, n, k)
        return -_log_likelihood(eta, n, k), -np.array([score.sum(), (score * t).sum()])

    found = optimize.minimize(negative, start, jac=True, method="BFGS", options={"gtol": 1e-10})
    return found.x, -found.fun


_LOG_SLOPE = (-12.0, 8.0)
"""Range of ln(1 / beta) over which the median's profile is maximised (beta from 3e-4 to 2e5)."""


def _profile_dispersion(log_beta, t, n, k):
    """max over a of ln L with b = 1 / beta fixed (concave in a)."""
    b = math.exp(-log_beta)
    found = optimize.minimize_scalar(lambda a: -_log_likelihood(a + b * t, n, k))
    return -found.fun


def _profile_median(centre, t, n, k):
    """max over beta of ln L with ln theta = `centre` (in the centred log intensity) fixed;
    concave in b = 1 / beta, searched over ln b in `_LOG_SLOPE`."""
    found = optimize.minimize_scalar(lambda s: -_log_likelihood(math.exp(s) * (t - centre), n, k),
                                     bounds=_LOG_SLOPE, method="bounded", options={"xatol": 1e-10})
    return -found.fun


def _end(profile, start, step, level, limit):
    """Where `profile` falls to `level` going from `start` in the direction of `step` (doubled
    until the drop is bracketed); `None` when it stays above it out to `limit` from `start`."""
    near, far = start, start + step
    while profile(far) > level:
        near, far = far, far + 2 * (far - near)
        if abs(far - start) > limit:
            return None
    return optimize.brentq(lambda v: profile(v) - level, near, far, xtol=1e-12, rtol=1e-12)


def fit_fragility(intensities, n_runs, n_exceed, *, confidence: float = 0.95) -> FragilityFit:
    """Lognormal fragility by maximum likelihood on exceedance counts (module docstring).

    **Arguments:**

    - `intensities` (J,) > 0, strictly increasing [any unit, e.g. g]: the levels x_j;
    - `n_runs` (J,): runs at each level n_j >= 1 (those whose solve converged);
    - `n_exceed` (J,): runs exceeding the limit k_j, 0 <= k_j <= n_j;
    - `confidence`: level of the profile-likelihood intervals, in (0, 1).

    **Returns:** a `FragilityFit` (median in the intensities' unit). `ValueError` naming the
    argument for data that admit no fit (`check_exceedances`).

    Reference: Baker (2015), Earthquake Spectra 31(1), 579-599.
    """
    if not 0 < confidence < 1:
        raise ValueError(f"confidence: must be in (0, 1), got {confidence}.")
    x, n, k = check_exceedances(intensities, n_runs, n_exceed)
    log_x = np.log(x)
    shift = float(np.mean(log_x))
    t = log_x - shift
    (a, b), best = _maximum(t, n, k)
    if not b > 0:
        raise ValueError(f"n_exceed: the fraction exceeding does not increase with intensity "
                         f"({(k / n).round(3).tolist()} at {x.tolist()}); a fragility curve does not fit.")
    level = best - 0.5 * stats.chi2.ppf(confidence, 1)
    log_beta, centre = -math.log(b), -a / b
    span = max(float(t[-1] - t[0]), 0.1)

    def dispersion_profile(v):
        return _profile_dispersion(v, t, n, k)

    def median_profile(v):
        return _profile_median(v, t, n, k)

    ends = []
    for profile, start in ((dispersion_profile, log_beta), (median_profile, centre)):
        pair = [_end(profile, start, sign * 0.05 * span, level, 40.0) for sign in (-1, 1)]
        ends.append(pair)
    (beta_low, beta_high), (median_low, median_high) = ends
    return FragilityFit(
        median=math.exp(centre + shift),
        dispersion=math.exp(log_beta),
        median_interval=(0.0 if median_low is None else math.exp(median_low + shift),
                         math.inf if median_high is None else math.exp(median_high + shift)),
        dispersion_interval=(0.0 if beta_low is None else math.exp(beta_low),
                             math.inf if beta_high is None else math.exp(beta_high)),
        confidence=float(confidence),
        log_likelihood=float(best),
        intensities=x,
        n_runs=n,
        n_exceed=k,
    )


@dataclasses.dataclass(frozen=True)
class FragilityBand:
    """A lognormal fragility with the uncertainty of the bearing's constants (`fragility_band`).

    - `pooled`: the `FragilityFit` of every run (counts summed over the draws);
    - `draw_medians`, `draw_dispersions` (K,): the fit of each draw's runs (NaN where a draw's
      counts admit no fit: `unfitted`, draw index -> why);
    - `median_band`, `dispersion_band`: (low, high) percentiles (1 -+ `band`) / 2 over the
      fitted draws; `median_interval`, `dispersion_interval`: the same percentiles of the
      draws' profile-likelihood interval ends (low ends for low, high ends for high), the band
      and the sampling uncertainty of each draw's runs together;
    - `band` in (0, 1): the share of draws the bands span; `draw_fits`: the fitted draws'
      `FragilityFit`s, in draw order.
    """

    pooled: FragilityFit
    draw_medians: np.ndarray
    draw_dispersions: np.ndarray
    median_band: tuple
    dispersion_band: tuple
    median_interval: tuple
    dispersion_interval: tuple
    band: float
    unfitted: dict
    draw_fits: tuple

    def probability_band(self, intensity) -> tuple[np.ndarray, np.ndarray]:
        """(low, high): the (1 -+ `band`) / 2 percentiles over the fitted draws of
        Phi(ln(x / theta_k) / beta_k) at each `intensity` x (pointwise)."""
        curves = np.stack([fit.probability(intensity) for fit in self.draw_fits])
        low, high = (1 - self.band) / 2, (1 + self.band) / 2
        return _percentile(curves, low), _percentile(curves, high)


def _percentile(values, q: float):
    """The q-quantile over axis 0 with linear interpolation between order statistics (numpy's
    default), where an infinite neighbour gives an infinite end instead of NaN."""
    ordered = np.sort(np.asarray(values, float), axis=0)
    position = q * (ordered.shape[0] - 1)
    below, frac = int(math.floor(position)), position - math.floor(position)
    above = min(below + 1, ordered.shape[0] - 1)
    if frac == 0:
        return ordered[below]
    with np.errstate(invalid="ignore"):
        value = ordered[below] + frac * (ordered[above] - ordered[below])
    return np.where(np.isinf(ordered[above]), ordered[above], value)


def _draw_counts(n_runs, n_exceed, levels: int) -> tuple[np.ndarray, np.ndarray]:
    n = np.asarray(n_runs)
    k = np.asarray(n_exceed)
    for name, array in (("n_runs", n), ("n_exceed", k)):
        if array.ndim != 2 or array.shape[1] != levels or array.shape[0] < 1:
            raise ValueError(f"{name}: expected (draws, levels) counts with {levels} levels, got shape "
                             f"{array.shape}.")
    if n.shape != k.shape:
        raise ValueError(f"n_exceed: shape {k.shape} differs from n_runs' {n.shape}.")
    return n, k


def fragility_band(intensities, n_runs, n_exceed, *, band: float = 0.90,
                   confidence: float = 0.95) -> FragilityBand:
    """The lognormal fragility of every run with the spread that the bearing's uncertainty adds.

    Each of K draws of the bearing's constants (a posterior's) ran its own motions; draw k's
    counts (n_kj, k_kj) over the levels x_j are fitted alone (`fit_fragility`, Baker 2015,
    Eq. 11), giving (theta_k, beta_k) and their profile-likelihood intervals. The band of a
    parameter is the (1 -+ `band`) / 2 percentiles of its K fits; the combined interval takes
    the same percentiles of the K intervals' ends, so that it is the sampling interval when
    the draws are alike and the band when each draw's runs are many. The curve band is the
    pointwise percentiles of P_k(x) = Phi(ln(x / theta_k) / beta_k) (`probability_band`).

    **Arguments:** `intensities` (J,) as `fit_fragility`; `n_runs`, `n_exceed` (K, J): the
    converged runs of each draw at each level and those exceeding; `band`, `confidence` in (0, 1).

    **Returns:** a `FragilityBand`; `pooled` is `fit_fragility` of the counts summed over the
    draws. A draw whose counts admit no fit (`check_exceedances`) is named in `unfitted` and
    left out of the bands; `ValueError` when fewer than two draws can be fitted, naming them.
    """
    if not 0 < band < 1:
        raise ValueError(f"band: must be in (0, 1), got {band}.")
    x = np.asarray(intensities, float)
    if x.ndim != 1:
        raise ValueError(f"intensities: expected one value per level, got shape {x.shape}.")
    n, k = _draw_counts(n_runs, n_exceed, x.shape[0])
    pooled = fit_fragility(x, n.sum(axis=0), k.sum(axis=0), confidence=confidence)
    fits, unfitted = [], {}
    for draw in range(n.shape[0]):
        try:
            fits.append(fit_fragility(x, n[draw], k[draw], confidence=confidence))
        except ValueError as error:
            fits.append(None)
            unfitted[draw] = str(error)
    fitted = [fit for fit in fits if fit is not None]
    if len(fitted) < 2:
        raise ValueError(f"n_exceed: only {len(fitted)} of {n.shape[0]} draws' counts admit a fit "
                         f"({'; '.join(f'draw {d}: {why}' for d, why in list(unfitted.items())[:3])}); "
                         "run more motions per draw.")
    low, high = (1 - band) / 2, (1 + band) / 2

    def spread(values):
        return float(_percentile(values, low)), float(_percentile(values, high))

    medians = np.array([f.median for f in fitted])
    dispersions = np.array([f.dispersion for f in fitted])
    return FragilityBand(
        pooled=pooled,
        draw_medians=np.array([np.nan if f is None else f.median for f in fits]),
        draw_dispersions=np.array([np.nan if f is None else f.dispersion for f in fits]),
        median_band=spread(medians),
        dispersion_band=spread(dispersions),
        median_interval=(spread([f.median_interval[0] for f in fitted])[0],
                         spread([f.median_interval[1] for f in fitted])[1]),
        dispersion_interval=(spread([f.dispersion_interval[0] for f in fitted])[0],
                             spread([f.dispersion_interval[1] for f in fitted])[1]),
        band=float(band),
        unfitted=unfitted,
        draw_fits=tuple(fitted),
    )
