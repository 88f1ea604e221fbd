"""Coulomb friction, no friction and the pendulum's restrainer and large-displacement force in
two ground components: closed forms, the optimality conditions of the Coulomb step, and the
uniaxial response along a line (an isotropic law in the plane, driven along a line, is the
law of one component along it)."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.optimize import minimize

from teflon_jax.bearing import concave_surface, paper_bearing
from teflon_jax.excitation import uniform_signal
from teflon_jax.solver import coupled_newton
from teflon_jax.studies import bidirectional_isolated_structure
from teflon_jax.systems import (
    PlanarStep,
    isolated_structure,
    peak_response,
    rigid_mass,
    simulate_history,
    six_storey_building,
)
from teflon_jax.tables import interface_parameters
from teflon_jax.units import PSI, STANDARD_GRAVITY

G = STANDARD_GRAVITY
WEIGHT = 1e5  # [N], the isolated rigid mass's default
ANGLE = np.deg2rad(30.0)


def _bearing(breakaway=False):
    params, b = interface_parameters("UF", 1000 * PSI)
    return paper_bearing(params, breakaway_ratio=b if breakaway else None)


def _pulse(duration=4.0, dt=0.01, peak=0.35):
    t = np.arange(0.0, duration + dt / 2, dt)
    return peak * G * np.sin(2 * np.pi * t) * np.sin(np.pi * t / duration) ** 2


def _along_a_line(record, angle=ANGLE, dt=0.01):
    return (uniform_signal(np.cos(angle) * record, dt), uniform_signal(np.sin(angle) * record, dt))


def _line_and_plane(kind, record, **law):
    """The uniaxial and the planar rigid mass (or building) of the same isolator, the plane
    driven along ANGLE by `record`."""
    gx, gy = _along_a_line(record)
    if kind == "rigid":
        common = dict(weight=1e5, bearing=_bearing(), time_step=0.0025,
                      isolation_period=law.pop("isolation_period", 2.5), damping_ratio=0.05)
        line = rigid_mass(ground_acceleration=uniform_signal(record, 0.01), **common, **law)
        plane = rigid_mass(components=2, ground_acceleration=gx, ground_y=gy, **common, **law)
    else:
        common = dict(bearing=_bearing(), time_step=0.0025, isolation_period=law.pop("isolation_period", 2.0))
        line = six_storey_building(ground_acceleration=uniform_signal(record, 0.01), **common, **law)
        plane = six_storey_building(components=2, ground_acceleration=gx, ground_y=gy, **common, **law)
    return line, plane


def _compare_along(line, plane, duration, rtol):
    """The plane's motion along ANGLE equals the line's, nothing moves across it."""
    n = line.mass.shape[0]
    uniaxial = simulate_history(line, duration)
    biaxial = simulate_history(plane, duration)
    u = np.asarray(uniaxial.displacement)
    qx, qy = np.asarray(biaxial.displacement[:, :n]), np.asarray(biaxial.displacement[:, n:])
    along = np.cos(ANGLE) * qx + np.sin(ANGLE) * qy
    across = -np.sin(ANGLE) * qx + np.cos(ANGLE) * qy
    peak = np.max(np.abs(u))
    np.testing.assert_allclose(along, u, rtol=0, atol=rtol * peak)
    assert np.max(np.abs(across)) <= rtol * peak
    return peak, uniaxial, biaxial


@pytest.mark.parametrize("kind", ["rigid", "building"])
def test_coulomb_along_a_line_is_the_uniaxial_coulomb_response(kind):
    """Coulomb's disc law, driven at 30 degrees, is the uniaxial Coulomb rule along the line
    (stick and slip both): to rounding, since both steps are closed forms for one group."""
    peak, uniaxial, _ = _compare_along(*_line_and_plane(kind, _pulse(), friction_model="coulomb"), 4.0, 1e-9)
    assert peak > 0.01
    velocity = np.asarray(uniaxial.velocity[:, 0])
    assert np.mean(np.abs(velocity) < 1e-9 * np.max(np.abs(velocity))) > 0.05  # it sticks at times: the set-valued law acts


def test_coulomb_sliding_under_a_ramped_ground_acceleration_is_the_closed_form():
    """A rigid mass on Coulomb sliders (mu constant) without springs, from rest, under a ground
    acceleration along 30 degrees ramped from 0 to 4 mu g over 0.01 s, then held: it sticks
    until a = mu g (t = 2.5 ms, one step) and then slides along the line with the relative
    velocity -int (a - mu g) dt, which Newmark's trapezoidal velocity update integrates
    exactly (the acceleration is linear over every step); displacement to the rule's O(dt^3)
    over the ramp. Held at 0.8 mu g it never slides."""
    params, _ = interface_parameters("UF", 1000 * PSI)
    constant = dataclasses.replace(params, delta_f=jnp.zeros(()))  # mu = f_max at any speed
    mu_g = float(constant.f_max) * G
    duration = 2.0
    ramp = np.minimum(np.arange(int(duration / 0.01) + 1), 1.0)
    for peak in (4.0 * mu_g, 0.8 * mu_g):
        gx, gy = _along_a_line(peak * ramp)
        plane = rigid_mass(components=2, weight=1e5, bearing=paper_bearing(constant), ground_acceleration=gx,
                                         ground_y=gy, time_step=0.0025, friction_model="coulomb")
        response = simulate_history(plane, duration)
        q, v = np.asarray(response.displacement), np.asarray(response.velocity)
        t = np.asarray(response.time)
        if peak < mu_g:
            assert np.max(np.abs(q)) < 1e-15 and np.max(np.abs(v)) < 1e-15
            continue
        ground = np.interp(t, np.arange(ramp.size) * 0.01, peak * ramp)
        excess = np.maximum(ground - mu_g, 0.0)
        velocity = -np.concatenate([[0.0], np.cumsum(0.5 * (excess[1:] + excess[:-1]) * np.diff(t))])
        along = np.cos(ANGLE) * v[:, 0] + np.sin(ANGLE) * v[:, 1]
        np.testing.assert_allclose(along, velocity, rtol=1e-10, atol=1e-14)
        along = np.cos(ANGLE) * q[:, 0] + np.sin(ANGLE) * q[:, 1]
        # Newmark's displacement is the trapezoidal integral of its velocity: to rounding
        trapezoid = np.concatenate([[0.0], np.cumsum(0.5 * (velocity[1:] + velocity[:-1]) * np.diff(t))])
        np.testing.assert_allclose(along, trapezoid, rtol=1e-10, atol=1e-14)
        # and the exact motion after the ramp (u(0.01) = -(a - mu g) 0.0075^2 / 6, then
        # v = -(a - mu g) (t - 6.25 ms)) less the rule's error over the three sliding steps of
        # the ramp, dt^3 / 12 times the jerk a / 0.01 each
        exact = -(peak - mu_g) * (0.0075**2 / 6 + ((t - 0.00625) ** 2 - 0.00375**2) / 2)
        late = t >= 0.01
        np.testing.assert_allclose(along[late] - exact[late], -3 * 0.0025**3 / 12 * peak / 0.01,
                                   rtol=1e-6, atol=1e-10 * np.max(np.abs(exact)))
        assert np.max(np.abs(-np.sin(ANGLE) * q[:, 0] + np.cos(ANGLE) * q[:, 1])) < 1e-11 * np.max(np.abs(q))


def test_the_coulomb_step_solves_its_convex_problem():
    """Groups coupled through an anisotropic compliance H: the step's forces minimise
    F^T H F / 2 - v*^T F over the discs |F_g| <= mu_g W_g (checked against scipy's SLSQP),
    sticking groups have v = 0 and sliding ones move along their force."""
    rng = np.random.default_rng(3)
    n = 3
    a = rng.normal(size=(2 * n, 2 * n))
    compliance = a @ a.T + 0.5 * np.eye(2 * n)  # H = (2 / dt) G_b
    dt = 0.01
    flexibility = compliance * dt / 2
    blocks = ((flexibility[:n, :n], flexibility[:n, n:]), (flexibility[n:, :n], flexibility[n:, n:]))
    params, _ = interface_parameters("UF", 1000 * PSI)
    bearing = jax.tree_util.tree_map(lambda x: jnp.broadcast_to(x, (n,)), paper_bearing(params))
    loads = np.array([1.0, 2.0, 0.5])
    system = type("Step", (), {"time_step": dt, "bearing": bearing, "bearing_load": jnp.asarray(loads)})()
    v_star = np.array([0.3, -0.01, 0.2, 0.25, 0.001, -0.4])
    p = {"flexibility": blocks, "d_linear": (jnp.asarray(v_star[:n] * dt / 2), jnp.asarray(v_star[n:] * dt / 2)),
         "d0": (jnp.zeros(n), jnp.zeros(n)), "vb0": (jnp.zeros(n), jnp.zeros(n)),
         "z0": (jnp.zeros(n), jnp.zeros(n))}
    (fx, fy), z, converged = PlanarStep._coulomb_solve(system, p)  # coulomb_disc_forces
    assert bool(converged)
    force = np.concatenate([fx, fy])
    capacity = np.asarray(bearing.coefficient(jnp.asarray(v_star[:n]), jnp.asarray(v_star[n:]), 1.0)) * loads

    def objective(f):
        return 0.5 * f @ compliance @ f - v_star @ f

    discs = [{"type": "ineq", "fun": lambda f, g=g: capacity[g] ** 2 - f[g] ** 2 - f[n + g] ** 2} for g in range(n)]
    best = minimize(objective, np.zeros(2 * n), constraints=discs, method="SLSQP",
                    options={"ftol": 1e-15, "maxiter": 1000})
    assert objective(force) <= best.fun + 1e-10 * abs(best.fun)
    np.testing.assert_allclose(force, best.x, atol=1e-5 * capacity.max())
    velocity = v_star - compliance @ force
    for g in range(n):
        f_g, v_g = np.array([force[g], force[n + g]]), np.array([velocity[g], velocity[n + g]])
        if np.linalg.norm(f_g) < capacity[g] * (1 - 1e-9):
            assert np.linalg.norm(v_g) < 1e-9 * np.abs(v_star).max()  # sticks
        else:
            assert abs(f_g[0] * v_g[1] - f_g[1] * v_g[0]) < 1e-9 * np.linalg.norm(f_g) * np.linalg.norm(v_g)
            assert f_g @ v_g > 0  # resists the motion
    np.testing.assert_allclose(np.asarray(z) * capacity[:, None], np.stack([fx, fy], -1), rtol=1e-12)


@pytest.mark.parametrize("kind", ["rigid", "building"])
def test_no_friction_in_the_plane_is_the_linear_structure_in_each_direction(kind):
    """friction_model="none": x and y are the uniaxial linear structure, each under its own
    component (to rounding)."""
    record = _pulse()
    line, plane = _line_and_plane(kind, record, friction_model="none")
    _compare_along(line, plane, 4.0, 1e-10)


@pytest.mark.parametrize("form", ["restrainer", "large displacement"])
def test_the_pendulums_nonlinear_surface_along_a_line_is_the_uniaxial_one(form):
    """A single pendulum with a restrainer (capacity 5 cm, k_r = 20 W / R) or in the
    large-displacement form (R = 0.25 m), driven at 30 degrees: the uniaxial response along
    the line (both solved to rounding, both with Newmark's rule for the linear part and no
    split of a step at a turn)."""
    weight = 1e5
    surface = (concave_surface(1.0, displacement_capacity=0.05, restrainer_stiffness=20 * weight)
               if form == "restrainer" else concave_surface(0.25, large_displacement=True))
    record = _pulse(peak=0.5)
    options = dict(isolator=surface, time_step=0.0025, newton_tolerance=0.0)
    line = isolated_structure("rigid", linear_rule="newmark", split_at_turn=False, **options)(uniform_signal(record, 0.01))
    plane = bidirectional_isolated_structure("rigid", **options)(_along_a_line(record))
    plane = dataclasses.replace(plane, newton_tolerance=0.0)
    peak, _, _ = _compare_along(line, plane, 4.0, 1e-6)
    if form == "restrainer":
        assert peak > 0.06  # the restrainer engaged
    else:
        assert peak > 0.02  # well into the large-displacement range of R = 0.25 m


@pytest.mark.slow
def test_the_restrainer_bounds_the_planar_displacement_and_counts_in_the_shear():
    """Through the isolated structure: the same planar pendulum with and without its restrainer
    (k_r = 50 W / R beyond 4 cm) under a strong pair: the restrainer cuts the peak resultant
    displacement and raises the peak base shear by at least k_r (peak - d) / W."""
    record = _pulse(peak=0.6)
    ground = (uniform_signal(record, 0.01), uniform_signal(0.6 * record[::-1].copy(), 0.01))
    peaks = {}
    for name, capacity in (("free", None), ("restrained", 0.04)):
        surface = (concave_surface(1.0) if capacity is None else
                   concave_surface(1.0, displacement_capacity=capacity, restrainer_stiffness=50 * WEIGHT))
        structure = bidirectional_isolated_structure("rigid", isolator=surface)
        peaks[name] = peak_response(structure(ground), 4.0)
    free, restrained = (float(peaks[k].base_disp) for k in ("free", "restrained"))
    assert free > 0.06 and restrained < free
    assert float(peaks["restrained"].base_shear_ratio) >= 50 * (restrained - 0.04) * 0.99
    assert bool(peaks["restrained"].converged)


def _planar_systems():
    """A slab on three groups of flat sliders (velocity-dependent, anisotropic friction with
    breakaway and a direction asymmetry, different in each group) and a rigid mass on a
    restrained pendulum (its restrainer engaged at the trial point): (system, the bearings'
    step parameters `p`, d)."""
    from teflon_jax.bearing import DirectionAsymmetry, FrictionParameters
    from teflon_jax.systems import slab_on_bearings

    rng = np.random.default_rng(3)
    ground = uniform_signal(np.zeros(11), 0.01)
    sliders = [dataclasses.replace(paper_bearing(FrictionParameters(0.10 + 0.01 * g, 0.05, 20.0), breakaway_ratio=1.3,
                                                 friction_perpendicular=FrictionParameters(0.14, 0.07, 30.0)),
                                   asymmetry=DirectionAsymmetry(0.1 * g)) for g in range(3)]
    slab = slab_on_bearings(length_x=20.0, length_y=12.0, weight=3e5, centre_of_mass=[10.0, 6.0],
                            positions=[[2.0, 1.0], [18.0, 1.0], [10.0, 11.0]], loads=[1e5] * 3, bearings=sliders,
                            ground_acceleration=ground, ground_y=ground, time_step=0.005, isolation_period=3.0)
    restrained = bidirectional_isolated_structure("rigid", isolator=concave_surface(
        1.0, displacement_capacity=0.04, restrainer_stiffness=50 * WEIGHT))((ground, ground))
    out = []
    for system, offset in ((slab, 0.0), (restrained, 0.05)):
        n = system.bearing_load.shape[0]
        d0 = tuple(jnp.asarray(offset + rng.normal(0, 1e-3, n)) for _ in range(2))
        p = {"d_linear": tuple(jnp.zeros(n) for _ in range(2)),
             "flexibility": [[jnp.asarray(rng.normal(0, 1e-7, (n, n))) + (2e-7 * jnp.eye(n) if i == j else 0.0)
                              for j in range(2)] for i in range(2)],
             "d0": d0, "vb0": tuple(jnp.asarray(rng.normal(0, 0.2, n)) for _ in range(2)),
             "z0": tuple(jnp.asarray(rng.uniform(-0.6, 0.6, n)) for _ in range(2)),
             "z_peak0": jnp.asarray(rng.uniform(0.5, 1.0, n))}
        d = tuple(d0[i] + jnp.asarray(rng.normal(0, 2e-3, n)) for i in range(2))
        out.append((system, p, d))
    return out


@pytest.mark.parametrize("case", [0, 1], ids=["slab-of-three-groups", "restrained-pendulum"])
def test_the_newton_matrix_is_the_residuals_jacobian(case):
    """The flat sliders' Newton matrix (`_tangent_jacobian` with `exact`: I + G_b K, the groups'
    2 x 2 blocks K from Park's slope written out, dmu/dv of Eq. 1, the asymmetry and the
    surface's restrainer) is dr/dd of r = d - d_lin + G_b F(d) by forward-mode AD through the
    whole force, for several groups sliding in different directions; the start's tangent (the
    Broyden stage's, without `exact`) is not."""
    system, p, d = _planar_systems()[case]
    n = d[0].shape[0]

    def residual(flat):
        return jnp.concatenate(system._residual_forces((flat[:n], flat[n:]), p)[0])

    exact = np.asarray(jax.jacfwd(residual)(jnp.concatenate(d)))
    blocks = np.asarray(jnp.block(system._tangent_jacobian(d, p, exact=True)[1]))
    np.testing.assert_allclose(blocks, exact, rtol=1e-9, atol=1e-9 * np.abs(exact).max())
    tangent = np.asarray(jnp.block(system._tangent_jacobian(d, p)[1]))
    assert np.abs(tangent - exact).max() > 1e-3 * np.abs(exact).max()
    assert np.abs(exact - np.eye(2 * n)).max() > 1e-2  # the bearings' part matters


@pytest.mark.parametrize("case", [0, 1], ids=["slab-of-three-groups", "restrained-pendulum"])
def test_the_newton_stage_converges_quadratically(case):
    """From the bearings' displacements of the linear step alone (no friction force), the
    flat sliders' Newton stage (`coupled_newton`'s, the exact Jacobian and its line search)
    balances the step to 1e-12 Y within eight iterations (line-search halvings counted), as
    Newton's method on an exact Jacobian does; on the end's tangent (the Broyden stage's start)
    it does not."""
    system, p, _ = _planar_systems()[case]
    system = dataclasses.replace(system, newton_iterations=8)
    start = p["d_linear"]
    r, _ = system._residual_forces(start, p)
    tolerance = 1e-12 * float(jnp.min(jnp.asarray(system.bearing.hysteresis.yield_disp)))
    assert float(jnp.max(jnp.abs(jnp.concatenate(r)))) > 1e3 * tolerance
    r, _ = coupled_newton(lambda d: system._residual_forces(d, p), lambda d, exact: system._tangent_jacobian(d, p, exact),
                          start, tolerance, system.newton_iterations, secant=False)
    assert float(jnp.max(jnp.abs(r))) <= tolerance


def test_the_tolerance_given_reaches_the_planar_solve():
    """`newton_tolerance` of an isolated structure on flat sliders ends the planar solve under
    two components as under one (in units of Y): a loose one (0.5 Y) moves the peak, one solved
    to rounding does not move from the default's by more than the default's tolerance."""
    record = _pulse(peak=0.5)
    ground = (uniform_signal(record, 0.01), uniform_signal(0.7 * record[::-1].copy(), 0.01))
    peaks = {}
    for tolerance in (0.0, 1e-5, 0.5):
        system = bidirectional_isolated_structure("rigid", newton_tolerance=tolerance)(ground)
        assert system.newton_tolerance == tolerance
        peaks[tolerance] = float(peak_response(system, 4.0).base_disp)
    assert abs(peaks[1e-5] - peaks[0.0]) < 1e-6 * peaks[0.0]
    assert abs(peaks[0.5] - peaks[0.0]) > 1e-3 * abs(peaks[1e-5] - peaks[0.0]) + 1e-9 * peaks[0.0]
