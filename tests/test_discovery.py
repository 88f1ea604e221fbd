"""Model discovery: hidden effects in synthetic records are found, named and removed.

The synthetic records come from an independent numpy generator written here (Bouc-Wen by
RK4 sub-steps with the analytic velocity of the protocol, heating by the direct O(n^2) Duhamel
sum of the 1/sqrt(t) kernel), not from the augmented simulator under test.
"""

import json
import math

import numpy as np
import pytest

from identification._augmented import active_mask, prepare_record, simulate_augmented
from identification._diagnostics import half_cycle_index, locate_residual
from identification._discovery import confidence_wording, discover_effects, effective_samples
from identification._effects import (
    AMBIENT_TEMPERATURE,
    EFFECTS,
    heat_kernel_exponentials,
    kumar_temperature_factor,
    surface_temperature_coefficient,
)
from teflon_jax._records import test_record_from_arrays
from teflon_jax._units import INCH, KIP, PSI

UF_1000_P = dict(f_max=0.1193, delta_f=0.0927, rate_a=0.60 / INCH)  # Table 1
UF_1000_T = dict(f_max=0.1420, delta_f=0.1181, rate_a=0.45 / INCH)  # Table 1, test No. 191


def generate_record(
    *,
    amplitude=1.0 * INCH,
    frequency=0.16,
    cycles=3,
    samples_per_cycle=400,
    friction=UF_1000_P,
    yield_disp=0.005 * INCH,
    normal_load=78.5 * KIP,
    contact_area=78.5 * INCH**2,
    load_variation=0.0,
    breakaway_ratio=None,
    pressure_exponent=0.0,
    heat_scale=0.0,
    asymmetry=0.0,
    wear_change=0.0,
    n_interfaces=1.0,
    noise=0.015,
    seed=0,
    substeps=20,
):
    """A sine test with hidden effects; force noise = `noise` x RMS force (white, Gaussian)."""
    w = 2 * math.pi * frequency
    n = int(cycles * samples_per_cycle) + 1
    t = np.linspace(0.0, cycles / frequency, n)
    ux = amplitude * np.sin(w * t)
    v = amplitude * w * np.cos(w * t)
    load = normal_load * (1 + load_variation * np.sin(2 * math.pi * 0.37 * frequency * t + 0.3))

    def zdot(z, vel):  # Bouc-Wen, A = 1, beta = 0.1, gamma = 0.9, eta = 2
        return (vel - 0.9 * abs(vel) * z * abs(z) - 0.1 * vel * z * z) / yield_disp

    z = np.zeros(n)
    z_peak = np.zeros(n)
    zi, peak = 0.0, 0.0
    for i in range(1, n):
        h = (t[i] - t[i - 1]) / substeps
        for k in range(substeps):
            s = t[i - 1] + k * h
            v0, v1, v2 = (amplitude * w * math.cos(w * x) for x in (s, s + h / 2, s + h))
            k1 = zdot(zi, v0)
            k2 = zdot(zi + h / 2 * k1, v1)
            k3 = zdot(zi + h / 2 * k2, v1)
            k4 = zdot(zi + h * k3, v2)
            zi += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            peak = max(peak, abs(zi))
        z[i], z_peak[i] = zi, peak

    f = friction
    mu_v = f["f_max"] - f["delta_f"] * np.exp(-f["rate_a"] * np.abs(v) / n_interfaces)
    if breakaway_ratio is not None:
        mu_v = np.where(z_peak < 0.999, breakaway_ratio * (f["f_max"] - f["delta_f"]), mu_v)
    travel = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(ux)))])
    factor = (
        (load / np.mean(load)) ** (-pressure_exponent)
        * (1 + asymmetry * np.sign(v))
        * (1 + wear_change * travel / travel[-1])
    )
    mu = mu_v * factor
    if heat_scale:
        coef = heat_scale * surface_temperature_coefficient()
        pressure = load / contact_area
        mu = mu.copy()
        flux = np.zeros(n)
        for i in range(1, n):
            # Duhamel sum with piecewise-constant flux: int (t_i - s)^-1/2 ds exactly.
            upper = np.sqrt(t[i] - t[:i])
            lower = np.sqrt(np.maximum(t[i] - t[1 : i + 1], 0.0))
            rise = coef * np.sum(flux[:i] * 2 * (upper - lower))
            mu[i] = mu[i] * kumar_temperature_factor(AMBIENT_TEMPERATURE + rise) / (
                kumar_temperature_factor(AMBIENT_TEMPERATURE)
            )
            flux[i] = mu[i] * pressure[i] * abs(v[i])
    force = mu * load * z
    rng = np.random.default_rng(seed)
    force = force + noise * np.sqrt(np.mean(force**2)) * rng.standard_normal(n)
    return test_record_from_arrays(
        ux, force, time=t, normal_load=load, metadata={"contact_area": contact_area}
    )


# ---------------------------------------------------------------------------------- pieces


def test_heat_kernel_matches_inverse_sqrt():
    rates, weights = heat_kernel_exponentials(1e-3, 100.0)
    t = np.geomspace(1e-3, 100.0, 200)
    approx = (weights[None, :] * np.exp(-rates[None, :] * t[:, None])).sum(axis=1)
    assert np.max(np.abs(approx * np.sqrt(t) - 1.0)) < 2e-3


def test_constant_flux_temperature_matches_carslaw_jaeger():
    # Semi-infinite body, constant surface flux q0: dT = 2 q0 sqrt(kappa t / pi) / k.
    t = np.linspace(0.0, 10.0, 2001)
    speed = 0.1
    record = test_record_from_arrays(
        speed * t, np.ones_like(t), time=t, normal_load=1.0e5, metadata={"contact_area": 0.01}
    )
    data, _ = prepare_record(record)
    params = {p: v for p, v in _defaults().items()}
    params.update(f_max=0.1, yield_disp=1e-6, heat_scale=1.0)
    out = simulate_augmented(params, data, active_mask(()))
    q0 = 0.1 * 1.0e5 / 0.01 * speed
    from identification._effects import STEEL_CONDUCTIVITY, STEEL_DIFFUSIVITY

    exact = 2 * q0 * np.sqrt(STEEL_DIFFUSIVITY * t / np.pi) / STEEL_CONDUCTIVITY
    got = np.asarray(out["heat_index"])
    assert np.max(np.abs(got[200:] - exact[200:])) < 2e-3 * exact[-1]


def _defaults():
    from identification._augmented import default_parameters

    return default_parameters()


def test_augmented_baseline_matches_core_simulator():
    import jax.numpy as jnp

    from teflon_jax import FrictionParameters, paper_bearing, simulate_bearing_test, tabulated_motion

    record = generate_record(noise=0.0, cycles=1, samples_per_cycle=300)
    fp = FrictionParameters(**{k: jnp.asarray(v) for k, v in UF_1000_P.items()})
    bearing = paper_bearing(fp, breakaway_ratio=2.5)
    motion = tabulated_motion(jnp.asarray(record.time), jnp.asarray(record.ux))
    core = simulate_bearing_test(bearing, motion, float(record.normal_load[0]))
    data, _ = prepare_record(record)
    params = _defaults()
    params.update(UF_1000_P, yield_disp=0.005 * INCH, breakaway_ratio=2.5)
    ours = simulate_augmented(params, data, active_mask(("velocity_dependence", "breakaway")))
    # Same Z update; velocities differ (central differences vs the table's), so compare loosely.
    scale = float(np.max(np.abs(core.fx)))
    assert np.max(np.abs(np.asarray(ours["force"]) - np.asarray(core.fx))) < 0.02 * scale
    np.testing.assert_allclose(np.asarray(ours["z"]), np.asarray(core.z[:, 0]), atol=1e-9)


def test_half_cycles_and_effective_samples():
    t = np.linspace(0, 3, 3001)
    ux = np.sin(2 * np.pi * t) + 0.01 * np.random.default_rng(1).standard_normal(t.size)
    hc = half_cycle_index(ux)
    assert hc.max() == 5  # 3 cycles starting at 0 towards +x: 6 strokes
    white = np.random.default_rng(2).standard_normal(5000)
    assert effective_samples(white) > 4500
    smooth = np.sin(np.linspace(0, 20, 5000))
    assert effective_samples(smooth) < 50


def test_confidence_scale():
    assert confidence_wording(1.0).startswith("not worth")
    assert confidence_wording(4.0) == "positive"
    assert confidence_wording(8.0) == "strong"
    assert confidence_wording(25.0) == "very strong"


def test_bad_inputs_raise():
    record = generate_record(cycles=1, samples_per_cycle=100)
    with pytest.raises(ValueError, match="baseline"):
        discover_effects(record, baseline="nonsense")
    with pytest.raises(ValueError, match="candidates"):
        discover_effects(record, candidates=["friction_magic"])
    no_load = test_record_from_arrays(record.ux, record.fx, time=record.time)
    with pytest.raises(ValueError, match="normal load"):
        prepare_record(no_load)


# ------------------------------------------------------------------------------ discovery


HIDDEN = {
    "asymmetry": dict(asymmetry=0.12),
    "wear": dict(wear_change=-0.35),
    "pressure_dependence": dict(load_variation=0.3, pressure_exponent=0.5),
    "breakaway": dict(breakaway_ratio=2.5),
    "heating": dict(amplitude=4 * INCH, frequency=0.6, heat_scale=1.0),
}


def _check_first(effect, seed=0):
    record = generate_record(seed=seed, **HIDDEN[effect])
    result = discover_effects(record)
    assert result.effects_added, f"nothing found; {result.final_round}"
    assert result.effects_added[0] == effect, result.to_json()["steps"][0]["candidates"]
    assert result.nrmse_final <= 0.5 * result.nrmse_initial
    return result


@pytest.mark.parametrize("effect", ["asymmetry", "wear", "pressure_dependence"])
def test_hidden_effect_is_named_first(effect):
    _check_first(effect)


@pytest.mark.slow
@pytest.mark.parametrize("effect", ["breakaway", "heating"])
def test_hidden_effect_is_named_first_slow(effect):
    _check_first(effect)
