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


def _suite_files(tmp_path, scales=(1, 1, 1)):
    t = DT * np.arange(401)
    rng = np.random.default_rng(3)
    for i in range(3):
        for axis, size in (("x", 0.3), ("y", 0.2)):
            a = size * (i + 1) * rng.normal(size=t.size) * np.sin(np.pi * t / t[-1]) ** 2
            (tmp_path / f"{axis}{i}.txt").write_text(
                "time acc\n" + "\n".join(f"{ti:.4f} {ai:.6e}" for ti, ai in zip(t, a)) + "\n")
    rows = "".join(f"p{i},x{i}.txt,y{i}.txt,{s}\n" for i, s in enumerate(scales))
    (tmp_path / "suite.csv").write_text("name,record_x,record_y,scale\n" + rows)
    (tmp_path / "target.csv").write_text("period [s], Sa [g]\n0.1, 0.6\n0.5, 1.0\n1.0, 0.6\n3.0, 0.2\n")
    return tmp_path / "suite.csv", tmp_path / "target.csv"


@pytest.mark.slow
def test_run_suite_scales_each_pair_to_the_target(tmp_path, capsys):
    """`run --suite --target-spectrum`: the JSON's factors are the hand calculation's from the
    records as read (within 0.1 %), the scaled suite lies at or above 0.9 of the target, the
    plot is written."""
    from teflon_jax.cli import main
    from teflon_jax.formats import read_two_column

    suite, target = _suite_files(tmp_path)
    code = main(["run", "--suite", str(suite), "--record-units", "g", "--target-spectrum", str(target),
                 "--period-range", "0.5s", "2s", "--min-ratio", "90%", "--spectrum-plot", str(tmp_path / "s.png"),
                 "--json", str(tmp_path / "s.json"), "--duration", "2s"])
    assert code == 0
    import json

    scaling = json.loads((tmp_path / "s.json").read_text())["spectrum_scaling"]
    periods = np.array([0.5, 1.0, 2.0])
    assert scaling["check_periods_s"] == pytest.approx(periods)
    goal = 0.9 * np.array([1.0, 0.6, 0.4]) * STANDARD_GRAVITY  # 2 s: 0.6 - (0.4 / 2) * 1 = 0.4 g
    for i in range(3):
        x = read_two_column(tmp_path / f"x{i}.txt", units="g")
        y = read_two_column(tmp_path / f"y{i}.txt", units="g")
        n = 201  # --duration 2s
        srss = np.hypot(_psa(x.acceleration[:n], periods), _psa(y.acceleration[:n], periods))
        assert scaling["factors"][f"p{i}"] == pytest.approx(np.max(goal / srss), rel=1e-3)
    assert scaling["suite_statistic_over_target_min"] >= 0.9 * (1 - 1e-12)
    assert (tmp_path / "s.png").stat().st_size > 0


@pytest.mark.parametrize("argv, message", [
    (["--target-spectrum", "{target}", "--period-range", "0.5s", "2s"], "scales the pairs of a suite; add --suite"),
    (["--suite", "{suite}", "--target-spectrum", "{target}"], "--period-range: a target spectrum needs the range"),
    (["--suite", "{suite}", "--target-spectrum", "{target}", "--period-range", "0.5s", "5s"],
     "--period-range: 0.5-5 s lies outside the target spectrum's periods 0.1-3 s"),
    (["--suite", "{suite}", "--target-spectrum", "{target}", "--period-range", "0.5s", "2s", "--max-factor", "0.01"],
     "--max-factor: 3 pair(s) would be scaled by more than 0.01: p0"),
    (["--suite", "{suite}", "--design-spectrum", "1g,0.6g", "--period-range", "0.5s", "2s"], "write S_DS,S_D1,T_L"),
    (["--suite", "{suite}", "--period-range", "0.5s", "2s"], "--period-range: only used with --target-spectrum"),
    (["--suite", "{suite}", "--target-spectrum", "{target}", "--period-range", "0.5s", "2s", "--scale", "2"],
     "--scale: the target spectrum sets the amplitude factors"),
    (["--suite", "{suite}", "--min-ratio", "90%"], "--min-ratio: only used with --target-spectrum"),
    (["--suite", "{suite}", "--combination", "rotd100"], "--combination: only used with --target-spectrum"),
    (["--suite", "{suite}", "--scaling", "suite"], "--scaling: only used with --target-spectrum"),
    (["--record-x", "{suite}", "--suite-statistic", "max"], "--suite-statistic: only used with --target-spectrum"),
    (["--suite", "{suite}", "--target-spectrum", "{target}", "--period-range", "0.5s", "2s", "--suite-statistic",
      "max"], "--suite-statistic max: the statistic one factor for the whole suite lifts to the target; add "
              "--scaling suite"),
])
def test_run_suite_target_mistakes_are_refused_before_any_run(tmp_path, capsys, argv, message):
    from teflon_jax.cli import main

    suite, target = _suite_files(tmp_path)
    argv = [a.replace("{suite}", str(suite)).replace("{target}", str(target)) for a in argv]
    code = main(["run", "--record-units", "g", "--json", str(tmp_path / "s.json"), *argv])
    assert code == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "s.json").exists()


def test_run_suite_with_a_target_refuses_scaled_rows(tmp_path, capsys):
    from teflon_jax.cli import main

    suite, target = _suite_files(tmp_path, scales=(1, 2, 1))
    code = main(["run", "--suite", str(suite), "--record-units", "g", "--target-spectrum", str(target),
                 "--period-range", "0.5s", "2s"])
    assert code == 2
    assert "--suite: pair p1 has scale 2" in capsys.readouterr().err
