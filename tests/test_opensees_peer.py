"""The OpenSees peer models (benchmarks/_opensees_models.py) against closed forms.

These prove that the independent OpenSees models are set up right (units of the rate
parameter, signs, the normal load, the spring/dashpot assembly) before the benchmarks and
cross-checks compare them with teflon-jax. Skipped when openseespy cannot be imported.
"""

import importlib.util
import pathlib

import numpy as np
import pytest

from teflon_jax.units import INCH, STANDARD_GRAVITY

_PATH = pathlib.Path(__file__).resolve().parents[1] / "benchmarks" / "_opensees_models.py"
_spec = importlib.util.spec_from_file_location("_opensees_models", _PATH)
om = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(om)

try:
    om.import_opensees()
except ImportError as error:
    pytest.skip(f"openseespy is not importable: {error}", allow_module_level=True)

G = STANDARD_GRAVITY
WEIGHT = 1.0e5  # [N]
MASS = WEIGHT / G
Y = 0.005 * INCH


def test_constant_friction_step_acceleration_closed_form():
    # Constant ground acceleration A > mu g: after a brief elastic stick phase the mass
    # slides with total acceleration +mu g, so the relative velocity is -(A - mu g) t.
    mu, amp, dt = 0.1, 0.5 * G, 1.0e-3
    acc = np.full(1001, amp)
    out = om.rigid_mass_on_slider(
        acc, dt, weight=WEIGHT, f_max=mu, delta_f=0.0, rate_a=0.0, yield_disp=Y
    )
    assert out["n_failed"] == 0
    t = out["time"]
    sliding = t > 0.05
    # rtol 1e-6: the iterations stop at a displacement increment of 1e-6 Y.
    np.testing.assert_allclose(out["total_acceleration"][sliding], mu * G, rtol=1e-6)
    np.testing.assert_allclose(out["friction_force"][sliding], -mu * WEIGHT, rtol=1e-6)
    slope = np.diff(out["velocity"][sliding]) / dt
    np.testing.assert_allclose(slope, -(amp - mu * G), rtol=1e-7)
    # Displacement: the stick phase (a few ms) only delays the closed form slightly.
    closed = -0.5 * (amp - mu * G) * t[-1] ** 2
    assert abs(out["displacement"][-1] - closed) < 0.01 * abs(closed)


def test_velocity_dependent_friction_follows_eq1_in_si_units():
    # Sinusoidal ground acceleration well above the friction level: while sliding, the
    # bearing force is mu(v) W with mu(v) = f_max - delta_f exp(-a |v|), a in s/m, and it
    # opposes the sliding velocity; the mass obeys m a_tot = -F.
    f_max, delta_f, rate_a = 0.1193, 0.0927, 0.60 / INCH
    dt = 2.0e-3
    t = np.arange(0.0, 4.0, dt)
    acc = 0.5 * G * np.sin(2 * np.pi * 1.0 * t)
    out = om.rigid_mass_on_slider(
        acc, dt, weight=WEIGHT, f_max=f_max, delta_f=delta_f, rate_a=rate_a, yield_disp=Y
    )
    assert out["n_failed"] == 0
    v, force = out["velocity"], out["friction_force"]
    sliding = np.abs(v) > 0.05
    assert sliding.mean() > 0.5
    # The force never exceeds Eq. 1 and equals it except in the short elastic transitions
    # that follow each reversal of the sliding direction.
    mu_eq1 = f_max - delta_f * np.exp(-rate_a * np.abs(v))
    assert np.all(np.abs(force) / WEIGHT <= mu_eq1 * (1 + 1e-9))
    on_law = np.isclose(np.abs(force) / WEIGHT, mu_eq1, rtol=1e-9, atol=0.0) & sliding
    assert on_law.sum() > 0.95 * sliding.sum()
    assert np.all(np.sign(force[on_law]) == np.sign(v[on_law]))
    np.testing.assert_allclose(MASS * out["total_acceleration"], -force, atol=1e-6 * WEIGHT)
    # Both ends of the friction law are reached: slow sliding near f_min, fast near f_max.
    assert np.abs(force).max() / WEIGHT > f_max - 0.01


def test_linear_sdof_matches_harmonic_solution():
    # Negligible friction (1e-9) plus spring and dashpot: a linear SDOF from rest under
    # a_g = A sin(W t); closed form = steady state + free vibration from rest.
    omega, zeta, big_omega, amp = 2 * np.pi, 0.05, 2 * np.pi * 0.7, 0.2 * G
    dt = 1.0e-3
    t = np.arange(0.0, 5.0, dt)
    out = om.rigid_mass_on_slider(
        amp * np.sin(big_omega * t),
        dt,
        weight=WEIGHT,
        f_max=1e-9,
        delta_f=0.0,
        rate_a=0.0,
        yield_disp=Y,
        spring_stiffness=MASS * omega**2,
        damping_ratio=zeta,
    )
    # u'' + 2 zeta omega u' + omega^2 u = -A sin(W t)
    h = -amp / (omega**2 - big_omega**2 + 2j * zeta * omega * big_omega)
    u_p = np.imag(h * np.exp(1j * big_omega * t))
    c1 = -np.imag(h)
    du_p0 = np.imag(1j * big_omega * h)
    omega_d = omega * np.sqrt(1 - zeta**2)
    c2 = (-du_p0 + zeta * omega * c1) / omega_d
    u = u_p + np.exp(-zeta * omega * t) * (
        c1 * np.cos(omega_d * t) + c2 * np.sin(omega_d * t)
    )
    peak = np.abs(u).max()
    np.testing.assert_allclose(out["displacement"], u, atol=2e-3 * peak)
    a_tot = -(2 * zeta * omega * out["velocity"] + omega**2 * out["displacement"])
    np.testing.assert_allclose(
        out["total_acceleration"], a_tot, atol=1e-6 * np.abs(a_tot).max()
    )


def test_building_full_condensed_matrices_match_state_space():
    # Three floors with full (not tridiagonal) K and C, negligible friction: the pairwise
    # spring/dashpot assembly must reproduce the equations of motion of the docstring,
    # integrated here independently with scipy's exact first-order-hold solver.
    signal = pytest.importorskip("scipy.signal")
    rng = np.random.default_rng(7)
    masses = np.array([1.0e5, 1.0e5, 0.8e5])
    base_mass = 1.2e5
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    w = 2 * np.pi * np.array([1.0, 2.5, 4.0])
    sq = np.sqrt(masses)
    stiff = sq[:, None] * (q * w**2) @ q.T * sq[None, :]
    damp = sq[:, None] * (q * (2 * 0.02 * w)) @ q.T * sq[None, :]
    assert np.all(np.abs(stiff[np.triu_indices(3, 1)]) > 0)
    total = base_mass + masses.sum()
    k_b = total * (2 * np.pi / 2.0) ** 2
    c_b = 2 * 0.05 * np.sqrt(k_b * total)
    dt = 1.0e-3
    t = np.arange(0.0, 3.0, dt)
    acc = 0.3 * G * np.sin(2 * np.pi * 0.8 * t) * np.exp(-0.5 * t)
    out = om.building_on_sliders(
        acc,
        dt,
        floor_masses=masses,
        stiffness=stiff,
        damping=damp,
        base_mass=base_mass,
        f_max=1e-9,
        delta_f=0.0,
        rate_a=0.0,
        yield_disp=Y,
        rubber_stiffness=k_b,
    )
    assert out["n_failed"] == 0
    # q = [u_b, u_1..u_n]: A q'' + B q' + D q = -e a_g
    n = 3
    r = np.ones(n)
    a_mat = np.zeros((n + 1, n + 1))
    a_mat[0, 0] = base_mass
    a_mat[1:, 0] = masses
    a_mat[1:, 1:] = np.diag(masses)
    b_mat = np.zeros_like(a_mat)
    b_mat[0, 0], b_mat[0, 1:], b_mat[1:, 1:] = c_b, -r @ damp, damp
    d_mat = np.zeros_like(a_mat)
    d_mat[0, 0], d_mat[0, 1:], d_mat[1:, 1:] = k_b, -r @ stiff, stiff
    e = np.concatenate([[base_mass], masses])
    a_inv = np.linalg.inv(a_mat)
    sys_a = np.block(
        [[np.zeros((n + 1, n + 1)), np.eye(n + 1)], [-a_inv @ d_mat, -a_inv @ b_mat]]
    )
    sys_b = np.concatenate([np.zeros(n + 1), -a_inv @ e])[:, None]
    sys_c = np.eye(2 * n + 2)
    _, _, x = signal.lsim((sys_a, sys_b, sys_c, np.zeros((2 * n + 2, 1))), acc, t)
    u_b, u = x[:, 0], x[:, 1 : n + 1]
    shear = -(x[:, n + 2 :] @ damp + u @ stiff) @ r
    np.testing.assert_allclose(out["base_displacement"], u_b, atol=5e-3 * np.abs(u_b).max())
    np.testing.assert_allclose(out["floor_displacement"], u, atol=5e-3 * np.abs(u).max())
    np.testing.assert_allclose(out["base_shear"], shear, atol=5e-3 * np.abs(shear).max())


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"delta_f": 0.2}, "delta_f"),
        ({"yield_disp": 0.0}, "yield_disp"),
        ({"damping_ratio": 0.05}, "damping_ratio"),
        ({"n_sub": 0}, "n_sub"),
    ],
)
def test_bad_inputs_name_the_parameter(kwargs, name):
    args = {
        "weight": WEIGHT,
        "f_max": 0.1,
        "delta_f": 0.05,
        "rate_a": 20.0,
        "yield_disp": Y,
    }
    args.update(kwargs)
    with pytest.raises(ValueError, match=name):
        om.rigid_mass_on_slider(np.zeros(10), 0.01, **args)
