"""The effect library of model discovery: each effect's law, and each hidden effect found.

Laws are checked against independent peers (teflon_jax's anisotropic Eq. 1, the exact
Bouc-Wen update, finite differences); hidden effects come from the numpy generators of
`test_discovery` (RK4 in time, not the augmented simulator). "The noise level" of a record is
the nrmse of the same record simulated with the true model: the generator without noise.
"""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from test_discovery import UF_1000_P, UF_1000_T, generate_record

from identification.discovery import (
    EFFECTS,
    active_mask,
    default_parameters,
    discover_effects,
    prepare_record,
    simulate_augmented,
    stack_check,
)
from teflon_jax import BoucWen, bouc_wen_exact_update
from teflon_jax.bearing import backlash_update, kumar_temperature_factor
from teflon_jax.formats import test_record_from_arrays
from teflon_jax.units import INCH


def true_model_nrmse(record, **hidden):
    """nrmse of the noise-free record (the true model) against the noisy one."""
    exact = generate_record(noise=0.0, **hidden)
    scale = np.sqrt(np.mean(record.fx**2))
    return float(np.sqrt(np.mean((exact.fx - record.fx) ** 2)) / scale)


def simulate(record, effects, **values):
    data, _ = prepare_record(record)
    params = default_parameters()
    params.update(UF_1000_P, yield_disp=0.005 * INCH)
    params.update(values)
    out = simulate_augmented(params, data, active_mask(effects))
    return data, {k: np.asarray(v) for k, v in out.items()}


# ------------------------------------------------------------------------------ anisotropy


def test_anisotropy_interpolates_all_three_constants_as_the_simulator():
    from teflon_jax import FrictionParameters
    from teflon_jax.bearing import anisotropic_friction, sliding_friction

    t = np.linspace(0.0, 2 * math.pi, 400)
    ux, uy = INCH * np.sin(t), INCH * np.sin(2 * t)
    record = test_record_from_arrays(
        ux, 1e3 * np.cos(t), time=t, uy=uy, fy=1e3 * np.cos(2 * t), normal_load=3.5e5
    )
    perpendicular = {f"{k}_perpendicular": v for k, v in UF_1000_T.items()}
    data, sim = simulate(record, ("velocity_dependence", "anisotropy"), **perpendicular)
    weight = np.asarray(data.angle_weight)
    speed = np.hypot(np.asarray(data.velocity), np.asarray(data.velocity_y))
    mixed = anisotropic_friction(
        FrictionParameters(**UF_1000_P), FrictionParameters(**UF_1000_T), weight
    )
    expected = np.asarray(sliding_friction(mixed, speed))
    np.testing.assert_allclose(sim["coefficient"], expected, rtol=1e-12)
    # T = P switches the effect off exactly (the neutral start of a fit)
    neutral = {f"{k}_perpendicular": v for k, v in UF_1000_P.items()}
    _, off = simulate(record, ("velocity_dependence",))
    _, same = simulate(record, ("velocity_dependence", "anisotropy"), **neutral)
    np.testing.assert_allclose(same["force"], off["force"], rtol=1e-12)
    assert {p.name for p in EFFECTS["anisotropy"].parameters} == set(perpendicular)


def noisy_figure_eight(amplitude, frequency, cycles, noise=0.01, seed=0):
    """An anisotropic figure-eight test (Eq. 16, UF at 1000 psi, P along x and T along y) from
    teflon_jax's simulator, with white Gaussian noise of `noise` x RMS force on fx and fy.

    **Returns:** (record, true-model nrmse, {P and T constants})."""
    import teflon_jax as tj
    from teflon_jax.units import PSI

    parallel, _ = tj.interface_parameters("UF", 1000 * PSI, "P")
    perpendicular, _ = tj.interface_parameters("UF", 1000 * PSI, "T")
    bearing = tj.paper_bearing(
        parallel, yield_disp=0.005 * INCH, friction_perpendicular=perpendicular
    )
    load = 78.5e3 * PSI * INCH**2
    motion = tj.FigureEightMotion(amplitude, frequency, cycles=cycles)
    run = tj.imposed_path_test(bearing, motion, load)
    fx, fy = np.asarray(run.fx), np.asarray(run.fy)
    rms = np.sqrt(np.mean(np.concatenate([fx, fy]) ** 2))
    nx, ny = noise * rms * np.random.default_rng(seed).standard_normal((2, fx.size))
    record = test_record_from_arrays(
        np.asarray(run.ux), fx + nx, time=np.asarray(run.time), uy=np.asarray(run.uy),
        fy=fy + ny, normal_load=load,
    )
    measured = np.concatenate([record.fx, record.fy])
    true_nrmse = np.sqrt(np.mean(np.concatenate([nx, ny]) ** 2) / np.mean(measured**2))
    truth = {}
    for suffix, constants in (("", parallel), ("_perpendicular", perpendicular)):
        for name in ("f_max", "delta_f", "rate_a"):
            truth[name + suffix] = float(getattr(constants, name))
    return record, float(true_nrmse), truth


@pytest.mark.slow
@pytest.mark.parametrize(
    "protocol, identifiable",
    [
        # Fig. 5 (U0 = 1 in, w = 1 rad/s): speeds 0.7-2.2 in/s, all six constants show
        ((1 * INCH, 1.0, 4), ("f_max", "delta_f", "rate_a")),
        # the tour's Fig. 6 test (4 in, 2.77 rad/s): above 7 in/s exp(-a v) < 1 %, so only f_max
        ((4 * INCH, 2.77, 1), ("f_max",)),
    ],
)
def test_hidden_anisotropy_in_a_figure_eight_reaches_the_noise_level(protocol, identifiable):
    # The interpolation of all three constants takes nrmse to within 20 % of
    # the true model's, and recovers the P and T constants within 5 %.
    record, true_nrmse, truth = noisy_figure_eight(*protocol, seed=1)
    result = discover_effects(record)
    assert result.effects_added[:1] == ["anisotropy"], result.to_json()["steps"]
    assert result.nrmse_final <= 1.2 * true_nrmse
    for name in identifiable:
        for key in (name, name + "_perpendicular"):
            assert result.parameters[key] == pytest.approx(truth[key], rel=0.05), key


# ------------------------------------------------------------------------------- asymmetry


def test_asymmetry_has_no_force_step_at_reversals():
    record = generate_record(noise=0.0, cycles=2, samples_per_cycle=800)
    asym = 0.2
    data, sim = simulate(record, ("velocity_dependence", "asymmetry"), asymmetry=asym)
    force, z = sim["force"], sim["z"]
    mu_n = np.asarray(data.normal) * sim["coefficient"]
    # while |Z| stays near 1 on both sides of a sample step the force changes smoothly: far less
    # than the 2 asymmetry mu N step of a factor that follows sign(v)
    both = (np.abs(z[1:]) > 0.99) & (np.abs(z[:-1]) > 0.99)
    step = np.abs(np.diff(force))[both] / mu_n[1:][both]
    assert step.max() < 0.1 * 2 * asym
    # there are reversals in that set: samples where the velocity changes sign with |Z| > 0.99
    v = np.asarray(data.velocity)
    flips = (np.sign(v[1:]) != np.sign(v[:-1])) & both
    assert flips.sum() >= 3
    # and while sliding the law is (1 + a) in +x and (1 - a) in -x
    _, base = simulate(record, ("velocity_dependence",))
    ratio = force / np.where(np.abs(base["force"]) > 0, base["force"], 1.0)
    sliding = np.abs(z) > 0.999
    np.testing.assert_allclose(ratio[sliding], 1 + asym * z[sliding], rtol=1e-9)


@pytest.mark.slow
def test_hidden_asymmetry_gap_closes_to_the_noise_level():
    hidden = {"asymmetry": 0.12, "seed": 4}
    record = generate_record(**hidden)
    result = discover_effects(record, candidates=["asymmetry", "wear", "backlash"])
    assert result.effects_added[:1] == ["asymmetry"], result.to_json()["steps"]
    assert result.nrmse_final <= 1.2 * true_model_nrmse(record, **hidden)
    assert result.parameters["asymmetry"] == pytest.approx(0.12, abs=0.01)


# --------------------------------------------------------------------------------- heating


def chamber(t_end):
    """A temperature that rises and falls again (an environmental chamber) [degC]."""
    return lambda t: 20.0 + 50.0 * math.sin(math.pi * t / t_end) ** 2


def test_heating_uses_the_measured_temperature_column():
    record = generate_record(noise=0.0, temperature=chamber(18.75), temperature_scale=1.0)
    data, sim = simulate(record, ("velocity_dependence", "heating"), heat_scale=1.0)
    assert data.measured_temperature
    temp = np.asarray(record.temperature)
    np.testing.assert_allclose(sim["temperature_rise"], temp - temp[0], atol=1e-12)
    _, cold = simulate(record, ("velocity_dependence",))
    expected = kumar_temperature_factor(temp) / kumar_temperature_factor(temp[0])
    np.testing.assert_allclose(sim["force"], cold["force"] * expected, rtol=1e-9, atol=1e-9)


def test_hidden_measured_heating_is_named_and_its_gap_closes():
    hidden = {"temperature": chamber(18.75), "temperature_scale": 1.0, "seed": 6}
    record = generate_record(**hidden)
    result = discover_effects(record, candidates=["heating", "wear", "asymmetry"])
    assert result.effects_added[:1] == ["heating"], result.to_json()["steps"]
    assert result.nrmse_final <= 1.2 * true_model_nrmse(record, **hidden)
    assert result.parameters["heat_scale"] == pytest.approx(1.0, rel=0.1)


@pytest.mark.slow
def test_measured_temperature_without_effect_adds_nothing():
    record = generate_record(temperature=chamber(18.75), temperature_scale=0.0, seed=9)
    result = discover_effects(record)
    assert result.effects_added == [], result.to_json()["steps"]


# ---------------------------------------------------------------------------------- stacks


def test_stack_count_and_rate_are_not_separable_at_any_speed():
    # Three amplitudes and frequencies in one record: still only rate_a / n enters Eq. 1, so
    # d F / d ln(rate_a) = -d F / d ln(n) at every sample.
    parts = [
        generate_record(
            amplitude=a * INCH, frequency=f, cycles=1, samples_per_cycle=200, noise=0.0
        )
        for a, f in ((0.5, 0.05), (2.0, 0.3), (4.0, 0.8))
    ]
    offset = np.cumsum([0.0] + [p.time[-1] + p.time[1] for p in parts[:-1]])
    record = test_record_from_arrays(
        np.concatenate([p.ux for p in parts]),
        np.concatenate([p.fx for p in parts]),
        time=np.concatenate([p.time + o for p, o in zip(parts, offset)]),
        normal_load=float(parts[0].normal_load[0]),
    )
    data, _ = prepare_record(record)
    base = default_parameters()
    base.update(UF_1000_P, yield_disp=0.005 * INCH, n_interfaces=24.0)
    active = active_mask(("velocity_dependence", "interfaces"))

    def force(log_rate, log_n):
        params = dict(base, rate_a=jnp.exp(log_rate), n_interfaces=jnp.exp(log_n))
        return simulate_augmented(params, data, active)["force"]

    args = (jnp.log(base["rate_a"]), jnp.log(24.0))
    d_rate, d_n = jax.jacfwd(force, argnums=(0, 1))(*args)
    assert float(jnp.max(jnp.abs(d_rate))) > 0.01 * float(jnp.max(jnp.abs(force(*args))))
    np.testing.assert_allclose(np.asarray(d_rate), -np.asarray(d_n), atol=1e-9)


def test_stack_check_brackets_the_count():
    single = stack_check(UF_1000_P["rate_a"])
    assert single["consistent_with_stated"] and single["n_low"] < 1 < single["n_high"]
    stack = stack_check(UF_1000_P["rate_a"] / 24)
    assert stack["n_low"] < 24 < stack["n_high"] and not stack["consistent_with_stated"]
    stated = stack_check(UF_1000_P["rate_a"], series=24)
    assert stated["consistent_with_stated"]


# -------------------------------------------------------------------------------- backlash


def test_backlash_update_holds_zero_force_over_the_gap():
    h = BoucWen(yield_disp=jnp.asarray(0.005 * INCH))
    gap = 0.1 * INCH
    step = 0.001 * INCH
    z, s = jnp.asarray(1.0), jnp.asarray(0.5 * gap)  # sliding in +x, gap closed on +x

    def back(carry, _):
        z, s = backlash_update(h, *carry, -step, gap)
        return (z, s), z

    _, path = jax.lax.scan(back, (z, s), None, length=300)  # 0.3 in back towards -x
    path = np.asarray(path)
    travel = step * np.arange(1, path.size + 1)
    zero = np.abs(path) < 1e-12
    # Z = 0 over a travel of g, after unloading along Bouc-Wen, then loads towards -1
    unload = float(bouc_wen_reversal_length_m(h))
    assert travel[zero].min() == pytest.approx(unload, abs=step)
    assert travel[zero].max() - travel[zero].min() == pytest.approx(gap, abs=2 * step)
    assert path[-1] < -0.99
    # g = 0 is the exact Bouc-Wen update
    z0 = jnp.asarray(0.7)
    for du in (-3e-4, -1e-5, 2e-4):
        plain = bouc_wen_exact_update(h, z0, du)
        np.testing.assert_allclose(backlash_update(h, z0, 0.0, du, 0.0)[0], plain, rtol=1e-14)
    # Z after a reversal is differentiable in g (finite differences)
    def z_end(g):
        z, s = jnp.asarray(1.0), 0.5 * g
        for du in (-0.04 * INCH, -0.04 * INCH, -0.04 * INCH):
            z, s = backlash_update(h, z, s, du, g)
        return z

    g0 = 0.08 * INCH
    fd = (z_end(g0 + 1e-7) - z_end(g0 - 1e-7)) / 2e-7
    np.testing.assert_allclose(jax.grad(z_end)(g0), fd, rtol=1e-5)
    assert abs(float(fd)) > 0


def bouc_wen_reversal_length_m(h):
    from teflon_jax import bouc_wen_reversal_length

    return bouc_wen_reversal_length(h, 1.0) * h.yield_disp


@pytest.mark.slow
def test_hidden_backlash_is_named_and_its_gap_closes():
    hidden = {"backlash_gap": 0.05 * INCH, "seed": 3}
    record = generate_record(**hidden)
    result = discover_effects(record, candidates=["backlash", "asymmetry", "breakaway"])
    assert result.effects_added[:1] == ["backlash"], result.to_json()["steps"]
    assert result.nrmse_final <= 1.2 * true_model_nrmse(record, **hidden)
    assert result.parameters["backlash_gap"] == pytest.approx(0.05 * INCH, rel=0.1)
