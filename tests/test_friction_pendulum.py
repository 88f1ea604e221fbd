"""The single friction pendulum (concave surface of radius R) against closed forms.

Each test names the statement of the pendulum's law it guards: the period 2 pi sqrt(R / g),
the Coulomb decay of 4 mu R per cycle, the restoring force W r / R along the displacement with
the friction along the velocity, the restrainer beyond the displacement capacity and the
large-displacement form N u / sqrt(R^2 - u^2). Reference: Zayas, Low & Mahin (1990).

The rigid mass on the pendulum is also compared with OpenSees' `singleFPBearing` under the PEER
RSN6 El Centro records (40 s, R = 88 in), with the same friction law on both sides
(benchmarks/_opensees_pendulum.py). OpenSees' slider is elastic-perfectly-plastic with an
initial stiffness mu_slow W / Y and takes the normal force on the surface as W + F u / R;
measured, ours minus OpenSees:

- Coulomb friction mu = 0.06, one component (180), 1 ms steps, OpenSees' Y = 1e-7 m:
  displacement +0.03 %, base shear -0.21 % (with Y = 1e-5 m at 2.5 ms OpenSees' stick-slip
  is not converged: -2.5 %, -1.0 %; an independent ODE with friction mu W tanh(v / 1e-4 m/s)
  gives 57.9 mm against our 58.0-58.2 mm);
- velocity-dependent friction (UF, f_max 0.1193, f_min 0.0266, a 0.6 s/in), the 180 + 270
  pair, 2.5 ms steps, Y = 0.001 in on both sides: displacement -0.38 %, base shear -0.27 %
  (-2.3 % and -0.64 % at the paper's Y = 0.005 in: Bouc-Wen's smooth loop against the
  elastic-perfectly-plastic one, as for the flat sliders in test_bidirectional_opensees.py).
"""

import pathlib
import sys

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from teflon_jax.bearing import FrictionParameters, concave_surface, paper_bearing
from teflon_jax.excitation import uniform_signal
from teflon_jax.formats import read_at2
from teflon_jax.studies import bidirectional_isolated_structure
from teflon_jax.systems import (
    imposed_path_test,
    isolated_structure,
    sampled_path,
    simulate_history,
)
from teflon_jax.units import INCH, STANDARD_GRAVITY

G = STANDARD_GRAVITY
WEIGHT = 100e3  # [N], the rigid mass of `isolated_structure`
RADIUS = 1.0  # [m]


def _kicked(duration, dt=0.005, amplitude=3.0, pulse=0.25):
    """A ground-acceleration pulse of `amplitude` [m/s^2] over `pulse` [s], then rest."""
    t = np.arange(0.0, duration + dt / 2, dt)
    return uniform_signal(np.where(t < pulse, amplitude, 0.0), dt), pulse


def _free_vibration(friction_model, bearing=None, duration=12.0, radius=RADIUS):
    ground, pulse = _kicked(duration)
    surface = concave_surface(radius)
    structure = isolated_structure("rigid", isolator=surface if bearing is None else (bearing, surface),
                                   time_step=0.001, friction_model=friction_model)
    response = simulate_history(structure(ground), duration)
    t = np.asarray(response.time)
    u = np.asarray(response.displacement[:, 0])
    after = t > pulse + 0.01
    return t[after], u[after]


def test_free_vibration_without_friction_has_the_pendulum_period():
    t, u = _free_vibration("none")
    # zero crossings, interpolated linearly between samples
    i = np.nonzero(np.sign(u[1:]) != np.sign(u[:-1]))[0]
    crossings = t[i] - u[i] * (t[i + 1] - t[i]) / (u[i + 1] - u[i])
    period = 2 * np.mean(np.diff(crossings))
    assert len(crossings) >= 8
    np.testing.assert_allclose(period, 2 * np.pi * np.sqrt(RADIUS / G), rtol=1e-5)


def test_coulomb_free_vibration_decays_by_four_mu_r_per_cycle():
    mu = 0.01
    bearing = paper_bearing(FrictionParameters(f_max=mu, delta_f=0.0, rate_a=1.0))
    t, u = _free_vibration("coulomb", bearing=bearing)
    interior = (u[1:-1] > u[:-2]) & (u[1:-1] >= u[2:]) & (u[1:-1] > 0)
    peaks = u[1:-1][interior]
    assert len(peaks) >= 3
    np.testing.assert_allclose(-np.diff(peaks), 4 * mu * RADIUS, rtol=2e-3)


def test_restoring_force_lies_along_the_displacement_and_friction_along_the_velocity():
    # A circular orbit of radius r at angular rate w: the surface pulls back along u with
    # magnitude W r / R; the liner's friction (Eq. 1, here constant) is along the velocity.
    r, w, mu = 0.2, 2.0, 0.05
    surface = concave_surface(RADIUS)
    time = np.linspace(0.0, 2 * (2 * np.pi / w), 4001)
    u = np.stack([r * np.cos(w * time), r * np.sin(w * time)], axis=-1)
    v = np.stack([-r * w * np.sin(w * time), r * w * np.cos(w * time)], axis=-1)
    restoring = np.asarray(surface.restoring_force(jnp.asarray(u), WEIGHT))
    radial = u / r
    np.testing.assert_allclose(restoring, WEIGHT * r / RADIUS * radial, rtol=1e-12)
    bearing = paper_bearing(FrictionParameters(f_max=mu, delta_f=0.0, rate_a=1.0))
    path = sampled_path(time, u[:, 0], WEIGHT, uy=u[:, 1], velocity=v[:, 0], velocity_y=v[:, 1])
    response = imposed_path_test(bearing, path, z_peak0=1.0)
    friction = np.stack([response.fx, response.fy], axis=-1)
    total = restoring + friction
    settled = time > 2 * np.pi / w  # the second turn: Z has reached the circle
    tangent = v / (r * w)
    np.testing.assert_allclose(np.sum(total * radial, -1)[settled], WEIGHT * r / RADIUS, atol=1e-3 * WEIGHT)
    np.testing.assert_allclose(np.sum(total * tangent, -1)[settled], mu * WEIGHT, rtol=2e-3)


def test_bidirectional_structure_pulls_back_along_the_displacement():
    """The two-direction rigid mass on the pendulum: the restoring force K q of its springs is
    the surface's W q / R, along q, in any direction."""
    ground = uniform_signal(np.zeros(11), 0.01)
    structure = bidirectional_isolated_structure("rigid", isolator=concave_surface(RADIUS))
    system = structure((ground, ground))
    q = np.array([0.3, -0.4])
    force = np.asarray(system.stiffness @ jnp.asarray(q))
    np.testing.assert_allclose(force, concave_surface(RADIUS).restoring_force(jnp.asarray(q), WEIGHT),
                               rtol=1e-12)
    np.testing.assert_allclose(force, WEIGHT * q / RADIUS, rtol=1e-12)
    assert float(system.damping[0, 0]) == 0.0  # the pendulum's damping is its friction


def test_restrainer_stiffens_beyond_the_displacement_capacity():
    capacity, k_r = 0.3, 5e6
    surface = concave_surface(RADIUS, displacement_capacity=capacity, restrainer_stiffness=k_r)
    u = jnp.array([-0.5, -0.3, 0.1, 0.3, 0.45])
    expected = WEIGHT * u / RADIUS + k_r * np.maximum(np.abs(u) - capacity, 0.0) * np.sign(u)
    np.testing.assert_allclose(surface.restoring_force(u, WEIGHT), expected, rtol=1e-12)
    np.testing.assert_allclose(surface.extra_force(u, WEIGHT), expected - WEIGHT * u / RADIUS,
                               atol=1e-9)
    # in two directions the restrainer acts along the displacement, on its length
    q = jnp.array([0.3, 0.4])  # |q| = 0.5
    np.testing.assert_allclose(surface.restoring_force(q, WEIGHT),
                               (WEIGHT * 0.5 / RADIUS + k_r * 0.2) * q / 0.5, rtol=1e-12)
    # the slope jumps by k_r at the capacity
    slope = jax.vmap(jax.grad(lambda x: surface.restoring_force(x, WEIGHT)))
    inside, outside = slope(jnp.array([0.29, 0.31]))
    np.testing.assert_allclose(outside - inside, k_r, rtol=1e-12)


def test_large_displacement_form_is_the_normal_reaction_on_the_sphere():
    # On a sphere of radius R at u = R sin(theta), a vertical load N balances the normal
    # reaction N / cos(theta), whose horizontal component is N tan(theta).
    surface = concave_surface(RADIUS, large_displacement=True)
    theta = jnp.array([-0.6, -0.2, 0.05, 0.3, 0.7])
    u = RADIUS * jnp.sin(theta)
    np.testing.assert_allclose(surface.restoring_force(u, WEIGHT), WEIGHT * np.tan(theta), rtol=1e-12)
    small = concave_surface(RADIUS)
    ratio = surface.restoring_force(u, WEIGHT) / small.restoring_force(u, WEIGHT)
    np.testing.assert_allclose(ratio, 1 / np.cos(theta), rtol=1e-12)
    q = RADIUS * np.sin(0.5) * jnp.array([0.6, 0.8])
    np.testing.assert_allclose(surface.restoring_force(q, WEIGHT), WEIGHT * np.tan(0.5) * q / jnp.linalg.norm(q),
                               rtol=1e-12)


def test_radius_sets_the_period_and_the_spring_of_the_structures():
    surface = concave_surface(88 * INCH)
    np.testing.assert_allclose(surface.isolation_period(), 2 * np.pi * np.sqrt(88 * INCH / G), rtol=1e-14)
    ground = uniform_signal(np.zeros(11), 0.01)
    for kind in ("rigid", "building"):
        system = isolated_structure(kind, isolator=concave_surface(88 * INCH))(ground)
        flat = isolated_structure(kind, isolation_period=float(surface.isolation_period()),
                                  isolation_damping=0.0)(ground)
        np.testing.assert_allclose(system.stiffness, flat.stiffness, rtol=1e-12)
        # the bearings carry the whole weight W: the base spring is W / R (R -> 2 R halves it)
        wide = isolated_structure(kind, isolator=concave_surface(2 * 88 * INCH))(ground)
        np.testing.assert_allclose(system.stiffness[0, 0] - wide.stiffness[0, 0],
                                   float(system.bearing_load) / (2 * 88 * INCH), rtol=1e-9)


@pytest.mark.parametrize("options, message", [
    ({"isolator": "curved"}, "isolator: expected None"),
    ({"isolator": concave_surface(1.0), "isolation_period": 2.0}, "isolation_period: the single-fp"),
    ({"isolator": concave_surface(1.0), "bearing": paper_bearing(FrictionParameters(0.1, 0.05, 25.0))},
     r"bearing: the isolator value \(ConcaveSurface\)"),
])
def test_bad_pendulum_inputs_are_refused_naming_the_parameter(options, message):
    with pytest.raises(ValueError, match=message):
        isolated_structure("rigid", **options)
    with pytest.raises(ValueError, match="radius: must be > 0"):
        concave_surface(0.0)


def test_surface_inputs_are_checked():
    with pytest.raises(ValueError, match="radius"):
        concave_surface(-1.0)
    with pytest.raises(ValueError, match="restrainer_stiffness"):
        concave_surface(1.0, displacement_capacity=0.2, restrainer_stiffness=-1.0)
    with pytest.raises(ValueError, match="displacement_capacity"):
        concave_surface(1.0, displacement_capacity=1.5, large_displacement=True)


def _strong_pulse(duration=6.0, dt=0.01):
    t = np.arange(0.0, duration + dt / 2, dt)
    return uniform_signal(np.where(t < 2.0, 5.0 * np.sin(np.pi * t), 0.0), dt)


def _on_restrained_surface(large_displacement, duration=6.0):
    surface = concave_surface(RADIUS, displacement_capacity=0.15, restrainer_stiffness=2e6,
                              large_displacement=large_displacement)
    structure = isolated_structure("rigid", isolator=surface, time_step=0.001)
    return structure(_strong_pulse(duration)), duration


@pytest.mark.slow
@pytest.mark.parametrize("large_displacement", [False, True])
def test_restrainer_and_large_displacement_in_the_step_agree_with_an_adaptive_solver(large_displacement):
    """The rigid mass on a surface whose restrainer engages: the step solve (the surface's
    force beyond W u / R inside Newton's residual and in the exact rule's start force)
    against Tsit5 on the vector field (measured: peaks within 1.2e-5 (displacement) and 3e-5
    (base shear) with and without the large-displacement form)."""
    import diffrax

    system, duration = _on_restrained_surface(large_displacement)
    stepped = simulate_history(system, duration)
    reference = simulate_history(system, duration, solver=diffrax.Tsit5(), rtol=1e-9, atol=1e-12,
                                   max_steps=2_000_000)
    u, u_ref = np.asarray(stepped.displacement[:, 0]), np.asarray(reference.displacement[:, 0])
    assert np.max(np.abs(u)) > 0.18  # beyond the capacity
    np.testing.assert_allclose(np.max(np.abs(u)), np.max(np.abs(u_ref)), rtol=2e-4)
    shear = np.max(np.abs(stepped.total_acceleration[:, 0])) / G
    shear_ref = np.max(np.abs(reference.total_acceleration[:, 0])) / G
    np.testing.assert_allclose(shear, shear_ref, rtol=2e-4)


@pytest.mark.slow
def test_restrainer_holds_the_mass_back_and_the_peak_loop_sees_its_force():
    from teflon_jax.systems import peak_response

    system, duration = _on_restrained_surface(False)
    response = simulate_history(system, duration)
    u = np.asarray(response.displacement[:, 0])
    shear = np.max(np.abs(response.total_acceleration[:, 0])) / G
    # m a_total = -(W u / R + E(u) + F): the base shear holds the restrainer's force
    force = -(WEIGHT / G) * np.asarray(response.total_acceleration[:, 0])
    expected = np.asarray(concave_surface(RADIUS, displacement_capacity=0.15, restrainer_stiffness=2e6)
                          .restoring_force(jnp.asarray(u), WEIGHT)) + np.asarray(response.friction_force)
    np.testing.assert_allclose(force, expected, atol=1e-9 * WEIGHT)
    peaks = peak_response(system, duration)
    np.testing.assert_allclose(peaks.base_disp, np.max(np.abs(u)), rtol=1e-9)
    np.testing.assert_allclose(peaks.base_shear_ratio, shear, rtol=1e-9)
    free = isolated_structure("rigid", isolator=concave_surface(RADIUS), time_step=0.001)(_strong_pulse())
    assert np.max(np.abs(u)) > 0.18  # beyond the capacity
    assert np.max(np.abs(simulate_history(free, duration).displacement[:, 0])) > 1.1 * np.max(np.abs(u))


def test_nonlinear_surface_is_refused_where_it_does_not_run():
    surface = concave_surface(RADIUS, displacement_capacity=0.15, restrainer_stiffness=2e6)
    with pytest.raises(ValueError, match="surface: its restrainer"):
        isolated_structure("rigid", isolator=surface, friction_model="coulomb")
    with pytest.raises(ValueError, match="surface: its restrainer"):  # in two components too
        bidirectional_isolated_structure("rigid", isolator=surface, friction_model="coulomb")


@pytest.mark.slow
def test_design_gradient_in_the_radius_matches_central_differences():
    """d(mean smooth peaks)/dR of the rigid mass on the pendulum: reverse mode through the
    solver against central differences of the same statistic."""
    from teflon_jax.excitation import StochasticGroundMotion, sample
    from teflon_jax.studies import expected_response, gradient_check

    dt = 0.01
    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=4.0, time_step=dt, rise_time=0.5,
                                   strong_motion_duration=2.0)
    records = sample(model, jax.random.key(2), 2)
    structure = isolated_structure("rigid", isolator=concave_surface(1.5), time_step=dt)

    def statistic(x):
        r = expected_response(structure, x, records, dt, disp_width=2e-4, shear_width=2e-3)
        return r["shear"] + 10.0 * r["disp"]

    gradient, differences, error = gradient_check(statistic, {"radius": 1.5, "f_max": 0.1}, relative_step=1e-5)
    assert error < 1e-4, (gradient, differences)
    assert abs(gradient["radius"]) > 1e-6  # the radius matters (a zero gradient would pass trivially)
    with pytest.raises(ValueError, match="'isolation_period' does not apply"):
        structure(uniform_signal(records[0], dt), {"isolation_period": 2.0})


# --------------------------------------------------------------------------- OpenSees peer


def _peer():
    """benchmarks/_opensees_pendulum.py, or a skip when openseespy cannot be loaded."""
    pytest.importorskip("openseespy")
    folder = str(pathlib.Path(__file__).resolve().parents[1] / "benchmarks")
    if folder not in sys.path:
        sys.path.insert(0, folder)
    import _opensees_pendulum

    try:
        _opensees_pendulum.import_opensees()
    except ImportError as error:
        pytest.skip(f"openseespy is not importable: {error}")
    return _opensees_pendulum


def _rsn6(external_data, duration=40.0):
    folder = external_data / "elcentro1940_peer_nga_rsn6"
    x = read_at2(folder / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2")
    y = read_at2(folder / "RSN6_IMPVALL.I_I-ELC270-hor2.AT2")
    n = int(round(duration / x.time_step)) + 1
    assert x.time_step == y.time_step and min(x.acceleration.size, y.acceleration.size) >= n
    return np.asarray(x.acceleration[:n]), np.asarray(y.acceleration[:n]), float(x.time_step)


@pytest.mark.external
def test_rigid_mass_with_coulomb_friction_agrees_with_opensees(external_data):
    peer = _peer()
    ax, _, dt = _rsn6(external_data)
    radius, mu, step = 88 * INCH, 0.06, 0.001
    disp_os, shear_os, _ = peer.rigid_mass_on_pendulum(ax, dt, weight=WEIGHT, radius=radius, mu_slow=mu,
                                                       yield_disp=1e-7, time_step=step)
    bearing = paper_bearing(FrictionParameters(f_max=mu, delta_f=0.0, rate_a=1.0))
    structure = isolated_structure("rigid", isolator=(bearing, concave_surface(radius)), friction_model="coulomb",
                                   time_step=step)
    response = simulate_history(structure(uniform_signal(ax, dt)), (ax.size - 1) * dt)
    disp = float(np.max(np.abs(response.displacement[:, 0])))
    shear = float(np.max(np.abs(response.total_acceleration[:, 0]))) / G
    assert disp > 0.04
    assert abs(disp / disp_os - 1) < 0.02
    assert abs(shear / shear_os - 1) < 0.02


@pytest.mark.external
def test_rigid_mass_under_the_rsn6_pair_agrees_with_opensees(external_data):
    peer = _peer()
    ax, ay, dt = _rsn6(external_data)
    radius, f_max, f_min, rate_a, yield_disp, step = 88 * INCH, 0.1193, 0.0266, 0.6 / INCH, 0.001 * INCH, 0.0025
    disp_os, shear_os, _ = peer.rigid_mass_on_pendulum(
        ax, dt, weight=WEIGHT, radius=radius, mu_slow=f_min, mu_fast=f_max, rate=rate_a,
        yield_disp=yield_disp, time_step=step, ay=ay)
    bearing = paper_bearing(FrictionParameters(f_max=f_max, delta_f=f_max - f_min, rate_a=rate_a),
                            yield_disp=yield_disp)
    structure = bidirectional_isolated_structure("rigid", isolator=(bearing, concave_surface(radius)),
                                                 breakaway=False, time_step=step)
    system = structure((uniform_signal(ax, dt), uniform_signal(ay, dt)))
    response = simulate_history(system, (ax.size - 1) * dt)
    q = np.asarray(response.displacement)
    total = np.asarray(response.total_acceleration)
    disp = float(np.max(np.hypot(q[:, 0], q[:, 1])))
    shear = float(np.max(np.hypot(total[:, 0], total[:, 1]))) / G
    assert disp > 0.03
    assert abs(disp / disp_os - 1) < 0.02
    assert abs(shear / shear_os - 1) < 0.02
