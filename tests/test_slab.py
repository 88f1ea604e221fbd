"""Rigid slab (x, y, rotation) on bearing groups: torsion from plan asymmetry."""

import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from teflon_jax.bearing import paper_bearing
from teflon_jax.excitation import uniform_signal
from teflon_jax.structures import check_plan, slab_corners, slab_point_displacement
from teflon_jax.systems import simulate_history, slab_on_bearings
from teflon_jax.tables import interface_parameters
from teflon_jax.units import PSI, STANDARD_GRAVITY

LX, LY, W = 20.0, 12.0, 1.0e6
Y = 1.0e-3  # a wider elastic branch keeps the scipy reference cheap; both models use it
T, ZETA = 2.5, 0.05


def _pulse(duration, frequency, phase, peak, dt=0.01):
    t = np.arange(0.0, duration + dt / 2, dt)
    return peak * STANDARD_GRAVITY * np.sin(2 * np.pi * frequency * t + phase) * np.sin(np.pi * t / duration) ** 2


def _plan(centre):
    corners = slab_corners(LX, LY)
    fx, fy = centre[0] / LX, centre[1] / LY
    share = np.array([(1 - fx) * (1 - fy), fx * (1 - fy), fx * fy, (1 - fx) * fy])  # statics
    return corners, W * share


def _bearings(n):
    out = []
    for pressure in (1000, 2000, 3000, 1000)[:n]:
        params, _ = interface_parameters("UF", pressure * PSI)
        out.append(paper_bearing(params, yield_disp=Y))
    return out


def _system(centre, ax, ay):
    positions, loads = _plan(centre)
    return slab_on_bearings(
        length_x=LX, length_y=LY, weight=W, centre_of_mass=centre, positions=positions,
        bearings=_bearings(4), loads=loads, ground_acceleration=uniform_signal(ax, 0.01),
        ground_y=uniform_signal(ay, 0.01), time_step=0.0025, isolation_period=T,
        isolation_damping=ZETA,
    )


def _scipy_slab(centre, ax, ay, duration):
    """The same slab written independently: numpy right-hand side, LSODA at rtol 1e-9."""
    positions, loads = _plan(centre)
    r = positions - np.asarray(centre)
    m = W / STANDARD_GRAVITY
    J = m * (LX**2 + LY**2) / 12
    omega = 2 * np.pi / T
    k = m * omega**2 / 4 * np.ones(4)
    c = 2 * ZETA / omega * k
    consts = []
    for pressure in (1000, 2000, 3000, 1000):
        p, _ = interface_parameters("UF", pressure * PSI)
        consts.append((float(p.f_max), float(p.delta_f), float(p.rate_a)))
    consts = np.array(consts)
    t_rec = 0.01 * np.arange(len(ax))

    def rhs(t, s):
        ux, uy, th, vx, vy, vth = s[:6]
        z = s[6:].reshape(4, 2)
        d = np.stack([ux - th * r[:, 1], uy + th * r[:, 0]], axis=1)
        vb = np.stack([vx - vth * r[:, 1], vy + vth * r[:, 0]], axis=1)
        speed = np.hypot(vb[:, 0], vb[:, 1])
        mu = consts[:, 0] - consts[:, 1] * np.exp(-consts[:, 2] * speed)
        force = (mu * loads)[:, None] * z + k[:, None] * d + c[:, None] * vb
        fx, fy = force[:, 0].sum(), force[:, 1].sum()
        moment = np.sum(r[:, 0] * force[:, 1] - r[:, 1] * force[:, 0])
        gx, gy = np.interp(t, t_rec, ax), np.interp(t, t_rec, ay)
        common = 0.9 * (np.abs(vb[:, 0] * z[:, 0]) + np.abs(vb[:, 1] * z[:, 1])) + 0.1 * np.sum(vb * z, axis=1)
        dz = (vb - common[:, None] * z) / Y
        return np.concatenate([[vx, vy, vth, -gx - fx / m, -gy - fy / m, -moment / J], dz.ravel()])

    t_eval = np.arange(0.0, duration + 1e-9, 0.0025)
    sol = solve_ivp(rhs, (0, duration), np.zeros(14), method="LSODA", rtol=1e-9, atol=1e-12,
                    t_eval=t_eval, max_step=0.005)
    return sol.y[:3].T


@pytest.mark.slow
def test_symmetric_slab_does_not_twist():
    """No eccentricity (centre of mass = centre of stiffness = friction centroid, equal
    bearings): the rotation stays zero and every bearing moves alike."""
    ax, ay = _pulse(4.0, 0.8, 0.0, 0.3), _pulse(4.0, 0.55, 1.0, 0.25)
    positions, loads = _plan((LX / 2, LY / 2))
    system = slab_on_bearings(
        length_x=LX, length_y=LY, weight=W, centre_of_mass=(LX / 2, LY / 2), positions=positions,
        bearings=paper_bearing(interface_parameters("UF", 1000 * PSI)[0], yield_disp=Y),
        loads=loads, ground_acceleration=uniform_signal(ax, 0.01), ground_y=uniform_signal(ay, 0.01),
        time_step=0.0025, isolation_period=T, isolation_damping=ZETA,
    )
    response = simulate_history(system, 4.0)
    assert np.max(np.abs(response.displacement[:, :2])) > 0.01
    assert np.max(np.abs(response.displacement[:, 2])) < 1e-12
    spread = np.max(np.abs(response.bearing_displacement - response.bearing_displacement[:, :1]))
    assert spread < 1e-12


@pytest.mark.slow
def test_eccentric_slab_twists_like_an_independent_scipy_model():
    """Centre of mass 3 m and 1 m off the centre of stiffness, groups at 1000-3000 psi: the
    corner displacement exceeds the centre's, and the rotation and corner peak agree with an
    independent numpy/scipy model (LSODA) within 1 %."""
    centre = (13.0, 7.0)
    ax, ay = _pulse(5.0, 0.8, 0.0, 0.3), _pulse(5.0, 0.55, 1.0, 0.25)
    response = simulate_history(_system(centre, ax, ay), 5.0)
    corners = slab_corners(LX, LY)
    corner = np.asarray(slab_point_displacement(response.displacement, corners, centre))
    corner_peak = np.max(np.hypot(corner[..., 0], corner[..., 1]))
    centre_peak = np.max(np.hypot(response.displacement[:, 0], response.displacement[:, 1]))
    assert corner_peak > 1.02 * centre_peak
    reference = _scipy_slab(centre, ax, ay, 5.0)
    ref_corner = np.asarray(slab_point_displacement(jnp.asarray(reference), corners, centre))
    ref_peak = np.max(np.hypot(ref_corner[..., 0], ref_corner[..., 1]))
    assert abs(corner_peak - ref_peak) < 0.01 * ref_peak
    theta_peak, ref_theta = np.max(np.abs(response.displacement[:, 2])), np.max(np.abs(reference[:, 2]))
    assert abs(theta_peak - ref_theta) < 0.01 * ref_theta


def test_plan_checks_name_the_problem():
    positions, loads = _plan((LX / 2, LY / 2))
    with pytest.raises(ValueError, match=r"add up to 900 kN but the slab weighs 1000 kN"):
        check_plan(length_x=LX, length_y=LY, weight=W, centre_of_mass=(10, 6),
                   positions=positions, loads=0.9 * loads)
    bad = positions.copy()
    bad[2] = (LX + 1, 3.0)
    with pytest.raises(ValueError, match=r"group 3 at \(21, 3\) m lies outside the slab"):
        check_plan(length_x=LX, length_y=LY, weight=W, centre_of_mass=(10, 6),
                   positions=bad, loads=loads)


@pytest.mark.parametrize("settings, message", [
    ({"isolation_period": -2.0}, r"isolation_period: must be > 0 s, got -2.0"),
    ({"isolation_period": 0.0}, r"isolation_period: must be > 0 s, got 0.0"),
    ({"isolation_damping": -0.05}, r"isolation_damping: must be >= 0, got -0.05"),
    ({"isolation_period": None, "isolation_damping": 0.05}, r"isolation_damping: needs springs"),
])
def test_slab_isolation_settings_are_refused_by_name(settings, message):
    """A spring period that is not positive, or a negative damping ratio, names its argument
    (as the building on a plan does), before any work."""
    positions, loads = _plan((LX / 2, LY / 2))
    ground = uniform_signal(_pulse(1.0, 1.0, 0.0, 0.1), 0.01)
    keywords = {"isolation_period": T, "isolation_damping": ZETA, **settings}
    with pytest.raises(ValueError, match=message):
        slab_on_bearings(length_x=LX, length_y=LY, weight=W, centre_of_mass=(LX / 2, LY / 2), positions=positions,
                         bearings=_bearings(4), loads=loads, ground_acceleration=ground, ground_y=ground, time_step=0.0025,
                         **keywords)
