"""Tests of scaling record pairs to a target spectrum (teflon_jax.studies.amplitude_factors).

References: hand calculations from each component's `response_spectrum` (SRSS), a brute-force
search over rotation angles (RotD100), the design shape's formula at its corners, and the
target-spectrum file refused line by line.
"""

import numpy as np
import pytest

from teflon_jax.excitation import GroundMotion, response_spectrum
from teflon_jax.formats import read_target_spectrum
from teflon_jax.studies import (
    DesignSpectrum,
    TabulatedSpectrum,
    amplitude_factors,
    check_factor_limit,
    check_period_range,
    combined_spectrum,
    suite_statistic,
)
from teflon_jax.units import STANDARD_GRAVITY

DT = 0.01


def _pairs():
    rng = np.random.default_rng(7)
    t = DT * np.arange(1200)
    envelope = np.sin(np.pi * t / t[-1]) ** 2
    return [(rng.normal(size=t.size) * envelope * s, rng.normal(size=t.size) * envelope * 0.7 * s)
            for s in (1.0, 2.0, 0.5)]


def _psa(values, periods):
    motion = GroundMotion(acceleration=values, time_step=DT)
    return response_spectrum(motion, periods, damping=0.05).pseudo_acceleration


TARGET = TabulatedSpectrum(np.array([0.1, 0.5, 1.0, 2.0, 4.0]), np.array([6.0, 9.0, 5.0, 2.5, 1.0]))


def test_srss_factors_of_three_pairs_match_a_hand_calculation():
    """f_i = max_T 0.9 S(T) / sqrt(PSA_x^2 + PSA_y^2) over [0.4, 3] s, from each component's
    spectrum: within 0.1 % (to rounding)."""
    periods = check_period_range(TARGET, 0.4, 3.0)
    np.testing.assert_allclose(periods, [0.4, 0.5, 1.0, 2.0, 3.0])
    spectra = np.array([combined_spectrum(x, y, DT, periods, method="srss") for x, y in _pairs()])
    factors, governing = amplitude_factors(spectra, TARGET(periods), min_ratio=0.9)
    target = np.interp(periods, TARGET.periods, TARGET.acceleration)  # 0.4 s: 6 + 0.75 * 3 = 8.25
    assert target[0] == pytest.approx(8.25)
    for i, (x, y) in enumerate(_pairs()):
        hand = max(0.9 * target[k] / np.hypot(_psa(x, periods)[k], _psa(y, periods)[k]) for k in range(5))
        assert factors[i] == pytest.approx(hand, rel=1e-3)
        assert factors[i] == pytest.approx(hand, rel=1e-12)
    scaled = factors[:, None] * spectra
    assert np.all(scaled >= 0.9 * TARGET(periods) * (1 - 1e-12))
    assert np.allclose(scaled[np.arange(3), governing], 0.9 * TARGET(periods)[governing])
    # the three pairs differ by amplitudes 1 : 2 : 0.5 of the same kind of noise, not the same noise
    assert len(set(np.round(factors, 6))) == 3


def test_rotd100_is_the_largest_response_over_all_directions():
    """omega^2 max_t |(u_x, u_y)| equals the largest PSA of the record rotated to any angle
    (brute force every 0.25 deg: within 1e-5), and is at least the SRSS / sqrt(2)."""
    x, y = _pairs()[0]
    periods = np.array([0.3, 1.0, 2.5])
    rotd100 = combined_spectrum(x, y, DT, periods, method="rotd100")
    angles = np.radians(np.arange(0, 180, 0.25))
    brute = np.max([_psa(np.cos(a) * x + np.sin(a) * y, periods) for a in angles], axis=0)
    np.testing.assert_allclose(rotd100, brute, rtol=1e-5)
    assert np.all(rotd100 >= brute)
    assert np.all(rotd100 >= combined_spectrum(x, y, DT, periods, method="srss") / np.sqrt(2))


def test_one_factor_for_the_suite_lifts_its_mean_or_maximum():
    periods = check_period_range(TARGET, 0.4, 3.0)
    spectra = np.array([combined_spectrum(x, y, DT, periods) for x, y in _pairs()])
    for statistic in ("mean", "max"):
        factors, _ = amplitude_factors(spectra, TARGET(periods), per="suite", statistic=statistic)
        assert np.all(factors == factors[0])
        statistic_values = spectra.mean(0) if statistic == "mean" else spectra.max(0)
        assert factors[0] == pytest.approx(np.max(TARGET(periods) / statistic_values), rel=1e-12)
        assert np.min(suite_statistic(spectra, factors, statistic) / TARGET(periods)) == pytest.approx(1.0)


def test_design_shape_at_its_corners():
    shape = DesignSpectrum(s_ds=1.0 * STANDARD_GRAVITY, s_d1=0.6 * STANDARD_GRAVITY, long_period=8.0)
    t0, ts, tl = shape.corners
    assert (t0, ts) == pytest.approx((0.12, 0.6))
    values = shape(np.array([0.0, t0, 0.3, ts, 1.2, tl, 16.0])) / STANDARD_GRAVITY
    np.testing.assert_allclose(values, [0.4, 1.0, 1.0, 1.0, 0.5, 0.075, 0.6 * 8 / 256], rtol=1e-12)
    assert set(shape.corners[:2]) <= set(shape.grid(0.1, 3.0))
    with pytest.raises(ValueError, match="^long_period: T_L = 0.5 s must be above T_S"):
        DesignSpectrum(s_ds=1.0, s_d1=0.6, long_period=0.5)


def test_bad_ranges_and_factors_are_reported_by_name():
    with pytest.raises(ValueError, match=r"^--period-range: 0.05-3 s lies outside the target spectrum's periods 0.1-4 s"):
        check_period_range(TARGET, 0.05, 3.0, "--period-range")
    with pytest.raises(ValueError, match="^--period-range: need 0 < LOW < HIGH"):
        check_period_range(TARGET, 2.0, 1.0, "--period-range")
    with pytest.raises(ValueError, match=r"^--max-factor: 1 pair\(s\) would be scaled by more than 4: B \(5.5\)"):
        check_factor_limit(["A", "B"], [1.5, 5.5], 4.0, "--max-factor")


@pytest.mark.parametrize("text, message", [
    ("period, Sa\n0.1 0.5\n1 0.3\n", "line 1: name the two columns with their units"),
    ("period [s], Sa [g]\n0.1, 0.5\n1.0, 0.3\n0.5, 0.2\n", "line 4, column 1: periods must increase; 0.5 is not above 1.0 (line 3)"),
    ("period [s], Sa [g]\n0.1, 0.5\n1.0, -0.3\n", "line 3, column 2: the spectral acceleration must be >= 0"),
    ("period [s], Sa [g]\n0.1, 0.5\n1.0, x\n", "line 3, column 2: 'x' is not a number"),
    ("period [s], Sa [in]\n0.1, 0.5\n1.0, 0.3\n", "column 2"),
    ("period [s], Sa [g]\n0.1, 0.5\n", "at least two rows"),
])
def test_target_spectrum_file_is_refused_line_by_line(tmp_path, text, message):
    path = tmp_path / "target.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=f"^{path}") as error:
        read_target_spectrum(path)
    assert message in str(error.value)


def test_target_spectrum_file_is_read_in_its_units(tmp_path):
    path = tmp_path / "target.txt"
    path.write_text("# design level\nT [s]  PSA [cm/s^2]\n0.1 500\n1.0 300\n")
    periods, acceleration = read_target_spectrum(path)
    np.testing.assert_allclose(periods, [0.1, 1.0])
    np.testing.assert_allclose(acceleration, [5.0, 3.0])
