"""The friction model against the paper's tests, closed forms and an independent integrator."""

import diffrax
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import teflon_jax as tj
from teflon_jax.units import INCH, KIP, PSI

UF_P_1000, _ = tj.interface_parameters("UF", 1000 * PSI, "P")
UF_T_1000, B_UF_T_1000 = tj.interface_parameters("UF", 1000 * PSI, "T")
LOAD = 100.0 * KIP


def last_cycle(result, samples_per_cycle=400):
    return jax.tree.map(lambda x: x[-samples_per_cycle - 1 :] if jnp.ndim(x) else x, result)


def test_75_peak_friction_and_rectangular_loop():
    """Test No. 75: UF 1000 psi P, 4 in at 0.6 Hz (15 in/s): peak mu = f_max = 0.1193, square loop."""
    bearing = tj.paper_bearing(UF_P_1000)
    result = tj.imposed_path_test(bearing, tj.SineMotion(4 * INCH, 0.6, cycles=3), LOAD)
    cycle = last_cycle(result)
    mu = np.asarray(cycle.fx / cycle.normal_load)
    assert np.max(np.abs(mu)) == pytest.approx(0.1193, rel=0.01)
    # Nearly rectangular: dissipated energy close to the rectangle 4 * U0 * F_peak.
    energy = np.trapezoid(np.asarray(cycle.fx), np.asarray(cycle.ux))
    rectangle = 4 * 4 * INCH * np.max(np.abs(np.asarray(cycle.fx)))
    assert energy / rectangle > 0.9
    assert energy > 0  # clockwise loop: the bearing dissipates


def test_62_friction_at_peak_velocity():
    """Test No. 62: 1 in at 0.16 Hz, peak velocity 1 in/s: mu = f_max - Df exp(-a 1 in/s) = 0.0684."""
    bearing = tj.paper_bearing(UF_P_1000)
    result = tj.imposed_path_test(bearing, tj.SineMotion(1 * INCH, 0.16, cycles=3), LOAD)
    cycle = last_cycle(result)
    i = int(np.argmax(np.asarray(cycle.vx)))
    assert float(cycle.vx[i]) == pytest.approx(2 * np.pi * 0.16 * INCH, rel=1e-3)
    assert float(cycle.fx[i] / cycle.normal_load[i]) == pytest.approx(0.0684, rel=0.01)
    # friction varies continuously along the loop: at the quarter-velocity point it is lower
    j = int(np.argmin(np.abs(np.asarray(cycle.vx) - 0.25 * float(cycle.vx[i]))))
    assert abs(float(cycle.fx[j])) < 0.9 * abs(float(cycle.fx[i]))


def eight(amplitude, omega, anisotropic):
    bearing = tj.paper_bearing(UF_P_1000, friction_perpendicular=UF_T_1000 if anisotropic else None)
    motion = tj.FigureEightMotion(amplitude, omega, cycles=2)
    return tj.imposed_path_test(bearing, motion, LOAD, samples_per_cycle=800)


def test_figure_eight_isotropic_z_follows_velocity_direction():
    """Eq. 16 motion: while sliding, (Zx, Zy) = (cos theta, sin theta).

    Z trails the velocity direction by an angle of about kappa * Y (kappa: path curvature), so
    the identity holds to 1e-3 where kappa Y < 1e-3, and the deviation elsewhere is that lag.
    """
    U0, w = 4 * INCH, 2.77
    result = eight(U0, w, anisotropic=False)
    t = np.asarray(result.time)
    vx, vy = np.asarray(result.vx), np.asarray(result.vy)
    ax, ay = -U0 * w**2 * np.sin(w * t), -4 * U0 * w**2 * np.sin(2 * w * t)
    lag = np.abs(vx * ay - vy * ax) / np.hypot(vx, vy) ** 3 * 0.005 * INCH
    theta = np.arctan2(vy, vx)
    z = np.asarray(result.z)
    sliding = (t > 0.5) & (np.hypot(vx, vy) > 1 * INCH)
    error = np.hypot(z[:, 0] - np.cos(theta), z[:, 1] - np.sin(theta))
    straight = sliding & (lag < 1e-3)
    assert straight.sum() > 500
    assert np.max(error[straight]) < 1e-3
    assert np.max(error[sliding]) < 1.5 * np.max(lag[sliding])
    assert np.max(np.abs(np.hypot(z[:, 0], z[:, 1])[sliding] - 1)) < 1e-3


def test_figure_eight_anisotropic_high_speed_friction():
    result = eight(4 * INCH, 2.77, anisotropic=True)
    vx, vy = np.asarray(result.vx), np.asarray(result.vy)
    mu = np.asarray(result.coefficient)
    along_y = np.abs(vx) < 0.02 * np.abs(vy)
    along_x = np.abs(vy) < 0.02 * np.abs(vx)
    assert along_x.any() and along_y.any()
    assert np.max(mu[along_y]) == pytest.approx(0.142, rel=0.01)
    assert np.max(mu[along_x]) == pytest.approx(0.119, rel=0.01)


def test_191_breakaway_first_peak_only():
    """Test No. 191: UF 1000 psi T, 0.5 in at 0.03 Hz, 78.5 kip, b = 3."""
    bearing = tj.paper_bearing(UF_T_1000, breakaway_ratio=3.0)
    load = 78.5 * KIP
    result = tj.imposed_path_test(bearing, tj.SineMotion(0.5 * INCH, 0.03, cycles=3), load)
    mu = np.asarray(result.fx) / load
    t = np.asarray(result.time)
    first = np.max(np.abs(mu[t < 0.25 / 0.03]))
    assert first == pytest.approx(3 * (0.1420 - 0.1181), rel=0.02)
    later = np.max(np.abs(mu[t > 0.5 / 0.03]))
    assert later < 0.1420 * 1.001  # never above Eq. 1's ceiling after breakaway
    # and the running max of |Z| passed the threshold in the first quarter cycle
    assert float(result.z_peak[np.searchsorted(t, 0.25 / 0.03)]) >= tj.BREAKAWAY_THRESHOLD


def test_stack_of_24_interfaces_follows_eq1_at_v_over_n():
    n = 24
    stack = tj.paper_bearing(UF_P_1000, n_interfaces=n)
    result = tj.imposed_path_test(stack, tj.TriangleMotion(4 * INCH, 0.5, cycles=2), LOAD)
    v = np.abs(np.asarray(result.vx))
    sliding = np.abs(np.asarray(result.z[:, 0])) > 0.9999
    mu = np.abs(np.asarray(result.fx))[sliding] / LOAD
    expected = np.asarray(tj.sliding_friction(UF_P_1000, v[sliding] / n))
    np.testing.assert_allclose(mu, expected * np.abs(np.asarray(result.z[:, 0]))[sliding], rtol=1e-9)
    single = float(tj.sliding_friction(UF_P_1000, v[sliding][0]))
    assert mu[0] < 0.8 * single  # much lower than one interface at the full speed


def test_vmap_over_table1_equals_separate_calls():
    params, b, labels = tj.table1_parameters()
    assert len(labels) == 16
    motion = tj.SineMotion(1 * INCH, 0.5, cycles=2)

    def run(friction, ratio):
        bearing = tj.paper_bearing(friction, breakaway_ratio=ratio)
        return tj.imposed_path_test(bearing, motion, LOAD, samples_per_cycle=200).fx

    batched = jax.vmap(run)(params, b)
    for k in (0, 7, 15):
        single = run(jax.tree.map(lambda x, k=k: x[k], params), b[k])
        np.testing.assert_allclose(np.asarray(batched[k]), np.asarray(single), rtol=1e-12, atol=1e-9)
    assert batched.shape == (16, 401)


def test_riccati_update_matches_the_ode_along_the_path():
    h = tj.BoucWen(yield_disp=jnp.asarray(0.005 * INCH))
    for z0 in (-0.9, -0.2, 0.0, 0.4, 1.0):
        for du in (-3e-4, -2e-5, 1e-5, 2e-4):
            direction = float(np.sign(du))

            def rhs(u, z, direction=direction):
                return np.asarray(tj.bouc_wen_rate(h, z[0], direction))[None]
            # unit speed in the direction of du: dZ/dt = dZ/d|u|; integrate over |du| with scipy
            sol = solve_ivp(rhs, (0, abs(du)), [z0], rtol=1e-11, atol=1e-13, method="LSODA")
            exact = float(tj.bouc_wen_exact_update(h, jnp.asarray(z0), jnp.asarray(du)))
            assert exact == pytest.approx(sol.y[0, -1], abs=1e-8)


def test_independent_scipy_integration_of_test_62():
    """The whole test simulated by scipy's LSODA on the plain ODE, written here in numpy."""
    f = UF_P_1000
    f_max, delta_f, rate_a = float(f.f_max), float(f.delta_f), float(f.rate_a)
    Y, A, beta, gamma = 0.005 * INCH, 1.0, 0.1, 0.9
    U0, w = 1 * INCH, 2 * np.pi * 0.16

    def rhs(t, z):
        v = U0 * w * np.cos(w * t)
        return [(A * v - gamma * abs(v) * z[0] * abs(z[0]) - beta * v * z[0] ** 2) / Y]

    times = np.linspace(0, 3 / 0.16, 1201)
    sol = solve_ivp(rhs, (0, times[-1]), [0.0], t_eval=times, rtol=1e-10, atol=1e-12, method="LSODA")
    v = U0 * w * np.cos(w * times)
    force = (f_max - delta_f * np.exp(-rate_a * np.abs(v))) * LOAD * sol.y[0]
    ours = tj.imposed_path_test(
        tj.paper_bearing(f), tj.SineMotion(U0, 0.16, cycles=3), LOAD, samples_per_cycle=400
    )
    np.testing.assert_allclose(np.asarray(ours.fx), force, atol=1e-5 * LOAD)


def test_riccati_agrees_with_adaptive_tsit5():
    bearing = tj.paper_bearing(UF_P_1000, breakaway_ratio=2.2)
    motion = tj.SineMotion(2 * INCH, 0.4, cycles=1.25)
    exact = tj.imposed_path_test(bearing, motion, LOAD)
    general = tj.imposed_path_test(
        bearing, motion, LOAD, solver=diffrax.Tsit5(), rtol=1e-9, atol=1e-11
    )
    np.testing.assert_allclose(np.asarray(exact.fx), np.asarray(general.fx), atol=1e-6 * LOAD)


def test_tabulated_motion_matches_the_analytic_protocol():
    """A finely tabulated sine reproduces the analytic sine test (loop energy within 0.2 %)."""
    bearing = tj.paper_bearing(UF_P_1000)
    analytic = tj.imposed_path_test(bearing, tj.SineMotion(1 * INCH, 0.5, cycles=1), LOAD,
                                        samples_per_cycle=800)
    t = np.linspace(0.0, 2.0, 801)
    motion = tj.tabulated_motion(t, 1 * INCH * np.sin(2 * np.pi * 0.5 * t))
    tabulated = tj.imposed_path_test(bearing, motion, LOAD)
    e1 = np.trapezoid(np.asarray(analytic.fx), np.asarray(analytic.ux))
    e2 = np.trapezoid(np.asarray(tabulated.fx), np.asarray(tabulated.ux))
    assert e2 == pytest.approx(e1, rel=2e-3)



def test_a_diagonal_path_is_the_one_direction_test_along_its_line():
    """Park's Eqs. 8-9 (eta = 2) along a straight line at 45 degrees: with Zx = Zy = |Z| / sqrt 2
    they reduce to Bouc-Wen's Eq. 3 in the distance along the line, and mu depends on the
    resultant speed, so the resultant force equals the force of the one-direction test of the
    same displacement. The motion's type picks the model: the plane's table runs Park (an
    adaptive solver), the one-direction table Bouc-Wen (the exact update)."""
    bearing = tj.paper_bearing(UF_P_1000)
    t = np.linspace(0.0, 2.0, 801)
    u = 1 * INCH * np.sin(2 * np.pi * 0.5 * t)
    along = tj.tabulated_motion(t, u)
    diagonal = tj.tabulated_motion(t, u / np.sqrt(2.0), u / np.sqrt(2.0))
    assert isinstance(along, tj.AbstractUniaxialMotion)
    assert isinstance(diagonal, tj.AbstractBiaxialMotion)
    one = tj.imposed_path_test(bearing, along, LOAD)
    plane = tj.imposed_path_test(bearing, diagonal, LOAD)
    assert np.all(np.asarray(one.fy) == 0.0)
    np.testing.assert_allclose(np.asarray(plane.fx), np.asarray(plane.fy), rtol=0, atol=1e-10 * LOAD)
    resultant = np.sign(np.asarray(plane.fx)) * np.hypot(np.asarray(plane.fx), np.asarray(plane.fy))
    np.testing.assert_allclose(resultant, np.asarray(one.fx), atol=2e-6 * LOAD)


GRADIENT_BASE = {"f_max": 0.1193, "delta_f": 0.0927, "rate_a": 0.6 / INCH,
                 "yield_disp": 0.005 * INCH, "breakaway_ratio": 2.2}


@pytest.fixture(scope="module")
def loop_energy():
    """Energy dissipated over two cycles of test No. 62 with breakaway [J], jitted once."""
    motion = tj.SineMotion(1 * INCH, 0.16, cycles=2)

    @jax.jit
    def energy(p):
        bearing = tj.paper_bearing(
            tj.FrictionParameters(p["f_max"], p["delta_f"], p["rate_a"]),
            yield_disp=p["yield_disp"],
            breakaway_ratio=p["breakaway_ratio"],
        )
        result = tj.imposed_path_test(bearing, motion, LOAD, samples_per_cycle=400)
        return jnp.trapezoid(result.fx, result.ux)

    params = {k: jnp.asarray(v) for k, v in GRADIENT_BASE.items()}
    return energy, params, jax.jit(jax.grad(energy))(params)


@pytest.mark.parametrize("name", list(GRADIENT_BASE))
def test_energy_gradient_matches_finite_differences(loop_energy, name):
    energy, params, grad = loop_energy
    h = 1e-5 * GRADIENT_BASE[name]
    plus = dict(params, **{name: params[name] + h})
    minus = dict(params, **{name: params[name] - h})
    fd = (energy(plus) - energy(minus)) / (2 * h)
    assert float(grad[name]) != 0.0
    assert float(grad[name]) == pytest.approx(float(fd), rel=1e-4)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: tj.interface_parameters("PTFE", 1000 * PSI), "ptfe: unknown PTFE type 'PTFE'; accepted values: UF, 15GF, 25GF"),
        (lambda: tj.interface_parameters("UF", -5.0), "pressure: must be > 0"),
        (lambda: tj.interface_parameters("UF", 500 * PSI), "pressure: 500 psi is outside"),
        (lambda: tj.interface_parameters("UF", 7000 * PSI), "extrapolat"),
        (lambda: tj.interface_parameters("25GF", 1000 * PSI, "T"), "direction: Table 1 has no T rows for 25GF"),
        (lambda: tj.interface_parameters("UF", 1000 * PSI, "X"), "direction: unknown direction 'X'"),
        (lambda: tj.imposed_path_test(tj.paper_bearing(UF_P_1000, yield_disp=0.0), tj.SineMotion(INCH, 1.0), LOAD), "yield_disp: must be"),
        (lambda: tj.imposed_path_test(tj.paper_bearing(UF_P_1000, breakaway_ratio=0.5), tj.SineMotion(INCH, 1.0), LOAD), "breakaway_ratio: must be >= 1"),
        (lambda: tj.imposed_path_test(tj.paper_bearing(UF_P_1000), tj.SineMotion(-INCH, 1.0), LOAD), "amplitude: must be"),
        (lambda: tj.imposed_path_test(tj.paper_bearing(UF_P_1000), tj.SineMotion(INCH, 0.0), LOAD), "frequency: must be"),
        (lambda: tj.imposed_path_test(tj.paper_bearing(UF_P_1000), tj.SineMotion(INCH, 1.0), -1.0), "normal_load: must be"),
        (lambda: tj.units.parse_quantity("4Hz", "length", where="--amplitude"), "--amplitude: 'Hz' is a unit of frequency, but a length is expected"),
    ],
)
def test_bad_input_names_the_parameter(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_pressure_interpolation_between_rows_and_gradient():
    table = tj.friction_table("UF", "P")
    mid, _ = table.at(1500 * PSI)
    assert float(mid.f_max) == pytest.approx(0.5 * (0.1193 + 0.0870), rel=1e-12)
    slope = jax.grad(lambda p: table.at(p)[0].f_max)(1500 * PSI)
    assert float(slope) == pytest.approx((0.0870 - 0.1193) / (1000 * PSI), rel=1e-9)
    # the table's cross-checks stated in the paper
    rows = {r.label: r for r in tj.load_table1()}
    assert rows["25GF 6500psi P"].f_max / (rows["25GF 6500psi P"].f_max - rows["25GF 6500psi P"].delta_f) == pytest.approx(1.8, abs=0.05)
    for p in (1000, 2000, 3000):
        r = rows[f"UF {p}psi P"]
        assert r.f_max / (r.f_max - r.delta_f) > 4.4


def test_reversal_length_is_where_z_crosses_zero():
    h = tj.BoucWen(yield_disp=jnp.asarray(0.005 * INCH))
    for z0 in (-1.0, -0.6, 0.05, 0.9):
        length = float(tj.bouc_wen_reversal_length(h, jnp.asarray(z0)))
        du = -np.sign(z0) * length * float(h.yield_disp)  # against Z, exactly to Z = 0
        assert abs(float(tj.bouc_wen_exact_update(h, jnp.asarray(z0), jnp.asarray(du)))) < 1e-12
        beyond = float(tj.bouc_wen_exact_update(h, jnp.asarray(z0), jnp.asarray(1.5 * du)))
        assert np.sign(beyond) == -np.sign(z0)  # past it, Z has changed sign
        # the precomputed length (as the Newton loop passes it) gives the same update
        for scale in (0.3, 1.0, 4.0):
            np.testing.assert_array_equal(
                tj.bouc_wen_exact_update(h, jnp.asarray(z0), jnp.asarray(scale * du), jnp.asarray(length)),
                tj.bouc_wen_exact_update(h, jnp.asarray(z0), jnp.asarray(scale * du)))


def test_rational_tangent_of_the_reversal_branch():
    """`_tan_pair` (Monte Carlo's tangent) against NumPy's tan over [0, pi/2), both halves of
    its reduction and tiny angles, to within 10 ulp."""
    from teflon_jax.bearing._hysteresis import _tan_pair

    angle = np.concatenate([np.linspace(0.0, 1.5, 30001), np.geomspace(1e-300, 0.1, 2001)])
    sin, cos = jax.jit(_tan_pair)(jnp.asarray(angle))
    np.testing.assert_allclose(np.asarray(sin) / np.asarray(cos), np.tan(angle), rtol=2e-15, atol=0)
    # the update with the rational tangent (Monte Carlo) and with jnp.tan (fits) agree, gradients too
    h = tj.BoucWen(yield_disp=jnp.asarray(0.005 * INCH))
    rng = np.random.default_rng(3)
    z0 = jnp.asarray(rng.uniform(-1.0, 1.0, 2000))
    du = jnp.asarray(rng.normal(0.0, 2e-4, 2000))
    for argnums in (None, 1, 2):
        results = []
        for tangent in ("library", "rational"):
            def update(z, d, tangent=tangent):
                return tj.bouc_wen_exact_update(h, z, d, tangent=tangent)
            f = update if argnums is None else jax.grad(update, argnums=argnums - 1)
            results.append(np.asarray(jax.vmap(f)(z0, du)))
        np.testing.assert_allclose(results[1], results[0], rtol=1e-12, atol=1e-12)
    with pytest.raises(ValueError, match="tangent"):
        tj.bouc_wen_exact_update(h, z0, du, tangent="cordic")
