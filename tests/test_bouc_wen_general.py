"""General Bouc-Wen (Eq. 3) and Park et al. (Eqs. 8-9) with any A, beta, gamma, eta, against
scipy integrations of the equations written out below (not the library's rate functions),
and the closed-form solver's refusal of the shapes it cannot handle."""

import diffrax
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import teflon_jax as tj
from teflon_jax.systems import rigid_mass
from teflon_jax.units import INCH, PSI, STANDARD_GRAVITY


def _along(bearing, time, ux, normal_load, **options):
    """(force [N], Z [-], running max |Z|) along sampled displacements ux [m]."""
    result = tj.imposed_path_test(bearing, tj.sampled_path(time, ux, normal_load), **options)
    return result.fx, result.z[:, 0], result.z_peak

FRICTION, _ = tj.interface_parameters("UF", 1000 * PSI, "P")
Y = 0.005 * INCH
SHAPES = {"eta1": dict(A=1.3, beta=0.2, gamma=0.7, eta=1.0), "eta3": dict(A=0.8, beta=-0.1, gamma=0.6, eta=3.0)}


def bearing(shape, **kwargs):
    h = tj.BoucWen(yield_disp=jnp.asarray(Y), **{k: jnp.asarray(v) for k, v in shape.items()})
    return tj.SlidingBearing(friction=FRICTION, hysteresis=h, **kwargs)


def eq3(z, v, A, beta, gamma, eta):
    """Y dZ/dt of Eq. 3, written out."""
    return A * v - gamma * abs(v) * z * abs(z) ** (eta - 1) - beta * v * abs(z) ** eta


def eqs89(z, v, A, beta, gamma, eta):
    """Y dZ/dt of Park's Eqs. 8-9 with the |Z|^(eta-2) factor, written out."""
    norm = np.hypot(z[0], z[1])
    factor = norm ** (eta - 2) if norm > 0 else 0.0
    common = (gamma * (abs(v[0] * z[0]) + abs(v[1] * z[1])) + beta * (v[0] * z[0] + v[1] * z[1])) * factor
    return [A * v[0] - common * z[0], A * v[1] - common * z[1]]


@pytest.mark.parametrize("name", list(SHAPES))
def test_uniaxial_sine_test_matches_scipy(name):
    shape = SHAPES[name]
    U0, f = 1 * INCH, 0.5
    w = 2 * np.pi * f
    result = tj.imposed_path_test(bearing(shape), tj.SineMotion(U0, f, cycles=0.75), 1.0,
                                      samples_per_cycle=200, rtol=1e-10, atol=1e-12)  # default: Tsit5 for eta != 2
    t = np.asarray(result.time)
    sol = solve_ivp(lambda s, z: [eq3(z[0], U0 * w * np.cos(w * s), **shape) / Y], (0, t[-1]), [0.0],
                    t_eval=t, rtol=1e-11, atol=1e-13, method="LSODA", max_step=float(t[1] - t[0]))
    np.testing.assert_allclose(np.asarray(result.z[:, 0]), sol.y[0], atol=2e-6)
    ultimate = (shape["A"] / (shape["beta"] + shape["gamma"])) ** (1 / shape["eta"])
    assert np.max(np.abs(sol.y[0])) == pytest.approx(ultimate, rel=1e-6)  # A != beta + gamma: |Z| != 1
    # the sampled-path form used by the fitter, on the same motion
    _, z, _ = _along(bearing(shape), t, np.asarray(result.ux), 1.0, rtol=1e-10, atol=1e-12)
    slope = np.diff(np.asarray(result.ux)) / np.diff(t)  # piecewise-constant velocity

    def along(s, z):
        return [eq3(z[0], slope[min(np.searchsorted(t, s, side="right") - 1, len(slope) - 1)], **shape) / Y]

    path = solve_ivp(along, (0, t[-1]), [0.0], t_eval=t, rtol=1e-11, atol=1e-13, method="LSODA",
                     max_step=float(t[1] - t[0]) / 4)
    np.testing.assert_allclose(np.asarray(z), path.y[0], atol=1e-5)


@pytest.mark.parametrize("name", list(SHAPES))
def test_figure_eight_matches_scipy(name):
    shape = SHAPES[name]
    U0, w = 1 * INCH, 2.0
    motion = tj.FigureEightMotion(U0, w, cycles=0.75)
    result = tj.imposed_path_test(bearing(shape), motion, 1.0, samples_per_cycle=200, rtol=1e-10, atol=1e-12)
    t = np.asarray(result.time)

    def rhs(s, z):
        v = (U0 * w * np.cos(w * s), 2 * U0 * w * np.cos(2 * w * s))
        return np.asarray(eqs89(z, v, **shape)) / Y

    sol = solve_ivp(rhs, (0, t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-11, atol=1e-13, method="LSODA", max_step=float(t[1] - t[0]))
    np.testing.assert_allclose(np.asarray(result.z), sol.y.T, atol=2e-6)
    # eta matters: the paper's eta = 2 gives a different Z here
    paper = dict(shape, eta=2.0)
    other = solve_ivp(lambda s, z: np.asarray(eqs89(z, (U0 * w * np.cos(w * s), 2 * U0 * w * np.cos(2 * w * s)), **paper)) / Y,
                      (0, t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-11, atol=1e-13, method="LSODA", max_step=float(t[1] - t[0]))
    assert np.max(np.abs(other.y.T - sol.y.T)) > 1e-2


def test_rigid_mass_with_eta_3_matches_scipy():
    shape = SHAPES["eta3"]
    omega, peak, duration = 3.14, 0.25 * STANDARD_GRAVITY, 1.0
    times = np.arange(0.0, duration + 1e-9, 1e-3)
    signal = tj.Signal(jnp.asarray(times), jnp.asarray(peak * np.sin(omega * times)))
    system = rigid_mass(weight=1.0e5, bearing=bearing(shape), ground_acceleration=signal, time_step=1e-3,
                        isolation_period=2.0, damping_ratio=0.05)
    with pytest.raises(ValueError, match="eta: RiccatiNewmark"):
        tj.simulate_history(system, duration)  # the closed form cannot, and says so
    ours = tj.simulate_history(system, duration, solver=diffrax.Tsit5(), rtol=1e-8, atol=1e-11)
    m, k, c = float(system.mass[0]), float(system.stiffness[0, 0]), float(system.damping[0, 0])
    f_max, delta_f, rate_a = float(FRICTION.f_max), float(FRICTION.delta_f), float(FRICTION.rate_a)

    def rhs(s, y):
        u, v, z = y
        mu = f_max - delta_f * np.exp(-rate_a * abs(v))
        force = mu * 1.0e5 * z
        return [v, (-m * peak * np.sin(omega * s) - c * v - k * u - force) / m, eq3(z, v, **shape) / Y]

    t = np.asarray(ours.time)
    sol = solve_ivp(rhs, (0, duration), [0.0, 0.0, 0.0], t_eval=t, rtol=1e-10, atol=1e-13, method="LSODA", max_step=1e-3)
    u = np.asarray(ours.displacement[:, 0])
    assert np.max(np.abs(u)) > 1e-3  # it slides
    np.testing.assert_allclose(u, sol.y[0], atol=2e-5 * np.max(np.abs(u)))
    np.testing.assert_allclose(np.asarray(ours.z), sol.y[2], atol=1e-4)


def test_riccati_newmark_with_a_above_beta_plus_gamma_agrees_with_tsit5():
    """A = 1.5 > beta + gamma: sliding |Z| = sqrt(1.5) > 1; the Newton bracket still holds it."""
    shape = dict(A=1.5, beta=0.1, gamma=0.9, eta=2.0)
    times = np.arange(0.0, 1.2 + 1e-9, 1e-3)
    signal = tj.Signal(jnp.asarray(times), jnp.asarray(0.3 * STANDARD_GRAVITY * np.sin(3.14 * times)))
    system = rigid_mass(weight=1.0e5, bearing=bearing(shape), ground_acceleration=signal, time_step=1e-3)
    newmark = tj.simulate_history(system, 1.2)
    assert bool(newmark.succeeded)
    assert float(jnp.max(jnp.abs(newmark.z))) == pytest.approx(np.sqrt(1.5), rel=1e-4)
    reference = tj.simulate_history(system, 1.2, solver=diffrax.Tsit5(), rtol=1e-8, atol=1e-11)
    u_ref = np.asarray(reference.displacement[:, 0])
    np.testing.assert_allclose(np.asarray(newmark.displacement[:, 0]), u_ref, atol=5e-3 * np.max(np.abs(u_ref)))


def test_closed_form_solver_refuses_other_shapes():
    motion = tj.SineMotion(INCH, 0.5, cycles=1)
    with pytest.raises(ValueError, match="eta: RiccatiNewmark.*Tsit5"):
        tj.imposed_path_test(bearing(SHAPES["eta3"]), motion, 1.0, solver=tj.RiccatiNewmark())
    with pytest.raises(ValueError, match="gamma: RiccatiNewmark"):
        tj.imposed_path_test(bearing(dict(A=1.0, beta=0.5, gamma=0.5, eta=2.0)), motion, 1.0,
                                 solver=tj.RiccatiNewmark())
    # traced constants: a runtime error, not a silent eta = 2
    t = jnp.linspace(0.0, 1.0, 51)
    ux = INCH * jnp.sin(2 * jnp.pi * t)

    @jax.jit
    def force(eta):
        h = tj.BoucWen(yield_disp=jnp.asarray(Y), eta=eta)
        return _along(tj.SlidingBearing(friction=FRICTION, hysteresis=h), t, ux, 1.0)[0]

    assert bool(jnp.all(jnp.isfinite(force(2.0))))
    with pytest.raises(Exception, match="eta = 2 and gamma > beta"):
        jax.block_until_ready(force(3.0))


def test_eta_changes_the_force_along_a_path():
    """eta = 1 and eta = 2 give different forces (the bug: eta was ignored)."""
    t = np.linspace(0.0, 2.0, 401)
    ux = INCH * np.sin(np.pi * t)
    forces = [np.asarray(_along(bearing(dict(A=1.0, beta=0.1, gamma=0.9, eta=e)), t, ux, 1.0)[0])
              for e in (1.0, 2.0)]
    assert np.max(np.abs(forces[0] - forces[1])) > 1e-3 * np.max(np.abs(forces[1]))


@pytest.mark.parametrize(
    "shape, match",
    [
        (dict(A=0.0), "A: must be"),
        (dict(gamma=-0.5), "gamma: must be"),
        (dict(beta=1.2, gamma=0.9), "beta: must satisfy -gamma <= beta <= gamma"),
        (dict(beta=float("nan")), "beta: must be finite"),
        (dict(eta=0.5), "eta: must be >= 1"),
    ],
)
def test_check_bearing_names_each_bouc_wen_constant(shape, match):
    full = dict(dict(A=1.0, beta=0.1, gamma=0.9, eta=2.0), **shape)
    with pytest.raises(ValueError, match=match):
        tj.check_bearing(bearing(full))
    with pytest.raises(ValueError, match=match):
        tj.imposed_path_test(bearing(full), tj.SineMotion(INCH, 1.0), 1.0)


def test_newton_bracket_holds_a_step_that_saturates_z_above_one():
    """One Newmark step from Z = 0 at 0.5 m/s with A = 1.5: Z reaches sqrt(1.5) within the step,
    so |F| = mu W sqrt(1.5) > f_max W; the bracket must still contain the root."""
    shape = dict(A=1.5, beta=0.1, gamma=0.9, eta=2.0)
    system = rigid_mass(weight=1.0e5, bearing=bearing(shape), ground_acceleration=tj.as_signal(0.0, duration=1.0),
                        time_step=1e-3)
    y0 = {"u": jnp.zeros(1), "v": jnp.asarray([0.5]), "z": jnp.asarray(0.0), "z_peak": jnp.asarray(1.0)}
    y1, converged = system.advance(0.0, 1e-3, y0, None)
    assert bool(converged)
    force = system.friction_force(y1["v"][0], y1["z"], y1["z_peak"])
    assert float(force) > 1.1 * float(FRICTION.f_max) * 1.0e5  # beyond the old bound f_max W
    # Newmark's relations hold with that force: m (v1 - v0) = -dt/2 (F0 + F1), F0 = 0 (Z = 0)
    m = float(system.mass[0])
    assert float(m * (y1["v"][0] - 0.5)) == pytest.approx(-1e-3 / 2 * float(force), rel=1e-6)
