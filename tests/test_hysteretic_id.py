"""Generic Bouc-Wen oscillator (Noel & Schoukens 2016 benchmark): identification and prediction."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from identification.hysteretic import (
    BENCHMARK,
    fine_input,
    fit_hysteretic,
    simulate_hysteretic,
)

FS = 750.0
T = 10.0


def _sweep(t, amplitude=10.0, f0=5.0, f1=60.0):
    return amplitude * np.sin(2 * np.pi * (f0 * t + (f1 - f0) * t**2 / (2 * T)))


def _multisine(t):
    rng = np.random.default_rng(1)
    freqs = np.arange(5.0, 51.0)
    phases = rng.uniform(0.0, 2 * np.pi, freqs.size)
    return 12.0 / np.sqrt(freqs.size / 2) * np.sum(
        np.sin(2 * np.pi * np.multiply.outer(t, freqs) + phases), axis=-1)


def _independent(u_of_t, t):
    """The benchmark's equations by scipy DOP853 (rtol 1e-10), input continuous in time."""
    p = BENCHMARK

    def rhs(tt, s):
        y, v, z = s
        dz = p["alpha"] * v - p["beta_gamma"] * abs(v) * z - p["beta_delta"] * v * abs(z)
        return [v, (u_of_t(tt) - p["c"] * v - p["k"] * y - z) / p["m"], dz]

    sol = solve_ivp(rhs, (t[0], t[-1]), [0.0, 0.0, 0.0], t_eval=t, method="DOP853", rtol=1e-10,
                    atol=1e-13, max_step=1 / 3000)
    return sol.y[0]


def test_simulator_matches_independent_integration():
    t = np.arange(0.0, 2.0, 1 / FS)
    y_ref = _independent(_sweep, t)
    y = np.asarray(simulate_hysteretic(BENCHMARK, t, fine_input(t, _sweep(t), 4)))
    assert np.sqrt(np.mean((y - y_ref) ** 2) / np.mean(y_ref**2)) < 1e-3
    # the hysteresis matters: without it (beta = 0) the response differs by far more
    linear = dict(BENCHMARK, beta_gamma=0.0, beta_delta=0.0)
    y_lin = np.asarray(simulate_hysteretic(linear, t, fine_input(t, _sweep(t), 4)))
    assert np.sqrt(np.mean((y_lin - y_ref) ** 2) / np.mean(y_ref**2)) > 1e-2


@pytest.mark.slow
def test_benchmark_parameters_recovered_and_multisine_predicted():
    t = np.arange(0.0, T, 1 / FS)
    fit = fit_hysteretic(t, _sweep(t), _independent(_sweep, t))
    assert fit.converged, fit.message
    for name, value in fit.parameters.items():
        assert abs(value / BENCHMARK[name] - 1.0) < 0.01, (name, value)
    tv = np.arange(0.0, 4.0, 1 / FS)
    assert fit.validate(tv, _multisine(tv), _independent(_multisine, tv)) < 1e-2


def test_bad_records_are_refused():
    t = np.arange(0.0, 1.0, 1 / FS)
    with pytest.raises(ValueError, match="u: 10 samples"):
        fit_hysteretic(t, np.ones(10), np.ones(t.size))
    with pytest.raises(ValueError, match="need at least 120"):
        fit_hysteretic(t[:50], np.ones(50), np.ones(50))
    y = np.ones(t.size)
    y[3] = np.nan
    with pytest.raises(ValueError, match="y: sample 3 is not finite"):
        fit_hysteretic(t, np.ones(t.size), y)
    with pytest.raises(ValueError, match="no motion"):
        fit_hysteretic(t, np.ones(t.size), np.zeros(t.size))
