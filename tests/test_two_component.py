"""Tests of the two-component stochastic ground motions (principal axes, Penzien & Watabe 1975).

References independent of the code under test: the covariance R diag(1, gamma^2) R^T
written out entry by entry, the band-limited variance sum_k 2 S(omega_k) d_omega of the
harmonics, Welch spectral estimates (scipy.signal), and the one-component generator.
"""

import math

import jax
import numpy as np
import pytest
from scipy import signal

from teflon_jax.excitation import (
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    num_time_steps,
    power_spectral_density,
    principal_covariance,
    sample,
    sample_two_components,
)

jax.config.update("jax_enable_x64", True)

N = 300
PGA = 3.0  # [m/s^2]
MODEL = StochasticGroundMotion(peak_ground_acceleration=PGA)


def _band_variance(model):
    """Variance of the harmonics a record holds, sum_k 2 S(omega_k) d_omega [m^2/s^4]."""
    nt = num_time_steps(model)
    d_omega = 2 * math.pi / (nt * model.time_step)
    omega = d_omega * np.arange(1, (nt - 1) // 2 + 1)
    return 2 * d_omega * float(np.sum(power_spectral_density(model, omega)))


def _covariances(records):
    """Per-record time averages of a_i a_j over the stationary records (N, 2, 2)."""
    return np.einsum("nit,njt->nij", records, records) / records.shape[-1]


def _expected_covariance(theta, gamma):
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c * c + gamma**2 * s * s, c * s * (1 - gamma**2)],
                     [c * s * (1 - gamma**2), s * s + gamma**2 * c * c]])


@pytest.mark.parametrize("theta, gamma", [(0.4, 1.0), (math.radians(30), 0.7), (-1.1, 0.3)])
def test_covariance_is_the_principal_axes_one(theta, gamma):
    """The sample covariance of (a_x, a_y) is sigma^2 R diag(1, gamma^2) R^T (within 4
    standard errors over the records); turned back by -theta the components are uncorrelated
    with variance ratio gamma^2. With gamma = 1 the components are independent."""
    motion = TwoComponentGroundMotion(MODEL, principal_angle=theta, minor_ratio=gamma)
    records = np.asarray(sample_two_components(motion, jax.random.key(5), N, stationary=True))
    per_record = _covariances(records) / _band_variance(MODEL)
    mean, error = per_record.mean(axis=0), per_record.std(axis=0) / math.sqrt(N)
    expected = _expected_covariance(theta, gamma)
    np.testing.assert_allclose(np.asarray(principal_covariance(motion)), expected, atol=1e-12)
    assert np.all(error < 0.02)  # the test can see a 5 % error
    assert np.all(np.abs(mean - expected) < 4 * error + 1e-12), (mean, expected, error)
    c, s = math.cos(theta), math.sin(theta)
    back = np.stack([c * records[:, 0] + s * records[:, 1], -s * records[:, 0] + c * records[:, 1]], axis=1)
    principal = _covariances(back) / _band_variance(MODEL)
    p_mean, p_error = principal.mean(axis=0), principal.std(axis=0) / math.sqrt(N)
    assert abs(p_mean[0, 1]) < 4 * p_error[0, 1]
    assert abs(p_mean[0, 0] - 1) < 4 * p_error[0, 0]
    assert abs(p_mean[1, 1] - gamma**2) < 4 * p_error[1, 1] + 1e-12


def test_each_component_has_the_target_spectrum_and_peak():
    """Welch spectra of a_x and a_y are the model's S scaled by cos^2 + gamma^2 sin^2 and
    sin^2 + gamma^2 cos^2 (10 % in bands); the mean peaks along the principal axes are the
    target PGA and gamma times it (15 %, as for one component)."""
    theta, gamma = math.radians(30), 0.7
    motion = TwoComponentGroundMotion(MODEL, principal_angle=theta, minor_ratio=gamma)
    stationary = np.asarray(sample_two_components(motion, jax.random.key(6), N, stationary=True))
    freq, welch = signal.welch(stationary, fs=1 / MODEL.time_step, nperseg=1024, axis=-1)
    omega = 2 * math.pi * freq
    estimate = welch.mean(axis=0) / (4 * math.pi)  # one-sided per Hz -> two-sided per rad/s
    closed = np.asarray(power_spectral_density(MODEL, omega))
    scale = np.diag(_expected_covariance(theta, gamma))
    for component in (0, 1):
        for target in (4.0, 8.0, 15.6, 25.0, 50.0):
            band = np.abs(omega - target) <= 1.5
            ratio = estimate[component, band].mean() / (scale[component] * closed[band].mean())
            assert ratio == pytest.approx(1.0, abs=0.10), (component, target)
    records = np.asarray(sample_two_components(motion, jax.random.key(7), N))
    c, s = math.cos(theta), math.sin(theta)
    major = c * records[:, 0] + s * records[:, 1]
    minor = -s * records[:, 0] + c * records[:, 1]
    assert np.abs(major).max(axis=1).mean() == pytest.approx(PGA, rel=0.15)
    assert np.abs(minor).max(axis=1).mean() == pytest.approx(gamma * PGA, rel=0.15)


def test_major_component_is_the_one_component_sample():
    """Along x (theta = 0) the x component is `sample` with the same key, bit for bit (the
    one-component generator is untouched); with gamma = 0 the motion is that record along theta."""
    key = jax.random.key(11)
    one = np.asarray(sample(MODEL, key, 3))
    along_x = np.asarray(sample_two_components(TwoComponentGroundMotion(MODEL, minor_ratio=0.7), key, 3))
    np.testing.assert_array_equal(along_x[:, 0], one)
    assert np.abs(along_x[:, 1]).max() > 0.1 * PGA
    theta = 0.5
    line = np.asarray(sample_two_components(TwoComponentGroundMotion(MODEL, theta, 0.0), key, 3))
    np.testing.assert_allclose(line[:, 0], math.cos(theta) * one, rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(line[:, 1], math.sin(theta) * one, rtol=1e-14, atol=1e-14)


@pytest.mark.parametrize("kwargs, name", [({"minor_ratio": 1.5}, "minor_ratio"),
                                          ({"minor_ratio": -0.1}, "minor_ratio"),
                                          ({"principal_angle": float("nan")}, "principal_angle")])
def test_bad_input_is_refused_by_name(kwargs, name):
    with pytest.raises(ValueError, match=name):
        TwoComponentGroundMotion(MODEL, **kwargs)
    with pytest.raises(ValueError, match="model"):
        TwoComponentGroundMotion("clough-penzien")
