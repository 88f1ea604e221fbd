"""Tests of the fragility band over bearing draws (teflon_jax.studies.fragility_band).

References: draws whose counts are alike (the band is the single fit, the combined interval
its profile interval), counts that follow two known lognormal fragilities exactly (the band
runs from one median to the other, the curve band from one curve to the other), and numpy's
percentiles of the per-draw fits.
"""

import numpy as np
import pytest
from scipy import stats

from teflon_jax.studies import fit_fragility, fragility_band

LEVELS = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0])


def _exact_counts(median, dispersion, n=10**6):
    """Counts whose fractions are Phi(ln(x / theta) / beta) to rounding."""
    runs = np.full(LEVELS.size, n)
    return runs, np.round(runs * stats.norm.cdf(np.log(LEVELS / median) / dispersion)).astype(int)


def test_identical_draws_collapse_the_band_to_the_single_fit():
    n = np.full(LEVELS.size, 20)
    k = np.array([0, 1, 4, 9, 12, 15, 19, 20])
    single = fit_fragility(LEVELS, n, k)
    band = fragility_band(LEVELS, np.tile(n, (6, 1)), np.tile(k, (6, 1)))
    assert band.median_band == pytest.approx((single.median, single.median), rel=1e-12)
    assert band.dispersion_band == pytest.approx((single.dispersion, single.dispersion), rel=1e-12)
    assert band.median_interval == pytest.approx(single.median_interval, rel=1e-12)
    assert band.dispersion_interval == pytest.approx(single.dispersion_interval, rel=1e-12)
    grid = np.linspace(0.05, 1.5, 50)
    for side in band.probability_band(grid):
        np.testing.assert_allclose(side, single.probability(grid), rtol=1e-12, atol=1e-15)
    # pooling six alike draws keeps the maximum and narrows the sampling interval
    assert band.pooled.median == pytest.approx(single.median, rel=1e-6)
    width = lambda interval: np.log(interval[1] / interval[0])  # noqa: E731
    assert width(band.pooled.median_interval) < width(single.median_interval)
    assert band.unfitted == {}


def test_draws_from_two_medians_span_them():
    """Five draws follow theta 0.3, five theta 0.6 (beta 0.4 each): the 90 % band runs from
    0.3 to 0.6, the curve band from the 0.6 curve (below) to the 0.3 curve (above), and the
    pooled fit lies between."""
    runs, low_k = _exact_counts(0.3, 0.4)
    _, high_k = _exact_counts(0.6, 0.4)
    n = np.tile(runs, (10, 1))
    k = np.stack([low_k] * 5 + [high_k] * 5)
    band = fragility_band(LEVELS, n, k[np.random.default_rng(3).permutation(10)])
    assert band.median_band == pytest.approx((0.3, 0.6), rel=1e-5)
    assert band.dispersion_band == pytest.approx((0.4, 0.4), rel=1e-4)
    assert band.median_interval[0] <= band.median_band[0] and band.median_interval[1] >= band.median_band[1]
    np.testing.assert_allclose(np.sort(band.draw_medians), [0.3] * 5 + [0.6] * 5, rtol=1e-5)
    grid = np.linspace(0.1, 1.2, 40)
    below, above = band.probability_band(grid)
    np.testing.assert_allclose(below, stats.norm.cdf(np.log(grid / 0.6) / 0.4), atol=1e-6)
    np.testing.assert_allclose(above, stats.norm.cdf(np.log(grid / 0.3) / 0.4), atol=1e-6)
    assert 0.3 < band.pooled.median < 0.6


def test_bands_are_numpy_percentiles_of_the_draw_fits():
    """Ten draws of 30 runs per level from medians spread over 0.3-0.6: each band end is
    numpy's percentile of the draws' own fits, and the combined interval that of their ends."""
    rng = np.random.default_rng(7)
    medians = np.linspace(0.3, 0.6, 10)
    n = np.full((10, LEVELS.size), 30)
    k = rng.binomial(n, stats.norm.cdf(np.log(LEVELS / medians[:, None]) / 0.35))
    band = fragility_band(LEVELS, n, k, band=0.8)
    fits = [fit_fragility(LEVELS, n[d], k[d]) for d in range(10)]
    assert band.median_band == pytest.approx(tuple(np.percentile([f.median for f in fits], [10, 90])), rel=1e-12)
    assert band.dispersion_band == pytest.approx(
        tuple(np.percentile([f.dispersion for f in fits], [10, 90])), rel=1e-12)
    assert band.median_interval[0] == pytest.approx(np.percentile([f.median_interval[0] for f in fits], 10), rel=1e-12)
    assert band.median_interval[1] == pytest.approx(np.percentile([f.median_interval[1] for f in fits], 90), rel=1e-12)
    x = np.array([0.25, 0.45, 0.7])
    curves = np.stack([f.probability(x) for f in fits])
    np.testing.assert_allclose(band.probability_band(x), np.percentile(curves, [10, 90], axis=0), rtol=1e-12)


def test_a_draw_without_a_fit_is_named_and_left_out():
    n = np.full((4, LEVELS.size), 20)
    k = np.tile(np.array([0, 1, 4, 9, 12, 15, 19, 20]), (4, 1))
    k[2] = 0  # no run of draw 2 exceeds
    band = fragility_band(LEVELS, n, k)
    assert list(band.unfitted) == [2] and "no run exceeds" in band.unfitted[2]
    assert np.isnan(band.draw_medians[2]) and len(band.draw_fits) == 3
    k[1] = 0
    k[3] = 0
    with pytest.raises(ValueError, match="only 1 of 4 draws' counts admit a fit"):
        fragility_band(LEVELS, n, k)


@pytest.mark.parametrize("n, k, band, message", [
    (np.full((2, 7), 5), np.zeros((2, 7), int), 0.9, r"^n_runs: expected \(draws, levels\) counts with 8 levels"),
    (np.full(8, 5), np.zeros(8, int), 0.9, r"^n_runs: expected \(draws, levels\) counts"),
    (np.full((2, 8), 5), np.zeros((3, 8), int), 0.9, r"^n_exceed: shape \(3, 8\) differs"),
    (np.full((2, 8), 5), np.zeros((2, 8), int), 1.0, r"^band: must be in \(0, 1\)"),
])
def test_bad_counts_are_refused_by_name(n, k, band, message):
    with pytest.raises(ValueError, match=message):
        fragility_band(LEVELS, n, k, band=band)


def _nested_result(peaks, converged, draws):
    """A `MonteCarloResult` of K bearing draws each run on the same motions (dims ("bearing",
    "motion")), made by hand: `peaks` (K, M) base displacements [m]."""
    from teflon_jax.studies import MonteCarloResult

    peaks = np.asarray(peaks, float)
    return MonteCarloResult(base_disp=peaks, base_shear_ratio=0.1 * np.ones_like(peaks), smooth_base_disp=peaks,
                            smooth_base_shear_ratio=0.1 * np.ones_like(peaks), converged=np.asarray(converged),
                            pga=np.ones(peaks.shape[1]), design={}, dims=("bearing", "motion"), n_devices=1,
                            chunk_size=1, wall_s=0.0, compile_s=0.0, memory_estimate_bytes=0,
                            bearing_draw=np.asarray(draws))


def test_montecarlo_levels_entry_of_nested_draws_is_the_band_of_their_counts():
    """The `montecarlo` fragility entry of K bearings x (L levels x N motions): the counts of
    all runs are fitted as before, and the band is `fragility_band` of each bearing's counts
    (a failed run counts nowhere)."""
    from teflon_jax.cli._engineering import Limit
    from teflon_jax.cli._levels import _fragility

    rng = np.random.default_rng(5)
    levels, n = LEVELS[:6], 40
    level_index = np.repeat(np.arange(levels.size), n)
    capacity = np.exp(np.log([0.25, 0.3, 0.35, 0.4])[:, None] + 0.3 * rng.standard_normal((4, level_index.size)))
    peaks = 0.05 * levels[level_index][None, :] / capacity  # exceeds 0.05 m where pga > capacity
    converged = np.ones(peaks.shape, bool)
    converged[1, 7] = False
    result = _nested_result(peaks, converged, draws=[12, 3, 40, 7])
    entry, band = _fragility(Limit("base_disp", 0.05, "base_disp=5cm"), result, level_index, levels, "g", 1.0)
    exceed = (peaks > 0.05) & converged
    n_runs = np.stack([np.bincount(level_index, converged[k], levels.size) for k in range(4)])
    n_exceed = np.stack([np.bincount(level_index, exceed[k], levels.size) for k in range(4)])
    assert entry["n_runs"] == n_runs.sum(0).tolist() and entry["n_exceed"] == n_exceed.sum(0).tolist()
    want = fragility_band(levels, n_runs, n_exceed)
    assert band.median_band == want.median_band and entry["bearing_band"]["median_band"] == list(want.median_band)
    assert entry["median"] == pytest.approx(want.pooled.median, rel=1e-12)
    assert entry["bearing_band"]["draws"] == [12, 3, 40, 7] and entry["bearing_band"]["n_fitted"] == 4
    below, above = entry["bearing_band"]["probability_band_at_levels"]
    assert np.all(np.array(below) <= np.array(above))


def test_the_plot_draws_a_band(tmp_path):
    """`plot_fragility` takes a `FragilityBand` beside a plain fit and writes the figure."""
    from teflon_jax.report import plot_fragility

    runs, low_k = _exact_counts(0.3, 0.4, n=50)
    _, high_k = _exact_counts(0.6, 0.4, n=50)
    band = fragility_band(LEVELS, np.stack([runs] * 4), np.stack([low_k, high_k, low_k, high_k]))
    path = tmp_path / "f.png"
    plot_fragility({"base_disp=2in": band, "drift=1%": band.draw_fits[0]}, path, title="band")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 20_000
