"""Tests of the Kanai-Tajimi / Clough-Penzien stochastic ground motions.

References used here are independent of the library code: the filters' complex transfer
functions written out from their differential equations, numerical quadrature of the
spectrum (scipy), Welch spectral estimates of the samples (scipy.signal), the classical
Kanai-Tajimi variance, and finite differences.
"""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy import integrate, signal

from teflon_jax.excitation import (
    StochasticGroundMotion,
    envelope,
    num_time_steps,
    power_spectral_density,
    sample,
    sample_times,
    stationary_variance,
    white_noise_intensity,
)

jax.config.update("jax_enable_x64", True)  # as tests/conftest.py does for the suite

N_RECORDS = 1000
PGA = 3.0  # [m/s^2]


def _model(high_pass_filter=True, **kwargs):
    kwargs.setdefault("peak_ground_acceleration", PGA)
    return StochasticGroundMotion(high_pass_filter=high_pass_filter, **kwargs)


def _transfer_squared(model, omega):
    """|H(i omega)|^2 of the filters, written from their equations of motion.

    Kanai-Tajimi: x'' + 2 zg wg x' + wg^2 x = -w, a_1 = -(wg^2 x + 2 zg wg x').
    Clough-Penzien: y'' + 2 zf wf y' + wf^2 y = a_1, a_g = y''.
    """
    wg, zg = float(model.site_frequency), float(model.site_damping)
    s = 1j * omega
    x_over_w = -1.0 / (s**2 + 2 * zg * wg * s + wg**2)
    a1_over_w = -(wg**2 + 2 * zg * wg * s) * x_over_w
    if not model.high_pass_filter:
        return np.abs(a1_over_w) ** 2
    wf, zf = float(model.high_pass_frequency), float(model.high_pass_damping)
    y_over_a1 = 1.0 / (s**2 + 2 * zf * wf * s + wf**2)
    return np.abs(s**2 * y_over_a1 * a1_over_w) ** 2


@pytest.fixture(
    scope="module", params=[True, False], ids=["clough_penzien", "kanai_tajimi"]
)
def model(request):
    return _model(request.param)


@pytest.fixture(scope="module")
def stationary_records(model):
    return np.asarray(sample(model, jax.random.key(0), N_RECORDS, stationary=True))


@pytest.fixture(scope="module")
def records(model):
    return np.asarray(sample(model, jax.random.key(1), N_RECORDS))


# ----------------------------------------------------------------- closed forms


def test_psd_matches_transfer_functions(model):
    omega = np.linspace(-120.0, 120.0, 241)
    s0 = float(white_noise_intensity(model))
    expected = s0 * _transfer_squared(model, omega)
    np.testing.assert_allclose(power_spectral_density(model, omega), expected, rtol=1e-12)


@pytest.mark.parametrize("high_pass_filter", [True, False])
@pytest.mark.parametrize(
    "params",
    [
        {},
        {"site_frequency": 5.0, "site_damping": 0.3},
        {"site_frequency": 25.0, "site_damping": 0.9, "high_pass_frequency": 4.0,
         "high_pass_damping": 0.2},
    ],
)
def test_variance_is_integral_of_psd(high_pass_filter, params):
    model = _model(high_pass_filter, **params)
    integral, _ = integrate.quad(
        lambda w: 2.0 * float(power_spectral_density(model, w)), 0.0, np.inf, limit=400
    )
    sigma2 = float(stationary_variance(model))
    assert sigma2 == pytest.approx((PGA / 3.0) ** 2, rel=1e-12)
    assert integral == pytest.approx(sigma2, rel=1e-6)


def test_kanai_tajimi_intensity_closed_form():
    """sigma^2 = pi S0 wg (1 + 4 zg^2) / (2 zg) for two-sided white noise S0."""
    wg, zg = 12.0, 0.4
    model = _model(False, site_frequency=wg, site_damping=zg)
    s0 = float(white_noise_intensity(model))
    assert s0 * math.pi * wg * (1 + 4 * zg**2) / (2 * zg) == pytest.approx(
        (PGA / 3.0) ** 2, rel=1e-12
    )


def test_envelope_shape():
    model = _model(rise_time=2.0, strong_motion_duration=6.0, decay_rate=0.5)
    t = np.array([-1.0, 0.0, 1.0, 2.0, 5.0, 8.0, 10.0, 14.0])
    expected = [0.0, 0.0, 0.25, 1.0, 1.0, 1.0, math.exp(-1.0), math.exp(-3.0)]
    np.testing.assert_allclose(envelope(model, t), expected, rtol=1e-12, atol=0.0)


def test_low_frequency_limits():
    """The reason for the second filter: finite velocity and displacement spectra at 0."""
    omega = np.array([0.0, 1e-4, 1e-3, 1e-2, 0.5, 3.0, 20.0])
    spectra = {}
    for name, model in (("cp", _model(True)), ("kt", _model(False))):
        spectra[name] = {
            q: np.asarray(power_spectral_density(model, omega, quantity=q))
            for q in ("acceleration", "velocity", "displacement")
        }
        spectra[name]["s0"] = float(white_noise_intensity(model))
        spectra[name]["model"] = model
    cp, kt = spectra["cp"], spectra["kt"]
    wf = float(cp["model"].high_pass_frequency)
    assert cp["acceleration"][0] == 0.0
    assert cp["velocity"][0] == 0.0
    assert cp["displacement"][0] == pytest.approx(cp["s0"] / wf**4, rel=1e-12)
    assert cp["displacement"][1] == pytest.approx(cp["displacement"][0], rel=1e-6)
    # Kanai-Tajimi keeps S0 at zero frequency, so its displacement spectrum blows up.
    assert kt["acceleration"][0] == pytest.approx(kt["s0"], rel=1e-12)
    assert not np.isfinite(kt["displacement"][0])
    assert kt["displacement"][2] / kt["displacement"][3] == pytest.approx(1e4, rel=1e-3)
    # Away from zero the three spectra differ by omega^2 and omega^4.
    for spectrum in (cp, kt):
        w, acc = omega[4:], spectrum["acceleration"][4:]
        np.testing.assert_allclose(spectrum["velocity"][4:], acc / w**2, rtol=1e-12)
        np.testing.assert_allclose(spectrum["displacement"][4:], acc / w**4, rtol=1e-12)


# ----------------------------------------------------------------- sample statistics


def test_mean_spectrum_matches_psd(model, stationary_records):
    """Welch estimate averaged over 1,000 records, band averaged, within 10 % of S."""
    fs = 1.0 / model.time_step
    freq, welch = signal.welch(stationary_records, fs=fs, nperseg=1024, axis=-1)
    omega = 2 * math.pi * freq
    estimate = welch.mean(axis=0) / (4 * math.pi)  # one-sided per Hz -> two-sided per rad/s
    closed = np.asarray(power_spectral_density(model, omega))
    for target in (4.0, 8.0, 15.6, 25.0, 50.0, 100.0):
        band = np.abs(omega - target) <= 1.5
        assert band.sum() >= 3
        ratio = estimate[band].mean() / closed[band].mean()
        assert ratio == pytest.approx(1.0, abs=0.10), f"omega = {target} rad/s"


def test_periodogram_exact_with_random_phases(model):
    """With fixed amplitudes each record's periodogram equals S at the harmonics."""
    x = sample(model, jax.random.key(3), 4, stationary=True, random_amplitudes=False)
    x = np.asarray(x)
    nt, dt = x.shape[-1], model.time_step
    periodogram = np.abs(np.fft.rfft(x, axis=-1)) ** 2 * dt / (2 * math.pi * nt)
    omega = 2 * math.pi * np.fft.rfftfreq(nt, dt)
    inner = slice(1, (nt - 1) // 2 + 1)
    expected = np.asarray(power_spectral_density(model, omega[inner]))
    np.testing.assert_allclose(
        periodogram[:, inner],
        np.broadcast_to(expected, (4, expected.size)),
        rtol=1e-8,
        atol=1e-12 * expected.max(),
    )


def test_ensemble_std_follows_envelope(model, records):
    """Ensemble RMS over 1 s windows equals sigma_N * RMS(envelope) within 3 %.

    `sigma_N^2 = sum_k 2 S(omega_k) delta_omega` is the variance of the harmonics the
    records contain (up to the Nyquist frequency); it is itself within 3 % of the
    variance of the continuous process.
    """
    t = np.asarray(sample_times(model))
    nt, dt = t.size, model.time_step
    delta_omega = 2 * math.pi / (nt * dt)
    omega_k = delta_omega * np.arange(1, (nt - 1) // 2 + 1)
    spectrum_k = np.asarray(power_spectral_density(model, omega_k))
    band_limited = 2 * delta_omega * np.sum(spectrum_k)
    assert band_limited == pytest.approx(float(stationary_variance(model)), rel=0.03)
    sigma = math.sqrt(band_limited)
    e = np.asarray(envelope(model, t))
    window = int(round(1.0 / dt))
    checked = 0
    for start in range(0, nt - window, window):
        part = slice(start, start + window)
        if e[part].min() < 0.05:
            continue
        rms = math.sqrt(np.mean(records[:, part] ** 2))
        expected = sigma * math.sqrt(np.mean(e[part] ** 2))
        assert rms == pytest.approx(expected, rel=0.03), f"t = {t[start]:.2f} s"
        checked += 1
    assert checked > 15


def test_mean_is_zero(model, records, stationary_records):
    t = np.asarray(sample_times(model))
    e = np.asarray(envelope(model, t))
    sigma = math.sqrt(float(stationary_variance(model)))
    mean = records.mean(axis=0)
    assert np.all(np.abs(mean) <= 5.0 * sigma * e / math.sqrt(N_RECORDS) + 1e-12)
    # No zero-frequency content: every stationary record averages to zero over its period.
    np.testing.assert_allclose(stationary_records.mean(axis=1), 0.0, atol=1e-12 * sigma)


def test_mean_peak_near_target(records):
    """The default peak factor makes the mean record peak land near the target PGA."""
    peaks = np.abs(records).max(axis=1)
    assert peaks.mean() == pytest.approx(PGA, rel=0.15)


# ----------------------------------------------------------------- keys, jit, vmap, grad


def test_keys_reproducible_and_distinct():
    model = _model()
    a = np.asarray(sample(model, jax.random.key(7), 3))
    b = np.asarray(sample(model, jax.random.key(7), 3))
    c = np.asarray(sample(model, jax.random.key(8), 3))
    np.testing.assert_array_equal(a, b)
    assert a.shape == (3, num_time_steps(model))
    assert np.all(np.abs(a - c).max(axis=1) > 0.1 * PGA)
    # Records in one batch differ from each other.
    assert np.abs(a[0] - a[1]).max() > 0.1 * PGA


def test_jit_and_vmap():
    model = _model()
    keys = jax.random.split(jax.random.key(11), 3)
    batched = jax.vmap(lambda k: sample(model, k, 3))(keys)
    assert batched.shape == (3, 3, num_time_steps(model))
    for i in range(3):
        single = sample(model, keys[i], 3)
        np.testing.assert_allclose(batched[i], single, rtol=1e-12, atol=1e-12)

    @jax.jit
    def scaled(pga):
        return sample(StochasticGroundMotion(peak_ground_acceleration=pga), keys[0], 3)

    pgas = jnp.array([1.0, 2.5])
    over_pga = jax.vmap(scaled)(pgas)
    np.testing.assert_allclose(over_pga[1], 2.5 * over_pga[0], rtol=1e-12, atol=1e-12)


def test_gradients():
    key = jax.random.key(5)

    def mean_square(pga, site_frequency):
        model = StochasticGroundMotion(
            peak_ground_acceleration=pga, site_frequency=site_frequency
        )
        return jnp.mean(sample(model, key, 3) ** 2)

    pga, wg = 2.0, 15.6
    value = float(mean_square(pga, wg))
    d_pga, d_wg = jax.grad(mean_square, argnums=(0, 1))(pga, wg)
    assert float(d_pga) == pytest.approx(2.0 * value / pga, rel=1e-10)  # quadratic in PGA
    h = 1e-5
    fd = (float(mean_square(pga, wg + h)) - float(mean_square(pga, wg - h))) / (2 * h)
    assert float(d_wg) == pytest.approx(fd, rel=1e-5)


# ----------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"peak_ground_acceleration": -1.0}, "peak_ground_acceleration"),
        ({"peak_factor": 0.0}, "peak_factor"),
        ({"site_frequency": 0.0}, "site_frequency"),
        ({"site_damping": 0.0}, "site_damping"),
        ({"site_damping": -0.1}, "site_damping"),
        ({"high_pass_frequency": -1.0}, "high_pass_frequency"),
        ({"high_pass_damping": 0.0}, "high_pass_damping"),
        ({"rise_time": 0.0}, "rise_time"),
        ({"strong_motion_duration": -1.0}, "strong_motion_duration"),
        ({"decay_rate": float("nan")}, "decay_rate"),
        ({"duration": -5.0}, "duration"),
        ({"duration": 0.0}, "duration"),
        ({"time_step": 0.0}, "time_step"),
        ({"time_step": -0.01}, "time_step"),
        ({"duration": 5.0}, "duration"),  # shorter than rise + strong phase
        ({"time_step": 0.15}, "time_step"),  # Nyquist below twice the site frequency
    ],
)
def test_bad_parameters_raise(kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        _model(**kwargs)


def test_kanai_tajimi_ignores_high_pass_fields():
    model = _model(False, high_pass_frequency=0.0)
    assert float(power_spectral_density(model, 1.0)) > 0.0


@pytest.mark.parametrize("n", [0, -3, 2.5, True])
def test_bad_record_count_raises(n):
    with pytest.raises(ValueError, match="`n`"):
        sample(_model(), jax.random.key(0), n)


@pytest.mark.parametrize("key", [0, np.array([1.0, 2.0])], ids=["int", "float_array"])
def test_bad_key_raises(key):
    with pytest.raises(ValueError, match="`key`"):
        sample(_model(), key, 2)


def test_bad_quantity_raises():
    with pytest.raises(ValueError, match="`quantity`"):
        power_spectral_density(_model(), 1.0, quantity="jerk")
