"""Tests of the lognormal fragility fit (teflon_jax.studies.fit_fragility).

References: counts drawn from a known lognormal fragility (coverage of the 95 % intervals),
counts that follow it exactly (recovery to rounding), a brute-force grid search of the
binomial likelihood, and the chi-square drop that defines a profile-likelihood interval.
"""

import math

import numpy as np
import pytest
from scipy import stats

from teflon_jax.studies import fit_fragility

LEVELS = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0])


def _probability(x, median, dispersion):
    return stats.norm.cdf(np.log(x / median) / dispersion)


def test_exact_fractions_recover_median_and_dispersion():
    """Fractions equal to Phi(ln(x / theta) / beta) are the binomial likelihood's maximum."""
    n = np.full(LEVELS.size, 10**7)
    k = np.round(n * _probability(LEVELS, 0.45, 0.35)).astype(int)
    fit = fit_fragility(LEVELS, n, k)
    assert fit.median == pytest.approx(0.45, rel=1e-6)
    assert fit.dispersion == pytest.approx(0.35, rel=1e-5)
    np.testing.assert_allclose(fit.probability(LEVELS), k / n, atol=1e-6)


def test_maximum_matches_a_grid_search():
    """The fit is the maximum of sum k ln p + (n - k) ln(1 - p) found by brute force."""
    n = np.array([12, 15, 10, 20, 9, 14, 11, 10])
    k = np.array([0, 1, 3, 9, 5, 11, 10, 10])
    fit = fit_fragility(LEVELS, n, k)
    medians = np.linspace(0.2, 0.7, 1001)[:, None]
    dispersions = np.linspace(0.1, 1.0, 901)[None, :]
    p = _probability(LEVELS[:, None, None], medians, dispersions)
    p = np.clip(p, 1e-300, 1 - 1e-16)
    log_l = np.sum(k[:, None, None] * np.log(p) + (n - k)[:, None, None] * np.log1p(-p), axis=0)
    i, j = np.unravel_index(np.argmax(log_l), log_l.shape)
    assert fit.median == pytest.approx(medians[i, 0], abs=1e-3)
    assert fit.dispersion == pytest.approx(dispersions[0, j], abs=2e-3)
    assert fit.log_likelihood >= log_l.max()


def test_interval_ends_drop_the_likelihood_by_the_chi_square_quantile():
    """At each end of the dispersion interval the likelihood maximised over the median is
    the maximum less chi2_1(0.95) / 2 = 1.9207."""
    n = np.full(LEVELS.size, 20)
    k = np.array([0, 1, 4, 9, 12, 15, 19, 20])
    fit = fit_fragility(LEVELS, n, k)
    for beta in fit.dispersion_interval:
        p = _probability(LEVELS[:, None], np.linspace(0.3, 0.6, 30001)[None, :], beta)
        profile = np.max(np.sum(k[:, None] * np.log(p) + (n - k)[:, None] * np.log1p(-p), axis=0))
        assert fit.log_likelihood - profile == pytest.approx(0.5 * stats.chi2.ppf(0.95, 1), abs=1e-4)
    assert fit.dispersion_interval[0] < fit.dispersion < fit.dispersion_interval[1]
    assert fit.median_interval[0] < fit.median < fit.median_interval[1]


def test_intervals_cover_the_true_fragility_in_90_of_100_seeds():
    """Counts of 20 runs at 8 levels drawn from theta = 0.4, beta = 0.4: each 95 % interval
    holds its true value in at least 90 of 100 seeds, and both at once in at least 90."""
    median, dispersion = 0.4, 0.4
    n = np.full(LEVELS.size, 20)
    covered = np.zeros((100, 2), bool)
    for seed in range(100):
        k = np.random.default_rng(seed).binomial(n, _probability(LEVELS, median, dispersion))
        fit = fit_fragility(LEVELS, n, k)
        covered[seed] = (fit.median_interval[0] <= median <= fit.median_interval[1],
                         fit.dispersion_interval[0] <= dispersion <= fit.dispersion_interval[1])
    assert covered[:, 0].sum() >= 90
    assert covered[:, 1].sum() >= 90
    assert covered.all(axis=1).sum() >= 90


def test_weak_data_leave_an_interval_end_open():
    """Two exceedances at the top level only, one miss: the dispersion is not bounded above."""
    fit = fit_fragility([0.1, 0.2, 0.3], [3, 3, 3], [0, 1, 2])
    assert fit.dispersion_interval[1] == math.inf
    assert fit.dispersion_interval[0] > 0


@pytest.mark.parametrize(("levels", "k", "message"), [
    ([0.1, 0.3, 0.2], [0, 1, 2], "level 3 (0.2) is not above level 2 (0.3)"),
    ([0.1, 0.2, 0.2], [0, 1, 2], "level 3"),
    ([0.1, -0.2, 0.3], [0, 1, 2], "finite and > 0"),
    ([0.1, 0.2, 0.3], [0, 0, 0], "no run exceeds"),
    ([0.1, 0.2, 0.3], [5, 5, 5], "every run exceeds"),
    ([0.1, 0.2, 0.3], [0, 0, 5], "no run exceeds up to 0.2 and every run exceeds from 0.3"),
    ([0.1, 0.2, 0.3], [0, 2, 5], "only level 2 (0.2)"),
    ([0.1, 0.2, 0.3], [0, 6, 5], "n_exceed: each count must be in 0..n_runs"),
    ([0.1, 0.2, 0.3], [0, 1.5, 5], "whole numbers"),
    ([0.1, 0.2, 0.3], [4, 2, 1], "does not increase with intensity"),
])
def test_bad_input_is_refused_by_name(levels, k, message):
    with pytest.raises(ValueError, match="^(intensities|n_exceed|n_runs): ") as error:
        fit_fragility(levels, [5, 5, 5], k)
    assert message in str(error.value)
