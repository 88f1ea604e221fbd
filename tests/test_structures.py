"""Model builders (rigid mass, Table 2 building) and batched sweeps: closed forms, limits,
energy balance, the paper's statements of Figs. 7-10, convergence and input checks."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg

import teflon_jax as tj
from teflon_jax.structures import signal_from_motion, superstructure_matrices
from teflon_jax.studies import (
    building_peaks,
    building_sweep,
    pad_signals,
    simulate_batch,
    stack_systems,
)
from teflon_jax.systems import (
    building_response_quantities,
    rigid_mass,
    six_storey_building,
)

G = tj.units.STANDARD_GRAVITY
PSI = tj.units.PSI


def _uf(pressure_psi):
    friction, _ = tj.friction_table("UF", "P").at(pressure_psi * PSI)
    return friction


def _sine_signal(amplitude, omega, duration, dt=5e-4):
    times = np.arange(0.0, duration + dt / 2, dt)
    return tj.Signal(jnp.asarray(times), jnp.asarray(amplitude * np.sin(omega * times)))


def test_rebuilt_building_has_table2_frequencies_and_damping():
    data = tj.load_table2()
    masses, stiffness, damping, modes = superstructure_matrices(data)
    omega2, shapes = scipy.linalg.eigh(stiffness, np.diag(masses))
    frequencies = np.sqrt(omega2) / (2 * np.pi)
    np.testing.assert_allclose(frequencies, data.frequencies, rtol=0.01)
    # Classical 2 % damping in every mode of the rebuilt frame.
    modal_c = shapes.T @ damping @ shapes
    np.testing.assert_allclose(np.diag(modal_c) / (2 * np.sqrt(omega2)), data.modal_damping, rtol=1e-6)
    # The orthogonalised shapes stay close to the published ones (least-squares scaled to them).
    scaled = modes * np.sum(modes * data.mode_shapes, axis=0) / np.sum(modes**2, axis=0)
    np.testing.assert_allclose(scaled, data.mode_shapes, atol=0.03)
    # Assembled system: base + six floors, total weight 672 kip on the bearings.
    system = six_storey_building(
        bearing=None, ground_acceleration=tj.as_signal(0.0, duration=1.0), time_step=0.01,
        isolation_period=2.0, friction_model="none",
    )
    assert system.mass.shape == (7,)
    np.testing.assert_allclose(float(jnp.sum(system.mass)) * G, data.total_weight, rtol=1e-12)
    np.testing.assert_allclose(float(system.mass[0]) * G, 42 * tj.units.KIP, rtol=1e-3)
    # Rigid-body mode: with K_s rigid the period is T_b.
    k_b = float(system.stiffness.sum())
    np.testing.assert_allclose(2 * np.pi * np.sqrt(float(system.mass.sum()) / k_b), 2.0, rtol=1e-9)


def test_rigid_mass_linear_spring_matches_harmonic_closed_form():
    period, amplitude, forcing = 1.0, 0.3 * G, 4.0  # [s], [m/s^2], [rad/s]
    omega = 2 * np.pi / period
    duration = 5.0
    system = rigid_mass(
        weight=1.0e5, bearing=None, ground_acceleration=_sine_signal(amplitude, forcing, duration),
        time_step=1e-3, isolation_period=period, friction_model="none",
    )
    response = tj.simulate_history(system, duration)
    t = np.asarray(response.time)
    exact = -amplitude / (omega**2 - forcing**2) * (np.sin(forcing * t) - forcing / omega * np.sin(omega * t))
    error = np.max(np.abs(np.asarray(response.displacement[:, 0]) - exact))
    assert error < 1e-3 * np.max(np.abs(exact))


def test_rigid_mass_coulomb_under_constant_acceleration_pulse():
    mu, a0, t1 = 0.1, 0.3 * G, 0.5  # slides while the pulse lasts, then decelerates at mu g
    times = jnp.array([0.0, t1, t1 + 1e-9, 3.0])
    signal = tj.Signal(times, jnp.array([a0, a0, 0.0, 0.0]))
    system = rigid_mass(
        weight=1.0e5, bearing=tj.paper_bearing(tj.coulomb_friction(mu)), ground_acceleration=signal,
        time_step=1e-3, friction_model="coulomb",
    )
    response = tj.simulate_history(system, 3.0)
    t, u = np.asarray(response.time), np.asarray(response.displacement[:, 0])
    sliding = (t > 0.01) & (t < t1 - 0.01)
    # Start-up error of the first Newmark step (its initial acceleration has Z = 0, i.e. no
    # friction): a velocity offset of at most mu g dt / 2, hence the absolute tolerance.
    startup = mu * G * 1e-3 / 2
    error = np.abs(u[sliding] + (a0 - mu * G) * t[sliding] ** 2 / 2)
    np.testing.assert_array_less(error, 1.01 * startup * t[sliding] + 1e-12)
    np.testing.assert_allclose(np.asarray(response.total_acceleration[sliding, 0]), mu * G, rtol=1e-6)
    v1 = (a0 - mu * G) * t1
    final = -(a0 - mu * G) * t1**2 / 2 - v1**2 / (2 * mu * G)
    # Besides the start-up offset, the trapezoidal load of the step where the pulse ends
    # carries a0 dt / 2 of spurious velocity; both persist until the mass sticks at t_stop.
    t_stop = t1 + v1 / (mu * G)
    assert abs(u[-1] - final) <= (mu * G + a0) * 1e-3 / 2 * t_stop
    assert abs(float(response.velocity[-1, 0])) < 1e-9  # stuck after t1 + v1 / (mu g)


@pytest.fixture(scope="module")
def elcentro(external_data):
    return tj.load_record("elcentro")


def test_building_energy_balance_over_el_centro(elcentro):
    bearing = tj.paper_bearing(_uf(1000), breakaway_ratio=4.0)
    system = six_storey_building(
        bearing=bearing, ground_acceleration=signal_from_motion(elcentro), time_step=0.005,
        isolation_period=2.0,
    )
    r = tj.simulate_history(system, 40.0)
    m, K, C = np.asarray(system.mass), np.asarray(system.stiffness), np.asarray(system.damping)
    u, v = np.asarray(r.displacement), np.asarray(r.velocity)
    du = np.diff(u, axis=0)
    load = -m[None, :] * np.asarray(r.ground[:, 0])[:, None]
    def work(force):  # trapezoidal work of a force history along the displacement increments
        return np.sum(0.5 * (force[1:] + force[:-1]) * du)
    friction = np.zeros_like(u)
    friction[:, 0] = np.asarray(r.friction_force)
    e_in = work(load)
    e_kin = 0.5 * np.sum(m * v[-1] ** 2)
    e_strain = 0.5 * u[-1] @ K @ u[-1]
    e_visc = work(v @ C.T)
    e_fric = work(friction)
    assert e_in > 0 and e_fric > 0.3 * e_in
    np.testing.assert_allclose(e_kin + e_strain + e_visc + e_fric, e_in, rtol=0.01)


def _peak_acceleration(friction, b, n_interfaces=1, duration=1.5):
    signal = _sine_signal(0.25 * G, 3.14, duration)
    bearing = tj.paper_bearing(friction, breakaway_ratio=b, n_interfaces=n_interfaces)
    system = rigid_mass(weight=1.0e5, bearing=bearing, ground_acceleration=signal, time_step=1e-3)
    r = tj.simulate_history(system, duration)
    mu_max = float(jnp.max(jnp.abs(r.friction_force))) / 1.0e5
    return float(jnp.max(jnp.abs(r.total_acceleration[:, 0]))), mu_max


@pytest.mark.slow
@pytest.mark.parametrize(
    "ptfe, pressure, n_interfaces",
    [("UF", 1000, 1), ("25GF", 6500, 1), ("UF", 1000, 24)],
)
def test_breakaway_raises_peak_only_above_experienced_ratio(ptfe, pressure, n_interfaces):
    friction, _ = tj.friction_table(ptfe, "P").at(pressure * PSI)
    base, mu_experienced = _peak_acceleration(friction, None, n_interfaces)
    threshold = mu_experienced / float(friction.f_min)  # Eq. 18 with the friction experienced
    for b in (2.0, 4.0, 6.0):
        peak, _ = _peak_acceleration(friction, b, n_interfaces)
        if b < 0.95 * threshold:
            assert peak == pytest.approx(base, rel=0.02), (b, threshold)
        elif b > 1.05 * threshold:
            assert peak > 1.05 * base, (b, threshold)
            assert peak == pytest.approx(b * float(friction.f_min) * G, rel=0.02)


@pytest.mark.slow
def test_coulomb_max_approximates_full_model_coulomb_min_overestimates(elcentro):
    friction = _uf(1000)
    signal = signal_from_motion(elcentro)

    def peak(bearing, model):
        system = rigid_mass(
            weight=1.0e6, bearing=bearing, ground_acceleration=signal, time_step=0.005, friction_model=model
        )
        return float(jnp.max(jnp.abs(tj.simulate_history(system, 10.0).displacement)))

    exact = peak(tj.paper_bearing(friction), "hysteretic")
    coulomb_max = peak(tj.paper_bearing(tj.coulomb_friction(friction.f_max)), "coulomb")
    coulomb_min = peak(tj.paper_bearing(tj.coulomb_friction(friction.f_min)), "coulomb")
    assert coulomb_max == pytest.approx(exact, rel=0.1)
    assert coulomb_min > 2 * exact


@pytest.mark.slow
def test_sct_building_converged_at_recommended_step(external_data):
    sct = signal_from_motion(tj.load_record("sct"))
    bearing = tj.paper_bearing(_uf(1000), breakaway_ratio=4.0)

    def peaks(dt):
        system = six_storey_building(
            bearing=bearing, ground_acceleration=sct, time_step=dt, isolation_period=2.0
        )
        q = building_response_quantities(system, tj.simulate_history(system, 50.0))
        return float(jnp.max(jnp.abs(q["base_displacement"]))), float(jnp.max(jnp.abs(q["base_shear_ratio"])))

    coarse, fine = peaks(0.005), peaks(0.00125)
    np.testing.assert_allclose(coarse, fine, rtol=0.005)


@pytest.mark.slow
def test_sct_rigid_mass_converged_at_recommended_step(external_data):
    sct = signal_from_motion(tj.load_record("sct"))
    bearing = tj.paper_bearing(_uf(1000))

    def peak(dt):
        system = rigid_mass(
            weight=1.0e6, bearing=bearing, ground_acceleration=sct, time_step=dt, isolation_period=2.0,
            damping_ratio=0.05,
        )
        return float(jnp.max(jnp.abs(tj.simulate_history(system, 50.0).displacement)))

    np.testing.assert_allclose(peak(0.005), peak(0.0025), rtol=0.005)


@pytest.mark.slow
def test_batch_equals_separate_calls_and_padding_is_masked():
    # Two records of unequal length; the short one is padded with zeros to the long one.
    long = _sine_signal(0.3 * G, 2 * np.pi, 3.0, dt=0.01)
    short = _sine_signal(-0.2 * G, 5.0, 2.0, dt=0.02)
    periods = np.array([1.0, 2.5])
    sweep = building_sweep(records={"long": long, "short": short}, periods=periods, pressures=[1000 * PSI],
                           time_step=0.01)
    assert sweep.systems == ("sliding_1000psi", "linear")
    assert sweep.peaks["base_disp"].shape == (2, 2, 2) and sweep.succeeded.all()
    for i, (signal, duration) in enumerate(((long, 3.0), (short, 2.0))):
        for k, period in enumerate(periods):
            system = six_storey_building(
                bearing=tj.paper_bearing(_uf(1000), breakaway_ratio=4.0), ground_acceleration=signal,
                time_step=0.01, isolation_period=period,
            )
            alone = building_peaks(system, duration, duration)
            for name in ("base_disp", "base_shear_ratio"):
                np.testing.assert_allclose(sweep.peaks[name][i, 0, k], float(alone[name]), rtol=1e-9)
    # simulate_batch on stacked systems equals the separate simulations.
    systems = [
        rigid_mass(weight=1e5, bearing=tj.paper_bearing(_uf(p)), ground_acceleration=long, time_step=0.01)
        for p in (1000, 3000)
    ]
    batch = simulate_batch(stack_systems(systems), 3.0)
    for j, system in enumerate(systems):
        alone = tj.simulate_history(system, 3.0)
        np.testing.assert_allclose(batch.displacement[j], alone.displacement, rtol=1e-9, atol=1e-12)
    padded, own = pad_signals([long, short])
    np.testing.assert_allclose(own, [3.0, 2.0])
    assert float(padded.values[1, -1]) == 0.0 and float(padded.times[1, -1]) >= 3.0


def test_bad_input_raises_clear_value_errors():
    bearing = tj.paper_bearing(_uf(1000))
    signal = tj.as_signal(0.0, duration=1.0)
    with pytest.raises(ValueError, match="isolation_period"):
        rigid_mass(weight=1.0, bearing=bearing, ground_acceleration=signal, time_step=0.01, isolation_period=0.0)
    with pytest.raises(ValueError, match="isolation_period"):
        six_storey_building(bearing=bearing, ground_acceleration=signal, time_step=0.01, isolation_period=-1.0)
    with pytest.raises(ValueError, match="weight"):
        rigid_mass(weight=0.0, bearing=bearing, ground_acceleration=signal, time_step=0.01)
    with pytest.raises(ValueError, match="friction_model"):
        rigid_mass(weight=1.0, bearing=bearing, ground_acceleration=signal, time_step=0.01, friction_model="viscous")
    with pytest.raises(ValueError, match="friction_model"):
        six_storey_building(bearing=bearing, ground_acceleration=signal, time_step=0.01, isolation_period=2.0,
                            friction_model="elastic")
    with pytest.raises(ValueError, match="damping_ratio"):
        rigid_mass(weight=1.0, bearing=bearing, ground_acceleration=signal, time_step=0.01, damping_ratio=0.05)
    with pytest.raises(ValueError, match="radius"):
        rigid_mass(weight=1.0, bearing=bearing, ground_acceleration=signal, time_step=0.01, radius=0.0)
    with pytest.raises(ValueError, match="pressures"):
        building_sweep(records={"x": signal}, periods=[1.0], pressures=[500 * PSI])
    with pytest.raises(ValueError, match="periods"):
        building_sweep(records={"x": signal}, periods=[0.0])


@pytest.mark.slow
def test_builders_are_differentiable_in_isolation_period():
    signal = _sine_signal(0.3 * G, 2 * np.pi, 2.0, dt=0.01)

    def peak(period):
        system = rigid_mass(weight=1e5, bearing=None, ground_acceleration=signal, time_step=0.01,
                            isolation_period=period, damping_ratio=0.05, friction_model="none")
        return jnp.max(jnp.abs(tj.simulate_history(system, 2.0).displacement))

    grad = jax.grad(peak)(1.5)
    step = 1e-5
    fd = (peak(1.5 + step) - peak(1.5 - step)) / (2 * step)
    np.testing.assert_allclose(grad, fd, rtol=1e-4)
